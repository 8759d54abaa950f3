"""The representation of a friction table: a shape-preserving quintic Hermite spline.

Each piece ``[x_i, x_{i+1}]`` is the quintic that takes the data's values ``y_i``,
``y_{i+1}`` and the slopes ``d`` and curvatures ``s`` estimated at its ends, so that
F, F' and F'' are continuous (C2) and F''' is defined on each piece. The estimates
come from the polynomial through the seven nearest points (accurate to order 6 on
smooth data) and are then shrunk into the region where the piece's Bernstein
control points ``b_0 .. b_5`` run monotonically from ``y_i`` to ``y_{i+1}``; by the
convex-hull property of the Bernstein form the piece is then monotone and stays
between its two data values (no new extremum). Where the data turn (a local extremum
of the samples) or stay flat, ``d = s = 0`` at the knot. This is the construction of
monotone quintic spline interpolation (Lux, Watson et al., "Algorithm 1031: MQSI",
ACM TOMS 49, 2023: quintic Hermite pieces with derivative estimates shrunk to a
monotone region), with the control polygon's sufficient condition instead of the
exact region, which makes the shrink one vectorised step: docs/methods.md,
"Tabulated friction laws".
"""
from __future__ import annotations

import numpy as np

DEGREE = 5
WINDOW = 7                 # points of the polynomial that estimates F' and F''
MARGIN = 1e-12             # relative rounding margin of the slope and curvature bounds


def estimates(x: np.ndarray, y: np.ndarray):
    """``(d, s)``: F' and F'' at every x_i of the interpolating polynomial through the
    ``WINDOW`` nearest points (a window shifted inside the table at its ends).

    The polynomial in Newton's form: the divided differences of consecutive points
    (shared by the windows: ``WINDOW`` array operations in all), in speeds scaled by
    the table's span; no linear solve (nothing to fail on a badly spaced table; a
    wild estimate is shrunk later)."""
    n = x.size
    w = min(WINDOW, n)
    start = np.clip(np.arange(n) - w // 2, 0, n - w)
    span = x[-1] - x[0]
    u = (x - x[0]) / span
    d = np.zeros(n)
    s = np.zeros(n)
    # omega_k(u) = prod_{m < k} (u - u_{start+m}) and its two derivatives at u_i
    om, om1, om2 = np.ones(n), np.zeros(n), np.zeros(n)
    dd = y
    with np.errstate(all="ignore"):
        for k in range(1, w):
            a = u - u[start + k - 1]
            om, om1, om2 = om * a, om1 * a + om, om2 * a + 2.0 * om1
            dd = (dd[1:] - dd[:-1]) / (u[k:] - u[:-k])
            coef = dd[start]
            d += coef * om1
            s += coef * om2
        d /= span
        s /= span * span
    return d, s


def shape_preserving(x, y, d, s, far_last: bool, free_turns: bool = False):
    """``(d, s)`` shrunk so that every piece's Bernstein control polygon is monotone
    between its end values; at the table's far end (the last point if ``far_last``,
    else the first) ``d = s = 0``, so that the force held beyond it joins C2.

    With ``D = d h``, ``S = s h^2`` and ``sg`` the data's direction on a piece of
    length h, the conditions are ``sg D >= 0`` at both ends, ``sg (4 D_0 + S_0) >= 0``
    and ``sg (4 D_1 - S_1) >= 0`` (b_1 <= b_2, b_3 <= b_4), and
    ``|y_1 - y_0| >= sg (2 (D_0 + D_1)/5 - (S_1 - S_0)/20)`` (b_2 <= b_3). Once the
    first three hold, each end's share of the last is >= 0, so scaling an end's
    (d, s) down only helps its neighbour too: one pass.

    ``free_turns``: where the samples turn, keep the estimates and leave the two
    pieces next to the turn unconstrained (a sampled function, whose extremum lies
    between the samples: its distance from the function is what is checked)."""
    h = np.diff(x)
    sg = np.sign(np.diff(y))
    left = np.concatenate([sg[:1], sg])         # the direction on either side of a knot
    right = np.concatenate([sg, sg[-1:]])
    direction = np.where(left == right, right, 0.0)
    turn = (direction == 0.0) & (left != 0.0) & (right != 0.0)
    free = turn if free_turns else np.zeros_like(turn)
    d = np.where(np.isfinite(d) & ((d * direction > 0.0) | free), d, 0.0)
    s = np.where(np.isfinite(s) & ((direction != 0.0) | free), s, 0.0)
    far = -1 if far_last else 0
    d[far] = s[far] = 0.0
    a = np.abs(d)
    with np.errstate(divide="ignore", invalid="ignore"):
        lo = np.concatenate([-4.0 * a[:-1] / h, [-np.inf]])
        hi = np.concatenate([[np.inf], 4.0 * a[1:] / h])
    s = np.where(free, s, direction * np.clip(direction * s, lo, hi))
    D0, D1 = d[:-1] * h, d[1:] * h
    S0, S1 = s[:-1] * h * h, s[1:] * h * h
    need = sg * (0.4 * (D0 + D1) - (S1 - S0) / 20.0)
    gap = np.abs(np.diff(y))
    with np.errstate(divide="ignore", invalid="ignore"):
        lam = np.where((need > gap) & ~free[:-1] & ~free[1:], gap / need, 1.0)
    scale = np.minimum(np.concatenate([lam, [1.0]]), np.concatenate([[1.0], lam]))
    return d * scale, s * scale


def coefficients(x, y, d, s) -> np.ndarray:
    """Ascending power coefficients (n, 6) in ``t = s - x_i`` of the quintic Hermite
    pieces with values y, slopes d and curvatures s at the breakpoints x."""
    h = np.diff(x)
    y0, y1, d0, d1, s0, s1 = y[:-1], y[1:], d[:-1], d[1:], s[:-1], s[1:]
    # the remainder A of the value, B of the slope, C of the curvature after the
    # quadratic Taylor part from the left end
    A = y1 - y0 - d0 * h - 0.5 * s0 * h * h
    B = (d1 - d0 - s0 * h) * h
    C = (s1 - s0) * h * h
    c = np.empty((h.size, DEGREE + 1))
    c[:, 0], c[:, 1], c[:, 2] = y0, d0, 0.5 * s0
    c[:, 3] = (10.0 * A - 4.0 * B + 0.5 * C) / h ** 3
    c[:, 4] = (-15.0 * A + 7.0 * B - C) / h ** 4
    c[:, 5] = (6.0 * A - 3.0 * B + 0.5 * C) / h ** 5
    return c


def bernstein(x, c) -> np.ndarray:
    """The control points (6, n) of each piece in the Bernstein basis of degree 5
    on its interval: ``b_k = sum_{j <= k} C(k, j)/C(5, j) c_j h^j``."""
    from math import comb
    h = np.diff(x)
    cT = c.T
    scaled = [cT[j] * h ** j for j in range(DEGREE + 1)]
    b = np.zeros((DEGREE + 1, h.size))
    for k in range(DEGREE + 1):
        for j in range(k + 1):
            b[k] += comb(k, j) / comb(DEGREE, j) * scaled[j]
    return b


def bounds(x, b):
    """``(least F', largest |F'|, largest |F''|)`` of each piece from the Bernstein
    coefficients of F' and F'' (convex hull: rigorous; ``b`` the control points),
    widened by a rounding margin."""
    h = np.diff(x)
    size = np.abs(b).max(axis=0)
    slope = DEGREE * np.diff(b, axis=0) / h
    curve = DEGREE * (DEGREE - 1) * np.diff(b, 2, axis=0) / (h * h)
    return (slope.min(axis=0) - MARGIN * DEGREE * size / h,
            np.abs(slope).max(axis=0) + MARGIN * DEGREE * size / h,
            np.abs(curve).max(axis=0) + MARGIN * 20.0 * size / (h * h))


def range_excess(y, b) -> tuple[float, int]:
    """The largest distance [force units] by which the representation leaves the
    range of its two data values on any piece (a bound: from the control points
    ``b``), and the index of that piece."""
    lo = np.minimum(y[:-1], y[1:])
    hi = np.maximum(y[:-1], y[1:])
    excess = np.maximum(b.max(axis=0) - hi, lo - b.min(axis=0))
    i = int(np.argmax(excess))
    return max(float(excess[i]), 0.0), i


def fit(x, y, far_last: bool, slopes=None, free_turns=False):
    """``((x, c, dmin, d2), dmax, excess)`` of the shape-preserving quintic through
    (x, y): the kernels' branch (breakpoints, coefficients, least F' and largest
    |F''| of each piece), the largest |F'| of each piece, and ``range_excess``.
    ``slopes``: ``(d, s)`` to use instead of the window estimates (a smoothing
    spline's); ``free_turns``: see ``shape_preserving``."""
    d, s = estimates(x, y) if slopes is None else slopes
    d, s = shape_preserving(x, y, d, s, far_last, free_turns)
    c = coefficients(x, y, d, s)
    b = bernstein(x, c)
    dmin, dmax, d2 = bounds(x, b)
    return (x, c, dmin, d2), dmax, range_excess(y, b)[0]
