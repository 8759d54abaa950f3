"""The tangent of a step: the derivative of the state with respect to a start.

The stroboscopic search (``strobe.py``) solves ``P^n(u) = u`` by Newton's method and
reports the multipliers of P^n: both need the Jacobian of the state after n forcing
periods with respect to the start. Along a slide it obeys the variational equations
of the sliding field (x' = zdot + v, zdot' = (-k x - F(zdot) - c (zdot + v) + e(t))/m):

    d/dt J = [[0, 1], [-k/m, -(c + F'(zdot))/m]] J,

and at every switch the driver passes it through the switch's saltation matrix
(``driver.py``). A Runge-Kutta method applied to the variational equations with the
stages of the state's own step gives the exact derivative of the step map
(Hairer, Norsett & Wanner, Solving ODEs I, section II.12, "internal
differentiation"): so for the methods that keep their stages (dopri5, dop853:
``stepper.step_kept``) the tangent is carried by the method's own tableau, with
the stage slopes ``F'`` at each stage's zdot. The other methods (rk4, gps, exact
arcs) carry it by forward differences of two re-steps (relative step sqrt(eps)).
"""
import math

import numpy as np
from numba.extending import overload

from . import dop853, dopri5
from .jit import OVERLOAD_OPTIONS, kernel, runtime
from .law import constants, field_slope
from .layout import K, M, O_LV, O_LX, S_N, S_STAGES, V
from .stepper import METHODS, _method

SQRT_EPS = math.sqrt(np.finfo(np.float64).eps)


def _dop853_tableau():
    a = np.zeros((12, 12))
    b = np.zeros(12)
    for i in range(2, 13):
        for j in range(1, i):
            a[i - 1, j - 1] = getattr(dop853, f"A{i}_{j}", 0.0)
    for i in (1, 6, 7, 8, 9, 10, 11, 12):
        b[i - 1] = getattr(dop853, f"B{i}")
    return a, b


A8, B8 = _dop853_tableau()
A5 = np.ascontiguousarray(dopri5.TABLEAU_A[:6, :6])
B5 = np.ascontiguousarray(dopri5.TABLEAU_B[:6])


@kernel
def rk_tangent(J, h, zs, nz_n, nz_j, nz_a, b, p, lw, cf, st):
    """J carried through a step h of a tableau whose stages had the relative speeds
    zs: the variational equations integrated by the same stages, both columns of J
    at once (the stage slopes in ``st``'s scratch, 4 a stage). The tableau is given
    by its nonzero entries a_ij (row i: ``nz_n[i]`` of them, columns ``nz_j``,
    values ``nz_a``) and its weights b."""
    k = p[K]
    im = 1.0 / p[M]
    kk = -k * im
    s11 = 0.0
    s12 = 0.0
    s21 = 0.0
    s22 = 0.0
    for i in range(b.shape[0]):
        w11 = J[0]
        w12 = J[1]
        w21 = J[2]
        w22 = J[3]
        for q in range(nz_n[i]):
            at = S_STAGES + 4 * nz_j[i, q]
            ha = h * nz_a[i, q]
            w11 += ha * st[at]
            w12 += ha * st[at + 1]
            w21 += ha * st[at + 2]
            w22 += ha * st[at + 3]
        g = field_slope(lw, cf, zs[i]) * im
        k11 = w21
        k12 = w22
        k21 = kk * w11 + g * w21
        k22 = kk * w12 + g * w22
        at = S_STAGES + 4 * i
        st[at] = k11
        st[at + 1] = k12
        st[at + 2] = k21
        st[at + 3] = k22
        s11 += b[i] * k11
        s12 += b[i] * k12
        s21 += b[i] * k21
        s22 += b[i] * k22
    return J[0] + h * s11, J[1] + h * s12, J[2] + h * s21, J[3] + h * s22


def _nonzeros(a):
    """The nonzero entries of a tableau by row: counts, columns, values."""
    n = a.shape[0]
    counts = np.array([np.count_nonzero(a[i]) for i in range(n)], np.int64)
    cols = np.zeros((n, n), np.int64)
    vals = np.zeros((n, n))
    for i in range(n):
        js = np.flatnonzero(a[i])
        cols[i, :js.size] = js
        vals[i, :js.size] = a[i, js]
    return counts, cols, vals


N8, J8, V8 = _nonzeros(A8)
N5, J5, V5 = _nonzeros(A5)


def tangent(meth, J, t, x, zd, h, s, p, lw, fx, o, x1, z1, ks, st):
    """J (4: row by row) carried through the step h of method ``meth`` from (x, zd)
    at t to (x1, z1), ``ks`` as ``step_kept`` returned it (module docstring)."""


@overload(tangent, prefer_literal=True, inline="always", jit_options=OVERLOAD_OPTIONS)
def _tangent(meth, J, t, x, zd, h, s, p, lw, fx, o, x1, z1, ks, st):
    code = _method(meth)
    if code == 4:           # dop853: every stage's x slope is zdot + v
        def by_dop853(meth, J, t, x, zd, h, s, p, lw, fx, o, x1, z1, ks, st):
            v = p[V]
            zs = (ks[0] - v, ks[1] - v, ks[2] - v, ks[3] - v, ks[4] - v, ks[5] - v,
                  ks[6] - v, ks[7] - v, ks[8] - v, ks[9] - v, ks[10] - v, ks[11] - v)
            return rk_tangent(J, h, zs, N8, J8, V8, B8, p, lw, constants(p, lw, s), st)
        return by_dop853
    if code == 3:           # dopri5: stages 1-6 (k2x kept last)
        def by_dopri5(meth, J, t, x, zd, h, s, p, lw, fx, o, x1, z1, ks, st):
            v = p[V]
            zs = (ks[0] - v, ks[12] - v, ks[1] - v, ks[2] - v, ks[3] - v, ks[4] - v)
            return rk_tangent(J, h, zs, N5, J5, V5, B5, p, lw, constants(p, lw, s), st)
        return by_dopri5
    fn = METHODS[code][6]

    def by_differences(meth, J, t, x, zd, h, s, p, lw, fx, o, x1, z1, ks, st):
        dx = SQRT_EPS * (abs(x) + o[O_LX])
        dz = SQRT_EPS * (abs(zd) + o[O_LV])
        xa, za, _a, _b, _c, _d, _e, _ok = fn(t, x + dx, zd, h, s, p, lw, fx, o,
                                             runtime(False))
        xb, zb, _a, _b, _c, _d, _e, _ok = fn(t, x, zd + dz, h, s, p, lw, fx, o,
                                             runtime(False))
        st[S_N] += 2.0
        d11 = (xa - x1) / dx
        d21 = (za - z1) / dx
        d12 = (xb - x1) / dz
        d22 = (zb - z1) / dz
        return (d11 * J[0] + d12 * J[2], d11 * J[1] + d12 * J[3],
                d21 * J[0] + d22 * J[2], d21 * J[1] + d22 * J[3])
    return by_differences
