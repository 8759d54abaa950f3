"""A tabulated friction law: a piecewise quintic on each side of zdot = 0.

The Python side (``sweepcore.laws.table``) represents a measured force-speed table,
or a sampled function, by a shape-preserving quintic Hermite spline (C2: F, F' and
F'' continuous, F''' defined on each piece, so the Hopf speeds, the first Lyapunov
coefficient and the equilibrium certificate are all defined) and hands the kernels
its piecewise-polynomial form: on the piece ``[x_i, x_{i+1}]`` of a branch,
``F(s) = sum_j c_ij (s - x_i)^j``, j = 0..5. Past the outermost speed of a branch
the end force is held (the spline ends there with zero slope and curvature: C2;
that speed is the end of the runout piece the Python side puts after the table).

Every table is data of the same numba type (``Table``, one float64 array ``d``):
a new table compiles nothing. One array rather than one per field: the law data is
an argument of nearly every kernel, and numba passes an array as seven words, nine
arrays as sixty-three (measured: a table law of nine arrays cost 7x the analytic
law per point, of one array ``benchmarks/laws.py`` gives). ``d`` holds

* ``d[:HEAD]``: the number of pieces of the branch s >= 0 and of the branch s <= 0,
  the static limits ``(r_pos, r_neg)`` [kN], and 1 for a law odd in s;
* then each branch (``pack``): its n + 1 breakpoints (from 0 up for s >= 0, up to
  0 for s <= 0), its (n, 6) coefficients row by row, and on each piece a lower
  bound of F' and an upper bound of |F''|. A law odd in s does not use its branch s <= 0:
  ``F(s) = -F(-s)`` is evaluated on the positive branch, so that the mirror image
  v -> -v is exact.

A branch is addressed as ``(b, n)``: the offset of its block in ``d`` and its number
of pieces.
"""
from collections import namedtuple

import numpy as np

from ..jit import kernel, runtime, unowned
from ..law import damping_root
from ..layout import C, V

Table = namedtuple("Table", ("d",))
HEAD = 5
# the branch helpers below take the branch's offset and side as runtime(HEAD),
# runtime(True): as literals each would compile them once more (jit.runtime)


def pack(pos, neg, r_pos: float, r_neg: float, odd: bool) -> np.ndarray:
    """The array ``d`` of a table from its branches ``(x, c, dmin, d2)`` (Python)."""
    parts = [np.array([len(pos[0]) - 1, len(neg[0]) - 1, r_pos, r_neg,
                       1.0 if odd else 0.0], np.float64)]
    for x, c, dmin, d2 in (pos, neg):
        parts += [x, np.ravel(c), dmin, d2]
    return np.ascontiguousarray(np.concatenate(parts), np.float64)


@kernel(inline="always")
def _branch(d, up):
    """``(b, n)`` of the branch s >= 0 (``up``) or s <= 0."""
    n_pos = int(d[0])
    if up:
        return HEAD, n_pos
    return HEAD + 9 * n_pos + 1, int(d[1])


@kernel(inline="always")
def _piece(d, b, n, s):
    """Index i of the piece with ``x[i] <= s < x[i+1]``; -1 below x[0], n past x[n]."""
    if s < d[b]:
        return -1
    if s >= d[b + n]:
        return n
    lo = 0
    hi = n
    while hi - lo > 1:
        mid = (lo + hi) >> 1
        if s < d[b + mid]:
            hi = mid
        else:
            lo = mid
    return lo


@kernel(inline="always")
def _poly(d, k, t):
    """``(F, F', F'', F''')`` of the quintic with coefficients ``d[k:k+6]`` at t."""
    f = d[k] + t * (d[k + 1] + t * (d[k + 2] + t * (d[k + 3] + t * (d[k + 4]
                                                                  + t * d[k + 5]))))
    d1 = d[k + 1] + t * (2.0 * d[k + 2] + t * (3.0 * d[k + 3] + t * (
        4.0 * d[k + 4] + t * 5.0 * d[k + 5])))
    d2 = 2.0 * d[k + 2] + t * (6.0 * d[k + 3] + t * (12.0 * d[k + 4]
                                                     + t * 20.0 * d[k + 5]))
    d3 = 6.0 * d[k + 3] + t * (24.0 * d[k + 4] + t * 60.0 * d[k + 5])
    return f, d1, d2, d3


@kernel
def _value(d, b, n, s, up):
    """``(F, F', F'', F''')`` at s of the branch s >= 0 (``up``) or s <= 0.

    Past the branch's far end (|s| beyond the table) the end force is held.
    Past its end at zero speed, where only the last stages of a slide go (they may
    overshoot zdot = 0), F continues as its cubic Taylor polynomial there (C3): the
    field of a slide stays smooth and bounded (the quintic of a short first piece
    is not)."""
    i = _piece(d, b, n, s)
    c = b + n + 1                                    # the coefficients' offset
    if (i >= n) if up else (i < 0):
        j = n - 1 if up else 0
        end = d[b + n] if up else d[b]
        return _poly(d, c + 6 * j, end - d[b + j])[0], 0.0, 0.0, 0.0
    if (i < 0) if up else (i >= n):
        j = 0 if up else n - 1
        zero = d[b] if up else d[b + n]
        f, d1, d2, d3 = _poly(d, c + 6 * j, zero - d[b + j])
        u = s - zero
        return (f + u * (d1 + u * (0.5 * d2 + u * d3 / 6.0)),
                d1 + u * (d2 + 0.5 * u * d3), d2 + u * d3, d3)
    return _poly(d, c + 6 * i, s - d[b + i])


@kernel
def _force_value(d, b, n, s, up):
    """F at s of one branch, by Horner's rule (the sliding field's hot path)."""
    i = _piece(d, b, n, s)
    if i < 0 or i >= n:
        return _value(d, b, n, s, up)[0]
    t = s - d[b + i]
    k = b + n + 1 + 6 * i
    return d[k] + t * (d[k + 1] + t * (d[k + 2] + t * (d[k + 3] + t * (d[k + 4]
                                                                      + t * d[k + 5]))))


@kernel(inline="always")
def borrowed(lw):
    return Table(unowned(lw.d))


@kernel(inline="always")
def force(lw, cf, zd, s):
    """The branch of the slide's sign s (of zd where s = 0), as the analytic law:
    the field of one slide stays smooth where its last stages overshoot zd = 0."""
    d = lw.d
    if s > 0.0 or (s == 0.0 and zd > 0.0):
        return _force_value(d, runtime(HEAD), int(d[0]), zd, runtime(True))
    if d[4] > 0.0:                               # odd: F(s) = -F(-s)
        return -_force_value(d, runtime(HEAD), int(d[0]), -zd, runtime(True))
    b, n = _branch(d, False)
    return _force_value(d, b, n, zd, runtime(False))


@kernel(inline="always")
def derivatives(p, lw, zd):
    d = lw.d
    if zd > 0.0:
        _f, d1, d2, d3 = _value(d, runtime(HEAD), int(d[0]), zd, runtime(True))
        return d1, d2, d3
    if d[4] > 0.0:
        _f, d1, d2, d3 = _value(d, runtime(HEAD), int(d[0]), -zd, runtime(True))
        return d1, -d2, d3
    b, n = _branch(d, False)
    _f, d1, d2, d3 = _value(d, b, n, zd, runtime(False))
    return d1, d2, d3


@kernel(inline="always")
def branch_derivatives(p, lw, zd, s):
    d = lw.d
    if s > 0.0 or (s == 0.0 and zd > 0.0):
        _f, d1, d2, _d3 = _value(d, runtime(HEAD), int(d[0]), zd, runtime(True))
        return d1, d2
    if d[4] > 0.0:                               # odd: F(s) = -F(-s)
        _f, d1, d2, _d3 = _value(d, runtime(HEAD), int(d[0]), -zd, runtime(True))
        return d1, -d2
    b, n = _branch(d, False)
    _f, d1, d2, _d3 = _value(d, b, n, zd, runtime(False))
    return d1, d2


@kernel(inline="always")
def anti_damped(p, lw):
    """Past the table the end force is held: the damping at high speed is c plus the
    slope at each branch's far end (0: the spline ends flat)."""
    d = lw.d
    n = int(d[0])
    far = _value(d, runtime(HEAD), n, d[HEAD + n], runtime(True))[1]
    if d[4] > 0.0:
        other = far
    else:
        b, m = _branch(d, False)
        other = _value(d, b, m, d[b], runtime(False))[1]
    return p[C] + far < 0.0 and p[C] + other < 0.0


@kernel(inline="always")
def static_limits(p, lw):
    return lw.d[2], lw.d[3]


@kernel
def _branch_bound(d, b, n, lo, hi, up):
    """Least F' of one branch over [lo, hi]: on each piece that meets it, the larger
    of the piece's least F' and the value at the middle of the overlap less the
    largest |F''| times half its width (mean value theorem: tight for a narrow
    interval, such as a small motion about the equilibrium); past the ends the end
    slope."""
    dmin = b + 7 * n + 1                 # offsets of the least F' and largest |F''|
    d2 = dmin + n
    least = np.inf
    if lo < d[b]:
        least = min(least, _value(d, b, n, d[b], up)[1])
    if hi > d[b + n]:
        least = min(least, _value(d, b, n, d[b + n], up)[1])
    i0 = max(_piece(d, b, n, lo), 0)
    i1 = min(_piece(d, b, n, hi), n - 1)
    for i in range(i0, i1 + 1):
        a = max(lo, d[b + i])
        e = min(hi, d[b + i + 1])
        local = _value(d, b, n, 0.5 * (a + e), up)[1] - 0.5 * (e - a) * d[d2 + i]
        least = min(least, max(d[dmin + i], local))
    return least


@kernel
def slope_bound(p, lw, lo, hi):
    d = lw.d
    least = np.inf
    if hi > 0.0:
        least = _branch_bound(d, runtime(HEAD), int(d[0]), max(lo, 0.0), hi,
                              runtime(True))
    if lo < 0.0:
        if d[4] > 0.0:                           # odd: F'(s) = F'(-s)
            other = _branch_bound(d, runtime(HEAD), int(d[0]), max(-hi, 0.0), -lo,
                                  runtime(True))
        else:
            b, n = _branch(d, False)
            other = _branch_bound(d, b, n, lo, min(hi, 0.0), runtime(False))
        least = min(least, other)
    return least


@kernel(inline="always")
def _sample(d, b, n, k, up):
    """The k-th of 16 samples a piece of the branch, in increasing |s|: from
    x[0] = 0 up (``up``), or from x[n] = 0 down."""
    if up:
        i = min(k // 16, n - 1)
        return d[b + i] + (d[b + i + 1] - d[b + i]) * ((k - 16 * i) / 16.0)
    i = max(n - 1 - k // 16, 0)
    return d[b + i + 1] - (d[b + i + 1] - d[b + i]) * ((k - 16 * (n - 1 - i)) / 16.0)


@kernel
def hopf_speeds(p, lw):
    """Roots u of ``c + F'(-u)`` (u with the sign of v) over the branch steady
    sliding uses: 16 samples of each piece (F' is a quartic there), refined by
    bisection; past the table F' = 0 (the end force held: no further root)."""
    d = lw.d
    up = p[V] < 0.0 or d[4] > 0.0        # the s >= 0 branch (odd: F'(-u) = F'(u))
    b, n = _branch(d, up)
    found = 0
    r1 = np.nan
    r2 = np.nan
    u_prev = 0.0
    g_prev = 0.0
    for k in range(16 * n + 1):
        s_ = _sample(d, b, n, k, up)
        g = p[C] + _value(d, b, n, s_, up)[1]
        if k > 0 and (g < 0.0) != (g_prev < 0.0):
            r = damping_root(p, lw, u_prev, abs(s_), g_prev < 0.0)
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


@kernel(inline="always")
def speed_range(p, lw):
    end = lw.d[HEAD + int(lw.d[0])]
    return 1e-9 * end, end


# ------------------------------------------------------------ the step at a knot
CROSS_SAFETY = 0.1    # of the velocity tolerance, the error a knot's crossing may add


@kernel
def _third(d, b, n, j, right):
    """F''' at knot j of a branch, from the piece on its right (``right``) or left;
    0 beyond the branch (the end force held past the far end; below zero speed the
    cubic continuation has the end piece's F''' there, so no jump: same value)."""
    c = b + n + 1
    if right:
        if j >= n:
            return 0.0
        return 6.0 * d[c + 6 * j + 3]
    if j <= 0:
        return 0.0
    h = d[b + j] - d[b + j - 1]
    return _poly(d, c + 6 * (j - 1), h)[3]


@kernel
def _knot_ahead(d, b, n, u, du, up):
    """``(distance, |jump of F'''|)`` of the next breakpoint of a branch that u
    reaches moving with sign du (inf, 0 for none). At the far end F''' jumps to 0
    (the held force); at the zero end it does not (the cubic continuation)."""
    i = _piece(d, b, n, u)
    if du > 0.0:
        j = i + 1
    elif i >= 0 and u > d[b + min(i, n)]:
        j = min(i, n)
    else:
        j = i - 1
    if j < 0 or j > n:
        return np.inf, 0.0
    zero_end = (j == 0) if up else (j == n)
    if zero_end:
        return abs(d[b + j] - u), 0.0
    return abs(d[b + j] - u), abs(_third(d, b, n, j, runtime(True))
                                  - _third(d, b, n, j, runtime(False)))


@kernel(inline="always")
def step_bound(x, zd, s, cf, lw, k, m, v, dz):
    """The generic bound (``law.step_bound``: the instability's rate, and the
    layer of the slope's own width), and a knot's: F''' jumps at the breakpoints
    (C2 pieces), so the fourth time derivative of zdot jumps by ``dF''' zdd^3 / m``
    there, a local error ``~ dF''' |zdd|^3 h^4 / (24 m)`` the steppers' error
    estimates (which assume a smooth field) do not weigh. A step either stops
    short of the next knot (half the time zdd needs to reach it) or crosses it
    short enough that this error is ``CROSS_SAFETY`` of the velocity tolerance
    ``dz``."""
    f1, f2 = branch_derivatives(cf[3], lw, zd, s)
    lam = -(cf[1] + f1) / m
    h = np.inf
    if lam > 0.0:
        drop = f1 * f1 / abs(f2) if f2 != 0.0 else np.inf
        h = max(1.0 / lam, m * dz / drop)
    a = (-k * x - force(lw, cf, zd, s) - cf[1] * (zd + cf[2])) / m
    if a == 0.0:
        return h, a
    d = lw.d
    if s > 0.0 or (s == 0.0 and zd > 0.0):
        dist, jump = _knot_ahead(d, runtime(HEAD), int(d[0]), zd, a, runtime(True))
    elif d[4] > 0.0:                             # odd: the positive branch at -zd
        dist, jump = _knot_ahead(d, runtime(HEAD), int(d[0]), -zd, -a, runtime(True))
    else:
        b, n = _branch(d, False)
        dist, jump = _knot_ahead(d, b, n, zd, a, runtime(False))
    aa = abs(a)
    if jump > 0.0:
        cross = (24.0 * CROSS_SAFETY * dz * m / (jump * aa * aa * aa)) ** 0.25
        h = min(h, max(0.5 * dist / aa, cross))
    return h, a
