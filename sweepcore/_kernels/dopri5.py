"""Dormand-Prince 5(4) with local extrapolation and error control (method "dopri5").

Tableau from Dormand & Prince (1980), as in Hairer, Norsett & Wanner, Solving ODEs I,
table II.5.2. The error is measured per component against
``rtol * (L + |y|)`` with the point's own scales ``L`` (length ``r_y/k + |v|/omega``
and the velocity of the motion, see ``scales``), so the tolerance is relative and the
units cancel.
"""
import numpy as np
from .jit import kernel

from .excitation import step_load, with_stage
from .law import constants, friction_force, integrand, length_scale, zdd_of
from .layout import K, M, O_LV, O_LX, O_RTOL, V

ORDER = 5
EPS = np.finfo(np.float64).eps
ERROR_ORDER = 4

C2, C3, C4, C5 = 1 / 5, 3 / 10, 4 / 5, 8 / 9
A21 = 1 / 5
A31, A32 = 3 / 40, 9 / 40
A41, A42, A43 = 44 / 45, -56 / 15, 32 / 9
A51, A52, A53, A54 = 19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729
A61, A62, A63, A64, A65 = 9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656
B1, B3, B4, B5, B6 = 35 / 384, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84
# E = b - b_hat (b_hat: the embedded fourth-order weights; stage 7 = FSAL stage)
E1, E3, E4, E5, E6, E7 = (71 / 57600, -71 / 16695, 71 / 1920, -17253 / 339200,
                          22 / 525, -1 / 40)

TABLEAU_A = np.array([
    [0, 0, 0, 0, 0, 0],
    [A21, 0, 0, 0, 0, 0],
    [A31, A32, 0, 0, 0, 0],
    [A41, A42, A43, 0, 0, 0],
    [A51, A52, A53, A54, 0, 0],
    [A61, A62, A63, A64, A65, 0],
    [B1, 0, B3, B4, B5, B6],
])
TABLEAU_C = np.array([0, C2, C3, C4, C5, 1.0, 1.0])
TABLEAU_B = np.array([B1, 0, B3, B4, B5, B6, 0])
TABLEAU_E = np.array([E1, 0, E3, E4, E5, E6, E7])


@kernel(inline="always")
def scales(p, lw):
    """Length scale [cm] and velocity scale [cm/s] of a point's attractor.

    Length ``r/k + |v|/omega`` (``law.length_scale``): the size of the breakaway
    offset plus the constant-friction cycle. Velocity: that of the motion relative
    to the belt, ``|v|`` (a stick-slip cycle spans zdot in [-2|v|, 0]; a slip cycle
    has |zdot| ~ |v|), and ``omega r/k`` for a still belt. It is not ``omega`` times
    the length: the offset ``r/k`` is a position, not a motion, and with
    ``omega r/k >> |v|`` it would let the zdot error outgrow the whole cycle
    (tiny v, soft springs). The start does not enter: a far start is covered by the
    relative part of the error weights, and must not loosen the tolerance of the
    attractor.
    """
    omega = np.sqrt(p[K] / p[M])
    lx = length_scale(p, lw)
    if not lx > 0.0:
        lx = 1.0
    lv = abs(p[V]) if p[V] != 0.0 else omega * lx
    return lx, lv


@kernel
def dopri5_step(t, x, zd, h, s, p, lw, fx, o, want_q):
    """One Dormand-Prince step of the sliding field from time t [s]; see
    ``stepper.py``."""
    k = p[K]
    im = 1.0 / p[M]
    cf = constants(p, lw, s)
    # zdot's weight has a floor at the rounding of the spring force k x, which the
    # estimate carries as noise ~ 0.15 h eps k |x| / m: a tolerance below the
    # resolution of x (tiny v far from x = 0) would otherwise shrink the steps for
    # ever. (From the step's start: off the chain of dependent stages.)
    floor_z = EPS * h * k * im * abs(x)
    step_load(fx, t, h, TABLEAU_C)
    k1x, k2x, k3x, k4x, k5x, k6x, k7x, k1z, k3z, k4z, k5z, k6z, k7z, x1, zd1, X, Z = \
        _stages(x, zd, h, s, p, lw, cf, fx)
    x3, x4, x5, x6 = X
    z3, z4, z5, z6 = Z
    ex = h * (E1 * k1x + E3 * k3x + E4 * k4x + E5 * k5x + E6 * k6x + E7 * k7x)
    ez = h * (E1 * k1z + E3 * k3z + E4 * k4z + E5 * k5z + E6 * k6z + E7 * k7z)
    lx = o[O_LX]
    lv = o[O_LV]
    rtol = o[O_RTOL]
    err = max(abs(ex) / (rtol * (lx + max(abs(x), abs(x1)))),
              abs(ez) / (rtol * (lv + max(abs(zd), abs(zd1))) + floor_z))
    qx = 0.0
    qv = 0.0
    qw = 0.0
    ql = 0.0
    if want_q:
        qx = h * (B1 * x + B3 * x3 + B4 * x4 + B5 * x5 + B6 * x6)
        qv = h * (B1 * k1x * k1x + B3 * k3x * k3x + B4 * k4x * k4x
                  + B5 * k5x * k5x + B6 * k6x * k6x)
        qw = h * (B1 * friction_force(lw, cf, zd, s) * k1x
                  + B3 * friction_force(lw, cf, z3, s) * k3x
                  + B4 * friction_force(lw, cf, z4, s) * k4x
                  + B5 * friction_force(lw, cf, z5, s) * k5x
                  + B6 * friction_force(lw, cf, z6, s) * k6x)
        ql = h * (B1 * integrand(lw, cf, zd) + B3 * integrand(lw, cf, z3)
                  + B4 * integrand(lw, cf, z4) + B5 * integrand(lw, cf, z5)
                  + B6 * integrand(lw, cf, z6))
    # the slopes the continuous extension needs (``dopri5_extend``) and, with k2x,
    # every stage's zdot (the tangent, ``variational.py``)
    ks = (k1x, k3x, k4x, k5x, k6x, k7x, k1z, k3z, k4z, k5z, k6z, k7z, k2x)
    return x1, zd1, qx, qv, qw, ql, err, True, ks


@kernel(inline="always")
def _stages(x, zd, h, s, p, lw, cf, fx):
    """The seven stages of a step (the seventh at its end): the slopes of x and zdot
    that the weights use, the step's end, and the states of stages 3-6."""
    v = p[V]
    k = p[K]
    im = 1.0 / p[M]
    # the newest slope of each stage enters last, by h A precomputed: the
    # chain from one stage to the next is then one product and one sum
    hA32 = h * A32
    hA43 = h * A43
    hA54 = h * A54
    hA65 = h * A65
    k1x = zd + v
    k1z = with_stage(fx, 0, zdd_of(x, zd, s, cf, lw, k, im), im)
    x2 = x + h * A21 * k1x
    z2 = zd + h * A21 * k1z
    k2x = z2 + v
    k2z = with_stage(fx, 1, zdd_of(x2, z2, s, cf, lw, k, im), im)
    x3 = x + h * (A31 * k1x) + hA32 * k2x
    z3 = zd + h * (A31 * k1z) + hA32 * k2z
    k3x = z3 + v
    k3z = with_stage(fx, 2, zdd_of(x3, z3, s, cf, lw, k, im), im)
    x4 = x + h * (A41 * k1x + A42 * k2x) + hA43 * k3x
    z4 = zd + h * (A41 * k1z + A42 * k2z) + hA43 * k3z
    k4x = z4 + v
    k4z = with_stage(fx, 3, zdd_of(x4, z4, s, cf, lw, k, im), im)
    x5 = x + h * (A51 * k1x + A52 * k2x + A53 * k3x) + hA54 * k4x
    z5 = zd + h * (A51 * k1z + A52 * k2z + A53 * k3z) + hA54 * k4z
    k5x = z5 + v
    k5z = with_stage(fx, 4, zdd_of(x5, z5, s, cf, lw, k, im), im)
    x6 = x + h * (A61 * k1x + A62 * k2x + A63 * k3x + A64 * k4x) + hA65 * k5x
    z6 = zd + h * (A61 * k1z + A62 * k2z + A63 * k3z + A64 * k4z) + hA65 * k5z
    k6x = z6 + v
    k6z = with_stage(fx, 5, zdd_of(x6, z6, s, cf, lw, k, im), im)
    x1 = x + h * (B1 * k1x + B3 * k3x + B4 * k4x + B5 * k5x + B6 * k6x)
    zd1 = zd + h * (B1 * k1z + B3 * k3z + B4 * k4z + B5 * k5z + B6 * k6z)
    k7x = zd1 + v
    k7z = with_stage(fx, 6, zdd_of(x1, zd1, s, cf, lw, k, im), im)
    return (k1x, k2x, k3x, k4x, k5x, k6x, k7x, k1z, k3z, k4z, k5z, k6z, k7z, x1, zd1,
            (x3, x4, x5, x6), (z3, z4, z5, z6))


# the continuous extension (dense output) of order 4: the weights of its highest
# term (Hairer, Norsett & Wanner, section II.6, and their code DOPRI5's contd5)
D1, D3, D4, D5, D6, D7 = (-12715105075 / 11282082432, 87487479700 / 32700410799,
                          -10690763975 / 1880347072, 701980252875 / 199316789632,
                          -1453857185 / 822651844, 69997945 / 29380423)


@kernel
def dopri5_extend(t, x, zd, h, s, p, lw, fx, x1, zd1, ks):
    """The continuous extension of the step ``h`` from ``(x, zd)`` to ``(x1, zd1)``
    from its slopes ``ks`` (as ``dopri5_step`` returns them; the seventh is the
    slope at the step's end): no stage beyond the step's."""
    k1x, k3x, k4x, k5x, k6x, k7x, k1z, k3z, k4z, k5z, k6z, k7z, _k2x = ks
    dx = x1 - x
    dz = zd1 - zd
    f3x = h * (D1 * k1x + D3 * k3x + D4 * k4x + D5 * k5x + D6 * k6x + D7 * k7x)
    f3z = h * (D1 * k1z + D3 * k3z + D4 * k4z + D5 * k5z + D6 * k6z + D7 * k7z)
    return (dx, h * k1x - dx, 2.0 * dx - h * (k7x + k1x), f3x, 0.0, 0.0, 0.0,
            dz, h * k1z - dz, 2.0 * dz - h * (k7z + k1z), f3z, 0.0, 0.0, 0.0)
