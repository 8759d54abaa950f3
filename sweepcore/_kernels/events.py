"""Locating events inside one sliding step: where zdot = 0, where x or xdot turn.

The step's Hermite cubic of ``g = s zdot`` (values and ``zdd`` at both ends) is
split at its critical points into monotone pieces (``zd_event``), so two crossings
inside one step and a touch between two samples are both seen (a sign test at the
step's ends sees neither). A root is then polished by safeguarded Newton
(``polish``) on the step's continuous extension (dop853, dopri5) or on re-steps of
the integrator (the fixed-step methods); the driver then takes the integrator's own
state at the root (``driver.py``).
"""
import math

import numpy as np

from .jit import kernel

from .law import zdd, zddd
from .layout import V
from .stepper import state_at

EPS = np.finfo(np.float64).eps

# functions whose roots are polished on re-steps. Floats, not ints: numba types an
# int constant as a literal and would compile ``polish`` once per value, with every
# branch of ``_fun`` in each copy; a float is an ordinary argument.
F_ZD = 0.0
F_XD = 1.0
F_ZDD = 2.0


@kernel(inline="always")
def _fun(which, x, zd, s, p, lw):
    v = p[V]
    if which == F_ZD:
        return zd, zdd(x, zd, s, p, lw)
    if which == F_XD:
        return zd + v, zdd(x, zd, s, p, lw)
    return zdd(x, zd, s, p, lw), zddd(x, zd, s, p, lw, v)


@kernel
def polish(meth, which, x, zd, s, p, lw, o, lo, hi, sign_lo, guess, st, dc, H):
    """Root in (lo, hi] of F(h) = fun(state at h into the step H from (x, zd));
    F(lo) has sign ``sign_lo``. The state is the interpolant ``dc`` of the step
    where the method has one, else a re-step (``stepper.state_at``).

    Safeguarded Newton: Newton steps inside the bracket, bisection otherwise.
    Returns (h, x1, zd1).
    """
    h = guess if lo < guess <= hi else 0.5 * (lo + hi)
    x1 = x
    z1 = zd
    for _ in range(60):
        x1, z1 = state_at(meth, x, zd, h, s, p, lw, o, dc, H, st)
        f, df = _fun(which, x1, z1, s, p, lw)
        if f == 0.0:
            break
        if (f > 0.0) == (sign_lo > 0.0):
            lo = h
        else:
            hi = h
        if hi - lo <= 2.0 * EPS * hi:
            break
        hn = h - f / df if df != 0.0 else 0.5 * (lo + hi)
        if not (lo < hn < hi):
            hn = 0.5 * (lo + hi)
        if abs(hn - h) <= 2.0 * EPS * hi:
            h = hn
            x1, z1 = state_at(meth, x, zd, h, s, p, lw, o, dc, H, st)
            break
        h = hn
    return h, x1, z1


@kernel(inline="always")
def cubic(f0, f1, d0, d1, th):
    """Cubic Hermite interpolant on [0, 1] (values f, theta-derivatives d)."""
    a = 2.0 * (f0 - f1) + d0 + d1
    b = 3.0 * (f1 - f0) - 2.0 * d0 - d1
    return ((a * th + b) * th + d0) * th + f0


@kernel
def _critical(f0, f1, d0, d1):
    """Critical points in (0, 1) of the Hermite cubic, sorted; (n, t1, t2)."""
    a = 3.0 * (2.0 * (f0 - f1) + d0 + d1)
    b = 2.0 * (3.0 * (f1 - f0) - 2.0 * d0 - d1)
    c = d0
    r1 = -1.0
    r2 = -1.0
    scale = abs(a) + abs(b) + abs(c)
    if scale == 0.0:
        return 0, 0.0, 0.0
    if abs(a) <= 1e-14 * scale:
        if b != 0.0:
            r1 = -c / b
    else:
        disc = b * b - 4.0 * a * c
        if disc >= 0.0:
            sq = math.sqrt(disc)
            q = -0.5 * (b + (sq if b >= 0.0 else -sq))
            if q != 0.0:
                r1 = q / a
                r2 = c / q
            else:
                r1 = -b / (2.0 * a)
    if r1 > r2:
        r1, r2 = r2, r1
    n = 0
    t1 = 0.0
    t2 = 0.0
    for r in (r1, r2):
        if 0.0 < r < 1.0:
            if n == 0:
                t1 = r
            else:
                t2 = r
            n += 1
    return n, t1, t2



@kernel
def zd_event(g0, g1, d0, d1, armed, near):
    """Scan the Hermite cubic of g = s zdot over a step.

    Returns (kind, th_a, th_b, th_c, armed): kind 0 nothing, 1 crossing bracketed
    in [th_a, th_b], 2 a turning point th_c (local min of g, bracketed by th_a, th_b)
    whose value is within ``near`` of 0 and must be checked on the integrator.
    """
    # The cubic is linear interpolation plus th (1 - th) [A (1 - th) - B th] with
    # A = d0 - (g1 - g0), B = d1 - (g1 - g0): it stays above min(g0, g1) - max|A, B|/4.
    # When that bound is above `near` nothing can be found: skip the scan.
    dg = g1 - g0
    if armed and min(g0, g1) - 0.25 * max(abs(d0 - dg), abs(d1 - dg)) > near:
        return 0, 0.0, 0.0, 0.0, armed
    n, c1, c2 = _critical(g0, g1, d0, d1)
    # candidate points 0 < critical points < 1; g is monotone between neighbours
    if n == 0:
        pts = (0.0, 1.0, 1.0, 1.0)
    elif n == 1:
        pts = (0.0, c1, 1.0, 1.0)
    else:
        pts = (0.0, c1, c2, 1.0)
    k = n + 2
    start = 0
    if not armed:
        # A start on the switching line (g0 = 0) is never itself an event: skip to
        # the first interior maximum of g (zdot turning back towards 0).
        start = -1
        if g0 > 0.0 and d0 <= 0.0:
            start = 0
        else:
            a = 2.0 * (g0 - g1) + d0 + d1
            b = 3.0 * (g1 - g0) - 2.0 * d0 - d1
            for i in range(1, k - 1):
                th = pts[i]
                if 6.0 * a * th + 2.0 * b < 0.0 and cubic(g0, g1, d0, d1, th) > 0.0:
                    start = i
                    break
        if start < 0:
            return 0, 0.0, 0.0, 0.0, g1 > 0.0 and d1 <= 0.0
        armed = True
    for i in range(start, k - 1):
        ta = pts[i]
        tb = pts[i + 1]
        gb = cubic(g0, g1, d0, d1, tb)
        if tb == 1.0:
            gb = g1
        if gb <= 0.0:
            return 1, ta, tb, 0.0, armed
        if i + 1 < k - 1 and gb <= near:
            a = 2.0 * (g0 - g1) + d0 + d1
            b = 3.0 * (g1 - g0) - 2.0 * d0 - d1
            if 6.0 * a * tb + 2.0 * b > 0.0:       # local minimum of g
                return 2, ta, pts[i + 2], tb, armed
    return 0, 0.0, 0.0, 0.0, armed
