"""The forced oscillator's closed forms against the independent reference.

What is proven (``sweepcore.excitations.theory`` against ``reference_forced``, a
scipy integration with exact sticks that imports nothing from sweepcore):

* Den Hartog's continuous motion (c = 0, v = 0): the amplitude to 1e-9 relative (the
  reference's fixed point is found to 1e-11 of the scales at rtol 1e-12), mean 0,
  two zero-duration stops and no stick a period, the forcing phase of the minimum
  to 1e-9 rad, and the multipliers
  ``mu = lambda^2`` to 1e-6 (the reference's central differences with steps 1e-5
  of the scales at rtol 1e-12: error ~ 1e-12/1e-5); the quoted values of x0 to their
  last digit;
* the continuous-motion boundary r_b: its quoted values to their last digit; at
  0.97 r_b no stick, at 1.03 r_b sticks (two a period where the reversal condition
  is the boundary, beta >= 1/2; below 1/2 the velocity first touches zero inside the
  half period: at beta = 0.4 the reversal condition alone would put 1.03 r_b in the
  continuous range, and the reference sticks there);
* the belt under a load (Coulomb friction, c > 0): just below F0_crit no stick, the
  linear response's amplitude and the mean r_k/k to 1e-9, and the multipliers of
  the damped linear oscillator exp(lambda T), ``m lambda^2 + c lambda + k = 0``;
  just above it one stick a period;
* a base motion is its equivalent load: the two runs agree to 1e-9 of the length
  scale, sticks and stops included, for a Stribeck law with a cubic term;
* the neutral family is flagged exactly where a multiplier is 1;
* without a load the reference is the autonomous reference of ``tests/reference.py``
  (sticks, slips and the trajectory to 1e-9 of the length scale);
* the reference's Lyapunov exponent (its answer for an aperiodic response) is
  ln(rho)/T on Den Hartog's motion at beta = 2, where the period's map is -rho I.

Runtime ~30 s of calls (the reference is Python; each steady response is a few hundred
periods of DOP853 at most).
"""
import math

import numpy as np
import pytest

from reference import reference_run
from reference_forced import Forced, forced_run, forced_steady, lyapunov
from sweepcore.excitations import theory

# Den Hartog's slider: omega = 5 rad/s, F0 = 10 kN, length unit F0/k = 0.2 cm
M, K, F0 = 2.0, 50.0, 10.0
OMEGA = math.sqrt(K / M)


@pytest.mark.parametrize("beta, r, x0", [
    (2.0, 0.3, 0.2976761850), (1.5, 0.5, 0.5537749242), (0.8, 0.3, 2.6261048757),
    (3.0, 0.1, 0.1235096338), (1.2, 0.3, 2.0723842680)])
def test_den_hartog_amplitude_is_the_quoted_value(beta, r, x0):
    # quoted to 10 decimals: agreement to half a unit of the last one
    assert theory.den_hartog_scaled(beta, r) == pytest.approx(x0, abs=5e-11)


@pytest.mark.parametrize("beta, rb", [(0.3, 0.08641), (0.4, 0.14389), (0.5, 1 / 3),
                                      (0.7, 0.72207), (0.8, 0.81741), (0.9, 0.81965),
                                      (1.2, 0.71321), (1.5, 0.64658), (2.0, 0.59628),
                                      (3.0, 0.56250), (10.0, 0.53926)])
def test_boundary_is_the_quoted_value(beta, rb):
    assert theory.continuous_motion_boundary(beta) == pytest.approx(rb, abs=5e-6)


def test_boundary_limits():
    # pi/4 at beta -> 1 from both sides; 1/sqrt(1 + pi^2/4) as beta -> infinity
    for beta in (1 - 1e-7, 1 + 1e-7):
        assert theory.continuous_motion_boundary(beta) == pytest.approx(math.pi / 4,
                                                                         rel=1e-6)
    assert theory.continuous_motion_boundary(1e7) == pytest.approx(
        1 / math.sqrt(1 + math.pi ** 2 / 4), rel=1e-12)


def _den_hartog_start(beta, r):
    """Den Hartog's minimum (x = -X, x' = 0 at forcing phase psi), 10 % off in x."""
    X = F0 / K * theory.den_hartog_scaled(beta, r)
    psi = theory.den_hartog_phase_scaled(beta, r)
    return dict(x0=-0.9 * X, xd0=0.0, t0=psi / (beta * OMEGA))


@pytest.mark.parametrize("beta, r, start", [(2.0, 0.3, "rest"), (1.5, 0.5, "near"),
                                            (0.8, 0.3, "near"), (3.0, 0.1, "near"),
                                            (1.2, 0.3, "near")])
def test_den_hartog_motion_and_multipliers_against_the_reference(beta, r, start):
    Omega = beta * OMEGA
    mod = Forced(M, K, F0=F0, Omega=Omega, r_y=r * F0)
    res = forced_steady(mod, **({} if start == "rest" else _den_hartog_start(beta, r)))
    assert res["status"] == "ok" and res["multiplicity"] == 1
    assert res["amplitude"] == pytest.approx(
        theory.den_hartog_amplitude(M, K, F0, Omega, r * F0), rel=1e-9)
    assert abs(res["mean"]) < 1e-9 * res["amplitude"]              # symmetric motion
    assert (res["sticks_per_period"], res["stops_per_period"]) == (0, 2)
    # the minimum's stop sits at the forcing phase psi
    t_min = [t for t, kind, x in res["events"] if x < 0]
    miss = Omega * t_min[0] - theory.den_hartog_phase_scaled(beta, r)
    assert abs(math.remainder(miss, 2 * math.pi)) < 1e-9
    mu = theory.den_hartog_multipliers(M, K, F0, Omega, r * F0)
    assert np.sort_complex(res["multipliers"]) == pytest.approx(np.sort_complex(mu),
                                                                abs=1e-6)


@pytest.mark.parametrize("beta, below, above", [
    (0.8, (0, 2), (2, 0)), (2.0, (0, 2), (2, 0)), (0.4, (0, 2), (2, 2))])
def test_boundary_separates_continuous_motion_from_sticking(beta, below, above):
    """(sticks, stops) a period at 0.97 r_b and 1.03 r_b, from Den Hartog's minimum."""
    rb = theory.continuous_motion_boundary(beta)
    if beta < 0.5:      # the interior touch, not the reversal, sets r_b here
        V, U = 1 / (1 - beta ** 2), math.tan(math.pi / (2 * beta)) / beta
        assert 1.03 * rb < beta ** 2 * V / math.sqrt(1 + beta ** 4 * U ** 2)
    for factor, expected in ((0.97, below), (1.03, above)):
        mod = Forced(M, K, F0=F0, Omega=beta * OMEGA, r_y=factor * rb * F0)
        start = _den_hartog_start(beta, min(factor, 0.999) * rb)
        res = forced_steady(mod, **start, rtol=1e-10, multipliers=False)
        assert res["status"] == "ok" and res["multiplicity"] == 1
        assert (res["sticks_per_period"], res["stops_per_period"]) == expected, factor


# a belt under a load: omega = 2 rad/s, c = 0.4 kN s/cm, Coulomb friction r_k = 0.7 kN
BELT = dict(m=1.0, k=4.0, c=0.4, v=0.5)
R_K, BELT_OMEGA = 0.7, 1.5


def _asymmetric(s):
    """A callable law: kinetic levels 1 kN (s > 0) and R_K (s < 0)."""
    return 1.0 if s > 0 else -R_K


@pytest.mark.parametrize("law", ["family", "callable"])
def test_below_the_critical_load_the_response_is_linear_and_shifted(law):
    """Only the kinetic level on the belt's slow side (s < 0) counts below F0_crit:
    the family's Coulomb law and a callable one with other levels and static
    limits (1.2, 0.8) give the same response."""
    crit = theory.belt_critical_load(**BELT, Omega=BELT_OMEGA)
    F0 = 0.99 * crit
    kw = dict(r_y=R_K) if law == "family" else dict(law=(_asymmetric, 1.2, 0.8))
    mod = Forced(**BELT, F0=F0, Omega=BELT_OMEGA, **kw)
    res = forced_steady(mod, x0=R_K / BELT["k"])
    amp, mean, _lag = theory.belt_linear_response(**BELT, r_k=R_K, F0=F0,
                                                  Omega=BELT_OMEGA)
    assert res["status"] == "ok" and res["sticks_per_period"] == 0
    assert res["amplitude"] == pytest.approx(amp, rel=1e-9)
    assert res["mean"] == pytest.approx(mean, rel=1e-9)
    assert res["xdot_max"] < BELT["v"]                  # 1 % below the belt speed
    # the damped linear oscillator's multipliers exp(lambda T)
    lam = np.roots([BELT["m"], BELT["c"], BELT["k"]])
    mu = np.exp(lam * 2 * math.pi / BELT_OMEGA)
    assert np.sort_complex(res["multipliers"]) == pytest.approx(np.sort_complex(mu),
                                                                abs=1e-6)


def test_above_the_critical_load_the_slider_sticks_once_a_period():
    crit = theory.belt_critical_load(**BELT, Omega=BELT_OMEGA)
    mod = Forced(**BELT, F0=1.01 * crit, Omega=BELT_OMEGA, r_y=R_K)
    res = forced_steady(mod, x0=R_K / BELT["k"], rtol=1e-10, multipliers=False)
    assert res["status"] == "ok" and res["multiplicity"] == 1
    assert res["sticks_per_period"] == 1 and res["stick_fraction"] > 0
    assert np.isnan(theory.belt_linear_response(**BELT, r_k=R_K, F0=1.01 * crit,
                                                Omega=BELT_OMEGA)[0])


def test_base_motion_is_its_equivalent_load():
    """Stribeck law with a cubic term, belt, damping: x(t) of the base-driven slider
    and of the slider under the equivalent load agree to 1e-9 L, event by event."""
    law = dict(m=1.0, k=4.0, c=0.3, v=0.4, r_y=1.0, r_k=0.6, v_s=0.3, alpha2=0.05)
    Y0, Omega = 0.5, 1.7
    F0_eq, phi_eq = theory.base_equivalent_load(law["k"], law["c"], Omega, Y0)
    base = Forced(**law, Y0=Y0, Omega=Omega)
    load = Forced(**law, F0=F0_eq, phi=phi_eq, Omega=Omega)
    t = np.linspace(0.0, 15.0, 751)
    a = forced_run(base, 0.0, 0.0, 0.0, t[-1], 1e-12, t)
    b = forced_run(load, 0.0, 0.0, 0.0, t[-1], 1e-12, t)
    kinds = [e[1] for e in a["events"]]
    assert "stick" in kinds and any(k.endswith("_stop") for k in kinds)
    assert kinds == [e[1] for e in b["events"]]
    np.testing.assert_allclose([e[0] for e in a["events"]], [e[0] for e in b["events"]],
                               atol=1e-9)
    assert np.max(np.abs(a["x"] - b["x"])) < 1e-9 * base.L


def test_neutral_family_is_flagged_where_a_multiplier_is_one():
    betas = np.array([1 / 2, 1 / 4, 1 / 6, 0.3, 0.45, 0.8, 2.0])
    Omega = betas * OMEGA
    flagged = theory.neutral_family(M, K, Omega)
    unit = np.abs(np.abs(theory.den_hartog_multipliers(M, K, F0, Omega, 0.01 * F0)[:, 0])
                  - 1.0) < 1e-12
    assert flagged.tolist() == unit.tolist() == [True] * 3 + [False] * 4
    # damping or a belt breaks the family
    assert not theory.neutral_family(M, K, 0.5 * OMEGA, c=0.1).any()
    assert not theory.neutral_family(M, K, 0.5 * OMEGA, v=1.0).any()


def test_closed_forms_say_nan_outside_their_motion_and_refuse_bad_input():
    rb = theory.continuous_motion_boundary(2.0)
    assert np.isnan(theory.den_hartog_amplitude(M, K, F0, 2 * OMEGA, 1.01 * rb * F0))
    assert np.isnan(theory.den_hartog_multipliers(M, K, F0, 2 * OMEGA,
                                                  1.01 * rb * F0)).all()
    with pytest.raises(ValueError, match="beta"):
        theory.den_hartog_scaled(-1.0, 0.3)
    with pytest.raises(ValueError, match="Omega"):
        theory.den_hartog_amplitude(M, K, F0, OMEGA, 1.0)           # resonance
    with pytest.raises(ValueError, match="v must"):
        theory.belt_critical_load(1.0, 4.0, 0.4, 0.0, 1.5)


def test_lyapunov_exponent_of_den_hartogs_motion_is_its_multipliers():
    """The reference's two-trajectory exponent (its aperiodic answer) on a motion
    whose multipliers are known: at beta = 2 the half-period matrix N has
    eigenvalues +-i sqrt(rho), so the period's map is -rho I and every perturbation
    shrinks by exactly rho a period: exponent ln(rho)/T, to 1e-6 relative (the
    neighbour 1e-6 of the scales away, rtol 1e-12)."""
    beta, r = 2.0, 0.3
    Omega = beta * OMEGA
    mod = Forced(M, K, F0=F0, Omega=Omega, r_y=r * F0)
    X = F0 / K * theory.den_hartog_scaled(beta, r)
    t0 = theory.den_hartog_phase_scaled(beta, r) / Omega
    lam, err = lyapunov(mod, (-X, 0.0), t0, 10)
    rho = abs(theory.den_hartog_multipliers(M, K, F0, Omega, r * F0)[0])
    assert lam == pytest.approx(math.log(rho) * Omega / (2 * math.pi), rel=1e-6)
    assert err < 1e-6 * abs(lam)


def test_without_a_load_the_run_is_the_autonomous_references():
    """F0 = Y0 = 0: a slider on the belt (cubic and Stribeck terms) started stuck,
    through a breakaway, a slide-slide reversal, a stick and a second breakaway, as
    the autonomous reference (tests/reference.py) computes it: events within 1e-9 s,
    x within 1e-9 of the length scale (both DOP853 at rtol 1e-12)."""
    p = dict(m=5.0, k=50.0, r_y=10.0, v=2.0, alpha1=1.0, alpha2=0.01)
    law = dict(r_k=6.0, v_s=0.5)
    t = np.linspace(0.0, 3.0, 301)
    x_ref, _xd, ev_ref = reference_run(**p, x0=0.0, xd0=p["v"], t_eval=t, **law)
    mod = Forced(p["m"], p["k"], v=p["v"], r_y=p["r_y"], alpha1=p["alpha1"],
                 alpha2=p["alpha2"], Omega=1.0, **law)
    run = forced_run(mod, 0.0, p["v"], 0.0, t[-1], 1e-12, t)
    kinds = [k.rstrip("+-") for _t, k, _x in run["events"]]
    assert kinds == [k for _t, k, _x in ev_ref] == ["slip", "normal_stop", "stick", "slip"]
    np.testing.assert_allclose([e[0] for e in run["events"]], [e[0] for e in ev_ref],
                               atol=1e-9)
    assert np.max(np.abs(run["x"] - x_ref)) < 1e-9 * mod.L
