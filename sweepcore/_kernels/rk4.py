"""Classical fourth-order Runge-Kutta, fixed step (method "rk4")."""
import numpy as np

from .jit import kernel

from .excitation import step_load, with_stage
from .law import constants, friction_force, integrand, zdd_of
from .layout import K, M, V

ORDER = 4
STAGE_C = np.array([0.0, 0.5, 0.5, 1.0])   # the fractions of the step of its stages


@kernel
def rk4_step(t, x, zd, h, s, p, lw, fx, o, want_q):
    """One RK4 step of the sliding field from time t [s]; see ``stepper.py``."""
    v = p[V]
    k = p[K]
    im = 1.0 / p[M]
    cf = constants(p, lw, s)
    step_load(fx, t, h, STAGE_C)
    k1x = zd + v
    k1z = with_stage(fx, 0, zdd_of(x, zd, s, cf, lw, k, im), im)
    x2 = x + 0.5 * h * k1x
    z2 = zd + 0.5 * h * k1z
    k2x = z2 + v
    k2z = with_stage(fx, 1, zdd_of(x2, z2, s, cf, lw, k, im), im)
    x3 = x + 0.5 * h * k2x
    z3 = zd + 0.5 * h * k2z
    k3x = z3 + v
    k3z = with_stage(fx, 2, zdd_of(x3, z3, s, cf, lw, k, im), im)
    x4 = x + h * k3x
    z4 = zd + h * k3z
    k4x = z4 + v
    k4z = with_stage(fx, 3, zdd_of(x4, z4, s, cf, lw, k, im), im)
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
        qw = h / 6.0 * (friction_force(lw, cf, zd, s) * k1x
                        + 2.0 * friction_force(lw, cf, z2, s) * k2x
                        + 2.0 * friction_force(lw, cf, z3, s) * k3x
                        + friction_force(lw, cf, z4, s) * k4x)
        ql = h / 6.0 * (integrand(lw, cf, zd) + 2.0 * integrand(lw, cf, z2)
                        + 2.0 * integrand(lw, cf, z3) + integrand(lw, cf, z4))
    return x1, zd1, qx, qv, qw, ql, 0.0, True
