"""Trigonometric polynomials of time: the load of a periodic excitation.

Every periodic excitation reaches the kernels as the force on the slider

    e(t) = sum_{n=1}^{N} alpha_n cos(n Omega t) + beta_n sin(n Omega t)    [kN]

(a load F0 p(Omega t + phi) with the harmonics of its shape p, and the anchor's
motion, which enters as ``k y + c y'`` at n = 1: ``excitations/periodic.py``). Its
coefficients for one point live in the excitation's work array ``xc`` (layout
below), written once per point by the kind's ``coefficients``; this module
evaluates e and its time derivatives from them. Within a step the load at
``t + tau`` is ``sum_n E_n cos(n Omega tau) + F_n sin(n Omega tau)`` with
``E_n, F_n`` the harmonics rotated to the step's start, so the loads at a step's
stages cost one library call (``stage_loads``, once per step; a stage reads its
own from xc).
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
XC_STAGE = 8     # the load at the stages of the last step (``stage_loads``), 20 slots:
XC_START = 26    # ... its last two: the load at the step's start
XC_END = 27      # ... and at its end
XC_PHASE = 28    # the last phase u = Omega t asked for, and its cos and sin (``phase``)
XC_STEP = 31     # the start t and length h [s] of the last step (E_n, F_n rotated to t)
XC_HEAD = 33     # then alpha_n, beta_n, E_n, F_n (N each), the critical phases


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
    by the rotation (cos, sin)(n u) from (cos, sin)(u). Inside the last step
    (t0 <= t <= t0 + h, where events are located) from its harmonics E_n, F_n
    rotated to t0, u = Omega (t - t0) and ``cos_sin`` (the step turns no harmonic's
    phase by more than 0.5: no library call); elsewhere from alpha_n, beta_n and u =
    Omega t."""
    om = xc[XC_OMEGA]
    n_h = int(xc[XC_N])
    tau = t - xc[XC_STEP]
    if 0.0 <= tau <= xc[XC_STEP + 1]:
        c1, s1 = cos_sin(om * tau)
        a0 = XC_HEAD + 2 * n_h
    else:
        c1, s1 = phase(xc, om * t)
        a0 = XC_HEAD
    cn = c1
    sn = s1
    total = 0.0
    for i in range(n_h):
        a = xc[a0 + i]
        b = xc[a0 + n_h + i]
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


@kernel(inline="always")
def phase(xc, u):
    """cos and sin of the phase u [rad], kept in xc for the next call at the same
    phase (an event asks for the load and its rates at one time)."""
    if u != xc[XC_PHASE]:
        xc[XC_PHASE] = u
        xc[XC_PHASE + 1] = math.cos(u)
        xc[XC_PHASE + 2] = math.sin(u)
    return xc[XC_PHASE + 1], xc[XC_PHASE + 2]


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
def stage_loads(xc, t, h, cs):
    """The load e(t + c h) [kN] at every fraction c of ``cs`` (a step's stages) into
    ``xc[XC_STAGE + i]``, and at the step's start and end (XC_START, XC_END): the
    harmonics rotated to the step's start, ``E_n = alpha_n
    cos(n Omega t) + beta_n sin(n Omega t)``, ``F_n = beta_n cos(n Omega t) - alpha_n
    sin(n Omega t)``, then ``e(t + tau) = sum_n E_n cos(n Omega tau) + F_n sin(n
    Omega tau)`` with cos and sin of ``Omega tau`` from ``cos_sin`` and of its
    multiples by rotation."""
    n_h = int(xc[XC_N])
    om = xc[XC_OMEGA]
    c1, s1 = phase(xc, om * t)
    cn = c1
    sn = s1
    e0 = XC_HEAD + 2 * n_h
    for i in range(n_h):
        a = xc[XC_HEAD + i]
        b = xc[XC_HEAD + n_h + i]
        xc[e0 + i] = a * cn + b * sn
        xc[e0 + n_h + i] = b * cn - a * sn
        cn, sn = cn * c1 - sn * s1, sn * c1 + cn * s1
    e_start = 0.0
    for i in range(n_h):
        e_start += xc[e0 + i]
    xc[XC_START] = e_start
    xc[XC_STEP] = t
    xc[XC_STEP + 1] = h
    th = om * h
    if n_h == 1:                # one harmonic: scalars only
        e1 = xc[e0]
        f1 = xc[e0 + 1]
        for j in range(cs.shape[0]):
            ct, st = cos_sin(th * cs[j])
            xc[XC_STAGE + j] = e1 * ct + f1 * st
        ct, st = cos_sin(th)
        xc[XC_END] = e1 * ct + f1 * st
        return
    for j in range(cs.shape[0]):
        xc[XC_STAGE + j] = _rotated(xc, e0, n_h, th * cs[j])
    xc[XC_END] = _rotated(xc, e0, n_h, th)


@kernel(inline="always")
def _rotated(xc, e0, n_h, th):
    """``sum_n E_n cos(n th) + F_n sin(n th)`` (E_n, F_n at ``e0`` in xc)."""
    ct, st = cos_sin(th)
    ck = ct
    sk = st
    total = 0.0
    for i in range(n_h):
        total += xc[e0 + i] * ck + xc[e0 + n_h + i] * sk
        ck, sk = ck * ct - sk * st, sk * ct + ck * st
    return total


TWO_PI = 2.0 * math.pi
# Taylor coefficients of cos and sin, (-1)^k/(2k)! and (-1)^k/(2k+1)!: products, not
# divisions (a division by a constant stays one without fastmath: ~16 of them a
# stage was most of a forced step's time)
K2, K4, K6, K8 = -1.0 / 2.0, 1.0 / 24.0, -1.0 / 720.0, 1.0 / 40320.0
K10, K12, K14, K16 = (-1.0 / 3628800.0, 1.0 / 479001600.0, -1.0 / 87178291200.0,
                      1.0 / 20922789888000.0)
K3, K5, K7, K9 = -1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0, 1.0 / 362880.0
K11, K13, K15, K17 = (-1.0 / 39916800.0, 1.0 / 6227020800.0, -1.0 / 1307674368000.0,
                      1.0 / 355687428096000.0)


@kernel(inline="always")
def cos_sin(th):
    """cos and sin of th, by their Taylor polynomials to degree 16 and 17 where
    |th| <= 0.6 (the next terms are below 3e-20: as exact as the library's, without
    its call on every stage; a step turns the load's phase by at most 0.5,
    ``excitation.capped``); a larger th is reduced to [-pi, pi], halved three times
    and doubled back (``_doubled``: within 2e-15 for |th| <= 2 pi, beyond that the
    rounding of th's reduction, ~|th| 1e-16)."""
    if abs(th) > 0.6:
        return _doubled(th)
    return _taylor(th)


@kernel(inline="always")
def _taylor(th):
    t2 = th * th
    c = 1.0 + t2 * (K2 + t2 * (K4 + t2 * (K6 + t2 * (K8 + t2 * (K10 + t2 * (
        K12 + t2 * (K14 + t2 * K16)))))))
    sn = th * (1.0 + t2 * (K3 + t2 * (K5 + t2 * (K7 + t2 * (K9 + t2 * (K11 + t2 * (
        K13 + t2 * (K15 + t2 * K17))))))))
    return c, sn


@kernel
def _doubled(th):
    """cos and sin of th from those of (th mod 2 pi)/8 by three doublings. Not the
    library's: numba's cos and sin are intrinsics the compiler evaluates ahead of
    the branch that needs them, so in ``cos_sin`` they ran on every call (8 sincos
    a forced step: the forced map on fixed ground took 97 us a point, 84 without)."""
    r = th - TWO_PI * math.floor(th / TWO_PI + 0.5)
    c, sn = _taylor(0.125 * r)
    for _ in range(3):
        c, sn = 1.0 - 2.0 * sn * sn, 2.0 * sn * c
    return c, sn
