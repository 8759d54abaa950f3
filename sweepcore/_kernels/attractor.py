"""Attractor of one grid point, reduced on line (no stored trajectory).

The search runs the hybrid driver and stops as soon as the answer is known:

* **stick-slip / grazing cycles**: for ``v != 0`` every slip after a stick starts from
  the breakaway point (``law.breakaway``), and so does every slide after a touch
  snapped to it. Once the run reaches that point (a *reset*), the motion until the
  next reset is one whole period of a periodic orbit: it is measured and the search
  ends (``on_reset``). No transient is integrated after the first reset.
* **slip cycles** (no stick): the fixed point of the return map of the maxima of x,
  solved by Newton's method at the sections (``sections.py``); next to the Hopf
  point the normal form decides where it is valid (``normal_form.py``).
* **equilibrium** (steady sliding at x_eq): the energy certificate of
  ``law.certified_rest`` (for methods that follow the ODE), the normal form's decay
  (q <= 0), or for gps a return of its own map that ends at x_eq to the tolerance.
* budget: ``max_periods`` natural periods of sliding and ``max_steps`` stepper calls;
  when spent the point is returned as unconverged with the last return's estimates.

State: ``st`` (the driver's, layout ``S_*``), ``w`` (the search's, ``W_*``) and the
accumulators ``acc`` (a row per interval, ``ACC_*``), all in ``layout.py``. Each
kernel below says what it reads and writes.
"""
import math

import numpy as np
from .jit import copy_into, kernel, runtime

from . import codes
from .dopri5 import scales
from .driver import advance, init_state
from .excitation import forced, load_bound, top_frequency
from .excitations import autonomous
from .law import (anti_damped, breakaway, certified_rest, conservative,
                  normal_form_valid, piecewise_linear, x_eq)
from .layout import (A_DT, A_IX, A_IXD2, A_NSTICK, A_TSTICK, A_XDMAX, A_XDMIN, A_XMAX,
                     A_XMIN, ACC_CYC, ACC_LAST, ACC_SEC, ACC_STEP, K, M, MAXED, MINNED,
                     NA, NACC, NO, NOBS, NP, NS, NW, O_DT, O_GPS_A, O_LV,
                     O_LX, O_MAX_STEPS, O_MAX_TIME, O_METHOD, O_RTOL, OB_AMPLITUDE,
                     OB_CYCLE_SIZE, OB_FLOQUET, OB_MEAN, OB_NSTEPS, OB_PERIOD,
                     OB_REGIME, OB_STATUS, OB_STICK_FRACTION, OB_STICKS_PER_PERIOD,
                     OB_T_SETTLE, OB_VAMPLITUDE, OB_X_MAX, OB_X_MIN, OB_XDOT_MAX,
                     S_MODE, S_N, S_SECTIONS, S_T, S_TOUCH, S_X, S_ZD, SUMMED, V, W_A,
                     W_CONSERVATIVE, W_E, W_E_REST, W_FD_SLOPE, W_ERR_JUMP, W_LX,
                     W_MODE0, W_N_EV, W_N_SEC, W_NEWTON_REST, W_NF_FLOOR, W_NF_OK,
                     W_ODE, W_OMEGA, W_ON_NF, W_RESET_SEEN, W_RTOL, W_RTOLH, W_SALT,
                     W_SALTH, W_T_BUDGET, W_T_CYC, W_T_LAST, W_T_NAT, W_T_OFF,
                     W_T_SLIDE, W_TOL, W_TOUCHED, W_XS, X0, XD0)
from .normal_form import nf_jump, nf_multiplier, nf_step
from .resolution import check_cycle
from .sections import (ACCEPT, ACCEPT_FLOOR, ACCEPT_NF, NEUTRAL, NF_JUMP,
                       RTOL_FLOOR, REST, TERMINAL, apply_decision, clear, neutral_decision,
                       newton_decision, note_event, own_map_step, push_section,
                       sharpen_touch, static_belt_decision, undo_jump)
from .return_map import return_slope
from .stepper import ADAPTIVE, CLOSED_FORM

EPS = np.finfo(np.float64).eps
# floats of ``attractor_point``'s workspace: options, driver state, search, accumulators
WORKSPACE = NO + NS + NW + NACC * NA

__all__ = ["RTOL_FLOOR", "WORKSPACE", "attractor_point", "resolve_options",
           "method_status"]


# ------------------------------------------------------------- the answers
@kernel(inline="always")
def _merge(dst, src):
    """Combine the accumulators of an interval into those of a longer one (layout)."""
    for i in SUMMED:
        dst[i] += src[i]
    for i in MAXED:
        dst[i] = max(dst[i], src[i])
    for i in MINNED:
        dst[i] = min(dst[i], src[i])


@kernel
def _write_cycle(out, acc, t0, omega, regime):
    T = acc[A_DT]
    out[OB_AMPLITUDE] = 0.5 * (acc[A_XMAX] - acc[A_XMIN])
    out[OB_MEAN] = acc[A_IX] / T
    out[OB_VAMPLITUDE] = 0.5 * (acc[A_XDMAX] - acc[A_XDMIN])
    out[OB_CYCLE_SIZE] = math.sqrt(max(acc[A_IXD2], 0.0) / (omega * math.pi))
    out[OB_PERIOD] = T
    out[OB_STICK_FRACTION] = acc[A_TSTICK] / T
    out[OB_STICKS_PER_PERIOD] = acc[A_NSTICK]
    out[OB_T_SETTLE] = t0
    out[OB_X_MAX] = acc[A_XMAX]
    out[OB_X_MIN] = acc[A_XMIN]
    out[OB_XDOT_MAX] = acc[A_XDMAX]
    out[OB_REGIME] = regime


@kernel
def answer_cycle(out, acc, t0, omega, regime, floquet, unresolved, p, n_steps):
    """Write a measured cycle with its Floquet multiplier and status: ok, or
    below_resolution (``check_cycle``), or unresolved when ``unresolved``."""
    _write_cycle(out, acc, t0, omega, regime)
    out[OB_FLOQUET] = floquet
    check_cycle(out, p)
    if unresolved and out[OB_STATUS] == codes.OK:
        out[OB_STATUS] = codes.UNRESOLVED
    out[OB_NSTEPS] = n_steps


@kernel
def answer_rest(out, x, t, regime, stuck, n_steps):
    """Write a point at rest (steady sliding at x, or stuck), status ok."""
    out[OB_AMPLITUDE] = 0.0
    out[OB_MEAN] = x
    out[OB_VAMPLITUDE] = 0.0
    out[OB_CYCLE_SIZE] = 0.0
    out[OB_PERIOD] = np.nan
    out[OB_STICK_FRACTION] = 1.0 if stuck else 0.0
    out[OB_STICKS_PER_PERIOD] = 0.0
    out[OB_T_SETTLE] = t
    out[OB_X_MAX] = x
    out[OB_X_MIN] = x
    out[OB_XDOT_MAX] = 0.0           # at rest (steady sliding, or stuck with v = 0)
    out[OB_REGIME] = regime
    out[OB_STATUS] = codes.OK
    out[OB_NSTEPS] = n_steps


@kernel
def answer_failure(out, w, acc, status, n_steps, unbounded):
    """Budget spent (the last return's estimates where there is one) or a numerical
    failure (NaN); ``unbounded``: a divergence is the motion's own growth
    (``grows_without_bound``)."""
    out[OB_NSTEPS] = n_steps
    if status == codes.UNCONVERGED or status == codes.STEP_BUDGET:
        if w[W_N_SEC] >= 3.0:
            _write_cycle(out, acc[ACC_LAST], w[W_T_LAST], w[W_OMEGA], codes.R_UNCONVERGED)
        out[OB_REGIME] = codes.R_UNCONVERGED
    elif status == codes.DIVERGED and unbounded:
        out[OB_REGIME] = codes.R_UNBOUNDED
    else:
        out[OB_REGIME] = codes.R_FAILED
    out[OB_STATUS] = status


# ------------------------------------------------------------------ set-up
@kernel
def resolve_options(meth, p, lw, fx, o_in):
    """Per-point option row: the method (a compile-time code: "auto" is resolved per
    point before the call, ``sweepcore.compiled.methods_of``), default dt and GPS
    shift resolved (``fx``: the excitation, prepared for the point)."""
    o = o_in.copy()
    resolve_into(meth, p, lw, fx, o)
    return o


@kernel
def resolve_into(meth, p, lw, fx, o):
    """``resolve_options`` in place on ``o``, a copy of the option row. Under a load
    the length scale grows by the load's bound over k, the velocity scale is at
    least omega times it, and the default fixed step resolves the load's highest
    frequency too."""
    omega = math.sqrt(p[K] / p[M])
    lx, lv = scales(p, lw)
    if forced(fx):
        lx = lx + load_bound(fx) / p[K]
        lv = max(abs(p[V]), omega * lx)
    o[O_METHOD] = meth
    if not o[O_DT] > 0.0:
        o[O_DT] = 2.0 * math.pi / max(omega, top_frequency(fx)) / 50.0
    o[O_LX] = lx
    o[O_LV] = lv
    if np.isnan(o[O_GPS_A]):
        o[O_GPS_A] = lx


@kernel
def method_status(meth, p, lw, fx, o):
    """A priori refusal: closed forms need a piecewise-linear law and no load; fixed
    steps must resolve 1/omega and the load's highest frequency."""
    if CLOSED_FORM[meth] and (forced(fx) or not piecewise_linear(p, lw)):
        return codes.BAD_METHOD
    if (meth == codes.GPS or meth == codes.RK4) and \
            o[O_DT] * max(math.sqrt(p[K] / p[M]), top_frequency(fx)) > 1.0:
        return codes.STEP_TOO_LARGE
    return codes.OK


@kernel
def setup(meth, p, lw, o, st, w, acc):
    """Fill ``w`` and ``acc`` for a search from the start in p; start the driver.

    A start exactly at the breakaway point is a reset; a start at rest (xdot = 0)
    beyond x_eq is itself a section point (a continuation started on a known cycle
    then costs one return less)."""
    v = p[V]
    omega = math.sqrt(p[K] / p[M])
    w[:] = 0.0
    w[W_TOL] = o[O_RTOL]
    w[W_LX] = scales(p, lw)[0]
    w[W_OMEGA] = omega
    w[W_T_NAT] = 2.0 * math.pi / omega
    w[W_T_BUDGET] = o[O_MAX_TIME] * w[W_T_NAT]
    w[W_XS] = breakaway(p, lw)
    w[W_E_REST] = -1.0
    w[W_FD_SLOPE] = np.nan
    w[W_ODE] = 0.0 if meth == codes.GPS else 1.0
    w[W_NF_OK] = 1.0 if normal_form_valid(p, lw) and meth != codes.GPS else 0.0
    w[W_CONSERVATIVE] = 1.0 if conservative(p, lw) else 0.0
    w[W_RTOL] = o[O_RTOL]
    for i in range(NACC):
        clear(acc[i])
    init_state(st, p[X0], p[XD0], p, lw, autonomous(), o)
    st[S_SECTIONS] = 1.0
    if v != 0.0 and st[S_ZD] == 0.0 and st[S_MODE] != codes.STICK and st[S_X] == w[W_XS]:
        w[W_RESET_SEEN] = 1.0
    if v != 0.0 and st[S_MODE] != codes.STICK and st[S_ZD] == -v and \
            (st[S_X] - x_eq(p, lw)) * v > 0.0:
        w[W_N_SEC] = 1.0
        w[W_A + 3] = st[S_X]


# ------------------------------------------------------------ the events
@kernel(inline="always")
def next_event(meth, st, p, lw, o, w, acc):
    """Advance the driver to its next event and add the interval to the cycle's and
    the section's accumulators. Clocks: st[S_T] is local and set back to 0 after
    every stick (absolute times after a stick of 2e5 s or 1e15 s would eat the
    digits of a 2 s period); W_T_OFF is the absolute time of the local origin. Only
    sliding time counts against the budget, and control returns at least every 1.5
    natural periods, so that overdamped approaches still meet the certificate. (Not
    every period: a cycle stops once a period, at its section, and a stop a natural
    period after the last would fall on the next section of a cycle whose period is
    2 pi/omega, as constant friction's circles, and hide it at a step's end.)"""
    w[W_MODE0] = st[S_MODE]
    step_acc = acc[ACC_STEP]
    if st[S_MODE] == codes.STICK:
        ev, status = advance(meth, st, p, lw, autonomous(), o, step_acc, np.inf)
        if ev == codes.EV_SLIP:
            w[W_T_OFF] += st[S_T]
            st[S_T] = 0.0
    else:
        t_start = st[S_T]
        ev, status = advance(meth, st, p, lw, autonomous(), o, step_acc,
                             t_start + min(1.5 * w[W_T_NAT], w[W_T_BUDGET] - w[W_T_SLIDE]))
        w[W_T_SLIDE] += st[S_T] - t_start
    _merge(acc[ACC_CYC], step_acc)
    _merge(acc[ACC_SEC], step_acc)
    clear(step_acc)
    return ev, status


@kernel
def _rested(st, p, lw, w, out):
    """Where the equilibrium certificate holds at the present state (ODE methods
    only), answer ``out`` with the equilibrium and return True."""
    if w[W_ODE] > 0.0 and st[S_MODE] != codes.STICK and \
            certified_rest(st[S_X], st[S_ZD], p, lw):
        answer_rest(out, x_eq(p, lw), w[W_T_OFF] + st[S_T], codes.R_EQUILIBRIUM,
                    runtime(False), st[S_N])
        return True
    return False


@kernel
def on_reset(meth, st, p, o, w, acc, out, touched):
    """At the breakaway point: the second reset ends a whole period (the answer,
    Floquet multiplier 0: every period restarts from the same point); the first
    starts measuring one. Returns True when answered.

    ``touched``: the reset is a tangential touch snapped to the breakaway point
    (``excitations/none.py``, ``zero_mode``), which hides whether the motion stuck for an instant,
    grazed, or passed below the belt speed by less than the touch tolerance (next to
    a fold, the last ends in steady sliding); or a stick of the period began at a
    touch (``W_TOUCHED``: placed at the turning point of zdot, its start and so the
    stick fraction are known to ~sqrt(touch tolerance) only). Unless the law is
    conservative (its touch is exact), such a period is measured again at a
    hundredth of the tolerance (``retouch``), whose touch tolerance is a hundredth
    too; a touch that remains at the floor RTOL_FLOOR is answered with status
    unresolved."""
    touched = touched or w[W_TOUCHED] > 0.0
    w[W_TOUCHED] = 0.0
    if w[W_RESET_SEEN] > 0.0:
        if not (touched and retouch(meth, p, o, w)):
            cyc = acc[ACC_CYC]
            regime = codes.R_STICK_SLIP if cyc[A_NSTICK] > 0 else codes.R_SLIP_CYCLE
            answer_cycle(out, cyc, w[W_T_CYC], w[W_OMEGA], regime, 0.0,
                         touched and w[W_CONSERVATIVE] == 0.0, p, st[S_N])
            return True
    w[W_RESET_SEEN] = 1.0
    w[W_T_CYC] = w[W_T_OFF] + st[S_T]
    clear(acc[ACC_CYC])
    clear(acc[ACC_SEC])
    w[W_N_SEC] = 0.0
    w[W_SALT] = 0.0
    w[W_N_EV] = 0.0
    return False


@kernel
def retouch(meth, p, o, w):
    """Lower the tolerance in force a hundredfold (to RTOL_FLOOR at most) to measure
    a period that ended on a touch again, and the touch tolerance's floor ``graze``
    with it (``driver.touch_tol``: max(graze, 20 rtol) |v|); False where that cannot
    sharpen the touch: a conservative law (exact touches), a method without error
    control (exact arcs, gps, rk4: their touch tolerance is ``graze``) or the floor
    reached."""
    if w[W_CONSERVATIVE] > 0.0 or not ADAPTIVE[meth] or not sharpen_touch(o):
        return False
    w[W_RTOL] = o[O_RTOL]
    return True


@kernel
def on_event(meth, ev, st, p, lw, o, w, acc, out):
    """Dispatch a phase event or a section; returns True when ``out`` is answered."""
    v = p[V]
    t = st[S_T]
    if ev == codes.EV_STOP_TIME:
        return _rested(st, p, lw, w, out)
    if v == 0.0 and ev == codes.EV_STICK:
        answer_rest(out, st[S_X], w[W_T_OFF] + t, codes.R_STUCK, runtime(True), st[S_N])
        return True
    if ev == codes.EV_STICK and st[S_TOUCH] > 0.0:
        w[W_TOUCHED] = 1.0
    if v != 0.0 and (ev == codes.EV_SLIP or (
            ev == codes.EV_ABNORMAL_STOP and st[S_X] == w[W_XS])):
        return on_reset(meth, st, p, o, w, acc, out, ev == codes.EV_ABNORMAL_STOP)
    # sections: maxima of x (minima for v < 0, so that v -> -v is an exact mirror)
    if not ((ev == codes.EV_XMAX and v > 0.0) or (ev == codes.EV_XMIN and v < 0.0)
            or (v == 0.0 and ev == codes.EV_NORMAL_STOP and st[S_X] > 0.0)):
        note_event(w, p, lw, ev, st[S_X], w[W_MODE0], st[S_MODE])
        # the other extremum too: half a period sooner for a fast decay
        return (ev == codes.EV_XMIN or ev == codes.EV_XMAX) and _rested(st, p, lw, w, out)
    if _rested(st, p, lw, w, out):
        return True
    push_section(w, acc, st[S_X], t)
    if w[W_CONSERVATIVE] > 0.0:
        action = neutral_decision(w, p, lw)
        regime = codes.R_NEUTRAL
    elif v == 0.0:
        action = static_belt_decision(w, o)
        regime = codes.R_SLIP_CYCLE
    elif w[W_N_SEC] >= 2.0:
        return slip_section(meth, st, p, lw, o, w, acc, out)
    else:
        return False
    if action == ACCEPT:
        answer_cycle(out, acc[ACC_LAST], w[W_T_LAST], w[W_OMEGA], regime, np.nan,
                     runtime(False), p, st[S_N])
        return True
    return False


@kernel
def slip_section(meth, st, p, lw, o, w, acc, out):
    """At a section of a slip motion: undo a Newton step that left its itinerary,
    let the normal form decide where it is valid, else ``newton_decision``; carry
    out the action. gps, whose map is not the ODE's, is solved on its own map
    (``own_map_step``). Returns True when ``out`` is answered."""
    xe = x_eq(p, lw)
    if w[W_ODE] == 0.0:
        n_steps = acc[ACC_LAST][A_DT] / o[O_DT]        # steps of the last return
        sigma = 4.0 * math.sqrt(n_steps) * EPS * (w[W_LX] + abs(w[W_A + 3]))
        action, value = own_map_step(st, p, w, acc, xe, sigma)
        return action >= TERMINAL and finish(action, value, st, p, lw, w, acc, out)
    undone, after_jump = undo_jump(st, p, w, acc)
    if undone:
        return False
    dP = return_slope(p, lw, w[W_A + 2], w[W_A + 3], acc[ACC_LAST], w[W_SALTH + 1])
    nf_here = w[W_NF_OK] > 0.0 and w[W_E + 2] == 0
    a_nf = np.nan
    if nf_here:
        action, a_nf = nf_step(st, p, lw, w, acc)
        if action == NF_JUMP:
            return False
        if action == REST:
            return finish(runtime(REST), dP, st, p, lw, w, acc, out)
    action, value, rtol, rest, err0 = newton_decision(
        w[W_A + 2], w[W_A + 3], dP, xe, w[W_E + 1], w[W_E + 2], w[W_RTOLH],
        w[W_RTOLH + 1], w[W_RTOL], w[W_TOL], w[W_LX], after_jump, w[W_ERR_JUMP],
        w[W_NEWTON_REST], nf_here, w[W_ON_NF] > 0.0, a_nf)
    if action == NF_JUMP:
        nf_jump(st, p, lw, o, w, acc, value)
        return False
    apply_decision(st, p, o, w, acc, action, value, rtol, rest, err0)
    if action < TERMINAL:
        return False
    return finish(action, value, st, p, lw, w, acc, out)


@kernel
def finish(action, value, st, p, lw, w, acc, out):
    """Write the answer of a slip section's terminal action; returns True."""
    last = acc[ACC_LAST]
    n = st[S_N]
    if action == REST:
        answer_rest(out, x_eq(p, lw), w[W_T_OFF] + st[S_T], codes.R_EQUILIBRIUM,
                    runtime(False), n)
    elif action == ACCEPT_NF:
        answer_cycle(out, last, w[W_T_LAST], w[W_OMEGA], codes.R_SLIP_CYCLE,
                     nf_multiplier(p, lw, last[A_DT]), w[W_NF_FLOOR] > 0.0, p, n)
    elif action == NEUTRAL:
        answer_cycle(out, last, w[W_T_LAST], w[W_OMEGA], codes.R_UNCONVERGED, value,
                     runtime(True), p, n)
    else:
        answer_cycle(out, last, w[W_T_LAST], w[W_OMEGA], codes.R_SLIP_CYCLE, value,
                     action == ACCEPT_FLOOR, p, n)
    return True


# ------------------------------------------------------------- entry points
@kernel(inline="always")
def attractor_point(meth, p, lw, o_in, out, ws):
    """Fill ``out`` (layout OB_*) with the attractor observables of one point.

    ``p``: parameter row (length ``layout.NP``); ``o_in``: option row (``layout.NO``);
    rows of another length are refused with status ``bad_kernel_row``. ``ws``: a
    workspace of ``WORKSPACE`` floats for the search's state (its caller's: one
    allocation per call, not per point, and a view without reference count,
    ``jit.unowned``, so that the many kernels the state passes through count none)."""
    for i in range(NOBS):
        out[i] = np.nan
    out[OB_NSTEPS] = 0.0
    if p.shape[0] != NP or o_in.shape[0] != NO or out.shape[0] != NOBS:
        out[OB_REGIME] = codes.R_FAILED
        out[OB_STATUS] = codes.BAD_ROW
        return
    o = ws[:NO]
    copy_into(o, o_in)
    resolve_into(meth, p, lw, autonomous(), o)
    refused = method_status(meth, p, lw, autonomous(), o)
    if refused != codes.OK:
        out[OB_REGIME] = codes.R_FAILED
        out[OB_STATUS] = refused
        return
    st = ws[NO:NO + NS]
    st[:] = 0.0
    w = ws[NO + NS:NO + NS + NW]
    acc = ws[NO + NS + NW:WORKSPACE].reshape((NACC, NA))
    setup(meth, p, lw, o, st, w, acc)
    if p[V] == 0.0 and st[S_MODE] == codes.STICK:
        answer_rest(out, st[S_X], 0.0, codes.R_STUCK, runtime(True), 0.0)
        return
    status = codes.OK
    for _it in range(int(o[O_MAX_STEPS]) + 10):
        ev, status = next_event(meth, st, p, lw, o, w, acc)
        if status != codes.OK:
            break
        if on_event(meth, ev, st, p, lw, o, w, acc, out):
            return
        if ev == codes.EV_STOP_TIME and w[W_T_SLIDE] >= w[W_T_BUDGET]:
            status = codes.UNCONVERGED
            break
    if status == codes.OK:
        status = codes.STEP_BUDGET        # the loop itself ran out
    answer_failure(out, w, acc, status, st[S_N], grows_without_bound(meth, p, lw))


@kernel(inline="always")
def grows_without_bound(meth, p, lw):
    """Whether a divergence (status ``diverged``) is the motion's own growth, regime
    ``unbounded``: a law anti-damped at high speed (``law.anti_damped``) integrated
    with a controlled error (the closed form or an adaptive pair). A fixed step
    (gps, rk4) can diverge by itself: that stays a failure."""
    return (meth == codes.EXACT or ADAPTIVE[meth]) and anti_damped(p, lw)
