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
from .jit import kernel

from .dopri5 import EPS, TABLEAU_E
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

# The floor of zdot's error weight at the rounding of the spring force (dopri5.py):
# the rounding of k x enters each estimate through the sum of its weights' sizes,
# 0.16 for dopri5's and 4.19 for the fifth-order estimate here, so the floor is
# raised by their ratio (else the estimate of a rounding-limited motion is its
# noise, and the steps shrink for it).
FLOOR_GAIN = (abs(E5_1) + abs(E5_6) + abs(E5_7) + abs(E5_8) + abs(E5_9) + abs(E5_10)
              + abs(E5_11) + abs(E5_12)) / float(abs(TABLEAU_E).sum())


@kernel
def dop853_step(x, zd, h, s, p, lw, o, want_q):
    """One DOP853 step of the sliding field; see ``stepper.py``."""
    v = p[V]
    k = p[K]
    im = 1.0 / p[M]
    cf = constants(p, lw, s)
    floor_z = FLOOR_GAIN * EPS * h * k * im * abs(x)
    k1x = zd + v
    k1z = zdd_of(x, zd, s, cf, lw, k, im)
    x2 = x + h * (A2_1 * k1x)
    z2 = zd + h * (A2_1 * k1z)
    k2x = z2 + v
    k2z = zdd_of(x2, z2, s, cf, lw, k, im)
    x3 = x + h * (A3_1 * k1x + A3_2 * k2x)
    z3 = zd + h * (A3_1 * k1z + A3_2 * k2z)
    k3x = z3 + v
    k3z = zdd_of(x3, z3, s, cf, lw, k, im)
    x4 = x + h * (A4_1 * k1x + A4_3 * k3x)
    z4 = zd + h * (A4_1 * k1z + A4_3 * k3z)
    k4x = z4 + v
    k4z = zdd_of(x4, z4, s, cf, lw, k, im)
    x5 = x + h * (A5_1 * k1x + A5_3 * k3x + A5_4 * k4x)
    z5 = zd + h * (A5_1 * k1z + A5_3 * k3z + A5_4 * k4z)
    k5x = z5 + v
    k5z = zdd_of(x5, z5, s, cf, lw, k, im)
    x6 = x + h * (A6_1 * k1x + A6_4 * k4x + A6_5 * k5x)
    z6 = zd + h * (A6_1 * k1z + A6_4 * k4z + A6_5 * k5z)
    k6x = z6 + v
    k6z = zdd_of(x6, z6, s, cf, lw, k, im)
    x7 = x + h * (A7_1 * k1x + A7_4 * k4x + A7_5 * k5x + A7_6 * k6x)
    z7 = zd + h * (A7_1 * k1z + A7_4 * k4z + A7_5 * k5z + A7_6 * k6z)
    k7x = z7 + v
    k7z = zdd_of(x7, z7, s, cf, lw, k, im)
    x8 = x + h * (A8_1 * k1x + A8_4 * k4x + A8_5 * k5x + A8_6 * k6x + A8_7 * k7x)
    z8 = zd + h * (A8_1 * k1z + A8_4 * k4z + A8_5 * k5z + A8_6 * k6z + A8_7 * k7z)
    k8x = z8 + v
    k8z = zdd_of(x8, z8, s, cf, lw, k, im)
    x9 = x + h * (A9_1 * k1x + A9_4 * k4x + A9_5 * k5x + A9_6 * k6x + A9_7 * k7x +
                  A9_8 * k8x)
    z9 = zd + h * (A9_1 * k1z + A9_4 * k4z + A9_5 * k5z + A9_6 * k6z + A9_7 * k7z +
                   A9_8 * k8z)
    k9x = z9 + v
    k9z = zdd_of(x9, z9, s, cf, lw, k, im)
    x10 = x + h * (A10_1 * k1x + A10_4 * k4x + A10_5 * k5x + A10_6 * k6x + A10_7 * k7x +
                   A10_8 * k8x + A10_9 * k9x)
    z10 = zd + h * (A10_1 * k1z + A10_4 * k4z + A10_5 * k5z + A10_6 * k6z + A10_7 * k7z +
                    A10_8 * k8z + A10_9 * k9z)
    k10x = z10 + v
    k10z = zdd_of(x10, z10, s, cf, lw, k, im)
    x11 = x + h * (A11_1 * k1x + A11_4 * k4x + A11_5 * k5x + A11_6 * k6x + A11_7 * k7x +
                   A11_8 * k8x + A11_9 * k9x + A11_10 * k10x)
    z11 = zd + h * (A11_1 * k1z + A11_4 * k4z + A11_5 * k5z + A11_6 * k6z + A11_7 * k7z +
                    A11_8 * k8z + A11_9 * k9z + A11_10 * k10z)
    k11x = z11 + v
    k11z = zdd_of(x11, z11, s, cf, lw, k, im)
    x12 = x + h * (A12_1 * k1x + A12_4 * k4x + A12_5 * k5x + A12_6 * k6x + A12_7 * k7x +
                   A12_8 * k8x + A12_9 * k9x + A12_10 * k10x + A12_11 * k11x)
    z12 = zd + h * (A12_1 * k1z + A12_4 * k4z + A12_5 * k5z + A12_6 * k6z + A12_7 * k7z +
                    A12_8 * k8z + A12_9 * k9z + A12_10 * k10z + A12_11 * k11z)
    k12x = z12 + v
    k12z = zdd_of(x12, z12, s, cf, lw, k, im)
    x_end = x + h * (B1 * k1x + B6 * k6x + B7 * k7x + B8 * k8x + B9 * k9x + B10 * k10x +
                     B11 * k11x + B12 * k12x)
    z_end = zd + h * (B1 * k1z + B6 * k6z + B7 * k7z + B8 * k8z + B9 * k9z + B10 * k10z +
                      B11 * k11z + B12 * k12z)
    sx = o[O_RTOL] * (o[O_LX] + max(abs(x), abs(x_end)))
    sz = o[O_RTOL] * (o[O_LV] + max(abs(zd), abs(z_end))) + floor_z
    err = _error(h, sx, sz, (k1x, k6x, k7x, k8x, k9x, k10x, k11x, k12x),
                 (k1z, k6z, k7z, k8z, k9z, k10z, k11z, k12z))
    if not want_q:
        return x_end, z_end, 0.0, 0.0, 0.0, 0.0, err, True
    qx, qv, qw, ql = _quadratures(h, s, p, lw, cf, (x, x6, x7, x8, x9, x10, x11, x12),
                                  (zd, z6, z7, z8, z9, z10, z11, z12))
    return x_end, z_end, qx, qv, qw, ql, err, True


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
    return abs(h) * e5 * e5 / den ** 0.5 if den > 0.0 else 0.0


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
