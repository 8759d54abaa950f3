"""Convergence order, measured on refinement ladders.

Reference: the exact stepper when alpha2 = 0, a much tighter dopri5 run when alpha2 > 0.
The order is the least-squares slope of log(error) against log(step); the bands
follow from the methods (1 for GPS, 4 for RK4) with room for the constants.
"""
import math

import numpy as np
import pytest

import sweepcore as sc
from sweepcore.options import make_options

T = 1.5     # inside the first sliding arc after the slip at 0.04 s: the smooth order
P0 = sc.Params(5.0, 50.0, 10.0, 5.0, alpha1=1.0, alpha2=0.0)
P1 = sc.Params(5.0, 50.0, 10.0, 5.0, alpha1=1.0, alpha2=0.01)


def x_end(p, method, **kw):
    return sc.simulate(p, T, method=method, output_dt=T, **kw).x.values[-1]


def slope(h, e):
    return np.polyfit(np.log(h), np.log(e), 1)[0]


@pytest.fixture(scope="module")
def refs():
    return {P0: x_end(P0, "exact"), P1: x_end(P1, "dopri5", tol=1e-13)}


@pytest.mark.parametrize("p", [P0, P1], ids=["alpha2=0 vs exact", "alpha2>0 vs tight"])
@pytest.mark.parametrize("method,dts,lo,hi", [
    ("gps", [2e-3, 1e-3, 5e-4, 2.5e-4], 0.9, 1.1),
    ("rk4", [0.04, 0.02, 0.01, 0.005], 3.7, 5.0),
])
def test_fixed_step_order(refs, p, method, dts, lo, hi):
    err = [abs(x_end(p, method, dt=d) - refs[p]) for d in dts]
    assert lo < slope(dts, err) < hi


@pytest.mark.parametrize("p", [P0, P1], ids=["alpha2=0 vs exact", "alpha2>0 vs tight"])
def test_adaptive_error_tracks_tolerance(refs, p):
    tols = [1e-6, 1e-8, 1e-10]
    err = np.array([abs(x_end(p, "dopri5", tol=t) - refs[p]) for t in tols])
    lx = p.r_y / p.k + abs(p.v) / p.omega          # the tolerance is relative to this
    assert (err < 20 * np.array(tols) * lx).all()
    assert 0.7 < slope(tols, err) < 1.3             # error proportional to tol


@pytest.mark.parametrize("method,dts,lo,hi", [
    ("gps", [1e-3, 5e-4, 2.5e-4], 0.85, 1.3),
    ("rk4", [0.04, 0.02, 0.01], 3.6, 4.4),
])
def test_order_holds_across_events(method, dts, lo, hi):
    """The stick-slip period (events located on re-steps) converges at the same order."""
    ref = sc.attractor(P1, method="dopri5", tol=1e-12).period
    err = [abs(sc.attractor(P1, method=method, dt=d).period - ref) for d in dts]
    assert lo < slope(dts, err) < hi


def test_events_are_located_to_1e_12_in_time():
    """Event times do not move with the adaptive tolerance beyond the method's error."""
    a = sc.simulate(P1, 10.0, method="dopri5", tol=1e-12)
    b = sc.simulate(P1, 10.0, method="dopri5", tol=1e-13)
    assert a.sizes["event"] == b.sizes["event"] >= 4
    np.testing.assert_allclose(a.event_time.values, b.event_time.values, atol=1e-10)
    np.testing.assert_array_equal(a.event_kind.values, b.event_kind.values)


@pytest.mark.parametrize("dt", [1e-3, 5e-4])
def test_gps_pumps_energy_at_the_forward_euler_rate(dt):
    """GPS's first-order error: a neutral circle grows like exp(omega^2 dt t / 2).

    Constant friction from rest: the exact orbit is a circle of radius r_y/k that
    never reaches belt speed (no events), so any growth is the method's.
    """
    p = sc.Params(5.0, 50.0, 10.0, 5.0)
    ds = sc.simulate(p, 20.0, x0=0.0, xdot0=0.0, method="gps", dt=dt, output_dt=1e-3)
    r = np.hypot(ds.x.values - p.r_y / p.k, ds.xdot.values / p.omega)
    rate = np.polyfit(ds.time.values, np.log(r), 1)[0]
    assert rate == pytest.approx(p.omega ** 2 * dt / 2, rel=0.02)


def test_paper_three_cases():
    qs = []
    for a2 in (0.05, 1 / 75, 0.01):
        qs.append(sc.Params(5, 50, 10, 5, 1.0, a2).q)
    np.testing.assert_allclose(qs, [-0.55, 0.0, 0.05], atol=1e-12)
    eq = sc.attractor(sc.Params(5, 50, 10, 5, 1.0, 0.05))
    assert eq.regime == "equilibrium" and eq.mean == pytest.approx(0.225, rel=1e-12)
    cyc = sc.attractor(sc.Params(5, 50, 10, 5, 1.0, 0.01))
    assert cyc.regime == "stick_slip" and cyc.converged


def test_dormand_prince_tableau_conditions():
    """Row sums of A equal c; b sums to 1; the error weights sum to 0; b and the
    embedded b_hat = b - e reach order 5 and 4 on the quadrature conditions."""
    from sweepcore._kernels import dopri5 as dp
    A, b, c, e = dp.TABLEAU_A, dp.TABLEAU_B, dp.TABLEAU_C, dp.TABLEAU_E
    np.testing.assert_allclose(A.sum(axis=1), c[:A.shape[0]], atol=1e-15)
    assert b.sum() == pytest.approx(1.0, abs=1e-15)
    assert e.sum() == pytest.approx(0.0, abs=1e-15)
    for q in range(1, 6):                     # sum b_i c_i^(q-1) = 1/q up to order 5
        assert (b * c ** (q - 1)).sum() == pytest.approx(1.0 / q, abs=1e-14)
    bh = b - e
    for q in range(1, 5):
        assert (bh * c ** (q - 1)).sum() == pytest.approx(1.0 / q, abs=1e-14)
    assert abs((bh * c ** 4).sum() - 1.0 / 5) > 1e-6   # and no higher: the 4th-order pair


def _dop853_tableau():
    """A, b, c and the two error weights of dop853, read back from its constants."""
    import re

    from sweepcore._kernels import dop853 as d
    A, c, b, e5, e3 = (np.zeros((12, 12)),) + tuple(np.zeros(12) for _ in range(4))
    for name in dir(d):
        for pat, arr in ((r"C(\d+)", c), (r"B(\d+)", b), (r"E5_(\d+)", e5),
                         (r"E3_(\d+)", e3)):
            m = re.fullmatch(pat, name)
            if m and int(m[1]) <= 12:       # C14-C16: the dense output's stages
                arr[int(m[1]) - 1] = getattr(d, name)
        m = re.fullmatch(r"A(\d+)_(\d+)", name)
        if m and int(m[1]) <= 12:           # 13-16: the dense output's stages
            A[int(m[1]) - 1, int(m[2]) - 1] = getattr(d, name)
    return A, b, c, e5, e3


def test_dop853_tableau_conditions():
    """Row sums of A equal c; b meets the quadrature conditions to order 8 and not 9,
    and the trees of order 4 and 5 (a typo in one coefficient breaks them); the
    embedded weights b - E5 and b - E3 are of order 5 and 3 exactly (Hairer,
    Norsett & Wanner, Solving ODEs I, II.10)."""
    A, b, c, e5, e3 = _dop853_tableau()
    np.testing.assert_allclose(A.sum(axis=1), c, atol=1e-15)
    for q in range(1, 9):
        assert (b * c ** (q - 1)).sum() == pytest.approx(1.0 / q, abs=1e-14)
    assert abs((b * c ** 8).sum() - 1.0 / 9) > 1e-6
    for lhs, rhs in ((b @ A @ c, 1 / 6), ((b * c) @ A @ c, 1 / 8), (b @ A @ c ** 2, 1 / 12),
                     (b @ A @ A @ c, 1 / 24), ((b * c * c) @ A @ c, 1 / 10),
                     (b @ A @ c ** 4, 1 / 30)):
        assert lhs == pytest.approx(rhs, abs=1e-14)
    for e, order in ((e5, 5), (e3, 3)):
        for q in range(1, order + 1):
            assert ((b - e) * c ** (q - 1)).sum() == pytest.approx(1.0 / q, abs=1e-14)
        assert abs(((b - e) * c ** order).sum() - 1.0 / (order + 1)) > 1e-4


@pytest.mark.parametrize("p", [P0, P1], ids=["alpha2=0 vs exact", "alpha2>0 vs tight"])
def test_dop853_error_stays_below_tolerance(refs, p):
    """dop853's error estimate is of order 7 in the step, conservative at loose
    tolerances (there the step is bounded by the driver, not by the error): the
    error is below tol L at every tolerance, never grows as tol falls, and falls by
    10x at least over the ladder."""
    tols = [1e-6, 1e-8, 1e-10]
    err = np.array([abs(x_end(p, "dop853", tol=t) - refs[p]) for t in tols])
    lx = p.r_y / p.k + abs(p.v) / p.omega
    assert (err < np.array(tols) * lx).all()
    assert (np.diff(err) <= 0).all() and err[-1] < 0.1 * err[0]


def test_dop853_and_dopri5_agree_on_a_stick_slip_cycle():
    """Two pairs, one answer: the stick-slip period and amplitude at tol 1e-12."""
    a, b = (sc.attractor(P1, method=m, tol=1e-12) for m in ("dopri5", "dop853"))
    assert a.regime == b.regime == "stick_slip"
    assert abs(a.period - b.period) < 1e-11 * a.period
    assert abs(a.amplitude - b.amplitude) < 1e-11 * (P1.r_y / P1.k + P1.v / P1.omega)


@pytest.mark.parametrize("forced", [False, True], ids=["autonomous", "a load"])
@pytest.mark.parametrize("method,order", [("dopri5", 4), ("dop853", 7)])
def test_dense_output_order(method, order, forced):
    """The continuous extension that events are located on (``stepper.extend``) is of
    the stated order inside the step: on a sliding arc of the linear law (alpha2 = 0:
    the field is affine, its flow a matrix exponential; with a harmonic load
    ``F0 cos(Omega t)`` the state grows by (cos, sin)(Omega t), still linear) the
    largest error at theta = 1/4, 1/2, 3/4 falls as h^(order + 1) over a ladder of
    steps, and the interpolant meets the step's own end at theta = 1 and its start at
    theta = 0. Under the load the extension's own stages must take the load at their
    own times (DOP853's c14, c15, c16), and the step starts at t0 != 0."""
    from numba import njit
    from scipy.linalg import expm

    from sweepcore import compiled
    from sweepcore._kernels import excitation, stepper
    from sweepcore._kernels.excitations import autonomous
    from sweepcore._kernels.jit import python_callable
    code = stepper.METHOD_CODES[method]
    F0, Om, t0 = (1.3, 2.1, 0.7) if forced else (0.0, 1.0, 0.0)
    params = sc.Params(5.0, 50.0, 10.0, 5.0, alpha1=1.0, alpha2=0.0, F0=F0, Omega=Om)
    p = params.row(0.0, 0.0)
    ((_m, _kind, _rows, lw),) = compiled.groups(p[None, :], (params.friction_law,),
                                                make_options(method), forced=forced)
    ex = params.loads[0].data() if forced else None
    step_fn, extend_fn = stepper.METHODS[code][6], stepper.EXTEND[code]

    @njit(cache=False)
    def run(ex, x0, z0, h, s, o, ths, out):
        owner = np.zeros(excitation.work_size(ex))
        fx = excitation.with_work(ex, owner)
        excitation.prepare(fx, p, lw)
        x1, z1, _a, _b, _c, _d, _e, _ok, ks = step_fn(t0, x0, z0, h, s, p, lw, fx, o,
                                                      False)
        dc = extend_fn(t0, x0, z0, h, s, p, lw, fx, x1, z1, ks)
        for i in range(ths.shape[0]):
            out[i, 0], out[i, 1] = stepper.interpolate(dc, ths[i], x0, z0)
        return x1, z1

    @njit(cache=False)
    def run_unforced(x0, z0, h, s, o, ths, out):
        fx = autonomous()
        x1, z1, _a, _b, _c, _d, _e, _ok, ks = step_fn(t0, x0, z0, h, s, p, lw, fx, o,
                                                      False)
        dc = extend_fn(t0, x0, z0, h, s, p, lw, fx, x1, z1, ks)
        for i in range(ths.shape[0]):
            out[i, 0], out[i, 1] = stepper.interpolate(dc, ths[i], x0, z0)
        return x1, z1

    o = make_options(method, tol=1e-8)
    s = -1.0                       # zdot < 0: F = -r_y - alpha1 zdot
    m, k, r, v, a1 = params.m, params.k, params.r_y, params.v, params.alpha1
    # y = (x, zdot, 1, cos(Om t), sin(Om t)): y' = J y
    J = np.array([[0.0, 1.0, v, 0.0, 0.0], [-k / m, a1 / m, -s * r / m, F0 / m, 0.0],
                  [0.0, 0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0, -Om],
                  [0.0, 0.0, 0.0, Om, 0.0]])
    x0, z0 = 0.1, -2.0
    y0 = np.array([x0, z0, 1.0, math.cos(Om * t0), math.sin(Om * t0)])
    hs = np.array([0.4, 0.2, 0.1, 0.05])
    ths = np.array([0.0, 0.25, 0.5, 0.75, 1.0])
    err = []
    for h in hs:
        out = np.empty((ths.size, 2))
        x1, z1 = run(ex, x0, z0, h, s, o, ths, out) if forced else \
            run_unforced(x0, z0, h, s, o, ths, out)
        e = 0.0
        for i, th in enumerate(ths[1:-1], start=1):
            xe, ze = (expm(J * th * h) @ y0)[:2]
            e = max(e, abs(out[i, 0] - xe), abs(out[i, 1] - ze) / params.omega)
        err.append(e)
        assert tuple(out[-1]) == pytest.approx((x1, z1), abs=1e-14)
        assert tuple(out[0]) == (x0, z0)
    assert order + 0.6 < slope(hs, err) < order + 1.6


def test_dop853_extension_stage_times_are_its_row_sums():
    """The fractions of the step at which DOP853's stages take the load are the row
    sums of its tableau: the step's (c2 .. c12, 1) and the extension's (1, c14, c15,
    c16, read from Hairer's contd8), else a load is taken at the wrong times."""
    from sweepcore._kernels import dop853
    rows = {14: (1, 7, 8, 9, 10, 11, 12, 13), 15: (1, 6, 7, 8, 11, 12, 13, 14),
            16: (1, 6, 7, 8, 9, 13, 14, 15)}
    for i, c in zip((14, 15, 16), dop853.EXTENSION_C[1:]):
        assert sum(getattr(dop853, f"A{i}_{j}") for j in rows[i]) == pytest.approx(
            c, abs=1e-14)
    A, _b, c, _e5, _e3 = _dop853_tableau()
    np.testing.assert_allclose(dop853.STAGE_C, c, atol=1e-15)


# a forced slider on a belt (two stops a period) under a harmonic load
FORCED = sc.Params(m=1.0, k=1.0, r_y=0.5, c=0.1, v=0.4, F0=1.0, Omega=1.3)


@pytest.fixture(scope="module")
def forced_ref():
    return sc.attractor(FORCED, method="dop853", tol=1e-12, x0=0.0, xdot0=0.0)


@pytest.mark.slow     # each compiles its method's forced kernels (20-40 s)
@pytest.mark.parametrize("method,dts,lo,hi", [
    ("gps", [2e-3, 1e-3], 0.9, 1.1),          # the paper's scheme, with time
    ("rk4", [0.04, 0.02, 0.01], 3.7, 4.3),
])
def test_every_method_runs_a_forced_slider_at_its_order(forced_ref, method, dts, lo, hi):
    """One driver for every method and excitation: the forced response's amplitude by
    the fixed-step methods converges to dop853's at their orders (GPS first, RK4
    fourth; the load taken at each stage's time), and dopri5's is within its
    tolerance."""
    assert forced_ref.status == "ok" and forced_ref.stops_per_period == 2
    err = []
    for d in dts:
        res = sc.attractor(FORCED, method=method, dt=d, x0=0.0, xdot0=0.0)
        assert res.status == "ok" and res.stops_per_period == 2, res
        err.append(abs(res.amplitude - forced_ref.amplitude))
    assert lo < slope(dts, err) < hi
    res = sc.attractor(FORCED, method="dopri5", tol=1e-8, x0=0.0, xdot0=0.0)
    assert abs(res.amplitude - forced_ref.amplitude) <= 1e-8 * (FORCED.r_y + FORCED.F0)
