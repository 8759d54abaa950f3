"""The normal form of the Hopf bifurcation at v* (first-order averaging).

With ``y = x - x_eq`` and ``w = ydot``, sliding with ``zdot < 0`` (v > 0) is, for the
paper's law (eq. 40, any damping c), exactly

    wdot = -omega^2 y + q w + c2 w^2 - c3 w^3,   c2 = 3 alpha2 v / m,  c3 = alpha2 / m

(eq. 41 expanded about zdot = -v; q of eq. 46; ``law.nf_coefficients`` gives the
coefficients of every law). Averaging over ``y = A cos(theta)`` gives
``dA/dt = q A / 2 - beta A^3`` with ``beta = 3 c3 omega^2 / 8``: for q > 0 a stable
cycle of amplitude ``A^2 = q / (2 beta)`` (the Hopf bifurcation is supercritical
since beta > 0); for q <= 0 every small motion decays to x_eq. The engine uses it
only where ``law.normal_form_valid`` (the polynomial law with alpha2 > 0, never a
subcritical point) and never for method gps, whose discrete map has a Hopf point of
its own. The
quadratic term alone is reversible (a centre), so it does not enter beta; it shifts
the cycle: mean ``c2 A^2 / 2``, second harmonic ``c2 A^2 / 6``, so the maximum of x is
at ``x_eq + A + (2/3) c2 A^2``. v < 0 is the mirror image.

The engine uses the normal form for two things only: to decide that a small motion
with q <= 0 decays (``nf_decays_to_rest``), and to place the motion on the cycle
(``nf_seed``, the maximum of x above); the cycle's observables are then measured on
one integrated return from there.

Second order: the amplitude of first-order averaging is low by the relative amount
``(7/18) G q/omega`` with ``G = c2^2 / (c3 omega)`` (the ratio of the squared quadratic
to the cubic coefficient; ``G = 3 alpha1/(m omega)`` at v*). The coefficient 7/18 was
measured, not derived: ``studies/normal_form.py`` finds it within 0.5 % for G from
0.15 to 9, with the remainder ~ ((1 + G) q/omega)^2, which ``nf_error`` bounds with
the factor ``NF_KAPPA``.
"""
import math

from .jit import kernel

from .law import nf_coefficients, normal_form_valid, x_eq
from .layout import (A_DT, ACC_LAST, O_RTOL, V, W_A, W_LX, W_NF_FLOOR, W_ON_NF,
                     W_RESET_SEEN, W_RTOL, W_SEEDED, W_TOL)
from .sections import FOLLOW, NF_JUMP, REST, RTOL_FLOOR, jump

NF_KAPPA = 10.0


@kernel(inline="always")
def _coefficients(p, lw):
    """(omega, q, c2, beta, sign of v, x_eq) of the normal form."""
    omega, q, c2, _c3, beta, sg, xe = nf_coefficients(p, lw)
    return omega, q, c2, beta, sg, xe


@kernel(inline="always")
def nf_amplitude(omega, q, c2, beta):
    """Cycle amplitude [cm] of the normal form, with its second-order correction."""
    A = math.sqrt(q / (2.0 * beta))
    c3 = 8.0 * beta / (3.0 * omega * omega)
    G = c2 * c2 / (c3 * omega)
    return A * (1.0 + 7.0 / 18.0 * G * q / omega)


@kernel(inline="always")
def nf_error(A, omega, q, c2, beta):
    """Bound of the normal form's amplitude error [cm] at amplitude A."""
    c3 = 8.0 * beta / (3.0 * omega * omega)
    G = c2 * c2 / (c3 * omega)
    return NF_KAPPA * A * ((1.0 + G) * abs(q) / omega) ** 2


@kernel
def nf_multiplier(p, lw, T):
    """Floquet multiplier of the normal form's cycle over a period T [s]: the averaged
    flow's slope at the cycle is d(dA/dt)/dA = q/2 - 3 beta A^2 = -q."""
    _omega, q, _c2, _beta, _sg, _xe = _coefficients(p, lw)
    return math.exp(-q * T)


@kernel
def _agrees(p, lw, a0, a1, T):
    """True when the return a0 -> a1 [cm] over T [s] (section values: x maxima, x
    minima for v < 0) is a small slip motion whose decrement the normal form
    predicts to 10 %."""
    omega, q, c2, c3, beta, sg, xe = nf_coefficients(p, lw)
    y0 = sg * (a0 - xe)
    y1 = sg * (a1 - xe)
    if not (y0 > 0.0 and y1 > 0.0):
        return False
    A0 = y0 - 2.0 / 3.0 * c2 * y0 * y0
    A1 = y1 - 2.0 / 3.0 * c2 * y1 * y1
    if A0 * omega >= 0.9 * abs(p[V]) or c2 * A0 > 0.05 or \
            c3 * omega * A0 * A0 > 0.05:
        return False
    u0 = 1.0 / (A0 * A0)
    if q != 0.0:
        e = math.exp(-q * T)
        u1 = u0 * e + 2.0 * beta * (e - 1.0) / (-q) if q < 0.0 else \
            u0 * e + 2.0 * beta * (1.0 - e) / q
    else:
        u1 = u0 + 2.0 * beta * T
    A1p = 1.0 / math.sqrt(u1)
    return abs(A1 - A1p) <= 0.1 * abs(A0 - A1p)


@kernel
def nf_decays_to_rest(p, lw, a0, a1, T):
    """True when q <= 0 and the normal form describes the return a0 -> a1 over T:
    it has no cycle below a0 then, and the motion decays to x_eq."""
    if not normal_form_valid(p, lw):
        return False
    _omega, q, _c2, _beta, sg, xe = _coefficients(p, lw)
    if q > 0.0 or not (0.0 < sg * (a1 - xe) < sg * (a0 - xe)):
        return False
    return _agrees(p, lw, a0, a1, T)


@kernel
def nf_seed(p, lw, a0, a1, T, tol_abs):
    """Section value [cm] of the normal-form cycle when q > 0, its cycle is accurate
    to tol_abs, and the motion (the return a0 -> a1 over T) is on it to 5 % or
    heading there as the normal form predicts; else NaN."""
    if not normal_form_valid(p, lw):
        return math.nan
    omega, q, c2, beta, sg, xe = _coefficients(p, lw)
    if not q > 0.0:
        return math.nan
    A = nf_amplitude(omega, q, c2, beta)
    if nf_error(A, omega, q, c2, beta) > tol_abs:
        return math.nan
    y_nf = A + 2.0 / 3.0 * c2 * A * A
    # the motion is on the cycle already (to 5 %), or heading there as the normal
    # form says it should
    if abs(sg * (a1 - xe) - y_nf) > 0.05 * A and not _agrees(p, lw, a0, a1, T):
        return math.nan
    return xe + sg * y_nf


@kernel
def nf_step(st, p, lw, w, acc):
    """The normal form's part at a section of a stop-free slip motion where it is
    valid: ``(action, a_nf)``.

    REST when q <= 0 and the normal form describes the last return (it then decays
    to x_eq: no waiting for an algebraic decay); NF_JUMP (done here) the first time
    a small motion that the normal form describes is heading for its cycle: Newton
    then starts on that cycle (accurate to 1 %) instead of following the slow
    approach of a weakly contracting cycle; else FOLLOW, with ``a_nf`` the section
    value of the normal form's cycle where it is accurate to tol L / 2 (NaN
    elsewhere), for ``sections.newton_decision``.
    """
    a0 = w[W_A + 2]
    a1 = w[W_A + 3]
    T = acc[ACC_LAST][A_DT]
    if nf_decays_to_rest(p, lw, a0, a1, T):
        return REST, math.nan
    if w[W_SEEDED] == 0.0:
        xe = x_eq(p, lw)
        a_nf = nf_seed(p, lw, a0, a1, T, 0.01 * abs(a1 - xe))
        if not math.isnan(a_nf) and (a_nf - a1) * (a1 - a0) > 0.0:
            w[W_SEEDED] = 1.0
            jump(st, p, w, acc, a_nf)
            w[W_RESET_SEEN] = 0.0        # a jump ends any period being measured
            w[W_ON_NF] = 0.0
            return NF_JUMP, a_nf
    return FOLLOW, nf_seed(p, lw, a0, a1, T, 0.5 * w[W_TOL] * w[W_LX])


@kernel
def nf_jump(st, p, lw, o, w, acc, a_nf):
    """Place the motion on the normal form's cycle (section value a_nf [cm]) to
    measure one return from there. That return is measured with velocity errors
    below tol times the cycle's own velocity (omega A), not the belt's: its maxima
    of x, where xdot crosses 0 with slope omega^2 A, are then timed to ~tol of the
    period (``W_NF_FLOOR`` where float64 cannot: status unresolved)."""
    jump(st, p, w, acc, a_nf)
    w[W_RESET_SEEN] = 0.0
    w[W_ON_NF] = 1.0
    omega, _q, _c2, _c3, _beta, _sg, xe = nf_coefficients(p, lw)
    small = omega * abs(a_nf - xe) / abs(p[V])
    tol = w[W_TOL]
    if small < 1.0:
        w[W_RTOL] = max(min(w[W_RTOL], tol * small), RTOL_FLOOR)
        o[O_RTOL] = w[W_RTOL]
    w[W_NF_FLOOR] = 1.0 if tol * small < RTOL_FLOOR else 0.0
