"""Closed-form sliding arcs of the piecewise-linear laws, method "exact".

Without cubic and Stribeck terms (``law.piecewise_linear``) and with the friction sign
``s`` frozen, the sliding equation is linear:

    m xdd - (alpha1 - c) xd + k x = -r_y s - alpha1 v,

so ``y = x - cen`` with the sliding centre ``cen = (-r_y s - alpha1 v) / k`` obeys
``y'' - 2 sigma y' + omega^2 y = 0``, ``sigma = (alpha1 - c) / (2 m)``
(``law.arc_constants``). With ``beta^2 = omega^2 - sigma^2`` and
``C, S = cos(beta t), sin(beta t)/beta`` (``cosh``/``sinh`` when ``beta^2 < 0``,
``1, t`` when ``beta^2 = 0``):

    y(t)  = e^{sigma t} [ y0 C + (y0' - sigma y0) S ]
    y'(t) = e^{sigma t} [ y0' C + (sigma (y0' - sigma y0) - beta^2 y0) S ]

For ``alpha1 = c = 0`` this is eq. (24) (a circle about ``(r_y/k, 0)`` in the
``(x, xdot/omega)`` plane, eq. (38)). There is no truncation error: a "step" is the
closed form evaluated at ``t + h``. The step proposal ends each step at the next
extremum of ``zdot`` (a zero of ``y''``, also closed form), so ``zdot`` is monotone
inside a step and the driver's sign test brackets every crossing and touch.
Quadratures use 8-point Gauss-Legendre on arcs of at most half an oscillation
(error below 1e-14 relative for sin/cos integrands).
"""
import math

import numpy as np
from .jit import kernel

from .law import arc_constants, friction
from .layout import K, M, V

GL_X, GL_W = np.polynomial.legendre.leggauss(8)
ORDER = 0  # no truncation error

# A zero of y'' closer than this fraction of the half-period to the step start is the
# start itself: steps end on extrema, and a tangential slip leaves the switching line
# with zdd = 0. Near a stable centre (|y| ~ 1e-9 |c|) rounding moves that zero by far
# more than 1e-9 of a half-period, so the margin is 1e-3; an extremum that really
# lies inside a step is still found by the driver's cubic scan.
_SAME_POINT = 1e-3


@kernel(inline="always")
def _cs(b2, t):
    if b2 > 0.0:
        b = math.sqrt(b2)
        return math.cos(b * t), math.sin(b * t) / b
    if b2 < 0.0:
        g = math.sqrt(-b2)
        return math.cosh(g * t), math.sinh(g * t) / g
    return 1.0, t


@kernel(inline="always")
def arc_eval(y0, yd0, sig, b2, t):
    """(y, y') at time t on the arc that starts at (y0, y0')."""
    C, S = _cs(b2, t)
    e = math.exp(sig * t)
    bb = yd0 - sig * y0
    return e * (y0 * C + bb * S), e * (yd0 * C + (sig * bb - b2 * y0) * S)


@kernel
def exact_step(t, x, zd, h, s, p, lw, fx, o, want_q):
    """Closed-form state after h [s]; see ``stepper.py`` for the contract (the
    autonomous field only: a load makes the method not applicable,
    ``attractor.method_status``)."""
    v = p[V]
    cen, sig, b2 = arc_constants(s, p, lw)
    y0 = x - cen
    yd0 = zd + v
    y1, yd1 = arc_eval(y0, yd0, sig, b2, h)
    qx = 0.0
    qv = 0.0
    qw = 0.0
    if want_q:
        half = 0.5 * h
        for i in range(GL_X.shape[0]):
            yi, ydi = arc_eval(y0, yd0, sig, b2, half * (1.0 + GL_X[i]))
            w = half * GL_W[i]
            qx += w * (cen + yi)
            qv += w * ydi * ydi
            qw += w * friction(ydi - v, s, p, lw) * ydi
    return cen + y1, yd1 - v, qx, qv, qw, 0.0, 0.0, True


@kernel
def exact_proposal(x, zd, s, p, lw):
    """Time [s] to the next extremum of zdot on the current arc (capped)."""
    v = p[V]
    cen, sig, b2 = arc_constants(s, p, lw)
    omega2 = p[K] / p[M]
    y0 = x - cen
    yd0 = zd + v
    w0 = 2.0 * sig * yd0 - omega2 * y0        # y''(0)
    w1 = 2.0 * sig * w0 - omega2 * yd0        # y'''(0)
    bb = w1 - sig * w0                        # y'' = e^{sig t}(w0 C + bb S)
    cap = 1.0 / (abs(sig) + math.sqrt(abs(b2)) + 1e-300)
    if b2 > 0.0:
        b = math.sqrt(b2)
        half = math.pi / b
        th0 = math.atan2(bb / b, w0) + 0.5 * math.pi
        n = math.ceil((_SAME_POINT * math.pi - th0) / math.pi)
        t = (th0 + n * math.pi) / b
        return min(t, half)
    if b2 < 0.0:
        g = math.sqrt(-b2)
        if bb != 0.0:
            r = -w0 * g / bb
            if 0.0 < r < 1.0:
                t = math.atanh(r) / g
                if t > _SAME_POINT * cap:
                    return min(t, cap)
        return cap
    if bb != 0.0:
        t = -w0 / bb
        if t > _SAME_POINT * cap:
            return min(t, cap)
    return cap
