"""The benchmark pipeline runs end to end on a handful of points (no timing asserted).

``python benchmarks/run.py --smoke`` shrinks every section (a 12 x 12 map, one setting
per method, two peer points) and writes its JSON, figures and README into a temporary
directory; this proves the scripts that produce benchmarks/README.md still work with
the current package, not how fast anything is.
"""
import json
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
pytest.importorskip("scipy")
pytest.importorskip("matplotlib")


@pytest.fixture(scope="module")
def smoke(tmp_path_factory):
    if str(ROOT) not in sys.path:
        sys.path.insert(0, str(ROOT))
    from benchmarks import run
    out = tmp_path_factory.mktemp("bench")
    readme = out / "README.md"
    run.main(["--smoke", "--outdir", str(out), "--readme", str(readme),
              "--keep-numba-cache"])
    return out, readme


def test_every_section_writes_json_with_machine_and_commit(smoke):
    out, _ = smoke
    for name in ("hopf_map", "work_precision", "throughput", "peers", "cost_model"):
        data = json.loads((out / f"{name}.json").read_text())
        assert data["mode"] == "smoke"
        assert {"date", "git_commit", "cpu_model", "numba", "numba_threading_layer"} \
            <= set(data["machine"])


def test_figures_and_readme_are_written(smoke):
    out, readme = smoke
    for png in ("hopf_map.png", "work_precision.png", "throughput.png"):
        assert (out / png).stat().st_size > 1000
    text = readme.read_text()
    for heading in ("1. Hopf map", "2. Work-precision", "3. Throughput", "4. Peers",
                    "5. Cost model"):
        assert heading in text


def test_map_results_agree_with_references(smoke):
    """Loose sanity on accuracy (not speed): the pipeline compares like with like."""
    out, _ = smoke
    hopf = json.loads((out / "hopf_map.json").read_text())
    acc = hopf["accuracy"]
    assert acc["map"]["1e-08"]["n_compared"] > 0
    assert acc["map"]["1e-08"]["amplitude_abs"]["max"] < 1e-3
    assert acc["scipy_check_regimes_agree"]
    wp = json.loads((out / "work_precision.json").read_text())
    exact = next(r for r in wp["settings"] if r["method"] == "exact")
    assert exact["const"]["amplitude_abs_max"] < 1e-12     # closed form, start stuck


def test_pair_choice_reference_is_within_scipys_tolerance_range():
    """The reference of benchmarks/pair_choice.py asks scipy for an rtol it honours
    (100 eps): no warning, and the state after one period agrees with the tightest
    ladder rung to better than 1e-10 L."""
    import warnings
    if str(ROOT) not in sys.path:
        sys.path.insert(0, str(ROOT))
    from benchmarks import pair_choice
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = pair_choice.one_point(5.5, 0.01)
    tight = [r for r in res["rows"] if r["method"] == "DOP853" and r["rtol"] == 1e-11]
    assert tight and tight[0]["error_over_L"] < 1e-10
