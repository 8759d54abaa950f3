"""Dormand-Prince 8(5,3) with error control (method "dop853").

The 12-stage eighth-order pair of Prince & Dormand (J. Comp. Appl. Math. 7 (1981)
67-75) with the error estimator of Hairer, Norsett & Wanner, Solving Ordinary
Differential Equations I (2nd ed., 1993), section II.10, and their code DOP853: a
fifth-order estimate corrected by a third-order one, ``err = E5^2 / sqrt(E5^2 + 0.01
E3^2)``, which behaves as an order-8 estimate. The coefficients are the published ones
(tests/test_convergence.py checks the weights' order conditions and the measured
order). Errors are measured per component against ``rtol * (L + |y|)`` as in
``dopri5.py``; the stepper contract is ``stepper.py``'s. Fewer right-hand sides than
dopri5 at equal error on the map's slip cycles: ``python benchmarks/pair_choice.py``.
"""
import math

import numpy as np

from .jit import kernel

from .dopri5 import EPS, TABLEAU_E
from .excitation import step_load, with_stage
from .law import constants, friction_force, integrand, zdd_of
from .layout import K, M, O_LV, O_LX, O_RTOL, V

ORDER = 8

C2 = 0.05260015195876773
C3 = 0.0789002279381516
C4 = 0.1183503419072274
C5 = 0.2816496580927726
C6 = 0.3333333333333333
C7 = 0.25
C8 = 0.3076923076923077
C9 = 0.6512820512820513
C10 = 0.6
C11 = 0.8571428571428571
C12 = 1.0
# the times of the continuous extension's three stages (DOP853's contd8)
C14 = 0.1
C15 = 0.2
C16 = 7.0 / 9.0
# the fractions of the step at which the stages take the field (the load's times):
# those of the step, and of the extension (its slope at the end, stages 14-16)
STAGE_C = np.array([0.0, C2, C3, C4, C5, C6, C7, C8, C9, C10, C11, C12])
EXTENSION_C = np.array([1.0, C14, C15, C16])
A2_1 = 0.05260015195876773
A3_1 = 0.0197250569845379
A3_2 = 0.0591751709536137
A4_1 = 0.02958758547680685
A4_3 = 0.08876275643042054
A5_1 = 0.2413651341592667
A5_3 = -0.8845494793282861
A5_4 = 0.924834003261792
A6_1 = 0.037037037037037035
A6_4 = 0.17082860872947386
A6_5 = 0.12546768756682242
A7_1 = 0.037109375
A7_4 = 0.17025221101954405
A7_5 = 0.06021653898045596
A7_6 = -0.017578125
A8_1 = 0.03709200011850479
A8_4 = 0.17038392571223998
A8_5 = 0.10726203044637328
A8_6 = -0.015319437748624402
A8_7 = 0.008273789163814023
A9_1 = 0.6241109587160757
A9_4 = -3.3608926294469414
A9_5 = -0.868219346841726
A9_6 = 27.59209969944671
A9_7 = 20.154067550477894
A9_8 = -43.48988418106996
A10_1 = 0.47766253643826434
A10_4 = -2.4881146199716677
A10_5 = -0.590290826836843
A10_6 = 21.230051448181193
A10_7 = 15.279233632882423
A10_8 = -33.28821096898486
A10_9 = -0.020331201708508627
A11_1 = -0.9371424300859873
A11_4 = 5.186372428844064
A11_5 = 1.0914373489967295
A11_6 = -8.149787010746927
A11_7 = -18.52006565999696
A11_8 = 22.739487099350505
A11_9 = 2.4936055526796523
A11_10 = -3.0467644718982196
A12_1 = 2.273310147516538
A12_4 = -10.53449546673725
A12_5 = -2.0008720582248625
A12_6 = -17.9589318631188
A12_7 = 27.94888452941996
A12_8 = -2.8589982771350235
A12_9 = -8.87285693353063
A12_10 = 12.360567175794303
A12_11 = 0.6433927460157636
# weights of the solution (b) and of the two error estimates, on stages 1, 6, 7, 8, 9, 10, 11, 12
B1 = 0.054293734116568765
B6 = 4.450312892752409
B7 = 1.8915178993145003
B8 = -5.801203960010585
B9 = 0.3111643669578199
B10 = -0.1521609496625161
B11 = 0.20136540080403034
B12 = 0.04471061572777259
E5_1 = 0.01312004499419488
E5_6 = -1.2251564463762044
E5_7 = -0.4957589496572502
E5_8 = 1.6643771824549864
E5_9 = -0.35032884874997366
E5_10 = 0.3341791187130175
E5_11 = 0.08192320648511571
E5_12 = -0.022355307863886294
E3_1 = -0.18980075407240762
E3_6 = 4.450312892752409
E3_7 = 1.8915178993145003
E3_8 = -5.801203960010585
E3_9 = -0.4226823213237919
E3_10 = -0.1521609496625161
E3_11 = 0.20136540080403034
E3_12 = 0.02265179219836082

# the continuous extension (dense output): three more stages (14-16, from stage 1-13,
# 13 being the slope at the step's end) and the weights D of its four highest terms
# (Hairer, Norsett & Wanner, section II.6, and their code DOP853's contd8)
A14_1 = 0.056167502283047954
A14_7 = 0.25350021021662483
A14_8 = -0.2462390374708025
A14_9 = -0.12419142326381637
A14_10 = 0.15329179827876568
A14_11 = 0.00820105229563469
A14_12 = 0.007567897660545699
A14_13 = -0.008298
A15_1 = 0.03183464816350214
A15_6 = 0.028300909672366776
A15_7 = 0.053541988307438566
A15_8 = -0.05492374857139099
A15_11 = -0.00010834732869724932
A15_12 = 0.0003825710908356584
A15_13 = -0.00034046500868740456
A15_14 = 0.1413124436746325
A16_1 = -0.42889630158379194
A16_6 = -4.697621415361164
A16_7 = 7.683421196062599
A16_8 = 4.06898981839711
A16_9 = 0.3567271874552811
A16_13 = -0.0013990241651590145
A16_14 = 2.9475147891527724
A16_15 = -9.15095847217987
D4_1 = -8.428938276109013
D4_6 = 0.5667149535193777
D4_7 = -3.0689499459498917
D4_8 = 2.38466765651207
D4_9 = 2.117034582445028
D4_10 = -0.871391583777973
D4_11 = 2.2404374302607883
D4_12 = 0.6315787787694688
D4_13 = -0.08899033645133331
D4_14 = 18.148505520854727
D4_15 = -9.194632392478356
D4_16 = -4.436036387594894
D5_1 = 10.427508642579134
D5_6 = 242.28349177525817
D5_7 = 165.20045171727028
D5_8 = -374.5467547226902
D5_9 = -22.113666853125306
D5_10 = 7.733432668472264
D5_11 = -30.674084731089398
D5_12 = -9.332130526430229
D5_13 = 15.697238121770845
D5_14 = -31.139403219565178
D5_15 = -9.35292435884448
D5_16 = 35.81684148639408
D6_1 = 19.985053242002433
D6_6 = -387.0373087493518
D6_7 = -189.17813819516758
D6_8 = 527.8081592054236
D6_9 = -11.57390253995963
D6_10 = 6.8812326946963
D6_11 = -1.0006050966910838
D6_12 = 0.7777137798053443
D6_13 = -2.778205752353508
D6_14 = -60.19669523126412
D6_15 = 84.32040550667716
D6_16 = 11.99229113618279
D7_1 = -25.69393346270375
D7_6 = -154.18974869023643
D7_7 = -231.5293791760455
D7_8 = 357.6391179106141
D7_9 = 93.40532418362432
D7_10 = -37.45832313645163
D7_11 = 104.0996495089623
D7_12 = 29.8402934266605
D7_13 = -43.53345659001114
D7_14 = 96.32455395918828
D7_15 = -39.17726167561544
D7_16 = -149.72683625798564

# The floor of zdot's error weight at the rounding of the spring force (dopri5.py):
# the rounding of k x enters each estimate through the sum of its weights' sizes,
# 0.16 for dopri5's and 4.19 for the fifth-order estimate here, so the floor is
# raised by their ratio (else the estimate of a rounding-limited motion is its
# noise, and the steps shrink for it).
FLOOR_GAIN = (abs(E5_1) + abs(E5_6) + abs(E5_7) + abs(E5_8) + abs(E5_9) + abs(E5_10)
              + abs(E5_11) + abs(E5_12)) / float(abs(TABLEAU_E).sum())


@kernel
def dop853_step(t, x, zd, h, s, p, lw, fx, o, want_q):
    """One DOP853 step of the sliding field from time t [s]; see ``stepper.py``."""
    k = p[K]
    cf = constants(p, lw, s)
    im = 1.0 / p[M]
    floor_z = FLOOR_GAIN * EPS * h * k * im * abs(x)
    step_load(fx, t, h, STAGE_C)
    KX, KZ, X, Z = _stages(x, zd, h, s, p, lw, cf, fx)
    x_end, z_end = X[7], Z[7]
    sx = o[O_RTOL] * (o[O_LX] + max(abs(x), abs(x_end)))
    sz = o[O_RTOL] * (o[O_LV] + max(abs(zd), abs(z_end))) + floor_z
    err = _error(h, sx, sz, (KX[0], KX[5], KX[6], KX[7], KX[8], KX[9], KX[10], KX[11]),
                 (KZ[0], KZ[5], KZ[6], KZ[7], KZ[8], KZ[9], KZ[10], KZ[11]))
    # the slopes the continuous extension needs (``dop853_extend``: stages 1, 6-12)
    # and the tangent (``variational.py``: every stage's zdot, from x's slopes)
    ks = (KX[0], KX[1], KX[2], KX[3], KX[4], KX[5], KX[6], KX[7], KX[8], KX[9], KX[10],
          KX[11], KZ[0], KZ[5], KZ[6], KZ[7], KZ[8], KZ[9], KZ[10], KZ[11])
    if not want_q:
        return x_end, z_end, 0.0, 0.0, 0.0, 0.0, err, True, ks
    qx, qv, qw, ql = _quadratures(h, s, p, lw, cf, (x, X[0], X[1], X[2], X[3], X[4], X[5],
                                                    X[6]),
                                  (zd, Z[0], Z[1], Z[2], Z[3], Z[4], Z[5], Z[6]))
    return x_end, z_end, qx, qv, qw, ql, err, True, ks


@kernel(inline="always")
def _stages(x, zd, h, s, p, lw, cf, fx):
    """The twelve stages of a step: their slopes (KX, KZ: of x and zdot, stages
    1-12) and the states (X, Z) of stages 6-12 and of the step's end (the last).
    Each stage's acceleration carries the load at its own time (``with_stage``,
    after the excitation's ``step_load``)."""
    v = p[V]
    k = p[K]
    im = 1.0 / p[M]
    # the newest slope of each stage enters last, by h A precomputed: the
    # chain from one stage to the next is then one product and one sum
    hA3_2 = h * A3_2
    hA4_3 = h * A4_3
    hA5_4 = h * A5_4
    hA6_5 = h * A6_5
    hA7_6 = h * A7_6
    hA8_7 = h * A8_7
    hA9_8 = h * A9_8
    hA10_9 = h * A10_9
    hA11_10 = h * A11_10
    hA12_11 = h * A12_11
    k1x = zd + v
    k1z = with_stage(fx, 0, zdd_of(x, zd, s, cf, lw, k, im), im)
    x2 = x + h * (A2_1 * k1x)
    z2 = zd + h * (A2_1 * k1z)
    k2x = z2 + v
    k2z = with_stage(fx, 1, zdd_of(x2, z2, s, cf, lw, k, im), im)
    x3 = x + h * (A3_1 * k1x) + hA3_2 * k2x
    z3 = zd + h * (A3_1 * k1z) + hA3_2 * k2z
    k3x = z3 + v
    k3z = with_stage(fx, 2, zdd_of(x3, z3, s, cf, lw, k, im), im)
    x4 = x + h * (A4_1 * k1x) + hA4_3 * k3x
    z4 = zd + h * (A4_1 * k1z) + hA4_3 * k3z
    k4x = z4 + v
    k4z = with_stage(fx, 3, zdd_of(x4, z4, s, cf, lw, k, im), im)
    x5 = x + h * (A5_1 * k1x + A5_3 * k3x) + hA5_4 * k4x
    z5 = zd + h * (A5_1 * k1z + A5_3 * k3z) + hA5_4 * k4z
    k5x = z5 + v
    k5z = with_stage(fx, 4, zdd_of(x5, z5, s, cf, lw, k, im), im)
    x6 = x + h * (A6_1 * k1x + A6_4 * k4x) + hA6_5 * k5x
    z6 = zd + h * (A6_1 * k1z + A6_4 * k4z) + hA6_5 * k5z
    k6x = z6 + v
    k6z = with_stage(fx, 5, zdd_of(x6, z6, s, cf, lw, k, im), im)
    x7 = x + h * (A7_1 * k1x + A7_4 * k4x + A7_5 * k5x) + hA7_6 * k6x
    z7 = zd + h * (A7_1 * k1z + A7_4 * k4z + A7_5 * k5z) + hA7_6 * k6z
    k7x = z7 + v
    k7z = with_stage(fx, 6, zdd_of(x7, z7, s, cf, lw, k, im), im)
    x8 = x + h * (A8_1 * k1x + A8_4 * k4x + A8_5 * k5x + A8_6 * k6x) + hA8_7 * k7x
    z8 = zd + h * (A8_1 * k1z + A8_4 * k4z + A8_5 * k5z + A8_6 * k6z) + hA8_7 * k7z
    k8x = z8 + v
    k8z = with_stage(fx, 7, zdd_of(x8, z8, s, cf, lw, k, im), im)
    x9 = (x + h * (A9_1 * k1x + A9_4 * k4x + A9_5 * k5x + A9_6 * k6x + A9_7 * k7x)
          + hA9_8 * k8x)
    z9 = (zd + h * (A9_1 * k1z + A9_4 * k4z + A9_5 * k5z + A9_6 * k6z + A9_7 * k7z)
          + hA9_8 * k8z)
    k9x = z9 + v
    k9z = with_stage(fx, 8, zdd_of(x9, z9, s, cf, lw, k, im), im)
    x10 = (x + h * (A10_1 * k1x + A10_4 * k4x + A10_5 * k5x + A10_6 * k6x +
                    A10_7 * k7x + A10_8 * k8x)
           + hA10_9 * k9x)
    z10 = (zd + h * (A10_1 * k1z + A10_4 * k4z + A10_5 * k5z + A10_6 * k6z +
                     A10_7 * k7z + A10_8 * k8z)
           + hA10_9 * k9z)
    k10x = z10 + v
    k10z = with_stage(fx, 9, zdd_of(x10, z10, s, cf, lw, k, im), im)
    x11 = (x + h * (A11_1 * k1x + A11_4 * k4x + A11_5 * k5x + A11_6 * k6x +
                    A11_7 * k7x + A11_8 * k8x + A11_9 * k9x)
           + hA11_10 * k10x)
    z11 = (zd + h * (A11_1 * k1z + A11_4 * k4z + A11_5 * k5z + A11_6 * k6z +
                     A11_7 * k7z + A11_8 * k8z + A11_9 * k9z)
           + hA11_10 * k10z)
    k11x = z11 + v
    k11z = with_stage(fx, 10, zdd_of(x11, z11, s, cf, lw, k, im), im)
    x12 = (x + h * (A12_1 * k1x + A12_4 * k4x + A12_5 * k5x + A12_6 * k6x +
                    A12_7 * k7x + A12_8 * k8x + A12_9 * k9x + A12_10 * k10x)
           + hA12_11 * k11x)
    z12 = (zd + h * (A12_1 * k1z + A12_4 * k4z + A12_5 * k5z + A12_6 * k6z +
                     A12_7 * k7z + A12_8 * k8z + A12_9 * k9z + A12_10 * k10z)
           + hA12_11 * k11z)
    k12x = z12 + v
    k12z = with_stage(fx, 11, zdd_of(x12, z12, s, cf, lw, k, im), im)
    x_end = x + h * (B1 * k1x + B6 * k6x + B7 * k7x + B8 * k8x + B9 * k9x + B10 * k10x +
                     B11 * k11x + B12 * k12x)
    z_end = zd + h * (B1 * k1z + B6 * k6z + B7 * k7z + B8 * k8z + B9 * k9z +
                      B10 * k10z + B11 * k11z + B12 * k12z)
    return ((k1x, k2x, k3x, k4x, k5x, k6x, k7x, k8x, k9x, k10x, k11x, k12x),
            (k1z, k2z, k3z, k4z, k5z, k6z, k7z, k8z, k9z, k10z, k11z, k12z),
            (x6, x7, x8, x9, x10, x11, x12, x_end), (z6, z7, z8, z9, z10, z11, z12, z_end))


@kernel(inline="always")
def _error(h, sx, sz, KX, KZ):
    """DOP853's scaled error (Hairer's estimator) from the stages KX, KZ (of x and
    zdot: stages 1, 6-12) with the error scales sx, sz: the fifth- and third-order
    estimates, each the larger of its two components."""
    e5x = (E5_1 * KX[0] + E5_6 * KX[1] + E5_7 * KX[2] + E5_8 * KX[3] + E5_9 * KX[4] +
           E5_10 * KX[5] + E5_11 * KX[6] + E5_12 * KX[7])
    e5z = (E5_1 * KZ[0] + E5_6 * KZ[1] + E5_7 * KZ[2] + E5_8 * KZ[3] + E5_9 * KZ[4] +
           E5_10 * KZ[5] + E5_11 * KZ[6] + E5_12 * KZ[7])
    e3x = (E3_1 * KX[0] + E3_6 * KX[1] + E3_7 * KX[2] + E3_8 * KX[3] + E3_9 * KX[4] +
           E3_10 * KX[5] + E3_11 * KX[6] + E3_12 * KX[7])
    e3z = (E3_1 * KZ[0] + E3_6 * KZ[1] + E3_7 * KZ[2] + E3_8 * KZ[3] + E3_9 * KZ[4] +
           E3_10 * KZ[5] + E3_11 * KZ[6] + E3_12 * KZ[7])
    e5 = max(abs(e5x) / sx, abs(e5z) / sz)
    e3 = max(abs(e3x) / sx, abs(e3z) / sz)
    den = e5 * e5 + 0.01 * e3 * e3
    return abs(h) * e5 * e5 / math.sqrt(den) if den > 0.0 else 0.0


@kernel(inline="always")
def _quadratures(h, s, p, lw, cf, X, Z):
    """The step's quadratures of x, xdot^2, the friction power and the law's slope
    term with the weights b, from the states X, Z (x, zdot) of the weighted stages."""
    v = p[V]
    qx = h * (B1 * X[0] + B6 * X[1] + B7 * X[2] + B8 * X[3] + B9 * X[4] + B10 * X[5] +
              B11 * X[6] + B12 * X[7])
    qv = h * (B1 * (Z[0] + v) ** 2 + B6 * (Z[1] + v) ** 2 + B7 * (Z[2] + v) ** 2 +
              B8 * (Z[3] + v) ** 2 + B9 * (Z[4] + v) ** 2 + B10 * (Z[5] + v) ** 2 +
              B11 * (Z[6] + v) ** 2 + B12 * (Z[7] + v) ** 2)
    qw = h * (B1 * friction_force(lw, cf, Z[0], s) * (Z[0] + v) +
              B6 * friction_force(lw, cf, Z[1], s) * (Z[1] + v) +
              B7 * friction_force(lw, cf, Z[2], s) * (Z[2] + v) +
              B8 * friction_force(lw, cf, Z[3], s) * (Z[3] + v) +
              B9 * friction_force(lw, cf, Z[4], s) * (Z[4] + v) +
              B10 * friction_force(lw, cf, Z[5], s) * (Z[5] + v) +
              B11 * friction_force(lw, cf, Z[6], s) * (Z[6] + v) +
              B12 * friction_force(lw, cf, Z[7], s) * (Z[7] + v))
    ql = h * (B1 * integrand(lw, cf, Z[0]) + B6 * integrand(lw, cf, Z[1]) +
              B7 * integrand(lw, cf, Z[2]) + B8 * integrand(lw, cf, Z[3]) +
              B9 * integrand(lw, cf, Z[4]) + B10 * integrand(lw, cf, Z[5]) +
              B11 * integrand(lw, cf, Z[6]) + B12 * integrand(lw, cf, Z[7]))
    return qx, qv, qw, ql


@kernel
def dop853_extend(t, x, zd, h, s, p, lw, fx, x_end, z_end, ks):
    """The continuous extension of the step ``h`` from ``(x, zd)`` to ``(x_end,
    z_end)`` from its slopes ``ks`` (stages 1, 6-12 of x, then of zdot, as
    ``dop853_step`` returns them): the slope at the step's end and three more stages
    (Hairer, Norsett & Wanner, section II.6, and their code DOP853's contd8)."""
    v = p[V]
    k = p[K]
    im = 1.0 / p[M]
    cf = constants(p, lw, s)
    step_load(fx, t, h, EXTENSION_C)
    (k1x, _k2x, _k3x, _k4x, _k5x, k6x, k7x, k8x, k9x, k10x, k11x, k12x,
     k1z, k6z, k7z, k8z, k9z, k10z, k11z, k12z) = ks
    k13x = z_end + v
    k13z = with_stage(fx, 0, zdd_of(x_end, z_end, s, cf, lw, k, im), im)
    x14 = x + h * (A14_1 * k1x + A14_7 * k7x + A14_8 * k8x + A14_9 * k9x + A14_10 * k10x
        + A14_11 * k11x + A14_12 * k12x + A14_13 * k13x)
    z14 = zd + h * (A14_1 * k1z + A14_7 * k7z + A14_8 * k8z + A14_9 * k9z + A14_10 *
        k10z + A14_11 * k11z + A14_12 * k12z + A14_13 * k13z)
    k14x = z14 + v
    k14z = with_stage(fx, 1, zdd_of(x14, z14, s, cf, lw, k, im), im)
    x15 = x + h * (A15_1 * k1x + A15_6 * k6x + A15_7 * k7x + A15_8 * k8x + A15_11 * k11x
        + A15_12 * k12x + A15_13 * k13x + A15_14 * k14x)
    z15 = zd + h * (A15_1 * k1z + A15_6 * k6z + A15_7 * k7z + A15_8 * k8z + A15_11 *
        k11z + A15_12 * k12z + A15_13 * k13z + A15_14 * k14z)
    k15x = z15 + v
    k15z = with_stage(fx, 2, zdd_of(x15, z15, s, cf, lw, k, im), im)
    x16 = x + h * (A16_1 * k1x + A16_6 * k6x + A16_7 * k7x + A16_8 * k8x + A16_9 * k9x +
        A16_13 * k13x + A16_14 * k14x + A16_15 * k15x)
    z16 = zd + h * (A16_1 * k1z + A16_6 * k6z + A16_7 * k7z + A16_8 * k8z + A16_9 * k9z
        + A16_13 * k13z + A16_14 * k14z + A16_15 * k15z)
    k16x = z16 + v
    k16z = with_stage(fx, 3, zdd_of(x16, z16, s, cf, lw, k, im), im)
    f3x = h * (D4_1 * k1x + D4_6 * k6x + D4_7 * k7x + D4_8 * k8x + D4_9 * k9x + D4_10 *
        k10x + D4_11 * k11x + D4_12 * k12x + D4_13 * k13x + D4_14 * k14x + D4_15 * k15x
        + D4_16 * k16x)
    f3z = h * (D4_1 * k1z + D4_6 * k6z + D4_7 * k7z + D4_8 * k8z + D4_9 * k9z + D4_10 *
        k10z + D4_11 * k11z + D4_12 * k12z + D4_13 * k13z + D4_14 * k14z + D4_15 * k15z
        + D4_16 * k16z)
    f4x = h * (D5_1 * k1x + D5_6 * k6x + D5_7 * k7x + D5_8 * k8x + D5_9 * k9x + D5_10 *
        k10x + D5_11 * k11x + D5_12 * k12x + D5_13 * k13x + D5_14 * k14x + D5_15 * k15x
        + D5_16 * k16x)
    f4z = h * (D5_1 * k1z + D5_6 * k6z + D5_7 * k7z + D5_8 * k8z + D5_9 * k9z + D5_10 *
        k10z + D5_11 * k11z + D5_12 * k12z + D5_13 * k13z + D5_14 * k14z + D5_15 * k15z
        + D5_16 * k16z)
    f5x = h * (D6_1 * k1x + D6_6 * k6x + D6_7 * k7x + D6_8 * k8x + D6_9 * k9x + D6_10 *
        k10x + D6_11 * k11x + D6_12 * k12x + D6_13 * k13x + D6_14 * k14x + D6_15 * k15x
        + D6_16 * k16x)
    f5z = h * (D6_1 * k1z + D6_6 * k6z + D6_7 * k7z + D6_8 * k8z + D6_9 * k9z + D6_10 *
        k10z + D6_11 * k11z + D6_12 * k12z + D6_13 * k13z + D6_14 * k14z + D6_15 * k15z
        + D6_16 * k16z)
    f6x = h * (D7_1 * k1x + D7_6 * k6x + D7_7 * k7x + D7_8 * k8x + D7_9 * k9x + D7_10 *
        k10x + D7_11 * k11x + D7_12 * k12x + D7_13 * k13x + D7_14 * k14x + D7_15 * k15x
        + D7_16 * k16x)
    f6z = h * (D7_1 * k1z + D7_6 * k6z + D7_7 * k7z + D7_8 * k8z + D7_9 * k9z + D7_10 *
        k10z + D7_11 * k11z + D7_12 * k12z + D7_13 * k13z + D7_14 * k14z + D7_15 * k15z
        + D7_16 * k16z)
    dx = x_end - x
    dz = z_end - zd
    return (dx, h * k1x - dx, 2.0 * dx - h * (k13x + k1x), f3x, f4x, f5x, f6x,
            dz, h * k1z - dz, 2.0 * dz - h * (k13z + k1z), f3z, f4z, f5z, f6z)
