"""Regime boundaries to full precision, located and continued beyond the grid.

Along the belt speed ``v`` (or another parameter) the attractor of Liu's model
changes regime at two bifurcations of the slip cycle:

* the **Hopf point** (cycle <-> equilibrium). Averaging eq. (41) about x_eq gives
  ``(A omega)^2 = 4 m q / (3 alpha2)`` (docs/physics.md), and ``q`` (eq. 46) is
  linear in ``v^2``: the cycle's amplitude squared ``A^2`` is a smooth function of
  ``w = v^2`` that vanishes at the Hopf point. It is measured on a few cycles a
  little away from the point (relative offsets ``i * offset``, i = 1..5; the offset
  is widened where the cycles would contract too weakly to be resolved at ``tol``,
  :func:`_hopf_offset`, which sets it at low damping), where the attractor search
  is fast and accurate, and its root found by a cubic through the
  four nearest samples (root of the polynomial by :func:`bracketed_root`). The
  cubic through samples 2..5 gives a second root; their difference is reported as
  the error estimate. The root must lie between the nearest cycle and an
  equilibrium (label check), else the status says so. A continued step
  (:func:`continue_boundary`) keeps the shape of that polynomial and needs two
  or three cycles (:func:`_seeded_hopf`).
* the **stick onset** (slip cycle <-> stick-slip): the slip cycle grazes the belt,
  its largest velocity reaching ``v``. The indicator ``g = v - xdot_max`` is
  smooth and positive on the slip cycles and reaches 0 at the grazing; on the
  stick-slip side only its sign is known (``xdot_max = v`` while stuck). The root
  is extrapolated from the slip side (:func:`_slip_root`: the polynomial through
  the nearest four values) inside the bracket kept by the regime labels
  (:func:`_graze`): each round asks for two slip cycles just beyond the predicted
  root (at ``h`` and ``3 h``, ``h`` twice the last correction, at least ``BAND``
  relative), bisects when no prediction lies inside the bracket, and ends when two
  successive estimates (or the polynomials of two degrees) agree to ``xtol``.
  Within ``BAND`` of the grazing the labels already say stick (a cycle passing
  within the driver's graze tolerance of the belt is snapped onto the grazing
  orbit), which is why the indicator, not the label, decides.

A start that does not reach an attractor within the kernel's budget is retried
once from rest on the belt (:func:`_drive`); an ``unresolved`` cycle next to the
Hopf point keeps its label in the scan.

Any other regime change in the bracket (e.g. the edges of the band of slip cycles
with slide-slide reversals at small alpha2, for which no smooth indicator is known)
is located by bisection on the regime labels, to ``xtol``.

The solvers are Python generators that ask for attractors and receive the kernel's
observables rows; :func:`_drive` runs the solvers of many grid points in lockstep,
each round one batched call of the attractor kernel (numba threads, or the serial
kernel inside a dask task), so Python costs a few microseconds per attractor.
"""
from __future__ import annotations

import datetime
import math

import numpy as np
import xarray as xr

from . import execute, variables
from ._kernels import codes, layout
from ._kernels.attractor import RTOL_FLOOR
from .grid import AXES, COLUMNS, Grid
from .law import v_star as _v_star
from .options import make_options
from .params import LONG_NAMES, UNITS

# Outcome of one boundary search (codes in _kernels/codes.py, the one table)
LOCATED = codes.B_LOCATED
ABSENT = codes.B_ABSENT
FAILED = codes.B_FAILED
INCONSISTENT = codes.B_INCONSISTENT
SEARCH_NAMES = codes.SEARCH_NAMES

CYCLES = (codes.R_SLIP_CYCLE, codes.R_STICK_SLIP)
PROPER = (codes.R_EQUILIBRIUM, codes.R_SLIP_CYCLE, codes.R_STICK_SLIP,
          codes.R_NEUTRAL, codes.R_STUCK)
N_SAMPLES = 5           # Hopf samples per round
N_SEEDED = 3            # Hopf samples of a continued step, at most (the shape known)
LOOKAHEAD = 8           # continuation steps predicted from one history, run together
RESOLVABLE = 2.0 * RTOL_FLOOR   # lowest rtol asked of a Hopf sample's cycle
MAX_OFFSET = 0.015      # widest relative spacing of the Hopf samples (the fifth stays
                        # well above the grazing, ~10 % below the Hopf point)
MAX_TRANSITIONS = 8     # regime changes kept per point (the first ones along the axis)
STUCK = math.nan        # xdot0 of a request: start stuck on the belt (xdot0 = v)
RETRY = (codes.UNCONVERGED, codes.STEP_BUDGET)  # retried from rest on the belt
BAND = 1e-6             # relative width next to a grazing where cycles get snapped
                        # onto the grazing orbit (measured ~3e-7 at tol 1e-10)
N_GRAZE = 3             # slip cycles of a seeded grazing step, at most
SEED_SPACING = 2 * BAND  # their relative spacing (beyond the band, close enough that
                         # the quadratic and linear roots agree to ~1e-11 relative)


# ------------------------------------------------------------- root solver
def bracketed_root(f, a: float, b: float, xtol: float, maxiter: int = 200) -> float:
    """Root of ``f`` in the bracket ``[a, b]`` (``f(a) f(b) <= 0``) to ``xtol``.

    Illinois (modified regula falsi): the end that stays twice in a row has its
    value halved, so both ends move and convergence is superlinear; a step that
    does not halve the bracket within three iterations is replaced by bisection.

    Raises
    ------
    ValueError
        If ``f(a)`` and ``f(b)`` have the same sign (no bracket).
    """
    fa, fb = float(f(a)), float(f(b))
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if math.copysign(1.0, fa) == math.copysign(1.0, fb):
        raise ValueError(f"no bracket: f({a!r}) = {fa!r} and f({b!r}) = {fb!r} have "
                         "the same sign")
    kept = 0           # +1: b kept last time, -1: a kept
    widths = [abs(b - a)]
    for _ in range(maxiter):
        if abs(b - a) <= xtol:
            break
        if len(widths) >= 4 and widths[-1] > 0.5 * widths[-4]:
            c = 0.5 * (a + b)
        else:
            c = (a * fb - b * fa) / (fb - fa)
            if not min(a, b) < c < max(a, b):
                c = 0.5 * (a + b)
        fc = float(f(c))
        if fc == 0.0:
            return c
        if math.copysign(1.0, fc) == math.copysign(1.0, fb):
            b, fb = c, fc
            if kept == -1:
                fa *= 0.5
            kept = -1
        else:
            a, fa = c, fc
            if kept == 1:
                fb *= 0.5
            kept = 1
        widths.append(abs(b - a))
    return (a * fb - b * fa) / (fb - fa) if fb != fa else 0.5 * (a + b)


# ------------------------------------------------------------- driving solvers
def _together(gens):
    """Run sub-solvers in lockstep inside one solver; returns their results."""
    results = [None] * len(gens)
    asks = {}
    for i, g in enumerate(gens):
        try:
            asks[i] = next(g)
        except StopIteration as stop:
            results[i] = stop.value
    while asks:
        rows = yield [r for i in asks for r in asks[i]]
        pos, nxt = 0, {}
        for i, req in asks.items():
            part = rows[pos:pos + len(req)]
            pos += len(req)
            try:
                nxt[i] = gens[i].send(part)
            except StopIteration as stop:
                results[i] = stop.value
        asks = nxt
    return results


def _drive(solvers, base: np.ndarray, col: int, o: np.ndarray, parallel: bool):
    """Run one solver per row of ``base`` to the end; returns (results, evaluations).

    A solver yields a list of requests ``(value, x0, xdot0)`` (``value`` goes in
    column ``col``; ``xdot0 = NaN`` starts stuck on the belt) and receives the
    observables rows (layout.OB_*) of their attractors.
    """
    n = len(solvers)
    results, evals, asks = [None] * n, np.zeros(n, np.int64), {}
    for i, g in enumerate(solvers):
        try:
            asks[i] = next(g)
        except StopIteration as stop:
            results[i] = stop.value
    while asks:
        owners = [i for i in asks for _ in asks[i]]
        P = base[owners].copy()
        req = np.array([r for i in asks for r in asks[i]], dtype=np.float64)
        P[:, col] = req[:, 0]
        P[:, layout.X0] = req[:, 1]
        P[:, layout.XD0] = np.where(np.isnan(req[:, 2]), P[:, layout.V], req[:, 2])
        out = np.empty((len(owners), layout.NOBS))
        execute.attractors(P, o, out, parallel)
        # A start inside a cycle that the search does not bring to an attractor
        # (a motion growing slowly onto a stick-slip cycle at low damping ends with
        # the budget spent) is retried once from rest on the belt at x = 0.
        again = np.flatnonzero(np.isin(out[:, layout.OB_STATUS], RETRY)
                               & ~np.isnan(req[:, 2]))
        if again.size:
            Q = P[again].copy()
            Q[:, layout.X0] = 0.0
            Q[:, layout.XD0] = Q[:, layout.V]
            redo = np.empty((again.size, layout.NOBS))
            execute.attractors(Q, o, redo, parallel)
            out[again] = redo
            for j in again:
                evals[owners[j]] += 1
        pos, nxt = 0, {}
        for i, r in asks.items():
            evals[i] += len(r)
            part = out[pos:pos + len(r)]
            pos += len(r)
            try:
                nxt[i] = solvers[i].send(part)
            except StopIteration as stop:
                results[i] = stop.value
        asks = nxt
    return results, evals


class _Point:
    """The fixed parameters of one search and what the solvers need from them."""

    def __init__(self, row: np.ndarray, along: str, tol: float | None = None):
        self.row, self.along, self.tol = row, along, tol
        self.col = COLUMNS[along]

    def at(self, value: float) -> np.ndarray:
        r = self.row.copy()
        r[self.col] = value
        return r

    def x_eq(self, value: float) -> float:
        """Steady-sliding position at ``along = value`` [cm], eq. (43)."""
        r = self.at(value)
        v = r[layout.V]
        if v == 0.0:
            return 0.0
        va = abs(v)
        return math.copysign(1.0, v) * (r[layout.RY] - r[layout.A1] * va
                                        + r[layout.A2] * va ** 3) / r[layout.K]

    def speed(self, value: float) -> float:
        return self.at(value)[layout.V]

    def contraction(self, value: float) -> float:
        """``|q| T`` at ``along = value``: q = (alpha1 - 3 alpha2 v^2)/m (eq. 46),
        T = 2 pi/omega; ``1 - mu`` of a small slip cycle there (mu its Floquet
        multiplier) is about this."""
        r = self.at(value)
        q = (r[layout.A1] - 3.0 * r[layout.A2] * r[layout.V] ** 2) / r[layout.M]
        return abs(q) * 2.0 * math.pi * math.sqrt(r[layout.M] / r[layout.K])

    def fit_variable(self, value):
        """The variable in which A^2 is fitted: v^2 along v (q is linear in it)."""
        return np.asarray(value) ** 2 if self.along == "v" else np.asarray(value)


def _ok(row) -> bool:
    return int(row[layout.OB_STATUS]) == codes.OK


def _regime(row) -> int:
    return int(row[layout.OB_REGIME])


# ------------------------------------------------------------------ Hopf point
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
            row = pt.at(r)
            omega = math.sqrt(row[layout.K] / row[layout.M])
            scale = row[layout.RY] / row[layout.K] + abs(row[layout.V]) / omega
            reach = 0.05 * scale * np.sqrt(np.arange(1, N_SAMPLES + 1))
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
    row = pt.at(guess)
    omega = math.sqrt(row[layout.K] / row[layout.M])
    dA = 2.0 * (pt.tol or 0.0) * (row[layout.RY] / row[layout.K]
                                  + abs(row[layout.V]) / omega)
    amp = np.sqrt([a2(0), a2(1)])
    moved = _shaped_root(w[0], (amp[0] + dA) ** 2, w[1], (amp[1] - dA) ** 2, shape, hi)
    err += abs(math.sqrt(moved) - root) if np.isfinite(moved) else math.inf
    got = np.array([r[layout.OB_X_MAX] - pt.x_eq(u) for r, u in zip(samples, us)])
    n = got.size
    full = np.r_[got, got[-1] * np.sqrt(np.arange(n + 1, N_SAMPLES + 1) / n)]
    return {"value": root, "error": err, "status": LOCATED, "reach": full,
            "shape": shape}


# ----------------------------------------------------------------- stick onset
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
    any is known): a start outside would touch the belt on the way in and, within
    the graze tolerance, be snapped onto the grazing orbit itself. A cycle that
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
        # belt within the graze tolerance and are snapped onto the grazing orbit
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


# ---------------------------------------------------------------- label changes
def _bisect(pt: _Point, a: float, b: float, ra: int, rb: int, xtol: float, start):
    """Solver: bisection on the regime labels between ``a`` (regime ``ra``) and
    ``b`` (regime ``rb``). Returns ``dict(value, width, status)``."""
    while abs(b - a) > xtol:
        c = 0.5 * (a + b)
        (row,) = yield [(c, *start)]
        if not _ok(row):
            return {"value": 0.5 * (a + b), "width": abs(b - a), "status": FAILED}
        if _regime(row) == ra:
            a = c
        elif _regime(row) == rb:
            b = c
        else:       # a third regime inside: two changes, not one
            return {"value": 0.5 * (a + b), "width": abs(b - a),
                    "status": INCONSISTENT}
    return {"value": 0.5 * (a + b), "width": abs(b - a), "status": LOCATED}


# ------------------------------------------------------------------ one point
def _empty():
    return {"v_hopf": math.nan, "v_hopf_error": math.nan, "hopf_status": ABSENT,
            "v_stick_onset": math.nan, "v_stick_onset_width": math.nan,
            "stick_status": ABSENT, "transitions": [], "hopf_reach": None,
            "hopf_shape": None}


def _hopf_guess(pt, values, rows, j, side, offset):
    """Secant of A^2 (in the fit variable) on the two scan cycles nearest the
    change between values[j] and values[j+1]; the midpoint when they are missing."""
    ic = j if side < 0 else j + 1
    ie = j + 1 if side < 0 else j
    mid = 0.5 * (values[j] + values[j + 1])
    i2 = ic + side
    if not (0 <= i2 < len(values)) or not _ok(rows[i2]) or \
            not _regime(rows[i2]) == _regime(rows[ic]) == codes.R_SLIP_CYCLE:
        return mid, None
    w = pt.fit_variable(np.array([values[ic], values[i2]]))
    a2 = np.array([rows[ic][layout.OB_AMPLITUDE], rows[i2][layout.OB_AMPLITUDE]]) ** 2
    if a2[0] == a2[1]:
        return mid, None
    w0 = w[0] - a2[0] * (w[1] - w[0]) / (a2[1] - a2[0])
    r = (math.sqrt(w0) if w0 > 0 else math.nan) if pt.along == "v" else w0
    lo, hi = sorted((values[ic], values[ie]))
    if not lo < r < hi:
        return mid, None
    # seeds: A^2 linear in the fit variable, through the scan's nearest cycle
    offset = _hopf_offset(pt, r, side, offset)
    us = r * (1.0 + side * offset * np.arange(1, N_SAMPLES + 1))
    amp = np.sqrt(a2[0] * np.abs(pt.fit_variable(us) - w0) / abs(w[0] - w0))
    return r, amp


def _changes(us, rows):
    """Indices j with a change of proper regimes between scan points j and j+1.

    A cycle returned ``unresolved`` (next to the Hopf point, its numbers only
    estimates) keeps its label: the scan needs no more."""
    reg = [_regime(r) if _ok(r) or int(r[layout.OB_STATUS]) == codes.UNRESOLVED
           else -1 for r in rows]
    return reg, [j for j in range(len(us) - 1) if reg[j] != reg[j + 1]
                 and reg[j] in PROPER and reg[j + 1] in PROPER]


def _smooth_kind(pt, us, rows, reg, j):
    """"hopf", "graze" or None: the smooth indicator that serves the change at j."""
    pair = {reg[j], reg[j + 1]}
    if pair == {codes.R_SLIP_CYCLE, codes.R_EQUILIBRIUM}:
        return "hopf"
    if pair == {codes.R_SLIP_CYCLE, codes.R_STICK_SLIP}:
        js = j if reg[j] == codes.R_SLIP_CYCLE else j + 1
        if pt.speed(us[js]) - rows[js][layout.OB_XDOT_MAX] > 0.0:
            return "graze"      # a slip cycle below belt speed grazes it
    return None


def _locate_point(pt: _Point, values: np.ndarray, xtol: float, offset: float, start,
                  max_rounds: int = 80):
    """Solver: coarse scan over ``values``, label changes without a smooth indicator
    bisected to ``xtol`` (splitting where a third regime appears), then the Hopf
    point and the grazings solved on their indicators."""
    rows = yield [(u, *start) for u in values]
    us, rows = list(values), list(rows)
    res = _empty()
    for _round in range(max_rounds):
        reg, changes = _changes(us, rows)
        # label changes to xtol; Hopf brackets down to the sample spacing
        todo = [j for j in changes[:MAX_TRANSITIONS]
                if (_smooth_kind(pt, us, rows, reg, j) is None
                    and abs(us[j + 1] - us[j]) > xtol)
                or (_smooth_kind(pt, us, rows, reg, j) == "hopf"
                    and abs(us[j + 1] - us[j]) > 2.0 * offset * abs(us[j + 1]))]
        if not todo:
            break
        mids = [0.5 * (us[j] + us[j + 1]) for j in todo]
        got = yield [(u, *start) for u in mids]
        for u, row in sorted(zip(mids, got), key=lambda q: -q[0]):
            k = int(np.searchsorted(us, u))
            us.insert(k, u)
            rows.insert(k, row)
    reg, changes = _changes(us, rows)
    if any(r == -1 for r in reg):
        res["hopf_status"] = res["stick_status"] = FAILED
    changes = changes[:MAX_TRANSITIONS]
    kinds = [_smooth_kind(pt, us, rows, reg, j) for j in changes]
    subs = []
    for j, kind in zip(changes, kinds):
        if kind == "hopf":
            side = -1 if reg[j] == codes.R_SLIP_CYCLE else 1
            guess, amp = _hopf_guess(pt, us, rows, j, side, offset)
            subs.append(_hopf(pt, guess, side, offset, reach=amp))
        elif kind == "graze":
            js = j if reg[j] == codes.R_SLIP_CYCLE else j + 1
            jt = j + 1 if js == j else j
            subs.append(_graze(pt, us[jt], us[js], xtol, [(us[js], rows[js])]))
    found = iter((yield from _together(subs)) if subs else [])
    hopfs, grazes = [], []
    for j, kind in zip(changes, kinds):
        if kind is None:
            out = {"value": 0.5 * (us[j] + us[j + 1]), "width": abs(us[j + 1] - us[j]),
                   "status": LOCATED if abs(us[j + 1] - us[j]) <= xtol
                   else INCONSISTENT}
        else:
            out = next(found)
            (hopfs if kind == "hopf" else grazes).append(out)
        width = out["error"] if kind == "hopf" else out["width"]
        res["transitions"].append((out["value"], width, reg[j], reg[j + 1],
                                   out["status"]))
    if hopfs:
        # the Hopf point of the cycle branch: the highest (first from above)
        best = max(hopfs, key=lambda o: o["value"] if np.isfinite(o["value"])
                   else -math.inf)
        res.update(v_hopf=best["value"], v_hopf_error=best["error"],
                   hopf_status=best["status"], hopf_reach=best["reach"],
                   hopf_shape=best.get("shape"))
    elif res["hopf_status"] != FAILED:
        res["hopf_status"] = ABSENT
    if grazes:
        # the stick onset of the Hopf branch: the grazing nearest the Hopf point
        ref = res["v_hopf"] if np.isfinite(res["v_hopf"]) else values[-1]
        best = min(grazes, key=lambda o: abs(o["value"] - ref)
                   if np.isfinite(o["value"]) else math.inf)
        res.update(v_stick_onset=best["value"], v_stick_onset_width=best["width"],
                   stick_status=best["status"], graze_amp=best["amp"])
    elif res["stick_status"] != FAILED:
        res["stick_status"] = ABSENT
    return res


# ------------------------------------------------------------------ arguments
def _scan_values(grid: Grid, along: str, bracket, scan: int) -> np.ndarray:
    ax = grid.axis(along)
    if bracket is None:
        if not isinstance(ax, np.ndarray):
            raise ValueError(f"bracket is needed when {along!r} is not swept in the "
                             f"grid (got {along}={ax!r})")
        bracket = (float(ax.min()), float(ax.max()))
    if not (isinstance(bracket, (tuple, list)) and len(bracket) == 2):
        raise ValueError(f"bracket must be a pair (lo, hi) [{UNITS[along]}], got "
                         f"{bracket!r}")
    lo, hi = (float(x) for x in bracket)
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ValueError(f"bracket must be finite with lo < hi, got {bracket!r}")
    if along == "v" and lo <= 0.0:
        raise ValueError(f"bracket along v must lie in v > 0 (the motion is mirror "
                         f"symmetric in v), got lo = {lo!r}")
    if isinstance(scan, bool) or not isinstance(scan, (int, np.integer)) or scan < 3:
        raise ValueError(f"scan must be an integer >= 3 (coarse scan points), got "
                         f"{scan!r}")
    return np.linspace(lo, hi, int(scan))


def _check_search(along, xtol, offset):
    if along not in AXES[:6]:
        raise ValueError(f"along must be one of {AXES[:6]}, got {along!r}")
    for name, val in (("xtol", xtol), ("offset", offset)):
        if isinstance(val, bool) or not isinstance(val, (int, float)) or \
                not (math.isfinite(val) and val > 0):
            raise ValueError(f"{name} must be a finite number > 0, got {val!r}")
    if not offset < 0.1:
        raise ValueError(f"offset must be < 0.1 (relative distance of the Hopf "
                         f"samples), got {offset!r}")


def _other_grid(grid: Grid, along: str, placeholder: float) -> Grid:
    """``grid`` with ``along`` fixed (its rows carry a placeholder there)."""
    if not isinstance(grid, Grid):
        raise TypeError(f"grid must be a sweepcore.Grid, got {type(grid).__name__}")
    if grid.mode != "product":
        raise ValueError("locate_boundaries needs a product Grid (Grid(...)), not "
                         "Grid.points")
    kw = {n: grid.axis(n) for n in AXES}
    kw[along] = placeholder
    return Grid(**kw)


def _start(grid: Grid):
    x0, xd0 = grid.axis("x0"), grid.axis("xdot0")
    if isinstance(x0, np.ndarray) or isinstance(xd0, np.ndarray):
        raise ValueError("x0 and xdot0 must be scalars (one start for every search)")
    return (x0, STUCK if xd0 is None else xd0)


# ------------------------------------------------------------------- executors
def locate_chunk(base: np.ndarray, along: str, values: np.ndarray, xtol: float,
                 offset: float, start, o: np.ndarray, parallel: bool = False):
    """Boundaries of the points ``base`` (kernel rows): the task of one chunk."""
    pts = [_Point(row, along, float(o[layout.O_RTOL])) for row in base]
    solvers = [_locate_point(p, values, xtol, offset, start) for p in pts]
    results, evals = _drive(solvers, base, COLUMNS[along], o, parallel)
    for r, n in zip(results, evals):
        r["evaluations"] = int(n)
        for key in ("hopf_reach", "hopf_shape", "graze_amp", "graze_reach"):
            r.pop(key, None)
    return results


# ----------------------------------------------------------------- public API
def locate_boundaries(grid: Grid, along: str = "v", bracket=None, xtol: float = 1e-9,
                      scan: int = 32, offset: float = 5e-3, tol: float = 1e-10,
                      method: str = "auto", chunks: int | None = None, client=None,
                      scheduler=None, **options) -> xr.Dataset:
    """Hopf point, stick onset and every regime change along ``along``, to ``xtol``.

    Parameters
    ----------
    grid : Grid
        Parameter sets (kN, cm, s). Every point of the grid *without* the
        ``along`` axis gets its boundaries; ``along``, if swept, gives the bracket.
    along : str
        The parameter searched, default the belt speed ``v``.
    bracket : (lo, hi), optional
        Search interval [units of ``along``]; default the range of ``along`` in
        ``grid``. Along v it must lie in v > 0.
    xtol : float
        Width of the final bracket of the stick onset and of label changes
        [units of ``along``].
    scan : int
        Points of the coarse scan that brackets the changes (an interval narrower
        than the scan step with two changes in it is missed).
    offset : float
        Relative distance between the Hopf samples (see the module notes).
    tol : float
        Tolerance of every attractor search (:func:`sweepcore.attractor`); it
        limits the accuracy of the indicators (benchmarks/README.md).
    method, **options
        As :func:`sweepcore.sweep`.
    chunks, client, scheduler
        As :func:`sweepcore.sweep`: one task per chunk of points, run by numba
        threads in this process (default), a dask local scheduler or a
        distributed cluster. Results do not depend on them.

    Returns
    -------
    xarray.Dataset
        Over the grid's other swept dimensions (CF-1.11, units on every
        variable): ``v_hopf`` and ``v_hopf_error`` (the Hopf point and the
        estimated error of its extrapolation), ``v_stick_onset`` and
        ``v_stick_onset_width`` (its uncertainty), their ``*_status`` flags
        (located, absent, attractor_failed, inconsistent), the analytic ``v_star``
        and the averaging estimate ``v_stick_onset_estimate = 2 v*/sqrt(5)``,
        ``evaluations`` (attractors computed) and, along ``transition``, every
        change found in the scan: ``transition_value``, ``transition_width``,
        ``regime_below``, ``regime_above``, ``transition_status``. (With
        ``along`` other than v the names keep the ``v_`` prefix; units follow
        ``along``.)
    """
    _check_search(along, xtol, offset)
    values = _scan_values(grid, along, bracket, scan)
    o = make_options(method, tol=tol, **options)
    kind, target = execute.resolve(client, scheduler)
    other = _other_grid(grid, along, float(values[0]))
    start = _start(grid)
    size = other.size
    execute.check_chunks(chunks)
    bounds = execute.chunk_bounds(size, size if chunks is None else min(int(chunks), size))
    parts = [None] * len(bounds)

    def task(i):
        rows = other.rows(*bounds[i])
        return locate_chunk, (rows, along, values, xtol, offset, start, o)
    execute.run(kind, target, range(len(bounds)), task, parts.__setitem__)
    results = [r for part in parts for r in part]
    call = (f"sweepcore.locate_boundaries({grid!r}, along={along!r}, "
            f"bracket={(float(values[0]), float(values[-1]))!r}, xtol={xtol!r}, "
            f"scan={scan!r}, offset={offset!r}, tol={tol!r}, method={method!r})")
    return _dataset(other, along, results, o, method, call, transitions=True)


def _predict(xs, ys, x):
    """Linear extrapolation of the last two points, in log-log when all > 0
    (v* ~ alpha2^-1/2 is a straight line there)."""
    (x1, x2), (y1, y2) = xs[-2:], ys[-2:]
    if min(x1, x2, x, y1, y2) > 0.0:
        lx1, lx2, ly1, ly2 = map(math.log, (x1, x2, y1, y2))
        return math.exp(ly2 + (ly2 - ly1) * (math.log(x) - lx2) / (lx2 - lx1))
    return y2 + (y2 - y1) * (x - x2) / (x2 - x1)


def _continued_point(pt, values, xtol, offset, start, hist, over_value):
    """Solver: one step of the natural continuation, seeded by ``hist`` (the
    previous steps); falls back to a scan when the seeds do not bracket."""
    subs, kinds = [], []
    hx = hist["x"]
    if len(hist["hopf"]) >= 2:
        guess = _predict(hx[-2:], hist["hopf"][-2:], over_value)
        reach = hist["reach"][-1] * guess / hist["hopf"][-1]
        shape = hist["shape"][-1]
        subs.append(_seeded_hopf(pt, guess, offset, reach, shape, xtol)
                    if shape is not None else _hopf(pt, guess, -1, offset, reach=reach))
        kinds.append("hopf")
    if len(hist["graze"]) >= 2:
        guess = _predict(hx[-2:], hist["graze"][-2:], over_value)
        # slip cycles beyond the band where the labels already say stick (the
        # graze tolerance, ~1e-6 relative) and beyond the prediction's error
        delta = max(4.0 * hist["graze_err"], SEED_SPACING * guess)
        scale = guess / hist["graze"][-1]
        seeds = hist["graze_reach"][-1]
        same = abs(delta - hist["graze_delta"] * guess) <= 1e-9 * delta
        if seeds is not None and same:
            seeds = seeds * scale            # the same offsets: scaled cycles
        else:
            seeds = None
        subs.append(_seeded_graze(pt, guess, delta, xtol,
                                  hist["graze_amp"][-1] * scale, seeds,
                                  hist["graze_width"]))
        kinds.append("graze")
    found = yield from (_together(subs) if subs else _nothing())
    res = _empty()
    missing = {"hopf", "graze"} - {k for k, f in zip(kinds, found)
                                   if f["status"] == LOCATED}
    for kind, out in zip(kinds, found):
        if kind == "hopf" and out["status"] == LOCATED:
            res.update(v_hopf=out["value"], v_hopf_error=out["error"],
                       hopf_status=LOCATED, hopf_reach=out["reach"],
                       hopf_shape=out.get("shape"))
        elif kind == "graze" and out["status"] == LOCATED:
            res.update(v_stick_onset=out["value"], v_stick_onset_width=out["width"],
                       stick_status=LOCATED, guess_error=out.get("guess_error", 0.0),
                       graze_amp=out["amp"], graze_reach=out.get("seed_reach"),
                       graze_delta=out.get("delta", math.nan))
    res["fallback"] = bool(missing)
    if missing:
        full = yield from _locate_point(pt, values, xtol, offset, start)
        for key in (("v_hopf", "v_hopf_error", "hopf_status", "hopf_reach",
                     "hopf_shape")
                    if "hopf" in missing else ()) + \
                   (("v_stick_onset", "v_stick_onset_width", "stick_status")
                    if "graze" in missing else ()):
            if key == "stick_status" and "graze_amp" in full:
                res["graze_amp"] = full["graze_amp"]
            res[key] = full[key]
    return res


def _nothing():
    return []
    yield  # pragma: no cover - makes this a generator


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


def _history():
    """What the continuation carries from step to step."""
    return {"x": [], "hopf": [], "reach": [], "shape": [], "graze": [], "graze_amp": [],
            "graze_reach": [], "graze_delta": math.nan, "graze_err": 0.0,
            "graze_width": math.inf}


def continue_boundary(grid: Grid, over: str = "alpha2", along: str = "v",
                      bracket=None, xtol: float = 1e-9, scan: int = 32,
                      offset: float = 5e-3, tol: float = 1e-10, method: str = "auto",
                      **options) -> xr.Dataset:
    """The Hopf and stick-onset curves along ``over`` by natural continuation.

    Each step is seeded by the previous ones: the two boundaries are predicted by
    linear extrapolation of the last two (in log-log when positive), for
    ``LOOKAHEAD`` steps at once (one batch of attractors); the Hopf point is
    extrapolated from three cycles with the shape of A^2 fitted on an earlier
    step (:func:`_seeded_hopf`, five cycles where that check fails), started on
    the previous step's cycles, scaled by the predicted ratio;
    the grazing is extrapolated from two slip cycles just above its prediction
    (spacing 2e-6 relative, or four times the last prediction error), started on the
    previous step's cycles, with one stick-slip check below it. Where the root
    through the two samples does not agree with the prediction to xtol/4, a
    third cycle is asked (and so for the Hopf point, :func:`_seeded_hopf`). A step whose seeds
    do not bracket falls back to the full scan of :func:`locate_boundaries` (so do
    the first two, and the ``continued`` flag says which). About 6 attractors a
    step against 32 for the scan alone. Only ``v`` is supported as ``along`` here.

    Parameters
    ----------
    grid : Grid
        ``over`` swept (1-D, in the order to follow), every other axis fixed
        except ``along`` (whose range is the default bracket).
    over : str
        The continuation parameter, default alpha2.
    along, bracket, xtol, scan, offset, tol, method, **options
        As :func:`locate_boundaries`.

    Returns
    -------
    xarray.Dataset
        As :func:`locate_boundaries` over ``over`` (without the ``transition``
        variables), plus ``continued`` (1 where the step was seeded, 0 where it
        fell back to a scan).
    """
    _check_search(along, xtol, offset)
    if along != "v":
        raise ValueError(f"continue_boundary follows boundaries along v only, got "
                         f"along={along!r}")
    values = _scan_values(grid, along, bracket, scan)
    o = make_options(method, tol=tol, **options)
    other = _other_grid(grid, along, float(values[0]))
    if other.swept != (over,):
        raise ValueError(f"continue_boundary needs {over!r} swept and every other "
                         f"parameter fixed (apart from {along!r}); swept: "
                         f"{other.swept}")
    start = _start(grid)
    xs = np.asarray(other.axis(over))
    base = other.rows(0, other.size)
    hist = _history()
    results = []
    i = 0
    while i < len(base):
        # the next steps, all predicted from the same history, in one batch: the
        # kernel gets ~10 LOOKAHEAD attractors a round instead of ~10
        n = LOOKAHEAD if len(hist["x"]) >= 2 else 1
        rows = base[i:i + n]
        solvers = [_continued_point(_Point(row, along, tol), values, xtol, offset,
                                    start, hist, xs[i + j])
                   for j, row in enumerate(rows)]
        found, evals = _drive(solvers, rows, COLUMNS[along], o, True)
        errs = []
        for j, (res, ne) in enumerate(zip(found, evals)):
            res["evaluations"] = int(ne)
            res["continued"] = int(not res.pop("fallback"))
            ok_h = res["hopf_status"] == LOCATED
            ok_g = res["stick_status"] == LOCATED
            if not (ok_h and ok_g):      # restart the histories where a curve is lost
                hist = _history()
            else:
                hist["x"].append(xs[i + j])
                hist["hopf"].append(res["v_hopf"])
                hist["reach"].append(res["hopf_reach"])
                hist["shape"].append(res.get("hopf_shape"))
                hist["graze"].append(res["v_stick_onset"])
                hist["graze_amp"].append(res["graze_amp"])
                hist["graze_reach"].append(res.get("graze_reach"))
                hist["graze_delta"] = res.get("graze_delta", math.nan)
                hist["graze_width"] = res["v_stick_onset_width"]
                errs.append(max(res.pop("guess_error", 0.0), xtol)
                            if res["continued"] else abs(values[1] - values[0]) / 8)
                hist["graze_err"] = max(errs)
            for key in ("hopf_reach", "hopf_shape", "guess_error", "graze_amp",
                        "graze_reach", "graze_delta"):
                res.pop(key, None)
            results.append(res)
        i += len(rows)
    call = (f"sweepcore.continue_boundary({grid!r}, over={over!r}, along={along!r}, "
            f"bracket={(float(values[0]), float(values[-1]))!r}, xtol={xtol!r}, "
            f"scan={scan!r}, offset={offset!r}, tol={tol!r}, method={method!r})")
    ds = _dataset(other, along, results, o, method, call, transitions=False)
    ds["continued"] = xr.Variable(
        other.dims, np.array([r["continued"] for r in results], np.int8),
        {"units": "1", "long_name": "step seeded by the previous ones",
         "flag_values": np.array([0, 1], np.int8),
         "flag_meanings": "scanned continued"})
    return ds


# ------------------------------------------------------------------- Dataset
def _flag(meanings: dict, long_name: str) -> dict:
    keys = sorted(meanings)
    return {"units": "1", "long_name": long_name,
            "flag_values": np.array(keys, np.int8),
            "flag_meanings": " ".join(meanings[k] for k in keys)}


def _analytic(ds: xr.Dataset) -> xr.Dataset:
    """``v_star`` and the averaging estimate of the stick onset beside the located
    boundaries (along v)."""
    vs_units, vs_long, vs_comment = variables.ANALYTIC["v_star"]
    vs = xr.apply_ufunc(_v_star, ds["alpha1"], ds["alpha2"])
    ds["v_star"] = xr.Variable(vs.dims, np.asarray(vs.values, np.float64),
                               {"units": vs_units, "long_name": vs_long,
                                "comment": vs_comment})
    ds["v_stick_onset_estimate"] = xr.Variable(
        vs.dims, 2.0 / math.sqrt(5.0) * np.asarray(vs.values, np.float64),
        {"units": "cm s-1", "long_name": "averaging estimate 2 v*/sqrt(5) of the "
                                         "stick onset",
         "comment": "the averaged cycle's velocity amplitude 2 sqrt(v*^2 - v^2) "
                    "reaches v"})
    return ds


def _dataset(other: Grid, along: str, results, o, method, call,
             transitions: bool) -> xr.Dataset:
    from .sweep import REFERENCE, _version
    dims, shape = other.dims, other.shape
    units = UNITS[along]

    def field(key, dtype=np.float64):
        return np.array([r[key] for r in results], dtype).reshape(shape)

    status = _flag(SEARCH_NAMES, "outcome of the boundary search")
    data = {
        "v_hopf": (field("v_hopf"), {
            "units": units, "long_name": "measured Hopf point (cycle | equilibrium)",
            "comment": "root of the cycle's amplitude squared, a cubic in v^2 through "
                       "four cycles at relative distances offset, 2 offset, ... "}),
        "v_hopf_error": (field("v_hopf_error"), {
            "units": units, "long_name": "estimated error of the Hopf point",
            "comment": "difference between the roots of the cubics through samples "
                       "1-4 and 2-5; continued steps: between the root and the "
                       "prediction (or a third sample's root), plus the move of "
                       "the root under amplitude errors of 2 tol L"}),
        "hopf_status": (field("hopf_status", np.int8),
                        {**status, "long_name": "outcome of the Hopf point search"}),
        "v_stick_onset": (field("v_stick_onset"), {
            "units": units, "long_name": "measured stick onset (slip cycle grazes the "
                                         "belt)",
            "comment": "root of v - xdot_max on the slip cycles (safeguarded secant) "
                       "inside a bracket of stick_slip | slip_cycle labels"}),
        "v_stick_onset_width": (field("v_stick_onset_width"), {
            "units": units, "long_name": "uncertainty of the stick onset",
            "comment": "last correction of the root estimate, or the distance "
                       "between the roots of the polynomials of two degrees"}),
        "stick_status": (field("stick_status", np.int8),
                         {**status, "long_name": "outcome of the stick-onset search"}),
        "evaluations": (field("evaluations", np.int64), {
            "units": "1", "long_name": "attractors computed for the point"}),
    }
    ds = xr.Dataset({k: (dims, v, a) for k, v, a in
                     ((k, *val) for k, val in data.items())}, other.coords())
    ds = ds.drop_vars([along] + [n for n in ("x0", "xdot0") if n in ds.coords])
    if transitions:
        n = max([len(r["transitions"]) for r in results] + [1])
        val = np.full(shape + (n,), np.nan)
        wid = np.full(shape + (n,), np.nan)
        below = np.full(shape + (n,), -1, np.int8)
        above = np.full(shape + (n,), -1, np.int8)
        st = np.full(shape + (n,), ABSENT, np.int8)
        for flat, r in enumerate(results):
            idx = np.unravel_index(flat, shape) if shape else ()
            for k, (x, w, rb, ra, s) in enumerate(r["transitions"]):
                val[idx + (k,)], wid[idx + (k,)] = x, w
                below[idx + (k,)], above[idx + (k,)], st[idx + (k,)] = rb, ra, s
        regimes = {-1: "none", **codes.REGIME_NAMES}
        tdims = dims + ("transition",)
        ds["transition"] = xr.Variable("transition", np.arange(n), {
            "units": "1", "long_name": "index of the regime change along " + along})
        ds["transition_value"] = xr.Variable(tdims, val, {
            "units": units, "long_name": f"{LONG_NAMES[along]} of a regime change"})
        ds["transition_width"] = xr.Variable(tdims, wid, {
            "units": units, "long_name": "final bracket width (Hopf: error estimate)"})
        ds["regime_below"] = xr.Variable(tdims, below, _flag(regimes,
                                                             "regime below the change"))
        ds["regime_above"] = xr.Variable(tdims, above, _flag(regimes,
                                                             "regime above the change"))
        ds["transition_status"] = xr.Variable(tdims, st, {
            **status, "long_name": "outcome of the search of the change"})
    if along == "v":        # the analytic values to compare with
        ds = _analytic(ds)
    now = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    ds.attrs.update({
        "Conventions": "CF-1.11",
        "title": "Regime boundaries of the stick-slip friction oscillator",
        "history": f"{now} sweepcore {_version()}: {call}",
        "source": f"sweepcore {_version()}: root solves on smooth indicators of the "
                  "attractor (sweepcore.boundaries)",
        "references": REFERENCE,
        "comment": "Units kN, cm, s. Status flags say where a boundary was not "
                   "located and why.",
        "along": along,
        "method": method,
        "tol": float(o[layout.O_RTOL]),
        "sweepcore_kind": "boundaries",
    })
    return ds
