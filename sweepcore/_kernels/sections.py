"""The attractor search at a Poincare section: history, decisions, Newton.

The section is ``xdot = 0`` at the maxima of x (minima for v < 0, so that v -> -v is
an exact mirror). At each section the search (``attractor.py``) pushes the return
just completed into the history (``push_section``) and asks what to do next:

* constant friction without damping (a neutral family): ``neutral_decision``;
* a still belt (no smooth return map, sections are stops): ``static_belt_decision``;
* a slip motion: ``slip_section``, which undoes a Newton step that left its
  itinerary, lets the normal form decide next to the Hopf point
  (``normal_form.nf_step``) and otherwise follows ``newton_decision``.

``newton_decision`` is pure (no writes): it maps the section history to an action.
The return map ``a -> P(a)`` of a slip cycle is solved by Newton's method with the
exact slope (``return_map.py``, Liouville); a fixed point is accepted on a verified
residual ``|P(a) - a| / (1 - P') <= tol L / 2`` from returns computed at
``rtol <= tol (1 - P') / 2``: the integrator's noise (~2 rtol L per return) is
amplified by ``1 / (1 - P')`` in the fixed point. Method gps follows its own map
(``own_map_step``): its discrete map is not the ODE's.
"""
import math

import numpy as np

from .jit import kernel

from . import codes
from .law import log_saltation, static_limits
from .layout import (A_XDMAX, A_XDMIN, A_XMAX, A_XMIN, ACC_LAST, ACC_SEC, NA, O_GRAZE,
                     O_RTOL,
                     S_T, S_X, S_ZD, V, W_A, W_A_FROM, W_E, W_E_JUMP, W_E_REST,
                     W_ERR_JUMP, W_FD_A0, W_FD_A1, W_FD_DELTA, W_FD_PROBE,
                     W_FD_SLOPE, W_JUMPED, W_LX, W_N_EV, W_N_SEC, W_NEWTON_REST,
                     W_ON_NF, W_RESET_SEEN, W_RTOL, W_RTOLH, W_SALT, W_SALTH,
                     W_T_LAST, W_T_OFF, W_TH, W_TOL)

# Lowest relative tolerance given to the integrator: below it, roundoff in the
# error estimate of dopri5 (weights rtol (L + |x|)) makes the controller erratic.
RTOL_FLOOR = 1e-14


@kernel(inline="always")
def sharpen_touch(o):
    """Lower the tolerance in force ``o[O_RTOL]`` a hundredfold (to RTOL_FLOOR at
    most) and the touch tolerance's floor ``graze`` with it (``driver.touch_tol``:
    max(graze, 20 rtol) |v|), to measure a touch again; False, changing nothing,
    where the floor is reached."""
    if o[O_RTOL] <= RTOL_FLOOR:
        return False
    o[O_RTOL] = max(0.01 * o[O_RTOL], RTOL_FLOOR)
    o[O_GRAZE] = 0.01 * o[O_GRAZE]
    return True

# actions (what the search does after a section); from TERMINAL on, the answer
FOLLOW = 0         # integrate the next return from where the motion is
EXPAND = 1         # ... the motion expands here (the normal form's jump stays marked)
NF_JUMP = 2        # move the motion to the normal form's cycle
NEWTON_JUMP = 3    # move the motion to the Newton iterate
TERMINAL = 4
ACCEPT = 4         # the last return is the cycle (its slope the Floquet multiplier)
ACCEPT_FLOOR = 5   # ... at the float64 floor of the integrator: status unresolved
ACCEPT_NF = 6      # the return measured from the normal form's cycle is the answer
NEUTRAL = 7        # neutral to float64 resolution: regime unknown (unresolved)
REST = 8           # the motion converges to x_eq


@kernel(inline="always")
def clear(acc):
    """Empty accumulators (sums 0, extrema at -inf/+inf)."""
    for i in range(NA):
        acc[i] = 0.0
    acc[A_XMAX] = -np.inf
    acc[A_XMIN] = np.inf
    acc[A_XDMAX] = -np.inf
    acc[A_XDMIN] = np.inf


@kernel
def jump(st, p, w, acc, a_new):
    """Move the motion to the section point a_new [cm] (xdot = 0) at the present
    time: the newest section value becomes a_new, the interval measured restarts,
    and a whole return is needed before the next decision."""
    st[S_X] = a_new
    st[S_ZD] = -p[V]
    w[W_A + 3] = a_new
    w[W_TH + 3] = st[S_T]
    w[W_N_SEC] = 1.0
    clear(acc[ACC_SEC])


@kernel
def note_event(w, p, lw, ev, x, mode0, mode1):
    """Count a phase event inside the return (its itinerary) and its saltation."""
    if ev != codes.EV_XMIN and ev != codes.EV_XMAX:
        w[W_N_EV] += 1.0
    if ev == codes.EV_NORMAL_STOP:
        w[W_SALT] += log_saltation(p, lw, x, mode0, mode1)


@kernel
def push_section(w, acc, x, t):
    """Shift the section history by the return just completed at x [cm], local
    time t [s]; the return's accumulators become ``acc[ACC_LAST]``."""
    for j in range(3):
        w[W_A + j] = w[W_A + j + 1]
        w[W_TH + j] = w[W_TH + j + 1]
    w[W_A + 3] = x
    w[W_TH + 3] = t
    w[W_E] = w[W_E + 1]
    w[W_E + 1] = w[W_E + 2]
    # the first section after a start or a reset ends a partial return: its
    # itinerary is unknown (-1), not that of a whole return
    w[W_E + 2] = w[W_N_EV] if w[W_N_SEC] >= 1.0 else -1.0
    w[W_N_EV] = 0.0
    w[W_SALTH] = w[W_SALTH + 1]
    w[W_SALTH + 1] = w[W_SALT]
    w[W_SALT] = 0.0
    w[W_RTOLH] = w[W_RTOLH + 1]
    w[W_RTOLH + 1] = w[W_RTOL]
    w[W_N_SEC] += 1.0
    if w[W_N_SEC] >= 2.0:
        last = acc[ACC_LAST]
        sec = acc[ACC_SEC]
        for i in range(NA):
            last[i] = sec[i]
        w[W_T_LAST] = w[W_T_OFF] + w[W_TH + 2]
    clear(acc[ACC_SEC])


@kernel
def neutral_decision(w, p, lw):
    """Constant friction without damping: a neutral family, no contraction. A steady
    section is the answer (ACCEPT); a circle must also have gone round without
    touching the belt (one that touches is a transient, not a family member)."""
    if w[W_N_SEC] < 3.0:
        return FOLLOW
    d1 = w[W_A + 3] - w[W_A + 2]
    T1 = w[W_TH + 3] - w[W_TH + 2]
    T0 = w[W_TH + 2] - w[W_TH + 1]
    tol = w[W_TOL]
    if abs(d1) <= tol * w[W_LX] and abs(T1 - T0) <= 10.0 * tol * T1 \
            and not (static_limits(p, lw)[0] > 0.0 and w[W_E + 2] > 0):
        return ACCEPT
    return FOLLOW


@kernel
def static_belt_decision(w, o):
    """v = 0: sections are stops on the switching line (no smooth map); a steady
    geometric sequence of returns is the answer. The integrator's error per return is
    ~rtol (lx + |x|), so the scale includes the cycle, and the returns are computed
    at rtol <= tol (1 - rho) / 2 (the noise amplification of ``newton_decision``)."""
    if w[W_N_SEC] < 3.0:
        return FOLLOW
    tol = w[W_TOL]
    d1 = w[W_A + 3] - w[W_A + 2]
    d0 = w[W_A + 2] - w[W_A + 1]
    rho = d1 / d0 if d0 != 0.0 else 0.0
    rem = abs(d1) * abs(rho) / (1.0 - abs(rho)) if abs(rho) < 1.0 else np.inf
    scale = w[W_LX] + abs(w[W_A + 3])
    need0 = 0.5 * tol * (1.0 - abs(rho))
    if abs(d1) <= tol * scale and rem <= tol * scale and \
            w[W_RTOLH + 1] <= max(need0, RTOL_FLOOR) * 1.000001:
        return ACCEPT
    if abs(rho) < 1.0 and need0 < w[W_RTOL]:
        w[W_RTOL] = max(need0, RTOL_FLOOR)
        o[O_RTOL] = w[W_RTOL]
    return FOLLOW


@kernel
def newton_decision(a0, a1, dP, xe, e1, e2, rtol_h0, rtol_h1, rtol_int, tol, lx,
                    after_jump, err_jump, newton_rest, nf_here, on_nf, a_nf):
    """The next action on a slip motion's return map: pure, no writes.

    Inputs: the last return ``a0 -> a1`` [cm] with slope ``dP``, x_eq, the phase events
    ``e1, e2`` of the last two returns (the itinerary), the tolerances they were
    computed at (``rtol_h0, rtol_h1``) and the one in force, the user's ``tol`` and
    length scale ``lx``; whether the last section was a Newton jump (``after_jump``,
    from ``err_jump`` away), the returns still to follow without Newton
    (``newton_rest``); whether the normal form may decide here (``nf_here``), whether
    the motion was just placed on its cycle (``on_nf``) and its cycle's section value
    ``a_nf`` (NaN where it is not accurate to tol L / 2).

    Returns ``(action, value, rtol, newton_rest, err0)``: the action (module
    constants), its value (the jump target [cm] or the Floquet multiplier), the
    tolerance and rest count to use next, and the estimated distance of a0 from
    the fixed point [cm].
    """
    F = a1 - a0
    gap = 1.0 - dP
    # The return map computed at rtol is wrong by ~ rtol lx / |a - x_eq| in its slope
    # (the integrator's own growth or decay); a slope within that noise of 1 is not
    # resolved at this tolerance.
    noise = 4.0 * rtol_h1 * lx / max(abs(a1 - xe), 1e-300)
    resolved = abs(gap) > noise
    if gap <= -noise:
        return EXPAND, 0.0, rtol_int, newton_rest, np.inf     # expanding: follow
    need = 0.5 * tol * gap
    floor = need < RTOL_FLOOR or (not resolved and rtol_h1 <= RTOL_FLOOR)
    if floor and nf_here:
        # too weak a contraction for float64 integration: next to the Hopf point,
        # where the normal form is accurate (if not: "unresolved")
        if on_nf and rtol_h1 <= tol:
            return ACCEPT_NF, 0.0, rtol_int, newton_rest, 0.0
        if not math.isnan(a_nf):
            return NF_JUMP, a_nf, rtol_int, newton_rest, 0.0
    if not resolved:
        if rtol_int > RTOL_FLOOR:
            return FOLLOW, 0.0, max(0.01 * rtol_int, RTOL_FLOOR), newton_rest, np.inf
        if e2 == 0 and abs(F) <= 4.0 * RTOL_FLOOR * lx:
            # neutral to float64 resolution, and the returns stand still: not even
            # the sign of the contraction is known, so not the regime
            return NEUTRAL, dP, rtol_int, newton_rest, np.inf
        return FOLLOW, 0.0, rtol_int, newton_rest, np.inf    # no step on this slope
    err0 = abs(F) / gap     # distance of a0 from the fixed point (Newton)
    # Newton iterates at the tolerance in force until its noise (~4 rtol lx / gap) is
    # reached; only then is the tolerance lowered for the last returns.
    fine = rtol_h1 <= max(need, RTOL_FLOOR) * 1.000001
    accept = 0.5 * tol * lx
    if floor:
        accept = max(accept, 4.0 * RTOL_FLOOR * lx / gap)
    if err0 <= accept and fine:
        return (ACCEPT_FLOOR if floor else ACCEPT), dP, rtol_int, newton_rest, err0
    # 10 % below the bound: the slope moves in its last digits from one iterate to
    # the next, and the bound must still hold for the accepted return
    tight = max(0.9 * need, RTOL_FLOOR)
    if not fine and err0 <= 4.0 * rtol_h1 * lx / gap:
        rtol_int = tight          # the tolerance's noise is reached: lower it
    if newton_rest > 0:
        return FOLLOW, 0.0, rtol_int, newton_rest - 1, err0
    if after_jump and err0 >= 0.5 * err_jump and rtol_h1 == rtol_h0 \
            and err0 > 4.0 * rtol_h1 * lx / gap:
        # the last jump did not halve the distance to the fixed point, and not for
        # noise: a step across a change of itinerary, where the slope of one return
        # does not hold. Follow the motion for a few returns instead.
        return FOLLOW, 0.0, rtol_int, 3, err0
    if e2 == e1 or e1 < 0:
        # Newton step from a0 (the map is smooth along one itinerary; the return
        # before a0 may be the partial one from the start); a jump never more than
        # halves or doubles the distance to x_eq
        a_new = _clamped(a0 + F / gap, a1, xe)
        if abs(a_new - a1) > 0.1 * tol * lx:
            if not fine and need >= 0.1 * tol and _last_two(err0, a1 - xe, accept):
                rtol_int = tight
            return NEWTON_JUMP, a_new, rtol_int, newton_rest, err0
    return FOLLOW, 0.0, rtol_int, newton_rest, err0


@kernel(inline="always")
def _clamped(a_new, a1, xe):
    """A Newton target that never more than halves or doubles the distance to x_eq."""
    r = (a_new - xe) / (a1 - xe)
    if r < 0.5:
        return xe + 0.5 * (a1 - xe)
    if r > 2.0:
        return xe + 2.0 * (a1 - xe)
    return a_new


@kernel(inline="always")
def _last_two(err0, size, accept):
    """Whether the iterate after the next is likely accepted: Newton's error squares
    relative to the cycle's ``size`` (within a factor 4). Its residual and the jump to
    it both need the lowered tolerance, so the return from the next iterate is
    computed at it; the earlier ones keep the user's tolerance."""
    e_next = 4.0 * err0 * err0 / abs(size)
    return 4.0 * e_next * e_next <= accept * abs(size)


@kernel
def undo_jump(st, p, w, acc):
    """``(undone, after_jump)``: whether the last section was a Newton jump, and
    whether that step left the itinerary whose slope it used (e.g. towards a cycle
    that exists only on the extrapolated map past the onset of stops); then the
    motion goes back to where the step started and is followed until its itinerary
    changes by itself."""
    after_jump = w[W_JUMPED] > 0.0
    w[W_JUMPED] = 0.0
    if after_jump and w[W_E + 2] != w[W_E_JUMP]:
        jump(st, p, w, acc, w[W_A_FROM])
        w[W_NEWTON_REST] = 1 << 30
        w[W_E_REST] = w[W_E_JUMP]
        return True, after_jump
    if w[W_NEWTON_REST] > 0 and w[W_E + 2] == w[W_E + 1] and w[W_E + 2] != w[W_E_REST]:
        w[W_NEWTON_REST] = 0.0
    return False, after_jump


@kernel
def own_map_step(st, p, w, acc, xe, sigma):
    """Method gps: Newton on its own section map, with the slope measured by a
    probe. Returns (action, value); carries out its jumps.

    gps's discrete map is not the ODE's (it has its own Hopf point), so Liouville's
    slope is not its slope, and the ratio of successive changes is lost in the
    rounding noise ``sigma`` [cm] of the section values as they converge. Instead,
    after a base return ``a0 -> a1`` the motion is moved to ``a0 + delta`` and one
    probe return measures the slope ``(P(a0 + delta) - a1) / delta``; ``delta`` is
    2000 sigma / (1 - slope) (the slope's noise ``2 sigma / delta`` 1e-3 of its
    distance from 1), at least 1e-4 and at most 1e-2 of the distance to x_eq (the
    map's curvature over delta stays small); a slope whose noise exceeds a quarter
    of its distance from 1 is not used. Newton then jumps from a0; the next base
    return is accepted (ACCEPT, value: the slope) when
    ``|a1 - a0| / (1 - slope) <= tol L / 2``. A fixed point (or Newton target)
    within tol L / 2 of x_eq is the equilibrium (REST). Where no
    delta fits (next to gps's own Hopf point), the motion is followed and the point
    may end unconverged: gps's answer, not the ODE's."""
    half = 0.5 * w[W_TOL] * w[W_LX]
    a0 = w[W_A + 2]
    a1 = w[W_A + 3]
    if w[W_E + 1] != w[W_E + 2]:
        w[W_FD_PROBE] = 0.0
        return FOLLOW, 0.0
    if w[W_FD_PROBE] > 0.0:                      # the probe return just ended
        w[W_FD_PROBE] = 0.0
        slope = (a1 - w[W_FD_A1]) / w[W_FD_DELTA]
        w[W_FD_SLOPE] = slope
        gap = 1.0 - slope
        if not gap > 8.0 * sigma / abs(w[W_FD_DELTA]):
            return FOLLOW, 0.0        # expanding, or the slope's noise above gap / 4
        base = w[W_FD_A0]
        a_new = base + (w[W_FD_A1] - base) / gap
        r = (a_new - xe) / (w[W_FD_A1] - xe)
        if w[W_E + 2] == 0 and abs(a_new - xe) <= half:
            return REST, 0.0
        a_new = xe + min(max(r, 0.5), 2.0) * (w[W_FD_A1] - xe)
        jump(st, p, w, acc, a_new)
        w[W_RESET_SEEN] = 0.0           # a jump ends any period being measured
        return FOLLOW, 0.0
    gap = 1.0 - w[W_FD_SLOPE]                    # NaN before the first probe
    if gap > 0.0 and abs(a1 - a0) / gap <= half:
        if w[W_E + 2] == 0 and abs(a0 + (a1 - a0) / gap - xe) <= half:
            return REST, 0.0                     # the fixed point is x_eq
        return ACCEPT, w[W_FD_SLOPE]
    dist = abs(a0 - xe)
    delta = 2e3 * sigma / gap if gap > 0.0 else 1e-4 * dist
    delta = max(delta, 1e-4 * dist)
    if not delta <= 1e-2 * dist:
        return FOLLOW, 0.0
    w[W_FD_PROBE] = 1.0
    w[W_FD_A0] = a0
    w[W_FD_A1] = a1
    w[W_FD_DELTA] = delta if a0 >= xe else -delta
    jump(st, p, w, acc, a0 + w[W_FD_DELTA])
    w[W_RESET_SEEN] = 0.0
    return FOLLOW, 0.0


@kernel
def apply_decision(st, p, o, w, acc, action, value, rtol, rest, err0):
    """Carry out ``newton_decision``'s tolerance, rest count and Newton jump."""
    if action != EXPAND:
        w[W_ON_NF] = 0.0
    if rtol != w[W_RTOL]:
        w[W_RTOL] = rtol
        o[O_RTOL] = rtol
    w[W_NEWTON_REST] = rest
    if action == NEWTON_JUMP:
        a_from = w[W_A + 3]
        jump(st, p, w, acc, value)
        w[W_RESET_SEEN] = 0.0           # a jump ends any period being measured
        w[W_JUMPED] = 1.0
        w[W_ERR_JUMP] = err0
        w[W_E_JUMP] = w[W_E + 2]
        w[W_A_FROM] = a_from
