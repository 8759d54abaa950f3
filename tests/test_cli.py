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
* ``sweepcore plot`` draws sweeps and simulations.
Subprocess tests run ``python -m sweepcore`` with the source tree on PYTHONPATH.
"""
from __future__ import annotations

import math
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

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
    with xr.open_dataset(tmp_path / "run.nc") as ds:
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
