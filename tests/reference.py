"""An independent reference: the hybrid system integrated with scipy, from the physics.

Shares no code with sweepcore's kernels. Sliding arcs use DOP853 with a terminal event
at zdot = 0 (direction: zdot returning from its side), sticking is closed form
(x moves with the belt until |k x| = r_y). Only for transversal events: grazing
touches are exactly what sign-change event detection cannot see (see peers.md).
"""
import numpy as np
from scipy.integrate import solve_ivp


def reference_run(m, k, r_y, v, alpha1, alpha2, x0, xd0, t_eval, rtol=1e-12):
    """Return (x(t_eval), xdot(t_eval), events[(t, kind, x)]) for v > 0."""
    assert v > 0
    xs = r_y / k
    t_eval = np.asarray(t_eval, float)
    t_end = t_eval[-1]
    xo = np.full(t_eval.shape, np.nan)
    xdo = np.full(t_eval.shape, np.nan)
    events = []
    t, x, zd = 0.0, float(x0), float(xd0) - v
    if zd > 0:
        s = 1
    elif zd < 0:
        s = -1
    else:
        s = -1 if x >= xs else (1 if x < -xs else 0)
    while t < t_end:
        if s == 0:
            t_slip = t + (xs - x) / v
            sel = (t_eval >= t) & (t_eval <= min(t_slip, t_end))
            xo[sel] = x + v * (t_eval[sel] - t)
            xdo[sel] = v
            if t_slip >= t_end:
                break
            t, x, zd, s = t_slip, xs, 0.0, -1
            events.append((t, "slip", x))
            continue
        sgn = s

        def rhs(_t, y):
            return [y[1] + v, (-k * y[0] - (r_y * sgn - alpha1 * y[1] + alpha2 * y[1] ** 3)) / m]

        def ev(_t, y):
            return y[1]
        ev.terminal = True
        ev.direction = -s
        sel = (t_eval >= t) & (t_eval <= t_end)
        sol = solve_ivp(rhs, (t, t_end), [x, zd], method="DOP853", rtol=rtol,
                        atol=rtol * 1e-2, events=ev, dense_output=True)
        t1 = sol.t[-1]
        inside = sel & (t_eval <= t1)
        y = sol.sol(t_eval[inside])
        xo[inside] = y[0]
        xdo[inside] = y[1] + v
        if sol.status != 1:
            break
        t, x, zd = t1, sol.y_events[0][0][0], 0.0
        if x >= xs:
            s, kind = -1, ("abnormal_stop" if s == -1 else "normal_stop")
        elif x < -xs:
            s, kind = 1, ("abnormal_stop" if s == 1 else "normal_stop")
        else:
            s, kind = 0, "stick"
        events.append((t, kind, x))
    return xo, xdo, events


def reference_slip_cycle(m, k, r_y, v, alpha1, alpha2, a_guess, rtol=1e-13):
    """A slip cycle without stops (v > 0) by shooting, with scipy only.

    The return map of the x maxima, ``a -> P(a)`` (start at x = a, xdot = 0, slide
    with zdot < 0 until the next maximum of x), is solved by the secant method;
    its slope at the fixed point (the Floquet multiplier) by a central difference.
    Returns dict(amplitude, x_max, x_min, period, floquet, xdot_max); raises if the
    orbit reaches belt speed (the cycle would stop: not a slip cycle).
    """
    assert v > 0

    def ret(a, full=False):
        r = reference_return(m, k, r_y, v, alpha1, alpha2, a, rtol)
        return r if full else r["a1"]

    # the first return settles direction; then secant on F(a) = P(a) - a
    a0 = float(a_guess)
    a1 = ret(a0)
    f0 = a1 - a0
    for _ in range(60):
        f1 = ret(a1) - a1
        if f1 == f0:
            break
        a2 = a1 - f1 * (a1 - a0) / (f1 - f0)
        a0, f0, a1 = a1, f1, a2
        if abs(a1 - a0) <= 1e-15 * abs(a1) + 1e-300:
            break
    out = ret(a1, full=True)
    d = 1e-5 * abs(out["x_max"] - out["x_min"])
    out["floquet"] = (ret(a1 + d) - ret(a1 - d)) / (2.0 * d)
    out["amplitude"] = 0.5 * (out["x_max"] - out["x_min"])
    if not out["xdot_max"] < v:
        raise ValueError("the orbit reaches belt speed: not a slip cycle")
    return out


def reference_return(m, k, r_y, v, alpha1, alpha2, a, rtol=1e-13):
    """One return of a stop-free slide (v > 0) from x = a, xdot = 0 to the next
    maximum of x, with scipy only: dict(a1 = the next maximum, x_max = a, x_min,
    period, xdot_max, xdot_min, cycle_size = sqrt(int xdot^2 dt / (pi omega)))."""
    assert v > 0
    w = np.sqrt(k / m)

    def rhs(_t, y):
        zd = y[1]
        return [zd + v, (-k * y[0] - (-r_y - alpha1 * zd + alpha2 * zd ** 3)) / m,
                (zd + v) ** 2]

    def x_max(_t, y):            # xdot = 0, falling: a maximum of x
        return y[1] + v
    x_max.direction = -1

    def x_min(_t, y):
        return y[1] + v
    x_min.direction = 1

    def vel(_t, y):              # xdot extremum: zdd = 0
        return rhs(_t, y)[1]

    horizon = 4.0 * np.pi / w
    sol = solve_ivp(rhs, (0.0, horizon), [a, -v, 0.0], method="DOP853", rtol=rtol,
                    atol=rtol * 1e-3, events=[x_max, x_min, vel], dense_output=True)
    # the start itself may register as a root of x_max: skip it
    ts = sol.t_events[0]
    i = np.nonzero(ts > 0.25 * horizon / 2.0)[0][0]
    T = float(ts[i])
    xd = [float(y[1] + v) for t, y in zip(sol.t_events[2], sol.y_events[2]) if t < T]
    return dict(a1=float(sol.y_events[0][i][0]), x_max=a,
                x_min=float(sol.y_events[1][0][0]), period=T,
                xdot_max=max(xd), xdot_min=min(xd),
                cycle_size=float(np.sqrt(sol.y_events[0][i][2] / (np.pi * w))))
