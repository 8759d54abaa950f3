"""The friction-law family and everything derived from it: the one home of the law.

The slider (Liu, eq. 3, with viscous damping c added)

    m x'' + c x' + k x + r_a = 0,      zdot = x' - v  (eqs. 1-2)

slides under the law (s = zdot, the relative speed)

    F(s) = sgn(s) (r_k + (r_y - r_k) exp(-|s|/v_s)) - alpha1 s + alpha2 s^3

and sticks (zdot = 0) while the force that holds it, ``|k x + c v|``, is at most the
static bound ``r_y = F(0+)``. ``r_k = r_y`` is the paper's law, eq. (40) (then v_s
does not enter); ``alpha1 = alpha2 = 0`` with it the constant Coulomb law (5)-(10).
The exponential Stribeck term is the law of Stender, Hoffmann & Papangelo,
"The Basin Stability of Bi-Stable Friction-Excited Oscillators", Lubricants 8(12):105
(2020) and of the bSTAB friction case; Modelica's friction elements use the same
exponential form.

Everything the kernels and the Python side need from the law lives here: F and its
derivatives, the breakaway point and the stick band, x_eq, the linearised damping
and q, the Hopf speeds and their criticality (first Lyapunov coefficient), the normal
form's coefficients, the equilibrium certificate, the law's part of the return
map's slope (Liouville) and the closed-form arcs of the piecewise-linear laws. A
further law changes this module and its tests only.

Floating-point notes: with ``r_k = r_y`` the Stribeck term is skipped (a branch, no
``exp``), and every expression reduces to the one of the cubic law bit for bit
(``x - 0 = x``); the damping is written into the sliding force so that it adds no
operation to the chain of dependent stages of a Runge-Kutta step.
"""
import math

import numpy as np

from .jit import kernel
from .layout import A1, A2, C, K, M, RK, RY, V, VS

EPS = np.finfo(np.float64).eps


# ------------------------------------------------------------------ the law F(s)
@kernel(inline="always")
def level(zd, p):
    """``|F|`` of the Coulomb-Stribeck part at relative speed zd [kN]:
    ``r_y + d expm1(-|zd|/v_s)``, exactly r_y at zd = 0 and r_k at high speed."""
    d = p[RY] - p[RK]
    if d == 0.0:
        return p[RY]
    return p[RY] + d * math.expm1(-abs(zd) / p[VS])


@kernel(inline="always")
def stribeck_drop(p):
    """``r_y - r_k`` [kN], or None for the polynomial law (r_k = r_y).

    Steppers pass it on as an argument: numba then compiles them twice, and in the
    polynomial version the Stribeck branches (calls to ``exp``) are pruned before
    they are typed. A call on a cold branch still makes the compiler save every
    live register around it, which on dopri5's chain of stages cost ~10 % of a step.
    """
    d = p[RY] - p[RK]
    return None if d == 0.0 else d


@kernel(inline="always")
def coefficients(s, p):
    """The law's constants for a slide with sign s, as locals:
    ``(k, f0, f1, a1, a2, r_y, v_s, c)`` with ``f0 = r_y s + c v`` and
    ``f1 = c - alpha1`` (the damping folded in, so that it adds no operation to the
    chain of stages). Steppers and the driver take them once per step instead of
    loading p at every stage."""
    return (p[K], p[RY] * s + p[C] * p[V], p[C] - p[A1], p[A1], p[A2], p[RY], p[VS],
            p[C])


@kernel
def force_of(zd, s, cf, d):
    """``F(zd) + c (zd + v)`` [kN] from the constants ``cf`` of ``coefficients``;
    ``d`` is ``stribeck_drop`` (None: the polynomial law)."""
    k, f0, f1, a1, a2, ry, vs, c = cf
    if d is not None:
        f0 += d * math.expm1(-abs(zd) / vs) * s
    return f0 + f1 * zd + a2 * zd * zd * zd


@kernel
def friction_of(zd, s, cf, d):
    """The friction force F(zd) [kN] alone (no damping) from ``cf``: eq. (40) for
    r_k = r_y (``d`` None)."""
    k, f0, f1, a1, a2, ry, vs, c = cf
    lev = ry
    if d is not None:
        lev = ry + d * math.expm1(-abs(zd) / vs)
    return lev * s - a1 * zd + a2 * zd * zd * zd


@kernel(inline="always")
def accel(x, zd, s, cf, d, m):
    """Sliding acceleration [cm/s^2] (eq. 41) from ``cf`` and ``d``."""
    return (-cf[0] * x - force_of(zd, s, cf, d)) / m


@kernel(inline="always")
def jerk(x, zd, s, cf, d, m, v):
    """Time derivative of the sliding acceleration along the flow [cm/s^3]."""
    k, f0, f1, a1, a2, ry, vs, c = cf
    g = a1 - 3.0 * a2 * zd * zd - c
    if d is not None:
        g += d / vs * math.exp(-abs(zd) / vs)
    return (-k * (zd + v) + g * accel(x, zd, s, cf, d, m)) / m


@kernel(inline="always")
def zdd_of(x, zd, s, cf, d, im):
    """Sliding acceleration [cm/s^2] from ``cf``, with ``im = 1/m`` (no division on
    the chain of stages)."""
    return (-cf[0] * x - force_of(zd, s, cf, d)) * im


@kernel(inline="always")
def friction(zd, s, p):
    """Friction force r_a on the slider while sliding with sign s [kN] (eq. 40 for
    r_k = r_y)."""
    return friction_of(zd, s, coefficients(s, p), stribeck_drop(p))


@kernel(inline="always")
def sliding_force(zd, s, p):
    """Friction plus damping on the slider while sliding, ``F(zd) + c (zd + v)`` [kN]."""
    return force_of(zd, s, coefficients(s, p), stribeck_drop(p))


@kernel(inline="always")
def slope(zd, p):
    """``F'(zd)`` for zd != 0 [kN s/cm]."""
    f1 = -p[A1] + 3.0 * p[A2] * zd * zd
    d = p[RY] - p[RK]
    if d != 0.0:
        f1 -= d / p[VS] * math.exp(-abs(zd) / p[VS])
    return f1


# ------------------------------------------------------------ the sliding field
@kernel(inline="always")
def zdd(x, zd, s, p):
    """Relative (= absolute) acceleration while sliding [cm/s^2], eq. (41)."""
    return accel(x, zd, s, coefficients(s, p), stribeck_drop(p), p[M])


@kernel(inline="always")
def zddd(x, zd, s, p, v):
    """Time derivative of zdd along the sliding flow [cm/s^3]."""
    return jerk(x, zd, s, coefficients(s, p), stribeck_drop(p), p[M], v)


# ------------------------------------------------------ sticking and breakaway
@kernel(inline="always")
def stick_band(p):
    """Positions [cm] between which a slider at belt speed sticks:
    ``|k x + c v| <= r_y``, i.e. ``x_lo <= x <= x_hi``."""
    return (-p[RY] - p[C] * p[V]) / p[K], (p[RY] - p[C] * p[V]) / p[K]


@kernel(inline="always")
def breakaway(p):
    """Breakaway point x_s [cm]: where a stick ends (``k x + c v = sgn(v) r_y``);
    every slip after a stick starts there with zdot = 0 (0 for v = 0: no slip)."""
    x_lo, x_hi = stick_band(p)
    if p[V] > 0.0:
        return x_hi
    if p[V] < 0.0:
        return x_lo
    return 0.0


@kernel(inline="always")
def stick_force(x, p):
    """Friction force while stuck [kN]: ``r_a = -(k x + c v)`` (x' = v)."""
    return -(p[K] * x + p[C] * p[V])


@kernel(inline="always")
def law_integrand(zd, p):
    """The law's non-polynomial slope term, ``exp(-|zd|/v_s)`` (1); its time integral
    (accumulator A_ILAW) enters the return map's slope (``log_jacobian``)."""
    return math.exp(-abs(zd) / p[VS])


@kernel(inline="always")
def log_jacobian(p, T, izd2, ilaw):
    """``int div f dt`` over a slide of duration T [s] (Liouville): with
    ``div f = d zdd/d zdot = -(c + F'(zdot))/m``, from ``izd2 = int zdot^2 dt`` and
    ``ilaw = int law_integrand dt``."""
    lj = p[A1] * T - 3.0 * p[A2] * izd2 - p[C] * T
    d = p[RY] - p[RK]
    if d != 0.0:
        lj += d / p[VS] * ilaw
    return lj / p[M]


@kernel(inline="always")
def log_saltation(p, x, s_before, s_after):
    """log |zdd+ / zdd-| of a crossing of zdot = 0 at x (F(0+-) = +-r_y there)."""
    kx = p[K] * x + p[C] * p[V]
    den = kx + p[RY] * s_before
    num = kx + p[RY] * s_after
    if den == 0.0 or num == 0.0:
        return 0.0
    return math.log(abs(num / den))


# ---------------------------------------------------------- the equilibrium
@kernel(inline="always")
def x_eq(p):
    """Steady-sliding position [cm]: ``k x_eq = -F(-v)`` (eq. 43 for r_k = r_y),
    mirrored for v < 0; 0 for v = 0 (the middle of the band of rest positions)."""
    v = p[V]
    if v == 0.0:
        return 0.0
    va = abs(v)
    sg = 1.0 if v > 0.0 else -1.0
    return sg * (level(va, p) - p[A1] * va + p[A2] * va ** 3) / p[K]


@kernel(inline="always")
def damping_at(p, va):
    """Linearised damping ``c + F'(-|v|)`` [kN s/cm] of steady sliding at belt speed
    ``va = |v|``; its sign decides stability."""
    g = p[C] - p[A1] + 3.0 * p[A2] * (va * va)
    d = p[RY] - p[RK]
    if d != 0.0:
        g -= d / p[VS] * math.exp(-va / p[VS])
    return g


@kernel(inline="always")
def q(p):
    """Hopf quantity ``q = -(c + F'(-|v|))/m`` [1/s] (eq. 46 for the paper's law):
    the equilibrium's eigenvalues solve ``lambda^2 - q lambda + omega^2 = 0`` (45)."""
    va = abs(p[V])
    qq = p[A1] - 3.0 * p[A2] * va * va - p[C]
    d = p[RY] - p[RK]
    if d != 0.0:
        qq += d / p[VS] * math.exp(-va / p[VS])
    return qq / p[M]


@kernel(inline="always")
def third_derivative(p, va):
    """``F'''(-va)`` [kN s^3/cm^3]: its sign gives the Hopf point's criticality."""
    f3 = 6.0 * p[A2]
    d = p[RY] - p[RK]
    if d != 0.0:
        f3 -= d / p[VS] ** 3 * math.exp(-va / p[VS])
    return f3


@kernel
def first_lyapunov(p, va):
    """First Lyapunov coefficient ``l1`` [1/(s cm^2)] at belt speed va: first-order
    averaging gives ``dA/dt = q A/2 + l1 A^3`` with ``l1 = -omega^2 F'''(-va)/(16 m)``
    (the quadratic term does not enter); ``l1 < 0`` supercritical, ``> 0``
    subcritical."""
    return -p[K] / p[M] * third_derivative(p, va) / (16.0 * p[M])


@kernel
def criticality(p, n, u1):
    """Kind of the lowest Hopf point u1 (n roots): 0 none, 1 supercritical, 2
    subcritical, 3 degenerate, by the sign of F'''(-u1): l1 can underflow to 0."""
    if n == 0:
        return 0
    f3 = third_derivative(p, u1)
    if f3 > 0.0:
        return 1
    if f3 < 0.0:
        return 2
    return 3


@kernel
def _bisect_root(p, lo, hi, rising):
    """Root of ``damping_at`` in [lo, hi] where it changes sign (rising: - to +)."""
    for _ in range(2200):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if (damping_at(p, mid) < 0.0) == rising:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@kernel
def _upper_bracket(p):
    """A speed where ``damping_at`` is positive (it grows like 3 alpha2 u^2 > 0)."""
    u = max(p[VS], 1.0)
    while not damping_at(p, u) > 0.0 and u < 1e300:
        u *= 2.0
    return u


@kernel
def _argmin(p, hi):
    """Minimiser in [0, hi] of the convex ``damping_at`` (golden section)."""
    lo = 0.0
    r = 0.5 * (math.sqrt(5.0) - 1.0)
    a = hi - r * hi
    b = r * hi
    fa = damping_at(p, a)
    fb = damping_at(p, b)
    for _ in range(2200):
        if hi - lo <= 4.0 * EPS * hi:
            break
        if fa < fb:
            hi, b, fb = b, a, fa
            a = hi - r * (hi - lo)
            fa = damping_at(p, a)
        else:
            lo, a, fa = a, b, fb
            b = lo + r * (hi - lo)
            fb = damping_at(p, b)
    return 0.5 * (lo + hi)


@kernel
def hopf_speeds(p):
    """Belt speeds ``u >= 0`` [cm/s] where the linearised damping ``c + F'(-u)``
    vanishes: ``(n, u1, u2)``, n in {0, 1, 2} roots in increasing order (u2 NaN
    unless n = 2).

    ``g(u) = c + F'(-u) = c - alpha1 + 3 alpha2 u^2 - (d/v_s) exp(-u/v_s)``
    (d = r_y - r_k) is increasing for d >= 0 and convex for d < 0, so it has at most
    two roots. Closed forms: the polynomial law, ``u = sqrt((alpha1 - c)/(3 alpha2))``
    (v* below eq. 51 for c = 0); no cubic term, ``u = v_s ln(d / (v_s (c - alpha1)))``
    (ln(10)/2 for the bSTAB case). With no root, u1 is inf where steady sliding is
    unstable at every speed and NaN where it is stable at every speed.
    """
    d = p[RY] - p[RK]
    a2 = p[A2]
    lin = p[C] - p[A1]
    if d == 0.0:
        if a2 == 0.0:
            return 0, (np.inf if lin < 0.0 else np.nan), np.nan
        if lin > 0.0:
            return 0, np.nan, np.nan
        return 1, math.sqrt(-lin / (3.0 * a2)), np.nan
    g0 = damping_at(p, 0.0)
    if a2 == 0.0:
        # g = lin - (d/v_s) exp(-u/v_s): monotone from g0 to lin
        if g0 == 0.0:
            return 1, 0.0, np.nan
        if (g0 < 0.0) == (lin < 0.0) or lin == 0.0:
            return 0, (np.inf if g0 < 0.0 else np.nan), np.nan
        # logarithms: d / (v_s lin) overflows for c - alpha1 = 5e-324 (root 372.2)
        return 1, p[VS] * (math.log(abs(d)) - math.log(p[VS]) - math.log(abs(lin))), \
            np.nan
    hi = _upper_bracket(p)
    if d > 0.0:
        if g0 >= 0.0:
            return (1, 0.0, np.nan) if g0 == 0.0 else (0, np.nan, np.nan)
        return 1, _bisect_root(p, 0.0, hi, True), np.nan
    umin = _argmin(p, hi)
    if damping_at(p, umin) >= 0.0:
        return 0, np.nan, np.nan
    if g0 <= 0.0:
        return 1, _bisect_root(p, umin, hi, True), np.nan
    return 2, _bisect_root(p, 0.0, umin, False), _bisect_root(p, umin, hi, True)


# --------------------------------------------------------------- normal form
@kernel(inline="always")
def nf_coefficients(p):
    """(omega, q, c2, c3, beta, sg, x_eq) of the Hopf normal form at this point.

    With ``y = x - x_eq``, ``w = ydot`` and F expanded about ``zdot = -|v|``:
    ``wdot = -omega^2 y + q w + c2 w^2 - c3 w^3 + ...`` with ``c2 = -F''(-v)/(2m)``,
    ``c3 = F'''(-v)/(6m)``; averaging gives ``dA/dt = q A/2 - beta A^3``,
    ``beta = 3 c3 omega^2 / 8`` (-l1 of ``first_lyapunov``). ``sg`` is the sign of v.
    """
    m = p[M]
    v = p[V]
    va = abs(v)
    omega = math.sqrt(p[K] / m)
    qq = q(p)
    s2 = 3.0 * p[A2] * va
    s3 = p[A2]
    d = p[RY] - p[RK]
    if d != 0.0:
        e = d * math.exp(-va / p[VS])
        s2 += e / (2.0 * p[VS] * p[VS])
        s3 -= e / (6.0 * p[VS] ** 3)
    c2 = s2 / m
    c3 = s3 / m
    beta = 3.0 * s3 / m * omega * omega / 8.0
    sg = 1.0 if v > 0.0 else -1.0
    return omega, qq, c2, c3, beta, sg, x_eq(p)


@kernel(inline="always")
def normal_form_valid(p):
    """True where the measured normal form (``normal_form.py``) describes the field:
    the polynomial law (its second-order term was measured on it; a Stribeck term adds
    quintic and higher terms of the same order) with a supercritical Hopf point
    (alpha2 > 0). Never at a subcritical point, where it would call a point
    equilibrium next to a large cycle."""
    return p[RY] - p[RK] == 0.0 and p[A2] > 0.0 and p[V] != 0.0


# ------------------------------------------------------ equilibrium certificate
@kernel
def certified_rest(x, zd, p):
    """True when (x, zdot) lies in a sublevel set of E that provably decays to x_eq.

    With ``y = x - x_eq``, ``w = ydot`` and ``E = (m w^2 + k y^2)/2``, the equation of
    motion gives ``dE/dt = -w^2 (c + S(w))`` with S the secant slope of F between
    ``-|v|`` and ``-|v| + w``. On the sublevel set through the state, ``|w| <= W =
    sqrt(2E/m)``; if ``W < |v|`` (no sticking) and ``c + S > 0`` for every such w, E
    decreases, the set is invariant and the motion converges to x_eq (LaSalle).
    The polynomial part of S is exact, ``-alpha1 + alpha2 (3 v^2 - 3 v w + w^2)``,
    least at ``w = sgn(v) W`` for alpha2 >= 0 (its minimum in w lies at 1.5 v,
    outside ``|w| <= W``; Params and Grid refuse alpha2 < 0); the Stribeck term's
    slope is monotone, least at one end of ``|s + |v|| <= W``. A margin of 1e-12 of
    the terms summed keeps rounding from deciding (the Stribeck slope at the set's
    end, ``smin``, with its exponent's rounding ``eps |v|/v_s``; not ``d/v_s``).
    """
    v = p[V]
    if v == 0.0:
        return False
    if not q(p) < 0.0:
        return False
    m = p[M]
    y = x - x_eq(p)
    yd = zd + v
    vel = math.sqrt(yd * yd + p[K] / m * y * y)     # sqrt(2E/m)
    va = abs(v)
    if not vel < va:
        return False
    poly = p[A2] * (3.0 * va * (va - vel) + vel * vel)
    size = abs(p[C]) + abs(p[A1]) + 3.0 * p[A2] * va * va
    d = p[RY] - p[RK]
    smin = 0.0
    if d != 0.0:
        s_end = -va + vel if d > 0.0 else -va - vel  # where the Stribeck slope is least
        smin = -d / p[VS] * math.exp(s_end / p[VS])
        size += abs(smin) * (1.0 + va / p[VS])
    return p[C] - p[A1] + poly + smin > 1e-12 * size


@kernel(inline="always")
def conservative(p):
    """A conservative sliding field, ``m x'' + k x = -(r_y s + c v)``: no cubic or
    Stribeck term, c = alpha1 (the constant law: 0). Circles; exact touches."""
    return p[A2] == 0.0 and p[RY] - p[RK] == 0.0 and p[C] == p[A1]


@kernel(inline="always")
def anti_damped(p):
    """Damping ``c + F'(s)`` negative at high sliding speed (no cubic term, alpha1 >
    c): an error-controlled integration that diverges follows the motion."""
    return p[A2] == 0.0 and p[C] - p[A1] < 0.0


# ------------------------------------------------- closed forms (linear laws)
@kernel(inline="always")
def piecewise_linear(p):
    """True when the sliding field is linear (closed-form arcs, method "exact"):
    no cubic term and no Stribeck term."""
    return p[A2] == 0.0 and p[RY] - p[RK] == 0.0


@kernel(inline="always")
def arc_constants(s, p):
    """Sliding centre [cm], growth rate sigma [1/s] and beta^2 [1/s^2] of the linear
    field: ``m x'' - (alpha1 - c) x' + k x = -r_y s - alpha1 v``."""
    cen = (-p[RY] * s - p[A1] * p[V]) / p[K]
    sig = (p[A1] - p[C]) / (2.0 * p[M])
    b2 = p[K] / p[M] - sig * sig
    return cen, sig, b2


# ---------------------------------------------------------- Python's view
# columns of the derived-quantity rows (derived_rows)
D_OMEGA, D_Q, D_XEQ, D_VSTAR, D_VSTAR2, D_NHOPF, D_LYAP, D_XS, D_CRIT = range(9)
ND = 9


@kernel
def derived_value(p, which):
    """Analytic quantity ``which`` (a column D_*) of one parameter row."""
    if which == D_OMEGA:
        return math.sqrt(p[K] / p[M])
    if which == D_Q:
        return q(p)
    if which == D_XEQ:
        return x_eq(p)
    if which == D_XS:
        return breakaway(p)
    n, u1, u2 = hopf_speeds(p)
    if which == D_VSTAR:
        return u1
    if which == D_VSTAR2:
        return u2
    if which == D_NHOPF:
        return float(n)
    if which == D_CRIT:
        return float(criticality(p, n, u1))
    return first_lyapunov(p, u1) if n > 0 else np.nan


@kernel
def derived_rows(P, which, out):
    """``derived_value(P[i], which)`` for every row of P into ``out[i]``."""
    for i in range(P.shape[0]):
        out[i] = derived_value(P[i], which)
