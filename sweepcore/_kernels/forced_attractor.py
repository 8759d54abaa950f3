"""The steady response of a forced slider: a fixed point of the stroboscopic map.

P maps the state (x, zdot, phase mode) at a time t = j T, T = 2 pi / Omega the
forcing period (``excitations/``), to the state one period later. From the given
start the search iterates P (the motion a long simulation would follow) and after
each period looks for the smallest n <= ``NMAX`` (the option ``periods``) for which
the last states nearly repeat after n periods. Such a candidate is solved as a fixed
point of P^n by Newton's method, with P^n's Jacobian by central differences of
re-runs at a tighter tolerance (the re-runs pass every switch as the motion does, so
the saltation at each switch is in the difference). The fixed point is accepted as
the response the start reaches when it is stable (every multiplier inside the unit
circle) and within the distance the iterates' contraction predicts; then one run of
n periods from it measures the observables on line. A state that starts P^n stuck
is one number (x: the stick forgets the velocity), so its Newton is one-dimensional
and its second multiplier is 0.

No period up to NMAX within the budget: the response is aperiodic; its largest
Lyapunov exponent is measured with a shadow run renormalised every period
(Benettin's method; its switches are the shadow's own), over blocks whose spread is
its error estimate. A negative exponent beyond three errors is a periodic response
not yet found (status unconverged), never a made-up cycle.
"""
import math

import numpy as np

from . import codes
from .excitation import coefficients, forcing_period
from .forced_driver import advance_forced, initial_forced
from .jit import kernel
from .law import anti_damped, length_scale
from .layout import (A_DT, A_IX, A_NSTICK, A_NSTOP, A_TSTICK, A_XDMAX, A_XDMIN, A_XMAX,
                     A_XMIN, K, M, NA, NFOB, NO, NP, NS, O_LV, O_LX, O_MAX_STEPS,
                     O_MAX_TIME, O_PERIODS, O_RTOL, OB_AMPLITUDE, OB_CYCLE_SIZE, OB_FLOQUET,
                     OB_LYAPUNOV, OB_LYAPUNOV_ERROR, OB_MEAN, OB_MULTIPLICITY, OB_NSTEPS,
                     OB_PERIOD, OB_REGIME, OB_STATUS, OB_STICK_FRACTION,
                     OB_STICKS_PER_PERIOD, OB_STOPS_PER_PERIOD, OB_T_SETTLE,
                     OB_VAMPLITUDE, OB_X_MAX, OB_X_MIN, OB_XDOT_MAX, S_ARMED, S_MODE, S_N, S_T,
                     S_X, S_ZD, V, X0, XD0)

NMAX_DEFAULT = 16
TRY = 1e-2            # states within this (in L) after n periods: try Newton on P^n
RTOL_FLOOR = 1e-13    # the tightest integration tolerance used
FD_DELTA = 1e-4       # central-difference step of the Jacobian [L]
LYAP_PERIODS = 256    # periods of the Lyapunov estimate
LYAP_BLOCKS = 8
NH = 40               # stroboscopic states kept (at least 2 NMAX + 2 used)


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
def run_periods(st, p, lw, fa, fb, om, o, acc, ws, T, n, measure):
    """Advance st by n forcing periods (its clock restarts at 0 each period: the load
    has period T); returns the status."""
    for _ in range(n):
        while st[S_T] < T:
            _ev, status = advance_forced(st, p, lw, fa, fb, om, o, acc, ws, T, measure)
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
def _image(u, n, p, lw, fa, fb, om, o, acc, ws, T, work, dx, dz):
    """P^n of the state u moved by (dx, dz): ``(x, zd, mode, status)``."""
    work[:] = u
    work[S_X] += dx
    if dz != 0.0:
        work[S_ZD] += dz
        work[S_MODE] = codes.SLIDE_POS if work[S_ZD] > 0.0 else codes.SLIDE_NEG
        work[S_ARMED] = 1.0
    status = run_periods(work, p, lw, fa, fb, om, o, acc, ws, T, n, False)
    u[S_N] += work[S_N] - u[S_N]
    return work[S_X], work[S_ZD], work[S_MODE], status



@kernel
def newton(u, n, p, lw, fa, fb, om, o, acc, ws, T, work, oft, tol):
    """Fixed point of P^n near u (modified in place): ``(ok, mu1, mu2 (|mu1| >=
    |mu2|, moduli), residual [L], status)``. ``oft``: the option row of the Jacobian's
    re-runs (tighter tolerance)."""
    lx = o[O_LX]
    lv = o[O_LV]
    stuck = u[S_MODE] == codes.STICK
    mu1 = np.nan
    mu2 = np.nan
    res = np.inf
    for _it in range(12):
        x1, z1, m1, status = _image(u, n, p, lw, fa, fb, om, o, acc, ws, T, work, 0.0, 0.0)
        if status != codes.OK:
            return False, mu1, mu2, res, status
        if m1 != u[S_MODE] and not (not stuck and m1 != codes.STICK):
            return False, mu1, mu2, res, codes.OK
        rx = x1 - u[S_X]
        rz = 0.0 if stuck else z1 - u[S_ZD]
        # the Jacobian (central differences at the tighter tolerance)
        d = FD_DELTA * lx
        xp, zp, _m, s1 = _image(u, n, p, lw, fa, fb, om, oft, acc, ws, T, work, d, 0.0)
        xm, zm, _m, s2 = _image(u, n, p, lw, fa, fb, om, oft, acc, ws, T, work, -d, 0.0)
        if s1 != codes.OK or s2 != codes.OK:
            return False, mu1, mu2, res, codes.OK
        jxx = (xp - xm) / (2.0 * d)
        if stuck:
            mu1 = abs(jxx)
            mu2 = 0.0
            dxn = -rx / (jxx - 1.0) if jxx != 1.0 else 0.0
            dzn = 0.0
        else:
            jzx = (zp - zm) / (2.0 * d)
            dv = FD_DELTA * lv
            if abs(u[S_ZD]) > 2.0 * dv:
                xp, zp, _m, s1 = _image(u, n, p, lw, fa, fb, om, oft, acc, ws, T, work,
                                        0.0, dv)
                xm, zm, _m, s2 = _image(u, n, p, lw, fa, fb, om, oft, acc, ws, T, work,
                                        0.0, -dv)
                den = 2.0 * dv
            else:                       # one-sided, away from the switching line
                sg = 1.0 if u[S_ZD] > 0.0 else -1.0
                xp, zp, _m, s1 = _image(u, n, p, lw, fa, fb, om, oft, acc, ws, T, work,
                                        0.0, sg * 2.0 * dv)
                xm, zm, _m, s2 = _image(u, n, p, lw, fa, fb, om, oft, acc, ws, T, work,
                                        0.0, sg * dv)
                den = sg * dv
            if s1 != codes.OK or s2 != codes.OK:
                return False, mu1, mu2, res, codes.OK
            jxz = (xp - xm) / den
            jzz = (zp - zm) / den
            tr = jxx + jzz
            det = jxx * jzz - jxz * jzx
            disc = tr * tr - 4.0 * det
            if disc >= 0.0:
                sq = math.sqrt(disc)
                l1 = abs(0.5 * (tr + sq))
                l2 = abs(0.5 * (tr - sq))
                mu1 = max(l1, l2)
                mu2 = min(l1, l2)
            else:
                mu1 = math.sqrt(max(det, 0.0))
                mu2 = mu1
            # solve (J - I) d = -r
            a11 = jxx - 1.0
            a22 = jzz - 1.0
            dd = a11 * a22 - jxz * jzx
            dxn = (-rx * a22 + rz * jxz) / dd if dd != 0.0 else 0.0
            dzn = (-rz * a11 + rx * jzx) / dd if dd != 0.0 else 0.0
        res = max(abs(rx) / lx, abs(rz) / lv)
        if res <= 1e-2 * tol:           # a fixed point already (a neutral one too)
            return True, mu1, mu2, res, codes.OK
        step = max(abs(dxn) / lx, abs(dzn) / lv)
        u[S_X] += dxn
        if not stuck:
            u[S_ZD] += dzn
            if u[S_ZD] == 0.0 or (u[S_ZD] > 0.0) != (u[S_MODE] > 0.0):
                return False, mu1, mu2, res, codes.OK
        if step <= 1e-2 * tol:
            return True, mu1, mu2, res, codes.OK
        if not step > 0.0:              # singular: no step to take
            return False, mu1, mu2, res, codes.OK
        if step > 10.0 * TRY:
            return False, mu1, mu2, res, codes.OK
    return False, mu1, mu2, res, codes.OK


@kernel
def measure(u, n, p, lw, fa, fb, om, o, acc, ws, T, work, out):
    """Run n periods from u with the observables on; write them into out. Returns
    the status and the distance [L] of the end from u."""
    work[:] = u
    fresh(acc)
    status = run_periods(work, p, lw, fa, fb, om, o, acc, ws, T, n, True)
    u[S_N] = work[S_N]
    if status != codes.OK:
        return status, np.inf
    dur = n * T
    out[OB_AMPLITUDE] = 0.5 * (acc[A_XMAX] - acc[A_XMIN])
    out[OB_MEAN] = acc[A_IX] / dur
    out[OB_VAMPLITUDE] = 0.5 * (acc[A_XDMAX] - acc[A_XDMIN])
    out[OB_X_MAX] = acc[A_XMAX]
    out[OB_X_MIN] = acc[A_XMIN]
    out[OB_XDOT_MAX] = acc[A_XDMAX]
    out[OB_STICK_FRACTION] = min(acc[A_TSTICK] / dur, 1.0)
    out[OB_STICKS_PER_PERIOD] = acc[A_NSTICK]
    out[OB_STOPS_PER_PERIOD] = acc[A_NSTOP]
    return codes.OK, _dist(work, u, o[O_LX], o[O_LV])


@kernel
def lyapunov(u, p, lw, fa, fb, om, o, acc, ws, T, work, shadow, out):
    """Largest Lyapunov exponent [1/s] and its error from LYAP_PERIODS periods from
    u (Benettin: a shadow at 1e-7 L renormalised every period); the observables of
    those periods into out. Returns the status."""
    lx = o[O_LX]
    lv = o[O_LV]
    d0 = 1e-7
    work[:] = u
    fresh(acc)
    per = LYAP_PERIODS // LYAP_BLOCKS
    sums = np.zeros(LYAP_BLOCKS)
    shadow[:] = work
    shadow[S_X] += d0 * lx
    for b in range(LYAP_BLOCKS):
        for _j in range(per):
            status = run_periods(work, p, lw, fa, fb, om, o, acc, ws, T, 1, True)
            if status != codes.OK:
                return status
            shadow[S_N] = 0.0
            status = run_periods(shadow, p, lw, fa, fb, om, o, acc, ws, T, 1, False)
            if status != codes.OK:
                return status
            ex = (shadow[S_X] - work[S_X]) / lx
            ez = (shadow[S_ZD] - work[S_ZD]) / lv
            d = math.hypot(ex, ez)
            if not d > 0.0:
                d = 1e-300
            sums[b] += math.log(d / d0)
            shadow[:] = work
            shadow[S_X] += d0 * lx * ex / d
            if shadow[S_MODE] != codes.STICK:
                shadow[S_ZD] += d0 * lv * ez / d
                if shadow[S_ZD] != 0.0:
                    shadow[S_MODE] = codes.SLIDE_POS if shadow[S_ZD] > 0.0 else codes.SLIDE_NEG
                    shadow[S_ARMED] = 1.0
    rates = sums / (per * T)
    lam = rates.mean()
    err = rates.std() / math.sqrt(LYAP_BLOCKS - 1.0)
    dur = LYAP_PERIODS * T
    out[OB_AMPLITUDE] = 0.5 * (acc[A_XMAX] - acc[A_XMIN])
    out[OB_MEAN] = acc[A_IX] / dur
    out[OB_VAMPLITUDE] = 0.5 * (acc[A_XDMAX] - acc[A_XDMIN])
    out[OB_X_MAX] = acc[A_XMAX]
    out[OB_X_MIN] = acc[A_XMIN]
    out[OB_XDOT_MAX] = acc[A_XDMAX]
    out[OB_STICK_FRACTION] = min(acc[A_TSTICK] / dur, 1.0)
    out[OB_STICKS_PER_PERIOD] = np.nan
    out[OB_STOPS_PER_PERIOD] = np.nan
    out[OB_LYAPUNOV] = lam
    out[OB_LYAPUNOV_ERROR] = err
    u[S_N] = work[S_N]
    return codes.OK


@kernel
def forced_point(meth, p, lw, ex, o_in, out):
    """Fill ``out`` (layout OB_*, length NFOB) with the steady response of one forced
    point reached from (p[X0], p[XD0]) at t = 0 (module docstring); the option
    ``O_PERIODS``: the largest multiplicity sought."""
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
    nmax = int(o_in[O_PERIODS])
    tol = o_in[O_RTOL]
    oft = o.copy()
    oft[O_RTOL] = RTOL_FLOOR
    lx = o[O_LX]
    lv = o[O_LV]
    omega = math.sqrt(p[K] / p[M])
    ws = np.empty((4, 12))
    acc = np.empty(NA)
    fresh(acc)
    st = np.zeros(NS)
    work = np.zeros(NS)
    shadow = np.zeros(NS)
    hist = np.zeros((NH, NS))
    initial_forced(st, p[X0], p[XD0], p, lw, fa, fb, om, o)
    nmax = min(nmax, (NH - 2) // 2)
    # the budget: max_periods natural periods, at least 4 nmax forcing periods
    jmax = max(int(o[O_MAX_TIME] * 2.0 * math.pi / omega / T), 4 * nmax + 8)
    hist[0] = st
    status = codes.OK
    cooldown = np.zeros(nmax + 1)
    tries = np.zeros(nmax + 1)
    for j in range(1, jmax + 1):
        status = run_periods(st, p, lw, fa, fb, om, o, acc, ws, T, 1, False)
        if status != codes.OK:
            break
        if st[S_N] >= o[O_MAX_STEPS]:
            status = codes.STEP_BUDGET
            break
        hist[j % NH] = st
        for n in range(1, min(nmax, j) + 1):
            d = _dist(st, hist[(j - n) % NH], lx, lv)
            if not d <= TRY or cooldown[n] > j:
                continue
            work[:] = st
            u = st.copy()
            ok, mu1, mu2, res, status = newton(u, n, p, lw, fa, fb, om, o, acc, ws, T,
                                               work, oft, tol)
            st[S_N] = u[S_N]
            if status != codes.OK:
                break
            if ok:
                n, ok, mu1, status = _least_period(u, n, p, lw, fa, fb, om, o, acc, ws, T,
                                                   work, oft, tol, mu1)
                st[S_N] = u[S_N]
                if status != codes.OK:
                    break
            # the start reaches it: stable, and as near as the contraction predicts
            near = _dist(u, st, lx, lv) <= max(2.0 * d / max(1.0 - mu1, 1e-3), 10.0 * tol)
            if ok and mu1 < 1.0 - 1e-9 and near:
                return _answer(u, n, j, mu1, p, lw, fa, fb, om, o, acc, ws, T, work, out,
                               tol, oft)
            if ok and near and abs(mu1 - 1.0) <= 1e-6:
                _answer(u, n, j, mu1, p, lw, fa, fb, om, o, acc, ws, T, work, out, tol,
                        oft)
                if out[OB_REGIME] != codes.R_STUCK:    # stuck throughout: exact
                    out[OB_REGIME] = codes.R_NEUTRAL   # a neutral family: the start
                    out[OB_STATUS] = codes.UNRESOLVED  # picks the member
                return
            if not ok and abs(mu1 - 1.0) <= 1e-3 and mu2 < 1.0:
                # no isolated fixed point next to a multiplier 1: a neutral family
                # (at Omega/omega = 1/(2 n), c = 0), whose member the start picks
                _answer(st.copy(), n, j, mu1, p, lw, fa, fb, om, o, acc, ws, T, work,
                        out, tol, oft)
                if out[OB_REGIME] != codes.R_STUCK:
                    out[OB_REGIME] = codes.R_NEUTRAL
                    out[OB_STATUS] = codes.UNRESOLVED
                return
            tries[n] += 1.0
            cooldown[n] = j + (2 * n + 2) * 2.0 ** min(tries[n], 20.0)
            break
        if status != codes.OK:
            break
    out[OB_NSTEPS] = st[S_N]
    if status == codes.DIVERGED:
        out[OB_REGIME] = codes.R_UNBOUNDED if anti_damped(p, lw) else codes.R_FAILED
        out[OB_STATUS] = codes.DIVERGED
        return
    if status != codes.OK:
        out[OB_REGIME] = codes.R_FAILED
        out[OB_STATUS] = status
        return
    status = lyapunov(st, p, lw, fa, fb, om, o, acc, ws, T, work, shadow, out)
    out[OB_NSTEPS] = st[S_N]
    if status != codes.OK:
        for i in range(NFOB):
            out[i] = np.nan
        out[OB_NSTEPS] = st[S_N]
        out[OB_REGIME] = codes.R_FAILED
        out[OB_STATUS] = status
        return
    out[OB_T_SETTLE] = jmax * T
    lam = out[OB_LYAPUNOV]
    if lam + 3.0 * out[OB_LYAPUNOV_ERROR] < 0.0:
        out[OB_REGIME] = codes.R_UNCONVERGED       # contracting: a period not found
        out[OB_STATUS] = codes.UNCONVERGED
    else:
        out[OB_REGIME] = codes.R_APERIODIC
        out[OB_STATUS] = codes.OK


@kernel
def _least_period(u, n, p, lw, fa, fb, om, o, acc, ws, T, work, oft, tol, mu1):
    """The least period m of the fixed point u of P^n (m divides n): the response
    is a fixed point of P^m when P^m(u) returns to u within the accuracy asked.
    Returns ``(m, ok, mu1, status)``, re-solved on P^m where m < n (P^n's
    multipliers are P^m's to the power n/m: a negative multiplier of P makes the
    iterates alternate, and P^2's candidate is found first)."""
    for m in range(1, n):
        if n % m != 0:
            continue
        x1, z1, m1, status = _image(u, m, p, lw, fa, fb, om, o, acc, ws, T, work, 0.0, 0.0)
        if status != codes.OK:
            return n, False, mu1, status
        work[S_X] = x1
        work[S_ZD] = z1
        work[S_MODE] = m1
        if _dist(work, u, o[O_LX], o[O_LV]) <= max(1e2 * tol, 1e4 * o[O_RTOL]):
            ok, mu, _mu2, _res, status = newton(u, m, p, lw, fa, fb, om, o, acc, ws, T,
                                                work, oft, tol)
            return m, ok, mu, status
    return n, True, mu1, codes.OK


@kernel
def _answer(u, n, j, mu1, p, lw, fa, fb, om, o, acc, ws, T, work, out, tol, oft):
    """Measure the response of the fixed point u of P^n; its error estimate: the
    integration error of n periods amplified by 1/(1 - mu1), against tol."""
    status, gap = measure(u, n, p, lw, fa, fb, om, o, acc, ws, T, work, out)
    out[OB_NSTEPS] = u[S_N]
    if status != codes.OK:
        out[OB_REGIME] = codes.R_FAILED
        out[OB_STATUS] = status
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
    amplified = 10.0 * n * o[O_RTOL] / max(1.0 - mu1, 1e-300)
    out[OB_STATUS] = codes.OK if amplified <= tol and gap <= max(tol, 1e3 * o[O_RTOL]) \
        else codes.UNRESOLVED
