"""The hybrid stick/slide driver of a forced slider.

The rules are the autonomous driver's (``driver.py``; eq. numbers of Liu's paper),
with the holding force moving in time. While stuck (x' = v) the force that holds the
slider is

    h(t) = e(t) - k x(t) - c v,      x(t) = x_0 + v (t - t_0),

with ``e(t) = a cos(Omega t) + b sin(Omega t)`` the load (``excitations/``): the
stick holds while ``-r_neg <= h <= r_pos`` (the law's static limits,
``law.static_limits``) and ends at the first time h leaves that band: slip forwards
(zdot > 0) above r_pos, backwards below -r_neg. That time is found exactly: h is cut
into monotone pieces at the roots of ``h' = e'(t) - k v`` (closed form for a
harmonic e), and the first piece that leaves the band holds the one root, bracketed,
so no short excursion of the load is stepped over (eq. 27 is the case e = 0).

While sliding, ``zdot = 0`` is located inside a step on the step's Hermite cubic
(``events.zd_event``: two crossings inside a step and a touch between samples are
seen) and polished on re-steps of the integrator; there the slider sticks if h is in
the band and otherwise slides on (a zero-duration stop, eq. 22: a reversal, eq. 30,
or on in the same direction, eq. 31). When ``measure`` is set, the extrema of x
(x' = 0) and of x' (x'' = 0) inside each step are located too, on the part of the
step the motion keeps (also before a stick or a stop), for the observables.
"""
import math

import numpy as np

from . import codes
from .driver import _note_x
from .events import cubic, zd_event
from .forced_step import forced_accel, forced_step, load
from .jit import copy_into, kernel, runtime
from .law import constants, field_slope, static_limits, step_bound
from .layout import (A_DT, A_IX, A_NSTICK, A_NSTOP, A_TSTICK, C, K, M, O_LV, O_LX,
                     O_MAX_STEPS, O_RTOL, S_ARMED, S_H, S_MODE, S_N, S_T, S_X, S_ZD, V)

EPS = np.finfo(np.float64).eps
TOUCH_FACTOR = 20.0     # zdot's error at a touch, in rtol lv (driver.touch_tol)


# ------------------------------------------------------------ the holding force
@kernel(inline="always")
def load_rate(fa, fb, om, t):
    """e'(t) [kN/s]."""
    w = om * t
    return om * (fb * math.cos(w) - fa * math.sin(w))


@kernel(inline="always")
def holding(t, t0, x0, p, fa, fb, om):
    """The force h(t) [kN] that holds a slider stuck since (t0, x0)."""
    return load(fa, fb, om, t) - p[K] * (x0 + p[V] * (t - t0)) - p[C] * p[V]


@kernel
def next_critical(fa, fb, om, kv, t):
    """The first time > t [s] at which ``h' = e'(t) - k v`` vanishes (inf: never):
    ``e' = -Omega R sin(Omega t - psi)``, so ``sin(Omega t - psi) = -k v/(Omega R)``."""
    amp = om * math.hypot(fa, fb)
    if not amp > abs(kv):
        return np.inf
    psi = math.atan2(fb, fa)
    sg = -kv / amp
    r1 = math.asin(sg)
    r2 = math.pi - r1
    th = om * t - psi
    best = np.inf
    for r in (r1, r2):
        # the first r + 2 pi j above th
        j = math.floor((th - r) / (2.0 * math.pi)) + 1.0
        cand = r + 2.0 * math.pi * j
        while cand <= th:
            cand += 2.0 * math.pi
        tc = (cand + psi) / om
        if tc <= t:                       # rounding of the phase
            tc = t + EPS * max(abs(t), 1.0)
        best = min(best, tc)
    return best


@kernel
def _band_root(lo, hi, t0, x0, p, fa, fb, om, level):
    """The root of h(t) = level in [lo, hi], where h - level changes sign once
    (a monotone piece): safeguarded Newton to the resolution of t."""
    flo = holding(lo, t0, x0, p, fa, fb, om) - level
    t = 0.5 * (lo + hi)
    for _ in range(100):
        f = holding(t, t0, x0, p, fa, fb, om) - level
        if f == 0.0:
            return t
        if (f > 0.0) == (flo > 0.0):
            lo = t
        else:
            hi = t
        if hi - lo <= 4.0 * EPS * max(abs(hi), 1.0):
            break
        df = load_rate(fa, fb, om, t) - p[K] * p[V]
        tn = t - f / df if df != 0.0 else 0.5 * (lo + hi)
        if not lo < tn < hi:
            tn = 0.5 * (lo + hi)
        t = tn
    return hi


@kernel
def breakaway_time(t0, x0, p, lw, fa, fb, om, t_stop):
    """``(t_b, mode)``: the first time in (t0, t_stop] at which the holding force of a
    slider stuck since (t0, x0) leaves the band, and the slide it starts (t_stop and
    STICK when it holds throughout)."""
    r_pos, r_neg = static_limits(p, lw)
    kv = p[K] * p[V]
    h0 = holding(t0, t0, x0, p, fa, fb, om)
    if h0 > r_pos:
        return t0, codes.SLIDE_POS
    if h0 < -r_neg:
        return t0, codes.SLIDE_NEG
    a = t0
    for _ in range(1000000):
        b = min(next_critical(fa, fb, om, kv, a), t_stop)
        hb = holding(b, t0, x0, p, fa, fb, om)
        if hb > r_pos:
            return _band_root(a, b, t0, x0, p, fa, fb, om, r_pos), codes.SLIDE_POS
        if hb < -r_neg:
            return _band_root(a, b, t0, x0, p, fa, fb, om, -r_neg), codes.SLIDE_NEG
        if b >= t_stop:
            return t_stop, codes.STICK
        a = b
    return t_stop, codes.STICK


@kernel
def stick_forced(st, p, lw, fa, fb, om, acc, t_stop):
    """Stick phase: x moves with the belt until the holding force leaves the band
    (exact time) or t_stop."""
    v = p[V]
    t = st[S_T]
    x = st[S_X]
    t1, mode = breakaway_time(t, x, p, lw, fa, fb, om, t_stop)
    dt = t1 - t
    x1 = x + v * dt
    acc[A_IX] += dt * (x + 0.5 * v * dt)
    acc[A_TSTICK] += dt
    acc[A_DT] += dt
    st[S_T] = t1
    st[S_X] = x1
    _note_x(acc, x1, v)
    if mode == codes.STICK:
        return codes.EV_STOP_TIME, codes.OK
    st[S_ZD] = 0.0
    st[S_MODE] = mode
    st[S_ARMED] = 0.0
    return codes.EV_SLIP, codes.OK


# --------------------------------------------------------------- the slides
@kernel
def classify_forced(x, t, s, p, lw, fa, fb, om, ftol):
    """Mode after zdot reached 0 at (x, t) while sliding with sign s, and the event:
    stick while the holding force is in the band (within ``ftol`` [kN] of an edge it
    slides on), else slide on by the sign of the force that exceeds it."""
    r_pos, r_neg = static_limits(p, lw)
    h = load(fa, fb, om, t) - p[K] * x - p[C] * p[V]
    over_pos = h - r_pos            # > 0: the band cannot hold the slider forwards
    over_neg = -r_neg - h           # > 0: ... backwards
    if max(over_pos, over_neg) < -ftol:
        return codes.STICK, codes.EV_STICK
    new = codes.SLIDE_POS if over_pos >= over_neg else codes.SLIDE_NEG
    if new == s:
        return new, codes.EV_ABNORMAL_STOP
    return new, codes.EV_NORMAL_STOP


@kernel
def initial_forced(st, x0, xd0, p, lw, fa, fb, om, o):
    """Fill st for a start (x0, xd0) at t = 0."""
    zd0 = xd0 - p[V]
    st[:] = 0.0
    st[S_X] = x0
    if zd0 > 0.0:
        mode = codes.SLIDE_POS
    elif zd0 < 0.0:
        mode = codes.SLIDE_NEG
    else:
        mode, _ev = classify_forced(x0, 0.0, 0.0, p, lw, fa, fb, om, 0.0)
    st[S_MODE] = mode
    st[S_ZD] = 0.0 if mode == codes.STICK else zd0
    st[S_ARMED] = 1.0 if zd0 != 0.0 else 0.0
    st[S_H] = 0.05 / max(math.sqrt(p[K] / p[M]), om)


@kernel(inline="always")
def _at(x, zd, t, tau, s, p, lw, cf, fa, fb, om, o, ws, vw):
    """The re-stepped state at t + tau (dense output is the stepper itself)."""
    return forced_step(x, zd, t, tau, s, p, lw, cf, fa, fb, om, o, ws, vw[0], vw[1],
                       runtime(False), runtime(False))


@kernel
def _polish(which, x, zd, t, s, p, lw, cf, fa, fb, om, o, ws, vw, lo, hi, sign_lo, guess,
            st):
    """Root in (lo, hi] of a function of the re-stepped state at t + tau (which 0:
    s zdot, 1: xdot, 2: zdot'), whose sign at lo is ``sign_lo``: safeguarded Newton
    from ``guess`` (the step's Hermite cubic's root), bisection where a Newton step
    leaves the bracket, as ``events.polish``. Returns (tau, x, zd)."""
    tau = guess if lo < guess <= hi else 0.5 * (lo + hi)
    x1 = x
    z1 = zd
    for _ in range(60):
        x1, z1, _q, _e = _at(x, zd, t, tau, s, p, lw, cf, fa, fb, om, o, ws, vw)
        st[S_N] += 1.0
        f, df = _value(which, x1, z1, t + tau, s, p, lw, cf, fa, fb, om)
        if f == 0.0:
            break
        if (f > 0.0) == (sign_lo > 0.0):
            lo = tau
        else:
            hi = tau
        if hi - lo <= 2.0 * EPS * hi:
            break
        tn = tau - f / df if df != 0.0 else 0.5 * (lo + hi)
        if not lo < tn < hi:
            tn = 0.5 * (lo + hi)
        if abs(tn - tau) <= 2.0 * EPS * hi:
            tau = tn
            x1, z1, _q, _e = _at(x, zd, t, tau, s, p, lw, cf, fa, fb, om, o, ws, vw)
            st[S_N] += 1.0
            break
        tau = tn
    return tau, x1, z1


@kernel(inline="always")
def _value(which, x, zd, t, s, p, lw, cf, fa, fb, om):
    """The function ``which`` of ``_polish`` and its time derivative."""
    a = forced_accel(x, zd, t, s, p, lw, cf, fa, fb, om)
    if which == 0:
        return s * zd, s * a
    if which == 1:
        return zd + p[V], a
    rate = load_rate(fa, fb, om, t)
    return a, (-p[K] * (zd + p[V]) + field_slope(lw, cf, zd) * a + rate) / p[M]


@kernel
def _cubic_root(g0, g1, d0, d1, ta, tb):
    """The root in [ta, tb] of the Hermite cubic (values g, theta-derivatives d),
    positive at ta, by bisection (a guess for ``_polish``)."""
    for _ in range(40):
        tm = 0.5 * (ta + tb)
        if cubic(g0, g1, d0, d1, tm) > 0.0:
            ta = tm
        else:
            tb = tm
    return 0.5 * (ta + tb)


@kernel
def _extrema(x, zd, t, s, p, lw, cf, fa, fb, om, o, ws, vw, hk, z1, a0, a1, acc, st):
    """Note the extrema of x (x' = 0) and of x' (x'' = 0) inside [0, hk] of the step
    from (x, zd) at t; z1, a1: zdot and zdot' at hk."""
    v = p[V]
    xd0 = zd + v
    xd1 = z1 + v
    if xd0 != 0.0 and (xd0 > 0.0) != (xd1 > 0.0):
        _h, xx, zx = _polish(runtime(1), x, zd, t, s, p, lw, cf, fa, fb, om, o, ws, vw,
                             0.0, hk, xd0, hk * xd0 / (xd0 - xd1), st)
        _note_x(acc, xx, zx + v)
    if a0 != 0.0 and (a0 > 0.0) != (a1 > 0.0):
        _h, xv, zv = _polish(runtime(2), x, zd, t, s, p, lw, cf, fa, fb, om, o, ws, vw,
                             0.0, hk, a0, hk * a0 / (a0 - a1), st)
        _note_x(acc, xv, zv + v)


@kernel
def slide_forced(st, p, lw, fa, fb, om, o, acc, ws, vw, t_stop, measure, track):
    """Integrate the slide until zdot = 0 (then the stop rules) or t_stop."""
    v = p[V]
    s = st[S_MODE]
    cf = constants(p, lw, s)
    k = p[K]
    m = p[M]
    omega = math.sqrt(k / m)
    gtol = TOUCH_FACTOR * o[O_RTOL] * o[O_LV] + 1e3 * EPS * omega * o[O_LX]
    ftol = 1e3 * EPS * (k * o[O_LX] + abs(fa) + abs(fb))
    near = max(gtol, 1e-3 * o[O_LV])
    hmax = 0.5 / max(omega, om)
    while True:
        t = st[S_T]
        if t >= t_stop:
            return codes.EV_STOP_TIME, codes.OK
        if st[S_N] >= o[O_MAX_STEPS]:
            return codes.EV_STOP_TIME, codes.STEP_BUDGET
        x = st[S_X]
        zd = st[S_ZD]
        hb, _a = step_bound(x, zd, s, cf, lw, k, m, v, o[O_RTOL] * o[O_LV])
        h = min(st[S_H], hmax, hb)
        last = t + h >= t_stop
        if last:
            h = t_stop - t
        if h <= EPS * max(abs(t), 1.0):
            if not last:
                return codes.EV_STOP_TIME, codes.STEP_UNDERFLOW
            st[S_T] = t_stop
            return codes.EV_STOP_TIME, codes.OK
        x1, z1, qx, err = forced_step(x, zd, t, h, s, p, lw, cf, fa, fb, om, o, ws, vw[0],
                                      vw[1], measure, track)
        st[S_N] += 1.0
        if not (err <= 1.0):
            st[S_H] = h * (0.2 if not (err < 1e300) else max(0.2, 0.9 * err ** -0.125))
            continue
        st[S_H] = h * min(5.0, max(0.2, 0.9 * (err + 1e-300) ** -0.125))
        if not (abs(x1) < 1e12 * o[O_LX] and abs(z1) < 1e12 * (o[O_LV] + omega * o[O_LX])):
            return codes.EV_STOP_TIME, codes.DIVERGED
        a0 = forced_accel(x, zd, t, s, p, lw, cf, fa, fb, om)
        a1 = forced_accel(x1, z1, t + h, s, p, lw, cf, fa, fb, om)
        g0 = s * zd
        g1 = s * z1
        kind, ta, tb, tc, armed = zd_event(g0, g1, s * a0 * h, s * a1 * h,
                                           st[S_ARMED] > 0.0, near)
        st[S_ARMED] = 1.0 if armed else 0.0
        h_ev = -1.0
        d0 = s * a0 * h
        d1 = s * a1 * h
        if kind == 1:
            tau, xe, ze = _polish(runtime(0), x, zd, t, s, p, lw, cf, fa, fb, om, o, ws, vw,
                                  ta * h, tb * h, 1.0,
                                  _cubic_root(g0, g1, d0, d1, ta, tb) * h, st)
            if s * ze <= gtol:
                h_ev = tau
        if kind == 2 or (kind == 1 and h_ev < 0.0 and s * a0 < 0.0 < s * a1):
            lo = 0.5 * (ta + tc) * h if kind == 2 else 0.0
            hi = 0.5 * (tc + tb) * h if kind == 2 else h
            guess = tc * h if kind == 2 else h * a0 / (a0 - a1)
            tau, xc, zc = _polish(runtime(2), x, zd, t, s, p, lw, cf, fa, fb, om, o, ws, vw,
                                  lo, hi, -s, guess, st)
            if s * zc <= gtol:
                if s * zc < 0.0:        # a double crossing: the first root
                    tau, xc, zc = _polish(runtime(0), x, zd, t, s, p, lw, cf, fa, fb, om, o,
                                          ws, vw, 0.0, tau, 1.0, 0.5 * tau, st)
                h_ev = tau
        if h_ev < 0.0 and armed and 0.0 < g1 <= gtol and g1 < g0:
            h_ev = h                     # the step ends on a touch
        if h_ev >= 0.0:
            return _finish(st, p, lw, fa, fb, om, o, acc, ws, vw, cf, x, zd, t, s, h_ev,
                           a0, ftol, measure, track)
        if measure:
            acc[A_IX] += qx
            _extrema(x, zd, t, s, p, lw, cf, fa, fb, om, o, ws, vw, h, z1, a0, a1, acc, st)
        if track:
            copy_into(vw[0], vw[1])
        acc[A_DT] += h
        st[S_T] = t + h if not last else t_stop
        st[S_X] = x1
        st[S_ZD] = z1
        _note_x(acc, x1, z1 + v)
        if last:
            return codes.EV_STOP_TIME, codes.OK


@kernel
def _finish(st, p, lw, fa, fb, om, o, acc, ws, vw, cf, x, zd, t, s, h_ev, a0, ftol, measure,
            track):
    """Take the partial step to the zdot = 0 event at h_ev and apply the stop rules;
    with ``track``, the variational state passes the switch through its saltation
    matrix: a stick forgets the velocity (its row is zeroed), a stop scales it by
    the ratio of the accelerations after and before (``zdot'+ / zdot'-``)."""
    v = p[V]
    xe, ze, qx, _e = forced_step(x, zd, t, h_ev, s, p, lw, cf, fa, fb, om, o, ws, vw[0],
                                 vw[1], measure, track)
    st[S_N] += 1.0
    ae = forced_accel(xe, 0.0, t + h_ev, s, p, lw, cf, fa, fb, om)
    if measure:
        acc[A_IX] += qx
        _extrema(x, zd, t, s, p, lw, cf, fa, fb, om, o, ws, vw, h_ev, 0.0, a0, ae, acc, st)
    acc[A_DT] += h_ev
    st[S_T] = t + h_ev
    new, ev = classify_forced(xe, st[S_T], s, p, lw, fa, fb, om, ftol)
    if track:
        copy_into(vw[0], vw[1])
        if new == codes.STICK:
            ratio = 0.0
        else:
            sn = float(new)         # a side is a float (st[S_MODE]) at every call
            after = forced_accel(xe, 0.0, st[S_T], sn, p, lw, constants(p, lw, sn), fa,
                                 fb, om)
            ratio = after / ae if ae != 0.0 else 1.0
        vw[0, 2] *= ratio
        vw[0, 3] *= ratio
    st[S_X] = xe
    st[S_ZD] = 0.0
    st[S_MODE] = new
    st[S_ARMED] = 0.0
    if new == codes.STICK:
        acc[A_NSTICK] += 1.0
    else:
        acc[A_NSTOP] += 1.0
    _note_x(acc, xe, v)
    return ev, codes.OK


@kernel
def advance_forced(st, p, lw, fa, fb, om, o, acc, ws, vw, t_stop, measure, track):
    """Advance to the next event or to t_stop; returns (event, status). ``vw[0]``: the
    variational state (advanced when ``track``; a stick leaves it as it is: x moves
    with the belt whatever its start, and the release at the band's edge starts with
    the stick's own velocity and acceleration, so its saltation is the identity)."""
    if st[S_MODE] == codes.STICK:
        return stick_forced(st, p, lw, fa, fb, om, acc, t_stop)
    return slide_forced(st, p, lw, fa, fb, om, o, acc, ws, vw, t_stop, measure, track)
