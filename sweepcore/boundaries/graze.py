"""The stick onset (slip cycle <-> stick-slip): the slip cycle grazes the belt.

At the grazing the slip cycle's largest velocity reaches ``v``. The indicator
``g = v - xdot_max`` is smooth and positive on the slip cycles and reaches 0 at the
grazing; on the stick-slip side only its sign is known (``xdot_max = v`` while
stuck). The root is extrapolated from the slip side (:func:`_slip_root`: the
polynomial through the nearest four values) inside the bracket kept by the regime
labels (:func:`_graze`): each round asks for two slip cycles just beyond the
predicted root (at ``h`` and ``3 h``, ``h`` twice the last correction, at least
``BAND`` relative), bisects when no prediction lies inside the bracket, and ends
when two successive estimates (or the polynomials of two degrees) agree to
``xtol``. Within ``BAND`` of the grazing a cycle passes within the driver's touch
tolerance of the belt, where the attractor search must measure it again at finer
tolerances to tell a stick from a graze (flagged unresolved within ~1e-12 of it):
the indicator, extrapolated from cycles beyond the band, decides. A continued step starts
from a predicted grazing (:func:`_seeded_graze`).
"""
from __future__ import annotations

import math

import numpy as np

from .._kernels import codes, layout
from .point import (ABSENT, CYCLES, FAILED, INCONSISTENT, LOCATED, STUCK, _ok, _Point,
                    _regime)

BAND = 1e-6             # relative width next to a grazing where cycles touch the belt
                        # within the touch tolerance (~3e-7 at tol 1e-10)
N_GRAZE = 3             # slip cycles of a seeded grazing step, at most
SEED_SPACING = 2 * BAND  # their relative spacing (beyond the band, close enough that
                         # the quadratic and linear roots agree to ~1e-11 relative)


def _slip_root(pts, a):
    """Root of g from the slip-side values nearest ``a``: (root, its uncertainty).

    The polynomial through the n nearest (n <= 4) values; the uncertainty is the
    distance of its root from that of the polynomial through the n - 1 nearest
    (infinite with two values); (None, inf) with fewer than two values. Each root
    is the real one nearest the previous (the secant's, first).
    """
    if len(pts) < 2:
        return None, math.inf
    near = sorted(pts, key=lambda q: abs(q[0] - a))[:4]
    us = np.array([q[0] for q in near])
    gs = np.array([q[1] for q in near])
    roots = []
    for n in range(2, len(near) + 1):
        ref, scale = us[0], us[n - 1] - us[0]
        t = (us[:n] - ref) / scale
        coef = np.linalg.solve(np.vander(t, n), gs[:n])    # interpolation
        if n == 2:
            found = np.array([-coef[1] / coef[0]])
        elif n == 3:
            a, b, c = coef
            disc = b * b - 4.0 * a * c
            if disc < 0.0:
                break
            # the two real roots, without cancellation
            qq = -0.5 * (b + math.copysign(math.sqrt(disc), b))
            found = np.array([qq / a, c / qq]) if qq != 0.0 else np.array([0.0])
        else:
            found = np.roots(coef)
            found = found[np.abs(found.imag) < 1e-12].real
        real = ref + scale * found[np.isfinite(found)]
        if not real.size:
            break
        roots.append(real[np.argmin(np.abs(real - (roots[-1] if roots else ref)))])
    if not roots:
        return None, math.inf
    if len(roots) < 2:
        return float(roots[-1]), math.inf
    return float(roots[-1]), abs(float(roots[-1] - roots[-2]))


def _graze(pt: _Point, stick: float, slip: float, xtol: float, slip_rows=(),
           amp: float | None = None, max_rounds: int = 80):
    """Solver: the grazing of the slip cycle with the belt between a stick-slip
    ``stick`` and a slip cycle ``slip`` (either order).

    ``slip_rows``: (value, observables) of slip cycles already known (e.g. from a
    scan). Every attractor is started inside its cycle, at x_eq + the amplitude
    (x_max - x_eq) of the known slip cycle nearest the stick side (``amp`` before
    any is known): a start outside would touch the belt on the way in. A cycle that
    still touches (``xdot_max = v``) counts on the stick side. Returns
    ``dict(value, width, status, amp)``: the root of the slip-side secant of
    ``g = v - xdot_max`` inside the final bracket, and that bracket's width.
    """
    a, b = stick, slip
    pts = []                       # (value, g, x_max - x_eq) on the slip side

    def fail(status):
        return {"value": math.nan, "width": abs(b - a), "status": status, "amp": amp}

    def g_of(u, row):
        return pt.speed(u) - row[layout.OB_XDOT_MAX]

    def start(u):
        if not pts:
            return (pt.x_eq(u) + amp, 0.0) if amp is not None else (0.0, STUCK)
        near = min(pts, key=lambda q: abs(q[0] - a))
        return (pt.x_eq(u) + near[2], 0.0)

    def add(u, row):
        pts.append((u, g_of(u, row), row[layout.OB_X_MAX] - pt.x_eq(u)))

    for u, row in slip_rows:
        add(u, row)
    if not pts:
        (row,) = yield [(b, *start(b))]
        if not _ok(row):
            return fail(FAILED)
        if _regime(row) != codes.R_SLIP_CYCLE or not g_of(b, row) > 0.0:
            return fail(INCONSISTENT)
        add(b, row)
    prev = None
    direction = math.copysign(1.0, b - a)

    step = None
    fresh = len(pts) >= 3          # did the last round add slip-side values?
    for _round in range(max_rounds):
        p, change = _slip_root(pts, a)
        if fresh and p is not None and prev is not None:
            change = min(change, abs(p - prev))
        if fresh and p is not None and change <= xtol:
            near = min(pts, key=lambda q: abs(q[0] - a))
            return {"value": p, "width": change, "status": LOCATED, "amp": near[2]}
        # aim just onto the slip side of the prediction, one correction beyond it
        # (the labels switch a little before g reaches 0: the graze tolerance)
        if p is None:
            h = 0.0
        elif prev is None:
            h = 0.1 * abs(b - p) if not math.isfinite(change) else 2.0 * change
        else:
            h = 2.0 * min(abs(p - prev), change)
        # not closer than BAND to the prediction: there the slip cycles touch the
        # belt within the touch tolerance (measured again finer, or flagged)
        h = max(h, xtol, BAND * abs(p) if p is not None else 0.0, step or 0.0)
        lo, hi = min(a, b), max(a, b)
        asks = [u for u in ((p + direction * h, p + direction * 3.0 * h)
                            if p is not None else ()) if lo < u < hi]
        if not asks:
            asks = [0.5 * (a + b)]
        prev = p if p is not None else prev
        rows = yield [(u, *start(u)) for u in asks]
        step, fresh = None, False
        for u, row in zip(asks, rows):
            if not _ok(row):
                return fail(FAILED)
            reg = _regime(row)
            if reg == codes.R_SLIP_CYCLE and g_of(u, row) > 0.0:
                add(u, row)
                fresh = True
                if abs(u - a) < abs(b - a):
                    b = u
            elif reg in CYCLES:      # stick-slip, or a cycle touching the belt
                if abs(u - b) < abs(a - b):
                    a = u
                step = 2.0 * h       # inside the band where labels say stick
            else:
                return fail(INCONSISTENT)
    return fail(INCONSISTENT)


def _seeded_graze(pt, guess, delta, xtol, amp, reach=None, width=math.inf):
    """Solver: the grazing near a predicted ``guess`` (stick below, slip above,
    along v): slip cycles at ``guess + delta`` and ``guess + 2 delta`` and a
    stick-slip check at ``guess - delta`` in one round. The root through the two
    (linear; the curvature moves it by ~the last step's ``width``) is accepted
    where it agrees with the prediction to ``xtol / 4``; else a third cycle at
    ``guess + 3 delta`` and :func:`_graze` from there. The cycles start at x_eq +
    ``reach[i]`` (the previous step's cycles, scaled) or else inside, at x_eq +
    0.999 ``amp``."""
    us = [guess + i * delta for i in range(1, N_GRAZE + 1)]
    check = guess - delta
    seeds = list(reach) if reach is not None else [0.999 * amp]
    seeds += [seeds[-1]] * (N_GRAZE - len(seeds))
    rows = yield [(u, pt.x_eq(u) + r, 0.0) for u, r in zip(us[:2], seeds)] + \
        [(check, 0.0, STUCK)]
    if not all(_ok(r) for r in rows):
        return {"value": math.nan, "width": math.nan, "status": FAILED}

    def slip_of(pairs):
        return [(u, r) for u, r in pairs if _regime(r) == codes.R_SLIP_CYCLE
                and pt.speed(u) - r[layout.OB_XDOT_MAX] > 0.0]
    slip = slip_of(zip(us[:2], rows[:2]))
    if len(slip) < 2 or _regime(rows[2]) not in CYCLES:
        return {"value": math.nan, "width": math.nan, "status": ABSENT}
    root, _ = _slip_root([(u, pt.speed(u) - r[layout.OB_XDOT_MAX]) for u, r in slip],
                         check)
    if root is not None and abs(root - guess) <= 0.25 * xtol:
        near = slip[0]
        out = {"value": root, "width": max(abs(root - guess), width),
               "status": LOCATED, "amp": near[1][layout.OB_X_MAX] - pt.x_eq(near[0])}
    else:
        (row,) = yield [(us[2], pt.x_eq(us[2]) + seeds[2], 0.0)]
        if not _ok(row):
            return {"value": math.nan, "width": math.nan, "status": FAILED}
        slip += slip_of([(us[2], row)])
        if len(slip) < N_GRAZE:
            return {"value": math.nan, "width": math.nan, "status": ABSENT}
        out = yield from _graze(pt, check, us[0], xtol, slip)
    out["guess_error"] = abs(out["value"] - guess) if out["status"] == LOCATED \
        else math.inf
    out["seed_reach"] = np.array([r[layout.OB_X_MAX] - pt.x_eq(u) for u, r in slip])
    out["delta"] = delta / guess
    return out
