"""Next to the Hopf point v*: slip cycles against an independent shooting solve, the
normal form where it is exact to the tolerance, and honest flags where neither is.

The reference (``reference.reference_slip_cycle``) shares no code with sweepcore: scipy
DOP853 at rtol 1e-13 with event location, the secant method on the return map, and a
central difference for its slope. The error contract of ``attractor`` is about
``tol * L`` per observable (L = r_y/k + |v|/omega: the dopri5 error over one period,
plus the fixed point's share); the tests allow 3 tol L.
"""
import math

import numpy as np
import pytest

import sweepcore as sc
from reference import reference_return, reference_slip_cycle

PAPER = dict(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, alpha2=0.01)
V_STAR = math.sqrt(PAPER["alpha1"] / (3.0 * PAPER["alpha2"]))
TOL = 1e-8                                     # the default


def length_scale(p):
    return p.r_y / p.k + abs(p.v) / p.omega


def normal_form_amplitude(p):
    """(A omega)^2 = 4 m q / (3 alpha2): first-order averaging (docs/physics.md)."""
    return math.sqrt(4.0 * p.m * p.q / (3.0 * p.alpha2)) / p.omega


@pytest.mark.parametrize("ratio", [0.9, 0.99, 0.999, 0.9999, 0.99999])
def test_slip_cycle_near_v_star_agrees_with_independent_shooting(ratio):
    """The points where waiting for convergence failed (errors up to 19 % within
    0.999 v*): the cycle's contraction per period 1 - mu falls from 7e-2 to 8e-6."""
    p = sc.Params(**PAPER, v=ratio * V_STAR)
    a = sc.attractor(p)
    assert a.status == "ok" and a.regime == "slip_cycle"
    ref = reference_slip_cycle(p.m, p.k, p.r_y, p.v, p.alpha1, p.alpha2, a.x_max)
    tol = 3.0 * TOL * length_scale(p)
    assert a.amplitude == pytest.approx(ref["amplitude"], abs=tol)
    assert a.x_max == pytest.approx(ref["x_max"], abs=tol)
    assert a.x_min == pytest.approx(ref["x_min"], abs=tol)
    assert a.period == pytest.approx(ref["period"], rel=3.0 * TOL)
    assert a.xdot_max == pytest.approx(ref["xdot_max"], abs=tol * p.omega)
    # the Floquet multiplier (Liouville's formula) against the difference quotient
    assert a.floquet == pytest.approx(ref["floquet"], abs=1e-7)
    assert 0.0 < a.floquet < 1.0


@pytest.mark.parametrize("tol", [1e-8, 1e-10])
def test_floquet_multiplier_tends_to_the_linearisation_at_v_star(tol):
    """Averaging: d(dA/dt)/dA = -q at the cycle, so mu = exp(-q T) + O(q^2)."""
    p = sc.Params(**PAPER, v=0.99999 * V_STAR)
    a = sc.attractor(p, tol=tol)
    assert a.status in ("ok", "unresolved")
    assert 1.0 - a.floquet == pytest.approx(1.0 - math.exp(-p.q * a.period), rel=1e-3)


@pytest.mark.parametrize("tol", [1e-8, 1e-10, 1e-12])
@pytest.mark.parametrize("ratio", [1.0 - 2e-6, 1.0 - 1e-7, 1.0 - 1e-9])
def test_cycle_at_the_hopf_point_is_placed_by_the_normal_form(ratio, tol):
    """q/omega ~ 1e-6 .. 1e-10: no integration resolves a contraction of 1e-6 .. 1e-9
    per period to the tolerance, so the normal form places the motion on the cycle
    (its remainder, 10 A ((1 + G) q/omega)^2, is below tol L there) and one integrated
    return from there gives every observable. Checked against that return computed
    independently with scipy, and the amplitude against averaging (whose relative
    error is ~0.07 q/omega here, studies/normal_form.py). At tol 1e-12 the return
    would need rtol tol omega A / v < 1e-14 to time its maxima (xdot crosses 0 with
    slope omega^2 A): 'unresolved' is then the right answer."""
    p = sc.Params(**PAPER, v=ratio * V_STAR)
    a = sc.attractor(p, tol=tol)
    if tol * p.omega * normal_form_amplitude(p) / p.v >= 1e-14:    # RTOL_FLOOR
        assert a.status == "ok", a
    if a.status != "ok":
        assert a.status == "unresolved"
        return
    assert a.regime == "slip_cycle"
    L = length_scale(p)
    ref = reference_return(p.m, p.k, p.r_y, p.v, p.alpha1, p.alpha2, a.x_max)
    assert ref["a1"] == pytest.approx(a.x_max, abs=tol * L)        # it is the cycle
    for name in ("x_min", "cycle_size"):
        assert getattr(a, name) == pytest.approx(ref[name], abs=3 * tol * L), name
    assert a.xdot_max == pytest.approx(ref["xdot_max"], abs=3 * tol * L * p.omega)
    assert a.period == pytest.approx(ref["period"], rel=3 * tol)
    assert a.amplitude == pytest.approx(normal_form_amplitude(p),
                                        rel=0.1 * p.q / p.omega + 3 * tol * L / a.amplitude)
    assert 0.0 < 1.0 - a.floquet < 1e-5


def test_exactly_at_v_star_the_cubic_term_decides():
    """q == 0.0 in floating point: the decay is algebraic (A ~ t^-1/2), so no
    amount of waiting certifies it; the normal form's cubic coefficient (> 0) does,
    after a few returns instead of the whole period budget."""
    v = 5.0
    p = sc.Params(m=5.0, k=50.0, r_y=10.0, v=v, alpha1=1.0, alpha2=1.0 / 75.0)
    assert p.q == 0.0
    a = sc.attractor(p)
    assert a.status == "ok" and a.regime == "equilibrium"
    assert a.n_steps < 2_000          # the budget is 2000 periods (~1e5 steps)


@pytest.mark.parametrize("ratio", [1.0 + 1e-9, 1.001, 1.1])
def test_equilibrium_just_above_v_star_is_found_without_waiting(ratio):
    p = sc.Params(**PAPER, v=ratio * V_STAR)
    assert p.q < 0.0
    a = sc.attractor(p)
    assert a.status == "ok" and a.regime == "equilibrium"
    assert math.isnan(a.floquet)
    assert a.n_steps < 2_000
    # and the motion does decay: a long simulation ends nearer x_eq than it started
    if ratio == 1.1:
        ds = sc.simulate(p, 1500.0, output_dt=1.0)       # exp(q t / 2) = 3e-14
        assert abs(ds.x.values[-1] - p.x_eq) < 1e-6


def test_a_cycle_float64_cannot_resolve_is_flagged_not_ok():
    """tol = 1e-12 at 0.9999 v* (1 - mu = 8e-5): the returns would have to be
    computed to rtol 0.5 tol (1 - mu) = 4e-17, below float64, and the normal form's
    remainder (~10 A ((1 + G) q/omega)^2 = 1e-10 cm) is above 1e-12 L. The answer is
    'unresolved', never a wrong 'ok'."""
    p = sc.Params(**PAPER, v=0.9999 * V_STAR)
    a = sc.attractor(p, tol=1e-12)
    assert a.status == "unresolved" and not a.converged
    assert a.regime == "slip_cycle"
    ref = reference_slip_cycle(p.m, p.k, p.r_y, p.v, p.alpha1, p.alpha2, a.x_max)
    assert a.amplitude == pytest.approx(ref["amplitude"], rel=1e-5)   # still an estimate


def test_stick_slip_cycle_has_floquet_multiplier_zero():
    """Every slip after a stick starts from the breakaway point: the return map is
    constant, its derivative 0."""
    a = sc.attractor(sc.Params(**PAPER, v=5.0))
    assert a.regime == "stick_slip" and a.floquet == 0.0
    assert a.xdot_max == pytest.approx(5.0, rel=1e-15)     # it sticks: xdot reaches v


def test_slip_cycle_with_reversals_agrees_with_long_hybrid_run():
    """Slide-slide reversals (normal stops, eq. 30) in every period: the return map's
    slope includes their saltation factors. Checked against a long run of the
    independent hybrid integrator (the transient contracts by 0.04 per period)."""
    from reference import reference_run

    pars = dict(PAPER, alpha2=0.004)
    p = sc.Params(**pars, v=5.0)
    a = sc.attractor(p)
    assert a.status == "ok" and a.regime == "slip_cycle" and a.sticks_per_period == 0
    assert 0.0 < a.floquet < 0.2
    t = np.linspace(0.0, 60.0 + 2.0 * a.period, 300001)
    x, _xd, events = reference_run(**pars, v=5.0, x0=0.0, xd0=5.0, t_eval=t)
    kinds = {kind for (te, kind, _x) in events if te > 60.0}
    assert kinds == {"normal_stop"}
    x = x[t >= 60.0]
    # sampled extrema: the sampling error is below (omega dt)^2 A / 8 ~ 2e-9
    assert 0.5 * (x.max() - x.min()) == pytest.approx(a.amplitude,
                                                      abs=3 * TOL * length_scale(p))


def test_random_points_of_the_6d_space_meet_the_error_contract():
    """200 log-uniform points (m, k, r_y, alpha1, alpha2 over 2.5-3 decades, v from
    0.3 v* to 1.3 v*): the default run agrees with a tol = 1e-11 run to 3 tol L in
    regime and amplitude wherever both say ok (and so does a start next to x_eq, where
    Newton steps once bounced between itineraries), and stop-free slip cycles agree with
    the independent scipy shooting solve (where its own noise, 1e-13 L / (1 - mu), is
    below 1e-9 L). Waiting for convergence failed this by up to 2.6e-3 relative."""
    rng = np.random.default_rng(7)
    checked = 0
    for _ in range(200):
        m, k, ry = 10 ** rng.uniform(-1, 1.5), 10 ** rng.uniform(0, 3), 10 ** rng.uniform(-1, 1.5)
        a1, a2 = 10 ** rng.uniform(-2, 1), 10 ** rng.uniform(-3, 0)
        v = math.sqrt(a1 / (3 * a2)) * rng.uniform(0.3, 1.3)
        p = sc.Params(m, k, ry, v, a1, a2)
        L = length_scale(p)
        a = sc.attractor(p)
        b = sc.attractor(p, tol=1e-11)
        assert a.status == "ok", p
        if b.status != "ok":
            continue
        assert a.regime == b.regime, p
        assert abs(a.amplitude - b.amplitude) <= 3 * TOL * L, p
        # a start next to x_eq (xdot = 0) reaches the same attractor: Newton steps
        # that would cross a change of itinerary are undone, not repeated
        c = sc.attractor(p, x0=p.x_eq + 0.1 * v / p.omega, xdot0=0.0)
        assert c.status == "ok" and c.regime == a.regime, p
        assert abs(c.amplitude - a.amplitude) <= 3 * TOL * L, p
        if a.regime == "slip_cycle" and a.sticks_per_period == 0 and a.xdot_max < 0.999 * v:
            ref = reference_slip_cycle(m, k, ry, v, a1, a2, a.x_max)
            if 1e-13 / (1.0 - ref["floquet"]) <= 1e-9:
                assert abs(a.amplitude - ref["amplitude"]) <= 3 * TOL * L, p
                checked += 1
    assert checked >= 10


@pytest.mark.parametrize("ratio", [0.79, 0.8])
def test_newton_never_bounces_between_itineraries(ratio):
    """From x_eq + 1e-3 at rest the motion grows slowly (stop-free, the map's slope
    falls below 1 on the way) and then sticks. Newton steps taken on the stop-free
    slope landed among returns with slide-slide reversals and back, forever (808
    jumps, unconverged after 2e5 steps). The attractor is the stick-slip cycle that a
    start stuck on the belt reaches in one period (every slip restarts from the
    breakaway point)."""
    p = sc.Params(**PAPER, v=ratio * V_STAR)
    a = sc.attractor(p, x0=p.x_eq + 1e-3, xdot0=0.0)
    b = sc.attractor(p)
    assert b.regime == "stick_slip"
    assert a.status == "ok" and a.regime == "stick_slip"
    assert a.amplitude == pytest.approx(b.amplitude, abs=3 * TOL * length_scale(p))


def test_slip_cycle_at_rest_belt_is_accurate_on_the_motion_scale():
    """v = 0: the sections are the stops at the maxima of x; the integrator's error
    per return is ~rtol (r_y/k + |x|), here 350 times r_y/k. At the default the
    amplitude must agree with a tol = 1e-12 run to 3 tol (r_y/k + |x|) (it was off
    by 550 tol r_y/k)."""
    p = sc.Params(m=5.0, k=50.0, r_y=0.5, v=0.0, alpha1=1.0, alpha2=0.01)
    a = sc.attractor(p, x0=3.0, xdot0=0.0)
    b = sc.attractor(p, x0=3.0, xdot0=0.0, tol=1e-12)
    assert a.status == b.status == "ok" and a.regime == b.regime == "slip_cycle"
    assert a.amplitude == pytest.approx(b.amplitude, abs=3 * TOL * (p.r_y / p.k + a.x_max))
