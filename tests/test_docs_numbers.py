"""Every shipped study runs, and the numbers the documentation quotes from it are the
numbers it prints now.

What is proven:
* every study of ``studies/`` runs as documented: the scripts (``python
  studies/NAME.py --out DIR``), the table studies (``paper_claims``,
  ``method_orders``, ``normal_form``; the last without ``--write`` writes nothing),
  every TOML study through ``sweepcore run`` and the boundary study through
  ``sweepcore boundary``, and ``studies/run_all.py`` itself;
* every markdown table row those table studies print stands verbatim in the page
  that quotes it (docs/physics.md, docs/methods.md), and the table quoted in the
  README's method list agrees with them;
* the numbers docs/studies.md and README.md quote from the other studies (shares,
  boundaries, amplitudes, ranges) are those the scripts and ``sweepcore info``
  print, formatted as the docs write them;
* ``sweepcore info`` and ``sweepcore plot`` handle every file a study writes
  (multi-run simulations, maps, cuts, boundary files).

The studies are cheap once the kernels are compiled (the largest, ``hopf_map``,
65,536 points, takes seconds), so they run on their full grids.
"""
from __future__ import annotations

import math
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from sweepcore.cli import main

ROOT = Path(__file__).resolve().parents[1]
STUDIES = ROOT / "studies"
SCRIPTS = ("paper_fig3", "paper_fig4", "paper_fig5", "design_map", "initial_conditions")
TABLES = {"paper_claims": "physics.md", "method_orders": "methods.md",
          "normal_form": "physics.md", "law_accuracy": "physics.md"}
TOML = sorted(p.stem for p in STUDIES.glob("*.toml"))


def _doc(name: str) -> str:
    text = (ROOT / name).read_text() if name == "README.md" else \
        (ROOT / "docs" / name).read_text()
    return re.sub(r"\s+", " ", text)          # quotes may wrap across lines


def _run(name: str, *args) -> str:
    env = {**os.environ, "NUMBA_NUM_THREADS": "1"}
    done = subprocess.run([sys.executable, str(STUDIES / f"{name}.py"), *args],
                          capture_output=True, text=True, env=env, cwd=STUDIES,
                          timeout=900)
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout


@pytest.fixture(scope="module")
def out(tmp_path_factory):
    return tmp_path_factory.mktemp("studies")


@pytest.fixture(scope="module")
def printed(out):
    """What every script and table study prints (each run once)."""
    text = {name: _run(name, "--out", str(out)) for name in SCRIPTS}
    text.update({name: _run(name) for name in TABLES})
    return text


@pytest.fixture(scope="module")
def toml_studies(out, printed):
    """The TOML studies and the boundary study run as documented (from the
    repository's root, the boundary study's map as its ``over`` names it), and what
    ``sweepcore info`` prints about each result."""
    cwd = Path.cwd()
    info = {}
    try:
        os.chdir(out)
        (out / "out").mkdir(exist_ok=True)
        # plain sweeps first: a boundary study draws over a map
        for name in sorted(TOML, key=lambda n: _command(n) != "run"):
            assert main([_command(name), str(STUDIES / f"{name}.toml"), "-o",
                         f"out/{name}.nc", "-q"]) == 0, name
    finally:
        os.chdir(cwd)
    return out / "out"


def _command(name: str) -> str:
    """The command that runs a TOML study: boundary, basins or run."""
    text = (STUDIES / f"{name}.toml").read_text()
    for table in ("boundary", "basins"):
        if re.search(rf"^\[{table}\]", text, flags=re.M):
            return table
    return "run"


def _info(path, capsys) -> str:
    capsys.readouterr()
    assert main(["info", str(path)]) == 0
    return capsys.readouterr().out


def _e(x: float) -> str:
    """``x`` as the docs write small numbers: two digits, ``2.7e-3``."""
    mantissa, exponent = f"{x:.1e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def _number(pattern: str, text: str, group: int = 1) -> str:
    found = re.search(pattern, text)
    assert found, f"{pattern!r} not in the output:\n{text}"
    return found.group(group)


# ------------------------------------------------------------------ tables
@pytest.mark.parametrize("name", list(TABLES))
def test_printed_tables_are_quoted_verbatim(name, printed):
    doc = (ROOT / "docs" / TABLES[name]).read_text()
    rows = [line for line in printed[name].splitlines()
            if line.startswith("|") and not line.startswith("|---")]
    assert rows
    if name == "normal_form":      # quoted as its range and largest remainder
        low = _number(r"coefficient (\S+) \.\.", printed[name])
        worst = float(_number(r"largest remainder (\S+);", printed[name]))
        methods = _doc("methods.md")
        bound = math.ceil(worst * 100) / 100      # a bound: rounded up
        assert f"below `{bound:.2f} A ((1 + G) q/omega)^2`" in methods
        assert abs(float(low) - 7 / 18) < 2e-3
        return
    missing = [row for row in rows if row not in doc]
    assert not missing, f"rows {name} prints that {TABLES[name]} lacks: {missing}"


def test_readme_quotes_the_gps_hopf_shift(printed):
    shifts = dict(re.findall(r"\| gps \| dt = (\S+) \| \S+ \| \S+ \| ([+-][\d.]+)%",
                             printed["method_orders"]))
    readme = _doc("README.md")
    assert f"+{float(shifts['0.01'][1:]):.1f} % at dt = 0.01 s" in readme
    assert f"+{shifts['0.0001'][1:]} % at 1e-4 s" in readme


# ------------------------------------------------------------------ scripts
def test_paper_fig3_to_5_numbers(printed):
    studies = _doc("studies.md")
    fig4 = printed["paper_fig4"]
    v_star = _number(r"v\* = (\S+) cm/s", fig4)
    lowest = _number(r"friction (\S+) kN", fig4)
    assert f"v* = {v_star} cm/s" in studies
    assert f"`r_y - (2/3) alpha1 v* = {lowest} kN`" in studies
    fig5 = printed["paper_fig5"]
    regimes = re.findall(r"alpha2 = (\S+): q = (\S+) 1/s -> (\w+) \(amplitude (\S+) cm, "
                         r"mean (\S+) cm, stick fraction (\S+), status (\w+)", fig5)
    assert [r[2] for r in regimes] == ["equilibrium", "equilibrium", "stick_slip"]
    assert all(r[6] == "ok" for r in regimes)
    assert f"equilibrium at `x_eq = {regimes[0][4]} cm`" in studies
    assert "| 1/75 | 0 | equilibrium" in studies
    assert f"one stick of {regimes[2][5]} of the period | {regimes[2][3]} |" in studies
    swing = _number(r"half-range (\S+) cm", fig5)
    assert f"half-range {swing} cm at 60 s" in studies


def test_design_map_numbers(printed):
    text, studies = printed["design_map"], _doc("studies.md")
    ryv = text.split("ryv, speed-dependent friction")[1]
    median = _number(r"median (\S+) cm", ryv)
    assert f"median change along r_y is {median} cm" in studies
    high = float(_number(r"on cycles: \S+ \.\. (\S+);", ryv))
    assert f"up to {high:.0f} times `v/omega`" in studies
    up_to = _number(r"along r_y at fixed v: up to (\S+) cm", ryv)
    assert f"by up to {float(up_to):.1f} cm along r_y" in studies
    share = _number(r"amplitude rises with v between (\S+) %", ryv)
    assert f"rises with v on only {float(share):.0f} % of neighbouring pairs" in studies
    km = text.split("km, speed-dependent friction")[1]
    span = _number(r"on cycles: (\S+ \.\. \S+);", km).replace(" .. ", "-")
    assert f"amplitude {span} times `v/omega`" in studies


def test_initial_conditions_numbers(printed):
    text, studies = printed["initial_conditions"], _doc("studies.md")
    lo, hi, avg = re.search(r"start stuck on the belt: A/sqrt\(v\* - v\) = (\S+) \.\. "
                            r"(\S+) \(averaging: sqrt\(8 v\*\)/omega = (\S+)\)",
                            text).groups()
    assert f"`A/sqrt(v* - v)` = {lo}-{hi} against {avg}" in studies
    stick = _number(r"stick_slip: amplitude (\S+) \.\.", text)
    slip = _number(r"slip_cycle: amplitude (\S+) \.\.", text)
    assert f"amplitude {stick} cm from every start" in studies
    assert f"{slip} cm from every start" in studies
    worst = float(_number(r"\|A - min\(R0, v/omega\)\| <= (\S+) cm", text))
    assert f"to {worst:.2g} cm" in studies


# ------------------------------------------------------------------ TOML studies
def test_hopf_map_numbers(toml_studies, capsys):
    text = _info(toml_studies / "hopf_map.nc", capsys)
    studies, readme = _doc("studies.md"), _doc("README.md")
    shares = dict(re.findall(r"^\s+(\w+)\s+\d+\s+\((\S+) %\)", text, flags=re.M))
    assert (f"equilibrium {shares['equilibrium']} %, stick-slip {shares['stick_slip']} "
            f"%, slip cycle {shares['slip_cycle']} %") in studies
    rows = _number(r"measured Hopf boundary: (\d+) of", text)
    assert f"On all {rows} alpha2 rows" in studies
    res = _number(r"grid resolution \+-(\S+)\)", text)
    assert f"(±{res} cm/s)" in studies
    onset = _number(r"measured stick onset: (\d+) of", text)
    assert f"on all {onset} rows where it lies inside the map" in studies
    lower = _number(r"lower edge: \d+ rows, \[(\S+),", text)
    assert f"v above {lower} cm/s" in studies
    upper_rows = _number(r"upper edge: (\d+) rows", text)
    assert f"map, {upper_rows} rows)" in studies
    import xarray as xr
    with xr.open_dataset(toml_studies / "hopf_map.nc") as ds:
        first = float(ds.alpha2[ds.v_stick_onset.notnull()].min())
        band = float(ds.alpha2[ds.v_reversal_lower.notnull()].max())
    assert f"alpha2 >= {_e(first)}" in studies
    assert f"above the map's speeds for alpha2 below {_e(first)}" in readme
    assert f"alpha2 below {_e(band)} and v above" in studies


def test_belt_speed_numbers(toml_studies):
    import xarray as xr
    from sweepcore._kernels import codes
    with xr.open_dataset(toml_studies / "belt_speed.nc") as ds:
        stick = ds.v[ds.regime == codes.R_STICK_SLIP]
        assert f"{ds.sizes['v']} speeds in [{float(ds.v[0]):g}, {float(ds.v[-1]):g}] cm/s" \
            in _doc("studies.md")
        assert f"Stick-slip up to {float(stick.max()):g} cm/s" in _doc("studies.md")


def test_forced_map_numbers(toml_studies, capsys):
    """docs/studies.md's counts of the forced map are what ``sweepcore info`` counts
    in the study's file now (they were the counts of an older engine: ok 65526 and
    unresolved 8 against 65285 and 251)."""
    text = _info(toml_studies / "forced_map.nc", capsys)
    doc = _doc("studies.md")

    def counts(title):
        line = _number(rf"{title}: ([^\n]+)", text)
        return dict(re.findall(r"(\w+(?: measured)?) (\d+)", line))

    sticks = counts("finite sticks per period")
    assert (f"0 on {sticks['0']} points, 2 on {sticks['2']}, 4 on {sticks['4']}, "
            f"6 on {sticks['6']}, 8 on {sticks['8']}, 10 on {sticks['10']}") in doc
    stops = counts("zero-duration stops per period")
    assert f"2 on {stops['2']} points" in doc and f"0 on {stops['0']};" in doc
    single = counts("multiplicity \\(response period / forcing period\\)")
    assert f"multiplicity 1 on every point with a response ({single['1']})" in doc
    block = text.split("status counts:")[1].split("converged:")[0]
    status = dict(re.findall(r"^\s+(\w+)\s+(\d+)", block, flags=re.M))
    said = [f"ok on {status.pop('ok')} points"] + \
        [f"`{name}` on {n}" for name, n in status.items()]
    for phrase in said:
        assert phrase in doc, phrase
    stuck = _number(r"\n\s+stuck\s+(\d+)", text.split("regime counts:")[1])
    assert f"stuck (F0 < r_y: the load never overcomes the friction bound): {stuck} " \
        "points" in doc


# ------------------------------------------------------------------ every file
def test_info_and_plot_handle_every_file_the_studies_write(out, toml_studies, capsys):
    files = sorted(out.glob("*.nc")) + sorted(toml_studies.glob("*.nc"))
    names = {f.name for f in files}
    assert {"paper_fig5.nc", "hopf_map.nc", "boundaries.nc",
            "initial_conditions_vstar.nc"} <= names, names
    for path in files:
        text = _info(path, capsys)
        assert "status: ok ok ok" not in text
        png = path.with_name(path.stem + "_replot.png")
        assert main(["plot", str(path), "-o", str(png)]) == 0, capsys.readouterr().err
        assert png.stat().st_size > 10_000


def test_run_all_runs(tmp_path):
    """``python studies/run_all.py`` (here with every study but one skipped)."""
    sys.path.insert(0, str(STUDIES))
    try:
        import run_all
    finally:
        sys.path.remove(str(STUDIES))
    skip = [n for n in run_all.TOML + run_all.BOUNDARY + run_all.BASINS + run_all.SCRIPTS
            if n != "paper_fig3"]
    env = {**os.environ, "NUMBA_NUM_THREADS": "1"}
    done = subprocess.run([sys.executable, str(STUDIES / "run_all.py"), "--out",
                           str(tmp_path), "--skip", *skip], capture_output=True,
                          text=True, env=env, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    assert (tmp_path / "paper_fig3.nc").is_file()


# ------------------------------------------------------------------ the README
def _blocks(text: str) -> list[str]:
    return re.findall(r"^```[a-z]*\n(.*?)^```", text, flags=re.M | re.S)


def test_readme_commands_and_snippet_run_as_written(tmp_path, monkeypatch, capsys):
    """Every ``sweepcore`` command of the README, from a checkout's root (studies/
    and an empty out/), then the Python snippet; the numbers in its comments are
    the values it computes."""
    import shlex
    (tmp_path / "studies").symlink_to(STUDIES)
    (tmp_path / "out").mkdir()
    monkeypatch.chdir(tmp_path)
    text = (ROOT / "README.md").read_text()
    blocks = _blocks(text)
    commands = [line.split("  #")[0].strip() for b in blocks for line in b.splitlines()
                if line.startswith("sweepcore ")]
    assert len(commands) >= 5, commands
    for command in commands:
        argv = shlex.split(command)[1:]
        assert main(argv) == 0, (command, capsys.readouterr().err)
    names: dict = {}
    for block in blocks:
        if block.startswith("import "):
            exec(compile(block, "README.md", "exec"), names)      # noqa: S102
    snippet = next(b for b in blocks if "p = sc.Params(" in b)
    p, ob = names["p"], names["ob"]
    comment = re.search(r"p\.q, p\.v_star, p\.x_eq\)?\s+# (\S+) 1/s, (\S+) cm/s, (\S+) cm",
                        snippet).groups()
    assert comment == (f"{p.q:.2g}", f"{p.v_star:.3g}", f"{p.x_eq:.3g}")
    amp, period = re.search(r"amplitude=(\S+), regime='(\w+)',\s+#\s+period=(\S+),",
                            snippet).group(1, 3)
    assert (f"{ob.amplitude:.5g}", f"{ob.period:.5g}") == (amp, period)
    assert ob.regime == "stick_slip" and ob.converged
    # every file the README writes lands in out/ (whose contents git ignores)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "studies"]
    assert {"map.nc", "map.csv", "map_units.csv", "map.png"} <= \
        {p.name for p in (tmp_path / "out").iterdir()}


def test_readme_quotes_what_the_boundary_command_prints(toml_studies, capsys):
    """The Hopf point's distance from v* and the stick-onset ratio the README quotes
    are those `sweepcore boundary studies/boundaries.toml` prints (its summary is
    `sweepcore info`'s)."""
    text = _info(toml_studies / "boundaries.nc", capsys)
    readme = _doc("README.md")
    dv = _number(r"\|v_hopf - v\*\| <= (\S+) cm s-1", text)
    assert f"the Hopf point is `v*` to {dv} cm/s on every alpha2" in readme
    assert f"`|v_hopf - v*| <= {dv} cm s-1`" in readme
    onset = _number(r"v_stick_onset / v\* in \[(\S+), ", text)
    assert f"sticking starts at `{onset} v*` for every alpha2" in readme


def test_stribeck_map_numbers(toml_studies, capsys):
    text = _info(toml_studies / "stribeck_map.nc", capsys)
    studies = _doc("studies.md")
    shares = dict(re.findall(r"^\s+(\w+)\s+\d+\s+\((\S+) %\)", text, flags=re.M))
    assert (f"equilibrium {shares['equilibrium']} %, stick-slip {shares['stick_slip']} "
            "%") in studies
    rows, total = _number(r"measured boundary: (\d+) of (\d+) rows", text), \
        _number(r"measured boundary: \d+ of (\d+) rows", text)
    assert f"(on {rows} of the {total} rows;" in studies
    lo, hi = re.search(r"v_measured - v\* in \[(\S+), (\S+)\] cm s-1", text).groups()
    assert f"by {lo} to {hi} cm/s" in studies


# ------------------------------------------------------------------ every study
def test_every_study_is_in_the_table_and_in_run_all():
    """Each TOML study and each study script is a row of docs/studies.md's table
    and is run by studies/run_all.py (stribeck_map was neither)."""
    sys.path.insert(0, str(STUDIES))
    try:
        import run_all
    finally:
        sys.path.remove(str(STUDIES))
    table = re.findall(r"^\| `(\w+)` \|", (ROOT / "docs" / "studies.md").read_text(),
                       flags=re.M)
    for name in TOML + list(SCRIPTS):
        assert name in table, name
    assert sorted(run_all.TOML + run_all.BOUNDARY + run_all.BASINS) == TOML
    assert {_command(n) for n in run_all.TOML} == {"run"}
    assert set(SCRIPTS) <= set(run_all.SCRIPTS)


def test_the_documented_errors_are_what_the_command_prints(tmp_path, monkeypatch,
                                                          capsys):
    """docs/studies.md shows `sweepcore run bad.toml` and `typo.toml`: the lines it
    quotes are the ones printed for such files (the key list included)."""
    studies = (ROOT / "docs" / "studies.md").read_text()
    shown = dict(re.findall(r"^\$ sweepcore run (\w+\.toml)\n(.*)$", studies, flags=re.M))
    assert set(shown) == {"bad.toml", "typo.toml"}
    monkeypatch.chdir(tmp_path)
    (tmp_path / "bad.toml").write_text("[axes]\nk = 50.0\nm = -5.0\nr_y = 10.0\nv = 5.0\n")
    (tmp_path / "typo.toml").write_text("[axes]\nm = 5.0\nk = 50.0\nr_y = 10.0\n"
                                        "v = 5.0\nalpha_1 = 1.0\n")
    for name, line in shown.items():
        capsys.readouterr()
        assert main(["run", name]) == 2
        assert capsys.readouterr().err.strip() == line


SCRIPT_FILES = sorted(p for p in (*STUDIES.glob("*.py"), *(ROOT / "benchmarks").glob(
    "*.py")) if "__main__" in p.read_text() and p.name != "run_all.py")


@pytest.mark.parametrize("script", SCRIPT_FILES, ids=lambda p: p.name)
def test_every_script_answers_help_without_running(script):
    """``--help`` prints the usage and exits at once (method_orders, paper_claims and
    pair_choice ran in full); the clock only guards a script that runs."""
    env = {**os.environ, "NUMBA_NUM_THREADS": "1"}
    # a module of the benchmarks package (relative imports) runs as `python -m`
    as_module = "from . import" in script.read_text()
    argv = ["-m", f"benchmarks.{script.stem}"] if as_module else [str(script)]
    done = subprocess.run([sys.executable, *argv, "--help"], capture_output=True,
                          text=True, env=env, cwd=ROOT if as_module else script.parent,
                          timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.startswith("usage: "), done.stdout[:300]
    assert done.stderr == ""


def test_forced_response_is_quoted_as_it_prints(tmp_path):
    """docs/studies.md says what studies/forced_response.py computes: each band of
    sticks with its multiplicity (it said "sticks once a cycle" up to a frequency
    where the response repeats every 13 forcing periods), the point not ok by its
    status name (the script printed codes), the two sweeps' agreement."""
    text = _run("forced_response", "--only", "response", "--out", str(tmp_path))
    doc = _doc("studies.md")
    bands = re.findall(r"(\d+) per (?:(\d+) )?T at Omega (?:= ([\d.]+)|in "
                       r"\[([\d.]+), ([\d.]+)\]) rad/s", text)
    assert bands, text
    for sticks, n, at, low, high in bands:
        if n:
            assert (f"at {at} rad/s the response repeats only every {n} forcing "
                    f"periods, with {sticks} sticks in them") in doc
        else:
            times = "once" if sticks == "1" else f"{sticks} times"
            assert f"between Omega = {low} and {high} rad/s it sticks {times} a " \
                "forcing period" in doc
    bad = re.findall(r"(up|down) at Omega = ([\d.]+) rad/s \((\w+)\)", text)
    assert not re.search(r"'\d+'", text)                  # names, not codes
    for sweep, at, status in bad:
        assert f"the {sweep} sweep's at {at} rad/s, ends `{status}`" in doc
    if not bad:
        assert "not ok: none;" in text
        assert "Every point of both sweeps ends ok" in doc
    gap = _number(r"where both are ok = (\S+);", text)
    assert f"|A_up - A_down| / max A = {gap}" in doc
