"""The steady response of a forced slider: a fixed point of the stroboscopic map.

P maps the state (x, zdot, phase mode) at a time t = j T, T = 2 pi / Omega the
forcing period (``excitations/``), to the state one period later. From the given
start the search iterates P (the motion a long simulation would follow) and after
each period looks for the smallest n <= ``periods`` (option ``O_PERIODS``) for which
the last states nearly repeat after n periods. Such a candidate is solved as a fixed
point of P^n by Newton's method with P^n's Jacobian from the variational equations,
integrated with the motion (``forced_step``) and passed through the saltation
matrix of every switch (``forced_driver._finish``: a stick zeroes the velocity's
row, a stop scales it by the ratio of the accelerations after and before; the
release from a stick is the identity). The fixed point is accepted as the response
the start reaches when it is stable (every multiplier inside the unit circle) and
within the distance the iterates' contraction predicts; it is then reduced to its
least period, and one run of n periods from it measures the observables on line. A
state that starts P^n stuck is one number (x: the stick forgets the velocity), so
its Newton is one-dimensional and its second multiplier is 0.

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
from .excitation import coefficients, forcing_period
from .forced_driver import advance_forced, initial_forced
from .jit import copy_into, kernel, runtime
from .law import anti_damped, length_scale
from .layout import (A_IX, A_NSTICK, A_NSTOP, A_TSTICK, A_XDMAX, A_XDMIN, A_XMAX, A_XMIN,
                     K, M, NA, NFOB, NO, NP, NS, O_LV, O_LX, O_MAX_STEPS, O_MAX_TIME,
                     O_PERIODS, O_RTOL, OB_AMPLITUDE, OB_FLOQUET, OB_LYAPUNOV,
                     OB_LYAPUNOV_ERROR, OB_MEAN, OB_MULTIPLICITY, OB_NSTEPS, OB_PERIOD,
                     OB_REGIME, OB_STATUS, OB_STICK_FRACTION, OB_STICKS_PER_PERIOD,
                     OB_STOPS_PER_PERIOD, OB_T_SETTLE, OB_VAMPLITUDE, OB_X_MAX, OB_X_MIN,
                     OB_XDOT_MAX, S_ARMED, S_MODE, S_N, S_T, S_X, S_ZD, V, X0, XD0)

TRY = 1.0             # states within this (in L) after n periods: try Newton on P^n
MEASURE_AT = 1e-4     # Newton's last step [L] below which its next run measures
RTOL_FLOOR = 1e-13    # the tightest integration tolerance used
LYAP_PERIODS = 256    # periods of the Lyapunov estimate
LYAP_BLOCKS = 8
NH = 40               # stroboscopic states kept (2 n + 2 of them used)


@kernel
def forced_options(p, lw, fa, fb, om, o_in):
    """The point's option row: scales L = r/k + |v|/omega + |e|/k [cm] and
    max(|v|, omega L) [cm/s]; the integration tolerance a hundredth of the asked
    one (>= RTOL_FLOOR)."""
    o = o_in.copy()
    omega = math.sqrt(p[K] / p[M])
    lx = length_scale(p, lw) + math.hypot(fa, fb) / p[K]
    if not lx > 0.0:
        lx = 1.0
    o[O_LX] = lx
    o[O_LV] = max(abs(p[V]), omega * lx)
    o[O_RTOL] = max(1e-2 * o_in[O_RTOL], RTOL_FLOOR)
    return o


@kernel
def fresh(acc):
    acc[:] = 0.0
    acc[A_XMAX] = -np.inf
    acc[A_XMIN] = np.inf
    acc[A_XDMAX] = -np.inf
    acc[A_XDMIN] = np.inf


@kernel
def run_periods(st, p, lw, fa, fb, om, o, acc, ws, vw, T, n, measure, track):
    """Advance st by n forcing periods (its clock restarts at 0 each period: the load
    has period T); returns the status."""
    for _ in range(n):
        while st[S_T] < T:
            _ev, status = advance_forced(st, p, lw, fa, fb, om, o, acc, ws, vw, T,
                                         measure, track)
            if status != codes.OK:
                return status
        st[S_T] = 0.0
    return codes.OK


@kernel(inline="always")
def _dist(a, b, lx, lv):
    """Distance of two stroboscopic states in units of L (inf: other phases)."""
    if a[S_MODE] != b[S_MODE]:
        return np.inf
    return max(abs(a[S_X] - b[S_X]) / lx, abs(a[S_ZD] - b[S_ZD]) / lv)


@kernel
def _image(u, n, p, lw, fa, fb, om, o, acc, ws, vw, T, work, measure):
    """P^n of the state u into ``work``, with its Jacobian in ``vw[0]`` (row by
    row), and with ``measure`` the observables on line in ``acc`` (reset first);
    the steps spent are added to u's count. Returns the status."""
    copy_into(work, u)
    vw[0, 0] = 1.0
    vw[0, 1] = 0.0
    vw[0, 2] = 0.0
    vw[0, 3] = 1.0
    if measure:
        fresh(acc)
    status = run_periods(work, p, lw, fa, fb, om, o, acc, ws, vw, T, n, measure,
                         runtime(True))
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
def newton(u, n, p, lw, fa, fb, om, o, acc, ws, vw, T, work, tol, out):
    """Fixed point of P^n near u (u moved to it): ``(ok, mu1, mu2, measured,
    status)``, the moduli of P^n's multipliers there (larger first). Once Newton's
    steps are below ``MEASURE_AT`` the next run measures the observables on line
    (into ``out``): when that run ends the search (its start within 1e-2 tol of the
    fixed point), ``measured`` says so and no run is spent on measuring."""
    lx = o[O_LX]
    lv = o[O_LV]
    stuck = u[S_MODE] == codes.STICK
    mu1 = np.nan
    mu2 = np.nan
    last = np.inf
    for _it in range(16):
        on = last <= MEASURE_AT
        status = _image(u, n, p, lw, fa, fb, om, o, acc, ws, vw, T, work, on)
        if status != codes.OK:
            return False, mu1, mu2, False, status
        if work[S_MODE] != u[S_MODE]:
            return False, mu1, mu2, False, codes.OK
        j11, j12, j21, j22 = vw[0, 0], vw[0, 1], vw[0, 2], vw[0, 3]
        rx = work[S_X] - u[S_X]
        if stuck:
            mu1, mu2 = abs(j11), 0.0
            dx = -rx / (j11 - 1.0) if j11 != 1.0 else 0.0
            dz = 0.0
            rz = 0.0
        else:
            mu1, mu2 = _multipliers(j11, j12, j21, j22)
            rz = work[S_ZD] - u[S_ZD]
            a11 = j11 - 1.0
            a22 = j22 - 1.0
            dd = a11 * a22 - j12 * j21
            dx = (-rx * a22 + rz * j12) / dd if dd != 0.0 else 0.0
            dz = (-rz * a11 + rx * j21) / dd if dd != 0.0 else 0.0
        step = max(abs(dx) / lx, abs(dz) / lv)
        if max(abs(rx) / lx, abs(rz) / lv) <= 1e-2 * tol or step <= 1e-2 * tol:
            # a fixed point (a neutral one too): u itself, within 1e-2 tol
            if on:
                _observables(acc, n * T, out)
            return True, mu1, mu2, on, codes.OK
        if not step > 0.0 or step > 10.0 * TRY:  # singular, or a jump away
            return False, mu1, mu2, False, codes.OK
        u[S_X] += dx
        if not stuck:
            u[S_ZD] += dz
            if u[S_ZD] == 0.0 or (u[S_ZD] > 0.0) != (u[S_MODE] > 0.0):
                return False, mu1, mu2, False, codes.OK
            u[S_ARMED] = 1.0
        last = step
    return False, mu1, mu2, False, codes.OK


@kernel
def measure(u, n, p, lw, fa, fb, om, o, acc, ws, vw, T, work, out):
    """Run n periods from u with the observables on; write them into out. Returns
    the status and the distance [L] of the end from u."""
    copy_into(work, u)
    fresh(acc)
    status = run_periods(work, p, lw, fa, fb, om, o, acc, ws, vw, T, n, runtime(True),
                         runtime(False))
    u[S_N] = work[S_N]
    if status != codes.OK:
        return status, np.inf
    _observables(acc, n * T, out)
    return codes.OK, _dist(work, u, o[O_LX], o[O_LV])


@kernel
def lyapunov(u, p, lw, fa, fb, om, o, acc, ws, vw, T, work, out):
    """Largest Lyapunov exponent [1/s] and its error over LYAP_PERIODS periods from
    u: a tangent vector of the variational equations (saltation at every switch)
    renormalised every period; the observables of those periods into out. Returns
    the status."""
    lx = o[O_LX]
    lv = o[O_LV]
    copy_into(work, u)
    fresh(acc)
    per = LYAP_PERIODS // LYAP_BLOCKS
    sums = np.zeros(LYAP_BLOCKS)
    wx = 1.0 / math.sqrt(2.0)          # the tangent vector, in units of (L, L omega)
    wz = 1.0 / math.sqrt(2.0)
    for b in range(LYAP_BLOCKS):
        for _j in range(per):
            vw[0, 0] = 1.0
            vw[0, 1] = 0.0
            vw[0, 2] = 0.0
            vw[0, 3] = 1.0
            status = run_periods(work, p, lw, fa, fb, om, o, acc, ws, vw, T, runtime(1),
                                 runtime(True), runtime(True))
            if status != codes.OK:
                return status
            dx = vw[0, 0] * wx * lx + vw[0, 1] * wz * lv
            dz = vw[0, 2] * wx * lx + vw[0, 3] * wz * lv
            ex = dx / lx
            ez = dz / lv
            d = math.hypot(ex, ez)
            if not d > 0.0:             # a stick forgot the vector: superstable
                sums[b] += -745.0
                wx, wz = 1.0, 0.0
                continue
            sums[b] += math.log(d)
            wx, wz = ex / d, ez / d
    rates = sums / (per * T)
    dur = LYAP_PERIODS * T
    _observables(acc, dur, out)
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
def forced_point(meth, p, lw, ex, o_in, out):
    """Fill ``out`` (layout OB_*, length NFOB) with the steady response of one forced
    point reached from (p[X0], p[XD0]) at t = 0 (module docstring)."""
    for i in range(NFOB):
        out[i] = np.nan
    out[OB_NSTEPS] = 0.0
    if p.shape[0] != NP or o_in.shape[0] != NO or out.shape[0] != NFOB:
        out[OB_REGIME] = codes.R_FAILED
        out[OB_STATUS] = codes.BAD_ROW
        return
    fa, fb, om = coefficients(ex, p)
    T = forcing_period(ex, p)
    o = forced_options(p, lw, fa, fb, om, o_in)
    nmax = min(int(o_in[O_PERIODS]), (NH - 2) // 2)
    tol = o_in[O_RTOL]
    lx = o[O_LX]
    lv = o[O_LV]
    ws = np.empty((8, 12))
    vw = np.zeros((2, 4))
    acc = np.empty(NA)
    fresh(acc)
    st = np.zeros(NS)
    work = np.zeros(NS)
    hist = np.zeros((NH, NS))
    initial_forced(st, p[X0], p[XD0], p, lw, fa, fb, om, o)
    # the budget: max_periods natural periods, at least 4 nmax + 8 forcing periods
    omega = math.sqrt(p[K] / p[M])
    jmax = max(int(o[O_MAX_TIME] * 2.0 * math.pi / omega / T), 4 * nmax + 8)
    copy_into(hist[0], st)
    status = codes.OK
    cooldown = np.zeros(nmax + 1)
    tries = np.zeros(nmax + 1)
    for j in range(1, jmax + 1):
        status = run_periods(st, p, lw, fa, fb, om, o, acc, ws, vw, T, runtime(1),
                             runtime(False), runtime(False))
        if status == codes.OK and st[S_N] >= o[O_MAX_STEPS]:
            status = codes.STEP_BUDGET
        if status != codes.OK:
            break
        copy_into(hist[j % NH], st)
        for n in range(1, min(nmax, j) + 1):
            d = _dist(st, hist[(j - n) % NH], lx, lv)
            if not d <= TRY or cooldown[n] > j:
                continue
            u = st.copy()
            ok, mu1, mu2, measured, status = newton(u, n, p, lw, fa, fb, om, o, acc, ws,
                                                    vw, T, work, tol, out)
            st[S_N] = u[S_N]
            if status == codes.OK and ok:
                m, ok, mu1, status = _least_period(u, n, p, lw, fa, fb, om, o, acc, ws,
                                                   vw, T, work, tol, mu1, out)
                measured = measured and m == n
                n = m
                st[S_N] = u[S_N]
            if status != codes.OK:
                break
            # the start reaches it: stable, and as near as the contraction predicts
            near = _dist(u, st, lx, lv) <= max(2.0 * d / max(1.0 - mu1, 1e-3), 10.0 * tol)
            if ok and near and mu1 < 1.0 - 1e-9:
                # the integration error of n periods, amplified by 1/(1 - mu1) in
                # the fixed point, must be within tol: else solve again, tighter
                need = n * o[O_RTOL] / (1.0 - mu1)
                if need > tol and o[O_RTOL] > RTOL_FLOOR:
                    o[O_RTOL] = max(RTOL_FLOOR, 0.5 * o[O_RTOL] * tol / need)
                    ok, mu1, mu2, measured, status = newton(u, n, p, lw, fa, fb, om, o,
                                                            acc, ws, vw, T, work, tol, out)
                    st[S_N] = u[S_N]
                    if status != codes.OK:
                        break
                _answer(u, n, j, mu1, p, lw, fa, fb, om, o, acc, ws, vw, T, work, out, tol,
                        measured)
                if not ok:
                    out[OB_STATUS] = codes.UNRESOLVED
                return
            if abs(mu1 - 1.0) <= 1e-3 and mu2 < 1.0 and (near or not ok):
                # a multiplier 1 and no isolated fixed point: a neutral family (at
                # Omega/omega = 1/(2 n), c = 0), whose member the start picks
                _answer(u if ok else st.copy(), n, j, mu1, p, lw, fa, fb, om, o, acc, ws,
                        vw, T, work, out, tol, runtime(False))
                if out[OB_REGIME] != codes.R_STUCK:   # stuck throughout: exact
                    out[OB_REGIME] = codes.R_NEUTRAL
                    out[OB_STATUS] = codes.UNRESOLVED
                return
            tries[n] += 1.0
            cooldown[n] = j + (2 * n + 2) * 2.0 ** min(tries[n], 20.0)
            break
        if status != codes.OK:
            break
    out[OB_NSTEPS] = st[S_N]
    if status != codes.OK:
        _failure(out, status, anti_damped(p, lw))
        return
    status = lyapunov(st, p, lw, fa, fb, om, o, acc, ws, vw, T, work, out)
    out[OB_NSTEPS] = st[S_N]
    if status != codes.OK:
        _failure(out, status, anti_damped(p, lw))
        return
    out[OB_T_SETTLE] = jmax * T
    if out[OB_LYAPUNOV] + 3.0 * out[OB_LYAPUNOV_ERROR] < 0.0:
        out[OB_REGIME] = codes.R_UNCONVERGED       # contracting: a period not found
        out[OB_STATUS] = codes.UNCONVERGED
    else:
        out[OB_REGIME] = codes.R_APERIODIC
        out[OB_STATUS] = codes.OK


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
def _least_period(u, n, p, lw, fa, fb, om, o, acc, ws, vw, T, work, tol, mu1, out):
    """The least period m of the fixed point u of P^n (m divides n): the response
    is a fixed point of P^m when P^m(u) returns to u within the accuracy asked.
    Returns ``(m, ok, mu1, status)``, re-solved on P^m where m < n (P^n's
    multipliers are P^m's to the power n/m: a negative multiplier of P makes the
    iterates alternate, and P^2's candidate is found first)."""
    for m in range(1, n):
        if n % m != 0:
            continue
        status = _image(u, m, p, lw, fa, fb, om, o, acc, ws, vw, T, work, runtime(False))
        if status != codes.OK:
            return n, False, mu1, status
        if _dist(work, u, o[O_LX], o[O_LV]) <= max(1e2 * tol, 1e4 * o[O_RTOL]):
            ok, mu, _mu2, _measured, status = newton(u, m, p, lw, fa, fb, om, o, acc, ws,
                                                     vw, T, work, tol, out)
            return m, ok, mu, status
    return n, True, mu1, codes.OK


@kernel
def _answer(u, n, j, mu1, p, lw, fa, fb, om, o, acc, ws, vw, T, work, out, tol,
            measured):
    """The response of the fixed point u of P^n, measured by a run of n periods
    (unless Newton's last run ``measured`` it). Its error estimate, the integration
    error of n periods amplified by 1/(1 - mu1), must be within tol."""
    status, gap = codes.OK, 0.0
    if not measured:
        status, gap = measure(u, n, p, lw, fa, fb, om, o, acc, ws, vw, T, work, out)
    out[OB_NSTEPS] = u[S_N]
    if status != codes.OK:
        _failure(out, status, runtime(False))
        return
    out[OB_MULTIPLICITY] = n
    out[OB_PERIOD] = n * T
    out[OB_FLOQUET] = mu1
    out[OB_T_SETTLE] = j * T
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
    out[OB_STATUS] = codes.OK if amplified <= tol and gap <= max(tol, 1e3 * o[O_RTOL]) \
        else codes.UNRESOLVED
