"""Shared fixtures. numba kernels are compiled (or loaded from cache) once per session."""
import math

import numpy as np
import pytest

import sweepcore as sc

PAPER = dict(m=5.0, k=50.0, r_y=10.0, v=5.0)          # the paper's Fig. 3 values


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
