"""Attractor of one grid point, reduced on line (no stored trajectory).

The search runs the hybrid driver and stops as soon as the answer is known:

* **stick-slip / grazing cycles**: for ``v != 0`` every slip after a stick starts from
  the breakaway point ``(sgn(v) r_y/k, v)`` (design fact 2), and so does every slide
  after a touch snapped to it. Once the run reaches that point (a *reset*), the
  motion until the next reset is one whole period of a periodic orbit: it is measured
  and the search ends. No transient is integrated after the first reset.
* **slip cycles** (no stick): the fixed point of the return map ``a -> P(a)`` of the
  maxima of ``x`` (minima for v < 0), solved by Newton's method. The slope ``P'(a)``
  is exact (Liouville's formula with the saltation of slide-slide reversals,
  ``return_map.py``), so each Newton step costs one period. A fixed point is accepted
  on a verified residual, ``|P(a) - a| / (1 - P') <= tol L / 2``, from returns
  computed at ``rtol <= tol (1 - P') / 2``: the integrator's noise (~2 rtol L per
  return) is amplified by ``1 / (1 - P')`` in the fixed point. Newton iterates at
  the user's tolerance first and tightens it only for the last returns. ``P'`` at
  the cycle is its Floquet multiplier (an output).
* **next to the Hopf point** (``1 - P'`` so small that the returns would need
  ``rtol`` below ``RTOL_FLOOR``): the normal form (``normal_form.py``) decides. For
  ``q <= 0`` a small motion whose decrement it predicts decays to x_eq (its cubic
  coefficient is stabilising: no waiting for an algebraic decay); for ``q > 0`` its
  cycle is the answer where its error bound is below the tolerance. A cycle that
  neither resolves is returned with status ``unresolved``, never as ``ok``.
* **equilibrium** (steady sliding at x_eq): with ``y = x - x_eq`` and
  ``E = (m ydot^2 + k y^2)/2``, eq. (41) gives
  ``dE/dt = ydot^2 (m q + 3 alpha2 v ydot - alpha2 ydot^2)`` (v > 0). If ``q < 0`` and
  ``sqrt(2E/m) < min(|v|, m|q|/(3 alpha2 |v|))`` the bracket is negative on the whole
  sublevel set, which is therefore invariant and free of sticking: the motion
  converges to x_eq (LaSalle). That certificate, or the normal form's (above), ends
  the search.
* budget: ``max_periods`` natural periods and ``max_steps`` stepper calls; when spent
  the point is returned as unconverged with the last period's estimates.
"""
import math

import numpy as np
from numba import prange

from .jit import kernel

from . import codes
from .dopri5 import scales
from .driver import advance, init_state
from .friction import x_equilibrium
from .normal_form import nf_decays_to_rest, nf_multiplier, nf_seed
from .return_map import log_saltation, return_slope
from .resolution import check_cycle
from .layout import (A_DT, A_IX, A_IXD2, A_NSTICK, A_TSTICK, A_WF, A_XDMAX, A_XDMIN, A_XMAX,
                     A_XMIN, A1, A2, K, M, NA, NOBS, NS, O_DT, O_GPS_A, O_LV, O_LX, O_MAX_STEPS,
                     O_MAX_TIME, O_METHOD, O_RTOL, OB_AMPLITUDE, OB_CYCLE_SIZE,
                     OB_MEAN, OB_NSTEPS, OB_PERIOD, OB_REGIME, OB_STATUS,
                     OB_STICK_FRACTION, OB_STICKS_PER_PERIOD, OB_T_SETTLE,
                     OB_VAMPLITUDE, OB_X_MAX, OB_X_MIN, OB_XDOT_MAX, OB_FLOQUET, RY, S_MODE, S_N, S_T, S_X,
                     S_ZD, V, X0, XD0)


# Lowest relative tolerance given to the integrator: below it, roundoff in the
# error estimate of dopri5 (weights rtol (L + |x|)) makes the controller erratic.
RTOL_FLOOR = 1e-14


@kernel(inline="always")
def _clear(acc):
    for i in range(NA):
        acc[i] = 0.0
    acc[A_XMAX] = -np.inf
    acc[A_XMIN] = np.inf
    acc[A_XDMAX] = -np.inf
    acc[A_XDMIN] = np.inf


@kernel(inline="always")
def _merge(dst, src):
    for i in (A_IX, A_IXD2, A_WF, A_TSTICK, A_NSTICK, A_DT):
        dst[i] += src[i]
    dst[A_XMAX] = max(dst[A_XMAX], src[A_XMAX])
    dst[A_XMIN] = min(dst[A_XMIN], src[A_XMIN])
    dst[A_XDMAX] = max(dst[A_XDMAX], src[A_XDMAX])
    dst[A_XDMIN] = min(dst[A_XDMIN], src[A_XDMIN])


@kernel(inline="always")
def _jump(st, a_hist, t_hist, acc_sec, a_new, v, t):
    """Move the motion to the section point a_new [cm] (xdot = 0) at time t: the
    newest section value becomes a_new and the interval being measured restarts."""
    st[S_X] = a_new
    st[S_ZD] = -v
    a_hist[3] = a_new
    t_hist[3] = t
    _clear(acc_sec)


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
def _answer_cycle(out, acc, t0, omega, regime, floquet, unresolved, p, n_steps):
    """Write a measured cycle with its Floquet multiplier and status: ok, or
    below_resolution (``check_cycle``), or unresolved when ``unresolved``."""
    _write_cycle(out, acc, t0, omega, regime)
    out[OB_FLOQUET] = floquet
    check_cycle(out, p)
    if unresolved and out[OB_STATUS] == codes.OK:
        out[OB_STATUS] = codes.UNRESOLVED
    out[OB_NSTEPS] = n_steps


@kernel
def _write_rest(out, x, t, regime, stuck):
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


@kernel
def resolve_options(p, o_in):
    """Per-point option row: 'auto' method, default dt and GPS shift resolved."""
    o = o_in.copy()
    if o[O_METHOD] < 0.0:
        o[O_METHOD] = codes.EXACT if p[A2] == 0.0 else codes.DOPRI5
    omega = math.sqrt(p[K] / p[M])
    if not o[O_DT] > 0.0:
        o[O_DT] = 2.0 * math.pi / omega / 50.0
    lx, lv = scales(p)
    o[O_LX] = lx
    o[O_LV] = lv
    if np.isnan(o[O_GPS_A]):
        o[O_GPS_A] = lx
    return o


@kernel
def method_status(p, o):
    """A priori refusal: exact needs alpha2 = 0; fixed steps must resolve 1/omega."""
    meth = int(o[O_METHOD])
    if meth == codes.EXACT and p[A2] != 0.0:
        return codes.BAD_METHOD
    if (meth == codes.GPS or meth == codes.RK4) and \
            o[O_DT] * math.sqrt(p[K] / p[M]) > 1.0:
        return codes.STEP_TOO_LARGE
    return codes.OK


@kernel
def _certified_rest(x, zd, p):
    """True when (x, zdot) lies in a sublevel set of E that provably decays to x_eq."""
    v = p[V]
    if v == 0.0:
        return False
    m = p[M]
    q = (p[A1] - 3.0 * p[A2] * v * v) / m
    if not q < 0.0:
        return False
    y = x - x_equilibrium(p)
    yd = zd + v
    vel = math.sqrt(yd * yd + p[K] / m * y * y)     # sqrt(2E/m)
    lim = abs(v)
    if p[A2] > 0.0:
        lim = min(lim, m * abs(q) / (3.0 * p[A2] * abs(v)))
    return vel < lim


@kernel(nogil=True)
def attractor_point(p, o_in, out):
    """Fill ``out`` (layout OB_*) with the attractor observables of one point."""
    for i in range(NOBS):
        out[i] = np.nan
    o = resolve_options(p, o_in)
    meth = int(o[O_METHOD])
    refused = method_status(p, o)
    if refused != codes.OK:
        out[OB_REGIME] = codes.R_FAILED
        out[OB_STATUS] = refused
        out[OB_NSTEPS] = 0.0
        return
    v = p[V]
    omega = math.sqrt(p[K] / p[M])
    t_nat = 2.0 * math.pi / omega
    t_budget = o[O_MAX_TIME] * t_nat
    tol = o[O_RTOL]
    lx, _lv = scales(p)
    xs = p[RY] / p[K]
    conservative = p[A1] == 0.0 and p[A2] == 0.0
    st = np.zeros(NS)
    acc = np.zeros(NA)
    acc_cyc = np.zeros(NA)
    acc_sec = np.zeros(NA)
    acc_last = np.zeros(NA)
    _clear(acc)
    _clear(acc_cyc)
    _clear(acc_sec)
    init_state(st, p[X0], p[XD0], p, o)
    reset_seen = False
    t_cyc = 0.0
    # a start exactly at the breakaway point is a reset
    if v != 0.0 and st[S_ZD] == 0.0 and st[S_MODE] != codes.STICK and \
            st[S_X] == (xs if v > 0.0 else -xs):
        reset_seen = True
    n_sec = 0
    a_hist = np.zeros(4)      # last section values x_max
    t_hist = np.zeros(4)
    e_hist = np.zeros(3)      # phase events inside each of the last section intervals
    n_ev_sec = 0
    t_last_sec = 0.0
    # a start at rest (xdot = 0) beyond x_eq is itself a section point: the first
    # return is then a whole one (a continuation started on a known cycle)
    if v != 0.0 and st[S_MODE] != codes.STICK and st[S_ZD] == -v and \
            (st[S_X] - x_equilibrium(p)) * v > 0.0:
        n_sec = 1
        a_hist[3] = st[S_X]
    status = codes.OK
    # Clocks: st[S_T] is local and set back to 0 after every stick (absolute times
    # after a stick of 2e5 s or 1e15 s would eat the digits of a 2 s period);
    # t_off is the absolute time of the local origin. Only sliding time counts
    # against the budget: sticking is closed form.
    t_off = 0.0
    t_slide = 0.0
    exhausted = True
    if v == 0.0 and st[S_MODE] == codes.STICK:
        _write_rest(out, st[S_X], 0.0, codes.R_STUCK, True)
        out[OB_STATUS] = codes.OK
        out[OB_NSTEPS] = 0.0
        return
    salt = 0.0                # log of the saltation factors of the current interval
    salt_hist = np.zeros(2)
    rtol_int = tol            # integration tolerance now in force (lowered by Newton)
    rtol_hist = np.zeros(2)
    seeded = False            # the motion was moved to the normal form's cycle once
    on_nf = False             # ... and the last section was that jump
    nf_floor = False          # ... whose return float64 cannot time to tol
    jumped = False            # the last section was a Newton jump ...
    err_jump = 0.0            # ... from this estimated distance to the fixed point,
    e_jump = 0.0              # ... along this itinerary (events per return),
    a_from = 0.0              # ... from this section point
    e_rest = -1.0             # itinerary on which Newton is suspended
    newton_rest = 0           # returns to follow without Newton steps
    for _it in range(int(o[O_MAX_STEPS]) + 10):
        mode0 = st[S_MODE]
        if st[S_MODE] == codes.STICK:
            ev, status = advance(st, p, o, acc, np.inf)
            if ev == codes.EV_SLIP:
                t_off += st[S_T]
                st[S_T] = 0.0
        else:
            # control returns at least once per natural period, so that approaches
            # without maxima of x (overdamped) still meet the equilibrium certificate
            t_start = st[S_T]
            ev, status = advance(st, p, o, acc,
                                 t_start + min(t_nat, t_budget - t_slide))
            t_slide += st[S_T] - t_start
        _merge(acc_cyc, acc)
        _merge(acc_sec, acc)
        _clear(acc)
        t = st[S_T]
        if status != codes.OK:
            break
        if ev == codes.EV_STOP_TIME:
            if st[S_MODE] != codes.STICK and _certified_rest(st[S_X], st[S_ZD], p):
                _write_rest(out, x_equilibrium(p), t_off + t, codes.R_EQUILIBRIUM, False)
                out[OB_STATUS] = codes.OK
                out[OB_NSTEPS] = st[S_N]
                return
            if t_slide >= t_budget:
                status = codes.UNCONVERGED
                exhausted = False
                break
            continue
        if v == 0.0 and ev == codes.EV_STICK:
            _write_rest(out, st[S_X], t_off + t, codes.R_STUCK, True)
            out[OB_STATUS] = codes.OK
            out[OB_NSTEPS] = st[S_N]
            return
        is_reset = v != 0.0 and (ev == codes.EV_SLIP or (
            ev == codes.EV_ABNORMAL_STOP and st[S_X] == (xs if v > 0.0 else -xs)))
        if is_reset:
            if reset_seen:
                regime = codes.R_STICK_SLIP if acc_cyc[A_NSTICK] > 0 else codes.R_SLIP_CYCLE
                # Floquet multiplier 0: every period restarts from the same point
                _answer_cycle(out, acc_cyc, t_cyc, omega, regime, 0.0, False, p, st[S_N])
                return
            reset_seen = True
            t_cyc = t_off + t
            _clear(acc_cyc)
            _clear(acc_sec)
            n_sec = 0
            salt = 0.0
            n_ev_sec = 0
            continue
        # sections: maxima of x (minima for v < 0, so that v -> -v is an exact mirror)
        section = (ev == codes.EV_XMAX and v > 0.0) or (ev == codes.EV_XMIN and v < 0.0) \
            or (v == 0.0 and ev == codes.EV_NORMAL_STOP and st[S_X] > 0.0)
        if not section:
            if ev != codes.EV_XMIN and ev != codes.EV_XMAX:
                n_ev_sec += 1
            if ev == codes.EV_NORMAL_STOP:
                salt += log_saltation(p, st[S_X], mode0, st[S_MODE])
            continue
        if _certified_rest(st[S_X], st[S_ZD], p):
            _write_rest(out, x_equilibrium(p), t_off + t, codes.R_EQUILIBRIUM, False)
            out[OB_STATUS] = codes.OK
            out[OB_NSTEPS] = st[S_N]
            return
        # shift the section history
        for j in range(3):
            a_hist[j] = a_hist[j + 1]
            t_hist[j] = t_hist[j + 1]
        a_hist[3] = st[S_X]
        t_hist[3] = t
        e_hist[0] = e_hist[1]
        e_hist[1] = e_hist[2]
        e_hist[2] = n_ev_sec
        n_ev_sec = 0
        salt_hist[0] = salt_hist[1]
        salt_hist[1] = salt
        salt = 0.0
        rtol_hist[0] = rtol_hist[1]
        rtol_hist[1] = rtol_int
        n_sec += 1
        if n_sec >= 2:
            for i in range(NA):
                acc_last[i] = acc_sec[i]
            t_last_sec = t_off + t_hist[2]
        _clear(acc_sec)
        if conservative:
            if n_sec < 3:
                continue
            # the conservative law has a neutral family, no contraction: a steady
            # section is the answer. A neutral circle must also have gone round
            # without touching the belt: one that touches is a transient of the
            # conservative law, not a member of the neutral family.
            d1 = a_hist[3] - a_hist[2]
            T1 = t_hist[3] - t_hist[2]
            T0 = t_hist[2] - t_hist[1]
            if abs(d1) <= tol * lx and abs(T1 - T0) <= 10.0 * tol * T1 \
                    and not (p[RY] > 0.0 and e_hist[2] > 0):
                _answer_cycle(out, acc_last, t_last_sec, omega, codes.R_NEUTRAL, np.nan,
                              False, p, st[S_N])
                return
            continue
        # --- slip motion: the return map a -> P(a) of the x maxima, solved by Newton
        if n_sec < 2 or v == 0.0:
            if v == 0.0 and n_sec >= 3:
                # v = 0: sections are stops on the switching line (no smooth map);
                # a steady geometric sequence of returns is the answer
                # The integrator's error per return is ~rtol (lx + |x|), so the scale
                # here includes the cycle, and the returns are computed at
                # rtol <= tol (1 - rho) / 2 (the same noise amplification as below).
                d1 = a_hist[3] - a_hist[2]
                d0 = a_hist[2] - a_hist[1]
                rho = d1 / d0 if d0 != 0.0 else 0.0
                rem = abs(d1) * abs(rho) / (1.0 - abs(rho)) if abs(rho) < 1.0 else np.inf
                scale = lx + abs(a_hist[3])
                need0 = 0.5 * tol * (1.0 - abs(rho))
                if abs(d1) <= tol * scale and rem <= tol * scale and \
                        rtol_hist[1] <= max(need0, RTOL_FLOOR) * 1.000001:
                    _answer_cycle(out, acc_last, t_last_sec, omega, codes.R_SLIP_CYCLE,
                                  np.nan, False, p, st[S_N])
                    return
                if abs(rho) < 1.0 and need0 < rtol_int:
                    rtol_int = max(need0, RTOL_FLOOR)
                    o[O_RTOL] = rtol_int
            continue
        a0 = a_hist[2]
        a1 = a_hist[3]
        after_jump = jumped
        jumped = False
        if after_jump and e_hist[2] != e_jump:
            # the Newton step left the itinerary whose slope it used (e.g. towards
            # a cycle that exists only on the extrapolated map, past the onset of
            # stops): go back to where it started and follow the motion until its
            # itinerary changes by itself
            _jump(st, a_hist, t_hist, acc_sec, a_from, v, t)
            n_sec = 1
            newton_rest = 1 << 30
            e_rest = e_jump
            continue
        if newton_rest > 0 and e_hist[2] == e_hist[1] and e_hist[2] != e_rest:
            newton_rest = 0
        dP = return_slope(p, a0, a1, acc_last, salt_hist[1])
        xe = x_equilibrium(p)
        F = a1 - a0
        gap = 1.0 - dP
        if p[A2] > 0.0 and e_hist[2] == 0 and \
                nf_decays_to_rest(p, a0, a1, acc_last[A_DT]):
            _write_rest(out, xe, t_off + t, codes.R_EQUILIBRIUM, False)
            out[OB_STATUS] = codes.OK
            out[OB_NSTEPS] = st[S_N]
            return
        if not seeded and e_hist[2] == 0 and p[A2] > 0.0 and p[A1] > 0.0:
            # a small stop-free motion that the Hopf normal form describes (its
            # decrement agrees): start Newton on the normal form's cycle (accurate
            # to 1 %) if the motion is heading there, instead of following the slow
            # approach of a weakly contracting cycle
            a_nf = nf_seed(p, a0, a1, acc_last[A_DT], 0.01 * abs(a1 - xe))
            if not math.isnan(a_nf) and (a_nf - a1) * F > 0.0:
                seeded = True
                _jump(st, a_hist, t_hist, acc_sec, a_nf, v, t)
                n_sec = 1
                reset_seen = False       # a jump ends any period being measured
                on_nf = False
                continue
        # The return map computed at rtol is wrong by ~ rtol lx / |a - x_eq| in its
        # slope (the integrator's own growth or decay); a slope within that noise
        # of 1 is not resolved at this tolerance. Returns used for the answer are
        # computed at rtol <= tol gap / 2: their noise (~2 rtol lx) is amplified by
        # 1 / gap in the fixed point, which is then within ~tol lx, as the period
        # measured on it (the integrator's own error over one period).
        noise = 4.0 * rtol_hist[1] * lx / max(abs(a1 - xe), 1e-300)
        resolved = abs(gap) > noise
        if gap <= -noise:
            continue            # expanding here: follow the motion
        need = 0.5 * tol * gap
        floor = need < RTOL_FLOOR or (not resolved and rtol_hist[1] <= RTOL_FLOOR)
        if floor and e_hist[2] == 0 and p[A2] > 0.0 and p[A1] > 0.0:
            # the cycle contracts too slowly for float64 integration to resolve it
            # at this tolerance: next to the Hopf point, where the normal form is
            # accurate (if it is not accurate enough either: "unresolved")
            if on_nf and rtol_hist[1] <= tol:
                # the return measured from the normal form's cycle (accurate to the
                # tolerance): its observables are the cycle's, to the normal form's
                # error plus one period's integration error
                # (unresolved where its maxima could not be timed to the tolerance)
                _answer_cycle(out, acc_last, t_last_sec, omega, codes.R_SLIP_CYCLE,
                              nf_multiplier(p, acc_last[A_DT]), nf_floor, p, st[S_N])
                return
            a_nf = nf_seed(p, a0, a1, acc_last[A_DT], 0.5 * tol * lx)
            if not math.isnan(a_nf):
                # the normal form describes this return and is accurate at the
                # cycle: go to its cycle and measure one return from there
                _jump(st, a_hist, t_hist, acc_sec, a_nf, v, t)
                n_sec = 1
                reset_seen = False       # a jump ends any period being measured
                on_nf = True
                # the return is measured with velocity errors below tol times the
                # cycle's own velocity (omega A), not the belt's: its maxima of x,
                # where xdot crosses 0 with slope omega^2 A, are then timed to
                # ~tol of the period
                small = omega * abs(a_nf - xe) / abs(v)
                if small < 1.0:
                    rtol_int = max(min(rtol_int, tol * small), RTOL_FLOOR)
                    o[O_RTOL] = rtol_int
                nf_floor = tol * small < RTOL_FLOOR
                continue
        on_nf = False
        if not resolved:
            if rtol_int > RTOL_FLOOR:
                rtol_int = max(0.01 * rtol_int, RTOL_FLOOR)
                o[O_RTOL] = rtol_int
            elif e_hist[2] == 0 and abs(F) <= 4.0 * RTOL_FLOOR * lx:
                # neutral to float64 resolution, and the returns stand still: not
                # even the sign of the contraction is known, so not the regime
                _answer_cycle(out, acc_last, t_last_sec, omega, codes.R_UNCONVERGED, dP,
                              True, p, st[S_N])
                return
            continue            # no Newton step on an unresolved slope
        err0 = abs(F) / gap     # distance of a0 from the fixed point (Newton)
        # Newton iterates at the tolerance in force until its noise (~4 rtol lx / gap)
        # is reached; only then is the tolerance lowered for the last returns.
        fine = rtol_hist[1] <= max(need, RTOL_FLOOR) * 1.000001
        accept = 0.5 * tol * lx
        if floor:
            accept = max(accept, 4.0 * RTOL_FLOOR * lx / gap)
        if err0 <= accept and fine:
            _answer_cycle(out, acc_last, t_last_sec, omega, codes.R_SLIP_CYCLE, dP, floor,
                          p, st[S_N])
            return
        if not fine and (err0 <= 4.0 * rtol_hist[1] * lx / gap or need >= 0.1 * tol):
            # (a tolerance within 10x of the user's costs < 1.6x the steps: take it
            # at once rather than pay the two returns that a late switch needs)
            rtol_int = max(need, RTOL_FLOOR)
            o[O_RTOL] = rtol_int
        if newton_rest > 0:
            newton_rest -= 1
        elif after_jump and err0 >= 0.5 * err_jump and rtol_hist[1] == rtol_hist[0] \
                and err0 > 4.0 * rtol_hist[1] * lx / gap:
            # the last jump did not halve the distance to the fixed point, and not
            # for noise (same tolerance, distance above the noise): a step across a
            # change of itinerary, where the slope of one return does not hold.
            # Follow the motion for a few returns instead.
            newton_rest = 3
        elif e_hist[2] == e_hist[1]:
            # Newton step from a0 (the map is smooth along one itinerary); a jump
            # never more than halves or doubles the distance to x_eq
            a_new = a0 + F / gap
            r = (a_new - xe) / (a1 - xe)
            if r < 0.5:
                a_new = xe + 0.5 * (a1 - xe)
            elif r > 2.0:
                a_new = xe + 2.0 * (a1 - xe)
            if abs(a_new - a1) > 0.1 * tol * lx:
                _jump(st, a_hist, t_hist, acc_sec, a_new, v, t)
                n_sec = 1
                reset_seen = False       # a jump ends any period being measured
                jumped = True
                err_jump = err0
                e_jump = e_hist[2]
                a_from = a1
                continue
    # budget spent or numerical failure
    if exhausted and status == codes.OK:
        status = codes.STEP_BUDGET        # the loop itself ran out
    out[OB_NSTEPS] = st[S_N]
    if status == codes.UNCONVERGED or status == codes.STEP_BUDGET:
        if n_sec >= 3:
            _write_cycle(out, acc_last, t_last_sec, omega, codes.R_UNCONVERGED)
        out[OB_REGIME] = codes.R_UNCONVERGED
        out[OB_STATUS] = status
        return
    if status == codes.DIVERGED and meth == codes.EXACT:
        out[OB_REGIME] = codes.R_UNBOUNDED
    else:
        out[OB_REGIME] = codes.R_FAILED
    out[OB_STATUS] = status


@kernel(nogil=True)
def attractor_rows(P, o, out):
    """Serial loop over the rows of P (for dask tasks: dask owns the parallelism)."""
    for i in range(P.shape[0]):
        attractor_point(P[i], o, out[i])


# Interleaved lanes of attractor_rows_parallel: many more than threads, and prime, so
# that a lane never lines up with a grid axis (256 lanes on a 256 x 256 map put one
# alpha2 in each lane, and split the threads by alpha2, the costly direction).
_LANES = 1021


@kernel(parallel=True)
def attractor_rows_parallel(P, o, out):
    """numba-threaded loop over the rows of P (one prange, sequential inside).

    prange hands each thread one contiguous block, but cost is clustered on a grid
    (slip cycles near v* cost ~10x a stick-slip point). The rows are dealt into
    ``_LANES`` interleaved lanes (lane b: rows b, b + _LANES, ...), and prange splits
    the lanes, so every thread gets a sample of every region. Points are independent,
    so the results do not depend on this order.
    """
    n = P.shape[0]
    lanes = min(_LANES, n)      # (a small batch: one row a lane, split evenly)
    for b in prange(lanes):
        for i in range(b, n, lanes):
            attractor_point(P[i], o, out[i])
