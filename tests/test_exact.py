"""Exactness: the event-driven stepper against closed forms (alpha2 = 0).

Tolerances are 1e-12 relative unless noted: the exact method has no truncation error,
so what is left is rounding.
"""
import math

import numpy as np
import pytest

import sweepcore as sc
from conftest import radius

RTOL = 1e-12


def kinds(ds):
    names = ds.event_kind.attrs["flag_meanings"].split()
    values = list(ds.event_kind.attrs["flag_values"])
    return [names[values.index(k)] for k in ds.event_kind.values]


def test_paper_case_slip_time_eq27(paper):
    ds = sc.simulate(sc.Params(**paper), 1.0, method="exact")
    assert kinds(ds)[0] == "slip"
    t_slip = paper["r_y"] / (paper["k"] * paper["v"])          # eq. (32): 0.04 s
    assert ds.event_time.values[0] == pytest.approx(t_slip, rel=RTOL)
    assert ds.event_x.values[0] == paper["r_y"] / paper["k"]


def test_paper_case_orbit_is_the_circle_eq39(paper):
    p = sc.Params(**paper)
    w = p.omega
    ds = sc.simulate(p, 40.0, method="exact", output_dt=0.01)
    after = ds.time.values > 0.04
    r = radius(ds.x.values[after], ds.xdot.values[after], p.r_y / p.k, w)
    np.testing.assert_allclose(r, p.v / w, rtol=RTOL)
    # every later event is a zero-duration (abnormal) stop, one period apart
    k = kinds(ds)
    assert k[0] == "slip" and set(k[1:]) == {"abnormal_stop"}
    np.testing.assert_allclose(np.diff(ds.event_time.values), 2 * math.pi / w, rtol=RTOL)
    # no finite stick: after the first slip the phase is never 0
    assert (ds.phase.values[after] != 0).all()
    assert float(ds["time_stuck"]) == pytest.approx(0.04, rel=RTOL)


@pytest.mark.parametrize("r_y", [0.5, 10.0, 40.0])
def test_amplitude_does_not_depend_on_r_y(paper, r_y):
    p = sc.Params(**{**paper, "r_y": r_y})
    ds = sc.simulate(p, 20.0, method="exact", output_dt=0.005)
    after = ds.time.values > r_y / (p.k * p.v)
    x = ds.x.values[after]
    # sampled extremes lie on the circle up to the sampling grid; the circle's
    # radius itself is checked to rounding
    np.testing.assert_allclose(radius(x, ds.xdot.values[after], r_y / p.k, p.omega),
                               p.v / p.omega, rtol=RTOL)
    assert 0.5 * (x.max() - x.min()) == pytest.approx(p.v / p.omega, rel=1e-4)


def test_start_at_rest_is_a_small_circle_that_never_reaches_the_belt(paper):
    p = sc.Params(**paper)
    ds = sc.simulate(p, 30.0, x0=0.0, xdot0=0.0, method="exact", output_dt=0.01)
    r = radius(ds.x.values, ds.xdot.values, p.r_y / p.k, p.omega)
    np.testing.assert_allclose(r, p.r_y / p.k, rtol=RTOL)
    assert ds.sizes["event"] == 0
    assert ds.xdot.values.max() < p.v


def start_radius(p, x0, xd0):
    return math.hypot(x0 - p.r_y / p.k, xd0 / p.omega)


# starts: inside the small-circle family, on the switching line inside and outside
# the stick band, faster than the belt, and far out (slide-slide reversals)
STARTS = [(0.0, 0.0), (1.0, -2.0), (0.1, 5.0), (-0.15, 5.0), (3.0, 5.0), (-4.0, 5.0),
          (0.0, 9.0), (-20.0, 0.0), (50.0, -30.0), (0.2, 5.0)]


@pytest.mark.parametrize("x0,xd0", STARTS)
def test_long_run_amplitude_is_min_of_start_radius_and_v_over_omega(paper, x0, xd0):
    p = sc.Params(**paper)
    a = sc.attractor(p, x0=x0, xdot0=xd0, method="exact")
    expect = min(start_radius(p, x0, xd0), p.v / p.omega)
    assert a.converged
    assert a.amplitude == pytest.approx(expect, rel=1e-11)
    assert a.mean == pytest.approx(p.r_y / p.k, rel=1e-11)
    assert a.period == pytest.approx(2 * math.pi / p.omega, rel=1e-11)


def test_reversals_happen_for_a_far_start(paper):
    p = sc.Params(**paper)
    ds = sc.simulate(p, 80.0, x0=-20.0, xdot0=0.0, method="exact")
    k = kinds(ds)
    assert "normal_stop" in k                 # slide-slide reversal, eq. (30)
    assert "stick" in k and "slip" in k       # then a stick and the reset slip


@pytest.mark.parametrize("x0,xd0", [(0.0, None), (-3.0, 0.0), (0.7, 9.0)])
@pytest.mark.parametrize("alpha1", [0.0, 0.3])
def test_mirror_symmetry_v_to_minus_v(paper, x0, xd0, alpha1):
    p = sc.Params(**paper, alpha1=alpha1)
    q = sc.Params(**{**paper, "v": -paper["v"]}, alpha1=alpha1)
    xd0_m = None if xd0 is None else -xd0
    a = sc.simulate(p, 15.0, x0=x0, xdot0=xd0, method="exact", output_dt=0.01)
    b = sc.simulate(q, 15.0, x0=-x0, xdot0=xd0_m, method="exact", output_dt=0.01)
    np.testing.assert_allclose(b.x.values, -a.x.values, rtol=RTOL, atol=1e-13)
    np.testing.assert_allclose(b.xdot.values, -a.xdot.values, rtol=RTOL, atol=1e-13)
    np.testing.assert_array_equal(b.event_kind.values, a.event_kind.values)


def friction_work_from_events(ds, p):
    """W = int r_a xdot dt from closed forms: r_y s dx while sliding, -k d(x^2)/2 stuck."""
    t = np.concatenate([[0.0], ds.event_time.values, [ds.time.values[-1]]])
    x = np.concatenate([[ds.x.values[0]], ds.event_x.values, [ds.x.values[-1]]])
    phase = ds.phase.to_series()
    w = 0.0
    for i in range(len(t) - 1):
        mid = 0.5 * (t[i] + t[i + 1])
        s = int(phase.iloc[np.searchsorted(ds.time.values, mid) - 1]) if t[i + 1] > t[i] else 0
        # the phase on (t_i, t_i+1) is the phase just after event i
        s = int(ds.phase.sel(time=mid, method="nearest")) if t[i + 1] - t[i] > 0.02 else s
        if s == 0:
            w += -0.5 * p.k * (x[i + 1] ** 2 - x[i] ** 2)
        else:
            w += p.r_y * s * (x[i + 1] - x[i])
    return w


def test_energy_balance_from_closed_forms(paper):
    """Change of k x^2/2 + m xdot^2/2 equals minus the friction work (constant law)."""
    p = sc.Params(**paper)
    ds = sc.simulate(p, 25.0, x0=-20.0, xdot0=0.0, method="exact", output_dt=0.001)
    e = 0.5 * p.k * ds.x.values ** 2 + 0.5 * p.m * ds.xdot.values ** 2
    w = friction_work_from_events(ds, p)
    assert e[-1] - e[0] == pytest.approx(-w, rel=1e-10)
    # and the kernel's own quadrature of r_a xdot agrees
    assert float(ds["friction_work"]) == pytest.approx(w, rel=1e-10)


@pytest.mark.parametrize("alpha1", [0.5, -0.5, 4.0])
def test_linear_law_events_are_zeros_of_zdot(paper, alpha1):
    """alpha1 != 0, alpha2 = 0: events located by safeguarded Newton on the closed form.

    Checked independently: scipy DOP853 (rtol 1e-13) from each event's state to the
    next event's time must find zdot = 0 there.
    """
    from scipy.integrate import solve_ivp
    p = sc.Params(**paper, alpha1=alpha1)
    ds = sc.simulate(p, 12.0, x0=-3.0, xdot0=0.0, method="exact")
    t, x, xd = ds.event_time.values, ds.event_x.values, ds.event_xdot.values
    assert len(t) >= 3
    for i in range(len(t) - 1):
        zd0 = xd[i] - p.v
        if zd0 != 0.0 or t[i + 1] - t[i] < 1e-9:
            continue
        if ds.event_kind.values[i] == 2:          # a stick: the next event is its slip
            continue
        s = int(ds.phase.sel(time=t[i] + 1e-6, method="bfill"))

        def rhs(_t, y):
            return [y[1] + p.v, (-p.k * y[0] - (p.r_y * s - p.alpha1 * y[1])) / p.m]
        sol = solve_ivp(rhs, (t[i], t[i + 1]), [x[i], 0.0], method="DOP853",
                        rtol=1e-13, atol=1e-15)
        assert abs(sol.y[1, -1]) <= 1e-9 * p.v
        assert sol.y[0, -1] == pytest.approx(x[i + 1], rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("alpha1", [0.5, -0.8])
def test_linear_law_trajectory_matches_independent_integration(paper, alpha1):
    from reference import reference_run
    p = sc.Params(**paper, alpha1=alpha1)
    ds = sc.simulate(p, 15.0, x0=-3.0, xdot0=0.0, method="exact", output_dt=0.01)
    xr, xdr, evs = reference_run(p.m, p.k, p.r_y, p.v, p.alpha1, 0.0, -3.0, 0.0,
                                 ds.time.values, rtol=1e-12)
    np.testing.assert_allclose(ds.x.values, xr, atol=1e-8)
    np.testing.assert_allclose(ds.xdot.values, xdr, atol=1e-7)
    np.testing.assert_allclose(ds.event_time.values[:len(evs)],
                               [e[0] for e in evs][:ds.sizes["event"]], atol=1e-9)
