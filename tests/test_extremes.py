"""Every velocity extreme of the attractor, against the independent reference.

What is proven: a stick-slip cycle whose slip reverses and overshoots the belt speed
before it sticks (the paper's law, m = k = r_y = v = 1, alpha2 = 0.02, c = 0) reports
its overshoot in ``xdot_max`` and ``velocity_amplitude``, at overshoots of 1e-2, 1e-3
and 1e-4 of v, for the analytic kind (dop853, dopri5, rk4) and a table of the same
law. The overshoot's maximum lies inside the step that ends on the stick, so a driver
that looks for extrema of xdot only in whole steps reports ``xdot_max = v`` exactly:
off by the whole overshoot, 1e3 to 1e5 times the tolerance below.

The reference (``tests/reference.py``: scipy DOP853 at rtol 1e-12 with exact events,
among them the extrema of x') gives alpha1 for each overshoot by a root solve, and
the cycle's extremes; nothing here is a stored number.
"""
import math

import numpy as np
import pytest
from scipy.optimize import brentq

import sweepcore as sc
from sweepcore.laws import TableLaw

import reference as R
import reference_law as RL

SLIDER = dict(m=1.0, k=1.0, r_y=1.0, v=1.0)
ALPHA2 = 0.02
OVERSHOOTS = (1e-2, 1e-3, 1e-4)
TOL = 1e-8                                  # the default tolerance
# the answer's error bound on a velocity [cm/s]: 10 tol |v| (the reference's error
# is 1e-12 |v|; the engine's measured error at the default is below 1e-9 |v|)
VTOL = 10.0 * TOL * SLIDER["v"]


def _reference(alpha1):
    return R.reference_stick_slip_cycle(SLIDER["m"], SLIDER["k"], SLIDER["r_y"],
                                        SLIDER["v"], alpha1, ALPHA2)


@pytest.fixture(scope="module")
def cases():
    """{overshoot: (alpha1, reference cycle)}: alpha1 where the reference's
    xdot_max - v equals the overshoot (times v)."""
    out = {}
    for ov in OVERSHOOTS:
        a1 = brentq(lambda a: _reference(a)["xdot_max"] - SLIDER["v"] * (1.0 + ov),
                    0.40, 0.45, xtol=1e-13)
        out[ov] = a1, _reference(a1)
    return out


@pytest.mark.parametrize("overshoot", OVERSHOOTS)
@pytest.mark.parametrize("method,dt", [("auto", None), ("dopri5", None), ("rk4", 1e-3)])
def test_an_overshoot_before_the_stick_is_the_velocity_maximum(cases, overshoot, method,
                                                                dt):
    alpha1, ref = cases[overshoot]
    assert ref["xdot_max"] - SLIDER["v"] == pytest.approx(overshoot, rel=1e-9)
    a = sc.attractor(sc.Params(**SLIDER, alpha1=alpha1, alpha2=ALPHA2), method=method,
                     dt=dt)
    assert (a.regime, a.status) == ("stick_slip", "ok")
    assert abs(a.xdot_max - ref["xdot_max"]) <= VTOL
    assert abs(a.velocity_amplitude - 0.5 * (ref["xdot_max"] - ref["xdot_min"])) <= VTOL


def test_an_overshoot_of_a_table_law_is_the_velocity_maximum(cases):
    """The same law as a table: the reference integrates the table's own piecewise
    polynomial (``reference_law.pp_branch``), so the overshoot is the table's."""
    alpha1, _ref = cases[1e-3]
    law = TableLaw.from_function(
        lambda s: np.sign(s) * SLIDER["r_y"] - alpha1 * s + ALPHA2 * s ** 3,
        speed_max=4.0, tol=1e-12, name="overshoot")
    mod = RL.LawModel(SLIDER["m"], SLIDER["k"], SLIDER["v"], 0.0,
                      RL.pp_branch(*law._pos[:2]), max(law.static_limits()))
    graze = 100.0 * 1e-12 * (mod.v + mod.r_y / math.sqrt(mod.k * mod.m))
    segments, _events, closed = R._hybrid(mod, 0.0, mod.x_s, 0.0, 40.0 * math.pi, 1e-12,
                                          side=-1, stop_at_breakaway=True,
                                          graze_tol=graze)
    assert closed
    _x_max, _x_min, xd_max, xd_min, _q, _stick = R._observe(mod, segments)
    assert xd_max - SLIDER["v"] > 0.5e-3 * SLIDER["v"]          # it overshoots
    a = sc.attractor(sc.Params(m=SLIDER["m"], k=SLIDER["k"], v=SLIDER["v"], law=law))
    assert (a.regime, a.status) == ("stick_slip", "ok")
    assert abs(a.xdot_max - xd_max) <= VTOL
    assert abs(a.velocity_amplitude - 0.5 * (xd_max - xd_min)) <= VTOL
