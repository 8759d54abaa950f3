"""The Hopf point (slip cycle <-> equilibrium), from the cycle's amplitude.

Averaging eq. (41) about x_eq gives ``(A omega)^2 = 4 m q / (3 alpha2)``
(docs/physics.md), and ``q`` (eq. 46) is linear in ``v^2``: the cycle's amplitude
squared ``A^2`` is a smooth function of ``w = v^2`` that vanishes at the Hopf point.
It is measured on a few cycles a little away from the point (relative offsets
``i * offset``, i = 1..5; the offset is widened where the cycles would contract too
weakly to be resolved at ``tol``, :func:`_hopf_offset`, which sets it at low
damping), where the attractor search is fast and accurate, and its root found by a
cubic through the four nearest samples (root of the polynomial by
:func:`~sweepcore.boundaries.roots.bracketed_root`). The cubic through samples 2..5
gives a second root; their difference is reported as the error estimate. The root
must lie between the nearest cycle and an equilibrium (label check), else the status
says so. A continued step (:func:`sweepcore.boundaries.continue_boundary`) keeps the
shape of that polynomial and needs two or three cycles (:func:`_seeded_hopf`).
"""
from __future__ import annotations

import math

import numpy as np

from .._kernels import codes, layout
from .._kernels.attractor import RTOL_FLOOR
from .point import CYCLES, FAILED, INCONSISTENT, LOCATED, _ok, _Point, _regime
from .roots import bracketed_root

N_SAMPLES = 5           # Hopf samples per round
N_SEEDED = 3            # Hopf samples of a continued step, at most (the shape known)
RESOLVABLE = 2.0 * RTOL_FLOOR   # lowest rtol asked of a Hopf sample's cycle
MAX_OFFSET = 0.015      # widest relative spacing of the Hopf samples (the fifth stays
                        # well above the grazing, ~10 % below the Hopf point)


def _fit_root(w, a2, w_lo, w_hi):
    """Root of the cubic through (w, a2) between w_lo and w_hi, or NaN."""
    ref, scale = w[0], (w[-1] - w[0]) or 1.0
    coef = np.polyfit((np.asarray(w) - ref) / scale, a2, len(w) - 1)
    f = lambda x: np.polyval(coef, (x - ref) / scale)   # noqa: E731
    try:
        return bracketed_root(f, w_lo, w_hi, 1e-15 * max(abs(w_lo), abs(w_hi)))
    except ValueError:
        return math.nan


def _hopf_offset(pt: _Point, r: float, side: int, offset: float) -> float:
    """``offset``, widened where the samples would come too close to the Hopf
    point for the attractor search to resolve them.

    The kernel integrates a slip cycle at rtol = tol (1 - mu) / 2 and gives up
    (status ``unresolved``) below RTOL_FLOOR; ``1 - mu`` grows about linearly with
    the distance from the Hopf point (:meth:`_Point.contraction`), so the nearest
    sample is moved out until tol (1 - mu) / 2 >= RESOLVABLE (at most MAX_OFFSET).
    At low damping (alpha1/sqrt(k m) << 0.1) this is what sets the offset.
    """
    if pt.tol is None:
        return offset
    need = 2.0 * RESOLVABLE / pt.tol
    s = offset
    for _ in range(4):          # 1 - mu is nearly linear in s: one step is enough
        c = pt.contraction(r * (1.0 + side * s))
        if c >= need or s >= MAX_OFFSET:
            break
        s = min(MAX_OFFSET, s * 1.05 * need / c if c > 0.0 else 2.0 * s)
    return s


def _hopf(pt: _Point, guess: float, side: int, offset: float, reach=None,
          max_rounds: int = 4):
    """Solver: the Hopf point near ``guess``, cycles on ``side`` (-1 below, +1 above).

    ``reach``: the expected ``x_max - x_eq`` [cm] of the cycles at the samples
    (each starts there, at rest); by default 5 % sqrt(i) of the length scale
    r_y/k + |v|/omega.

    Returns ``dict(value, error, status, reach)``, ``reach`` measured.
    """
    r = guess
    result = {"value": math.nan, "error": math.nan, "status": FAILED,
              "reach": None}
    asked = offset
    for _round in range(max_rounds):
        offset = _hopf_offset(pt, r, side, asked)
        us = r * (1.0 + side * offset * np.arange(1, N_SAMPLES + 1))
        check = r * (1.0 - side * offset)
        if reach is None:
            reach = 0.05 * pt.length_scale(r) * np.sqrt(np.arange(1, N_SAMPLES + 1))
        reqs = [(u, pt.x_eq(u) + a, 0.0) for u, a in zip(us, reach)]
        rows = yield reqs + [(check, pt.x_eq(check), 0.0)]
        samples, eq_row = rows[:N_SAMPLES], rows[N_SAMPLES]
        if not all(_ok(s) for s in samples) or not _ok(eq_row):
            return result
        cyc = [_regime(s) == codes.R_SLIP_CYCLE for s in samples]
        if _regime(eq_row) != codes.R_EQUILIBRIUM or not all(cyc):
            # the guess was off by more than the offsets: move to the label change
            if _regime(eq_row) in CYCLES:
                r = check * (1.0 - side * offset)
            elif not cyc[0]:
                r = us[next((i for i, c in enumerate(cyc) if c), N_SAMPLES - 1)]
            else:
                result["status"] = INCONSISTENT
                return result
            reach = None
            continue
        amp = np.array([s[layout.OB_AMPLITUDE] for s in samples])
        w = pt.fit_variable(us)
        wc = float(pt.fit_variable(check))
        near = _fit_root(w[:4], amp[:4] ** 2, float(w[0]), wc)
        far = _fit_root(w[1:], amp[1:] ** 2, float(w[0]), wc)
        if not np.isfinite(near):
            result["status"] = INCONSISTENT
            return result
        root = math.sqrt(near) if pt.along == "v" else near
        err = abs(root - (math.sqrt(far) if pt.along == "v" else far)) \
            if np.isfinite(far) else math.inf
        got = np.array([s[layout.OB_X_MAX] - pt.x_eq(u) for s, u in zip(samples, us)])
        result.update(value=root, error=err, status=LOCATED, reach=got,
                      shape=_shape(w[:4], amp[:4] ** 2, near))
        if abs(root - r) <= 0.3 * offset * abs(r):
            return result
        # the fit lies well off the centre: sample again around it
        reach = got * np.sqrt(np.abs(us - root) / np.abs(us - r))
        r = root
    result["status"] = INCONSISTENT
    return result


def _shape(w, a2, w0):
    """(b2, b3) of ``A^2 = c1 x (1 + b2 x + b3 x^2)``, x = (w0 - w)/w0, by least
    squares through the samples with the root ``w0`` fixed."""
    x = (w0 - np.asarray(w)) / w0
    c = np.linalg.lstsq(np.c_[x, x ** 2, x ** 3], a2, rcond=None)[0]
    return c[1] / c[0], c[2] / c[0]


def _shaped_root(wa, a2a, wb, a2b, shape, hi):
    """Root w0 of ``A^2 = c1 x (1 + b2 x + b3 x^2)`` (x = (w0 - w)/w0, shape
    (b2, b3) given) through two samples below it, searched in (wa, hi]; NaN if
    none."""
    b2, b3 = shape

    def f(x):
        return x * (1.0 + b2 * x + b3 * x * x)

    def F(w0):
        return a2a * f((w0 - wb) / w0) - a2b * f((w0 - wa) / w0)
    lo = wa * (1.0 + 1e-9 * (1.0 if hi > wa else -1.0))
    try:
        return bracketed_root(F, lo, hi, 1e-15 * abs(hi))
    except ValueError:
        return math.nan


def _seeded_hopf(pt: _Point, guess: float, offset: float, reach, shape, xtol):
    """Solver: the Hopf point near a predicted ``guess`` (cycles below, along v),
    the shape of A^2 (:func:`_shape`) taken from the previous steps.

    Two cycles first: the root through them is accepted where it agrees with the
    prediction to ``xtol / 4`` (two independent estimates: the previous steps and
    these samples). Else a third cycle, and the root through samples 1 and 2 is
    accepted where it agrees with the root through 1 and 3 (their difference,
    doubled, being the error estimate: the shape's error moves them apart); else
    :func:`_hopf`. The error estimate adds the root's move under amplitude errors
    of 2 tol L (L = r_y/k + |v|/omega), the samples' accuracy.
    """
    s = _hopf_offset(pt, guess, -1, offset)
    us = guess * (1.0 - s * np.arange(1, N_SEEDED + 1))
    check = guess * (1.0 + s)
    rows = yield [(u, pt.x_eq(u) + a, 0.0) for u, a in zip(us[:2], reach)] \
        + [(check, pt.x_eq(check), 0.0)]
    samples, eq_row = list(rows[:2]), rows[2]
    if not (all(_ok(r) and _regime(r) == codes.R_SLIP_CYCLE for r in samples) and
            _ok(eq_row) and _regime(eq_row) == codes.R_EQUILIBRIUM):
        return (yield from _hopf(pt, guess, -1, offset, reach=reach))
    w, hi = us ** 2, check ** 2

    def a2(k):
        return samples[k][layout.OB_AMPLITUDE] ** 2
    r12 = _shaped_root(w[0], a2(0), w[1], a2(1), shape, hi)
    if not np.isfinite(r12):
        return (yield from _hopf(pt, guess, -1, offset, reach=reach))
    root = math.sqrt(r12)
    err = abs(root - guess)
    if err > 0.25 * xtol:
        (row,) = yield [(us[2], pt.x_eq(us[2]) + reach[2], 0.0)]
        if not (_ok(row) and _regime(row) == codes.R_SLIP_CYCLE):
            return (yield from _hopf(pt, guess, -1, offset, reach=reach))
        samples.append(row)
        r13 = _shaped_root(w[0], a2(0), w[2], a2(2), shape, hi)
        err = 2.0 * abs(root - math.sqrt(r13)) if np.isfinite(r13) else math.inf
        if not err <= 0.5 * xtol:
            return (yield from _hopf(pt, guess, -1, offset, reach=reach))
    # plus the amplitudes' error (measured up to ~2 tol L) moving the root
    dA = 2.0 * (pt.tol or 0.0) * pt.length_scale(guess)
    amp = np.sqrt([a2(0), a2(1)])
    moved = _shaped_root(w[0], (amp[0] + dA) ** 2, w[1], (amp[1] - dA) ** 2, shape, hi)
    err += abs(math.sqrt(moved) - root) if np.isfinite(moved) else math.inf
    got = np.array([r[layout.OB_X_MAX] - pt.x_eq(u) for r, u in zip(samples, us)])
    n = got.size
    full = np.r_[got, got[-1] * np.sqrt(np.arange(n + 1, N_SAMPLES + 1) / n)]
    return {"value": root, "error": err, "status": LOCATED, "reach": full,
            "shape": shape}
