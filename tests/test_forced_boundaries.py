"""Forced boundaries beyond the grid (locate_boundaries / continue_boundary of a
forced grid, sweepcore.boundaries.forced) against closed forms and the
independent reference (tests/reference_forced.py).

What is proven, and to what tolerance:

* c = 0, v = 0, Coulomb friction, one cosine: ``F0_stick_onset`` equals Den
  Hartog's continuous-motion boundary r_y / r_b(beta) (the closed form of
  sweepcore.excitations.theory, itself checked against the reference in
  tests/test_forced_theory.py) within 1e-9 relative at beta = 0.6, 0.8, 1.5, 2, 3,
  with two sticks a period below it and none above, the stops change at the same
  load (two stops above: the reversals stop sticking), in physical units (m = 2,
  k = 8, r_y = 3: the load scales with r_y and the frequency with omega = 2);
* with damping c = 0.05 (no closed form): the reference, started from sweepcore's
  periodic point, finds finite sticks at 1 - 1e-7 of the located load and none at
  1 + 1e-7 (beta = 0.8 and 2);
* continue_boundary along Omega: every step within 1e-9 of Den Hartog's boundary,
  the steps after the first two searched around their prediction (``continued``),
  drawn by plot_result with Den Hartog's curve beside it;
* refusals name the argument and its value.

Runtime: ~10 s of calls after the kernels are compiled.
"""
import math

import numpy as np
import pytest

import sweepcore as sc
from reference_forced import Forced, forced_steady
from sweepcore.boundaries.point import LOCATED
from sweepcore.excitations import theory

M, K, R = 2.0, 8.0, 3.0         # omega = 2 rad/s
OMEGA = math.sqrt(K / M)
BETAS = np.array([0.6, 0.8, 1.5, 2.0, 3.0])


def test_the_stick_onset_in_F0_is_den_hartogs_boundary():
    g = sc.Grid(m=M, k=K, r_y=R, v=0.0, F0=1.1 * R, Omega=BETAS * OMEGA, x0=0.0,
                xdot0=0.0)
    ds = sc.locate_boundaries(g, along="F0", bracket=(1.1 * R, 3.0 * R))
    exact = R / theory.continuous_motion_boundary(BETAS)
    found = ds.F0_stick_onset.values
    assert (ds.stick_status.values == LOCATED).all()
    assert np.abs(found - exact).max() <= 1e-9 * exact.min()
    assert (ds.F0_stick_onset_width.values <= 1e-9 * exact).all()
    assert (ds.sticks_below.values == 2).all() and (ds.sticks_above.values == 0).all()
    # the reversals that stuck become two stops a period, at the same load
    assert np.abs(ds.F0_stops_change.values - exact).max() <= 1e-9 * exact.min()
    assert (ds.stops_below.values == 0).all() and (ds.stops_above.values == 2).all()
    assert ds.F0_stick_onset.attrs["units"] == "kN"
    assert np.allclose(ds.F0_den_hartog.values, exact, rtol=1e-12)


@pytest.mark.parametrize("beta", [0.8, 2.0])
def test_with_damping_the_reference_sticks_below_and_not_above(beta):
    g = sc.Grid(m=1.0, k=1.0, r_y=1.0, v=0.0, c=0.05, F0=1.1, Omega=[beta], x0=0.0,
                xdot0=0.0)
    ds = sc.locate_boundaries(g, along="F0", bracket=(1.1, 3.0))
    onset = float(ds.F0_stick_onset[0])
    assert int(ds.stick_status[0]) == LOCATED
    # damping moves it off the undamped boundary
    assert abs(onset - 1.0 / theory.continuous_motion_boundary(beta)) > 1e-3
    for factor, sticks in ((1 - 1e-7, 2), (1 + 1e-7, 0)):
        F0 = onset * factor
        start = sc.attractor(sc.Params(m=1.0, k=1.0, r_y=1.0, v=0.0, c=0.05, F0=F0,
                                       Omega=beta), x0=0.0, xdot0=0.0, tol=1e-10)
        ref = forced_steady(Forced(1.0, 1.0, c=0.05, F0=F0, Omega=beta, r_y=1.0),
                            x0=start.x_section, xd0=start.xdot_section,
                            multipliers=False)
        assert ref["status"] == "ok" and ref["sticks_per_period"] == sticks, factor


def test_continue_boundary_follows_den_hartogs_boundary_along_omega():
    betas = np.linspace(1.2, 2.4, 7)
    g = sc.Grid(m=M, k=K, r_y=R, v=0.0, F0=1.1 * R, Omega=betas * OMEGA, x0=0.0,
                xdot0=0.0)
    ds = sc.continue_boundary(g, over="Omega", along="F0", bracket=(1.1 * R, 3.0 * R))
    exact = R / theory.continuous_motion_boundary(betas)
    assert np.abs(ds.F0_stick_onset.values - exact).max() <= 1e-9 * exact.min()
    assert (ds.continued.values[2:] == 1).all()
    labels = [ln.get_label() for ln in sc.plot_result(ds).axes[0].get_lines()]
    assert "F0 stick onset (located)" in labels and \
        any(lb.startswith("Den Hartog") for lb in labels)


@pytest.mark.parametrize("kwargs, match", [
    (dict(along="F0"), "bracket is needed when 'F0' is not swept"),
    (dict(along="F0", bracket=(2.0, 1.0)), "lo < hi"),
    (dict(along="F0", bracket=(1.0, 1e300)), "bracket\\[1\\] = 1e\\+300 for 'F0'"),
    (dict(along="F00", bracket=(1.0, 2.0)), "did you mean 'F0'"),
])
def test_refusals_name_the_argument_and_the_value(kwargs, match):
    g = sc.Grid(m=1.0, k=1.0, r_y=1.0, v=0.0, F0=1.1, Omega=[1.5, 2.0])
    with pytest.raises((TypeError, ValueError), match=match):
        sc.locate_boundaries(g, **kwargs)
