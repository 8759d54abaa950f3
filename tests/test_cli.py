"""The ``sweepcore`` command end to end, and study-file validation.

What is proven:
* ``sweepcore run`` on a small constant-friction study writes a netCDF whose
  amplitude and mean are the closed forms v/omega and r_y/k (eq. 39) of a start
  stuck on the belt, to 1e-9 relative (method exact: rounding only), and a PNG;
* bad study files (unknown key, wrong type, missing axis, negative mass, TOML syntax)
  are refused with the key and its line, exit code 2, and nothing written;
* library errors (Params validation) are one clean line, exit code 2;
* ``sweepcore info`` prints the regime counts of the file;
* ``sweepcore simulate`` writes netCDF + PNG whose orbit is the circle of eq. (39);
* ``sweepcore plot`` draws sweeps and simulations, and refuses a failed simulation;
* a simulation that fails (gps with omega dt > 1) says the rule with its numbers,
  lets no numpy warning through, exits 1 and writes nothing;
* unknown options get "did you mean", a missing output directory is refused
  (nothing is created), a closed output pipe ends the command quietly;
* the compile notice appears exactly when numba's cache is cold;
* ``sweepcore export`` writes CSV whose values are the file's, under the variables'
  names and units (``amplitude [cm]``), with a table of their units.
Subprocess tests run ``python -m sweepcore`` with the source tree on PYTHONPATH.
"""
from __future__ import annotations

import math
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from sweepcore.io import check_cf, open_result
from sweepcore.study import StudyError, key_line, parse_study

ROOT = Path(__file__).resolve().parents[1]
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"

SMALL = textwrap.dedent("""\
    title = "constant friction, started stuck"
    [axes]
    m = 5.0
    k = [20.0, 50.0]
    r_y = 10.0
    v = { start = 1.0, stop = 5.0, num = 3 }
    [solver]
    method = "exact"
    tol = 1e-8
    [output]
    path = "small.nc"
    """)


def sweepcore(*args, cwd) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get(
        "PYTHONPATH", ""), "MPLBACKEND": "Agg"}
    return subprocess.run([sys.executable, "-m", "sweepcore", *map(str, args)],
                          cwd=cwd, env=env, capture_output=True, text=True, timeout=300)


def assert_png(path: Path, min_kb: float = 10.0):
    data = path.read_bytes()
    assert data[:8] == PNG_MAGIC, f"{path} is not a PNG"
    assert len(data) > min_kb * 1024, f"{path} is only {len(data)} bytes"


@pytest.fixture(scope="module")
def small_run(tmp_path_factory):
    """``sweepcore run small.toml --png fig.png`` once for the module."""
    d = tmp_path_factory.mktemp("run")
    (d / "small.toml").write_text(SMALL)
    proc = sweepcore("run", "small.toml", "--png", "fig.png", cwd=d)
    assert proc.returncode == 0, proc.stderr
    return d, proc


# ------------------------------------------------------------------ run
def test_run_writes_closed_form_constant_friction(small_run):
    """Started stuck, constant friction: amplitude v/omega, mean r_y/k (eq. 39)."""
    d, _ = small_run
    with xr.open_dataset(d / "small.nc") as ds:
        assert dict(ds.sizes) == {"k": 2, "v": 3}
        omega = np.sqrt(ds.k / ds.m)
        amplitude, mean = xr.broadcast(ds.v / omega, ds.r_y / ds.k + 0 * ds.v)
        np.testing.assert_allclose(ds.amplitude.transpose(*amplitude.dims), amplitude,
                                   rtol=1e-9)
        np.testing.assert_allclose(ds["mean"].transpose(*mean.dims), mean, rtol=1e-9)
        assert ds.converged.values.all()
        assert ds.attrs["study_title"] == "constant friction, started stuck"
        assert ds.attrs["study"] == SMALL          # the run is reproducible from the file
        assert "sweepcore run small.toml" in ds.attrs["history"]
    assert not list(d.glob("*.partial"))           # the working store is cleaned up


def test_run_draws_png(small_run):
    d, proc = small_run
    assert_png(d / "fig.png")
    assert "wrote fig.png" in proc.stdout


def test_run_default_output_is_study_stem(tmp_path):
    """Without [output] path nor -o, the result is <study stem>.nc in the cwd."""
    (tmp_path / "tiny.toml").write_text(SMALL.replace('[output]\npath = "small.nc"\n', ""))
    proc = sweepcore("run", "tiny.toml", "--no-png", "-q", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "tiny.nc").is_file()
    assert not (tmp_path / "tiny.png").exists()
    assert proc.stdout == ""


BAD = {
    # name: (replace this, by this, expected key, expected line)
    "unknown key": ("m = 5.0", "m = 5.0\nmass = 5.0", "axes.mass", 4),
    "wrong type": ("r_y = 10.0", 'r_y = "ten"', "axes.r_y", 5),
    "missing axis": ("v = { start = 1.0, stop = 5.0, num = 3 }\n", "", "axes.v", 2),
    "negative mass": ("m = 5.0", "m = -5.0", "axes.m", 3),
    "bad range": ("num = 3", "num = 2.5", "axes.v.num", 6),
    "bad method": ('method = "exact"', 'method = "euler"', "solver.method", 8),
}


def test_bad_study_refused_by_the_process(tmp_path):
    """Exit code 2 of the real process, one line on stderr, nothing written."""
    (tmp_path / "bad.toml").write_text(SMALL.replace("m = 5.0", "m = -5.0"))
    proc = sweepcore("run", "bad.toml", "--png", "bad.png", cwd=tmp_path)
    assert proc.returncode == 2
    assert proc.stderr == ("sweepcore run: error: bad.toml:3: axes.m: m must be > 0 "
                           "[kN s2 cm-1], got -5.0\n")
    assert proc.stdout == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]   # nothing written


def run_in_process(argv, tmp_path, monkeypatch, capsys):
    from sweepcore.cli import main
    monkeypatch.chdir(tmp_path)
    code = main(argv)
    return code, capsys.readouterr()


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_study_refused_with_key_and_line(case, tmp_path, monkeypatch, capsys):
    old, new, key, line = BAD[case]
    assert old in SMALL
    (tmp_path / "bad.toml").write_text(SMALL.replace(old, new, 1))
    code, out = run_in_process(["run", "bad.toml", "--png", "bad.png"], tmp_path,
                               monkeypatch, capsys)
    assert code == 2
    assert f"bad.toml:{line}: {key}:" in out.err, out.err
    assert len(out.err.strip().splitlines()) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]   # nothing written


def test_toml_syntax_error_has_line(tmp_path, monkeypatch, capsys):
    (tmp_path / "bad.toml").write_text(SMALL.replace("tol = 1e-8", "tol = = 1e-8"))
    code, out = run_in_process(["run", "bad.toml"], tmp_path, monkeypatch, capsys)
    assert code == 2
    assert "bad.toml:9: TOML syntax error" in out.err
    assert not (tmp_path / "small.nc").exists()


def test_library_error_is_one_clean_line(tmp_path, monkeypatch, capsys):
    code, out = run_in_process(["simulate", "--m", "5", "--k", "50", "--r-y", "10",
                                "--v", "5", "--alpha2", "-1", "-o", "run.nc"],
                               tmp_path, monkeypatch, capsys)
    assert code == 2
    assert out.err.startswith("sweepcore simulate: error: alpha2 must be >= 0 "
                              "[kN s3 cm-3], got -1.0")
    assert len(out.err.strip().splitlines()) == 1
    assert not (tmp_path / "run.nc").exists()


def test_sweep_refusal_is_one_clean_line(tmp_path, monkeypatch, capsys):
    """A refusal from sweep() itself (not the study checks) exits 2, writes nothing."""
    (tmp_path / "s.toml").write_text(SMALL)
    code, out = run_in_process(["run", "s.toml", "--chunks", "2", "--scheduler",
                                "nonsense"], tmp_path, monkeypatch, capsys)
    assert code == 2
    assert "scheduler must be one of" in out.err
    assert len(out.err.strip().splitlines()) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]


# ----------------------------------------------------------------- info
def test_info_prints_regime_counts(small_run):
    d, _ = small_run
    proc = sweepcore("info", "small.nc", cwd=d)
    assert proc.returncode == 0, proc.stderr
    with xr.open_dataset(d / "small.nc") as ds:
        meanings = ds.regime.attrs["flag_meanings"].split()
        codes = list(np.atleast_1d(ds.regime.attrs["flag_values"]))
        counts = {meanings[codes.index(c)]: int((ds.regime.values == c).sum())
                  for c in np.unique(ds.regime.values)}
    assert "regime counts:" in proc.stdout
    for name, n in counts.items():
        rows = [line.split()[:2] for line in proc.stdout.splitlines()]
        assert [name, str(n)] in rows, proc.stdout
    assert "converged: 6 of 6" in proc.stdout
    assert "k        spring stiffness [kN cm-1]: 2 values in [20, 50]" in proc.stdout


# ------------------------------------------------------------- simulate
def test_simulate_writes_nc_and_png_on_the_circle(tmp_path):
    """Fig. 3 run: after the slip at t = r_y/(k v) the orbit is the circle of eq. (39)."""
    m, k, r_y, v = 5.0, 50.0, 10.0, 5.0
    proc = sweepcore("simulate", "--m", m, "--k", k, "--r-y", r_y, "--v", v,
                     "--t-end", 10, "-o", "run.nc", "--png", "run.png", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert_png(tmp_path / "run.png", min_kb=50)
    with open_result(tmp_path / "run.nc") as ds:
        w = math.sqrt(k / m)
        after = ds.time > r_y / (k * v) + 1e-9
        R = np.hypot(ds.x[after] - r_y / k, ds.xdot[after] / w)
        np.testing.assert_allclose(R, v / w, rtol=1e-9)
        assert ds.attrs["status"] == "ok"
    assert "events: slip 1, abnormal_stop" in proc.stdout


# ----------------------------------------------------------------- plot
def test_plot_sweep_and_simulation(small_run, tmp_path):
    d, _ = small_run
    proc = sweepcore("plot", d / "small.nc", "-o", tmp_path / "map.png", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert_png(tmp_path / "map.png")
    proc = sweepcore("plot", tmp_path / "nothing.nc", cwd=tmp_path)
    assert proc.returncode == 2 and "no such result file" in proc.stderr


def test_help_states_units(capsys):
    from sweepcore.cli import main
    with pytest.raises(SystemExit) as exit_:
        main(["--help"])
    assert exit_.value.code == 0
    out = capsys.readouterr().out
    assert "kN" in out and "cm" in out
    for command in ("run", "plot", "simulate", "info"):
        assert command in out


def test_help_says_what_the_forced_scene_offers(capsys):
    """``sweepcore --help`` names the forced slider's ways in (a study's
    [excitation] table, simulate's --F0/--Omega/--phi/--Y0, frequency_response and
    stroboscopic_diagram from Python) and the sections of the pages documenting
    them, each of which exists."""
    from sweepcore.cli import main
    with pytest.raises(SystemExit):
        main(["--help"])
    out = " ".join(capsys.readouterr().out.split())
    for word in ("[excitation]", "--F0", "--Omega", "--phi", "--Y0",
                 "sweepcore.frequency_response", "sweepcore.stroboscopic_diagram"):
        assert word in out, word
    for page, section in (("studies.md", "The [excitation] table"),
                          ("variables.md", "Forced response"),
                          ("physics.md", "Forced vibration")):
        assert f"{page} ({section})" in out
        headings = [ln.replace("`", "") for ln in
                    (ROOT / "docs" / page).read_text().splitlines()
                    if ln.startswith("#")]
        assert any(section in h for h in headings), (page, section)


# -------------------------------------------------- study file (in process)
def test_key_line_finds_tables_dotted_and_inline_keys():
    text = textwrap.dedent("""\
        title = "x"           # 1
        [axes]                # 2
        m = 5.0               # 3
        "r_y" = 1.0           # 4
        v = { start = 1.0,  num = 3 }
        alpha2.start = 0.1    # 6
        [axes.x0]             # 7
        start = 0.0           # 8
        """)
    assert key_line(text, ("axes",)) == 2
    assert key_line(text, ("axes", "m")) == 3
    assert key_line(text, ("axes", "r_y")) == 4
    assert key_line(text, ("axes", "v", "num")) == 5
    assert key_line(text, ("axes", "alpha2", "start")) == 6
    assert key_line(text, ("axes", "x0", "start")) == 8
    assert key_line(text, ("solver", "tol")) is None


def test_parse_study_ranges_and_defaults():
    s = parse_study(SMALL.replace("num = 3 }", 'num = 3, spacing = "geometric" }'))
    np.testing.assert_allclose(s.axes["v"].values, [1.0, math.sqrt(5.0), 5.0])
    assert s.axes["v"].spacing == "geometric"
    assert s.shape == (2, 3) and s.size == 6
    assert "xdot0" not in s.grid_kwargs()        # unlisted: start stuck on the belt
    assert s.method == "exact" and s.tol == 1e-8 and s.png is None


@pytest.mark.parametrize("old, new, message", [
    ("num = 3 }", 'num = 3, spacing = "log" }', "must be one of 'linear', 'geometric'"),
    ("start = 1.0", "start = -1.0", None),
    ("k = [20.0, 50.0]", "k = [20.0, 20.0]", "must be distinct"),
    ("k = [20.0, 50.0]", "k = []", "must not be empty"),
    ('path = "small.nc"', 'path = "small.h5"', "must end in .nc"),
    ("tol = 1e-8", "tol = 0", "must be > 0"),
])
def test_parse_study_refusals_name_the_value(old, new, message):
    text = SMALL.replace(old, new)
    if message is None:         # a negative speed is fine (mirror image), no error
        parse_study(text)
        return
    with pytest.raises(StudyError, match=message) as err:
        parse_study(text, "s.toml")
    assert err.value.line is not None
    assert str(err.value).startswith(f"s.toml:{err.value.line}:")


def test_geometric_range_needs_positive_ends():
    text = SMALL.replace("num = 3 }", 'num = 3, spacing = "geometric" }').replace(
        "start = 1.0", "start = -1.0")
    with pytest.raises(StudyError, match=r"axes.v.start: a geometric range needs") as err:
        parse_study(text, "s.toml")
    assert err.value.line == 6


def test_shipped_studies_are_valid():
    for path in sorted((ROOT / "studies").glob("*.toml")):
        study = parse_study(path.read_text(), path)
        assert study.size >= 2, path


# ------------------------------------------------- first-hour messages and rules
SLIDER = ("--m", 5, "--k", 50, "--r-y", 10, "--v", 5)


def test_failed_simulation_says_the_rule_and_writes_nothing(tmp_path):
    """gps at dt = 1 s, omega = sqrt(10): omega dt = 3.16 > 1 breaks the fixed-step rule."""
    proc = sweepcore("simulate", *SLIDER, "--alpha1", 1, "--alpha2", 0.01, "--method",
                     "gps", "--dt", 1, "-o", "g.nc", "--png", "g.png", cwd=tmp_path)
    assert proc.returncode == 1
    assert "Warning" not in proc.stderr and "nan" not in proc.stdout
    omega = math.sqrt(50 / 5)
    err = [line for line in proc.stderr.strip().splitlines()   # the compile notice
           if not line.startswith("sweepcore: ")]                 # aside
    assert len(err) == 1, proc.stderr
    assert err[0].startswith("sweepcore simulate: failed: fixed_step_too_large: ")
    assert "omega dt <= 1" in err[0]
    assert f"dt <= {1 / omega:.6g} s" in err[0]
    assert err[0].endswith("nothing written")
    assert list(tmp_path.iterdir()) == []


def test_plot_refuses_a_failed_simulation(tmp_path):
    """A failed run saved through the Python API is refused by plot (exit 2)."""
    import sweepcore as sc
    ds = sc.simulate(sc.Params(m=5.0, k=50.0, r_y=10.0, v=5.0), 1.0, method="rk4",
                     dt=1.0)
    assert ds.attrs["status"] == "fixed_step_too_large"
    sc.write_netcdf(ds, tmp_path / "bad.nc")
    proc = sweepcore("plot", "bad.nc", cwd=tmp_path)
    assert proc.returncode == 2
    assert "failed simulation (status fixed_step_too_large)" in proc.stderr
    assert not (tmp_path / "bad.png").exists()


def test_bad_setting_message_has_its_unit(tmp_path, monkeypatch, capsys):
    code, out = run_in_process(["simulate", *map(str, SLIDER), "--t-end", "-1"],
                               tmp_path, monkeypatch, capsys)
    assert code == 2
    assert out.err == "sweepcore simulate: error: t_end must be > 0 [s], got -1.0\n"


@pytest.mark.parametrize("argv, expected", [
    (["simulate", "--m", "5", "--k", "50", "--ry", "10", "--v", "5"],
     "sweepcore simulate: error: unknown option --ry; did you mean --r-y?"),
    (["simulate", *map(str, SLIDER), "--tend=3"],
     "sweepcore simulate: error: unknown option --tend; did you mean --t-end?"),
    (["--thread", "2", "info", "x.nc", "--verbose"],
     "sweepcore info: error: unknown option --verbose"),
    (["run", "s.toml", "--chunk", "5", "--no_png"],
     "sweepcore run: error: unknown option --no_png; did you mean --no-png?"),
])
def test_unknown_option_did_you_mean(argv, expected, tmp_path, monkeypatch, capsys):
    code, out = run_in_process(argv, tmp_path, monkeypatch, capsys)
    assert code == 2
    assert out.err.startswith(expected), out.err
    assert len(out.err.strip().splitlines()) == 1


def test_known_options_values_and_prefixes_pass():
    """Negative numbers, values that look like options, unambiguous prefixes: no error."""
    from sweepcore.cli import build_parser, unknown_option
    parser = build_parser()
    assert unknown_option(parser, ["simulate", *map(str, SLIDER), "--x0", "-1",
                                   "--x0=-2", "--t-e", "3", "-o", "a.nc"]) is None
    assert unknown_option(parser, ["--threads", "2", "plot", "r.nc", "--x", "v"]) is None
    assert unknown_option(parser, ["run", "s.toml", "-qo", "x.nc"]) is None   # grouped
    assert parser.parse_args(["run", "s.toml", "-qo", "x.nc"]).output == "x.nc"


def test_missing_output_directory_is_refused_not_created(tmp_path, monkeypatch, capsys):
    """One rule with the Python API (write_netcdf, sweep): nothing creates directories."""
    (tmp_path / "s.toml").write_text(SMALL)
    code, out = run_in_process(["run", "s.toml", "-o", "new/dir/s.nc"], tmp_path,
                               monkeypatch, capsys)
    assert code == 2
    assert "directory 'new/dir' of 'new/dir/s.nc' does not exist" in out.err
    assert "mkdir -p new/dir" in out.err
    code, out = run_in_process(["simulate", *map(str, SLIDER), "--png", "no/f.png"],
                               tmp_path, monkeypatch, capsys)
    assert code == 2 and "directory 'no' of 'no/f.png' does not exist" in out.err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]


def test_closed_pipe_is_quiet(small_run):
    """``sweepcore info small.nc | head -0``: no traceback, no BrokenPipeError."""
    d, _ = small_run
    read, write = os.pipe()
    os.close(read)                       # the reader is gone before anything is written
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.run([sys.executable, "-m", "sweepcore", "info", "small.nc"],
                          cwd=d, env=env, stdout=write, stderr=subprocess.PIPE,
                          text=True, timeout=120)
    os.close(write)
    assert proc.stderr == ""
    assert proc.returncode == 0


@pytest.mark.slow    # two cold compiles (40 s); test_compile's notices run by default
def test_compile_notice_only_on_a_cold_cache(tmp_path):
    """While numba compiles, the command says what (the kernel, its method and law
    kind) and, at the end, how long it took; from the filled cache it says nothing.
    The second run's estimate is the first run's time."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "SWEEPCORE_CACHE_DIR": str(tmp_path)}
    env.pop("NUMBA_CACHE_DIR", None)
    args = [sys.executable, "-m", "sweepcore", "simulate", *map(str, SLIDER),
            "--t-end", "1"]
    cold = subprocess.run(args, env=env, capture_output=True, text=True, timeout=600)
    warm = subprocess.run(args, env=env, capture_output=True, text=True, timeout=300)
    assert cold.returncode == 0 and warm.returncode == 0, cold.stderr + warm.stderr
    lines = cold.stderr.splitlines()
    assert any(line.startswith("sweepcore: compiling the trajectory kernel (")
               for line in lines)
    took = float(re.search(r"sweepcore: compiled the trajectory kernel \(.*\) in ([\d.]+)"
                           r" s ", cold.stderr)[1])
    assert warm.stderr == ""
    assert list(tmp_path.glob("numba-*/*/*.nbi"))           # the cache it filled
    # another install location of the same sources compiles again (numba keys its
    # cache on each file's location), and then says how long it took here before
    import shutil
    shutil.copytree(ROOT / "sweepcore", tmp_path / "elsewhere" / "sweepcore",
                    ignore=shutil.ignore_patterns("__pycache__"))
    again = subprocess.run(args, env={**env, "PYTHONPATH": str(tmp_path / "elsewhere")},
                           cwd=tmp_path, capture_output=True, text=True, timeout=600)
    start = [line for line in again.stderr.splitlines()
             if line.startswith("sweepcore: compiling the trajectory kernel (")]
    assert f"about {round(took, 1):g} s measured here" in start[0]


def test_export_csv_holds_the_file_values(small_run, tmp_path):
    d, _ = small_run
    proc = sweepcore("export", d / "small.nc", "--csv", tmp_path / "small.csv",
                     cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    import pandas as pd
    # the plain names, as docs/variables.md says
    table = pd.read_csv(tmp_path / "small.csv").rename(
        columns=lambda c: c.split(" [")[0])
    ds = open_result(d / "small.nc")
    assert len(table) == ds.sizes["k"] * ds.sizes["v"]
    for _, row in table.iterrows():
        point = ds.sel(k=row["k"], v=row["v"])
        assert row["amplitude"] == float(point.amplitude)     # round trip, exact
        code = int(point.regime)
        names = ds.regime.attrs["flag_meanings"].split()
        values = list(np.atleast_1d(ds.regime.attrs["flag_values"]))
        assert row["regime"] == names[values.index(code)]
        assert row["m"] == 5.0                                   # fixed parameter
        assert row["sticks_per_period"] == int(point.sticks_per_period)   # a count


def test_export_headers_carry_units_and_tables_them(small_run, tmp_path):
    """Every column with units says them in its header, ``amplitude [cm]`` (the
    headers carried no units), and pandas still reads the numbers as numbers; the
    name, units and long name of every column are in OUT_units.csv, the file's
    own."""
    d, _ = small_run
    proc = sweepcore("export", d / "small.nc", "--csv", tmp_path / "small.csv",
                     cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    import pandas as pd
    table = pd.read_csv(tmp_path / "small.csv")
    units = pd.read_csv(tmp_path / "small_units.csv", keep_default_na=False)
    ds = open_result(d / "small.nc")
    assert list(units["column"]) == list(table.columns)
    assert set(units["name"]) == set(ds.variables) - {"point"}
    for _, row in units.iterrows():
        given = ds[row["name"]].attrs.get("units", "")
        stated = "" if given == "1" else given
        assert row["column"] == (f"{row['name']} [{stated}]" if stated
                                 else row["name"])
        assert row["units"] == stated
        assert row["long_name"] == ds[row["name"]].attrs.get("long_name", "")
    assert table["amplitude [cm]"].dtype == np.float64


def test_export_simulation_splits_events(tmp_path):
    proc = sweepcore("simulate", *SLIDER, "--t-end", 3, "-o", "run.nc", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    proc = sweepcore("export", "run.nc", "--csv", "run.csv", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    import pandas as pd
    ds = open_result(tmp_path / "run.nc")
    samples = pd.read_csv(tmp_path / "run.csv")
    events = pd.read_csv(tmp_path / "run_events.csv")
    assert len(samples) == ds.sizes["time"] and len(events) == ds.sizes["event"]
    np.testing.assert_array_equal(samples["time [s]"], ds.time.values)
    np.testing.assert_array_equal(samples["x [cm]"], ds.x.values)
    units = pd.read_csv(tmp_path / "run_units.csv")
    assert dict(zip(units["column"], units["units"]))["time [s]"] == "s"
    assert set(events["event_kind"]) <= set(ds.event_kind.attrs["flag_meanings"].split())


def test_simulation_file_passes_check_cf(tmp_path):
    proc = sweepcore("simulate", *SLIDER, "--alpha1", 1, "--alpha2", 0.01, "--t-end", 5,
                     "-o", "run.nc", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    ds = open_result(tmp_path / "run.nc")
    assert check_cf(ds) == []
    for name in ("m", "k", "r_y", "v", "alpha1", "alpha2", "x0", "xdot0"):
        assert ds[name].ndim == 0 and ds[name].attrs["units"], name


# ----------------------------------------------------- what a new user reads
def test_info_counts_a_table_law_sweep_over_its_grid(tmp_path, capsys):
    """A table law's samples (``law_point``) are the law's data, not an axis: the
    points, the converged share and the axes are the grid's (it said "112 points
    (v: 16 x law_point: 7)" and "converged: 16 of 112")."""
    import sweepcore as sc
    from sweepcore.cli import main
    law = sc.TableLaw([0.0, 0.1, 0.25, 0.5, 1.0, 2.0, 4.0],
                      [1.0, 0.93, 0.82, 0.68, 0.55, 0.51, 0.50], static=1.1)
    ds = sc.sweep(sc.Grid(m=1.0, k=1.0, c=0.1, v=np.linspace(0.2, 0.6, 4), law=law),
                  path=tmp_path / "t.nc")
    converged = int(ds["converged"].sum())
    assert main(["info", str(tmp_path / "t.nc")]) == 0
    out = capsys.readouterr().out
    assert "sweep of 4 points (v: 4)" in out
    assert f"converged: {converged} of 4 (" in out
    axes = out.split("  axes:\n")[1].split("  fixed:")[0]
    assert "law_point" not in axes
    assert "law_point: 7 samples of the law's table" in out


def test_run_and_info_name_the_axes_in_one_order(tmp_path):
    """``run`` announces the grid in the result's order (v last), as ``info``
    reads it from the file (run said "v x alpha2", info "alpha2 x v")."""
    (tmp_path / "s.toml").write_text(textwrap.dedent("""\
        [axes]
        m = 5.0
        k = 50.0
        r_y = 10.0
        alpha1 = 1.0
        v = [4.0, 6.0]
        alpha2 = [0.01, 0.02, 0.03]
        [output]
        path = "s.nc"
        """))
    run = sweepcore("run", "s.toml", "--no-png", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    info = sweepcore("info", "s.nc", cwd=tmp_path)
    said = re.search(r"\((\w+: \d+ x \w+: \d+)\)", run.stdout)[1]
    assert said == "alpha2: 3 x v: 2"
    assert f"sweep of 6 points ({said})" in info.stdout


def test_run_prints_status_counts_and_progress_lines_to_a_file(small_run):
    """run prints the status counts beside the regime counts, as the file holds
    them; where stderr is not a terminal (a pipe here) its progress is plain lines,
    the last one at every point."""
    d, proc = small_run
    ds = open_result(d / "small.nc")
    names = dict(zip(np.atleast_1d(ds.status.attrs["flag_values"]).tolist(),
                     ds.status.attrs["flag_meanings"].split()))
    codes, counts = np.unique(ds.status.values, return_counts=True)
    expect = "status: " + ", ".join(f"{names[c]} {n}" for c, n in zip(codes.tolist(),
                                                                      counts))
    assert expect in proc.stdout.splitlines()
    size = ds.status.size
    assert re.search(rf"^sweep: {size} of {size} points \(100%\), \d+ s$",
                     proc.stderr, re.M), proc.stderr


def test_progress_lines_every_tenth_or_every_ten_seconds(capsys):
    """A plain progress line every tenth of the work when points are quick, every
    10 s when they are slow, with the time left at the pace so far."""
    from sweepcore.resumable import ProgressLines
    now = [0.0]
    quick = ProgressLines(1000, clock=lambda: now[0])
    for _ in range(1000):           # 1 ms a point
        now[0] += 0.001
        quick.update(1)
    lines = capsys.readouterr().err.splitlines()
    assert [ln.split("(")[1].split("%")[0] for ln in lines] == \
        [str(p) for p in range(10, 101, 10)]
    now[0] = 0.0
    slow = ProgressLines(1000, clock=lambda: now[0])
    for _ in range(50):             # 4 s a point: a line every third point
        now[0] += 4.0
        slow.update(1)
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 50 // 3
    assert lines[0] == f"sweep: 3 of 1,000 points (0%), 12 s, about {4 * 997} s left"


def test_info_and_export_read_a_result_without_numba(small_run, tmp_path):
    """``sweepcore info`` and ``export`` only read a file: they import neither numba
    nor the kernels (a header cost 1.1 s of CPU with them, 0.75 s without)."""
    d, _ = small_run
    code = ("import sys\nfrom sweepcore.cli import main\n"
            f"assert main(['info', {str(d / 'small.nc')!r}]) == 0\n"
            f"assert main(['export', {str(d / 'small.nc')!r}, '--csv', "
            f"{str(tmp_path / 'small.csv')!r}]) == 0\n"
            "print(sorted(m for m in ('numba', 'sweepcore._kernels', 'matplotlib') "
            "if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120, cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().splitlines()[-1] == "[]"


def test_help_answers_without_numba():
    """``sweepcore --help`` imports neither numba nor xarray (it took 10 s wall on a
    loaded machine importing them): the package and the command import lazily."""
    code = ("import sys\nfrom sweepcore.cli import build_parser\n"
            "build_parser().format_help()\n"
            "print(sorted(m for m in ('numba', 'xarray', 'matplotlib', 'scipy') "
            "if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[]"
