"""Attractor of one grid point, reduced on line (no stored trajectory).

The search runs the hybrid driver and stops as soon as the answer is known:

* **stick-slip / grazing cycles**: for ``v != 0`` every slip after a stick starts from
  the breakaway point ``(sgn(v) r_y/k, v)`` (design fact 2), and so does every slide
  after a touch snapped to it. Once the run reaches that point (a *reset*), the
  motion until the next reset is one whole period of a periodic orbit: it is measured
  and the search ends. No transient is integrated after the first reset.
* **slip cycles** (no stick): a Poincare section at the maxima of ``x``. Successive
  returns ``a_n`` converge geometrically with ratio ``rho``; the point is converged
  when the step ``|a_n - a_{n-1}|`` and the remaining distance
  ``|a_n - a_{n-1}| rho / (1 - rho)`` are both below ``tol * L``. When ``rho`` is near
  1 (near v*, transients ~ 2/|q|), an Aitken jump to the extrapolated fixed point
  replaces the slow approach (Steffensen's method on the Poincare map), and the
  convergence test is repeated from there.
* **equilibrium** (steady sliding at x_eq): with ``y = x - x_eq`` and
  ``E = (m ydot^2 + k y^2)/2``, eq. (41) gives
  ``dE/dt = ydot^2 (m q + 3 alpha2 v ydot - alpha2 ydot^2)`` (v > 0). If ``q < 0`` and
  ``sqrt(2E/m) < min(|v|, m|q|/(3 alpha2 |v|))`` the bracket is negative on the whole
  sublevel set, which is therefore invariant and free of sticking: the motion
  converges to x_eq (LaSalle). That certificate ends the search.
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
from .resolution import check_cycle
from .layout import (A_DT, A_IX, A_IXD2, A_NSTICK, A_TSTICK, A_XDMAX, A_XDMIN, A_XMAX,
                     A_XMIN, A1, A2, K, M, NA, NOBS, NS, O_DT, O_GPS_A, O_LV, O_LX, O_MAX_STEPS,
                     O_MAX_TIME, O_METHOD, O_RTOL, OB_AMPLITUDE, OB_CYCLE_SIZE,
                     OB_MEAN, OB_NSTEPS, OB_PERIOD, OB_REGIME, OB_STATUS,
                     OB_STICK_FRACTION, OB_STICKS_PER_PERIOD, OB_T_SETTLE,
                     OB_VAMPLITUDE, OB_X_MAX, OB_X_MIN, OB_XDOT_MAX, OB_FLOQUET, RY, S_MODE, S_N, S_T, S_X,
                     S_ZD, V, X0, XD0)


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
    for i in (A_IX, A_IXD2, 2, A_TSTICK, A_NSTICK, A_DT):
        dst[i] += src[i]
    dst[A_XMAX] = max(dst[A_XMAX], src[A_XMAX])
    dst[A_XMIN] = min(dst[A_XMIN], src[A_XMIN])
    dst[A_XDMAX] = max(dst[A_XDMAX], src[A_XDMAX])
    dst[A_XDMIN] = min(dst[A_XDMIN], src[A_XDMIN])


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
def x_equilibrium(p):
    """Steady-sliding position (eq. 43, mirrored for v < 0; 0 for v = 0) [cm]."""
    v = p[V]
    if v == 0.0:
        return 0.0
    va = abs(v)
    sg = 1.0 if v > 0.0 else -1.0
    return sg * (p[RY] - p[A1] * va + p[A2] * va ** 3) / p[K]


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
    for _it in range(int(o[O_MAX_STEPS]) + 10):
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
                _write_cycle(out, acc_cyc, t_cyc, omega, regime)
                out[OB_FLOQUET] = 0.0     # every period restarts from the same point
                check_cycle(out, p)
                out[OB_NSTEPS] = st[S_N]
                return
            reset_seen = True
            t_cyc = t_off + t
            _clear(acc_cyc)
            _clear(acc_sec)
            n_sec = 0
            continue
        section = ev == codes.EV_XMAX or (v == 0.0 and ev == codes.EV_NORMAL_STOP
                                          and st[S_X] > 0.0)
        if not section:
            if ev != codes.EV_XMIN and ev != codes.EV_XMAX:
                n_ev_sec += 1
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
        n_sec += 1
        if n_sec >= 2:
            for i in range(NA):
                acc_last[i] = acc_sec[i]
            t_last_sec = t_off + t_hist[2]
        _clear(acc_sec)
        if n_sec < 3:
            continue
        d1 = a_hist[3] - a_hist[2]
        d0 = a_hist[2] - a_hist[1]
        T1 = t_hist[3] - t_hist[2]
        T0 = t_hist[2] - t_hist[1]
        rho = d1 / d0 if d0 != 0.0 else 0.0
        rem = abs(d1) * abs(rho) / (1.0 - abs(rho)) if abs(rho) < 1.0 else np.inf
        # a cycle is accepted only when it is resolved: an orbit within 1e3 tol L of
        # x_eq cannot be told from the equilibrium at this tolerance
        amp = 0.5 * (acc_last[A_XMAX] - acc_last[A_XMIN])
        # (the conservative law has a neutral family, no contraction: a steady
        # section is the answer, and rem is meaningless there)
        # A neutral circle must also have gone round without touching the belt: one
        # that touches is a transient of the conservative law, not a member of the
        # neutral family.
        if abs(d1) <= tol * lx and (rem <= tol * lx or conservative) \
                and abs(T1 - T0) <= 10.0 * tol * T1 \
                and (amp > 1e3 * tol * lx or conservative) \
                and not (conservative and p[RY] > 0.0 and e_hist[2] > 0):
            regime = codes.R_NEUTRAL if conservative else codes.R_SLIP_CYCLE
            _write_cycle(out, acc_last, t_last_sec, omega, regime)
            check_cycle(out, p)
            out[OB_NSTEPS] = st[S_N]
            return
        # Aitken jump on the section sequence, only where the return map is smooth
        # with a steady geometric ratio: the same itinerary (number of stops) in the
        # last three intervals, two consecutive ratios that agree, and not the
        # conservative law (every circle is a fixed point there).
        if n_sec >= 4 and not conservative and 0.5 < rho < 1.0 and rem > tol * lx \
                and e_hist[0] == e_hist[1] and e_hist[1] == e_hist[2]:
            dm = a_hist[1] - a_hist[0]
            rho0 = d0 / dm if dm != 0.0 else 0.0
            a_star = a_hist[3] - d1 * d1 / (d1 - d0)
            # geometric, not algebraic, approach: 1 - rho steady to 20 %
            if abs(rho - rho0) <= 0.2 * (1.0 - rho) and \
                    abs(a_star - a_hist[3]) < 10.0 * abs(a_hist[3] - x_equilibrium(p)):
                st[S_X] = a_star
                st[S_ZD] = -v
                n_sec = 1
                a_hist[3] = a_star
                t_hist[3] = t
                _clear(acc_sec)
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
    for b in prange(_LANES):
        for i in range(b, n, _LANES):
            attractor_point(P[i], o, out[i])
