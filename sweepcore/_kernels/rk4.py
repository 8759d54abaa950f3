"""Classical fourth-order Runge-Kutta, fixed step (method "rk4")."""
from numba import njit

from .friction import friction, zdd
from .layout import V

ORDER = 4


@njit(cache=True)
def rk4_step(x, zd, h, s, p, want_q):
    """One RK4 step of the sliding field; see ``stepper.py`` for the contract."""
    v = p[V]
    k1x = zd + v
    k1z = zdd(x, zd, s, p)
    x2 = x + 0.5 * h * k1x
    z2 = zd + 0.5 * h * k1z
    k2x = z2 + v
    k2z = zdd(x2, z2, s, p)
    x3 = x + 0.5 * h * k2x
    z3 = zd + 0.5 * h * k2z
    k3x = z3 + v
    k3z = zdd(x3, z3, s, p)
    x4 = x + h * k3x
    z4 = zd + h * k3z
    k4x = z4 + v
    k4z = zdd(x4, z4, s, p)
    x1 = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x)
    zd1 = zd + h / 6.0 * (k1z + 2.0 * k2z + 2.0 * k3z + k4z)
    qx = 0.0
    qv = 0.0
    qw = 0.0
    if want_q:
        # the same weights applied to the quadrature components (I' = g(stage))
        qx = h / 6.0 * (x + 2.0 * x2 + 2.0 * x3 + x4)
        qv = h / 6.0 * (k1x * k1x + 2.0 * k2x * k2x + 2.0 * k3x * k3x + k4x * k4x)
        qw = h / 6.0 * (friction(zd, s, p) * k1x + 2.0 * friction(z2, s, p) * k2x
                        + 2.0 * friction(z3, s, p) * k3x + friction(z4, s, p) * k4x)
    return x1, zd1, qx, qv, qw, 0.0, True
