"""Shared fixtures. numba kernels are compiled (or loaded from cache) once per session."""
import math
import os

# Under pytest-xdist each worker keeps its own kernel cache below the usual one: a
# cache that both workers had written was once left with an entry that failed at its
# call ("NRT_adapt_ndarray_to_python: 'descr' is NULL", 2026-12-08), and a directory
# one process writes alone cannot be raced. Set before sweepcore is imported.
_WORKER = os.environ.get("PYTEST_XDIST_WORKER")
if _WORKER and not os.environ.get("NUMBA_CACHE_DIR"):
    _BASE = os.environ.get("SWEEPCORE_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "sweepcore")
    os.environ["SWEEPCORE_CACHE_DIR"] = os.path.join(_BASE, "test-" + _WORKER)

import numpy as np
import pytest

import sweepcore as sc

PAPER = dict(m=5.0, k=50.0, r_y=10.0, v=5.0)          # the paper's Fig. 3 values
# the [axes] of a study of the bSTAB friction case (Stribeck law with damping), v apart
BSTAB_AXES = "[axes]\nm = 1.0\nk = 1.0\nr_y = 1.0\nr_k = 0.5\nv_s = 0.5\nc = 0.1\n"


@pytest.fixture(scope="session", autouse=True)
def warm_kernels():
    """Compile the kernels once (cache=True makes later sessions cheap)."""
    p = sc.Params(**PAPER, alpha1=1.0, alpha2=0.01)
    sc.attractor(p)
    sc.simulate(p, 0.1)
    yield


@pytest.fixture
def paper():
    return dict(PAPER)


def omega(m, k):
    return math.sqrt(k / m)


def radius(x, xdot, centre, w):
    """Distance from (centre, 0) in the (x, xdot/omega) plane."""
    return np.hypot(np.asarray(x) - centre, np.asarray(xdot) / w)


@pytest.fixture(scope="session")
def warm_sweep():
    """Compile the sweep's two kernels (serial ``attractor_rows`` for dask tasks,
    ``attractor_rows_parallel`` for the direct path) with a two-point sweep."""
    from sweepcore.grid import Grid
    from sweepcore.sweep import sweep

    grid = Grid(m=5.0, k=50.0, r_y=10.0, v=[1.0, 2.0], alpha1=1.0, alpha2=0.01)
    sweep(grid, progress=False)
    sweep(grid, scheduler="synchronous", progress=False)


@pytest.fixture(scope="session")
def paper_map(warm_sweep):
    """The paper's slider on a small (v, alpha2) Hopf map (m=5, k=50, r_y=10,
    alpha1=1; v* = 5.77, 4.08, 3.33 cm/s inside the v range)."""
    from sweepcore.grid import Grid

    return Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, v=np.linspace(3.0, 8.0, 24),
                alpha2=[0.01, 0.02, 0.03])
