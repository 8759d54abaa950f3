"""The representation of a friction table: a shape-preserving quintic Hermite spline,
accurate where the samples turn smoothly.

Each piece ``[x_i, x_{i+1}]`` is the quintic that takes the data's values ``y_i``,
``y_{i+1}`` and the slopes ``d`` and curvatures ``s`` estimated at its ends, so that
F, F' and F'' are continuous (C2) and F''' is defined on each piece. The estimates
come from the polynomial through the seven nearest points (accurate to order 6 on
smooth data). Then the shape, piece by piece, read from the Bernstein control points
``b_0 .. b_5`` of the piece (by the convex-hull property the piece lies in their
hull, and has no more sign changes of F' or F'' than their differences have):

* where the data run one way on and next to a piece, its (d, s) are shrunk into the
  region where the control points run monotonically from ``y_i`` to ``y_{i+1}``:
  the piece is monotone and stays between its two data values (no overshoot, even
  after a steep step). This is monotone quintic spline interpolation (Lux, Watson et
  al., "Algorithm 1031: MQSI", ACM TOMS 49, 2023: quintic Hermite pieces with
  derivative estimates shrunk to a monotone region), with the control polygon's
  sufficient condition instead of the exact region, which makes the shrink one
  vectorised step;
* where the samples turn (a local extremum of the data), the curve's own extremum
  lies between samples. The turn is *smooth* when the second divided differences
  of the data at the turn and at both neighbours have the turn's sign (convex
  samples about a minimum, concave about a maximum: the smooth-extremum test of
  Colella & Sekora, "A limiter for PPM that preserves accuracy at smooth extrema",
  J. Comput. Phys. 227, 2008; noise, turns next to each other, fails it). There
  the estimates are kept, provided the two pieces next to the turn have convex
  (concave) control polygons: each piece is then convex, holds exactly one
  extremum and lies below its chord, no deeper than the step into the turn lets
  a convex curve go (convexity as the shape to keep, as in Dougherty, Edelman &
  Hyman, "Nonnegativity-, monotonicity-, or convexity-preserving cubic and
  quintic Hermite interpolation", Math. Comp. 52, 1989). Any other turn is
  flattened onto its sample (``d = s = 0``, the monotone rule).

Past the far end (the largest |speed|) the force is held; so that the last piece
keeps its accuracy, a *runout* piece follows the table, in which the slope decays
from the end's ``(d, s)`` to 0 as a cubic Hermite (its integral: the force moves
monotonically by ``d w/2 + s w^2/12`` over the runout's width w, the last piece's
width or less, to the held force), by at most the last piece's change (a larger
end slope is scaled down), and flat (``d = s = 0``) where the force would change
sign.

``deviation``: an estimate of the largest distance between the representation and
the curve the samples came from, on the table: on each piece the larger of two
bounds (the control points of a difference). (1) Its distance from the same
construction built from five-point estimates (order 4): on smooth data that one's
error is the larger, so this estimates the order-6 representation's error from
above. (2) Where the shape rules changed the estimates (under-resolved data: a
step, a wild slope estimate), its distance from the unconstrained interpolant, at
most the piece's own spread of samples (within which a monotone curve stays).
"""
from __future__ import annotations

from math import comb

import numpy as np

DEGREE = 5
WINDOW = 7                 # points of the polynomial that estimates F' and F''
CHECK = 5                  # ... of the lower-order estimate that deviation compares
MARGIN = 1e-12             # relative rounding margin of the slope and curvature bounds


def estimates(x: np.ndarray, y: np.ndarray, window: int = WINDOW):
    """``(d, s)``: F' and F'' at every x_i of the interpolating polynomial through the
    ``window`` nearest points (a window shifted inside the table at its ends).

    The polynomial in Newton's form: the divided differences of consecutive points
    (shared by the windows: ``window`` array operations in all), in speeds scaled by
    the table's span; no linear solve (nothing to fail on a badly spaced table; a
    wild estimate is shrunk later)."""
    n = x.size
    w = min(window, n)
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
    return np.where(np.isfinite(d), d, 0.0), np.where(np.isfinite(s), s, 0.0)


def smooth_turns(x, y):
    """``(turns, kind)``: the knots where the samples turn smoothly (docstring), and
    each knot's kind, +1 a minimum of the data, -1 a maximum, 0 no turn."""
    n = x.size
    sg = np.sign(np.diff(y))
    kind = np.zeros(n)
    kind[1:-1] = np.where(sg[:-1] * sg[1:] < 0.0, sg[1:], 0.0)
    curve = np.full(n + 2, np.nan)             # second divided differences, padded
    curve[2:-2] = 2.0 * np.diff(np.diff(y) / np.diff(x)) / (x[2:] - x[:-2])
    agree = [~(kind * curve[j:j + n] <= 0.0) for j in (0, 1, 2)]   # NaN: no neighbour
    return (kind != 0.0) & agree[0] & agree[1] & agree[2], kind


def shape_preserving(x, y, d, s, turns):
    """``(d, s)`` shrunk so that every piece away from a kept turn (``turns``) has a
    control polygon monotone between its end values; at a turn not kept ``d = s =
    0``, at a kept one the estimates.

    With ``D = d h``, ``S = s h^2`` and ``sg`` the data's direction on a piece of
    length h, the conditions are ``sg D >= 0`` at both ends, ``sg (4 D_0 + S_0) >= 0``
    and ``sg (4 D_1 - S_1) >= 0`` (b_1 <= b_2, b_3 <= b_4), and
    ``|y_1 - y_0| >= sg (2 (D_0 + D_1)/5 - (S_1 - S_0)/20)`` (b_2 <= b_3). Once the
    first three hold, each end's share of the last is >= 0, so scaling an end's
    (d, s) down only helps its neighbour too: one pass."""
    h = np.diff(x)
    sg = np.sign(np.diff(y))
    left = np.concatenate([sg[:1], sg])         # the direction on either side of a knot
    right = np.concatenate([sg, sg[-1:]])
    direction = np.where(left == right, right, 0.0)
    near = turns[:-1] | turns[1:]               # pieces next to a kept turn
    d = np.where((d * direction > 0.0) | turns, d, 0.0)
    s = np.where((direction != 0.0) | turns, s, 0.0)
    a = np.abs(d)
    with np.errstate(divide="ignore", invalid="ignore"):
        lo = np.concatenate([np.where(near, -np.inf, -4.0 * a[:-1] / h), [-np.inf]])
        hi = np.concatenate([[np.inf], np.where(near, np.inf, 4.0 * a[1:] / h)])
    s = np.where(turns, s, direction * np.clip(direction * s, lo, hi))
    D0, D1 = d[:-1] * h, d[1:] * h
    S0, S1 = s[:-1] * h * h, s[1:] * h * h
    need = sg * (0.4 * (D0 + D1) - (S1 - S0) / 20.0)
    gap = np.abs(np.diff(y))
    with np.errstate(divide="ignore", invalid="ignore"):
        lam = np.where((need > gap) & ~near, gap / need, 1.0)
    scale = np.minimum(np.concatenate([lam, [1.0]]), np.concatenate([[1.0], lam]))
    return d * scale, s * scale


def runout(x, y, d, s, far_last: bool):
    """``(d, s, w, held)``: the far end's (d, s) (flattened where the runout would
    change the force's sign), the runout's width w [cm/s] and the force held past
    it. The slope decays as the cubic Hermite from (d, s) to (0, 0) over w, monotone
    while ``sgn(d) (3 d + o s w) >= 0`` (o = +1 outwards up, -1 down): w is the last
    piece's width, or less where the curvature turns the slope back sooner; the
    force moves over it by at most the last piece's change (a larger (d, s) at the
    far end is scaled down, which keeps the last piece's control polygon as it
    was: monotone, or convex)."""
    far, o = (-1, 1.0) if far_last else (0, -1.0)
    w = abs(x[-1] - x[-2]) if far_last else abs(x[1] - x[0])
    df, sf = d[far], s[far]
    width = w
    if df == 0.0:
        sf = 0.0
    elif (3.0 * df + o * sf * w) * np.sign(df) < 0.0:
        w = 3.0 * abs(df / sf)
    change = o * df * w / 2.0 + sf * w * w / 12.0
    last = abs(y[far] - y[far - int(o)])   # the last piece's change: the runout's most
    if abs(change) > last:              # (d, s) scaled down; w stays (scale-free)
        df, sf, change = (x_ * last / abs(change) for x_ in (df, sf, change))
    held = y[far] + change
    # the force keeps its sign (o on this branch); a runout far narrower than the
    # last piece is a turn at the end: flat
    if held * o < 0.0 or not np.isfinite(held) or w < 1e-3 * width:
        df = sf = 0.0
        w, held = width, y[far]
    d, s = d.copy(), s.copy()
    d[far], s[far] = df, sf
    return d, s, w, held


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


def range_excess(y, b) -> np.ndarray:
    """The distance [force units] by which each piece leaves the range of its two
    data values (a bound: from the control points ``b``; 0 inside)."""
    lo = np.minimum(y[:-1], y[1:])
    hi = np.maximum(y[:-1], y[1:])
    return np.maximum(np.maximum(b.max(axis=0) - hi, lo - b.min(axis=0)), 0.0)


def _represent(x, y, raw, far_last):
    """``(c, (d, s), w, held, turns)``: the pieces' coefficients, the knots' (d, s),
    the runout's width and held force, and the turns kept, of the shape-preserving
    spline through (x, y) built from the estimates ``raw = (d, s)``."""
    turns, kind = smooth_turns(x, y)
    while True:
        d, s = shape_preserving(x, y, raw[0], raw[1], turns)
        d, s, w, held = runout(x, y, d, s, far_last)
        c = coefficients(x, y, d, s)
        # a kept turn's two pieces must be convex (concave at a maximum)
        kept = np.where(turns, kind, 0.0)
        curve = np.diff(bernstein(x, c), 2, axis=0)
        convex = np.all((kept[:-1] + kept[1:]) * curve >= 0.0, axis=0)
        bad = turns & ~(np.concatenate([[True], convex])
                        & np.concatenate([convex, [True]]))
        if not bad.any():
            return c, (d, s), w, held, turns
        turns = turns & ~bad


def fit(x, y, far_last: bool, slopes=None):
    """``((x, c, dmin, d2), dmax, excess, deviation)`` of the spline through (x, y):
    the kernels' branch (breakpoints, the runout's included; coefficients; least F'
    and largest |F''| of each piece), the largest |F'| of each piece, the largest
    ``range_excess`` of the pieces kept monotone (rounding only), and the deviation
    estimate (module docstring; None with ``slopes``). ``slopes``: ``(d, s)`` to use
    instead of the window estimates (a smoothing spline's)."""
    raw = estimates(x, y) if slopes is None else \
        tuple(np.where(np.isfinite(a), a, 0.0) for a in slopes)
    c, (d, s), w, held, turns = _represent(x, y, raw, far_last)
    b = bernstein(x, c)
    near = turns[:-1] | turns[1:]
    excess = float(np.max(range_excess(y, b)[~near], initial=0.0))
    deviation = None
    if slopes is None:
        lower = _represent(x, y, estimates(x, y, CHECK), far_last)[0]
        shaped = np.abs(bernstein(x, c - coefficients(x, y, *raw))).max(axis=0)
        deviation = float(np.max(np.maximum(
            np.abs(bernstein(x, c - lower)).max(axis=0),
            np.minimum(shaped, np.abs(np.diff(y))))))
    # the runout: (x_far, y_far, d, s) to (x_far +- w, held, 0, 0)
    ends = (x[-1], x[-1] + w, y[-1], held, d[-1], 0.0, s[-1], 0.0) if far_last else \
        (x[0] - w, x[0], held, y[0], 0.0, d[0], 0.0, s[0])
    xr, yr, dr, sr = (np.array(ends[i:i + 2]) for i in (0, 2, 4, 6))
    cr = coefficients(xr, yr, dr, sr)
    xs = np.concatenate([x, xr[1:]]) if far_last else np.concatenate([xr[:1], x])
    cs = np.concatenate([c, cr]) if far_last else np.concatenate([cr, c])
    dmin, dmax, d2 = bounds(xs, bernstein(xs, cs))
    return (xs, cs, dmin, d2), dmax, excess, deviation
