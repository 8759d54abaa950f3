"""Coulomb friction with static above kinetic: ``v_s = 0``, the exact jump.

``F(s) = sgn(s) (r_k + (r_y - r_k) exp(-|s|/v_s)) - alpha1 s + alpha2 s^3`` at its
limit v_s -> 0+: sliding at ``sgn(s) r_k - alpha1 s + alpha2 s^3`` (F(0+-) = +-r_k),
sticking up to the static bound r_y (Shaw, J. Sound Vib. 108, 1986). What is proven,
each against closed forms or the independent solvers of ``tests/reference.py`` and
``tests/reference_forced.py`` (scipy with exact sticks; they take ``v_s = 0`` as the
jump):

* v_s = 0 is accepted by Params, Grid, study files and the command line; a negative
  v_s is refused naming v_s and its value;
* the derived quantities (q, x_eq, the Hopf speed and its criticality, the
  breakaway point) are the closed forms of the polynomial law at the level r_k,
  with the breakaway at the static bound r_y, and the limit of small v_s;
* the force the Python side draws is the jump's, F(0+-) = +-r_k;
* on fixed ground the slider comes to rest where Coulomb's closed form puts it
  (half-swings about +-r_k/k until |k x| <= r_y);
* stick-slip cycles on a belt (the slip starts with the acceleration
  ``(r_y - r_k)/m``), both belt directions, closed-form arcs (alpha2 = 0) and
  dop853/dopri5, and a trajectory, agree with the reference; a slip cycle of the
  cycle scan too;
* forced responses on fixed ground and on a belt agree with the forced reference;
* the keywords and a flat ``TableLaw(..., static=r_y)`` (the way before) give the
  same answers.
"""
import math

import numpy as np
import pytest

import sweepcore as sc
from sweepcore import law
from reference import (reference_run, reference_slip_cycle,
                        reference_stick_slip_cycle)
from reference_forced import Forced, forced_steady
from sweepcore import compiled
from sweepcore._kernels import codes, layout as L
from sweepcore._kernels.cycles import MAX_CYCLES
from sweepcore.options import make_options

CONTRACT = 1e-6                 # status ok: within 1e-6 of the length scale


def _length(m, k, r_y, v, **_):
    return r_y / k + abs(v) / math.sqrt(k / m)


# ------------------------------------------------------------------ the keywords
def test_v_s_zero_is_accepted_and_a_negative_one_refused_by_name(tmp_path, capsys,
                                                                  monkeypatch):
    p = sc.Params(m=1.0, k=1.0, r_y=1.0, r_k=0.6, v_s=0.0, v=0.5)
    assert p.v_s == 0.0
    g = sc.Grid(m=1.0, k=1.0, r_y=1.0, r_k=0.6, v_s=[0.0, 0.3], v=[0.5, 1.0])
    assert list(g.v_s) == [0.0, 0.3]
    with pytest.raises(ValueError, match=r"v_s must be >= 0 \[cm s-1\], got -0\.1"):
        sc.Params(m=1.0, k=1.0, r_y=1.0, r_k=0.6, v_s=-0.1, v=0.5)
    with pytest.raises(ValueError, match=r"v_s must be >= 0 .* got -0\.2 \(element 1 "
                                         r"of the v_s axis\)"):
        sc.Grid(m=1.0, k=1.0, r_y=1.0, r_k=0.6, v_s=[0.0, -0.2], v=0.5)
    # the Stribeck slope r_y - r_k over the least v_s > 0 (0 adds none) still bounds q
    with pytest.raises(ValueError, match=r"Hopf quantity .* overflows .* v_s in "
                                         r"\[1e-310, 1\.0\]"):
        sc.Grid(m=1.0, k=1.0, r_y=1.0, r_k=0.6, v_s=[0.0, 1e-310, 1.0], v=0.5)
    from sweepcore.study import StudyError, parse_study
    study = ("[axes]\nm = 1.0\nk = 1.0\nr_y = 1.0\nr_k = 0.6\nv_s = {}\n"
             "v = [0.5, 1.0]\n")
    assert parse_study(study.format("0.0"), "s.toml") is not None
    with pytest.raises(StudyError, match=r"v_s.*>= 0.*-1\.5") as err:
        parse_study(study.format("-1.5"), "s.toml")
    assert err.value.line == 6                     # the v_s line
    from sweepcore.cli import main
    monkeypatch.chdir(tmp_path)
    slider = ["simulate", "--m", "1", "--k", "1", "--r-y", "1", "--r-k", "0.6",
              "--v", "0.5", "--t-end", "1"]
    assert main(slider + ["--v-s", "-0.1"]) == 2
    assert "v_s must be >= 0 [cm s-1], got -0.1" in capsys.readouterr().err


@pytest.mark.parametrize("seed", range(3))
def test_derived_quantities_are_the_polynomial_laws_at_the_kinetic_level(seed):
    """q, x_eq, v* and the criticality slide on ``sgn(s) r_k - alpha1 s + alpha2
    s^3``; the breakaway point sticks up to r_y: ``x_s = (r_y - c v)/k``. A tiny
    v_s (1e-9 |v|: exp(-1e9) = 0) gives the same numbers (the limit)."""
    rng = np.random.default_rng(seed)
    m, k, r_y = rng.uniform(0.5, 2.0, 3)
    r_k = r_y * rng.uniform(0.2, 0.9)
    a1, a2, c = rng.uniform(0.2, 1.0), rng.uniform(0.01, 0.1), rng.uniform(0.0, 0.1)
    v = rng.uniform(0.3, 3.0)
    p = sc.Params(m=m, k=k, r_y=r_y, r_k=r_k, v_s=0.0, alpha1=a1, alpha2=a2, c=c, v=v)
    assert p.q == pytest.approx((a1 - 3.0 * a2 * v * v - c) / m, rel=1e-13)
    assert p.x_eq == pytest.approx((r_k - a1 * v + a2 * v ** 3) / k, rel=1e-13)
    assert p.v_star == pytest.approx(math.sqrt((a1 - c) / (3.0 * a2)), rel=1e-13)
    assert p.criticality == "supercritical"
    assert law.derived("x_s", p) == pytest.approx((r_y - c * v) / k, rel=1e-13)
    mirrored = sc.Params(m=m, k=k, r_y=r_y, r_k=r_k, v_s=0.0, alpha1=a1, alpha2=a2,
                         c=c, v=-v)
    assert mirrored.x_eq == -p.x_eq and mirrored.q == p.q
    near = sc.Params(m=m, k=k, r_y=r_y, r_k=r_k, v_s=1e-9 * v, alpha1=a1, alpha2=a2,
                     c=c, v=v)
    for name in ("q", "x_eq", "v_star"):
        assert getattr(near, name) == pytest.approx(getattr(p, name), rel=1e-12), name
    s = np.array([-2.0, -0.5, 0.5, 2.0])
    np.testing.assert_allclose(law.friction(s, p),
                               np.sign(s) * r_k - a1 * s + a2 * s ** 3, rtol=1e-14)
    assert law.friction(0.0, p, phase=1.0) == r_k                # the sliding limits
    assert law.friction(0.0, p, phase=-1.0) == -r_k
    assert law.stick_onset_estimate(p) == pytest.approx(
        2.0 / math.sqrt(5.0) * p.v_star, rel=1e-14)


def _coulomb_rest(m, k, r_y, r_k, x0):
    """Where a slider let go at rest at x0 on fixed ground stops for good (alpha1 =
    alpha2 = c = 0): half-swings about +-r_k/k, each from rest to rest, until
    ``|k x| <= r_y`` holds it."""
    x = x0
    while abs(k * x) > r_y:
        centre = math.copysign(r_k / k, x)     # sliding towards 0: F = -sgn(x) r_k
        x = 2.0 * centre - x
    return x


@pytest.mark.parametrize("x0", [4.3, -7.9, 2.2])
def test_on_fixed_ground_the_slider_stops_where_coulomb_puts_it(x0):
    """The jump decides the stop: a swing ends at rest and sticks when ``|k x| <=
    r_y`` (not r_k: the constant law r_y = r_k = 0.4 would slide on from 2.2)."""
    m, k, r_y, r_k = 1.0, 1.0, 1.0, 0.4
    want = _coulomb_rest(m, k, r_y, r_k, x0)
    for method in ("exact", "dop853"):
        a = sc.attractor(sc.Params(m=m, k=k, r_y=r_y, r_k=r_k, v_s=0.0, v=0.0),
                         x0=x0, xdot0=0.0, method=method)
        assert (a.regime, a.status) == ("stuck", "ok"), method
        assert a.mean == pytest.approx(want, abs=CONTRACT * r_y / k), method


# ------------------------------------------------------------- on a moving belt
def _belt_point(seed):
    """A slider whose attractor from a stuck start is a stick-slip cycle: the slip
    from the breakaway point starts ``(r_y - r_k)/k`` off its sliding centre, which
    brings it back to belt speed for ``|v|`` below ``omega (r_y - r_k)/k`` (damped
    where alpha2 = 0, alpha1 < c; below v* else)."""
    rng = np.random.default_rng(100 + seed)
    m, k, r_y = rng.uniform(0.5, 2.0, 3)
    r_k = r_y * rng.uniform(0.3, 0.8)
    c = rng.uniform(0.02, 0.1) * math.sqrt(k * m)
    if seed % 2 == 0:
        a1, a2, top = rng.uniform(0.0, c), 0.0, math.inf
    else:
        a1, a2 = c + rng.uniform(0.05, 0.5), rng.uniform(0.01, 0.1)
        top = math.sqrt((a1 - c) / (3.0 * a2))
    v = rng.uniform(0.1, 0.5) * min(math.sqrt(k / m) * (r_y - r_k) / k, top)
    return dict(m=m, k=k, r_y=r_y, r_k=r_k, alpha1=a1, alpha2=a2, c=c,
                v=v if seed % 3 else -v)


@pytest.mark.parametrize("seed", range(6))
def test_stick_slip_cycles_agree_with_the_exact_stick_reference(seed):
    """From the breakaway point the slip starts with ``zdd = -(r_y - r_k)/m`` (v >
    0): no tangential release. Closed-form arcs where alpha2 = 0, dop853 else, and
    dopri5 on one; both belt directions."""
    kw = _belt_point(seed)
    ref = reference_stick_slip_cycle(**kw, v_s=0.0)
    L_ = _length(**kw)
    methods = ["auto"] + (["dopri5"] if seed == 1 else [])
    for method in methods:
        a = sc.attractor(sc.Params(**kw, v_s=0.0), method=method)
        assert (a.regime, a.status) == ("stick_slip", "ok"), (method, a)
        for name in ("amplitude", "x_max", "x_min", "mean"):
            assert abs(getattr(a, name) - ref[name]) <= CONTRACT * L_, (method, name)
        assert a.period == pytest.approx(ref["period"], rel=CONTRACT)
        assert a.stick_fraction == pytest.approx(ref["stick_time"] / ref["period"],
                                                 abs=CONTRACT)


def test_a_trajectory_agrees_with_the_reference():
    """The trajectory kernel: x(t) from a start off the belt through slips, sticks
    and the release at r_y, against the reference's exact sticks."""
    kw = _belt_point(3)
    t = np.linspace(0.0, 40.0, 401)
    ds = sc.simulate(sc.Params(**kw, v_s=0.0), t_end=40.0, x0=0.3, xdot0=0.0,
                     output_dt=0.1)
    x_ref, xd_ref, events = reference_run(**kw, x0=0.3, xd0=0.0, t_eval=t, v_s=0.0)
    assert any(kind == "slip" for _t, kind, _x in events)
    x = np.interp(t, ds.time.values, ds.x.values)
    assert np.max(np.abs(x - x_ref)) <= 1e-7 * _length(**kw)


def test_a_slip_cycle_of_the_scan_is_the_references():
    """Just below v* the polynomial law's supercritical Hopf point leaves a stable
    slip cycle that never reaches the belt: the scan finds it (it never sees the
    jump), and shooting on the reference's return map agrees."""
    kw = dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, c=0.02, alpha1=0.6, alpha2=0.1)
    p = sc.Params(**kw, v_s=0.0, v=1.0)
    p = sc.Params(**kw, v_s=0.0, v=0.99 * p.v_star)
    out = np.empty((1, MAX_CYCLES, L.NOBS))
    found = np.zeros(1, np.int64)
    compiled.cycles(p.row(0.0, p.v)[None, :], (p.friction_law,), make_options(), out,
                    found)
    (row,) = out[0, :found[0]]
    assert row[L.OB_STATUS] == codes.OK and 0.0 < row[L.OB_FLOQUET] < 1.0
    ref = reference_slip_cycle(p.m, p.k, p.r_y, p.v, p.alpha1, p.alpha2,
                               row[L.OB_X_MAX], c=p.c, r_k=p.r_k, v_s=0.0)
    L_ = _length(**kw, v=p.v)
    for col, name in ((L.OB_AMPLITUDE, "amplitude"), (L.OB_MEAN, "mean")):
        assert abs(row[col] - ref[name]) <= 1e-7 * L_, name
    assert row[L.OB_FLOQUET] == pytest.approx(ref["floquet"], rel=1e-5)


def _x_maxima(t, x, xd):
    """The maxima of x on a dense sampling (x' from + to -), each from a quartic
    fitted to the seven samples around it (error ~1e-12 cm at dt = 2e-3 s)."""
    out = []
    for j in np.flatnonzero((xd[:-1] > 0.0) & (xd[1:] <= 0.0)):
        c = np.polyfit(t[j - 3:j + 4] - t[j], x[j - 3:j + 4], 4)
        r = np.roots(np.polyder(c))
        r = r[np.isreal(r)].real
        out.append(np.polyval(c, r[np.argmin(np.abs(r))]))
    return np.array(out)


def test_a_slip_cycle_with_reversals_has_the_jumps_multiplier():
    """A slip cycle whose slides reverse at zero speed without sticking (|k x + c v|
    > r_y there): each reversal's saltation is the ratio of the accelerations after
    and before, with F(0+-) = +-r_k (not the static r_y). The multiplier is the
    reference's: the ratio of successive deviations of the x maxima from the cycle's,
    from a start 1e-4 cm off (error ~1e-5)."""
    kw = dict(m=1.0, k=1.0, r_y=0.8, r_k=0.5, alpha1=0.5, alpha2=0.02, c=0.09, v=1.0)
    a = sc.attractor(sc.Params(**kw, v_s=0.0), tol=1e-11)
    assert (a.regime, a.status) == ("slip_cycle", "ok")
    t = np.arange(0.0, 6.0 * a.period, 2e-3)
    x, xd, events = reference_run(**kw, x0=a.x_max + 1e-4, xd0=0.0, t_eval=t, v_s=0.0)
    assert {kind for _t, kind, _x in events} == {"normal_stop"}
    d = _x_maxima(t, x, xd) - a.x_max
    assert a.floquet == pytest.approx(d[-1] / d[-2], abs=1e-4)


# ------------------------------------------------------------------ forced
def _forced_point(seed):
    """A forced slider with sticks likely: a load of the order of r_y."""
    rng = np.random.default_rng(200 + seed)
    m, k = rng.uniform(0.5, 2.0, 2)
    r_y = rng.uniform(0.5, 1.0)
    kw = dict(m=m, k=k, c=rng.uniform(0.02, 0.3), v=0.0 if seed % 2 == 0 else
              rng.uniform(0.2, 1.0), F0=r_y * rng.uniform(1.0, 1.6),
              Omega=math.sqrt(k / m) * rng.uniform(0.3, 1.0), phi=rng.uniform(0, 6.2),
              r_y=r_y, r_k=r_y * rng.uniform(0.3, 0.8), alpha1=rng.uniform(0.0, 0.1),
              alpha2=rng.uniform(0.0, 0.05))
    return kw


def _forced_pair(kw):
    coef = {n: kw[n] for n in ("r_y", "r_k", "alpha1", "alpha2")}
    ref_law = (lambda s, f=coef: math.copysign(f["r_k"], s) - f["alpha1"] * s
               + f["alpha2"] * s ** 3, coef["r_y"], coef["r_y"])
    slider = {n: kw[n] for n in kw if n not in coef}
    res = sc.attractor(sc.Params(**kw, v_s=0.0), x0=0.0, xdot0=0.0)
    mod = Forced(**slider, law=ref_law)
    ref = forced_steady(mod, x0=0.0, xd0=0.0)
    if ref["status"] != "ok":
        pytest.skip(f"reference: {ref['status']}")
    return res, ref, mod


@pytest.mark.parametrize("seed", range(6))
def test_forced_responses_agree_with_the_exact_stick_reference(seed):
    """Fixed ground and a belt: the response the start at rest settles on, its
    counts and observables (the reference's law a callable with static limits
    r_y: the jump written out, sharing nothing with the family)."""
    res, ref, mod = _forced_pair(_forced_point(seed))
    assert res.status == "ok", res
    assert (res.multiplicity, res.sticks_per_period, res.stops_per_period) == \
        (ref["multiplicity"], ref["sticks_per_period"], ref["stops_per_period"])
    for name in ("amplitude", "mean", "x_max", "x_min"):
        assert abs(getattr(res, name) - ref[name]) <= CONTRACT * mod.L, name
    for name in ("xdot_max", "velocity_amplitude"):
        assert abs(getattr(res, name) - ref[name]) <= CONTRACT * mod.Lv, name
    assert res.stick_fraction == pytest.approx(ref["stick_fraction"], abs=CONTRACT)


@pytest.mark.parametrize("seed", [2, 3, 5])
def test_forced_multipliers_with_sticks_agree_with_the_reference(seed):
    """The largest multiplier of a response that sticks (the reference's central
    differences of P^n, ~1e-7): the release from a stick starts with the jump of
    the acceleration (r_y - r_k)/m, whose saltation the driver takes
    (``driver._salt_release``)."""
    res, ref, _mod = _forced_pair(_forced_point(seed))
    assert ref["sticks_per_period"] > 0
    assert res.floquet == pytest.approx(ref["floquet"], abs=1e-5)


# ------------------------------------------------------ the flat table, as before
FLAT_SPEED = np.linspace(0.0, 8.0, 9)


@pytest.mark.parametrize("v", [0.3, -0.25])
def test_the_keywords_and_a_flat_table_with_stiction_agree(v):
    """``TableLaw(speed, r_k, static=r_y)`` was the way to this law: the same
    stick-slip cycle (same stepper, two law kinds) and the same forced response."""
    kw = dict(m=1.2, k=0.9, c=0.05)
    r_y, r_k = 1.0, 0.45
    table = sc.TableLaw(FLAT_SPEED, np.full(FLAT_SPEED.size, r_k), static=r_y)
    for extra in ({}, dict(F0=1.0, Omega=0.5, phi=0.4)):
        a = sc.attractor(sc.Params(**kw, v=v, r_y=r_y, r_k=r_k, v_s=0.0, **extra),
                         method="dop853", x0=0.0, xdot0=0.0)
        b = sc.attractor(sc.Params(**kw, v=v, law=table, **extra), method="dop853",
                         x0=0.0, xdot0=0.0)
        assert (a.regime, a.status) == (b.regime, b.status) == ("stick_slip", "ok")
        L_ = _length(**kw, r_y=r_y, v=v)
        for name in ("amplitude", "mean", "x_max", "x_min"):
            assert abs(getattr(a, name) - getattr(b, name)) <= 1e-10 * L_, (extra, name)
        assert a.period == pytest.approx(b.period, rel=1e-10)
        assert a.floquet == pytest.approx(b.floquet, abs=1e-9)
