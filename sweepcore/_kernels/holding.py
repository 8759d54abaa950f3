"""The stick under a periodic load: when the holding force leaves the static band.

While stuck (x' = v) the force that holds the slider is

    h(t) = e(t) - k x(t) - c v,      x(t) = x_0 + v (t - t_0),

with e the load (``trig.py``). The stick holds while ``-r_neg <= h <= r_pos`` (the
law's static limits) and ends at the first time h leaves that band: slip forwards
(zdot > 0) above r_pos, backwards below -r_neg (eq. 27 is the case e = 0). That time
is found exactly: h is cut into monotone pieces at the roots of ``h' = e'(t) - k v``
(the *critical phases*, found once per point over one period), the first piece whose
end lies outside the band holds the one crossing, bracketed, so no short excursion
of the load is stepped over; a piece that only touches the band's edge (a tangency)
continues the stick.

The critical phases cannot be missed: on an interval [a, b] a root of g = h' needs
``|g(a)| + |g(b)| <= M2 (b - a)``, M2 a bound of |g'| = |e''| (``trig.bound``); where
that fails the interval holds none. Where ``|g'(m)| > M3 (b - a)/2`` at its middle
(M3 a bound of |e'''|), g is monotone there and a sign change holds exactly one root,
solved to rounding; other intervals are halved. An interval that neither test settles
by 1e-9 of the period (g touching 0: a double root) is cut at its middle, which never
harms (a cut only splits a monotone piece).
"""
import math

import numpy as np

from . import codes
from .jit import kernel, runtime
from .law import static_limits
from .layout import C, K, V
from .trig import XC_HEAD, XC_N, XC_NCRIT, XC_PERIOD, bound, crit_at, derivative

EPS = np.finfo(np.float64).eps
GRID = 4              # first intervals per harmonic
FLOOR = 1e-9          # the smallest interval, of the period


@kernel
def critical_phases(xc, kv):
    """The roots of ``g(t) = e'(t) - kv`` in [0, T) into xc (sorted, count at
    XC_NCRIT; module docstring). Returns False where more than the space allows
    were found (never for a trigonometric polynomial: at most 2 N roots)."""
    T = xc[XC_PERIOD]
    n_h = int(xc[XC_N])
    at = crit_at(xc)
    room = 4 * n_h + 8
    m2 = bound(xc, runtime(2))
    m3 = bound(xc, runtime(3))
    if not m2 > 0.0:                    # no load (a load and an anchor that cancel)
        xc[XC_NCRIT] = 0
        return True
    n_grid = GRID * n_h + 4
    cap = n_grid + 128
    sa = np.empty(cap)
    sb = np.empty(cap)
    top = 0
    for i in range(n_grid - 1, -1, -1):     # the stack holds the first intervals
        sa[top] = T * i / n_grid
        sb[top] = T * (i + 1) / n_grid
        top += 1
    found = 0
    while top > 0:
        top -= 1
        a = sa[top]
        b = sb[top]
        ga = derivative(xc, a, runtime(1)) - kv
        gb = derivative(xc, b, runtime(1)) - kv
        w = b - a
        if abs(ga) + abs(gb) > m2 * w:
            continue                        # no root
        m = 0.5 * (a + b)
        root = np.nan
        if abs(derivative(xc, m, runtime(2))) > 0.5 * m3 * w:
            if (ga > 0.0) != (gb > 0.0) or ga == 0.0:
                root = _trig_root(xc, runtime(1), kv, 0.0, 0.0, a, b)
        elif w <= FLOOR * T or top + 2 > cap:
            root = m                        # a double root or a near miss: a cut
        else:
            sa[top] = m
            sb[top] = b
            sa[top + 1] = a
            sb[top + 1] = m
            top += 2
        if root == root and root < T:
            if found == room:
                return False
            xc[at + found] = root
            found += 1
    _sort(xc, at, found)
    xc[XC_NCRIT] = found
    return True


@kernel
def _trig_root(xc, d, a0, a1, t0, lo, hi):
    """The one root in [lo, hi] of ``f(t) = e^(d)(t) - a0 - a1 (t - t0)`` (d = 0: the
    holding force at a level; d = 1: h'), where f changes sign once: safeguarded
    Newton (f' = e^(d+1) - a1), bisection where a step leaves the bracket, to the
    resolution of t (the bracket's width, or Newton's step: converging from one
    side, Newton never narrows the bracket)."""
    flo = derivative(xc, lo, d) - a0 - a1 * (lo - t0)
    t = 0.5 * (lo + hi)
    for _ in range(100):
        f = derivative(xc, t, d) - a0 - a1 * (t - t0)
        if f == 0.0:
            return t
        if (f > 0.0) == (flo > 0.0):
            lo = t
        else:
            hi = t
        if hi - lo <= 4.0 * EPS * max(abs(hi), 1.0):
            break
        df = derivative(xc, t, d + 1) - a1
        tn = t - f / df if df != 0.0 else 0.5 * (lo + hi)
        if not lo < tn < hi:
            tn = 0.5 * (lo + hi)
        elif abs(tn - t) <= 2.0 * EPS * max(abs(t), 1.0):
            return tn                       # Newton's step below the resolution of t
        t = tn
    return 0.5 * (lo + hi)


@kernel
def _sort(xc, at, n):
    """Insertion sort of xc[at:at + n]."""
    for i in range(at + 1, at + n):
        key = xc[i]
        j = i - 1
        while j >= at and xc[j] > key:
            xc[j + 1] = xc[j]
            j -= 1
        xc[j + 1] = key


@kernel
def next_cut(xc, a):
    """The first critical time after a [s] (half a period on when h is monotone)."""
    T = xc[XC_PERIOD]
    n = int(xc[XC_NCRIT])
    if n == 0:
        return a + 0.5 * T
    at = crit_at(xc)
    j = math.floor(a / T)
    for _ in range(3):
        base = j * T
        for i in range(n):
            tc = base + xc[at + i]
            if tc > a:
                return tc
        j += 1.0
    return a + 0.5 * T


@kernel(inline="always")
def holding(xc, t, t0, x0, p):
    """The force h(t) [kN] that holds a slider stuck since (t0, x0)."""
    return derivative(xc, t, runtime(0)) - p[K] * (x0 + p[V] * (t - t0)) - p[C] * p[V]


@kernel
def trig_exit(xc, t0, x0, p, lw, t_stop):
    """``(dt, slips, mode, x_slip)``: the duration of the stick entered at (t0, x0)
    until the holding force leaves the band or t_stop, whether it ends in a slip,
    the slide it starts and the position there (module docstring)."""
    r_pos, r_neg = static_limits(p, lw)
    v = p[V]
    h0 = holding(xc, t0, t0, x0, p)
    if h0 > r_pos:
        return 0.0, True, codes.SLIDE_POS, x0
    if h0 < -r_neg:
        return 0.0, True, codes.SLIDE_NEG, x0
    a = t0
    T = xc[XC_PERIOD]
    while True:
        b = min(next_cut(xc, a), t_stop)
        hb = holding(xc, b, t0, x0, p)
        if hb > r_pos or hb < -r_neg:
            up = hb > r_pos
            # h(t) = e(t) - k x0 - c v - k v (t - t0) at the level
            level = (r_pos if up else -r_neg) + p[K] * x0 + p[C] * v
            tb = _trig_root(xc, runtime(0), level, p[K] * v, t0, a, b)
            return (tb - t0, True, codes.SLIDE_POS if up else codes.SLIDE_NEG,
                    x0 + v * (tb - t0))
        if b >= t_stop or (v == 0.0 and b - t0 > T):
            # held to t_stop (on a still belt h is periodic: held over a whole
            # period, it holds for ever)
            return t_stop - t0, False, codes.STICK, x0 + v * (t_stop - t0)
        a = b
