"""Hard cases: each ends in finite, flagged results, in bounded time, with no hang.

"Flagged" means: either the answer is right (checked against a closed form or
symmetry), or the status says why there is none. Never a plausible wrong number
with status "ok".
"""
import math

import numpy as np
import pytest

import sweepcore as sc

PAPER = dict(m=5.0, k=50.0, r_y=10.0, v=5.0)


def finite_or_flagged(a):
    if a.converged:
        assert all(math.isfinite(getattr(a, n)) for n in ("amplitude", "mean"))
    else:
        assert a.status != "ok"


@pytest.mark.parametrize("method,dt", [("rk4", 0.01), ("gps", 0.01), ("rk4", 0.0015)])
def test_stiff_spring_with_too_large_a_step_is_refused(method, dt):
    p = sc.Params(m=1.0, k=1e6, r_y=10.0, v=5.0, alpha1=1.0, alpha2=0.01)   # omega 1e3
    a = sc.attractor(p, method=method, dt=dt)
    assert (a.regime, a.status) == ("failed", "fixed_step_too_large")
    assert math.isnan(a.amplitude)
    assert sc.simulate(p, 0.01, method=method, dt=dt).attrs["status"] == "fixed_step_too_large"


def test_stiff_spring_adaptive_gives_the_scaled_cycle():
    """k/m = 1e6: the paper's case with time scaled by omega; dopri5 adapts."""
    p = sc.Params(m=1.0, k=1e6, r_y=10.0, v=5.0)
    a = sc.attractor(p, method="dopri5", tol=1e-10)
    assert a.converged and a.amplitude == pytest.approx(p.v / p.omega, rel=1e-8)
    assert a.period == pytest.approx(2 * math.pi / p.omega, rel=1e-8)


def test_unstable_fixed_step_diverges_with_a_status():
    a = sc.attractor(sc.Params(**PAPER, alpha1=1.0, alpha2=10.0), method="rk4")
    assert (a.regime, a.status) == ("failed", "diverged")


@pytest.mark.parametrize("alpha2", [1.0, 10.0])
def test_large_cubic_coefficient_reaches_its_equilibrium(alpha2):
    p = sc.Params(**PAPER, alpha1=1.0, alpha2=alpha2)
    a = sc.attractor(p)
    assert a.regime == "equilibrium" and a.mean == pytest.approx(p.x_eq, rel=1e-12)


def test_tiny_belt_speed_long_sticks_many_events():
    p = sc.Params(**{**PAPER, "v": 1e-6}, alpha1=1.0, alpha2=0.01)
    a = sc.attractor(p)                      # first stick lasts r_y/(k v) = 2e5 s
    assert a.regime == "stick_slip" and a.converged
    assert a.t_settle == pytest.approx(p.r_y / (p.k * p.v), rel=1e-12)
    ds = sc.simulate(p, 2e5 + 2000.0, output_dt=100.0)
    assert ds.attrs["status"] == "ok" and ds.sizes["event"] > 1000
    assert np.isfinite(ds.x.values).all()


@pytest.mark.parametrize("alpha2", [0.0, 0.01, 0.05])
def test_negative_belt_speed_is_the_mirror_image(alpha2):
    a = sc.attractor(sc.Params(**PAPER, alpha1=1.0, alpha2=alpha2))
    b = sc.attractor(sc.Params(**{**PAPER, "v": -5.0}, alpha1=1.0, alpha2=alpha2))
    assert b.regime == a.regime
    assert b.amplitude == pytest.approx(a.amplitude, rel=1e-12, abs=1e-15)
    assert b.mean == pytest.approx(-a.mean, rel=1e-12, abs=1e-15)


def test_zero_friction_bound_is_a_smooth_friction_law():
    a = sc.attractor(sc.Params(**{**PAPER, "r_y": 0.0}))
    assert a.amplitude == pytest.approx(5.0 / math.sqrt(10.0), rel=1e-12)   # v/omega
    b = sc.attractor(sc.Params(**{**PAPER, "r_y": 0.0}, alpha1=1.0, alpha2=0.01))
    finite_or_flagged(b)


@pytest.mark.parametrize("x0", [0.2, -0.2, 0.1999999999, 0.2000000001, 0.0])
def test_start_exactly_on_the_switching_line(x0):
    """xdot0 = v: inside the stick band it sticks, at/after the breakaway it slides."""
    p = sc.Params(**PAPER, alpha1=1.0, alpha2=0.01)
    a = sc.attractor(p, x0=x0, xdot0=5.0)
    ref = sc.attractor(p)                    # the stuck start: same cycle
    assert a.regime == "stick_slip"
    assert a.amplitude == pytest.approx(ref.amplitude, rel=1e-7)
    ds = sc.simulate(p, 3.0, x0=x0, xdot0=5.0)
    assert ds.attrs["status"] == "ok"
    assert ds.sizes["event"] < 10            # no chain of zero-length events


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_q_within_1e_9_of_zero_is_decided_by_the_normal_form(sign):
    """|q| = 2e-11 s-1: the transient lasts ~1e11 s, so no integration can wait for
    it. The Hopf normal form decides: q < 0 decays to x_eq (its cubic coefficient is
    stabilising), q > 0 has the cycle (A omega)^2 = 4 m q / (3 alpha2), whose
    neglected terms are ~q/omega = 6e-12 relative here."""
    v = 5.0
    a2 = 1.0 / (3.0 * v * v) * (1.0 + sign * 1e-10)
    p = sc.Params(**PAPER, alpha1=1.0, alpha2=a2)
    assert abs(p.q) < 1e-9
    a = sc.attractor(p, max_periods=300)
    assert a.status == "ok"
    if p.q < 0.0:
        assert a.regime == "equilibrium"
    else:
        q = 1e-10 / PAPER["m"]          # alpha1 - 3 alpha2 v^2 = 1e-10 exactly
        omega = (PAPER["k"] / PAPER["m"]) ** 0.5
        closed = (4.0 * PAPER["m"] * q / (3.0 * a2)) ** 0.5 / omega
        assert a.regime == "slip_cycle"
        assert a.amplitude == pytest.approx(closed, rel=1e-5)
        assert 0.0 < 1.0 - a.floquet < 1e-9


def test_huge_start_forces_slide_slide_reversals():
    p = sc.Params(**PAPER, alpha1=1.0, alpha2=0.01)
    a = sc.attractor(p, x0=1e4, xdot0=0.0)
    assert a.regime == "stick_slip"
    assert a.amplitude == pytest.approx(sc.attractor(p).amplitude, rel=1e-6)
    # constant friction: each half swing loses 2 r_y/k; from 1e4 cm that takes longer
    # than the budget, and the point says so
    b = sc.attractor(sc.Params(**PAPER), x0=1e4, xdot0=0.0, max_periods=50)
    assert (b.regime, b.status) == ("unconverged", "unconverged")
    c = sc.attractor(sc.Params(**PAPER), x0=40.0, xdot0=0.0)
    assert c.amplitude == pytest.approx(5.0 / math.sqrt(10.0), rel=1e-11)


def test_1e5_periods_lose_no_digits():
    """t_end = 1e5 periods: x stays bounded, so no digits go into a growing z."""
    p = sc.Params(**PAPER)
    ds = sc.simulate(p, 1e5 * 2 * math.pi / p.omega, output_dt=997.0, method="exact")
    after = ds.time.values > 1.0
    r = np.hypot(ds.x.values[after] - 0.2, ds.xdot.values[after] / p.omega)
    np.testing.assert_allclose(r, p.v / p.omega, rtol=1e-13)
    assert ds.attrs["status"] == "ok"


def test_static_belt_sticks_for_ever():
    """v = 0 from x0 = 1: swings 1 -> -0.6 -> 0.2 (each loses 2 r_y/k), stuck at 0.2."""
    a = sc.attractor(sc.Params(**{**PAPER, "v": 0.0}), x0=1.0, xdot0=0.0)
    assert a.regime == "stuck" and a.stick_fraction == 1.0
    assert a.mean == pytest.approx(0.2, rel=1e-12)


def test_static_belt_decay_is_the_coulomb_staircase():
    """v = 0, constant friction: swings about +-r_y/k shrink by 2 r_y/k each."""
    ds = sc.simulate(sc.Params(**{**PAPER, "v": 0.0}), 10.0, x0=1.0, xdot0=0.0,
                     method="exact")
    x = ds.event_x.values
    # turning points 1.0 -> -0.6 -> 0.2 (inside |x| <= 0.2: stick at 0.2)
    np.testing.assert_allclose(x, [-0.6, 0.2], rtol=1e-12)
    assert ds.event_kind.values[-1] == 2     # stick


def test_overdamped_laws():
    up = sc.attractor(sc.Params(**PAPER, alpha1=100.0))     # sigma = 10 > omega
    assert (up.regime, up.status) == ("unbounded", "diverged")
    down = sc.attractor(sc.Params(**PAPER, alpha1=-100.0))
    assert down.regime == "equilibrium"
    assert down.mean == pytest.approx(sc.Params(**PAPER, alpha1=-100.0).x_eq, rel=1e-12)


def test_gps_denominator_guard_stops_the_point_with_a_status():
    """With the shift a = -r_y/k, ||u|| = 0 exactly at the breakaway point: the
    denominator ||u||^2 - tau^2 ||f||^2 is negative at every step size."""
    p = sc.Params(**PAPER, alpha1=1.0, alpha2=0.01)
    a = sc.attractor(p, method="gps", dt=1e-3, gps_a=-p.r_y / p.k)
    assert (a.regime, a.status) == ("failed", "gps_denominator_guard")
    ds = sc.simulate(p, 1.0, method="gps", dt=1e-3, gps_a=-p.r_y / p.k)
    assert ds.attrs["status"] == "gps_denominator_guard"
    assert np.isnan(ds.x.values[-1])          # no plausible number after the failure
