"""Peers and an independent reference, written from the physics (no sweepcore code).

Three solvers of the same hybrid system (Liu's slider, friction law eq. (40), true
sticking), all event-driven exactly as the physics says:

* stick: ``xdot = v``, ``x`` grows with the belt until ``|k x| = r_y`` (closed form);
* slide: eq. (41) with ``sgn(zdot)`` frozen, until ``zdot = 0``;
* at ``zdot = 0``: stick if ``|k x| < r_y``, else slide on in the direction of the net
  spring force (``k x >= r_y`` -> ``zdot < 0``; ``k x <= -r_y`` -> ``zdot > 0``).

``scipy_protocol``  the fixed-horizon protocol: integrate to ``t_end`` = 200 s with
    ``scipy.integrate.solve_ivp`` (terminal event at zdot = 0, restart per phase) and
    measure amplitude/mean from samples on [150, 200] (step 0.01 s). With RK45 at
    rtol = atol = 1e-8 it is the "scipy loop" peer; with DOP853 at 1e-12 it is the
    reference of that protocol.
``scipy_attractor`` the same event-driven solver used as an attractor finder: one
    stick-slip cycle between two slips, or Poincare returns (maxima of x) until they
    agree; amplitude from the exact extrema (events at xdot = 0), mean from the
    quadrature of x carried as a third ODE component. An independent check of
    sweepcore's attractor observables on a handful of points.
``numba_rk4_protocol`` the fastest peer: hand-written numba RK4 at a
    fixed step, zdot = 0 located inside the step by Illinois (bracketed regula falsi)
    on the step's own polynomial, prange over points, same 200 s protocol.

All three assume ``v > 0`` (the benchmark grids).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange
from scipy.integrate import solve_ivp

T_END = 200.0
T_SAMPLE0 = 150.0
DT_SAMPLE = 0.01
N_SAMPLES = 5001           # t = 150 + 0.01 j, j = 0..5000


def sample_times():
    return T_SAMPLE0 + DT_SAMPLE * np.arange(N_SAMPLES)


# ------------------------------------------------------------------ scipy
def _slide_rhs(m, k, r_y, v, a1, a2, s):
    def rhs(_t, y):
        zd = y[1]
        ra = r_y * s - a1 * zd + a2 * zd * zd * zd      # eq. (40), sgn frozen
        return [zd + v, (-k * y[0] - ra) / m, y[0]]     # x', zdot', (int x)'
    return rhs


def _zero_events(m, k, r_y, v, a1, a2, s, armed):
    """Terminal event of a slide with sign s.

    Armed: zdot returning to 0 from its side. Not armed (the slide has just left
    zdot = 0 at a slip or a stop): the first maximum of s*zdot, where it turns back
    towards 0. A departure whose excursion is shorter than a step would otherwise
    be seen as a zero at the start of the step (a zero-length event, repeated
    forever); after the turn the next zero is the true one.
    """
    if armed:
        def ev(_t, y):
            return y[1]
        ev.direction = -s
    else:
        def ev(_t, y):
            zd = y[1]
            return s * (-k * y[0] - (r_y * s - a1 * zd + a2 * zd * zd * zd)) / m
        ev.direction = -1
    ev.terminal = True
    return ev


def _after_zero(x, k, r_y):
    """Mode after zdot reached 0 at position x (v > 0): 0 stick, -1/+1 slide."""
    if k * x >= r_y:
        return -1
    if k * x <= -r_y:
        return 1
    return 0


def _start_mode(x0, xd0, v, k, r_y):
    zd = xd0 - v
    if zd > 0:
        return 1
    if zd < 0:
        return -1
    return _after_zero(x0, k, r_y)


def scipy_protocol(p, method="RK45", rtol=1e-8, atol=1e-8, t_end=T_END, max_step=np.inf):
    """The fixed-horizon protocol for one kernel row p of the paper's law (eq. 40).

    Returns dict(amplitude, mean, events, n_rhs): samples of x on t = 150 + 0.01 j.
    """
    from sweepcore import law
    from sweepcore._kernels import layout
    par = law.from_row(p)              # the row's parameters by name
    m, k, r_y, v, a1, a2 = (par[n] for n in ("m", "k", "r_y", "v", "alpha1", "alpha2"))
    x0, xd0 = float(p[layout.X0]), float(p[layout.XD0])
    assert v > 0.0
    ts = sample_times()
    ts = ts[ts <= t_end]
    xs_out = np.full(ts.shape, np.nan)
    xs = r_y / k
    t, x, zd = 0.0, x0, xd0 - v
    s = _start_mode(x0, xd0, v, k, r_y)
    n_events = 0
    n_rhs = 0
    armed = zd != 0.0
    while t < t_end:
        if s == 0:                                   # stick: closed form
            t_slip = t + (xs - x) / v
            sel = (ts >= t) & (ts <= min(t_slip, t_end))
            xs_out[sel] = x + v * (ts[sel] - t)
            if t_slip >= t_end:
                break
            t, x, zd, s = t_slip, xs, 0.0, -1        # slip at |k x| = r_y, zdot < 0
            armed = False
            n_events += 1
            continue

        ev = _zero_events(m, k, r_y, v, a1, a2, s, armed)
        sel = (ts >= t) & (ts <= t_end)
        sol = solve_ivp(_slide_rhs(m, k, r_y, v, a1, a2, s), (t, t_end), [x, zd, 0.0],
                        method=method, rtol=rtol, atol=atol, events=ev,
                        t_eval=ts[sel] if sel.any() else None, max_step=max_step)
        n_rhs += sol.nfev
        if sol.status < 0:
            raise RuntimeError(f"solve_ivp failed at t={t}: {sol.message}")
        if sel.any():
            ys = np.asarray(sol.y, dtype=float).reshape(3, -1)
            idx = np.flatnonzero(sel)[: ys.shape[1]]
            xs_out[idx] = ys[0]
        if sol.status == 1 and sol.t_events[0].size:
            t = float(sol.t_events[0][0])
            x = float(sol.y_events[0][0][0])
            if not armed:                             # turned back towards zdot = 0
                zd = float(sol.y_events[0][0][1])
                armed = True
                continue
            zd = 0.0
            s = _after_zero(x, k, r_y)
            armed = False
            n_events += 1
        else:
            break
    ok = np.isfinite(xs_out)
    return {"amplitude": 0.5 * (xs_out[ok].max() - xs_out[ok].min()) if ok.any() else np.nan,
            "mean": xs_out[ok].mean() if ok.any() else np.nan,
            "events": n_events, "n_rhs": n_rhs, "complete": bool(ok.all())}


def scipy_attractor(p, rtol=1e-12, atol=1e-13, max_periods=3000.0, conv=1e-10):
    """Attractor observables of one row p by event-driven DOP853 (independent check).

    Stick-slip: the cycle between two slips (every slip starts at (r_y/k, v), so it
    is periodic from the first slip). Otherwise the maxima of x (events xdot = 0) are
    followed until two successive returns agree to ``conv`` times the length scale
    (slip cycle), or until the oscillation about x_eq falls below that (equilibrium).

    Returns dict(amplitude, mean, period, regime) with regime in
    {"stick_slip", "slip_cycle", "equilibrium", "unconverged"}.
    """
    m, k, r_y, v, a1, a2 = map(float, p[:6])     # the paper's law (row layout: common.rows)
    x0, xd0 = float(p[9]), float(p[10])
    assert v > 0.0
    om = math.sqrt(k / m)
    T0 = 2.0 * math.pi / om
    L = r_y / k + v / om
    xs = r_y / k
    x_eq = (r_y - a1 * v + a2 * v ** 3) / k
    t_max = max_periods * T0
    t, x, zd = 0.0, x0, xd0 - v
    s = _start_mode(x0, xd0, v, k, r_y)
    # cycle bookkeeping (from the latest slip or the latest x maximum)
    t_slip = None
    cyc = None            # [t0, int_x, xmax, xmin]
    maxima = []           # (t, x, int_x at that time, xmin since previous max)
    int_x = 0.0
    xmin_run = math.inf
    armed = zd != 0.0

    def cycle_result(t1, ix1, c, regime):
        T = t1 - c[0]
        return {"amplitude": 0.5 * (c[2] - c[3]), "mean": (ix1 - c[1]) / T, "period": T,
                "regime": regime}

    while t < t_max:
        if s == 0:
            t1 = t + (xs - x) / v
            int_x += (t1 - t) * (x + 0.5 * v * (t1 - t))
            xmin_run = min(xmin_run, x)
            if cyc is not None:
                cyc[2] = max(cyc[2], xs)
                cyc[3] = min(cyc[3], x)
            t, x, zd, s = t1, xs, 0.0, -1
            armed = False
            if cyc is not None and t_slip is not None:
                return cycle_result(t, int_x, cyc, "stick_slip")
            t_slip = t
            cyc = [t, int_x, xs, xs]
            maxima.clear()
            continue

        ev_zero = _zero_events(m, k, r_y, v, a1, a2, s, armed)

        def ev_ext(_t, y):
            return y[1] + v                         # xdot = 0: extremum of x
        ev_ext.terminal = False
        ev_ext.direction = 0
        t_seg = min(t + 50.0 * T0, t_max)
        sol = solve_ivp(_slide_rhs(m, k, r_y, v, a1, a2, s), (t, t_seg), [x, zd, int_x],
                        method="DOP853", rtol=rtol, atol=atol, events=[ev_zero, ev_ext],
                        max_step=0.05 * T0)
        if sol.status < 0:
            raise RuntimeError(sol.message)
        # extrema of x inside the segment, in time order
        for te, ye in zip(sol.t_events[1], sol.y_events[1]):
            xe, ixe = ye[0], ye[2]
            if cyc is not None:
                cyc[2] = max(cyc[2], xe)
                cyc[3] = min(cyc[3], xe)
            # a maximum of x: xddot = zdd < 0 there (xdot = 0, zd = -v)
            acc = (-k * xe - (r_y * s + a1 * v - a2 * v ** 3)) / m
            if acc < 0.0:
                maxima.append((te, xe, ixe, xmin_run))
                xmin_run = math.inf
                if len(maxima) >= 3:
                    (ta, xa, ia, _), (tb, xb, ib, _), (tc, xc, ic, mc) = maxima[-3:]
                    d1, d0 = xc - xb, xb - xa
                    rho = abs(d1 / d0) if d0 != 0.0 else 0.0
                    rem = abs(d1) * rho / (1.0 - rho) if rho < 1.0 else math.inf
                    if abs(d1) <= conv * L and rem <= conv * L:
                        if 0.5 * (xc - mc) <= 100.0 * conv * L:
                            return {"amplitude": 0.0, "mean": x_eq, "period": np.nan,
                                    "regime": "equilibrium"}
                        return {"amplitude": 0.5 * (xc - mc), "mean": (ic - ib) / (tc - tb),
                                "period": tc - tb, "regime": "slip_cycle"}
            else:
                xmin_run = min(xmin_run, xe)
        if sol.status == 1 and sol.t_events[0].size:
            t = float(sol.t_events[0][0])
            y = sol.y_events[0][0]
            if not armed:                       # turned back towards zdot = 0
                x, zd, int_x = float(y[0]), float(y[1]), float(y[2])
                armed = True
                continue
            x, zd, int_x = float(y[0]), 0.0, float(y[2])
            armed = False
            if cyc is not None:
                cyc[2] = max(cyc[2], x)
                cyc[3] = min(cyc[3], x)
            s = _after_zero(x, k, r_y)
        else:
            t = float(sol.t[-1])
            x, zd, int_x = (float(c) for c in sol.y[:, -1])
            # a decaying oscillation far below the conv level between maxima
            if abs(x - x_eq) < conv * L and abs(zd + v) < conv * L * om:
                return {"amplitude": 0.0, "mean": x_eq, "period": np.nan,
                        "regime": "equilibrium"}
    return {"amplitude": np.nan, "mean": np.nan, "period": np.nan, "regime": "unconverged"}


# ------------------------------------------------------------ numba RK4 peer
@njit(cache=True, inline="always")
def _acc(x, zd, s, k, m, r_y, a1, a2):
    return (-k * x - (r_y * s - a1 * zd + a2 * zd * zd * zd)) / m


@njit(cache=True)
def _rk4(x, zd, h, s, v, k, m, r_y, a1, a2):
    k1x = zd + v
    k1z = _acc(x, zd, s, k, m, r_y, a1, a2)
    k2x = zd + 0.5 * h * k1z + v
    k2z = _acc(x + 0.5 * h * k1x, zd + 0.5 * h * k1z, s, k, m, r_y, a1, a2)
    k3x = zd + 0.5 * h * k2z + v
    k3z = _acc(x + 0.5 * h * k2x, zd + 0.5 * h * k2z, s, k, m, r_y, a1, a2)
    k4x = zd + h * k3z + v
    k4z = _acc(x + h * k3x, zd + h * k3z, s, k, m, r_y, a1, a2)
    return (x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x),
            zd + h / 6.0 * (k1z + 2.0 * k2z + 2.0 * k3z + k4z))


@njit(cache=True)
def _protocol_point(p, dt, t_end, t_s0, dt_s, n_s, out):
    m, k, r_y, v, a1, a2, x0, xd0 = p[0], p[1], p[2], p[3], p[4], p[5], p[9], p[10]
    xs = r_y / k
    t = 0.0
    x = x0
    zd = xd0 - v
    if zd > 0.0:
        s = 1.0
    elif zd < 0.0:
        s = -1.0
    else:
        s = -1.0 if k * x >= r_y else (1.0 if k * x <= -r_y else 0.0)
    xmax = -np.inf
    xmin = np.inf
    xsum = 0.0
    ns = 0
    j = 0                                  # next sample index
    n_events = 0
    n_steps = 0
    while t < t_end and n_events < 10_000_000:     # guard against chattering
        if s == 0.0:
            t1 = min(t + (xs - x) / v, t_end)
            while j < n_s and t_s0 + j * dt_s <= t1:
                xj = x + v * (t_s0 + j * dt_s - t)
                xmax = max(xmax, xj)
                xmin = min(xmin, xj)
                xsum += xj
                ns += 1
                j += 1
            if t1 >= t_end:
                break
            t = t1
            x = xs
            zd = 0.0
            s = -1.0
            n_events += 1
            continue
        h = min(dt, t_end - t)
        x1, z1 = _rk4(x, zd, h, s, v, k, m, r_y, a1, a2)
        n_steps += 1
        if s * z1 <= 0.0:
            # Illinois on g(th) = s zdot(step(th h)), g(0) > 0 >= g(1)
            lo, hi = 0.0, 1.0
            glo, ghi = s * zd, s * z1
            if glo <= 0.0:
                # the step starts on the switching line (a slip or a stop) and its
                # excursion returns within the step: bracket the second zero from a
                # point inside the excursion, found by halving the step
                th = 0.5
                for _ in range(60):
                    xm, zm = _rk4(x, zd, th * h, s, v, k, m, r_y, a1, a2)
                    n_steps += 1
                    if s * zm > 0.0:
                        lo, glo = th, s * zm
                        break
                    th *= 0.5
            side = 0
            th = 1.0 if glo <= 0.0 else lo
            for _ in range(60):
                if glo <= 0.0:
                    th = 0.0                 # no excursion at all: a zero-length stop
                    break
                th = (lo * ghi - hi * glo) / (ghi - glo)
                xm, zm = _rk4(x, zd, th * h, s, v, k, m, r_y, a1, a2)
                n_steps += 1
                gm = s * zm
                if gm == 0.0 or hi - lo < 1e-15:
                    break
                if gm > 0.0:
                    lo, glo = th, gm
                    if side == 1:
                        ghi *= 0.5
                    side = 1
                else:
                    hi, ghi = th, gm
                    if side == -1:
                        glo *= 0.5
                    side = -1
                if abs(gm) < 1e-15 * (abs(zd) + abs(v)):
                    break
            h = th * h
            x1, z1 = _rk4(x, zd, h, s, v, k, m, r_y, a1, a2)
            n_steps += 1
            z1 = 0.0
            n_events += 1
            s_new = -1.0 if k * x1 >= r_y else (1.0 if k * x1 <= -r_y else 0.0)
        else:
            s_new = s
        # samples inside (t, t + h]: the RK4 step's own polynomial from the step start
        while j < n_s and t_s0 + j * dt_s <= t + h:
            tj = t_s0 + j * dt_s
            if tj >= t + h:
                xj = x1
            else:
                xj, _zj = _rk4(x, zd, tj - t, s, v, k, m, r_y, a1, a2)
            xmax = max(xmax, xj)
            xmin = min(xmin, xj)
            xsum += xj
            ns += 1
            j += 1
        t += h
        x = x1
        zd = z1
        s = s_new
    out[0] = 0.5 * (xmax - xmin)
    out[1] = xsum / ns if ns > 0 else np.nan
    out[2] = n_events
    out[3] = n_steps
    out[4] = ns


@njit(cache=True, parallel=True)
def numba_rk4_protocol(P, dt, out):
    """The numba RK4 peer over the rows of P: out (n, 5) =
    (amplitude, mean, events, rk4 steps, samples)."""
    for i in prange(P.shape[0]):
        _protocol_point(P[i], dt, T_END, T_SAMPLE0, DT_SAMPLE, N_SAMPLES, out[i])
