"""The independent scipy reference (``tests/reference.py``) checked against closed forms.

Nothing here imports sweepcore, and no check compares the reference with itself along
one code path: every expected value is a formula derived below (or, for the published
case, a number from the literature).

* constant Coulomb law (r_k = r_y, alpha = 0, c = 0): the stick-slip cycle is the circle
  of radius v/omega about r_y/k, period 2 pi/omega, no stick (the return grazes belt
  speed at the breakaway point);
* jump law (static r_y > kinetic r_k: v_s = 0, alpha = 0, c = 0), scaled to
  u = x - r_k/k, w = x'/omega: slip arcs are circles about u = 0 through the breakaway
  point (d, v/omega), d = (r_y - r_k)/k, of radius R = sqrt(d^2 + (v/omega)^2); the arc
  turns clockwise from angle -atan(v/(omega d)) to pi + atan(v/(omega d)), i.e. it
  sticks at x = (2 r_k - r_y)/k after the slip time (pi + 2 atan(v sqrt(k m)/(r_y -
  r_k)))/omega; stick time 2 (r_y - r_k)/(k v); x_max, x_min = r_k/k +- R; x' min =
  -omega R; the time average of x is r_k/k (the stick is symmetric about r_k/k and
  int cos over an arc symmetric about pi/2 vanishes); v -> -v mirrors all of it;
* viscous damping with the constant law: the slip arc is the decaying sinusoid
  x = r_y/k + exp(-zeta omega t) (A cos omega_d t + B sin omega_d t);
* slide-slide reversals of the constant law: circle arcs about -+r_y/k;
* steady sliding: k x_eq = r_k + (r_y - r_k) exp(-v/v_s) - alpha1 v + alpha2 v^3, the
  linearised damping c + F'(-v), the Hopf points ln(10)/2 (published case) and
  sqrt((alpha1 - c)/(3 alpha2)) (cubic law), sub/supercritical by the sign of F''';
* the unstable slip cycle next to the subcritical Hopf point against first-order
  averaging: A^2 = -8 delta/F'''(-v), multiplier ~ exp(2 pi delta) (m = k = 1);
* polygon clipping against areas of discs cut by a box (quadrature of the formula).
"""
import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from reference import (clip_polygon_to_box, polygon_area, reference_basin_fraction,
                       reference_equilibrium, reference_find_slip_cycles, reference_fold,
                       reference_hopf, reference_run, reference_slip_cycle,
                       reference_stick_slip_cycle)

# the bSTAB / pybasin friction case in sweepcore's parameters
BSTAB = dict(m=1.0, k=1.0, r_y=1.0, alpha1=0.0, alpha2=0.0, c=0.1, r_k=0.5, v_s=0.5)


@pytest.mark.parametrize("m, k, r_y, v", [(1.0, 1.0, 1.0, 1.0), (5.0, 50.0, 10.0, 3.0),
                                          (0.2, 7.0, 0.3, 0.05)])
def test_coulomb_stick_slip_cycle_is_a_circle(m, k, r_y, v):
    w = math.sqrt(k / m)
    r = reference_stick_slip_cycle(m, k, r_y, v, 0.0, 0.0)
    L = r_y / k + v / w
    assert r["amplitude"] == pytest.approx(v / w, abs=1e-10 * L)
    assert r["x_max"] == pytest.approx(r_y / k + v / w, abs=1e-10 * L)
    assert r["x_min"] == pytest.approx(r_y / k - v / w, abs=1e-10 * L)
    assert r["mean"] == pytest.approx(r_y / k, abs=1e-10 * L)
    assert r["period"] == pytest.approx(2 * math.pi / w, rel=1e-10)
    assert r["stick_time"] <= 1e-9 / w
    assert r["xdot_min"] == pytest.approx(-v, rel=1e-10)


def _jump_law_cycle(m, k, r_y, r_k, v):
    w = math.sqrt(k / m)
    d = (r_y - r_k) / k
    R = math.hypot(d, v / w)
    return dict(x_stick=(2 * r_k - r_y) / k, stick_time=2 * (r_y - r_k) / (k * v),
                slip_time=(math.pi + 2 * math.atan(v * math.sqrt(k * m) / (r_y - r_k))) / w,
                x_max=r_k / k + R, x_min=r_k / k - R, amplitude=R, mean=r_k / k,
                xdot_max=v, xdot_min=-w * R)


@pytest.mark.parametrize("m, k, r_y, r_k, v", [(1.0, 1.0, 1.0, 0.5, 1.0),
                                               (2.0, 3.0, 1.2, 0.8, 0.7),
                                               (5.0, 50.0, 10.0, 2.0, 0.3),
                                               (1.0, 4.0, 1.0, 0.0, 2.0)])
@pytest.mark.parametrize("sign", [1, -1])
def test_jump_law_stick_slip_cycle_closed_form(m, k, r_y, r_k, v, sign):
    ex = _jump_law_cycle(m, k, r_y, r_k, v)
    r = reference_stick_slip_cycle(m, k, r_y, sign * v, 0.0, 0.0, r_k=r_k, v_s=0.0)
    L = r_y / k + v / math.sqrt(k / m)
    if sign < 0:                                   # the mirror x -> -x, v -> -v
        ex.update(x_stick=-ex["x_stick"], x_max=-ex["x_min"], x_min=-ex["x_max"],
                  mean=-ex["mean"], xdot_max=-ex["xdot_min"], xdot_min=-v)
    kinds = [e[1] for e in r["events"]]
    assert kinds == ["stick", "slip"]
    assert r["events"][0][2] == pytest.approx(ex["x_stick"], abs=1e-10 * L)
    assert r["events"][1][2] == pytest.approx(sign * (r_y / k), abs=1e-12 * L)
    for name in ("stick_time", "slip_time"):
        assert r[name] == pytest.approx(ex[name], rel=1e-10), name
    for name in ("x_max", "x_min", "amplitude", "mean"):
        assert r[name] == pytest.approx(ex[name], abs=1e-10 * L), name
    for name in ("xdot_max", "xdot_min"):
        assert r[name] == pytest.approx(ex[name], abs=1e-10 * v), name


def test_stribeck_law_tends_to_the_jump_law_as_v_s_shrinks():
    """v_s -> 0+ approaches the jump law, slowly (the drop from r_y to r_k takes the
    time in which |zdot| grows to ~v_s from the breakaway point, where zdot ~ t^2)."""
    m, k, r_y, r_k, v = 2.0, 3.0, 1.2, 0.8, 0.7
    ex = _jump_law_cycle(m, k, r_y, r_k, v)
    errs = [abs(reference_stick_slip_cycle(m, k, r_y, v, 0.0, 0.0, r_k=r_k,
                                           v_s=vs)["period"]
                - ex["stick_time"] - ex["slip_time"]) for vs in (1e-2, 1e-3, 1e-4)]
    assert errs[0] > 3 * errs[1] > 9 * errs[2]
    assert errs[2] < 1e-3 * (ex["stick_time"] + ex["slip_time"])


def test_damped_slip_arc_is_the_decaying_sinusoid():
    m, k, r_y, c, v = 2.0, 3.0, 1.2, 0.3, 0.8
    x0, xd0 = -0.5, 0.0
    w = math.sqrt(k / m)
    zeta = c / (2.0 * math.sqrt(k * m))
    wd = w * math.sqrt(1.0 - zeta ** 2)
    A = x0 - r_y / k
    B = (xd0 + zeta * w * A) / wd

    def x(t):
        return r_y / k + np.exp(-zeta * w * t) * (A * np.cos(wd * t) + B * np.sin(wd * t))

    def xd(t):
        e = np.exp(-zeta * w * t)
        return e * ((-zeta * w * A + wd * B) * np.cos(wd * t)
                    + (-zeta * w * B - wd * A) * np.sin(wd * t))

    t = np.linspace(0.0, 3.0, 301)
    xr, xdr, events = reference_run(m, k, r_y, v, 0.0, 0.0, x0, xd0, t, c=c)
    t_hit = events[0][0]
    assert t_hit == pytest.approx(brentq(lambda s: xd(s) - v, 0.1, t_hit + 0.3),
                                  abs=1e-11)
    assert events[0][1] == "stick" and events[0][2] == pytest.approx(x(t_hit), abs=1e-11)
    arc = t <= t_hit
    np.testing.assert_allclose(xr[arc], x(t[arc]), atol=1e-11)
    np.testing.assert_allclose(xdr[arc], xd(t[arc]), atol=1e-11)
    # then it sticks: x moves with the belt until k x + c v = r_y
    after = (t > t_hit) & (t < events[1][0])
    np.testing.assert_allclose(xdr[after], v, rtol=0, atol=0)
    assert events[1][1] == "slip" and events[1][2] == pytest.approx((r_y - c * v) / k,
                                                                    abs=1e-14)


def test_slide_slide_reversals_of_the_constant_law():
    """m = k = r_y = v = 1, start x = -5.5 at belt speed (k x + c v <= -r_y: slide with
    zdot > 0): circle about -1 to x = 3.5 (reversal), about +1 to x = -1.5 (reversal),
    about -1 to x = -0.5 (stick), stick to x = 1 (slip). Arc times are angles swept."""
    t1 = math.pi - 2 * math.atan(1 / 4.5)
    t2 = t1 + math.pi + 2 * math.atan(1 / 2.5)
    t3 = t2 + math.pi - 2 * math.atan(2.0)
    t4 = t3 + 1.5
    t = np.linspace(0.0, t4 + 0.5, 2001)
    x, xd, events = reference_run(1.0, 1.0, 1.0, 1.0, 0.0, 0.0, -5.5, 1.0, t)
    assert [e[1] for e in events] == ["normal_stop", "normal_stop", "stick", "slip"]
    for (te, _kind, xe), (ts, xs) in zip(events, [(t1, 3.5), (t2, -1.5), (t3, -0.5),
                                                   (t4, 1.0)]):
        assert te == pytest.approx(ts, abs=1e-10)
        assert xe == pytest.approx(xs, abs=1e-10)
    first = t < t1                            # on the circle about -1: radius^2 = 21.25
    np.testing.assert_allclose((x[first] + 1) ** 2 + xd[first] ** 2, 21.25, rtol=1e-11)


@pytest.mark.parametrize("v", [0.3, 1.0, 1.5, 2.5])
def test_equilibrium_of_the_published_case(v):
    eq = reference_equilibrium(v=v, **BSTAB)
    assert eq["x_eq"] == pytest.approx(0.5 + 0.5 * math.exp(-2 * v), rel=1e-14)
    assert eq["damping"] == pytest.approx(0.1 - math.exp(-2 * v), abs=1e-9)
    assert eq["f3"] == pytest.approx(-4.0 * math.exp(-2 * v), rel=1e-4)
    assert eq["criticality"] == "subcritical"
    assert eq["stable"] == (v > math.log(10) / 2)


def test_equilibrium_of_the_whole_family():
    p = dict(m=2.0, k=3.0, r_y=1.2, r_k=0.7, v_s=0.3, alpha1=0.1, alpha2=0.02, c=0.05)
    for v in (0.3, 0.8, 1.5):
        eq = reference_equilibrium(v=v, **p)
        F = (0.7 + 0.5 * math.exp(-v / 0.3) - 0.1 * v + 0.02 * v ** 3)
        assert eq["x_eq"] == pytest.approx(F / 3.0, rel=1e-14)
        dF = -0.5 / 0.3 * math.exp(-v / 0.3) - 0.1 + 0.06 * v * v   # F'(-v)
        assert eq["damping"] == pytest.approx(0.05 + dF, abs=1e-9)
        assert reference_equilibrium(v=-v, **p)["x_eq"] == -eq["x_eq"]


def test_hopf_points():
    h = reference_hopf(1.0, 1.0, 1.0, 0.0, 0.0, 1.0, 1.3, c=0.1, r_k=0.5, v_s=0.5)
    assert h["v_hopf"] == pytest.approx(math.log(10) / 2, abs=1e-9)
    assert h["criticality"] == "subcritical"
    # cubic law (r_k = r_y): v* = sqrt((alpha1 - c)/(3 alpha2)), supercritical
    for c in (0.0, 0.4):
        h = reference_hopf(5.0, 50.0, 10.0, 1.0, 0.01, 1.0, 10.0, c=c)
        assert h["v_hopf"] == pytest.approx(math.sqrt((1.0 - c) / 0.03), abs=1e-9)
        assert h["criticality"] == "supercritical"


@pytest.mark.parametrize("v", [1.155, 1.16])
def test_unstable_cycle_next_to_the_hopf_point_matches_averaging(v):
    """m = k = 1: xi'' + xi = -delta xi' - F''(-v) xi'^2/2 - F'''(-v) xi'^3/6 + ...;
    averaging gives dA/dt = -(delta A/2 + F''' A^3/16), so A^2 = -8 delta/F''' =
    2 (0.1 exp(2 v) - 1), and the multiplier exp(2 pi delta) to first order. The
    neglected terms are O(A^2) relative (measured: 0.08 A^2 and 0.33 A^2)."""
    cycles = reference_find_slip_cycles(v=v, **BSTAB, n_scan=12)
    assert len(cycles) == 1
    cy = cycles[0]
    delta = 0.1 - math.exp(-2 * v)
    A = math.sqrt(2 * (0.1 * math.exp(2 * v) - 1))
    assert abs(cy["amplitude"] / A - 1) < 0.12 * A * A
    assert abs((cy["floquet"] - 1) / (2 * math.pi * delta) - 1) < 0.5 * A * A
    assert cy["floquet"] > 1.0
    assert cy["floquet"] == pytest.approx(cy["floquet_liouville"], abs=1e-7)


def test_floquet_multiplier_of_a_stable_cubic_law_cycle():
    """Difference quotient of the return map against Liouville's formula, and below 1."""
    v_star = math.sqrt(1.0 / (3 * 0.01))
    cy = reference_slip_cycle(5.0, 50.0, 10.0, 0.95 * v_star, 1.0, 0.01, None,
                              bracket=(0.2 + 0.05, 0.2 + 1.5))
    assert 0.0 < cy["floquet"] < 1.0
    assert cy["floquet"] == pytest.approx(cy["floquet_liouville"], abs=1e-7)


def _disc(R, x0, y0, n=20000):
    th = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    return x0 + R * np.cos(th), y0 + R * np.sin(th)


@pytest.mark.parametrize("R, x0", [(1.0, 0.3), (2.5, 0.3), (3.5, -1.0), (0.5, 1.9)])
def test_clipping_a_disc_to_the_box(R, x0):
    box = ((-2.0, 2.0), (0.0, 2.0))
    x, y = _disc(R, x0, 0.0)
    cx, cy = clip_polygon_to_box(x, y, box)
    assert cx.min() >= -2.0 and cx.max() <= 2.0 and cy.min() >= 0.0 and cy.max() <= 2.0

    def height(s):
        h2 = R * R - (s - x0) ** 2
        return min(2.0, math.sqrt(h2)) if h2 > 0 else 0.0
    lo, hi = max(-2.0, x0 - R), min(2.0, x0 + R)
    exact = quad(height, lo, hi, limit=200, epsabs=1e-13, points=[x0])[0]
    # the inscribed 20000-gon misses (2 pi/n)^2/6 of the disc area near its rim
    assert polygon_area(cx, cy) == pytest.approx(exact, rel=2e-7)


def test_clipping_a_concave_polygon_and_a_polygon_outside():
    box = ((0.0, 1.0), (0.0, 1.0))
    L = ([-1.0, 2.0, 2.0, 0.5, 0.5, -1.0], [-1.0, -1.0, 0.5, 0.5, 2.0, 2.0])   # an L
    cx, cy = clip_polygon_to_box(*L, box)
    assert polygon_area(cx, cy) == pytest.approx(0.5 + 0.25, abs=1e-15)
    cx, cy = clip_polygon_to_box([3.0, 4.0, 4.0], [3.0, 3.0, 4.0], box)
    assert polygon_area(cx, cy) == 0.0


def test_basin_fraction_of_the_published_case_at_1_5():
    """Published 0.304 +- 0.0065 (5,000 samples): the exact area lies within it."""
    cy = reference_slip_cycle(v=1.5, a_guess=None, bracket=(1.8, 1.9), **BSTAB)
    assert cy["floquet"] > 1.0
    bf = reference_basin_fraction(v=1.5, a=cy["x_max"], **BSTAB)
    assert bf["fraction"] == pytest.approx(0.304, abs=0.0065)
    coarse = reference_basin_fraction(v=1.5, a=cy["x_max"], n=4001, **BSTAB)
    assert coarse["fraction"] == pytest.approx(bf["fraction"], abs=2e-6)


def test_fold_of_the_published_case():
    """The last stick-slip cycle: just below the fold it exists, just above the slide
    from the breakaway point spirals into steady sliding; near the fold the unstable
    slip cycle's top speed approaches the belt speed (the two cycles meet), and above
    it no slip cycle is left."""
    f = reference_fold(1.0, 1.0, 1.0, 0.0, 0.0, 1.7, 1.9, c=0.1, r_k=0.5, v_s=0.5,
                       xtol=1e-9)
    vf = f["v_fold"]
    assert vf == pytest.approx(1.83660, abs=1e-5)
    reference_stick_slip_cycle(v=vf - 1e-4, **BSTAB)
    with pytest.raises(ValueError):
        reference_stick_slip_cycle(v=vf + 1e-4, **BSTAB, max_periods=6)
    gaps = []
    for dv in (1e-2, 1e-3):
        cy = reference_find_slip_cycles(v=vf - dv, **BSTAB, n_scan=24)[-1]
        gaps.append(vf - dv - cy["xdot_max"])
    assert 0.0 < gaps[1] < gaps[0] / 3
    assert reference_find_slip_cycles(v=vf + 1e-3, **BSTAB, n_scan=24) == []


def test_stick_slip_cycle_against_a_long_run():
    """The published case at v = 1.5 from a start outside the unstable cycle: after a
    transient the breakaways are one cycle period apart, all at x_s = 1 - 0.1 v."""
    cyc = reference_stick_slip_cycle(v=1.5, **BSTAB)
    t = np.linspace(0.0, 60.0, 601)
    _x, _xd, events = reference_run(v=1.5, x0=-2.0, xd0=0.0, t_eval=t, **BSTAB)
    slips = [e for e in events if e[1] == "slip"]
    assert len(slips) >= 5
    assert all(e[2] == pytest.approx(0.85, abs=1e-14) for e in slips)
    np.testing.assert_allclose(np.diff([e[0] for e in slips])[1:], cyc["period"],
                               rtol=1e-10)


# --------------------------------------------- tests/reference_edges.py, validated
def test_layered_reference_agrees_with_the_plain_one_on_a_wide_layer():
    """v_s = 0.1 |v|-ish: the plain DOP853 run resolves the layer by its own error
    control; the layered run (step capped in the layer) gives the same cycle."""
    from reference_edges import layered_stick_slip_cycle
    kw = dict(m=1.0, k=1.0, r_y=1.0, c=0.05, r_k=0.5, v_s=0.1)
    a = layered_stick_slip_cycle(**kw, v=0.3)
    b = reference_stick_slip_cycle(1.0, 1.0, 1.0, 0.3, 0.0, 0.0, c=0.05, r_k=0.5,
                                   v_s=0.1)
    for name in ("amplitude", "x_max", "x_min", "period", "stick_time", "mean"):
        assert a[name] == pytest.approx(b[name], abs=1e-10), name


@pytest.mark.parametrize("v_s", [1e-3, 1e-6])
def test_layered_reference_converges_in_its_cap_and_tolerance(v_s):
    from reference_edges import layered_stick_slip_cycle
    kw = dict(m=1.0, k=1.0, r_y=1.0, c=0.05, r_k=0.5, v_s=v_s, v=0.3)
    a = layered_stick_slip_cycle(**kw)
    b = layered_stick_slip_cycle(**kw, cap_fraction=0.01, rtol=1e-13)
    for name in ("amplitude", "period", "stick_time"):
        assert a[name] == pytest.approx(b[name], abs=2e-12), name


def test_layered_reference_tends_to_the_jump_law_linearly_in_v_s():
    """c = 0: the jump law's closed form (above) is the limit v_s -> 0+; the
    layered reference approaches it in proportion to v_s (the release through the
    layer, where the friction is still above r_k, lasts ~v_s (m/d) ln(...))."""
    from reference_edges import layered_stick_slip_cycle
    m, k, r_y, r_k, v = 2.0, 3.0, 1.2, 0.8, 0.7
    ex = _jump_law_cycle(m, k, r_y, r_k, v)
    errs = []
    for vs in (1e-5, 1e-7, 1e-9):
        r = layered_stick_slip_cycle(m, k, r_y, v, r_k=r_k, v_s=vs)
        errs.append(abs(r["period"] - ex["stick_time"] - ex["slip_time"]))
        assert r["amplitude"] == pytest.approx(ex["amplitude"], abs=100 * vs)
    assert errs[0] > 30 * errs[1] > 900 * errs[2]


def test_reference_attractor_on_closed_forms():
    """The jump law (v_s -> 0) from the stuck start: its closed-form stick-slip
    cycle; constant friction with damping from next to x_eq: the equilibrium (the
    damped linear oscillator, certified); a cubic law below v*: the slip cycle of
    the shooting solve, with the averaging amplitude to 1 % (docs/physics.md: 0.1 %)."""
    from reference_edges import reference_attractor
    m, k, r_y, r_k, v = 2.0, 3.0, 1.2, 0.8, 0.7
    ex = _jump_law_cycle(m, k, r_y, r_k, v)
    got = reference_attractor(m, k, r_y, v, 0.0, 0.0, 0.0, None, r_k=r_k, v_s=0.0)
    assert got["regime"] == "stick_slip"
    assert got["cycle"]["amplitude"] == pytest.approx(ex["amplitude"], abs=1e-10)
    eq = reference_attractor(1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 1.0 - 0.1 + 0.05, 0.0, c=0.1)
    assert eq["regime"] == "equilibrium" and eq["cycle"] is None
    # the paper's law at 0.95 v*: a stable slip cycle, A omega = 2 sqrt(v*^2 - v^2)
    vs = math.sqrt(1.0 / (3 * 0.01))
    cyc = reference_attractor(5.0, 50.0, 10.0, 0.95 * vs, 1.0, 0.01, 0.2 + 0.5, 0.0,
                              max_periods=4000)
    assert cyc["regime"] == "slip_cycle"
    w = math.sqrt(10.0)
    assert cyc["cycle"]["amplitude"] * w == pytest.approx(
        2 * math.sqrt(vs ** 2 - (0.95 * vs) ** 2), rel=1e-2)
