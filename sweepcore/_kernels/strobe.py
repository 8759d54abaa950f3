"""The steady response of a forced slider: a fixed point of the stroboscopic map.

P maps the state (x, zdot, phase mode) at a time t = j T, T the forcing period
(``excitation.period``), to the state one period later: the one driver
(``driver.py``) run over a period, its clock set back to 0 at each period's end (the
load has period T). From the given start the search iterates P (the motion a long
simulation would follow) and after each period looks for the smallest n <=
``periods`` (option ``O_PERIODS``) for which the last states nearly repeat after n
periods. Such a candidate is solved as a fixed point of P^n by Newton's method with
P^n's Jacobian: the driver's tangent (``variational.py``: the variational equations
on the method's own stages, passed through the saltation matrix of every switch).
The fixed point is accepted as the response the start reaches when it is stable
(every multiplier inside the unit circle) and within the distance the iterates'
contraction predicts; it is then reduced to its least period, and the observables
are those of Newton's last run (measured on line, within 1e-2 tol of the fixed
point). A state that starts P^n stuck is one number (x: the stick forgets the
velocity), so its Newton is one-dimensional and its second multiplier is 0.

No period up to ``periods`` within the budget: the response is aperiodic; its
largest Lyapunov exponent is the growth of a tangent vector of the same variational
equations (saltation included), renormalised every period, over ``LYAP_PERIODS``
periods in ``LYAP_BLOCKS`` blocks whose spread gives its error. A negative exponent
beyond three errors is a periodic response not yet found (status unconverged),
never a made-up cycle.
"""
import math

import numpy as np

from . import codes
from .attractor import method_status, resolve_into
from .driver import advance, init_state
from .excitation import period, prepare, rest_band
from .jit import copy_into, kernel, runtime
from .law import anti_damped
from .layout import (IM_J, IM_MODE, IM_MODE0, IM_X, IM_XDOT, NIM, A_IX, A_NSTICK, A_NSTOP, A_TSTICK, A_XDMAX, A_XDMIN, A_XMAX, A_XMIN,
                     K, M, NA, NFOB, NO, NP, NS, NSTATE, O_LV, O_LX, O_MAX_STEPS,
                     O_MAX_TIME, O_PERIODS, O_RTOL, OB_AMPLITUDE, OB_FLOQUET, OB_LYAPUNOV,
                     OB_LYAPUNOV_ERROR, OB_MEAN, OB_MULTIPLICITY, OB_NSTEPS, OB_PERIOD,
                     OB_REGIME, OB_STATUS, OB_STICK_FRACTION, OB_STICKS_PER_PERIOD,
                     OB_STOPS_PER_PERIOD, OB_T_SETTLE, OB_VAMPLITUDE, OB_X_MAX, OB_X_MIN,
                     OB_X_SECTION, OB_XDOT_MAX, OB_XDOT_SECTION, S_ARMED, S_J, S_MODE, S_N,
                     S_SECTIONS, S_T, S_TRACK, S_X, S_ZD, V, X0, XD0)

TRY = 1.0             # states within this (in L) after n periods: try Newton on P^n
RTOL_FLOOR = 1e-13    # the tightest integration tolerance used
COARSE = 1e-6         # the loosest, of a Newton iterate far from the fixed point
LYAP_PERIODS = 256    # periods of the Lyapunov estimate
LYAP_BLOCKS = 8
NH = 40               # stroboscopic states kept (2 n + 2 of them used)
# a point's workspace (``strobe_point``): the option row, the state, the image's
# state, the accumulators, then the search's: its states kept and their counts, the
# cooldown and tries of each n, the fixed point pending with its record, Newton's start
SEARCH = NH * (NSTATE + 2) + 2 * NH + NS + 12 + NSTATE
PEND = NH * (NSTATE + 2) + 2 * NH + NS      # where the pending fixed point's record is
BASE = NO + 2 * NS + NA
WORKSPACE = BASE + SEARCH
# the start's iterate within this (in L) of a stable fixed point of P^n, contracting
# towards it with its pattern of sticks and stops: the response it reaches
CERTIFY = 0.02
# ... or within NEAR (or a quarter of a slide's margin to the belt's speed), its
# deviation predicted by the fixed point's Jacobian to this share of the last one
LINEAR = 0.1
NEAR = 0.1
# a multiplier 1 and an iterate that repeats within this (in L) after n periods: a
# neutral family's member (a stick carried along by the belt has the multiplier 1 of
# its position, but moves by v n T: no fixed point at all)
NEUTRAL = 1e-3
# a stick-slip fixed point on fixed ground with a multiplier within CREEP of 1, within
# EDGE (in L) outside the positions where the slider rests for ever: the motion creeps
# to the edge of that band, its slips shrinking without end (``_creeps``)
CREEP = 1e-3
EDGE = 1e-3
# what a candidate fixed point did to the search
GO_ON = 0
ANSWERED = 1
PENDING = 2


@kernel
def fresh(acc):
    """Accumulators of a measured run: sums 0, extrema empty."""
    acc[:] = 0.0
    acc[A_XMAX] = -np.inf
    acc[A_XMIN] = np.inf
    acc[A_XDMAX] = -np.inf
    acc[A_XDMIN] = np.inf


@kernel
def run_periods(meth, st, p, lw, fx, o, acc, T, n):
    """Advance st by n forcing periods (its clock restarts at 0 each period: the load
    has period T); returns the status."""
    for _ in range(n):
        while st[S_T] < T:
            _ev, status = advance(meth, st, p, lw, fx, o, acc, T)
            if status != codes.OK:
                return status
        st[S_T] = 0.0
    return codes.OK


@kernel
def keep(dst, src):
    """Copy the state proper (``NSTATE`` slots, no scratch) from src to dst."""
    for i in range(NSTATE):
        dst[i] = src[i]


@kernel(inline="always")
def _dist(a, b, lx, lv):
    """Distance of two stroboscopic states in units of L (inf: other phases)."""
    if a[S_MODE] != b[S_MODE]:
        return np.inf
    return max(abs(a[S_X] - b[S_X]) / lx, abs(a[S_ZD] - b[S_ZD]) / lv)


@kernel
def _image(meth, u, n, p, lw, fx, o, acc, T, work, track):
    """P^n of the state u into ``work``, the observables of the run in ``acc``, and
    with ``track`` its Jacobian in ``work[S_J:]`` (row by row); the steps spent are
    added to u's count. Returns the status."""
    keep(work, u)
    work[S_TRACK] = 1.0 if track else 0.0
    work[S_J] = 1.0
    work[S_J + 1] = 0.0
    work[S_J + 2] = 0.0
    work[S_J + 3] = 1.0
    fresh(acc)
    status = run_periods(meth, work, p, lw, fx, o, acc, T, n)
    u[S_N] = work[S_N]
    return status


@kernel(inline="always")
def _multipliers(j11, j12, j21, j22):
    """Moduli of the eigenvalues of a 2 x 2 matrix, larger first."""
    tr = j11 + j22
    det = j11 * j22 - j12 * j21
    disc = tr * tr - 4.0 * det
    if disc >= 0.0:
        sq = math.sqrt(disc)
        a = abs(0.5 * (tr + sq))
        b = abs(0.5 * (tr - sq))
        return max(a, b), min(a, b)
    r = math.sqrt(max(det, 0.0))
    return r, r


@kernel
def newton(meth, u, n, p, lw, fx, o, acc, T, work, tol, out):
    """Fixed point of P^n near u (u moved to it): ``(ok, mu1, mu2, status)``, the
    moduli of P^n's multipliers there (larger first); on ok the observables of the
    last run (from within 1e-2 tol of the fixed point, at the point's integration
    tolerance) are in ``out``. An inexact Newton: far from the fixed point an image
    is integrated only as finely as the next step needs (``COARSE`` at most, and a
    thousandth of the square of the last step: Newton's error after it)."""
    lx = o[O_LX]
    lv = o[O_LV]
    rtol = o[O_RTOL]
    stuck = u[S_MODE] == codes.STICK
    mu1 = np.nan
    mu2 = np.nan
    last = np.inf
    for _it in range(20):
        o[O_RTOL] = max(rtol, min(COARSE, 1e-3 * last * last))
        status = _image(meth, u, n, p, lw, fx, o, acc, T, work, runtime(True))
        fine = o[O_RTOL] == rtol
        o[O_RTOL] = rtol
        if status != codes.OK:
            return False, mu1, mu2, status
        if work[S_MODE] != u[S_MODE]:
            return False, mu1, mu2, codes.OK
        mu1, mu2, dx, dz, res = _newton_step(u, work, stuck, lx, lv)
        step = max(abs(dx) / lx, abs(dz) / lv)
        # a fixed point (a neutral one too): u itself, within 1e-2 tol (a small step
        # counts only beside a small residual: a singular Jacobian gives none)
        if res <= 1e-2 * tol or (step <= 1e-2 * tol and res <= 10.0 * tol):
            if fine:
                _observables(acc, n * T, out)
                return True, mu1, mu2, codes.OK
            last = 0.0      # once more, at the point's tolerance
            continue
        if not step > 0.0 or step > 10.0 * TRY:  # singular, or a jump away
            return False, mu1, mu2, codes.OK
        u[S_X] += dx
        if not stuck:
            u[S_ZD] += dz
            if u[S_ZD] == 0.0 or (u[S_ZD] > 0.0) != (u[S_MODE] > 0.0):
                return False, mu1, mu2, codes.OK
            u[S_ARMED] = 1.0
        last = step
    return False, mu1, mu2, codes.OK


@kernel
def _newton_step(u, work, stuck, lx, lv):
    """From u and its image with the tangent in ``work``: the multipliers' moduli,
    Newton's step (dx, dz) and the residual [L]. A stuck u is one number (x)."""
    j11, j12, j21, j22 = work[S_J], work[S_J + 1], work[S_J + 2], work[S_J + 3]
    rx = work[S_X] - u[S_X]
    if stuck:
        return abs(j11), 0.0, -rx / (j11 - 1.0) if j11 != 1.0 else 0.0, 0.0, abs(rx) / lx
    mu1, mu2 = _multipliers(j11, j12, j21, j22)
    rz = work[S_ZD] - u[S_ZD]
    a11 = j11 - 1.0
    a22 = j22 - 1.0
    dd = a11 * a22 - j12 * j21
    dx = (-rx * a22 + rz * j12) / dd if dd != 0.0 else 0.0
    dz = (-rz * a11 + rx * j21) / dd if dd != 0.0 else 0.0
    return mu1, mu2, dx, dz, max(abs(rx) / lx, abs(rz) / lv)


@kernel
def lyapunov(meth, u, p, lw, fx, o, acc, T, work, out):
    """Largest Lyapunov exponent [1/s] and its error over LYAP_PERIODS periods from
    u: a tangent vector of the variational equations (saltation at every switch)
    renormalised every period; the observables of those periods into out. Returns
    the status."""
    lx = o[O_LX]
    lv = o[O_LV]
    keep(work, u)
    work[S_TRACK] = 1.0
    fresh(acc)
    per = LYAP_PERIODS // LYAP_BLOCKS
    sums = np.zeros(LYAP_BLOCKS)
    wx = 1.0 / math.sqrt(2.0)          # the tangent vector, in units of (L, L omega)
    wz = 1.0 / math.sqrt(2.0)
    for b in range(LYAP_BLOCKS):
        for _j in range(per):
            work[S_J] = 1.0
            work[S_J + 1] = 0.0
            work[S_J + 2] = 0.0
            work[S_J + 3] = 1.0
            status = run_periods(meth, work, p, lw, fx, o, acc, T, runtime(1))
            if status != codes.OK:
                return status
            ex = (work[S_J] * wx * lx + work[S_J + 1] * wz * lv) / lx
            ez = (work[S_J + 2] * wx * lx + work[S_J + 3] * wz * lv) / lv
            d = math.hypot(ex, ez)
            if not d > 0.0:             # a stick forgot the vector: superstable
                sums[b] += -745.0
                wx, wz = 1.0, 0.0
                continue
            sums[b] += math.log(d)
            wx, wz = ex / d, ez / d
    rates = sums / (per * T)
    _observables(acc, LYAP_PERIODS * T, out)
    out[OB_STICKS_PER_PERIOD] = np.nan
    out[OB_STOPS_PER_PERIOD] = np.nan
    out[OB_LYAPUNOV] = rates.mean()
    out[OB_LYAPUNOV_ERROR] = rates.std() / math.sqrt(LYAP_BLOCKS - 1.0)
    u[S_N] = work[S_N]
    return codes.OK


@kernel
def _observables(acc, dur, out):
    """The on-line observables of a measured run of duration dur [s]."""
    out[OB_AMPLITUDE] = 0.5 * (acc[A_XMAX] - acc[A_XMIN])
    out[OB_MEAN] = acc[A_IX] / dur
    out[OB_VAMPLITUDE] = 0.5 * (acc[A_XDMAX] - acc[A_XDMIN])
    out[OB_X_MAX] = acc[A_XMAX]
    out[OB_X_MIN] = acc[A_XMIN]
    out[OB_XDOT_MAX] = acc[A_XDMAX]
    out[OB_STICK_FRACTION] = min(acc[A_TSTICK] / dur, 1.0)
    out[OB_STICKS_PER_PERIOD] = acc[A_NSTICK]
    out[OB_STOPS_PER_PERIOD] = acc[A_NSTOP]


@kernel
def strobe_point(meth, p, lw, fx, o_in, out, ws):
    """Fill ``out`` (layout OB_*, length NFOB) with the steady response of one forced
    point reached from (p[X0], p[XD0]) at t = 0 (module docstring); ``fx`` the
    excitation as the call's kernels use it (``excitation.with_work``); ``ws`` a
    workspace of ``WORKSPACE`` floats for the point's state (its caller's, a view
    without reference count, ``jit.unowned``: the many kernels the state passes
    through count none)."""
    o, st, work, acc, ok = _start(meth, p, lw, fx, o_in, out, NFOB, ws)
    if not ok:
        return
    T = period(fx)
    answered, status = _search(meth, st, p, lw, fx, o, o_in, acc, T, work, out,
                               ws[BASE:])
    out[OB_NSTEPS] = st[S_N]
    if answered:
        return
    if status == codes.OK:
        status = lyapunov(meth, st, p, lw, fx, o, acc, T, work, out)
        out[OB_NSTEPS] = st[S_N]
    if status != codes.OK:
        _failure(out, status, anti_damped(p, lw))
        return
    if out[OB_LYAPUNOV] + 3.0 * out[OB_LYAPUNOV_ERROR] < 0.0 or ws[BASE + PEND] > 0.0:
        # contracting, or on its way to a stable fixed point not reached in the
        # budget (a multiplier near 1): a period not found, not an aperiodic motion
        out[OB_REGIME] = codes.R_UNCONVERGED
        out[OB_STATUS] = codes.UNCONVERGED
    else:
        out[OB_REGIME] = codes.R_APERIODIC
        out[OB_STATUS] = codes.OK


@kernel
def _start(meth, p, lw, fx, o_in, out, size, ws):
    """A point's start: out (``size`` floats) cleared, the row checked, the
    excitation prepared, the workspace carved (``_carve``) and the state set at
    (p[X0], p[XD0]), t = 0; ``ok`` False where out holds a failure instead."""
    for i in range(out.shape[0]):
        out[i] = np.nan
    out[OB_NSTEPS] = 0.0
    o = ws[:NO]
    st = ws[NO:NO + NS]
    work = ws[NO + NS:NO + 2 * NS]
    acc = ws[NO + 2 * NS:BASE]
    if p.shape[0] != NP or o_in.shape[0] != NO or out.shape[0] != size:
        _failure(out, codes.BAD_ROW, runtime(False))
        return o, st, work, acc, False
    if not prepare(fx, p, lw):
        _failure(out, codes.EVENT_FAILURE, runtime(False))
        return o, st, work, acc, False
    _carve(meth, p, lw, fx, o_in, ws)
    refused = method_status(meth, p, lw, fx, o)
    if refused != codes.OK:
        _failure(out, refused, runtime(False))
        return o, st, work, acc, False
    init_state(st, p[X0], p[XD0], p, lw, fx, o)
    st[S_SECTIONS] = 2.0                 # extrema of x noted, never a stop
    return o, st, work, acc, True


@kernel(inline="always")
def _carve(meth, p, lw, fx, o_in, ws):
    """The option row (resolved for the point, its integration tolerance 1e-2 the
    requested), the state, the image's state and the accumulators: views of ws."""
    o = ws[:NO]
    copy_into(o, o_in)
    resolve_into(meth, p, lw, fx, o)
    o[O_RTOL] = max(1e-2 * o_in[O_RTOL], RTOL_FLOOR)
    st = ws[NO:NO + NS]
    work = ws[NO + NS:NO + 2 * NS]
    for i in range(NS):
        st[i] = 0.0
        work[i] = 0.0
    return o, st, work, ws[NO + 2 * NS:BASE]


@kernel
def _search(meth, st, p, lw, fx, o, o_in, acc, T, work, out, ws):
    """Iterate P from st, trying Newton on P^n where states nearly repeat after n
    periods; a stable fixed point found is the answer once the start's own motion
    is shown to converge to it (``_certify``). Returns ``(answered, status)``:
    answered when ``out`` holds the answer, else the status with which the search
    ended (ok: the budget spent, out[OB_T_SETTLE] set). ``ws``: the workspace's
    ``SEARCH`` floats for the states kept."""
    nmax = min(int(o_in[O_PERIODS]), (NH - 2) // 2)
    lx = o[O_LX]
    lv = o[O_LV]
    for i in range(SEARCH):
        ws[i] = 0.0
    hist = ws[:NH * NSTATE].reshape((NH, NSTATE))
    counts = ws[NH * NSTATE:NH * (NSTATE + 2)].reshape((NH, 2))   # sticks, stops
    # the budget: max_periods natural periods, at least 4 nmax + 8 forcing periods
    omega = math.sqrt(p[K] / p[M])
    jmax = max(int(o[O_MAX_TIME] * 2.0 * math.pi / omega / T), 4 * nmax + 8)
    keep(hist[0], st)
    at = NH * (NSTATE + 2)
    cooldown = ws[at:at + NH]
    tries = ws[at + NH:at + 2 * NH]
    u = ws[at + 2 * NH:at + 2 * NH + NS]
    # the fixed point u pending: its n (0: none), its last check's period and
    # distance [L], its mu1, whether it is resolved, its Jacobian (4), the last
    # deviation of the motion from it (x, zdot), its margin to the belt's speed [L]
    pend = ws[PEND:PEND + 12]
    start = ws[PEND + 12:SEARCH]
    for j in range(1, jmax + 1):
        fresh(acc)
        status = run_periods(meth, st, p, lw, fx, o, acc, T, runtime(1))
        if status == codes.OK and st[S_N] >= o[O_MAX_STEPS]:
            status = codes.STEP_BUDGET
        if status != codes.OK:
            return False, status
        keep(hist[j % NH], st)
        counts[j % NH, 0] = acc[A_NSTICK]
        counts[j % NH, 1] = acc[A_NSTOP]
        if pend[0] > 0.0:
            verdict = _certify(st, u, j, pend, lx, lv, o_in[O_RTOL],
                               _same_pattern(counts, j, int(pend[0]), out))
            if verdict == ANSWERED:
                _answered(u, int(pend[0]), j, pend[3], pend[4] > 0.0, p, o, T, out,
                          o_in[O_RTOL])
                return True, codes.OK
            if verdict == PENDING:
                continue
        for n in range(1, min(nmax, j) + 1):
            d = _dist(st, hist[(j - n) % NH], lx, lv)
            if not d <= TRY or cooldown[n] > j:
                continue
            keep(u, st)
            verdict, status = _candidate(meth, u, n, j, d, p, lw, fx, o, o_in[O_RTOL],
                                         acc, T, work, out, pend, start)
            st[S_N] = u[S_N]
            if status != codes.OK:
                return False, status
            if verdict == PENDING:      # on it already: the motion's iterate is u
                pend[1] = j
                pend[2] = _dist(st, u, lx, lv)
                pend[9] = st[S_X] - u[S_X]
                pend[10] = st[S_ZD] - u[S_ZD]
                if pend[2] <= 10.0 * o_in[O_RTOL]:
                    verdict = ANSWERED
                    _answered(u, int(pend[0]), j, pend[3], pend[4] > 0.0, p, o, T, out,
                              o_in[O_RTOL])
            if verdict == ANSWERED:
                return True, codes.OK
            tries[n] += 1.0
            cooldown[n] = j + (2 * n + 2) * 2.0 ** min(tries[n], 20.0)
            break
    out[OB_T_SETTLE] = jmax * T
    return False, codes.OK


@kernel
def _certify(st, u, j, pend, lx, lv, tol, same):
    """Whether the start's own motion st (period j) converges to the stable fixed
    point u of P^n (``pend``: n, the period of the last check, its distance [L],
    mu1, ok, P^n's Jacobian at u (4), the last deviation st - u (2), u's margin to
    the belt's speed [L]). Every n-th period the deviation must be what u's
    linearisation predicts, J times the last one (to ``LINEAR`` of it: a spiral's
    distance need not shrink every period), or shrink by ``(1 + |mu1|)/2`` at least.
    The motion is then u's response (ANSWERED) once it has u's sticks and stops
    (``same``) and is within ``CERTIFY`` of u, shrinking, or follows the
    linearisation within ``NEAR`` of u; for a slide that never reaches the belt's
    speed, within a quarter of its margin to that speed in both (farther, it could
    reach the belt and stick: a coexisting stick-slip response); within 10 tol it
    is u. Still on its way: PENDING. Neither (a coexisting
    response it does not reach): GO_ON, and u is dropped."""
    n = int(pend[0])
    if (j - int(pend[1])) % n != 0:
        return PENDING
    dx = st[S_X] - u[S_X]
    dz = st[S_ZD] - u[S_ZD]
    e = _dist(st, u, lx, lv)
    if e <= 10.0 * tol:
        return ANSWERED
    px = pend[5] * pend[9] + pend[6] * pend[10]
    pz = pend[7] * pend[9] + pend[8] * pend[10]
    linear = max(abs(dx - px) / lx, abs(dz - pz) / lv) <= LINEAR * pend[2]
    shrinks = e <= 0.5 * (1.0 + min(pend[3], 1.0)) * pend[2]
    if not (linear or shrinks):
        pend[0] = 0.0
        return GO_ON
    # a slide that never reaches the belt's speed: a quarter of its margin to that
    # speed bounds both radii (a deviation beyond it can reach the belt and stick)
    slide = pend[11] > 0.0
    close = min(CERTIFY, 0.25 * pend[11]) if slide else CERTIFY
    near = 0.25 * pend[11] if slide else NEAR
    if same and ((e <= close and shrinks) or (linear and e <= near)):
        return ANSWERED
    pend[1] = j
    pend[2] = e
    pend[9] = dx
    pend[10] = dz
    return PENDING


@kernel
def _candidate(meth, u, n, j, d, p, lw, fx, o, tol, acc, T, work, out, pend, start):
    """Newton on P^n from the state u, j periods in, whose iterate moved by d (in L)
    over the last n periods: ``(verdict, status)``, PENDING with u the stable fixed
    point (``pend``: its n, mu1 and whether it is resolved; ``out``: its
    observables) that the start's motion must then be shown to reach
    (``_certify``); ANSWERED for a multiplier 1 where the motion itself repeats
    (within ``NEUTRAL`` L: a neutral family, never ok); else GO_ON."""
    keep(start, u)
    ok, mu1, mu2, status = newton(meth, u, n, p, lw, fx, o, acc, T, work, tol, out)
    _keep_jacobian(pend, work)
    if status == codes.OK and ok:
        m, ok, mu1, status = _least_period(meth, u, n, p, lw, fx, o, acc, T, work, tol,
                                           mu1, out)
        if m != n:                  # solved again on P^m
            _keep_jacobian(pend, work)
        n = m
    if status != codes.OK:
        return GO_ON, status
    if ok and mu1 >= 1.0 - CREEP and out[OB_STICKS_PER_PERIOD] > 0.0:
        edge = _creeps(u[S_X], start[S_X], p, lw, fx, o)
        if not math.isnan(edge):
            return _at_rest(meth, u, edge, j, p, lw, fx, o, acc, T, work, out, tol)
    if ok and mu1 < 1.0 - 1e-9:
        # the integration error of n periods, amplified by 1/(1 - mu1) in the fixed
        # point, must be within tol: else solve again, tighter
        need = n * o[O_RTOL] / (1.0 - mu1)
        if need > tol and o[O_RTOL] > RTOL_FLOOR:
            o[O_RTOL] = max(RTOL_FLOOR, 0.5 * o[O_RTOL] * tol / need)
            ok, mu1, mu2, status = newton(meth, u, n, p, lw, fx, o, acc, T, work, tol,
                                          out)
            if status != codes.OK:
                return GO_ON, status
            _keep_jacobian(pend, work)
        pend[0] = n
        pend[3] = mu1
        pend[4] = 1.0 if ok else 0.0
        pend[11] = _margin(p, o, out)
        return PENDING, codes.OK
    if abs(mu1 - 1.0) <= 1e-3 and mu2 < 1.0 and d <= NEUTRAL:
        # a multiplier 1 and no isolated fixed point: the motion's own numbers, never
        # ok (a neutral family, whose member the start picks, is named by the Python
        # side where one exists: sweepcore.excitations.periodic._flag_neutral)
        if not ok:
            keep(u, start)
            status = _image(meth, u, n, p, lw, fx, o, acc, T, work, runtime(False))
            if status != codes.OK:
                return GO_ON, status
            _observables(acc, n * T, out)
        _answer(u, n, j, mu1, p, o, T, out, tol)
        if out[OB_REGIME] != codes.R_STUCK:   # stuck throughout: exact
            out[OB_STATUS] = codes.UNRESOLVED
        return ANSWERED, codes.OK
    return GO_ON, codes.OK


@kernel
def _creeps(x, x_motion, p, lw, fx, o):
    """The edge [cm] of the band where a slider on fixed ground rests for ever
    (``excitation.rest_band``) to which the motion creeps, NaN if it does not: the
    stick-slip fixed point x found (a multiplier near 1) lies within EDGE outside the
    band and the motion's iterate x_motion outside on the same side. There every
    period's slip is towards the band and shrinks with the distance to its edge, so
    the motion approaches the edge without end and P's near-fixed points beside it
    are not fixed points (Newton's residual vanishes there to a higher order, and a
    residual within tol leaves the point far more than tol from the edge)."""
    lo, hi = rest_band(fx, p, lw)
    if not lo <= hi:
        return np.nan
    lx = o[O_LX]
    if hi < x <= hi + EDGE * lx and x_motion > hi:
        return hi
    if lo - EDGE * lx <= x < lo and x_motion < lo:
        return lo
    return np.nan


@kernel
def _at_rest(meth, u, edge, j, p, lw, fx, o, acc, T, work, out, tol):
    """The answer of a motion creeping to ``edge`` (``_creeps``): its limit, the
    slider at rest there (a thousandth of tol inside the band: the rest is exact to
    that), which the motion reaches only as time goes to infinity (t_settle: when
    it was found). Returns ``(ANSWERED, status)``."""
    inward = 1e-3 * tol * o[O_LX]
    u[S_X] = edge - inward if u[S_X] > edge else edge + inward
    u[S_ZD] = 0.0
    u[S_MODE] = codes.STICK
    u[S_ARMED] = 0.0
    one = runtime(1)            # one period (a literal would compile _image again)
    status = _image(meth, u, one, p, lw, fx, o, acc, T, work, runtime(False))
    if status != codes.OK:
        return GO_ON, status
    _observables(acc, T, out)
    _answer(u, one, j, 1.0, p, o, T, out, tol)
    if out[OB_REGIME] != codes.R_STUCK:     # the band's edge not held: no answer
        return GO_ON, codes.OK
    return ANSWERED, codes.OK


@kernel
def _margin(p, o, out):
    """How far [L] the response of ``out`` keeps from the belt's speed (its velocity
    scale's units): a slide that never sticks or stops, 0 otherwise."""
    if out[OB_STICKS_PER_PERIOD] != 0.0 or out[OB_STOPS_PER_PERIOD] != 0.0:
        return 0.0
    v = p[V]
    top = out[OB_XDOT_MAX]
    bottom = top - 2.0 * out[OB_VAMPLITUDE]
    return min(abs(v - top), abs(v - bottom)) / o[O_LV]


@kernel
def _same_pattern(counts, j, n, out):
    """Whether the last n periods had the fixed point's sticks and stops (``out``,
    measured by Newton over its n periods)."""
    sticks = 0.0
    stops = 0.0
    for i in range(n):
        sticks += counts[(j - i) % NH, 0]
        stops += counts[(j - i) % NH, 1]
    return sticks == out[OB_STICKS_PER_PERIOD] and stops == out[OB_STOPS_PER_PERIOD]


@kernel(inline="always")
def _keep_jacobian(pend, work):
    """P^n's Jacobian at the fixed point, from Newton's last (tracked) image."""
    for i in range(4):
        pend[5 + i] = work[S_J + i]


@kernel
def _answered(u, n, j, mu1, ok, p, o, T, out, tol):
    """The answer of the certified fixed point u of P^n (observables in ``out``)."""
    _answer(u, n, j, mu1, p, o, T, out, tol)
    if not ok:
        out[OB_STATUS] = codes.UNRESOLVED


@kernel
def _least_period(meth, u, n, p, lw, fx, o, acc, T, work, tol, mu1, out):
    """The least period m of the fixed point u of P^n (m divides n): the response
    is a fixed point of P^m when P^m(u) returns to u within the accuracy asked.
    Returns ``(m, ok, mu1, status)``, re-solved on P^m where m < n (P^n's
    multipliers are P^m's to the power n/m: a negative multiplier of P makes the
    iterates alternate, and P^2's candidate is found first)."""
    for m in range(1, n):
        if n % m != 0:
            continue
        status = _image(meth, u, m, p, lw, fx, o, acc, T, work, runtime(False))
        if status != codes.OK:
            return n, False, mu1, status
        if _dist(work, u, o[O_LX], o[O_LV]) <= max(1e2 * tol, 1e4 * o[O_RTOL]):
            ok, mu, _mu2, status = newton(meth, u, m, p, lw, fx, o, acc, T, work, tol,
                                          out)
            return m, ok, mu, status
    return n, True, mu1, codes.OK


@kernel
def _failure(out, status, grows):
    """A failed search: no numbers, its status; a divergence of a law anti-damped at
    high speed is the motion's own growth (regime unbounded)."""
    n = out[OB_NSTEPS]
    for i in range(NFOB):
        out[i] = np.nan
    out[OB_NSTEPS] = n
    out[OB_STATUS] = status
    out[OB_REGIME] = codes.R_UNBOUNDED if status == codes.DIVERGED and grows \
        else codes.R_FAILED


@kernel
def _answer(u, n, j, mu1, p, o, T, out, tol):
    """The response of the fixed point u of P^n, its observables measured on line
    (``newton``). Its error estimate, the integration error of n periods amplified
    by 1/(1 - mu1), must be within tol."""
    out[OB_NSTEPS] = u[S_N]
    out[OB_MULTIPLICITY] = n
    out[OB_PERIOD] = n * T
    out[OB_FLOQUET] = mu1
    out[OB_T_SETTLE] = j * T
    out[OB_X_SECTION] = u[S_X]
    out[OB_XDOT_SECTION] = u[S_ZD] + p[V]
    out[OB_LYAPUNOV] = math.log(max(mu1, 1e-300)) / (n * T)
    out[OB_LYAPUNOV_ERROR] = 0.0
    if out[OB_STICK_FRACTION] >= 1.0:
        out[OB_REGIME] = codes.R_STUCK
        out[OB_STATUS] = codes.OK
        out[OB_LYAPUNOV] = np.nan
        return
    if out[OB_STICKS_PER_PERIOD] > 0.0:
        out[OB_REGIME] = codes.R_STICK_SLIP
    else:
        out[OB_REGIME] = codes.R_SLIP_CYCLE
    amplified = n * o[O_RTOL] / max(1.0 - mu1, 1e-300)
    out[OB_STATUS] = codes.OK if amplified <= tol else codes.UNRESOLVED


@kernel
def image_point(meth, p, lw, fx, o_in, n, out, ws):
    """``P^n`` of the start (p[X0], p[XD0]) at t = 0 (the periodic point's coordinates:
    a state at a whole number of forcing periods), with its tangent and the
    observables of the run, into ``out`` (layout OB_*, length NFOB, and
    ``IM_*``): the primitive of a continuation (``sweepcore.continuation``), whose
    Newton and pseudo-arclength steps run in Python on these images."""
    o, u, work, acc, ok = _start(meth, p, lw, fx, o_in, out, NFOB + NIM, ws)
    if not ok:
        return
    T = period(fx)
    status = _image(meth, u, n, p, lw, fx, o, acc, T, work, runtime(True))
    out[OB_NSTEPS] = u[S_N]
    out[OB_STATUS] = status
    if status != codes.OK:
        out[OB_REGIME] = codes.R_FAILED
        return
    _observables(acc, n * T, out)
    out[OB_PERIOD] = n * T
    out[NFOB + IM_MODE0] = u[S_MODE]
    out[NFOB + IM_MODE] = work[S_MODE]
    out[NFOB + IM_X] = work[S_X]
    out[NFOB + IM_XDOT] = work[S_ZD] + p[V]
    for i in range(4):
        out[NFOB + IM_J + i] = work[S_J + i]
