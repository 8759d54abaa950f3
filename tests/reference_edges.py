"""The independent reference at the edges of the law family: which attractor a start
reaches, and the steep Stribeck layer resolved by construction.

Shares no code with sweepcore (nothing here imports it); builds on ``reference.py``
(scipy DOP853, sticks in closed form, shooting on the section map). Units kN, cm, s.

* :func:`reference_attractor`: the attractor reached from a start, by following the
  hybrid motion period by period until one of three things is proven: the motion
  passes the breakaway point and the slip arc from there comes back to the belt
  (a stick-slip cycle: every slip restarts there, so the cycle is the motion from
  that point, :func:`reference.reference_stick_slip_cycle`); its state enters a
  sublevel set of the energy about x_eq on which the energy provably decays (the
  equilibrium; the minimum of ``c + F'`` over the set's speeds is taken on a fine
  grid of the analytic F', with a margin); or its returns to the x maxima settle
  (a slip cycle, refined by shooting, :func:`reference.reference_slip_cycle`).
* :func:`layered_stick_slip_cycle`: the stick-slip cycle with the Stribeck layer
  (|zdot| within ``M v_s`` of the belt, where ``exp(-|zdot|/v_s)`` is not
  negligible) integrated with the step capped at a fraction of the time the motion
  needs to cross ``v_s``: every stage of the integrator samples the layer, whatever
  the error estimate sees.
"""
import math

import numpy as np
from scipy.integrate import solve_ivp

from reference import (_hybrid, _Model, reference_breakaway_peak,
                       reference_equilibrium, reference_slip_cycle,
                       reference_stick_slip_cycle)

__all__ = ["reference_attractor", "certified_rest", "layered_stick_slip_cycle"]


def _dforce_min(mod, lo, hi, n=20001):
    """Least ``c + F'(s)`` over s in [lo, hi] (s < 0 side), on a grid of n points of
    the analytic derivative; F' is smooth there, so the grid minimum is within
    ``max|F''| (hi - lo)/(2 n)`` of the true one (returned as a margin)."""
    s = np.linspace(lo, hi, n)
    dr, vs = mod.dr, mod.v_s
    f1 = -dr / vs * np.exp(np.minimum(s / vs, 60.0)) - mod.a1 + 3.0 * mod.a2 * s * s
    f2 = -dr / vs ** 2 * np.exp(np.minimum(s / vs, 60.0)) + 6.0 * mod.a2 * s
    margin = np.max(np.abs(f2)) * (hi - lo) / (2.0 * (n - 1))
    return float(np.min(mod.c + f1)), float(margin)


def certified_rest(mod, x, xd):
    """True when (x, x') lies in a sublevel set of E = (m y'^2 + k y^2)/2 (y = x -
    x_eq) on which dE/dt = -y'^2 (c + S) < 0, S the secant slope of F between -v and
    -v + y' (bounded below by min F' on [-v - W, -v + W], W = sqrt(2E/m) < v: the
    slider never reaches the belt speed inside). v > 0."""
    v = mod.v
    x_eq = reference_equilibrium(mod.m, mod.k, mod.r_y, v, mod.a1, mod.a2, mod.c,
                                 mod.r_k, mod.v_s if mod.dr else 1.0)["x_eq"]
    y, yd = x - x_eq, xd
    W = math.sqrt(yd * yd + mod.k / mod.m * y * y)
    if not W < 0.999 * v:
        return False
    least, margin = _dforce_min(mod, -v - W, -v + W)
    # rounding: of the terms evaluated over the set, not of the Stribeck slope at
    # the belt (d/v_s, which a narrow layer far from the set never reaches)
    size = abs(mod.c) + abs(mod.a1) + 3.0 * mod.a2 * (v + W) ** 2 + \
        mod.dr / mod.v_s * math.exp(min((W - v) / mod.v_s, 0.0))
    return least > margin + 1e-9 * size


def reference_attractor(m, k, r_y, v, alpha1, alpha2, x0, xd0=None, c=0.0, r_k=None,
                        v_s=1.0, rtol=1e-12, max_periods=200, graze_tol=None):
    """The attractor reached from (x0, x'(0) = xd0) (``xd0=None``: stuck on the belt),
    v > 0. Returns dict(regime = 'stick_slip' | 'equilibrium' | 'slip_cycle', cycle =
    the cycle's dict (None at the equilibrium), t = the time at which it was proven).
    A slip arc from the breakaway point that comes back within ``graze_tol``
    (default 100 rtol (|v| + r_y/sqrt(k m)), this reference's own error) of the belt
    speed grazes it: the grazing circle (slip_cycle) of a conservative field (c =
    alpha1, no cubic or Stribeck term); for any other law RuntimeError (undecided).

    Proofs (module docstring): a slip at the breakaway point whose slip arc comes
    back to the belt and sticks (:func:`reference.reference_breakaway_peak`) is the
    stick-slip cycle; the energy certificate at an extremum of x is the
    equilibrium; a return map whose steps contract below 1e-9 of the length scale
    is refined by shooting into the slip cycle. Raises RuntimeError when none is proven
    within ``max_periods`` natural periods."""
    assert v > 0
    mod = _Model(m, k, r_y, v, alpha1, alpha2, c, r_k, v_s)
    kw = dict(c=c, r_k=r_k, v_s=v_s)
    period = 2.0 * math.pi / mod.omega
    L = r_y / k + v / mod.omega
    grazing = 100.0 * rtol * (v + r_y / math.sqrt(k * m)) if graze_tol is None \
        else graze_tol
    conservative = alpha2 == 0.0 and mod.dr == 0.0 and c == alpha1
    t, x, zd = 0.0, float(x0), (0.0 if xd0 is None else float(xd0) - v)
    side = None
    maxima = []
    for _ in range(int(max_periods)):
        segs, events, _closed = _hybrid(mod, t, x, zd, t + period, rtol, side=side)
        if any(kind == "slip" for _t, kind, _x in events):
            peak = reference_breakaway_peak(m, k, r_y, v, alpha1, alpha2, **kw,
                                            rtol=rtol)
            if abs(peak["peak"]) <= grazing:
                # the slip arc from the breakaway point comes back to the belt speed
                # within this reference's own error: a conservative field grazes
                # there exactly (the grazing circle, slip_cycle); any other law is
                # within ~1e-10 of a fold or stick onset, which this cannot decide
                if not conservative:
                    raise RuntimeError("the breakaway arc grazes the belt within the "
                                       "reference's tolerance: undecided")
                cyc = reference_stick_slip_cycle(m, k, r_y, v, alpha1, alpha2, **kw,
                                                 rtol=rtol, graze_tol=grazing)
                return dict(regime="slip_cycle", cycle=cyc, t=t)
            if peak["sticks"]:
                cyc = reference_stick_slip_cycle(m, k, r_y, v, alpha1, alpha2, **kw,
                                                 rtol=rtol, graze_tol=grazing)
                return dict(regime="stick_slip", cycle=cyc, t=t)
        last = segs[-1]
        if last["kind"] == "stick":
            t, x, zd, side = last["t1"], last["x0"] + v * (last["t1"] - last["t0"]), 0.0, 0
            continue
        w = last["windows"][-1]
        t, y1 = w["t1"], w["y1"]
        x, zd, side = float(y1[0]), float(y1[1]), (None if y1[1] != 0.0 else w["sgn"])
        for win in last["windows"]:
            for _ts, xs in win["stills"]:
                xdd = mod.acc(xs, -v, win["sgn"])
                if xdd < 0.0:
                    maxima.append(xs)
                if certified_rest(mod, xs, 0.0):
                    return dict(regime="equilibrium", cycle=None, t=t)
        if len(maxima) >= 4 and not any(e[1] in ("stick", "slip") for e in events):
            # settled: contracting returns (a slow escape from a ghost next to a
            # fold also moves little per return, but its steps grow)
            d = np.abs(np.diff(maxima[-4:]))
            if d[-1] < 1e-9 * L and d[-1] < 0.9 * d[-2] < 0.81 * d[-3]:
                cyc = reference_slip_cycle(m, k, r_y, v, alpha1, alpha2, maxima[-1],
                                           **kw)
                return dict(regime="slip_cycle", cycle=cyc, t=t)
    raise RuntimeError(f"no attractor proven within {max_periods} periods")


# ------------------------------------------------------------ the steep layer
def _layer_arc(mod, x, t_max, rtol, cap_fraction, width):
    """Slide on side -1 from the breakaway point (x, zdot = 0) until zdot comes back
    to 0 from below (or t_max), with the step capped inside the layer |zdot| <
    ``width`` (module docstring): at most ``cap_fraction`` of the time the motion
    takes to cross v_s there, ``v_s / (|x''| + |r_y - r_k|/m + sqrt(k v v_s/(2 m)))``
    (the last term: the departure from rest, where x'' = 0). Returns (t, x at the
    return, x_max, x_min, xd_min, int x dt)."""
    v = mod.v
    lx = mod.r_y / mod.k + v / mod.omega
    atol = rtol * 1e-3 * lx

    def rhs(_t, y):
        return [y[1] + v, mod.acc(y[0], y[1], -1), y[0]]

    def cross(_t, y):
        return y[1]
    cross.terminal = True
    cross.direction = 1

    def still(_t, y):
        return y[1] + v

    def turn(_t, y):
        return mod.acc(y[0], y[1], -1)

    def leave(_t, y):                 # zdot falls through -width: out of the layer
        return y[1] + width
    leave.terminal = True
    leave.direction = -1

    def enter(_t, y):                 # zdot rises through -width: into the layer
        return y[1] + width
    enter.terminal = True
    enter.direction = 1

    t, y = 0.0, [x, 0.0, 0.0]
    xs, xds = [x], [v]
    inside = width > 0.0
    for _ in range(10000):
        if inside:
            scale = abs(mod.acc(y[0], y[1], -1)) + mod.dr / mod.m + math.sqrt(
                mod.k * v * mod.v_s / (2.0 * mod.m))
            opts = dict(max_step=cap_fraction * mod.v_s / scale,
                        events=[cross, still, turn, leave])
        else:
            opts = dict(events=[cross, still, turn] + ([enter] if width > 0 else []))
        sol = solve_ivp(rhs, (t, t_max), y, method="DOP853", rtol=rtol, atol=atol,
                        **opts)
        if sol.status < 0:
            raise RuntimeError(sol.message)
        xs += [float(ye[0]) for ye in sol.y_events[1]]
        xds += [float(ye[1] + v) for ye in sol.y_events[2]]
        t, y = float(sol.t[-1]), list(sol.y[:, -1])
        if sol.t_events[0].size:
            xs.append(y[0])
            return t, y[0], max(xs), min(xs), min(xds), y[2]
        if sol.status == 0:
            raise RuntimeError("no return to the belt")
        inside = not inside
    raise RuntimeError("too many layer crossings")


def layered_stick_slip_cycle(m, k, r_y, v, alpha1=0.0, alpha2=0.0, c=0.0, r_k=None,
                             v_s=1.0, rtol=1e-12, cap_fraction=0.05, layer=40.0):
    """The stick-slip cycle (v > 0, one stick per period) with the Stribeck layer
    |zdot| < ``layer`` v_s integrated at a step of at most ``cap_fraction`` of the
    time to cross v_s (module docstring). Returns dict(amplitude, x_max, x_min, mean,
    period, stick_time, xdot_min)."""
    assert v > 0
    mod = _Model(m, k, r_y, v, alpha1, alpha2, c, r_k, v_s)
    width = layer * mod.v_s if mod.dr else 0.0
    horizon = 20.0 * 2.0 * math.pi / mod.omega
    t_slide, x_stick, x_max, x_min, xd_min, ix = _layer_arc(
        mod, mod.x_s, horizon, rtol, cap_fraction, width)
    if abs(mod.stick_load(x_stick)) >= mod.r_y:
        raise ValueError("the slip arc does not stick when it returns to the belt")
    stick = (mod.x_s - x_stick) / v
    period = t_slide + stick
    ix += x_stick * stick + 0.5 * v * stick * stick
    x_max, x_min = max(x_max, mod.x_s), min(x_min, x_stick)
    return dict(amplitude=0.5 * (x_max - x_min), x_max=x_max, x_min=x_min,
                mean=ix / period, period=period, stick_time=stick, xdot_min=xd_min)


def reference_fold_of(m, k, r_y, alpha1, alpha2, c, r_k, v_s, v_from, step=1.05,
                      xtol=1e-13):
    """The fold (largest belt speed with a stick-slip cycle) above ``v_from``: the
    slip arc from the breakaway point sticks when it returns at ``v_from`` and no
    longer at ``v_from step^j`` for the first such j (a scan of
    :func:`reference.reference_breakaway_peak`), bisected by
    :func:`reference.reference_fold` to ``xtol``."""
    from reference import reference_fold

    def sticks(v):
        return reference_breakaway_peak(m, k, r_y, v, alpha1, alpha2, c, r_k,
                                        v_s)["sticks"]
    if not sticks(v_from):
        raise ValueError("no stick-slip cycle at v_from")
    lo = v_from
    for _ in range(200):
        hi = lo * step
        if not sticks(hi):
            return reference_fold(m, k, r_y, alpha1, alpha2, lo, hi, c, r_k, v_s,
                                  xtol=xtol)["v_fold"]
        lo = hi
    raise ValueError("no fold found")
