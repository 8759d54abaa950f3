"""Liu's group-preserving scheme (GPS), eqs. (49)-(50), fixed step (method "gps").

The paper applies the Cayley-form GPS of Liu (2001) to ``u = (z + a, zdot)``. Here
``u = (x + a, zdot)``: the same scheme on the autonomous form of the same equation.
``z = x - v t`` grows without bound over a long run, so ``||u||`` would grow and the
scheme would drift towards forward Euler with a time-dependent effective step; ``x``
stays bounded, so ``||u||`` does too. ``a`` (cm) keeps ``||u||`` away from zero; by
default it is the length scale ``r_y/k + |v|/omega``.

The update ``u1 = u0 + eta f`` with

    eta = (2 tau ||u||^2 + 2 tau^2 f.u) / (||u||^2 - tau^2 ||f||^2),  tau = h/2,

is first-order accurate: for ``tau ||f|| << ||u||``, ``eta -> h`` and the step is
forward Euler, which pumps energy into an oscillator (growth ~ omega^2 h / 2 per unit
time). When the denominator is not safely positive (``<= ||u||^2 / 2``) the step is
refused (``ok = False``) and the driver halves it.
"""
from .jit import kernel

import numpy as np

from .excitation import step_load, with_stage
from .law import constants, friction, integrand, zdd
from .layout import M, O_GPS_A, V

ORDER = 1
STAGE_C = np.array([0.0])     # the field is taken at the step's start


@kernel
def gps_step(t, x, zd, h, s, p, lw, fx, o, want_q):
    """One GPS step of the sliding field from time t [s] (the field taken at the
    step's start, as the scheme takes it); see ``stepper.py`` for the contract."""
    v = p[V]
    a = o[O_GPS_A]
    u1 = x + a
    u2 = zd
    f1 = zd + v
    step_load(fx, t, h, STAGE_C)
    f2 = with_stage(fx, 0, zdd(x, zd, s, p, lw), 1.0 / p[M])
    tau = 0.5 * h
    uu = u1 * u1 + u2 * u2
    ff = f1 * f1 + f2 * f2
    fu = f1 * u1 + f2 * u2
    den = uu - tau * tau * ff
    if not (den > 0.5 * uu):
        return x, zd, 0.0, 0.0, 0.0, 0.0, 0.0, False
    eta = (2.0 * tau * uu + 2.0 * tau * tau * fu) / den
    x1 = x + eta * f1
    zd1 = zd + eta * f2
    qx = 0.0
    qv = 0.0
    qw = 0.0
    ql = 0.0
    if want_q:  # trapezoid rule: second order, above the scheme's own order
        xd0 = f1
        xd1 = zd1 + v
        qx = 0.5 * h * (x + x1)
        qv = 0.5 * h * (xd0 * xd0 + xd1 * xd1)
        qw = 0.5 * h * (friction(zd, s, p, lw) * xd0 + friction(zd1, s, p, lw) * xd1)
        cf = constants(p, lw, s)
        ql = 0.5 * h * (integrand(lw, cf, zd) + integrand(lw, cf, zd1))
    return x1, zd1, qx, qv, qw, ql, 0.0, True
