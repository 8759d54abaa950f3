"""Derivative of the Poincare return map of a slip motion (its Floquet multiplier).

The section is the line ``xdot = 0`` at the maxima of ``x``; a return maps the
section value ``a`` to ``P(a)``. For a planar flow the Jacobian determinant of the
flow over the return is ``J = exp(int div f dt)`` (Liouville), and the flux of the
flow through the section is conserved, so

    P'(a) = J * zdd(a) / zdd(P(a)),        zdd at xdot = 0, i.e. zdot = -v,

which at a fixed point (a cycle) is its nontrivial Floquet multiplier. In the
coordinates ``(x, zdot)``, ``div f = d zdd / d zdot = -(c + F'(zdot))/m``; its time
integral is the law's (``law.log_jacobian``, from the driver's quadratures). A
slide-slide reversal (normal stop, eq. 30) crosses the discontinuity of the friction
law transversally and multiplies ``J`` by its saltation factor ``zdd+ / zdd-``
(``law.log_saltation``: the ratio of the normal components of the field after and
before the crossing).
"""
import math

from .jit import kernel

from . import codes
from .law import log_jacobian, zdd
from .layout import A_DT, A_ILAW, A_IXD2, V


@kernel
def return_slope(p, lw, a0, a1, acc, log_salt):
    """P'(a0) for the return a0 -> a1 whose quadratures are in ``acc`` [1]."""
    v = p[V]
    T = acc[A_DT]
    # int zdot^2 dt = int xdot^2 dt - 2 v (x(T) - x(0)) + v^2 T
    izd2 = acc[A_IXD2] - 2.0 * v * (a1 - a0) + v * v * T
    log_j = log_jacobian(p, lw, T, izd2, acc[A_ILAW]) + log_salt
    s = float(codes.SLIDE_NEG if v > 0.0 else codes.SLIDE_POS)   # a side is a float
    f0 = zdd(a0, -v, s, p, lw)
    f1 = zdd(a1, -v, s, p, lw)
    if f1 == 0.0:
        return math.nan
    return math.exp(log_j) * f0 / f1
