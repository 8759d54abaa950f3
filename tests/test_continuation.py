"""Continuation of forced responses (sweepcore.follow_response) against the
independent reference (tests/reference_forced.py: scipy DOP853 at rtol 1e-12 with
exact sticks; nothing of sweepcore in it) and closed forms.

What is proven, and to what tolerance:

* a branch through a fold (the Stribeck belt slider m = k = 1, r_y = 1, r_k = 0.5,
  v_s = 0.1, c = 0.05, v = 1, F0 = 0.08, followed from its slip response at
  Omega = 1.3 down to 0.95): it holds unstable stretches (a torus where the slip
  response's complex pair leaves the unit circle, a grazing-sliding non-smooth fold
  where it reaches the belt and sticks, a fold of the stick-slip response); every
  periodic point sampled on it (stable and unstable, sliding and stuck at t = 0) is
  a fixed point of the reference's map P^n to 1e-8 of the length scale L; the
  multipliers, where the reference's central differences (steps 1e-5 of the scales:
  error ~1e-7 |mu|) are valid (away from a switch within the step, |mu| < 5), agree
  within 1e-5; at the fold the reference's largest multiplier is 1 within 1e-6, and
  at the torus its modulus is 1 within 1e-5;
* stability: a point marked unstable has a reference multiplier outside the unit
  circle, a stable one inside;
* Den Hartog's continuous-motion boundary (c = 0, v = 0, Coulomb friction): the
  stick onset met on a branch followed in F0 lies within 1e-9 (relative) of
  r_y / r_b(beta) (sweepcore.excitations.theory, checked against the reference in
  tests/test_forced_theory.py);
* the test functions of a point: det(J - I), det(J + I) and det J - 1 of the
  multipliers' closed forms; the labels of pattern changes;
* a correction that fails leaves a point with the failure's status and NaN values,
  and a warning; refusals name the argument and its value;
* frequency_response(branches=True) holds the branch, unstable points included, and
  its picture draws them dashed with the special points marked.

Runtime: ~25 s of calls after the kernels are compiled (the reference is Python).
"""
import math
import warnings

import numpy as np
import pytest

import sweepcore as sc
from reference_forced import Forced, _jacobian, forced_run
from sweepcore import branch
from sweepcore._kernels import codes
from sweepcore.excitations import theory

SLIDER = dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.1, c=0.05, v=1.0, F0=0.08)


@pytest.fixture(scope="module")
def fold_branch():
    p = sc.Params(**SLIDER, Omega=1.3)
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # no failure, no budget spent
        return sc.follow_response(p, over="Omega", to=0.95, x0=p.x_eq, xdot0=0.0)


def _special(ds, name):
    meanings = ds.special.attrs["flag_meanings"].split()
    code = ds.special.attrs["flag_values"][meanings.index(name)]
    return ds.isel(point=np.flatnonzero(ds.special.values == code))


def _reference(q):
    """The reference's model at the point q, its periodic point and n."""
    mod = Forced(1.0, 1.0, c=0.05, v=1.0, F0=0.08, Omega=float(q.Omega), r_y=1.0,
                 r_k=0.5, v_s=0.1)
    return mod, np.array([float(q.x_section), float(q.xdot_section)]), \
        int(q.multiplicity)


def _reference_multipliers(q):
    mod, z, n = _reference(q)
    J = _jacobian(mod, z, 0.0, n, 1e-12, np.array([mod.L, mod.Lv]), h=1e-5)
    mu = np.linalg.eigvals(J)
    return mu[np.argsort(-np.abs(mu))]


def test_the_branch_turns_through_a_fold_onto_unstable_responses(fold_branch):
    ds = fold_branch
    assert ds.attrs["ended"] == "reached" and float(ds.Omega[-1]) == 0.95
    assert (ds.status.values == codes.OK).all()
    stable = ds.stable.values.astype(bool)
    assert stable[0] and stable[-1] and (~stable).sum() > 10
    # one fold, one torus, one stick onset (the grazing of the belt)
    assert [_special(ds, k).sizes["point"] for k in ("fold", "torus", "stick_onset")] \
        == [1, 1, 1]
    fold = _special(ds, "fold")
    # the parameter turns back at the fold: below it on both sides
    i = int(fold.point[0])
    w = ds.Omega.values
    assert w[i - 1] < w[i] and w[i + 1] < w[i]
    assert abs(float(fold.multiplier_real[0, 0]) - 1.0) < 1e-9
    assert float(fold.special_width[0]) <= 1e-9 * float(fold.Omega[0])


@pytest.mark.parametrize("start", [1.1, 1.175])
def test_from_inside_the_window_the_branch_turns_at_the_grazing(start, fold_branch):
    """Started on the slip response between the torus and Omega = 1.3, the branch
    (inside the window 0.95-1.3) meets the grazing's non-smooth fold and turns onto
    the stick-slip arm, as from 1.3: the same fold (whose multiplier the reference
    puts on the circle, above) to 1e-9."""
    p = sc.Params(**SLIDER, Omega=start)
    ds = sc.follow_response(p, over="Omega", to=0.95, x0=p.x_eq, xdot0=0.0,
                            bounds=(0.95, 1.3))
    assert ds.attrs["ended"] == "reached"
    names = ds.special.attrs["flag_meanings"].split()
    assert [names[c] for c in ds.special.values if c > 0] == \
        ["start", "torus", "stick_onset", "fold", "end"]
    fold = float(_special(ds, "fold").special_value[0])
    assert abs(fold - float(_special(fold_branch, "fold").special_value[0])) < 1e-9


def _sampled(ds, every=5):
    """Regular points of the branch, every ``every``-th."""
    regular = np.flatnonzero(ds.special.values == branch.REGULAR)
    return [ds.isel(point=int(i)) for i in regular[::every]]


def test_every_periodic_point_is_a_fixed_point_of_the_reference(fold_branch):
    worst = 0.0
    kinds = set()
    for q in _sampled(fold_branch):
        mod, z, n = _reference(q)
        r = forced_run(mod, z[0], z[1], 0.0, n * mod.T)
        worst = max(worst, abs(r["x1"] - z[0]) / mod.L, abs(r["xd1"] - z[1]) / mod.Lv)
        kinds.add((int(q.stable), int(q.sticks_per_period) > 0, z[1] == 1.0))
        # the reference's sticks per period are the branch's
        assert sum(e[1] == "stick" for e in r["events"]) == int(q.sticks_per_period)
    assert worst < 1e-8
    # stable and unstable, slip and stick-slip, sliding and stuck at t = 0
    assert {(1, False, False), (0, False, False), (0, True, False), (1, True, False),
            (1, True, True)} <= kinds


def test_multipliers_and_stability_agree_with_the_reference(fold_branch):
    ds = fold_branch
    events = ds.special_value.values[np.isfinite(ds.special_value.values)]
    checked = 0
    for q in _sampled(ds, every=3):
        ours = q.multiplier_real.values + 1j * q.multiplier_imag.values
        if np.abs(ours).max() >= 5.0 or \
                np.min(np.abs(events - float(q.Omega))) < 2e-3:
            continue        # the reference's differences straddle a switch there
        ref = _reference_multipliers(q)
        assert np.abs(ref - ours).max() < 1e-5, float(q.Omega)
        assert (np.abs(ref).max() < 1.0) == bool(q.stable)
        checked += 1
    assert checked >= 8


def test_at_the_fold_and_the_torus_the_reference_has_a_multiplier_on_the_circle(
        fold_branch):
    fold = _special(fold_branch, "fold").isel(point=0)
    assert abs(np.abs(_reference_multipliers(fold)).max() - 1.0) < 1e-6
    torus = _special(fold_branch, "torus").isel(point=0)
    mu = _reference_multipliers(torus)
    assert abs(mu[0].imag) > 0.1 and abs(np.abs(mu[0]) - 1.0) < 1e-5


def test_the_stick_onset_on_a_branch_in_F0_is_den_hartogs_boundary():
    for beta in (0.8, 2.0):
        p = sc.Params(m=1.0, k=1.0, r_y=1.0, v=0.0, F0=1.1, Omega=beta)
        ds = sc.follow_response(p, over="F0", to=3.0, x0=0.0, xdot0=0.0)
        onset = _special(ds, "stick_onset")
        assert onset.sizes["point"] == 1
        exact = 1.0 / theory.continuous_motion_boundary(beta)
        assert abs(float(onset.special_value[0]) - exact) <= 1e-9 * exact
        # two sticks a period below it, two stops and no stick above (Den Hartog)
        assert (int(ds.sticks_per_period[0]), int(ds.stops_per_period[-1]),
                int(ds.sticks_per_period[-1])) == (2, 2, 0)


def test_a_start_stuck_at_t0_is_its_position_alone():
    """Den Hartog's slider with the load's phase pi/2: below the stick onset the
    periodic point is stuck at t = 0 (xdot = 0): P^n depends on x alone, its
    second multiplier is 0; both multipliers and the fixed point as the
    reference's (which perturbs the stuck velocity too)."""
    p = sc.Params(m=1.0, k=1.0, r_y=1.0, v=0.0, F0=1.05, Omega=0.8, phi=math.pi / 2)
    ds = sc.follow_response(p, over="F0", to=1.3, x0=0.0, xdot0=0.0)
    stuck = np.flatnonzero(ds.xdot_section.values == 0.0)
    assert stuck.size >= 5
    for i in stuck[::2]:
        q = ds.isel(point=int(i))
        mod = Forced(1.0, 1.0, F0=float(q.F0), Omega=0.8, r_y=1.0, phi=math.pi / 2)
        r = forced_run(mod, float(q.x_section), 0.0, 0.0, mod.T)
        assert abs(r["x1"] - float(q.x_section)) < 1e-8 * mod.L and r["xd1"] == 0.0
        J = _jacobian(mod, np.array([float(q.x_section), 0.0]), 0.0, 1, 1e-12,
                      np.array([mod.L, mod.Lv]), h=1e-5)
        ref = np.linalg.eigvals(J)
        ours = q.multiplier_real.values + 1j * q.multiplier_imag.values
        assert np.abs(ref[np.argsort(-np.abs(ref))] - ours).max() < 1e-5
        assert ours[1] == 0.0


# ------------------------------------------------------------------ the labels
def _point(J):
    pt = branch.Point()
    pt.J = np.asarray(J, float)
    return pt


@pytest.mark.parametrize("mu1, mu2", [(0.5, 0.2), (1.3, 0.4), (-1.2, 0.1), (0.9, 0.0)])
def test_test_functions_are_the_multipliers_closed_forms(mu1, mu2):
    S = np.array([[1.0, 2.0], [0.5, 3.0]])
    pt = _point(S @ np.diag([mu1, mu2]) @ np.linalg.inv(S))
    fold, pd, torus = pt.tests()
    assert fold == pytest.approx((mu1 - 1) * (mu2 - 1), abs=1e-12)
    assert pd == pytest.approx((mu1 + 1) * (mu2 + 1), abs=1e-12)
    assert math.isnan(torus)                    # real multipliers: no torus test
    rho, th = 1.1, 0.7                          # a complex pair rho exp(+-i th)
    pt = _point(rho * np.array([[math.cos(th), -math.sin(th)],
                                [math.sin(th), math.cos(th)]]))
    assert pt.tests()[2] == pytest.approx(rho ** 2 - 1, abs=1e-12)
    assert np.abs(pt.multipliers()) == pytest.approx([rho, rho])


def test_pattern_changes_are_labelled_by_what_changes():
    assert branch.pattern_kind((0, 2), (2, 0)) == branch.STICK_ONSET
    assert branch.pattern_kind((1, 0), (0, 0)) == branch.STICK_ONSET
    assert branch.pattern_kind((0, 0), (0, 2)) == branch.GRAZING
    assert branch.pattern_kind((1, 1), (1, 2)) == branch.STOPS_CHANGE


# ------------------------------------------------------------------ failures
def test_a_failed_correction_is_a_status_never_a_number(monkeypatch):
    p = sc.Params(m=1.0, k=1.0, r_y=1.0, v=0.0, F0=1.1, Omega=2.0)
    real = branch.Problem.evaluate

    def failing(self, w):      # every image beyond F0 = 1.3 spends its step budget
        if self.lam(w) > 1.3:
            raise branch.Failed(codes.STEP_BUDGET, w)
        return real(self, w)
    monkeypatch.setattr(branch.Problem, "evaluate", failing)
    with pytest.warns(RuntimeWarning, match="no correction converged"):
        ds = sc.follow_response(p, over="F0", to=2.0, x0=0.0, xdot0=0.0)
    last = ds.isel(point=-1)
    assert ds.attrs["ended"] == "failed"
    assert int(last.status) == codes.STEP_BUDGET
    assert math.isnan(float(last.amplitude)) and math.isnan(float(last.floquet))
    assert (ds.status.values[:-1] == codes.OK).all()
    assert float(ds.F0[-2]) <= 1.3


@pytest.mark.parametrize("kwargs, match", [
    (dict(over="Omegaa", to=1.0), "over must be one of .*did you mean 'Omega'"),
    (dict(over="Omega"), "needs to="),
    (dict(over="Omega", to=2.0), "to = 2.0 is the start's own Omega"),
    (dict(over="Omega", to=-1.0), "to = -1.0 for 'Omega'"),
    (dict(over="F0", to=0.0), "to = 0.0 for 'F0' leaves no excitation"),
    (dict(over="Omega", to=1.5, bounds=(1.6, 3.0)), "bounds = .* must hold"),
    (dict(over="Omega", to=1.5, multiplicity=1), "x0 .* must be the periodic point"),
    (dict(over="Omega", to=1.5, step=0.0), "step must be a number in"),
])
def test_refusals_name_the_argument_and_the_value(kwargs, match):
    p = sc.Params(m=1.0, k=1.0, r_y=0.3, v=0.0, F0=1.0, Omega=2.0)
    with pytest.raises((TypeError, ValueError), match=match):
        sc.follow_response(p, **kwargs)


def test_a_start_without_a_period_is_refused_by_name():
    p = sc.Params(**SLIDER, Omega=1.2)          # aperiodic from this start
    with pytest.raises(ValueError, match="x0=0.5, xdot0=0.9 is aperiodic"):
        sc.follow_response(p, over="Omega", to=1.1, x0=0.5, xdot0=0.9)
    with pytest.raises(ValueError, match="not a periodic point"):
        sc.follow_response(p, over="Omega", to=1.1, x0=40.0, xdot0=0.0,
                           multiplicity=1)


def test_every_variable_has_units_and_the_labels_are_flags(fold_branch):
    ds = fold_branch
    for name, var in ds.variables.items():
        assert "units" in var.attrs and "long_name" in var.attrs, name
    for name in ("special", "status", "stable"):
        attrs = ds[name].attrs
        assert len(attrs["flag_values"]) == len(attrs["flag_meanings"].split())
    assert ds.Omega.attrs["units"] == "rad s-1"
    assert ds.special_value.attrs["units"] == "rad s-1"


def test_frequency_response_draws_its_unstable_branch_dashed():
    p = sc.Params(**SLIDER, Omega=1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        ds = sc.frequency_response(p, np.linspace(0.95, 1.3, 8), x0=p.x_eq, xdot0=0.0,
                                   branches=True)
    assert ds.attrs["branches"] >= 1
    assert (ds.branch_stable.values == 0).any() and (ds.branch_stable.values == 1).any()
    fig = sc.plot_frequency_response(ds)
    lines = fig.axes[0].get_lines()
    assert any(ln.get_linestyle() == "--" and ln.get_label() == "unstable branch"
               for ln in lines)
    assert {"fold", "stick onset"} <= {ln.get_label() for ln in lines}
