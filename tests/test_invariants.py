"""Invariants over wide parameter ranges (hypothesis): energy balance, mirror symmetry,
the constant-friction closed form, finite-or-flagged outputs, step budgets.

Ranges: m, k log-uniform in [1e-3, 1e3]; r_y in [0, 1e2] (zero, uniform, log-uniform
down to 1e-6); |v| log-uniform in [1e-6, 1e2], both signs; alpha1 a damping ratio
|alpha1| / (2 sqrt(k m)) <= 0.3; alpha2 a cubic term of relative size 1e-3 .. 10 at the
point's velocity scale omega L; starts within 3 L of the origin in the
(x, xdot/omega) plane, or stuck. L = r_y/k + |v|/omega is the point's length scale.
The hostile strategy widens all of this (1e-6 .. 1e6, subnormal speeds, 1e12 starts).

Default run: a few dozen derandomized examples per property (deterministic, fast).
``pytest -m slow`` runs the soak variants with many more random examples.
"""
import math
import time

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import sweepcore as sc

FAST = settings(max_examples=50, deadline=None, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow])
# the soak draws the same examples every run (derandomized: CI answers for the code,
# not for the draw); with derandomize=False each run explores new draws, as it did
# when it found the examples of HOSTILE_EXAMPLES
SOAK = settings(max_examples=1500, deadline=None, print_blob=True, derandomize=True,
                database=None, suppress_health_check=[HealthCheck.too_slow])

# One driver iteration may overrun the step budget by finishing what it started: one
# step, <= 40 GPS halvings, and up to five event polishes of <= 62 stepper calls each
# (sweepcore/_kernels/driver.py: slide_until_event, _polish, _velocity_extremum).
BUDGET_SLACK = 400

CYCLES = {"slip_cycle", "stick_slip", "neutral"}
AT_REST = {"equilibrium", "stuck"}
ANSWERS = CYCLES | AT_REST
NOT_ANSWERS = {"unconverged", "failed", "unbounded"}


# ------------------------------------------------------------------ strategies
def log_uniform(lo, hi):
    return st.floats(math.log10(lo), math.log10(hi)).map(lambda e: 10.0 ** e)


def scales(m, k, r_y, v):
    w = math.sqrt(k / m)
    L = r_y / k + abs(v) / w
    return w, (L if L > 0 else 1.0)


@st.composite
def sliders(draw, law="any", stuck=True, v_zero=False):
    """A physical slider with a start: dict of Params fields plus x0, xdot0.

    law: "constant" (alpha1 = alpha2 = 0), "linear" (alpha2 = 0), "cubic"
    (alpha2 > 0) or "any".
    """
    m = draw(log_uniform(1e-3, 1e3))
    k = draw(log_uniform(1e-3, 1e3))
    r_y = draw(st.one_of(st.just(0.0), st.floats(1e-6, 100.0), log_uniform(1e-6, 1e2)))
    sign = draw(st.sampled_from([-1.0, 1.0]))
    v = sign * draw(log_uniform(1e-6, 1e2))
    if v_zero and draw(st.booleans()):
        v = 0.0
    w, L = scales(m, k, r_y, v)
    if law == "any":
        law = draw(st.sampled_from(["constant", "linear", "cubic"]))
    alpha1 = 0.0 if law == "constant" else \
        draw(st.floats(-0.3, 0.3)) * 2.0 * math.sqrt(k * m)
    alpha2 = 0.0 if law != "cubic" else \
        draw(log_uniform(1e-3, 10.0)) * m * w / (w * L) ** 2
    if stuck and draw(st.booleans()):
        x0, xdot0 = draw(st.floats(-1.0, 1.0)) * r_y / k, None
    else:
        x0 = draw(st.floats(-3.0, 3.0)) * L
        xdot0 = draw(st.floats(-3.0, 3.0)) * w * L
    return dict(m=m, k=k, r_y=r_y, v=v, alpha1=alpha1, alpha2=alpha2, x0=x0,
                xdot0=xdot0)


def params(s):
    return sc.Params(**{n: s[n] for n in ("m", "k", "r_y", "v", "alpha1", "alpha2")})


def mirrored(s):
    return {**s, "v": -s["v"], "x0": -s["x0"],
            "xdot0": None if s["xdot0"] is None else -s["xdot0"]}


def natural_period(s):
    return 2.0 * math.pi / math.sqrt(s["k"] / s["m"])


ABNORMAL_STOP = 4          # sweepcore._kernels.codes.EV_ABNORMAL_STOP


# --------------------------------------------------------------- energy balance
TOL_DOPRI = 1e-10


def check_energy_balance(s):
    """Delta(k x^2/2 + m xdot^2/2) = -friction_work over a run of five periods.

    exact (alpha2 = 0): no truncation error, so rounding only: 1e-9 of the energy
    scale. dopri5 at tol: the driver's own accuracy model is ~100 local errors of
    tol per natural period (driver.py: graze tolerance), so 100 tol per period of
    the energy scale (energy error ~ 2 x relative state error, halved by margin).
    """
    p = params(s)
    T = natural_period(s)
    n_periods = 5
    method = "exact" if s["alpha2"] == 0.0 else "dopri5"
    ds = sc.simulate(p, n_periods * T, x0=s["x0"], xdot0=s["xdot0"], method=method,
                     tol=TOL_DOPRI, output_dt=T / 8, max_steps=400_000)
    assert ds.attrs["status"] == "ok", ds.attrs
    x, xd = ds.x.values, ds.xdot.values
    e = 0.5 * p.k * x ** 2 + 0.5 * p.m * xd ** 2
    _w, L = scales(p.m, p.k, p.r_y, p.v)
    scale = e.max() + p.k * L ** 2
    rtol = 1e-9 if method == "exact" else 100.0 * TOL_DOPRI * (n_periods + 1)
    residual = (e[-1] - e[0]) + float(ds["friction_work"])
    assert abs(residual) <= rtol * scale, (residual / scale, method)


@FAST
@given(s=sliders())
def test_energy_balance(s):
    check_energy_balance(s)


@pytest.mark.slow
@SOAK
@given(s=sliders(v_zero=True))
def test_energy_balance_soak(s):
    check_energy_balance(s)


def test_energy_balance_stable_linear_law_long_run():
    """A stable slider (q = -0.2 /s) run until it has settled on x_eq: the exact arcs
    must get there (decay e^{-0.1 t}: |x - x_eq| < 1e-6 cm after 200 s) with the
    energy balance intact. Regression: the exact stepper's step collapsed near the
    equilibrium (step_budget_exceeded)."""
    p = sc.Params(m=5.0, k=50.0, r_y=10.0, v=5.0, alpha1=-1.0)
    ds = sc.simulate(p, 200.0, method="exact", output_dt=1.0, max_steps=100_000)
    assert ds.attrs["status"] == "ok"
    assert abs(ds.x.values[-1] - p.x_eq) < 1e-6
    e = 0.5 * p.k * ds.x.values ** 2 + 0.5 * p.m * ds.xdot.values ** 2
    assert abs(e[-1] - e[0] + float(ds["friction_work"])) <= 1e-9 * e.max()


# ---------------------------------------------------------------- mirror symmetry
def check_mirror_trajectory(s):
    """v -> -v with (x0, xdot0) -> -(x0, xdot0): the trajectory negates.

    Both methods treat the two signs with the same operations up to signs, so the
    only difference is rounding: 1e-10 of the run's size.
    """
    p, q = params(s), params(mirrored(s))
    T = natural_period(s)
    method = "exact" if s["alpha2"] == 0.0 else "dopri5"
    kw = dict(method=method, tol=TOL_DOPRI, output_dt=T / 8, max_steps=400_000)
    a = sc.simulate(p, 5 * T, x0=s["x0"], xdot0=s["xdot0"], **kw)
    m = mirrored(s)
    b = sc.simulate(q, 5 * T, x0=m["x0"], xdot0=m["xdot0"], **kw)
    assert a.attrs["status"] == b.attrs["status"]
    # the transversal events agree (one within rounding of t_end may fall either
    # side). Tangential touches (abnormal stops) are decided within the graze
    # tolerance and leave the state as it is, so they are not compared here.
    inside = [ds.event_kind.values[(ds.event_time.values < 4.999 * T)
                                   & (ds.event_kind.values != ABNORMAL_STOP)]
              for ds in (a, b)]
    np.testing.assert_array_equal(*inside)
    w, L = scales(p.m, p.k, p.r_y, p.v)
    size = np.nanmax(np.abs(a.x.values)) + L
    np.testing.assert_allclose(b.x.values, -a.x.values, rtol=0, atol=1e-10 * size)
    np.testing.assert_allclose(b.xdot.values, -a.xdot.values, rtol=0,
                               atol=1e-10 * w * size)
    # phases agree except at samples that fall on an event (zdot = 0: either side)
    moving = np.abs(a.zdot.values) > 1e-9 * w * size
    np.testing.assert_array_equal(b.phase.values[moving], -a.phase.values[moving])


@FAST
@given(s=sliders())
def test_mirror_symmetry_of_trajectories(s):
    check_mirror_trajectory(s)


@pytest.mark.slow
@SOAK
@given(s=sliders())
def test_mirror_symmetry_of_trajectories_soak(s):
    check_mirror_trajectory(s)


MIRROR_TOL = 1e-8


def mirror_attractors(s, max_periods):
    kw = dict(tol=MIRROR_TOL, max_periods=max_periods, max_steps=100_000)
    m = mirrored(s)
    a = sc.attractor(params(s), x0=s["x0"], xdot0=s["xdot0"], **kw)
    b = sc.attractor(params(m), x0=m["x0"], xdot0=m["xdot0"], **kw)
    return a, b


def check_mirror_attractor(s):
    """The attractor of the mirror image has the same regime and amplitude, and the
    negated mean, to the search's tolerance (tol L per Poincare return; 100 tol L
    allows for the integration error of both runs).

    A point that converges on one side only may sit at the edge of the time budget:
    both are rerun with four times the budget before that counts as a failure.
    """
    a, b = mirror_attractors(s, 50.0)
    if a.converged != b.converged:
        a, b = mirror_attractors(s, 200.0)
    assert (a.regime, a.status) == (b.regime, b.status), (a, b)
    if a.converged:
        _w, L = scales(s["m"], s["k"], s["r_y"], s["v"])
        assert b.amplitude == pytest.approx(a.amplitude, rel=0, abs=100 * MIRROR_TOL * L)
        assert b.mean == pytest.approx(-a.mean, rel=0, abs=100 * MIRROR_TOL * L)


# known failure (reported): tiny v/omega against r_y/k, q < 0. v > 0 is (rightly) the
# equilibrium; v < 0 came out "stick_slip" with status ok.
@FAST
@given(s=sliders())
@example(s=dict(m=5.0, k=50.0, r_y=10.0, v=1e-7, alpha1=-1.0, alpha2=0.01, x0=0.0,
                xdot0=None))
def test_mirror_symmetry_of_attractors(s):
    check_mirror_attractor(s)


def test_mirror_symmetry_tiny_belt_speed_stable_slider():
    """m=5, k=50, r_y=10, alpha1=-1 (q = -0.2): starting stuck, the slip at r_y/k
    leaves a damped orbit whose xdot never returns to v (amplitude ~ v/omega, decaying),
    so the attractor is the equilibrium for both signs of v (the exact arcs say so).
    With dopri5 the slider with v = -1e-7 was called "stick_slip" (status ok)."""
    for method in ("exact", "dopri5"):
        for v in (1e-7, -1e-7):
            a = sc.attractor(sc.Params(m=5.0, k=50.0, r_y=10.0, v=v, alpha1=-1.0),
                             method=method)
            assert (a.regime, a.status) == ("equilibrium", "ok"), (method, v, a)


@pytest.mark.slow
@SOAK
@given(s=sliders())
def test_mirror_symmetry_of_attractors_soak(s):
    check_mirror_attractor(s)


# ------------------------------------------------------ constant-friction closed form
CF_TOL = 1e-10


def check_constant_friction(s, max_periods):
    """alpha1 = alpha2 = 0 (design fact 1): the attractor is the circle about
    (sgn(v) r_y/k, 0) in the (x, xdot/omega) plane of radius min(R0, |v|/omega)
    (R0: the start's distance from the centre); with r_y = 0 nothing is dissipated
    and the radius stays R0. Mean sgn(v) r_y/k, period 2 pi/omega. The exact method
    has no truncation error: 1e-9 relative. A far start that needs more slide-slide
    reversals than the budget allows must say "unconverged".

    The search runs at tol = 1e-10; its answer must be within 10 tol of the size
    L + R0 (the exact arcs themselves are exact to rounding).
    """
    p = params(s)
    w = p.omega
    centre = math.copysign(p.r_y / p.k, p.v)
    xd0 = p.v if s["xdot0"] is None else s["xdot0"]
    R0 = math.hypot(s["x0"] - centre, xd0 / w)
    expect = R0 if p.r_y == 0.0 else min(R0, abs(p.v) / w)
    a = sc.attractor(p, x0=s["x0"], xdot0=s["xdot0"], method="exact",
                     tol=CF_TOL, max_periods=max_periods)
    if a.status == "below_resolution":
        # the circle spans fewer than 1e6 roundings of x (eps (|centre| + R)) or of
        # xdot = zdot + v (eps (|v| + omega R)): its digits are not there
        eps = np.finfo(float).eps
        assert a.regime == "failed", a
        assert expect * 1e-6 < 2 * eps * (abs(centre) + expect) or \
            w * expect * 1e-6 < 2 * eps * (abs(p.v) + w * expect), a
        return
    if not a.converged:
        assert (a.regime, a.status) == ("unconverged", "unconverged"), a
        # only far starts may run out of budget, and starts on the centre itself
        # (an orbit within 1e3 tol L of the centre: the slider all but rests there
        # and no Poincare section ever comes)
        _w, L = scales(p.m, p.k, p.r_y, p.v)
        assert R0 <= 1e3 * CF_TOL * L or (p.r_y > 0.0 and R0 > abs(p.v) / w), a
        return
    _w, L = scales(p.m, p.k, p.r_y, p.v)
    size = L + R0
    # rounding of x at the centre, u = eps |centre|, costs the period up to 0.25 u/R
    # and the amplitude 1.5 u (measured: sweepcore/_kernels/resolution.py)
    u = np.finfo(float).eps * (abs(centre) + expect)
    assert a.regime in ("neutral", "slip_cycle", "stick_slip"), a
    assert a.amplitude == pytest.approx(expect, rel=0, abs=10 * CF_TOL * size + 2 * u)
    assert a.mean == pytest.approx(centre, rel=0, abs=10 * CF_TOL * size + 2 * u)
    assert a.period == pytest.approx(2 * math.pi / w, rel=10 * CF_TOL + 0.5 * u / expect)


# known failures (reported): an orbit just outside |v|/omega with a tiny r_y loses
# energy so slowly that its Poincare returns look steady: accepted at R0 (6e-8 off).
# And after a stick of 1.6e11 s the period and mean lose digits (mean 0.04 cm off,
# outside [x_min, x_max]).
@FAST
@given(s=sliders(law="constant"))
@example(s=dict(m=1.0, k=1.0, r_y=5.960464477539063e-08, v=-1.0, alpha1=0.0,
                alpha2=0.0, x0=0.0, xdot0=1.0000000596046448))
@example(s=dict(m=1.0, k=1e-5, r_y=16.0, v=-1e-5, alpha1=0.0, alpha2=0.0, x0=0.0,
                xdot0=None))
def test_constant_friction_closed_form(s):
    check_constant_friction(s, max_periods=200.0)


def test_period_and_mean_keep_their_digits_after_a_long_stick():
    """The paper's slider on a belt of 1e-9 cm/s sticks for 2e8 s, then rides the
    circle of radius v/omega = 3.2e-10 cm about r_y/k = 0.2 cm: the mean is 0.2 to
    rounding (1e-16 of x). Absolute times near 2e8 s carry 3e-8 s of rounding: the
    period must be measured relative to the cycle's start, not as a difference of
    absolute times. What is left is the phase resolution of the orbit itself: x is
    stored as 0.2 + (a 3.2e-10 cm circle), so rounding x costs eps (r_y/k)/(v/omega)
    = 1.4e-7 rad of phase; the period is asked to that bound, not to 1e-12."""
    p = sc.Params(m=5.0, k=50.0, r_y=10.0, v=1e-9)
    a = sc.attractor(p)
    assert a.converged
    assert a.x_min <= a.mean <= a.x_max, a
    assert a.mean == pytest.approx(0.2, rel=1e-14)
    phase_res = np.finfo(float).eps * (p.r_y / p.k) / (p.v / p.omega)
    assert a.period == pytest.approx(2 * math.pi / p.omega, rel=phase_res)


@pytest.mark.slow
@SOAK
@given(s=sliders(law="constant"))
def test_constant_friction_closed_form_soak(s):
    check_constant_friction(s, max_periods=2000.0)


# ------------------------------------------------- finite or flagged, within budget
@st.composite
def hostile(draw):
    """Anything Params accepts, weighted towards the extremes, and a small budget."""
    m = draw(log_uniform(1e-6, 1e6))
    k = draw(log_uniform(1e-6, 1e6))
    r_y = draw(st.sampled_from([0.0, 1e-300, 1e-6, 1e6]) | st.floats(0.0, 100.0))
    v = draw(st.sampled_from([0.0, 5e-324, 1e-300, 1e-6, 1e6]) | log_uniform(1e-6, 1e2))
    v *= draw(st.sampled_from([-1.0, 1.0]))
    w, L = scales(m, k, r_y, v)
    alpha1 = draw(st.sampled_from([0.0, 100.0, -100.0])
                  | st.floats(-2.0, 2.0).map(lambda c: c * math.sqrt(k * m)))
    alpha2 = draw(st.sampled_from([0.0, 1e3]) | log_uniform(1e-6, 1e3))
    x0 = draw(st.sampled_from([0.0, 1e12, -1e12]) | st.floats(-3, 3).map(lambda u: u * L))
    xdot0 = draw(st.sampled_from([None, 1e12]) | st.floats(-3, 3).map(lambda u: u * w * L))
    method = draw(st.sampled_from(["auto", "exact", "gps", "rk4", "dopri5"]))
    if method == "exact" and alpha2 != 0.0:
        method = "auto"
    max_steps = draw(st.integers(1, 5000))
    max_periods = draw(st.floats(0.1, 50.0))
    return dict(p=dict(m=m, k=k, r_y=r_y, v=v, alpha1=alpha1, alpha2=alpha2),
                x0=x0, xdot0=xdot0, method=method, max_steps=max_steps,
                max_periods=max_periods)


_COMPILED = set()


def _compiled(method):
    """The method's kernel compiled (or loaded) before a point is timed: the 5 s bound
    of ``check_finite_or_flagged`` is on the search (a hang), not on a cold
    compilation (~40 s)."""
    if method not in _COMPILED:
        sc.attractor(sc.Params(m=1.0, k=1.0, r_y=1.0, v=1.0, alpha1=0.1, alpha2=0.0),
                     method=method)
        _COMPILED.add(method)


def check_finite_or_flagged(h):
    """Every point returns, within its budget, either an answer (status ok, a regime
    that is an answer, finite amplitude and mean, x_min <= mean <= x_max) or a failure
    status with a regime that says so. Never a NaN with status ok, never an answer
    regime with a failure status, never an exception."""
    p = sc.Params(**h["p"])
    _compiled(h["method"])
    t0 = time.perf_counter()
    a = sc.attractor(p, x0=h["x0"], xdot0=h["xdot0"], method=h["method"],
                     max_steps=h["max_steps"], max_periods=h["max_periods"])
    elapsed = time.perf_counter() - t0
    assert a.converged == (a.status == "ok")
    if a.status == "ok":
        assert a.regime in ANSWERS, a
        assert math.isfinite(a.amplitude) and math.isfinite(a.mean), a
        assert a.amplitude >= 0.0
        span = abs(a.x_max) + abs(a.x_min)
        assert a.x_min - 1e-12 * span <= a.mean <= a.x_max + 1e-12 * span, a
        if a.regime in CYCLES:
            assert math.isfinite(a.period) and a.period > 0.0, a
    elif a.status == "unresolved":
        # a contracting slip cycle whose fixed point float64 cannot pin to tol (its
        # regime is known, its numbers are estimates), or a motion that stands still
        # to float64 resolution without a known sign of contraction (unconverged)
        assert a.regime in ("slip_cycle", "unconverged"), a
        assert math.isfinite(a.amplitude), a
    else:
        assert a.regime in NOT_ANSWERS, a
    assert 0 <= a.n_steps <= h["max_steps"] + BUDGET_SLACK, a
    assert elapsed < 5.0


HOSTILE_EXAMPLES = [
    # subnormal belt speed, no friction bound: r_y/k + |v|/omega times tol underflows
    # (this raised ZeroDivisionError out of the kernel before the numpy error model)
    dict(p=dict(m=1.0, k=1.0, r_y=0.0, v=5e-324, alpha1=0.0, alpha2=0.0), x0=0.0,
         xdot0=None, method="dopri5", max_steps=2000, max_periods=50.0),
    # a long stick (3e10 s), then an overdamped exact arc: the driver's loop ran out
    # with status "ok" and regime "failed"
    dict(p=dict(m=17985.802202506817, k=2.0065055614143824e-06, r_y=90.59598690074868,
                v=0.0013387119438976402, alpha1=-18305.6726384866, alpha2=0.0),
         x0=0.0, xdot0=None, method="auto", max_steps=1, max_periods=50.0),
    # a subnormal belt speed loads the spring across the band in 1e334 s: gps said ok,
    # stick_slip, with period inf and mean NaN (found by the soak on 2026-12-08)
    dict(p=dict(m=1000.0, k=10.0 ** -4.609375, r_y=1e6, v=5e-324, alpha1=100.0,
                alpha2=1000.0), x0=0.0, xdot0=None, method="gps", max_steps=57,
         max_periods=1.0),
]


@FAST
@given(h=hostile())
@example(h=HOSTILE_EXAMPLES[0])
@example(h=HOSTILE_EXAMPLES[1])
@example(h=HOSTILE_EXAMPLES[2])
def test_every_output_is_finite_or_flagged(h):
    check_finite_or_flagged(h)


@pytest.mark.slow
@settings(SOAK, max_examples=5000)
@given(h=hostile())
def test_every_output_is_finite_or_flagged_soak(h):
    check_finite_or_flagged(h)


@pytest.mark.parametrize("v", [1e-15, 1e-17])
def test_attractor_after_an_extremely_long_stick(v):
    """m = k = r_y = 1, starting stuck: a stick of r_y/(k v) = 1e15 .. 1e17 s, then
    the circle of radius v/omega about r_y/k = 1. Absolute times there carry
    0.2 .. 20 s of rounding (more than a natural period at 1e17), so the point may
    say it cannot resolve the cycle, but an answer with status ok must be right.
    Found: v = 1e-15 gave "slip_cycle"/ok with mean 0.9666 and amplitude 5.6e-16;
    v = 1e-17 gave regime "failed" with status "ok" (converged True)."""
    a = sc.attractor(sc.Params(m=1.0, k=1.0, r_y=1.0, v=v))
    if a.status == "ok":
        assert a.regime in ANSWERS, a
        assert a.mean == pytest.approx(1.0, rel=1e-12), a
        assert a.amplitude == pytest.approx(v, rel=1e-6), a
    else:
        assert a.regime in NOT_ANSWERS and not a.converged, a


def _long_stick_then_slide():
    """After a stick of 3.4e10 s the slide must still be integrated. Here the exact
    arc's first step is shorter than the rounding of t (7.5e-6 s) and the driver
    jumped to the sample time instead, leaving x frozen at the breakaway point with
    status "ok" and 0 steps. Checked against scipy's Radau on the sliding equation
    (constant sign: the reference run has no zdot = 0 crossing in these 2 periods)."""
    from scipy.integrate import solve_ivp

    p = sc.Params(m=17985.802202506817, k=2.0065055614143824e-06, r_y=90.59598690074868,
                  v=0.0013387119438976402, alpha1=-18305.6726384866)
    t_slip = p.r_y / p.k / p.v
    T = 2 * math.pi / p.omega
    ds = sc.simulate(p, t_slip + 2 * T, output_dt=T / 4, method="exact")
    after = ds.time.values > t_slip

    def sliding(_t, y):                      # zdot < 0: r_a = -r_y - alpha1 zdot
        ra = -p.r_y - p.alpha1 * (y[1] - p.v)
        return [y[1], (-p.k * y[0] - ra) / p.m]
    ref = solve_ivp(sliding, (0.0, 2 * T), [p.r_y / p.k, p.v], method="Radau",
                    rtol=1e-11, atol=1e-9, dense_output=True)
    x_ref = ref.sol(ds.time.values[after] - t_slip)[0]
    assert np.all(ref.sol(np.linspace(0, 2 * T, 2001))[1][1:] < p.v)   # no stop
    if ds.attrs["status"] == "ok":          # integrated: it must be right
        np.testing.assert_allclose(ds.x.values[after], x_ref, rtol=1e-8)
    else:                                   # or flagged, with no number after it
        assert np.isnan(ds.x.values[-1])
    return ds.attrs["status"]

@pytest.mark.xfail(strict=True, reason=(
    "known limitation: the touch tolerance now comes from the motion (1e-10 |v| + "
    "rounding = 1e-10 cm/s), but the exact arc's zdot = y' - v carries ~4e-10 cm/s of "
    "rounding here (the sliding centre is 1.2e7 cm from x, y' a difference of terms "
    "~3e6), of the wrong sign and above the creeping |zdot| (5e-14 at 1 s, 1.5e-10 at "
    "1e3 s after the slip): the noise turns zdot back towards 0 and the driver books "
    "chains of abnormal stops until its budget (flagged step_budget_exceeded, never a "
    "wrong number). The fix is a zdot without that cancellation in the exact stepper."))
def test_slide_after_a_long_stick_is_integrated_ideal():
    assert _long_stick_then_slide() == "ok"


def test_slide_after_a_long_stick_is_integrated_not_skipped():
    _long_stick_then_slide()



@FAST
@given(s=sliders(), max_steps=st.integers(1, 300),
       method=st.sampled_from(["auto", "gps", "rk4", "dopri5"]))
def test_simulate_stops_at_its_step_budget(s, max_steps, method):
    """A run that needs more steps than max_steps stops there with the status
    "step_budget_exceeded" (samples after it NaN); one that finishes within it is ok."""
    T = natural_period(s)
    ds = sc.simulate(params(s), 3 * T, x0=s["x0"], xdot0=s["xdot0"], method=method,
                     output_dt=T / 4, max_steps=max_steps)
    n = ds.attrs["n_steps"]
    assert n <= max_steps + BUDGET_SLACK
    assert ds.attrs["status"] in ("ok", "step_budget_exceeded", "diverged")
    if ds.attrs["status"] == "ok":
        assert np.isfinite(ds.x.values).all() and np.isfinite(ds.xdot.values).all()
    else:
        assert np.isnan(ds.x.values[-1])
    if ds.attrs["status"] == "step_budget_exceeded":
        assert n >= max_steps
