"""Slip cycles as fixed points of the return map, stable and unstable alike.

The attractor search (``attractor.py``) follows the motion, so it only ever finds
what attracts. Here the return map ``a -> P(a)`` of the maxima of x (minima for
v < 0) is solved for its fixed points directly: ``G(a) = P(a) - a`` is scanned
outward from x_eq on a geometric ladder of amplitudes, every change of sign brackets
a cycle, and safeguarded Newton (the exact slope of ``return_map.py``; bisection
where Newton leaves the bracket) refines it. Newton does not care about stability:
a cycle with ``P' > 1`` (unstable; in the plane, the boundary between two basins)
is found like a stable one. A cycle is accepted on the verified residual of the
attractor search, ``|P(a) - a| / |1 - P'| <= tol L / 2`` from a return computed at
``rtol <= tol |1 - P'| / 2`` (the integration noise is amplified by
``1 / |1 - P'|`` in the fixed point, on either side of 1).

Only stop-free slip cycles are searched: a return that reaches belt speed (or
reverses) counts as growing (outside such a cycle the motion sticks); one that only
touches it within the touch tolerance next to a bracketed cycle is computed again at
finer tolerances first (``_refine``: next to a fold the unstable cycle lies there). The ladder's
spacing decides which cycles are seen: two cycles closer together than one rung, or
a cycle smaller than the lowest rung (next to a Hopf point), can be missed.
"""
import math

import numpy as np
from .jit import kernel

from . import codes
from .attractor import answer_cycle, clear, method_status, resolve_options
from .driver import advance, init_state
from .excitations import autonomous
from .law import x_eq
from .layout import (K, M, NA, NO, NOBS, NP, NS, O_GRAZE, O_LX, O_MAX_STEPS, O_RTOL,
                     OB_NSTEPS, OB_REGIME, OB_STATUS, OB_X_MAX, OB_X_MIN, S_N, S_TOUCH,
                     S_X, V)
from .return_map import return_slope
from .sections import RTOL_FLOOR, sharpen_touch

N_RUNGS = 40          # amplitudes of the scan, geometric from LOWEST to TOP
LOWEST = 1e-4         # lowest rung, of the length scale
TOP = 2.0             # highest rung, of |v|/omega (a damped or nonlinear slip cycle can
                      # reach farther in x than the circle of radius |v|/omega)
MAX_CYCLES = 4        # cycles reported per point


@kernel
def one_return(meth, p, lw, o, a, st, acc):
    """One return of the section map from ``(x = a, xdot = 0)``: ``(P(a), P'(a),
    ok, touched)``; ok False when the motion sticks, stops or reverses before the
    next section (the return leaves the stop-free slip region) or the integration
    fails; ``touched``: that stop or stick was a tangential touch, decided within
    the touch tolerance only (``driver.touch_tol``, layout S_TOUCH). ``acc`` holds
    the return's quadratures, ``st[S_N]`` counts the steps."""
    v = p[V]
    n = st[S_N]
    init_state(st, a, 0.0, p, lw, autonomous(), o)
    st[S_N] = n
    st[S_TOUCH] = 0.0
    clear(acc)
    section = codes.EV_XMAX if v > 0.0 else codes.EV_XMIN
    t_max = 4.0 * 2.0 * math.pi * math.sqrt(p[M] / p[K])
    for _ in range(64):
        ev, status = advance(meth, st, p, lw, autonomous(), o, acc, t_max)
        if status != codes.OK or ev == codes.EV_STOP_TIME:
            return np.nan, np.nan, False, False
        if ev == section:
            a1 = st[S_X]
            return a1, return_slope(p, lw, a, a1, acc, 0.0), True, False
        if ev != codes.EV_XMIN and ev != codes.EV_XMAX:
            # a stick or a stop: not stop-free
            return np.nan, np.nan, False, st[S_TOUCH] > 0.0
    return np.nan, np.nan, False, False


@kernel
def _refine(meth, p, lw, o, lo, g_lo, dp_lo, hi, st, acc):
    """Fixed point of G = P(a) - a in the bracket [lo, hi] (G(lo) = g_lo, P'(lo) =
    dp_lo, G(hi) of the other sign). Returns ``(a, P'(a), ok, floor)``; on ok,
    ``acc`` holds the accepted return.

    First safeguarded Newton (bisection where Newton leaves the bracket) at the
    user's tolerance, to a residual of tol L / 2; then the returns are recomputed at
    ``rtol = tol |1 - P'| / 2`` and Newton goes on, unbracketed, from there: the
    fixed point of the finer returns is off the coarse one by up to the coarse
    noise amplified by ``1 / |1 - P'|``, so the coarse bracket no longer holds it.

    A return that stops at a tangential touch of the belt may as well pass just
    below it: next to a fold the unstable cycle lies within the touch tolerance of
    the belt speed. Where Newton from the last return on the ``lo`` side puts the
    fixed point between it and the touched start, that start is computed again at
    a hundredth of the tolerance in force (whose touch tolerance is a hundredth
    too), down to RTOL_FLOOR, before it counts as leaving the slip region (the
    starts whose return just touches the belt bound that region whether or not a
    cycle lies next to them: above a fold Newton puts the fixed point beyond them).
    ``floor`` (returned True with ok False): such touches remained at RTOL_FLOOR, a
    cycle within float64's touch tolerance of the belt."""
    tol = o[O_RTOL]
    lx = o[O_LX]
    a = 0.5 * (lo + hi)
    fine = False
    touched_floor = False
    for _ in range(80):
        a1, dP, ok, touched = one_return(meth, p, lw, o, a, st, acc)
        if not ok:
            # Newton from lo: the fixed point inside (lo, a] may hide in the touch
            r = -g_lo / ((dp_lo - 1.0) * (a - lo)) if dp_lo != 1.0 else -1.0
            touched = touched and 0.0 < r <= 1.0
            if touched and sharpen_touch(o):
                continue                          # the same start again, finer
            touched_floor = touched_floor or touched
            if fine:
                return a, np.nan, False, touched_floor
            hi = a                                # outside the slip region: shrink
            a = 0.5 * (lo + hi)
            if abs(hi - lo) <= 4.0 * RTOL_FLOOR * lx:
                return a, np.nan, False, touched_floor
            continue
        g = a1 - a
        gap = 1.0 - dP
        need = max(0.5 * tol * abs(gap), RTOL_FLOOR)
        if abs(g) <= 0.5 * tol * lx * abs(gap):
            if fine:
                return a, dP, True, 0.5 * tol * abs(gap) < RTOL_FLOOR
            fine = True
            o[O_RTOL] = min(o[O_RTOL], need)      # verify on finer returns
            continue
        a_new = a - g / (dP - 1.0)
        if not fine:
            if (g < 0.0) == (g_lo < 0.0):
                lo, g_lo, dp_lo = a, g, dP
            else:
                hi = a
            if not (min(lo, hi) < a_new < max(lo, hi)):
                a_new = 0.5 * (lo + hi)
            if abs(hi - lo) <= 4.0 * RTOL_FLOOR * lx:
                return a, dP, False, touched_floor
        a = a_new
    return a, np.nan, False, touched_floor


@kernel
def slip_cycles(meth, p, lw, o_in, out):
    """Every stop-free slip cycle the scan brackets (module docstring): up to
    ``MAX_CYCLES`` rows of observables (layout OB_*) in ``out``, in increasing
    amplitude, the unused rows NaN with status ``unconverged``. ``floquet`` > 1 marks
    an unstable cycle. Returns the number found."""
    for j in range(out.shape[0]):
        for i in range(NOBS):
            out[j, i] = np.nan
        out[j, OB_NSTEPS] = 0.0
    if p.shape[0] != NP or o_in.shape[0] != NO or out.shape[1] != NOBS:
        out[0, OB_REGIME] = codes.R_FAILED
        out[0, OB_STATUS] = codes.BAD_ROW
        return 0
    o = resolve_options(meth, p, lw, autonomous(), o_in)
    if method_status(meth, p, lw, autonomous(), o) != codes.OK or p[V] == 0.0 or meth == codes.GPS:
        return 0
    v = p[V]
    sg = 1.0 if v > 0.0 else -1.0
    xe = x_eq(p, lw)
    lx = o[O_LX]
    omega = math.sqrt(p[K] / p[M])
    top = TOP * abs(v) / omega
    st = np.zeros(NS)
    acc = np.empty(NA)
    ratio = (top / (LOWEST * lx)) ** (1.0 / (N_RUNGS - 1))
    found = 0
    a_prev = np.nan
    g_prev = np.nan
    dp_prev = np.nan
    for k in range(N_RUNGS):
        a = xe + sg * LOWEST * lx * ratio ** k
        o[O_RTOL] = o_in[O_RTOL]
        o[O_GRAZE] = o_in[O_GRAZE]
        a1, dP, ok, _touched = one_return(meth, p, lw, o, a, st, acc)
        # a return that leaves the slip region (it reaches the belt) is growing: a
        # change of sign after contracting returns (a false bracket refines to
        # nothing: its residual never passes)
        g = a1 - a if ok else sg * np.inf
        if not math.isnan(g_prev) and (g < 0.0) != (g_prev < 0.0) \
                and found < out.shape[0]:
            a_c, dP_c, ok_c, floor = _refine(meth, p, lw, o, a_prev, g_prev, dp_prev, a,
                                             st, acc)
            if ok_c:       # acc holds the accepted return, at the verified tolerance
                answer_cycle(out[found], acc, 0.0, omega, codes.R_SLIP_CYCLE, dP_c,
                             floor, p, st[S_N])
                found += 1
            elif floor:    # a cycle within float64's touch tolerance of the belt:
                out[found, OB_REGIME] = codes.R_SLIP_CYCLE      # there, unresolved
                out[found, OB_STATUS] = codes.UNRESOLVED
                out[found, OB_X_MAX if v > 0.0 else OB_X_MIN] = a_c
                out[found, OB_NSTEPS] = st[S_N]
                found += 1
        if st[S_N] >= o[O_MAX_STEPS]:
            break
        a_prev = a
        g_prev = g
        dp_prev = dP
    for j in range(found, out.shape[0]):
        out[j, OB_STATUS] = codes.UNCONVERGED
        out[j, OB_NSTEPS] = st[S_N]
    return found

