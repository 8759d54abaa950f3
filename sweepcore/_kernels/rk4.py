"""Classical fourth-order Runge-Kutta, fixed step (method "rk4")."""
from .jit import kernel

from .law import friction, law_integrand, zdd_im
from .layout import M, RK, RY, V

ORDER = 4


@kernel
def rk4_step(x, zd, h, s, p, o, want_q):
    """One RK4 step of the sliding field; see ``stepper.py`` for the contract."""
    v = p[V]
    im = 1.0 / p[M]
    k1x = zd + v
    k1z = zdd_im(x, zd, s, p, im)
    x2 = x + 0.5 * h * k1x
    z2 = zd + 0.5 * h * k1z
    k2x = z2 + v
    k2z = zdd_im(x2, z2, s, p, im)
    x3 = x + 0.5 * h * k2x
    z3 = zd + 0.5 * h * k2z
    k3x = z3 + v
    k3z = zdd_im(x3, z3, s, p, im)
    x4 = x + h * k3x
    z4 = zd + h * k3z
    k4x = z4 + v
    k4z = zdd_im(x4, z4, s, p, im)
    x1 = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x)
    zd1 = zd + h / 6.0 * (k1z + 2.0 * k2z + 2.0 * k3z + k4z)
    qx = 0.0
    qv = 0.0
    qw = 0.0
    ql = 0.0
    if want_q:
        # the same weights applied to the quadrature components (I' = g(stage))
        qx = h / 6.0 * (x + 2.0 * x2 + 2.0 * x3 + x4)
        qv = h / 6.0 * (k1x * k1x + 2.0 * k2x * k2x + 2.0 * k3x * k3x + k4x * k4x)
        qw = h / 6.0 * (friction(zd, s, p) * k1x + 2.0 * friction(z2, s, p) * k2x
                        + 2.0 * friction(z3, s, p) * k3x + friction(z4, s, p) * k4x)
        if p[RY] != p[RK]:
            ql = h / 6.0 * (law_integrand(zd, p) + 2.0 * law_integrand(z2, p)
                            + 2.0 * law_integrand(z3, p) + law_integrand(z4, p))
    return x1, zd1, qx, qv, qw, ql, 0.0, True
