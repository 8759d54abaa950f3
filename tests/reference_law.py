"""An independent reference for a friction law given as a function of the speed.

The hybrid oscillator of ``reference.py`` (scipy DOP853, exact events, sticks in
closed form; its stick/slide machinery ``_hybrid``, ``_observe``) with F and F' from
any pair of Python functions on each side of zdot = 0, instead of the analytic
family. Shares no code with sweepcore: for a ``TableLaw`` the test hands it the
table's piecewise polynomial evaluated here by numpy (``pp_branch``), for Leine's
law the formula.
"""
import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import reference as R


class LawModel:
    """``reference._Model``'s interface for an odd friction law: ``branch(s, sgn)``
    gives ``(F, F')`` on the side ``sgn`` of zdot = 0, continued past 0; sticking
    holds while ``|k x + c v| <= static``."""

    def __init__(self, m, k, v, c, branch, static):
        self.m, self.k, self.v, self.c = float(m), float(k), float(v), float(c)
        self.branch, self.r_y = branch, float(static)
        self.omega = math.sqrt(self.k / self.m)
        self.x_s = (self.r_y - self.c * self.v) / self.k

    def force(self, s, sgn):
        return self.branch(s, sgn)[0]

    def dforce(self, s, sgn):
        return self.branch(s, sgn)[1]

    def acc(self, x, zd, sgn):
        return (-self.k * x - self.c * (zd + self.v) - self.force(zd, sgn)) / self.m

    def side_after_stop(self, x):
        load = self.k * x + self.c * self.v
        if load >= self.r_y:
            return -1
        if load <= -self.r_y:
            return 1
        return 0


def pp_branch(x, c):
    """``branch(s, sgn)`` of an odd law from the positive side's piecewise polynomial
    (breakpoints x, coefficients c[i, j] of (s - x_i)^j), by numpy; past the ends
    linear with the end's value and slope (the representation's rule)."""
    def side(s):
        i = int(np.clip(np.searchsorted(x, s, side="right") - 1, 0, len(x) - 2))
        if s > x[-1] or s < x[0]:
            end = x[-1] if s > x[-1] else x[0]
            j = len(x) - 2 if s > x[-1] else 0
            t = end - x[j]
            f = np.polynomial.polynomial.polyval(t, c[j])
            d = np.polynomial.polynomial.polyval(t, c[j, 1:] * np.arange(1, c.shape[1]))
            return f + d * (s - end), d
        t = s - x[i]
        return (np.polynomial.polynomial.polyval(t, c[i]),
                np.polynomial.polynomial.polyval(t, c[i, 1:] * np.arange(1, c.shape[1])))

    def branch(s, sgn):
        if sgn > 0:
            return side(s)
        f, d = side(-s)
        return -f, d
    return branch


def stick_slip_cycle(mod, rtol=1e-12, max_periods=20.0):
    """One period from the breakaway point (v > 0): ``dict(amplitude, period,
    x_max, x_min, mean, stick_time)``."""
    graze = 100.0 * rtol * (mod.v + mod.r_y / math.sqrt(mod.k * mod.m))
    horizon = max_periods * 2.0 * math.pi / mod.omega
    segments, events, closed = R._hybrid(mod, 0.0, mod.x_s, 0.0, horizon, rtol, side=-1,
                                         stop_at_breakaway=True, graze_tol=graze)
    if not closed:
        raise ValueError("no stick-slip cycle")
    period = events[-1][0]
    x_max, x_min, _xd_max, _xd_min, q, stick = R._observe(mod, segments)
    return dict(amplitude=0.5 * (x_max - x_min), period=period, x_max=x_max,
                x_min=x_min, mean=q / period, stick_time=stick)


def equilibrium(mod):
    """Steady sliding: x_eq from ``k x + F(-v) = 0`` (Brent on the acceleration) and
    the linearised damping ``c + F'(-v)``."""
    def acc(x):
        return mod.acc(x, -mod.v, -1)
    span = (abs(mod.force(-mod.v, -1)) + mod.r_y) / mod.k + 1.0
    x_eq = brentq(acc, -span, span, xtol=1e-300, rtol=8.9e-16)
    return dict(x_eq=x_eq, damping=mod.c + mod.dforce(-mod.v, -1))


def section_return(mod, a, rtol=1e-13):
    """One return of a stop-free slide from (x = a, x' = 0) to the next maximum of x:
    ``(a1, period, log_floquet, reaches_belt)``."""
    v = mod.v

    def rhs(_t, y):
        return [y[1] + v, mod.acc(y[0], y[1], -1), -(mod.c + mod.dforce(y[1], -1)) / mod.m]

    def belt(_t, y):
        return y[1]
    belt.terminal, belt.direction = True, 1
    y = [float(a), -v, 0.0]
    t_total = 0.0
    for direction in (1, -1):
        def still(_t, yy):
            return yy[1] + v
        still.terminal, still.direction = True, direction
        sol = solve_ivp(rhs, (0.0, 8.0 * math.pi / mod.omega), y, method="DOP853",
                        rtol=rtol, atol=rtol * 1e-3, events=[still, belt])
        t_total += float(sol.t[-1])
        y = list(sol.y[:, -1])
        if sol.t_events[1].size:
            return float(y[0]), t_total, float(y[2]), True
    return float(y[0]), t_total, float(y[2]), False


def slip_cycle(mod, a_guess, rtol=1e-13):
    """The slip cycle through a maximum near ``a_guess``, by the secant method on the
    return map: ``dict(x_max, period, floquet)`` (the Floquet multiplier by a
    central difference of the map)."""
    def g(a):
        a1, _t, _l, belt = section_return(mod, a, rtol)
        if belt:
            raise ValueError("the orbit reaches belt speed")
        return a1 - a
    a0, a1 = float(a_guess), float(a_guess) * (1.0 + 1e-3)
    f0, f1 = g(a0), g(a1)
    for _ in range(60):
        if f1 == f0:
            break
        a0, a1, f0 = a1, a1 - f1 * (a1 - a0) / (f1 - f0), f1
        f1 = g(a1)
        if abs(a1 - a0) <= 1e-15 * abs(a1):
            break
    _a, period, _l, _b = section_return(mod, a1, rtol)
    d = 1e-5 * abs(a1)
    floquet = (g(a1 + d) + d - (g(a1 - d) - d)) / (2.0 * d)
    return dict(x_max=a1, period=period, floquet=floquet)
