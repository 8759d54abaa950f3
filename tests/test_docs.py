"""The documentation says what the code does, and the repository stands alone.

What is proven:
* docs/variables.md lists every variable a sweep and a simulation hold, with the
  units the files carry, and every regime, status and event code with its number,
  exactly as ``sweepcore._kernels.codes`` and ``sweepcore.variables`` define them (a
  new observable or code fails here until it is documented);
* the README's speed block is the one ``benchmarks/report.py`` generates from the
  saved full-mode results (no figure typed by hand, none left stale);
* no tracked text cites a document outside the repository (the team's shared
  folder, its research notes, issue texts or session notes; patterns in
  ``FOREIGN``), and the LICENSE matches pyproject's MIT.
"""
import re
import sys
from pathlib import Path

import numpy as np
import pytest

import sweepcore as sc
from sweepcore import variables
from sweepcore._kernels import codes

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "variables.md"


def _sections(text: str) -> dict:
    """``{heading: body}`` for the ``## `` and ``### `` sections of a markdown text."""
    parts = re.split(r"^#{2,3} (.+)$", text, flags=re.M)
    return {parts[i].strip(): parts[i + 1] for i in range(1, len(parts), 2)}


def _unit_rows(body: str) -> dict:
    return dict(re.findall(r"^\| `([A-Za-z_0-9]+)` \| ([^|]+?) \|", body, flags=re.M))


def _code_rows(body: str) -> dict:
    return {int(c): n for c, n in re.findall(r"^\| (\d+) \| `([a-z_]+)` \|", body,
                                             flags=re.M)}


@pytest.fixture(scope="module")
def doc():
    return _sections(DOC.read_text())


@pytest.fixture(scope="module")
def documented_units(doc):
    rows = {}
    for heading, body in doc.items():
        if not heading.endswith("codes"):
            for name, units in _unit_rows(body).items():
                rows.setdefault(name, set()).add(units)
    return rows


def test_every_observable_is_documented_with_its_units(documented_units):
    for name, (_col, units, *_rest) in variables.OBSERVABLES.items():
        assert units in documented_units.get(name, ()), (name, units)
    for name, (units, *_rest) in variables.ANALYTIC.items():
        assert units in documented_units.get(name, ()), (name, units)


def _assert_documented(ds, documented_units):
    for name, var in ds.variables.items():
        assert name in documented_units, f"{name} is not in docs/variables.md"
        assert var.attrs["units"] in documented_units[name], \
            (name, var.attrs["units"], documented_units[name])


def test_every_variable_of_a_sweep_is_documented(documented_units):
    ds = sc.sweep(sc.Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, v=np.linspace(1, 8, 4),
                          alpha2=[0.005, 0.01], x0=[0.0, 0.5], xdot0=1.0))
    _assert_documented(ds, documented_units)


def test_every_variable_of_a_simulation_is_documented(documented_units):
    ds = sc.simulate(sc.Params(m=5.0, k=50.0, r_y=10.0, v=5.0), 3.0)
    _assert_documented(ds, documented_units)


def test_every_variable_of_a_boundary_file_is_documented(documented_units):
    grid = sc.Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, v=[1.0], alpha2=[0.01, 0.02])
    ds = sc.locate_boundaries(grid, along="v", bracket=(1.0, 10.0))
    _assert_documented(ds, documented_units)
    cont = sc.continue_boundary(grid, over="alpha2", bracket=(1.0, 10.0))
    _assert_documented(cont, documented_units)
    diag = sc.bifurcation_diagram(sc.Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0,
                                          v=np.linspace(4.0, 6.5, 4), alpha2=0.01))
    _assert_documented(diag, documented_units)


def test_code_tables_match_the_code_table(doc):
    assert _code_rows(doc["Boundary search codes"]) == codes.SEARCH_NAMES
    assert _code_rows(doc["Regime codes"]) == codes.REGIME_NAMES
    assert _code_rows(doc["Status codes"]) == codes.STATUS_NAMES
    written = {k: n for k, n in codes.EVENT_NAMES.items() if k <= codes.EV_ABNORMAL_STOP}
    assert _code_rows(doc["Event codes"]) == written


def test_readme_speed_block_is_generated_from_the_saved_results():
    if str(ROOT) not in sys.path:
        sys.path.insert(0, str(ROOT))
    from benchmarks import report
    text = (ROOT / "README.md").read_text()
    block = text.split(report.START, 1)[1].split(report.END, 1)[0]
    assert block.strip() == report.readme_block(ROOT / "benchmarks" / "results" /
                                                "full").strip(), \
        "README speed block is stale: run `python -m benchmarks.report`"


# Citations of documents a user does not have, as patterns that also match across
# the line breaks of wrapped prose: the team's shared folder and its performance
# note, session notes, issue texts.
FOREIGN = tuple(re.compile(p) for p in (
    r"\bshared[/\\]", r"performance\.md", r"closing\s+notes?\b", r"\bthe\s+issue\b",
    r"\bissue's"))
TEXT = {".py", ".md", ".toml", ".txt", ".json", ".cfg", ".ini", ".yml", ".yaml"}
SKIP = {".git", "out", ".venv", "__pycache__", ".pytest_cache", ".hypothesis",
        "quick", "build", "dist"}


def test_nothing_cites_files_outside_the_repository():
    hits = []
    for path in ROOT.rglob("*"):
        rel = path.relative_to(ROOT)
        if (path.suffix not in TEXT or not path.is_file() or set(rel.parts) & SKIP
                or rel.parts[0].endswith(".egg-info") or path == Path(__file__)):
            continue
        text = path.read_text(errors="replace").lower()
        hits += [f"{rel}: {pat.pattern}" for pat in FOREIGN if pat.search(text)]
    assert hits == []


def test_license_is_mit_as_pyproject_says():
    text = (ROOT / "LICENSE").read_text()
    assert text.startswith("MIT License")
    assert "Copyright (c)" in text and "sweepcore developers" in text
    assert '\nlicense = "MIT"\n' in (ROOT / "pyproject.toml").read_text()


def test_only_a_full_run_rewrites_the_tracked_tables():
    """A quick (or smoke, or redirected) benchmark run writes beside its own results."""
    if str(ROOT) not in sys.path:
        sys.path.insert(0, str(ROOT))
    from benchmarks import common
    from benchmarks.run import summary_targets
    full = common.RESULTS / "full"
    assert summary_targets("full", full) == (common.BENCH / "README.md", True)
    quick = common.RESULTS / "quick"
    assert summary_targets("quick", quick) == (quick / "README.md", False)
    assert summary_targets("full", "/tmp/x", outdir_arg="/tmp/x") == \
        (Path("/tmp/x") / "README.md", False)
    assert summary_targets("smoke", "/tmp/s", "/tmp/s", "none") == (None, False)
    ignored = (ROOT / ".gitignore").read_text()
    assert "benchmarks/results/quick/" in ignored


# ------------------------------------------------ what a new user copies from it
def _readme_blocks(language: str) -> list[str]:
    text = (ROOT / "README.md").read_text()
    return re.findall(rf"```{language}\n(.*?)```", text, flags=re.S)


# calls run for what they do, not for a value to show
_ACTIONS = {"print", "savefig", "plot", "to_csv"}


def test_readme_python_blocks_print_what_they_show():
    """Saved to a file and run, a README block shows what its comments promise: no
    bare expression whose value only an interactive prompt would print."""
    import ast
    bare = []
    for block in _readme_blocks("python"):
        for node in ast.walk(ast.parse(block)):
            if not isinstance(node, ast.Expr):
                continue
            f = node.value.func if isinstance(node.value, ast.Call) else None
            name = getattr(f, "id", None) or getattr(f, "attr", None)
            if name not in _ACTIONS:
                bare.append(ast.unparse(node)[:60])
    assert bare == []


def test_readme_commands_parse():
    """Every ``sweepcore`` command the README writes out is a valid command line
    (``sweepcore simulate --law-table curve.csv`` lacked the slider's --m, --k, --v)."""
    import shlex
    from sweepcore.cli import build_parser
    text = (ROOT / "README.md").read_text()
    commands = [line.split("#")[0].strip() for block in _readme_blocks("bash")
                for line in block.splitlines() if line.startswith("sweepcore ")]
    commands += [c for c in re.findall(r"`(sweepcore [^`]*)`", text)
                 if "[" not in c and len(c.split()) > 2]     # not a mere name
    assert any("--law-table" in c for c in commands)
    parser = build_parser()
    for command in commands:
        try:
            parser.parse_args(shlex.split(command)[1:])
        except SystemExit:
            pytest.fail(f"the README's command does not parse: {command}")


def test_study_files_state_no_unmeasured_duration():
    """A study's header says what a run costs only where it was measured: the basins
    study said "(a few seconds)" and took 189 s from a cold cache."""
    claims = [f"{p.name}: {line.strip()}" for p in sorted((ROOT / "studies").glob("*.toml"))
              for line in p.read_text().splitlines()
              if line.startswith("#") and re.search(r"few seconds|\bseconds\)", line)]
    assert claims == []
