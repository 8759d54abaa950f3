"""Attractor observables: closed forms, agreement between methods and tolerances,
and the definitions (whole-period mean, cycle size) checked independently."""
import math

import numpy as np
import pytest

import sweepcore as sc

PAPER = dict(m=5.0, k=50.0, r_y=10.0, v=5.0)


def test_constant_friction_started_stuck_closed_form():
    p = sc.Params(**PAPER)
    a = sc.attractor(p)
    w = p.omega
    assert a.regime == "slip_cycle" and a.converged       # the grazing cycle
    assert a.amplitude == pytest.approx(p.v / w, rel=1e-10)
    assert a.cycle_size == pytest.approx(p.v / w, rel=1e-10)
    assert a.velocity_amplitude == pytest.approx(p.v, rel=1e-10)
    assert a.mean == pytest.approx(p.r_y / p.k, rel=1e-10)
    assert a.period == pytest.approx(2 * math.pi / w, rel=1e-10)
    assert a.stick_fraction == 0.0 and a.sticks_per_period == 0


def test_constant_friction_small_start_is_neutral():
    p = sc.Params(**PAPER)
    a = sc.attractor(p, x0=0.0, xdot0=0.0)
    assert a.regime == "neutral" and a.amplitude == pytest.approx(p.r_y / p.k, rel=1e-10)


def test_stable_case_is_the_equilibrium_x_eq():
    p = sc.Params(**PAPER, alpha1=1.0, alpha2=0.05)        # q = -0.55
    a = sc.attractor(p)
    assert a.regime == "equilibrium" and a.converged
    assert a.mean == pytest.approx(p.x_eq, rel=1e-12)
    assert a.amplitude == 0.0 and a.cycle_size == 0.0 and math.isnan(a.period)
    # and the run really gets there: a long simulation ends at x_eq, at rest
    ds = sc.simulate(p, 200.0, output_dt=1.0)
    assert ds.x.values[-1] == pytest.approx(p.x_eq, abs=1e-9)


@pytest.fixture(scope="module")
def stick_slip():
    p = sc.Params(**PAPER, alpha1=1.0, alpha2=0.01)        # q = 0.05
    return p, {tol: sc.attractor(p, method="dopri5", tol=tol) for tol in (1e-10, 1e-12)}


def test_stick_slip_agrees_between_tolerances(stick_slip):
    p, runs = stick_slip
    a, b = runs[1e-10], runs[1e-12]
    assert a.regime == b.regime == "stick_slip"
    for name in ("amplitude", "mean", "period", "cycle_size", "stick_fraction"):
        assert getattr(a, name) == pytest.approx(getattr(b, name), rel=1e-8), name
    assert a.sticks_per_period == 1


def test_stick_slip_agrees_between_adaptive_and_rk4(stick_slip):
    p, runs = stick_slip
    r = sc.attractor(p, method="rk4", dt=1e-3)
    for name in ("amplitude", "mean", "period"):
        assert getattr(r, name) == pytest.approx(getattr(runs[1e-12], name), rel=1e-8), name


def test_mean_is_the_average_over_whole_periods(stick_slip):
    """Independent check: sample one period finely and integrate x (Simpson).

    A window average over 1.5 periods differs by far more than the tolerance, so
    this test fails for a windowed mean.
    """
    from scipy.integrate import simpson
    p, runs = stick_slip
    a = runs[1e-12]
    T = a.period
    # start at the breakaway point: the cycle then begins at t = 0, on the sample grid
    xs = p.r_y / p.k
    assert sc.attractor(p, x0=xs, xdot0=p.v, tol=1e-12).t_settle == 0.0
    n = 40001
    ds = sc.simulate(p, 2 * T, x0=xs, xdot0=p.v, method="dopri5", tol=1e-12,
                     output_dt=T / (n - 1))
    t = ds.time.values
    sel = t <= T * (1 + 1e-12)
    assert sel.sum() == n
    whole = simpson(ds.x.values[sel], x=t[sel]) / T
    assert a.mean == pytest.approx(whole, rel=1e-7)
    win = t <= 1.5 * T
    windowed = simpson(ds.x.values[win], x=t[win]) / (t[win][-1] - t[win][0])
    assert abs(windowed - whole) > 1e-3 * abs(whole)


def test_cycle_size_is_sqrt_area_over_pi(stick_slip):
    """Area of the orbit in (x, xdot/omega) by the shoelace formula on samples."""
    p, runs = stick_slip
    a = runs[1e-12]
    ds = sc.simulate(p, a.period, x0=p.r_y / p.k, xdot0=p.v, method="dopri5",
                     tol=1e-12, output_dt=a.period / 40000)
    x, y = ds.x.values, ds.xdot.values / p.omega
    area = 0.5 * abs(np.dot(x, np.roll(y, 1)) - np.dot(y, np.roll(x, 1)))
    assert a.cycle_size == pytest.approx(math.sqrt(area / math.pi), rel=1e-5)
    assert a.amplitude == pytest.approx(0.5 * (x.max() - x.min()), rel=1e-6)


def test_slip_cycle_below_v_star_converges_and_agrees():
    """Just below v* the cycle never sticks (amplitude ~ sqrt(q)); two tolerances agree."""
    p = sc.Params(**{**PAPER, "v": 5.6}, alpha1=1.0, alpha2=0.01)   # v* = 5.77
    a = sc.attractor(p, tol=1e-10)
    b = sc.attractor(p, tol=1e-12)
    assert a.regime == b.regime == "slip_cycle"
    assert a.amplitude == pytest.approx(b.amplitude, rel=1e-6)
    assert a.period == pytest.approx(b.period, rel=1e-8)
    # small-amplitude (averaging) prediction: (A omega)^2 = 4 m q / (3 alpha2)
    pred = math.sqrt(4 * p.m * p.q / (3 * p.alpha2)) / p.omega
    assert a.amplitude == pytest.approx(pred, rel=0.1)


def test_initial_condition_axes_find_different_attractors():
    """Constant friction: the amplitude depends on the start (design fact 1)."""
    p = sc.Params(**PAPER)
    amps = {sc.attractor(p, x0=x0, xdot0=0.0).amplitude for x0 in (0.0, 0.5, 1.0)}
    assert len(amps) == 3
