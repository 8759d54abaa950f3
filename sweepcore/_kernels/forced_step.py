"""One DOP853 step of the forced sliding field (method "dop853" with time).

The sliding field of a slider under the harmonic load ``e(t) = a cos(Omega t) +
b sin(Omega t)`` (``excitations/harmonic.py``) is the autonomous one plus ``e(t)/m``:

    x' = zdot + v,    zdot' = (-k x - F(zdot) - c (zdot + v) + e(t)) / m.

The step is Prince & Dormand's 12-stage eighth-order pair with Hairer, Norsett &
Wanner's error estimator (the coefficients of ``dop853.py``, read from it, so there is
one copy of them), written as loops over the tableau: a stage sees its own time
``t + c_i h``. As in ``stepper.py``'s contract the state at ``t + theta h`` is the step
itself over ``theta h`` (events are located on re-steps), and the quadrature of x is
the step's own, at the method's order. ``ws`` is an (8, 12) work array (stage slopes
of x and zdot, stage states, and the variational equations' stage slopes), taken
once per point so the loop allocates nothing.
"""
import math

import numpy as np

from . import dop853
from .dop853 import FLOOR_GAIN
from .dopri5 import EPS
from .jit import kernel
from .law import field_slope, zdd_of
from .layout import K, M, O_LV, O_LX, O_RTOL
from .layout import V as V_

STAGES = 12
_C = np.zeros(STAGES)
_A = np.zeros((STAGES, STAGES))
for _i in range(2, STAGES + 1):
    _C[_i - 1] = getattr(dop853, f"C{_i}")
    for _j in range(1, _i):
        _A[_i - 1, _j - 1] = getattr(dop853, f"A{_i}_{_j}", 0.0)
_WEIGHTED = (1, 6, 7, 8, 9, 10, 11, 12)        # the stages b, E5 and E3 weigh
_B = np.zeros(STAGES)
_E5 = np.zeros(STAGES)
_E3 = np.zeros(STAGES)
for _i in _WEIGHTED:
    _B[_i - 1] = getattr(dop853, f"B{_i}")
    _E5[_i - 1] = getattr(dop853, f"E5_{_i}")
    _E3[_i - 1] = getattr(dop853, f"E3_{_i}")
C_, A_, B_, E5_, E3_ = _C, _A, _B, _E5, _E3


@kernel(inline="always")
def load(fa, fb, om, t):
    """The harmonic load ``a cos(Omega t) + b sin(Omega t)`` [kN]."""
    w = om * t
    return fa * math.cos(w) + fb * math.sin(w)


@kernel
def forced_step(x, zd, t, h, s, p, lw, cf, fa, fb, om, o, ws, V, vout, want_q, want_v):
    """One step from (x, zd) at time t [s] over h [s] of the slide with sign s:
    ``(x1, zd1, q_x, err)`` (q_x the step's quadrature of x [cm s], 0 unless
    ``want_q``; err the error scaled by the tolerance, <= 1 accept). With ``want_v``
    the variational equations ride along: ``V`` (4: the Jacobian of the state
    (x, zdot) with respect to a start, row by row) is advanced by the same stages
    into ``vout``, with ``d zdot'/d x = -k/m`` and ``d zdot'/d zdot = -(c + F')/m``
    (the slide's branch of F')."""
    v = p[V_]
    k = p[K]
    im = 1.0 / p[M]
    for i in range(STAGES):
        sx = 0.0
        sz = 0.0
        for j in range(i):
            aij = A_[i, j]
            if aij != 0.0:
                sx += aij * ws[0, j]
                sz += aij * ws[1, j]
        xi = x + h * sx
        zi = zd + h * sz
        ws[2, i] = xi
        ws[3, i] = zi
        ws[0, i] = zi + v
        ws[1, i] = zdd_of(xi, zi, s, cf, lw, k, im) + load(fa, fb, om, t + C_[i] * h) * im
        if want_v:
            g = field_slope(lw, cf, zi) * im
            for c in range(2):             # the two columns of the Jacobian
                px = 0.0
                pz = 0.0
                for j in range(i):
                    aij = A_[i, j]
                    if aij != 0.0:
                        px += aij * ws[4 + 2 * c, j]
                        pz += aij * ws[5 + 2 * c, j]
                vx = V[c] + h * px
                vz = V[2 + c] + h * pz
                ws[4 + 2 * c, i] = vz
                ws[5 + 2 * c, i] = -k * im * vx + g * vz
    bx = 0.0
    bz = 0.0
    e5x = 0.0
    e5z = 0.0
    e3x = 0.0
    e3z = 0.0
    qx = 0.0
    for i in range(STAGES):
        if B_[i] != 0.0 or E5_[i] != 0.0:
            bx += B_[i] * ws[0, i]
            bz += B_[i] * ws[1, i]
            e5x += E5_[i] * ws[0, i]
            e5z += E5_[i] * ws[1, i]
            e3x += E3_[i] * ws[0, i]
            e3z += E3_[i] * ws[1, i]
            if want_q:
                qx += B_[i] * ws[2, i]
    if want_v:
        for c in range(2):
            px = 0.0
            pz = 0.0
            for i in range(STAGES):
                if B_[i] != 0.0:
                    px += B_[i] * ws[4 + 2 * c, i]
                    pz += B_[i] * ws[5 + 2 * c, i]
            vout[c] = V[c] + h * px
            vout[2 + c] = V[2 + c] + h * pz
    x1 = x + h * bx
    z1 = zd + h * bz
    floor_z = FLOOR_GAIN * EPS * h * k * im * abs(x)
    scx = o[O_RTOL] * (o[O_LX] + max(abs(x), abs(x1)))
    scz = o[O_RTOL] * (o[O_LV] + max(abs(zd), abs(z1))) + floor_z
    e5 = max(abs(e5x) / scx, abs(e5z) / scz)
    e3 = max(abs(e3x) / scx, abs(e3z) / scz)
    den = e5 * e5 + 0.01 * e3 * e3
    err = abs(h) * e5 * e5 / math.sqrt(den) if den > 0.0 else 0.0
    return x1, z1, h * qx, err


@kernel(inline="always")
def forced_accel(x, zd, t, s, p, lw, cf, fa, fb, om):
    """zdot' of the forced slide [cm/s^2] at (x, zd, t)."""
    return zdd_of(x, zd, s, cf, lw, p[K], 1.0 / p[M]) + load(fa, fb, om, t) / p[M]
