"""Classical fourth-order Runge-Kutta, fixed step (method "rk4")."""
from .jit import kernel

from .law import coefficients, friction_of, law_integrand, zdd_of
from .layout import M, RK, RY, V

ORDER = 4


@kernel(inline="always")
def rk4_step(x, zd, h, s, p, o, want_q):
    """One RK4 step of the sliding field; see ``stepper.py`` for the contract."""
    if p[RY] == p[RK]:          # the polynomial law: no Stribeck branch
        return _rk4_step(x, zd, h, s, p, o, want_q, None)
    return _rk4_step(x, zd, h, s, p, o, want_q, p[RY] - p[RK])


@kernel
def _rk4_step(x, zd, h, s, p, o, want_q, d):
    """``rk4_step`` for the Stribeck drop ``d = r_y - r_k`` (None: none; see
    ``law.stribeck_drop``)."""
    v = p[V]
    im = 1.0 / p[M]
    cf = coefficients(s, p)
    k1x = zd + v
    k1z = zdd_of(x, zd, s, cf, d, im)
    x2 = x + 0.5 * h * k1x
    z2 = zd + 0.5 * h * k1z
    k2x = z2 + v
    k2z = zdd_of(x2, z2, s, cf, d, im)
    x3 = x + 0.5 * h * k2x
    z3 = zd + 0.5 * h * k2z
    k3x = z3 + v
    k3z = zdd_of(x3, z3, s, cf, d, im)
    x4 = x + h * k3x
    z4 = zd + h * k3z
    k4x = z4 + v
    k4z = zdd_of(x4, z4, s, cf, d, im)
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
        qw = h / 6.0 * (friction_of(zd, s, cf, d) * k1x + 2.0 * friction_of(z2, s, cf, d) * k2x
                        + 2.0 * friction_of(z3, s, cf, d) * k3x + friction_of(z4, s, cf, d) * k4x)
        if d is not None:
            ql = h / 6.0 * (law_integrand(zd, p) + 2.0 * law_integrand(z2, p)
                            + 2.0 * law_integrand(z3, p) + law_integrand(z4, p))
    return x1, zd1, qx, qv, qw, ql, 0.0, True
