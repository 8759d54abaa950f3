"""The friction-law family (sweepcore/_kernels/law.py) against an independent solver.

Every check compares sweepcore with ``tests/reference.py`` (scipy only, written from
the physics, sharing no code with the kernels), with a closed form, or with an
exact invariance of the equations. Tolerances: observables at the default tol 1e-8
are within a few tol L (L = r_y/k + |v|/omega); 1e-7 L is asserted, and the accuracy
contract of status ok (1e-6 relative, or 1e-6 L absolute near 0) on random points.
"""
import math

import numpy as np
import pytest

import sweepcore as sc
from sweepcore import law

from reference import (reference_equilibrium, reference_hopf, reference_slip_cycle,
                       reference_stick_slip_cycle)

# the bSTAB / pybasin friction case (Stender, Hoffmann & Papangelo 2020) in sweepcore's
# terms: x'' + 0.1 x' + x = -F, mu_d = 0.5, mu_sd = 2, v0 = 0.5
BSTAB = dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.5, c=0.1, alpha1=0.0, alpha2=0.0)
# a law with every term (Stribeck, cubic, damping), away from the published case
FAMILY = dict(m=2.0, k=3.0, r_y=1.2, r_k=0.7, v_s=0.3, c=0.05, alpha1=0.1, alpha2=0.02)
# Stribeck with a stabilising cubic term: a supercritical Hopf point (stable slip cycles)
SUPER = dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.5, c=0.02, alpha1=0.6, alpha2=0.1)


def scale(p):
    return p.r_y / p.k + abs(p.v) / p.omega


def ref_kwargs(p):
    return dict(c=p.c, r_k=p.r_k, v_s=p.v_s if p.v_s is not None else 1.0)


# ----------------------------------------------------------- analytic quantities
def test_bstab_hopf_speed_is_ln10_over_2_and_subcritical():
    p = sc.Params(**BSTAB, v=1.5)
    assert p.v_star == pytest.approx(math.log(10.0) / 2.0, rel=1e-14)
    assert p.q == pytest.approx(-(0.1 - math.exp(-3.0)), rel=1e-14)   # c + F'(-v)
    assert p.criticality == "subcritical" and p.first_lyapunov > 0.0


@pytest.mark.parametrize("pars, lo, hi", [(BSTAB, 1.0, 1.3), (FAMILY, 0.9, 1.4),
                                          (SUPER, 1.2, 1.7)])
def test_hopf_speed_and_criticality_against_the_reference(pars, lo, hi):
    p = sc.Params(**pars, v=1.0)
    ref = reference_hopf(p.m, p.k, p.r_y, p.alpha1, p.alpha2, lo, hi, **ref_kwargs(p))
    assert p.v_star == pytest.approx(ref["v_hopf"], rel=1e-9)
    assert p.criticality == ref["criticality"]


def test_criticality_follows_the_sign_of_the_third_derivative_on_random_laws():
    rng = np.random.default_rng(7)
    for _ in range(40):
        pars = dict(m=10 ** rng.uniform(-1, 1), k=10 ** rng.uniform(-1, 1), r_y=1.0,
                    r_k=rng.uniform(0.1, 0.9), v_s=10 ** rng.uniform(-1, 0.5),
                    c=rng.uniform(0, 0.2), alpha1=rng.uniform(0, 1),
                    alpha2=10 ** rng.uniform(-3, 0))
        p = sc.Params(**pars, v=1.0)
        if not math.isfinite(p.v_star):
            assert p.criticality == "none"
            continue
        ref = reference_equilibrium(p.m, p.k, p.r_y, p.v_star, p.alpha1, p.alpha2,
                                    **ref_kwargs(p))
        assert abs(ref["damping"]) < 1e-6             # v_star is a Hopf speed
        if abs(ref["f3"]) > 1e-6:
            assert p.criticality == ref["criticality"]


def test_paper_law_is_supercritical_with_the_averaging_coefficient():
    p = sc.Params(m=5.0, k=50.0, r_y=10.0, v=5.0, alpha1=1.0, alpha2=0.01)
    # l1 = -omega^2 F'''/(16 m) with F''' = 6 alpha2 (first-order averaging)
    assert p.first_lyapunov == pytest.approx(-10.0 * 0.06 / 80.0, rel=1e-14)
    assert p.criticality == "supercritical"


@pytest.mark.parametrize("pars", [BSTAB, FAMILY, SUPER])
@pytest.mark.parametrize("v", [0.4, 1.1, 2.5])
def test_equilibrium_position_and_damping_against_the_force_balance(pars, v):
    p = sc.Params(**pars, v=v)
    ref = reference_equilibrium(p.m, p.k, p.r_y, v, p.alpha1, p.alpha2, **ref_kwargs(p))
    assert p.x_eq == pytest.approx(ref["x_eq"], rel=1e-13, abs=1e-15)
    assert -p.q * p.m == pytest.approx(ref["damping"], rel=1e-6, abs=1e-9)


def test_two_hopf_speeds_where_the_law_strengthens_at_low_speed():
    # r_k > r_y: the Stribeck term stabilises low speeds; with a negative linear
    # slope and a cubic term steady sliding is unstable between two speeds
    p = sc.Params(m=1.0, k=1.0, r_y=0.5, r_k=1.0, v_s=0.2, alpha1=1.0, alpha2=0.1, v=1.0)
    u1, u2 = p.hopf_speeds
    for u in (u1, u2):
        ref = reference_equilibrium(1.0, 1.0, 0.5, u, 1.0, 0.1, r_k=1.0, v_s=0.2)
        assert abs(ref["damping"]) < 1e-9
    assert 0.0 < u1 < u2


def test_no_hopf_speed_is_said_so():
    stable = sc.Params(m=1.0, k=1.0, r_y=1.0, r_k=0.9, v_s=1.0, c=1.0, v=1.0)
    unstable = sc.Params(m=1.0, k=1.0, r_y=1.0, alpha1=1.0, v=1.0)
    assert math.isnan(stable.v_star) and stable.hopf_speeds == ()
    assert stable.criticality == "none"
    assert unstable.v_star == math.inf and unstable.hopf_speeds == ()


def test_friction_force_is_eq_40_for_r_k_equal_r_y_and_continuous_at_rest():
    s = np.array([-3.0, -0.5, 1e-300, 0.7])
    cubic = dict(m=1.0, k=1.0, r_y=2.0, v=1.0, alpha1=0.3, alpha2=0.05)
    np.testing.assert_array_equal(
        law.friction(s, cubic), 2.0 * np.sign(s) - 0.3 * s + 0.05 * s ** 3)
    p = sc.Params(**BSTAB, v=1.0)
    assert law.friction(1e-300, p) == p.r_y                  # F(0+) = r_y, the bound
    assert law.friction(50.0, p) == pytest.approx(p.r_k)     # high speed: r_k
    assert law.friction(0.5, p) == pytest.approx(0.5 + 0.5 * math.exp(-1.0), rel=1e-15)


# ------------------------------------------------------------------ attractors
@pytest.mark.parametrize("pars, v", [(BSTAB, 1.175), (BSTAB, 1.5), (BSTAB, 1.83),
                                     (FAMILY, 0.3), (FAMILY, 0.8), (FAMILY, 1.3)])
def test_stick_slip_cycle_against_the_reference(pars, v):
    p = sc.Params(**pars, v=v)
    a = sc.attractor(p)
    ref = reference_stick_slip_cycle(p.m, p.k, p.r_y, v, p.alpha1, p.alpha2,
                                     **ref_kwargs(p))
    assert a.status == "ok" and a.regime == "stick_slip" and a.floquet == 0.0
    L = scale(p)
    for name in ("amplitude", "x_max", "x_min", "mean"):
        assert abs(getattr(a, name) - ref[name]) <= 1e-7 * L, name
    assert a.period == pytest.approx(ref["period"], rel=1e-7)
    # (next to the fold the return to belt speed is almost tangential, so the time
    # at which the stick begins is ill-conditioned: the contract's absolute 1e-6)
    assert a.stick_fraction == pytest.approx(ref["stick_time"] / ref["period"], abs=1e-6)


@pytest.mark.parametrize("nu", [0.99, 0.999])
def test_slip_cycle_and_floquet_multiplier_against_shooting(nu):
    """A Stribeck law with a supercritical Hopf point: stable slip cycles below v*;
    the multiplier comes from Liouville's formula with the law's own divergence."""
    p = sc.Params(**SUPER, v=nu * sc.Params(**SUPER, v=1.0).v_star)
    a = sc.attractor(p)
    assert a.status == "ok" and a.regime == "slip_cycle"
    ref = reference_slip_cycle(p.m, p.k, p.r_y, p.v, p.alpha1, p.alpha2, a.x_max,
                               **ref_kwargs(p))
    L = scale(p)
    for name in ("amplitude", "x_max", "x_min", "mean"):
        assert abs(getattr(a, name) - ref[name]) <= 1e-7 * L, name
    assert a.period == pytest.approx(ref["period"], rel=1e-7)
    assert a.floquet == pytest.approx(ref["floquet"], abs=1e-7)
    assert a.floquet == pytest.approx(math.exp(-p.q * a.period), abs=0.05)


@pytest.mark.parametrize("v", [1.9, 2.5])
def test_above_the_fold_the_stuck_start_ends_at_rest(v):
    p = sc.Params(**BSTAB, v=v)
    a = sc.attractor(p)
    ref = reference_equilibrium(p.m, p.k, p.r_y, v, 0.0, 0.0, **ref_kwargs(p))
    assert a.status == "ok" and a.regime == "equilibrium"
    assert a.mean == pytest.approx(ref["x_eq"], rel=1e-13)


def test_start_inside_the_unstable_cycle_decays_to_rest():
    """Bistable band (v = 1.5): near x_eq, inside the unstable slip cycle (x_max
    1.855 by the reference), steady sliding is reached: the energy certificate holds
    for the Stribeck law's secant slopes."""
    p = sc.Params(**BSTAB, v=1.5)
    a = sc.attractor(p, x0=p.x_eq + 0.3, xdot0=0.0)
    assert a.status == "ok" and a.regime == "equilibrium"
    assert a.mean == p.x_eq


def test_exact_method_takes_viscous_damping_in_closed_form():
    """Constant friction with damping: the slide after the breakaway is a decaying
    sinusoid about r_y/k that never returns to belt speed: steady sliding. The
    closed form and dopri5 at a tight tolerance agree along the way."""
    p = sc.Params(m=2.0, k=8.0, r_y=1.0, v=0.5, c=0.4)
    t = np.linspace(0.0, 6.0, 13)
    ex = sc.simulate(p, 6.0, method="exact", output_dt=0.5)
    dp = sc.simulate(p, 6.0, method="dopri5", tol=1e-12, output_dt=0.5)
    np.testing.assert_allclose(ex.x.values, dp.x.values, rtol=0, atol=1e-10)
    # closed form of the first slide: y'' + (c/m) y' + (k/m) y = 0 about r_y/k
    t_slip = (p.r_y - p.c * p.v) / p.k / p.v
    s = t[t > t_slip] - t_slip
    sig, w = -p.c / (2 * p.m), math.sqrt(p.k / p.m - (p.c / (2 * p.m)) ** 2)
    y0, yd0 = (p.r_y - p.c * p.v) / p.k - p.r_y / p.k, p.v
    y = np.exp(sig * s) * (y0 * np.cos(w * s) + (yd0 - sig * y0) / w * np.sin(w * s))
    np.testing.assert_allclose(ex.x.values[t > t_slip], p.r_y / p.k + y, atol=1e-13)
    assert sc.attractor(p).regime == "equilibrium"


def test_exact_method_is_refused_for_a_stribeck_law():
    with pytest.raises(ValueError, match="piecewise-linear law"):
        sc.attractor(sc.Params(**BSTAB, v=1.5), method="exact")


# ------------------------------------------------------------------ invariances
def _groups_cubic(eps, nu, m, k, r_y, vstar):
    """Eq. (40) without damping with eps = alpha1/sqrt(k m), v* and nu = v/v*."""
    a1 = eps * math.sqrt(k * m)
    return sc.Params(m=m, k=k, r_y=r_y, v=nu * vstar, alpha1=a1,
                     alpha2=a1 / (3.0 * vstar ** 2))


@pytest.mark.parametrize("eps, nu", [(0.3, 0.5), (0.3, 0.95), (1.5, 0.99), (0.3, 1.2)])
def test_cubic_law_depends_only_on_eps_and_nu(eps, nu):
    """Eq. (40) without damping: with y = x - r_y/k, t omega and velocities in units
    of v*, the sliding and sticking dynamics depend on eps = alpha1/sqrt(k m) and
    nu = v/v* only (r_y enters only where the slider outruns the belt: a slide-slide
    reversal). Amplitude omega/v*, period omega and the multiplier must agree."""
    rng = np.random.default_rng(int(1000 * eps + 100 * nu))
    got = []
    for _ in range(4):
        m, k, vstar = 10 ** rng.uniform(-1, 1, 3)
        # r_y large enough that the slider never outruns the belt (no reversal)
        r_y = k * vstar / math.sqrt(k / m) * 10 ** rng.uniform(0.7, 1.5)
        p = _groups_cubic(eps, nu, m=m, k=k, r_y=r_y, vstar=vstar)
        a = sc.attractor(p, tol=1e-11)
        assert a.status == "ok"
        w, vs = p.omega, p.v_star
        got.append((a.regime, a.amplitude * w / vs, a.period * w if a.period == a.period
                    else 0.0, (a.mean - p.r_y / p.k) * w / vs, a.floquet))
    assert len({g[0] for g in got}) == 1
    vals = np.array([g[1:] for g in got], dtype=float)
    np.testing.assert_allclose(vals, np.broadcast_to(vals[0], vals.shape), rtol=1e-8,
                               atol=1e-8)


def _scaled(pars, v, mu, kappa, sigma, shift=0.0):
    """Dimensional scaling (mass mu, stiffness kappa, speed sigma) and a common shift
    of r_y and r_k (keeping d = r_y - r_k) of a Stribeck law with damping."""
    g = math.sqrt(kappa * mu)
    return sc.Params(m=mu * pars["m"], k=kappa * pars["k"], c=g * pars["c"],
                     alpha1=g * pars["alpha1"], alpha2=g * pars["alpha2"] / sigma ** 2,
                     r_y=g * sigma * (pars["r_y"] + shift),
                     r_k=g * sigma * (pars["r_k"] + shift),
                     v_s=sigma * pars["v_s"], v=sigma * v)


@pytest.mark.parametrize("pars, v", [(BSTAB, 1.5), (FAMILY, 0.8), (SUPER, 1.43)])
def test_stribeck_law_with_damping_depends_only_on_its_groups(pars, v):
    """m z'' + c z' + k (x - r_k/k) = d exp(s/v_s) + alpha1 s - alpha2 s^3 while
    sliding with s = x' - v < 0 (d = r_y - r_k), sticking until k (x - r_k/k) =
    d - c v: with t omega and speeds in units of v_s the dynamics depend on
    c/sqrt(km), alpha1/sqrt(km), alpha2 v_s^2/sqrt(km), d/(sqrt(km) v_s) and v/v_s
    only (r_y + r_k enters only at a slide-slide reversal). Amplitude omega/v_s,
    period omega, (mean - r_k/k) omega/v_s and the multiplier must agree."""
    rng = np.random.default_rng(11)
    got = []
    for i in range(4):
        p = _scaled(pars, v, 10 ** rng.uniform(-1, 1), 10 ** rng.uniform(-1, 1),
                    10 ** rng.uniform(-1, 1), shift=0.3 * i)
        a = sc.attractor(p, tol=1e-11)
        assert a.status == "ok"
        w, u = p.omega, p.v_s
        got.append((a.regime, a.amplitude * w / u, a.period * w,
                    (a.mean - p.r_k / p.k) * w / u, a.floquet))
    assert len({g[0] for g in got}) == 1
    vals = np.array([g[1:] for g in got], dtype=float)
    np.testing.assert_allclose(vals, np.broadcast_to(vals[0], vals.shape), rtol=1e-8,
                               atol=1e-8)


# -------------------------------------------------------- the accuracy contract
@pytest.mark.parametrize("family", ["cubic", "stribeck", "all terms"])
def test_ok_means_within_the_contract_on_random_points(family):
    """Status ok promises 1e-6 relative (1e-6 L absolute near 0); checked against an
    independent tighter run (tol 1e-11) on random points of each law."""
    rng = np.random.default_rng({"cubic": 1, "stribeck": 2, "all terms": 3}[family])
    for _ in range(25):
        pars = dict(m=10 ** rng.uniform(-1, 1), k=10 ** rng.uniform(-1, 1), r_y=1.0,
                    v=10 ** rng.uniform(-1, 0.5), alpha1=0.0, alpha2=0.0)
        if family in ("cubic", "all terms"):
            pars.update(alpha1=rng.uniform(0, 1) * math.sqrt(pars["k"] * pars["m"]),
                        alpha2=10 ** rng.uniform(-3, 0))
        if family in ("stribeck", "all terms"):
            pars.update(r_k=rng.uniform(0.2, 0.9), v_s=10 ** rng.uniform(-1, 0.3),
                        c=rng.uniform(0, 0.3) * math.sqrt(pars["k"] * pars["m"]))
        p = sc.Params(**pars)
        a = sc.attractor(p)
        if a.status != "ok":
            continue
        b = sc.attractor(p, tol=1e-11)
        assert a.regime == b.regime, pars
        L = scale(p)
        for name in ("amplitude", "mean", "x_max", "x_min"):
            x, y = getattr(a, name), getattr(b, name)
            assert abs(x - y) <= max(1e-6 * abs(y), 1e-6 * L), (name, pars)
        if a.regime != "equilibrium":
            assert a.period == pytest.approx(b.period, rel=1e-6)
