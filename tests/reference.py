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
