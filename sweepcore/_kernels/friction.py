"""The friction law and the smooth sliding field.

Sliding with the friction sign ``s = sgn(zdot)`` frozen, eq. (40)

    r_a = r_y s - alpha1 zdot + alpha2 zdot^3,

and eq. (41), written in the bounded coordinates ``(x, zdot)`` (z = x - v t grows
without bound, x does not):

    xdot    = zdot + v
    zdotdot = (-k x - r_a) / m .
"""
from .jit import kernel

from .layout import A1, A2, K, M, RY, V


@kernel(inline="always")
def friction(zd, s, p):
    """Friction force r_a on the slider while sliding [kN], eq. (40)."""
    return p[RY] * s - p[A1] * zd + p[A2] * zd * zd * zd


@kernel(inline="always")
def zdd(x, zd, s, p):
    """Relative (= absolute) acceleration while sliding [cm/s^2], eq. (41)."""
    return (-p[K] * x - friction(zd, s, p)) / p[M]


@kernel(inline="always")
def zdd_im(x, zd, s, p, im):
    """``zdd`` with ``im = 1/m`` given: steppers take the reciprocal once per step, so
    no division sits on the chain of dependent stages."""
    return (-p[K] * x - friction(zd, s, p)) * im


@kernel(inline="always")
def zddd(x, zd, s, p, v):
    """Time derivative of zdd along the sliding flow [cm/s^3]."""
    a = zdd(x, zd, s, p)
    return (-p[K] * (zd + v) + (p[A1] - 3.0 * p[A2] * zd * zd) * a) / p[M]


@kernel
def x_equilibrium(p):
    """Steady-sliding position (eq. 43, mirrored for v < 0; 0 for v = 0) [cm]."""
    v = p[V]
    if v == 0.0:
        return 0.0
    va = abs(v)
    sg = 1.0 if v > 0.0 else -1.0
    return sg * (p[RY] - p[A1] * va + p[A2] * va ** 3) / p[K]
