"""Right or flagged at the edges of the law family: one label for one motion.

Every expected value here comes from the independent scipy reference
(``tests/reference.py``) or from a closed form, never from sweepcore's own earlier
output. Scans across a window must be monotone in their labels (one label change
per boundary), and a point that is not right within the contract must say so in its
status.

* constant Coulomb law (alpha1 = alpha2 = c = 0, r_k = r_y) from the stuck start:
  the circle of radius |v|/omega through the breakaway point (eq. 39), label
  ``slip_cycle`` at every speed of a scan (it was ``neutral`` where the closed-form
  arc ended exactly on the touch and the touch was dropped);
"""
import math

import numpy as np
import pytest

import sweepcore as sc
from sweepcore._kernels import codes

R = codes.REGIME_NAMES
S = codes.STATUS_NAMES


def changes(labels) -> int:
    """Number of label changes along a scan."""
    return sum(a != b for a, b in zip(labels[:-1], labels[1:]))


def _coulomb_cases():
    """Random sliders (fixed seed) and one where the dropped touch was seen."""
    rng = np.random.default_rng(2911)
    cases = [(22.847656556327163, 0.1548972049032519, 0.4902051347772474,
              0.01607671889669675)]
    for _ in range(4):
        m, k, r_y = 10 ** rng.uniform(-3, 3, 3)
        cases.append((m, k, r_y, 10 ** rng.uniform(-4, 2) * rng.choice([-1.0, 1.0])))
    return cases


@pytest.mark.parametrize("m, k, r_y, v0", _coulomb_cases())
@pytest.mark.parametrize("method", ["auto", "dop853"])
def test_constant_coulomb_law_from_the_stuck_start_is_its_grazing_circle(m, k, r_y, v0,
                                                                         method):
    """A +-10 % scan of v (201 speeds): every point is the circle of radius |v|/omega
    about r_y/k through the breakaway point (eq. 39), labelled slip_cycle."""
    v = np.linspace(0.9, 1.1, 201) * v0
    ds = sc.sweep(sc.Grid(m=m, k=k, r_y=r_y, v=v), method=method, progress=False)
    w = math.sqrt(k / m)
    assert {R[int(r)] for r in ds.regime.values} == {"slip_cycle"}
    assert {S[int(s)] for s in ds.status.values} == {"ok"}
    L = r_y / k + np.abs(v) / w
    np.testing.assert_array_less(np.abs(ds.amplitude.values - np.abs(v) / w), 1e-8 * L)
    np.testing.assert_allclose(ds.period.values, 2 * math.pi / w, rtol=1e-8)
