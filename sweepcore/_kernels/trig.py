"""Trigonometric polynomials of time: the load of a periodic excitation.

Every periodic excitation reaches the kernels as the force on the slider

    e(t) = sum_{n=1}^{N} alpha_n cos(n Omega t) + beta_n sin(n Omega t)    [kN]

(a load F0 p(Omega t + phi) with the harmonics of its shape p, and the anchor's
motion, which enters as ``k y + c y'`` at n = 1: ``excitations/periodic.py``). Its
coefficients for one point live in the excitation's work array ``xc`` (layout
below), written once per point by the kind's ``coefficients``; this module
evaluates e and its time derivatives from them. Within a step the load at
``t + tau`` is ``sum_n E_n cos(n Omega tau) + F_n sin(n Omega tau)`` with
``E_n, F_n`` the harmonics rotated to the step's start (``step_start``), so a
stage costs no library call (``stage``).
"""
import math

from .jit import kernel

# the work array xc of a periodic excitation
XC_OMEGA = 0     # Omega [rad/s]
XC_PERIOD = 1    # T = 2 pi / Omega [s]
XC_N = 2         # N, the number of harmonics held
XC_NCRIT = 3     # number of critical phases (roots of h' over a period, holding.py)
XC_FTOL = 4      # force tolerance of the stop rules [kN] (rounding of the forces)
XC_TOP = 5       # the highest harmonic with a nonzero coefficient
XC_HEAD = 8      # then alpha_n, beta_n, E_n, F_n (N each), the critical phases


@kernel(inline="always")
def work_size(n):
    """Floats of the work array of a load with n harmonics."""
    return XC_HEAD + 8 * n + 8


@kernel(inline="always")
def alpha_at(xc):
    """Offset of alpha_1 in xc (alpha_n at + n - 1, beta_n at + N + n - 1)."""
    return XC_HEAD


@kernel(inline="always")
def crit_at(xc):
    """Offset of the critical phases in xc."""
    return XC_HEAD + 4 * int(xc[XC_N])


@kernel
def derivative(xc, t, d):
    """The d-th time derivative of e at t (d = 0, 1, 2, 3) [kN / s^d]: the harmonics
    by the rotation (cos, sin)(n u) from (cos, sin)(u), u = Omega t."""
    om = xc[XC_OMEGA]
    n_h = int(xc[XC_N])
    u = om * t
    c1 = math.cos(u)
    s1 = math.sin(u)
    cn = c1
    sn = s1
    total = 0.0
    for i in range(n_h):
        a = xc[XC_HEAD + i]
        b = xc[XC_HEAD + n_h + i]
        w = (i + 1) * om
        if d == 0:
            total += a * cn + b * sn
        elif d == 1:
            total += w * (b * cn - a * sn)
        elif d == 2:
            total -= w * w * (a * cn + b * sn)
        else:
            total -= w * w * w * (b * cn - a * sn)
        cn, sn = cn * c1 - sn * s1, sn * c1 + cn * s1
    return total


@kernel
def bound(xc, d):
    """A bound of |e^(d)| over all t: ``sum_n (n Omega)^d |(alpha_n, beta_n)|``."""
    om = xc[XC_OMEGA]
    n_h = int(xc[XC_N])
    total = 0.0
    for i in range(n_h):
        total += ((i + 1) * om) ** d * math.hypot(xc[XC_HEAD + i], xc[XC_HEAD + n_h + i])
    return total


@kernel
def step_start(xc, t):
    """The harmonics rotated to a step that starts at t: ``E_n = alpha_n cos(n Omega
    t) + beta_n sin(n Omega t)``, ``F_n = beta_n cos(n Omega t) - alpha_n sin(n Omega
    t)`` into xc, so that e(t + tau) = sum_n E_n cos(n Omega tau) + F_n sin(n Omega
    tau)."""
    n_h = int(xc[XC_N])
    u = xc[XC_OMEGA] * t
    c1 = math.cos(u)
    s1 = math.sin(u)
    cn = c1
    sn = s1
    e0 = XC_HEAD + 2 * n_h
    for i in range(n_h):
        a = xc[XC_HEAD + i]
        b = xc[XC_HEAD + n_h + i]
        xc[e0 + i] = a * cn + b * sn
        xc[e0 + n_h + i] = b * cn - a * sn
        cn, sn = cn * c1 - sn * s1, sn * c1 + cn * s1


@kernel(inline="always")
def cos_sin(th):
    """cos and sin of th, by their Taylor polynomials to degree 16 and 17 where
    |th| <= 0.6 (the next terms are below 3e-20: as exact as the library's, and
    without its calls on every stage), else the library's."""
    if abs(th) > 0.6:
        return math.cos(th), math.sin(th)
    t2 = th * th
    c = 1.0 - t2 / 2.0 * (1.0 - t2 / 12.0 * (1.0 - t2 / 30.0 * (1.0 - t2 / 56.0 * (
        1.0 - t2 / 90.0 * (1.0 - t2 / 132.0 * (1.0 - t2 / 182.0 * (1.0 - t2 / 240.0)))))))
    sn = th * (1.0 - t2 / 6.0 * (1.0 - t2 / 20.0 * (1.0 - t2 / 42.0 * (1.0 - t2 / 72.0 * (
        1.0 - t2 / 110.0 * (1.0 - t2 / 156.0 * (1.0 - t2 / 210.0 * (1.0 - t2 / 272.0))))))))
    return c, sn


@kernel
def stage(xc, th):
    """e at ``tau = th / Omega`` into the step of the last ``step_start`` [kN]."""
    n_h = int(xc[XC_N])
    e0 = XC_HEAD + 2 * n_h
    c1, s1 = cos_sin(th)
    total = xc[e0] * c1 + xc[e0 + n_h] * s1
    cn = c1
    sn = s1
    for i in range(1, n_h):
        cn, sn = cn * c1 - sn * s1, sn * c1 + cn * s1
        total += xc[e0 + i] * cn + xc[e0 + n_h + i] * sn
    return total
