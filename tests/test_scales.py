"""Magnitudes the kernels cannot resolve are flagged ``unresolvable_scale``, never
returned as plausible numbers (``sweepcore.law.flag_unresolvable``).

What is proven: a change of units leaves the paper's slider unchanged (period and
amplitude to 1e-12, same regime) while its time scale 1/omega stays below
``TIME_SCALE_MAX``, and beyond it (m = 5e200, alpha2 = 1e298,
v = 5e-100) the point is flagged; m = 1e300 points (q < 0: the
equilibrium is the attractor, by linear stability) are flagged, not reported as
slip cycles of amplitude v/omega; a law too weak per period for the touch tolerance
is flagged at tol 1e-8 while at m 10x lighter the search finds the equilibrium that
q < 0 predicts; constant friction without damping (zeta = 0) keeps its closed-form
circle (eq. 39) at any mass; the boundary searches' batches are flagged too.
"""
import numpy as np
import pytest

import sweepcore as sc
from sweepcore import execute, law
from sweepcore._kernels import codes, layout
from sweepcore.options import make_options

PAPER = dict(m=5.0, k=50.0, r_y=10.0, v=5.0, alpha1=1.0, alpha2=0.01)


def units(tau, lam=1.0):
    """The paper's slider with time measured in units 1/tau s, length in 1/lam cm:
    a period P becomes tau P, an amplitude A becomes lam A."""
    return dict(m=5.0 * tau**2 / lam, k=50.0 / lam, r_y=10.0, v=5.0 * lam / tau,
                alpha1=1.0 * tau / lam, alpha2=0.01 * tau**3 / lam**3)


def one(tol=1e-8, **p):
    ds = sc.sweep(sc.Grid(**p), tol=tol, progress=False)
    return {n: ds[n].item() for n in ("period", "amplitude", "regime", "status", "q",
                                      "omega", "x_eq")}


@pytest.fixture(scope="module")
def paper():
    got = one(**PAPER)
    assert got["status"] == codes.OK and got["regime"] == codes.R_STICK_SLIP
    return got


@pytest.mark.parametrize("tau, lam", [(1e78, 1.0), (1e50, 1e-50), (1e-10, 1e90)])
def test_a_change_of_units_changes_nothing_inside_the_range(paper, tau, lam):
    got = one(**units(tau, lam))
    assert 1.0 / got["omega"] < law.TIME_SCALE_MAX
    assert (got["status"], got["regime"]) == (codes.OK, codes.R_STICK_SLIP)
    assert got["period"] / tau == pytest.approx(paper["period"], rel=1e-12)
    assert got["amplitude"] / lam == pytest.approx(paper["amplitude"], rel=1e-12)


def test_a_time_scale_beyond_the_range_is_flagged():
    """m = 5e200, alpha2 = 1e298, v = 5e-100: stick-slip of period 1.98786e100 s was reported as an ok
    slip cycle of period 1.98747e100 s."""
    p = units(1e100)
    assert (p["m"], p["alpha2"], p["v"]) == pytest.approx((5e200, 1e298, 5e-100))
    got = one(**p)
    assert (got["status"], got["regime"]) == (codes.SCALE, codes.R_FAILED)


@pytest.mark.parametrize("v, alpha2", [(7.0, 0.01), (7.0, 0.02), (5.0, 0.02)])
def test_a_heavy_slider_with_a_stable_equilibrium_is_flagged(v, alpha2):
    got = one(**{**PAPER, "m": 1e300, "v": v, "alpha2": alpha2})
    assert got["q"] < 0.0                       # the equilibrium is the attractor
    assert (got["status"], got["regime"]) == (codes.SCALE, codes.R_FAILED)


def test_a_law_too_weak_for_the_touch_tolerance_is_flagged():
    """pi zeta = 1.47 pi / sqrt(k m) against the touch tolerance 20 tol = 2e-7."""
    weak = one(**{**PAPER, "m": 1e13, "v": 7.0})
    assert (weak["status"], weak["regime"]) == (codes.SCALE, codes.R_FAILED)
    # ten times lighter: resolved, and the equilibrium q < 0 predicts (eq. 43)
    fine = one(**{**PAPER, "m": 1e12, "v": 7.0})
    assert fine["q"] < 0.0
    assert (fine["status"], fine["regime"]) == (codes.OK, codes.R_EQUILIBRIUM)
    assert fine["amplitude"] == 0.0
    # a tighter tolerance resolves the weaker law too
    tight = one(tol=1e-10, **{**PAPER, "m": 1e14, "v": 7.0})
    assert (tight["status"], tight["regime"]) == (codes.OK, codes.R_EQUILIBRIUM)


def test_constant_friction_keeps_its_closed_form_at_any_mass():
    """zeta = 0: the neutral circle of a start stuck, amplitude v/omega (eq. 39)."""
    light = one(**{**PAPER, "alpha1": 0.0, "alpha2": 0.0})
    got = one(**{**PAPER, "m": 1e20, "alpha1": 0.0, "alpha2": 0.0})
    assert (got["status"], got["regime"]) == (codes.OK, light["regime"])
    assert got["amplitude"] == pytest.approx(5.0 / np.sqrt(50.0 / 1e20), rel=1e-9)


def test_a_conservative_field_keeps_its_closed_form_at_any_mass():
    """c = alpha1 (no cubic term): m x'' + k x = -(r_y s + c v), the constant law's
    circles about the breakaway point; zeta > 0 from c and alpha1 alone, but no
    motion changes: the grazing circle of radius v/omega, not unresolvable_scale."""
    got = one(**{**PAPER, "m": 1e20, "alpha2": 0.0, "c": 1.0})
    assert (got["status"], got["regime"]) == (codes.OK, codes.R_SLIP_CYCLE)
    assert got["amplitude"] == pytest.approx(5.0 / np.sqrt(50.0 / 1e20), rel=1e-9)
    weak = one(**{**PAPER, "m": 1e20, "alpha2": 0.0, "c": 1.5})    # c != alpha1
    assert (weak["status"], weak["regime"]) == (codes.SCALE, codes.R_FAILED)


def test_a_static_belt_is_not_flagged_however_weak_the_law():
    """v = 0, started stuck inside the stick band: stuck for ever (|k x0| < r_y)."""
    got = one(**{**PAPER, "m": 1e20, "v": 0.0, "x0": 0.1})
    assert (got["status"], got["regime"]) == (codes.OK, codes.R_STUCK)


def test_the_boundary_searches_batches_are_flagged_too():
    g = sc.Grid(**{**PAPER, "m": 1e300, "v": 7.0})
    P = g.rows(0, 1)
    out = np.empty((1, layout.NOBS))
    execute.attractors(P, g.laws, make_options("auto", tol=1e-8), out, parallel=False)
    assert out[0, layout.OB_STATUS] == codes.SCALE


@pytest.mark.parametrize("p", [
    {**PAPER, "m": 1e300, "v": 7.0},                       # too weak a law per period
    units(1e100),                                          # 1/omega beyond the range
    {**PAPER, "m": 3e250, "v": 2.0, "alpha2": 0.03},       # the same two, elsewhere
    units(1e90, 1e20),
    {**PAPER, "v": 7.0},                                   # resolved: both ok
])
def test_attractor_and_sweep_apply_one_scale_rule(p):
    """``attractor()`` and ``sweep()`` run the same call (kernel, then the scale
    rule): the same row, bit for bit, flagged or not."""
    params = sc.Params(**p)
    a = sc.attractor(params)
    ds = sc.sweep(sc.Grid(**p), progress=False)
    flagged = bool(law.unresolvable(sc.Grid(**p).rows(0, 1), make_options())[0])
    assert (a.status == "unresolvable_scale") == flagged
    assert a.status == codes.STATUS_NAMES[int(ds.status)]
    assert a.regime == codes.REGIME_NAMES[int(ds.regime)]
    for name in ("amplitude", "period", "mean", "floquet", "n_steps"):
        np.testing.assert_array_equal(getattr(a, name), ds[name].item())


def test_every_cycle_slot_of_an_unresolvable_point_is_flagged():
    """``slip_cycles`` rows hold a slot per cycle: the m = 1e300 slider (flagged, as
    above) is flagged in every slot, with its numbers kept; the paper's slider in
    none."""
    P = sc.Grid(**{**PAPER, "m": [5.0, 1e300]}).rows(0, 2)
    out = np.zeros((2, 4, layout.NOBS))
    out[..., layout.OB_AMPLITUDE] = 1.5
    law.flag_unresolvable(P, make_options(), out)
    assert np.all(out[1, :, layout.OB_STATUS] == codes.SCALE)
    assert np.all(out[1, :, layout.OB_REGIME] == codes.R_FAILED)
    assert np.all(out[0, :, layout.OB_STATUS] == codes.OK)
    assert np.all(out[..., layout.OB_AMPLITUDE] == 1.5)
    ds = sc.slip_cycles(sc.Grid(**{**PAPER, "v": 7.0, "m": [5.0, 1e300]}), progress=False)
    assert np.all(ds.cycle_status.sel(m=1e300) == codes.SCALE)
    assert not np.any(ds.cycle_status.sel(m=5.0) == codes.SCALE)
