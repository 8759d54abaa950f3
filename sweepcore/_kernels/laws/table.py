"""A tabulated friction law: a piecewise quintic on each side of zdot = 0.

The Python side (``sweepcore.laws.table``) fits a measured force-speed table, or a
sampled function, with a quintic spline (C4: F, F', F'' and F''' continuous, so the
Hopf speeds, the first Lyapunov coefficient and the equilibrium certificate are all
defined) and hands the kernels its piecewise-polynomial form: on the piece
``[x_i, x_{i+1}]`` of a branch, ``F(s) = sum_j c_ij (s - x_i)^j``, j = 0..5. Past the
outermost speed of a branch the law continues linearly with the end's value and
slope (C1), as Modelica's friction tables extrapolate.

Every table is data of the same numba type (``Table``): a new table compiles
nothing. Fields (float64 arrays):

* ``pos_x`` (n+1), ``pos_c`` (n, 6), ``pos_dmin`` (n), ``pos_d2`` (n): the branch
  s >= 0 (from ``pos_x[0] = 0``), its coefficients, and on each piece the least F'
  and the largest |F''|;
* ``neg_x``, ``neg_c``, ``neg_dmin``, ``neg_d2``: the branch s <= 0 (to
  ``neg_x[-1] = 0``); for
  a law odd in s they are not used: ``F(s) = -F(-s)`` is evaluated on the positive
  branch, so that the mirror image v -> -v is exact;
* ``info`` (3): the static limits ``(r_pos, r_neg)`` [kN] and 1 for an odd law.
"""
from collections import namedtuple

import numpy as np

from ..jit import kernel
from ..layout import C, V

Table = namedtuple("Table", ("pos_x", "pos_c", "pos_dmin", "pos_d2", "neg_x", "neg_c",
                             "neg_dmin", "neg_d2", "info"))


@kernel(inline="always")
def _piece(x, s):
    """Index i of the piece with ``x[i] <= s < x[i+1]``; -1 below x[0], n past x[n]."""
    n = x.shape[0] - 1
    if s < x[0]:
        return -1
    if s >= x[n]:
        return n
    lo = 0
    hi = n
    while hi - lo > 1:
        mid = (lo + hi) >> 1
        if s < x[mid]:
            hi = mid
        else:
            lo = mid
    return lo


@kernel
def _value(x, c, s):
    """``(F, F', F'', F''')`` of one branch at s (linear past its ends)."""
    n = x.shape[0] - 1
    i = _piece(x, s)
    out = i < 0 or i >= n
    if out:
        j = 0 if i < 0 else n - 1
        t = x[0] - x[j] if i < 0 else x[n] - x[j]
    else:
        j = i
        t = s - x[i]
    f = c[j, 0] + t * (c[j, 1] + t * (c[j, 2] + t * (c[j, 3] + t * (c[j, 4]
                                                                  + t * c[j, 5]))))
    d1 = c[j, 1] + t * (2.0 * c[j, 2] + t * (3.0 * c[j, 3] + t * (4.0 * c[j, 4]
                                                                  + t * 5.0 * c[j, 5])))
    if out:
        return f + d1 * (s - (x[0] if i < 0 else x[n])), d1, 0.0, 0.0
    d2 = 2.0 * c[j, 2] + t * (6.0 * c[j, 3] + t * (12.0 * c[j, 4] + t * 20.0 * c[j, 5]))
    d3 = 6.0 * c[j, 3] + t * (24.0 * c[j, 4] + t * 60.0 * c[j, 5])
    return f, d1, d2, d3


@kernel
def _force_value(x, c, s):
    """F of one branch at s, by Horner's rule (the sliding field's hot path)."""
    n = x.shape[0] - 1
    i = _piece(x, s)
    if i < 0 or i >= n:
        return _value(x, c, s)[0]
    t = s - x[i]
    return c[i, 0] + t * (c[i, 1] + t * (c[i, 2] + t * (c[i, 3] + t * (c[i, 4]
                                                                      + t * c[i, 5]))))


@kernel(inline="always")
def force(lw, cf, zd, s):
    if zd > 0.0 or (zd == 0.0 and s > 0.0):
        return _force_value(lw.pos_x, lw.pos_c, zd)
    if lw.info[2] > 0.0:                         # odd: F(s) = -F(-s)
        return -_force_value(lw.pos_x, lw.pos_c, -zd)
    return _force_value(lw.neg_x, lw.neg_c, zd)


@kernel(inline="always")
def derivatives(p, lw, zd):
    if zd > 0.0:
        _f, d1, d2, d3 = _value(lw.pos_x, lw.pos_c, zd)
        return d1, d2, d3
    if lw.info[2] > 0.0:
        _f, d1, d2, d3 = _value(lw.pos_x, lw.pos_c, -zd)
        return d1, -d2, d3
    _f, d1, d2, d3 = _value(lw.neg_x, lw.neg_c, zd)
    return d1, d2, d3


@kernel(inline="always")
def static_limits(p, lw):
    return lw.info[0], lw.info[1]


@kernel
def _branch_bound(x, c, dmin, d2, lo, hi):
    """Least F' of one branch over [lo, hi]: on each piece that meets it, the larger
    of the piece's least F' and the value at the middle of the overlap less the
    largest |F''| times half its width (mean value theorem: tight for a narrow
    interval, such as a small motion about the equilibrium); past the ends the end
    slope."""
    n = x.shape[0] - 1
    least = np.inf
    if lo < x[0]:
        least = min(least, _value(x, c, x[0])[1])
    if hi > x[n]:
        least = min(least, _value(x, c, x[n])[1])
    i0 = max(_piece(x, lo), 0)
    i1 = min(_piece(x, hi), n - 1)
    for i in range(i0, i1 + 1):
        a = max(lo, x[i])
        b = min(hi, x[i + 1])
        local = _value(x, c, 0.5 * (a + b))[1] - 0.5 * (b - a) * d2[i]
        least = min(least, max(dmin[i], local))
    return least


@kernel
def slope_bound(p, lw, lo, hi):
    least = np.inf
    if hi > 0.0:
        least = _branch_bound(lw.pos_x, lw.pos_c, lw.pos_dmin, lw.pos_d2, max(lo, 0.0),
                              hi)
    if lo < 0.0:
        if lw.info[2] > 0.0:                     # odd: F'(s) = F'(-s)
            b = _branch_bound(lw.pos_x, lw.pos_c, lw.pos_dmin, lw.pos_d2, max(-hi, 0.0),
                              -lo)
        else:
            b = _branch_bound(lw.neg_x, lw.neg_c, lw.neg_dmin, lw.neg_d2, lo,
                              min(hi, 0.0))
        least = min(least, b)
    return least


@kernel(inline="always")
def _sample(x, k, up):
    """The k-th of 16 samples a piece of the branch x, in increasing |s|: from
    x[0] = 0 up (``up``), or from x[n] = 0 down."""
    n = x.shape[0] - 1
    if up:
        i = min(k // 16, n - 1)
        return x[i] + (x[i + 1] - x[i]) * ((k - 16 * i) / 16.0)
    i = max(n - 1 - k // 16, 0)
    return x[i + 1] - (x[i + 1] - x[i]) * ((k - 16 * (n - 1 - i)) / 16.0)


@kernel
def hopf_speeds(p, lw):
    """Roots u of ``c + F'(-u)`` (u with the sign of v) over the branch steady
    sliding uses: 16 samples of each piece (F' is a quartic there), refined by
    bisection; past the table F' is the end slope (constant: no further root)."""
    up = p[V] < 0.0 or lw.info[2] > 0.0   # the s >= 0 branch (odd: F'(-u) = F'(u))
    x = lw.pos_x if up else lw.neg_x
    c = lw.pos_c if up else lw.neg_c
    n = x.shape[0] - 1
    found = 0
    r1 = np.nan
    r2 = np.nan
    u_prev = 0.0
    g_prev = 0.0
    for k in range(16 * n + 1):
        s_ = _sample(x, k, up)
        g = p[C] + _value(x, c, s_)[1]
        if k > 0 and (g < 0.0) != (g_prev < 0.0):
            r = _bisect(x, c, p[C], u_prev, abs(s_), g_prev < 0.0, up)
            if found == 0:
                r1 = r
            elif found == 1:
                r2 = r
            found += 1
        u_prev = abs(s_)
        g_prev = g
    if found == 0:
        return 0, (np.inf if g_prev < 0.0 else np.nan), np.nan
    return found, r1, r2


@kernel
def _bisect(x, c, damping, lo, hi, rising, up):
    """Speed u in [lo, hi] where ``c + F'`` at ``s = u`` (up) or ``-u`` changes sign
    (rising: - to +)."""
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if (damping + _value(x, c, mid if up else -mid)[1] < 0.0) == rising:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@kernel(inline="always")
def speed_range(p, lw):
    x = lw.pos_x
    return 1e-9 * x[x.shape[0] - 1], x[x.shape[0] - 1]
