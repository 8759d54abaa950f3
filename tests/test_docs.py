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
