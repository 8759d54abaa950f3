"""Every kind of file sweepcore writes passes the IOOS compliance-checker's CF suite.

What is proven: a sweep file (``sweep`` -> ``write_netcdf``), a simulation file
(``simulate`` -> ``write_netcdf``) and the files of the ``sweepcore`` command (run,
simulate) have no high- or medium-priority failure in the checker's ``cf:1.8``
suite, apart from the one notice that the Conventions attribute names a later CF
version (CF-1.11) than the suite checks; and they pass sweepcore's own
:func:`sweepcore.check_cf`. Skipped when compliance-checker is not installed (it is
not a dependency: ``pip install compliance-checker``).
"""
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import sweepcore as sc

checker = pytest.importorskip("compliance_checker.runner")
# the checker's own deprecation notices (its ioos_sos plug-in) are not ours
pytestmark = pytest.mark.filterwarnings("ignore::DeprecationWarning")

ROOT = Path(__file__).resolve().parents[1]
CONVENTIONS_NOTICE = 'Conventions global attribute does not contain "CF-1.8"'


def cf_failures(path) -> list[str]:
    """High- and medium-priority failures of the cf:1.8 suite on ``path``."""
    from compliance_checker.runner import CheckSuite
    suite = CheckSuite()
    suite.load_all_available_checkers()
    ds = suite.load_dataset(str(path))
    groups = suite.run_all(ds, ["cf:1.8"], skip_checks=[])
    results, errors = groups["cf:1.8"]
    assert not errors, errors
    out = []
    for r in results:
        if r.weight >= 2 and r.value is not None:
            scored, possible = r.value if isinstance(r.value, tuple) else \
                (int(r.value), 1)
            if scored < possible:
                out += [m for m in r.msgs if CONVENTIONS_NOTICE not in m]
    return out


def test_sweep_file(tmp_path):
    ds = sc.sweep(sc.Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0,
                          v=np.linspace(1.0, 8.0, 5), alpha2=[0.005, 0.01]))
    path = sc.write_netcdf(ds, tmp_path / "sweep.nc")
    assert sc.check_cf(sc.open_result(path)) == []
    assert cf_failures(path) == []


@pytest.mark.parametrize("method", ["auto", "exact"])
def test_simulation_file(tmp_path, method):
    alpha = dict(alpha1=1.0, alpha2=0.01) if method == "auto" else {}
    ds = sc.simulate(sc.Params(m=5.0, k=50.0, r_y=10.0, v=5.0, **alpha), 5.0,
                     method=method)
    path = sc.write_netcdf(ds, tmp_path / "sim.nc")
    assert sc.check_cf(sc.open_result(path)) == []
    assert cf_failures(path) == []


def test_files_of_the_command(tmp_path):
    (tmp_path / "s.toml").write_text(
        'title = "t"\n[axes]\nm = 5.0\nk = 50.0\nr_y = 10.0\n'
        'v = { start = 1.0, stop = 5.0, num = 3 }\n[solver]\nmethod = "exact"\n')
    env = {"PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg", "PATH": ""}
    for argv in (["run", "s.toml", "--no-png", "-q"],
                 ["simulate", "--m", "5", "--k", "50", "--r-y", "10", "--v", "5",
                  "--t-end", "3", "-o", "sim.nc"]):
        proc = subprocess.run([sys.executable, "-m", "sweepcore", *argv], cwd=tmp_path,
                              env=env, capture_output=True, text=True, timeout=300)
        assert proc.returncode == 0, proc.stderr
    for name in ("s.nc", "sim.nc"):
        assert sc.check_cf(sc.open_result(tmp_path / name)) == [], name
        assert cf_failures(tmp_path / name) == [], name
