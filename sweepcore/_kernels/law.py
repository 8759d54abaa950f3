"""The friction law's interface: what the steppers, the driver, the events, the
attractor search, the cycle scan and the normal form know of the law.

The slider (Liu, eq. 3, with viscous damping c added)

    m x'' + c x' + k x + r_a = 0,      zdot = x' - v  (eqs. 1-2)

slides under a friction law ``r_a = F(s)`` (s = zdot, the relative speed) and sticks
(zdot = 0) while the force that holds it, ``-(k x + c v)``, lies between the law's
static limits. Which law is a *kind* of the law table (``laws/__init__.py``), and
its data is the value ``lw`` that every kernel carries next to the parameter row
``p``: a namedtuple whose class names the kind (per-point parameters stay in the
row; a measured table is an array in ``lw``, data, not code). Each function below
is resolved when it is compiled, by the class of ``lw``, to the kind module's
function of that name, or to the generic one written here from the kind's
primitives; nothing outside the law modules tests the kind or reads a law column.

A kind module defines its data class and at least

* ``force(lw, cf, zd, s)``: F(zd) [kN] while sliding with sign s (zd = 0: the limit
  ``F(0^s)`` of that side);
* ``derivatives(p, lw, zd)``: ``(F', F'', F''')`` at zd != 0;
* ``static_limits(p, lw)``: ``(r_pos, r_neg)`` [kN]: sticking holds while
  ``-r_pos <= k x + c v <= r_neg`` (``r_pos >= F(0+)``, ``r_neg >= -F(0-)``);
* ``slope_bound(p, lw, lo, hi)``: a lower bound of F' on [lo, hi] (the equilibrium
  certificate).

``speed_range(p, lw)``, the speeds between which the law's slope changes (the scan
for the Hopf speeds), is optional: its generic form is 1e-6 ... 1e6 cm/s.

It may define any other function of this module by name (closed forms, exact
roundings: the analytic family defines them all, which keeps the cubic map bit for
bit what it was); a kind that defines ``constants`` defines every function taking
``cf`` too (the generic ones read the generic ``constants``: ``(k, c, v, p, s)``).
"""
import math

import numpy as np

from .jit import kernel, resolved_by
from .layout import C, K, M, V

EPS = np.finfo(np.float64).eps


def _modules():
    from .laws import MODULES
    return MODULES


interface = resolved_by("lw", _modules, "law")
_DEFAULTS = interface.defaults


# ------------------------------------------------------- the kind's primitives
@interface(required=True)
def force(lw, cf, zd, s):
    """F(zd) [kN] while sliding with sign s, from ``cf = constants(p, lw, s)``."""


@interface(required=True)
def derivatives(p, lw, zd):
    """``(F'(zd), F''(zd), F'''(zd))`` [kN s/cm, kN s^2/cm^2, kN s^3/cm^3], zd != 0."""


@interface(required=True)
def static_limits(p, lw):
    """``(r_pos, r_neg)`` [kN]: a stuck slider holds while ``-r_pos <= k x + c v <=
    r_neg`` (the largest forces sticking holds on either side)."""


@interface(required=True)
def slope_bound(p, lw, lo, hi):
    """A lower bound of F' on [lo, hi] [kN s/cm]."""


@interface(inline=True)
def borrowed(lw):
    """The law data as views that carry no reference count (``jit.unowned``), for
    the duration of one entry kernel's call (kinds whose data holds arrays)."""
    return lw


@interface()
def speed_range(p, lw):
    """``(u_lo, u_hi)`` [cm/s]: relative speeds between which the law's slope
    changes; the Hopf speeds are sought there."""
    return 1e-6, 1e6


# ------------------------------------- the sliding field (per slide: constants)
@interface()
def constants(p, lw, s):
    """The law's constants for a slide with sign s, as locals of a stepper (taken once
    per step instead of loading p at every stage)."""
    return p[K], p[C], p[V], p, s


@interface()
def sliding_force(lw, cf, zd, s):
    """``F(zd) + c (zd + v)`` [kN]: friction and damping on the slider."""
    return force(lw, cf, zd, s) + cf[1] * (zd + cf[2])


@interface()
def friction_force(lw, cf, zd, s):
    """F(zd) [kN], the friction force alone (the friction work's integrand)."""
    return force(lw, cf, zd, s)


@interface()
def branch_derivatives(p, lw, zd, s):
    """``(F'(zd), F''(zd))`` of the branch a slide with sign s follows (as ``force``:
    at zd = 0, or a stage just past it, the slide's side; the law's two sides may
    differ in slope)."""
    f1, f2, _f3 = derivatives(p, lw, zd)
    return f1, f2


@interface()
def field_slope(lw, cf, zd):
    """``-(c + F'(zd))`` [kN s/cm]: m times the sliding field's d zdd / d zdot."""
    return -(cf[1] + branch_derivatives(cf[3], lw, zd, cf[4])[0])


@interface()
def integrand(lw, cf, zd):
    """The part of F'(zd) [kN s/cm] whose time integral (the steppers' quadrature
    ``q_l``, accumulator A_ILAW) ``log_jacobian`` needs beside ``int zdot^2 dt``."""
    return branch_derivatives(cf[3], lw, zd, cf[4])[0]


@interface()
def log_jacobian(p, lw, T, izd2, ilaw):
    """``int div f dt`` over a slide of duration T [s] (Liouville): with ``div f =
    d zdd/d zdot = -(c + F'(zdot))/m``, from ``izd2 = int zdot^2 dt`` and
    ``ilaw = int integrand dt``."""
    return (-p[C] * T - ilaw) / p[M]


# -------------------------------------------------------- per point, derived
@interface()
def edge_force(p, lw, s):
    """``F(0^s)`` [kN]: the sliding force's limit at zdot = 0 on the side s."""
    return force(lw, constants(p, lw, s), 0.0, s)


@interface()
def slope(p, lw, zd):
    """``F'(zd)`` for zd != 0 [kN s/cm]."""
    return derivatives(p, lw, zd)[0]


@interface()
def x_eq(p, lw):
    """Steady-sliding position [cm]: ``k x_eq = -F(-v)`` (eq. 43 for the paper's law);
    for v = 0 the middle of the band of rest positions."""
    v = p[V]
    if v == 0.0:
        r_pos, r_neg = static_limits(p, lw)
        return 0.5 * (r_neg - r_pos) / p[K]
    s = -1.0 if v > 0.0 else 1.0
    return -force(lw, constants(p, lw, s), -v, s) / p[K]


@interface()
def damping_at(p, lw, va):
    """Linearised damping ``c + F'(-v)`` [kN s/cm] of steady sliding at belt speed
    ``|v| = va`` (with the sign of p's v); its sign decides stability."""
    sg = -1.0 if p[V] < 0.0 else 1.0
    return p[C] + slope(p, lw, -sg * va)


@interface()
def q(p, lw):
    """Hopf quantity ``q = -(c + F'(-v))/m`` [1/s] (eq. 46 for the paper's law): the
    equilibrium's eigenvalues solve ``lambda^2 - q lambda + omega^2 = 0`` (45)."""
    return -damping_at(p, lw, abs(p[V])) / p[M]


@interface()
def third_derivative(p, lw, va):
    """``F'''(-v)`` [kN s^3/cm^3] at belt speed ``|v| = va``: its sign gives the Hopf
    point's criticality."""
    sg = -1.0 if p[V] < 0.0 else 1.0
    return derivatives(p, lw, -sg * va)[2]


@interface()
def hopf_speeds(p, lw):
    """Belt speeds ``u >= 0`` [cm/s] where the linearised damping ``c + F'(-u)``
    vanishes: ``(n, u1, u2)``, n roots found, the first two in increasing order (u2
    NaN unless n >= 2). With no root, u1 is inf where steady sliding is unstable at
    every speed and NaN where it is stable at every speed. Generic form: sign
    changes on a geometric ladder over ``speed_range``, refined by bisection."""
    u_lo, u_hi = speed_range(p, lw)
    n_pts = 4000
    ratio = (u_hi / u_lo) ** (1.0 / (n_pts - 1))
    u_prev = 0.0
    g_prev = damping_at(p, lw, u_lo)
    n = 0
    r1 = np.nan
    r2 = np.nan
    for i in range(n_pts):
        u = u_lo * ratio ** i
        g = damping_at(p, lw, u)
        if i > 0 and (g < 0.0) != (g_prev < 0.0):
            r = damping_root(p, lw, u_prev, u, g_prev < 0.0)
            if n == 0:
                r1 = r
            elif n == 1:
                r2 = r
            n += 1
        u_prev = u
        g_prev = g
    if n == 0:
        return 0, (np.inf if g_prev < 0.0 else np.nan), np.nan
    return n, r1, r2


@kernel
def damping_root(p, lw, lo, hi, rising):
    """Root of ``damping_at`` in [lo, hi] where it changes sign (rising: - to +)."""
    for _ in range(2200):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if (damping_at(p, lw, mid) < 0.0) == rising:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@interface()
def nf_coefficients(p, lw):
    """(omega, q, c2, c3, beta, sg, x_eq) of the Hopf normal form at this point.

    With ``y = x - x_eq``, ``w = ydot`` and F expanded about ``zdot = -v``:
    ``wdot = -omega^2 y + q w + c2 w^2 - c3 w^3 + ...`` with ``c2 = -F''(-v)/(2m)``,
    ``c3 = F'''(-v)/(6m)``; averaging gives ``dA/dt = q A/2 - beta A^3``,
    ``beta = 3 c3 omega^2 / 8`` (-l1 of ``first_lyapunov``). ``sg`` is the sign of v.
    """
    m = p[M]
    v = p[V]
    sg = 1.0 if v > 0.0 else -1.0
    omega = math.sqrt(p[K] / m)
    _f1, f2, f3 = derivatives(p, lw, -v)
    c2 = -sg * f2 / (2.0 * m)     # the mirror image for v < 0
    c3 = f3 / (6.0 * m)
    beta = 3.0 * c3 * omega * omega / 8.0
    return omega, q(p, lw), c2, c3, beta, sg, x_eq(p, lw)


@interface()
def normal_form_valid(p, lw):
    """True where the measured normal form (``normal_form.py``) describes the field;
    never at a subcritical point, where it would call a point equilibrium next to a
    large cycle. Generic form: nowhere (its second-order term was measured on the
    polynomial law only)."""
    return False


@kernel
def rest_radius(x, zd, p, lw):
    """``W = sqrt(2E/m)`` [cm/s] of the state (x [cm], zdot [cm/s]) about x_eq, with
    ``E = (m w^2 + k y^2)/2``, ``y = x - x_eq``, ``w = zdot + v``: the largest
    relative speed change on the sublevel set of E through the state. NaN where no
    equilibrium certificate applies: v = 0, steady sliding not decaying (q >= 0), or
    a set that reaches sticking (``W >= |v|``)."""
    v = p[V]
    if v == 0.0 or not q(p, lw) < 0.0:
        return np.nan
    y = x - x_eq(p, lw)
    yd = zd + v
    vel = math.sqrt(yd * yd + p[K] / p[M] * y * y)
    return vel if vel < abs(v) else np.nan


@interface()
def certified_rest(x, zd, p, lw):
    """True when (x, zdot) lies in a sublevel set of E that provably decays to x_eq.

    With ``y = x - x_eq``, ``w = ydot`` and ``E = (m w^2 + k y^2)/2``, the equation of
    motion gives ``dE/dt = -w^2 (c + S(w))`` with S the secant slope of F between
    ``-v`` and ``-v + w``. On the sublevel set through the state, ``|w| <= W =
    sqrt(2E/m)``; if ``W < |v|`` (no sticking) and ``c + S > 0`` for every such w, E
    decreases, the set is invariant and the motion converges to x_eq (LaSalle).
    Generic form: S is at least the least F' on ``[-v - W, -v + W]`` (mean value
    theorem), ``slope_bound``; a margin of 1e-12 keeps rounding from deciding."""
    vel = rest_radius(x, zd, p, lw)
    if not vel < abs(p[V]):             # NaN: no certificate applies
        return False
    v = p[V]
    smin = slope_bound(p, lw, -v - vel, -v + vel)
    return p[C] + smin > 1e-12 * (abs(p[C]) + abs(smin))


@interface()
def piecewise_linear(p, lw):
    """True when the sliding field is linear (closed-form arcs, method "exact")."""
    return False


@interface()
def arc_constants(s, p, lw):
    """Sliding centre [cm], growth rate sigma [1/s] and beta^2 [1/s^2] of a linear
    field (only where ``piecewise_linear``)."""
    return np.nan, np.nan, np.nan


@interface()
def conservative(p, lw):
    """True where the sliding field is conservative, ``m x'' + k x`` equal to a
    constant on each slide (the constant Coulomb law, or damping c that the law's
    slope cancels): a neutral family of circles, exact touches."""
    return False


@interface()
def anti_damped(p, lw):
    """True where the damping ``c + F'`` is negative at high sliding speed on both
    sides (an error-controlled integration that diverges follows the motion: growth
    without bound). Generic form: F' at the far end of ``speed_range``."""
    _u_lo, u_hi = speed_range(p, lw)
    return (p[C] + derivatives(p, lw, u_hi)[0] < 0.0
            and p[C] + derivatives(p, lw, -u_hi)[0] < 0.0)


@interface(inline=True)
def step_bound(x, zd, s, cf, lw, k, m, v, dz):
    """``(h, a)``: the largest sliding step [s] the law itself needs resolved at the
    state (x, zd) of a slide with sign s, with ``dz`` the velocity tolerance [cm/s],
    and the acceleration a [cm/s^2] it computed on the way (NaN: none).

    Generic form: where the slope makes the field unstable, at the rate ``lam =
    -(c + F')/m > 0``, a step is at most ``1/lam`` (the release from the breakaway
    point starts with zdd = 0, and a step spanning many e-folds of a steep law's
    instability is accepted by an error estimate that never saw them: Leine's law
    with delta = 300 put the stick-slip cycle 3e-7 L off at tol 1e-8), or where
    longer the time in which the force's drop over the slope's own width ``|F'/F''|``
    moves zdot by ``dz`` (a layer narrower than the tolerance is crossed at once).
    The analytic family's Stribeck layer has its own form (``laws/analytic.py``)."""
    f1, f2 = branch_derivatives(cf[3], lw, zd, s)
    lam = -(cf[1] + f1) / m
    if not lam > 0.0:
        return np.inf, np.nan
    drop = f1 * f1 / abs(f2) if f2 != 0.0 else np.inf
    return max(1.0 / lam, m * dz / drop), np.nan


# ------------------------------------------- the law in the field (generic)
@interface()
def zdd_of(x, zd, s, cf, lw, k, im):
    """Sliding acceleration [cm/s^2] (eq. 41) from ``cf``, with ``im = 1/m`` (no
    division on the chain of stages): the steppers' right-hand side. A kind may
    give its own form, arranged for the chain of dependent stages of a step (the
    longest path from ``zd`` to the result is what a step's time is made of)."""
    return (-k * x - sliding_force(lw, cf, zd, s)) * im


@kernel(inline="always")
def accel(x, zd, s, cf, lw, k, m):
    """Sliding acceleration [cm/s^2] (eq. 41) from ``cf``."""
    return (-k * x - sliding_force(lw, cf, zd, s)) / m


@kernel(inline="always")
def jerk(x, zd, s, cf, lw, k, m, v):
    """Time derivative of the sliding acceleration along the flow [cm/s^3]."""
    return (-k * (zd + v) + field_slope(lw, cf, zd) * accel(x, zd, s, cf, lw, k, m)) / m


@kernel(inline="always")
def zdd(x, zd, s, p, lw):
    """Relative (= absolute) acceleration while sliding [cm/s^2], eq. (41)."""
    return accel(x, zd, s, constants(p, lw, s), lw, p[K], p[M])


@kernel(inline="always")
def zddd(x, zd, s, p, lw, v):
    """Time derivative of zdd along the sliding flow [cm/s^3]."""
    return jerk(x, zd, s, constants(p, lw, s), lw, p[K], p[M], v)


@kernel(inline="always")
def friction(zd, s, p, lw):
    """Friction force r_a on the slider while sliding with sign s [kN]."""
    return friction_force(lw, constants(p, lw, s), zd, s)


@kernel(inline="always")
def stick_band(p, lw):
    """Positions [cm] between which a slider at belt speed sticks:
    ``-r_pos <= k x + c v <= r_neg``, i.e. ``x_lo <= x <= x_hi``."""
    r_pos, r_neg = static_limits(p, lw)
    return (-r_pos - p[C] * p[V]) / p[K], (r_neg - p[C] * p[V]) / p[K]


@kernel(inline="always")
def breakaway(p, lw):
    """Breakaway point x_s [cm]: where a stick ends; every slip after a stick starts
    there with zdot = 0 (0 for v = 0: no slip)."""
    x_lo, x_hi = stick_band(p, lw)
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
def length_scale(p, lw):
    """The point's length scale [cm]: the breakaway offset ``r/k`` (r the larger
    static limit) plus the constant-friction cycle ``|v|/omega``."""
    r_pos, r_neg = static_limits(p, lw)
    return max(r_pos, r_neg) / p[K] + abs(p[V]) / math.sqrt(p[K] / p[M])


@kernel(inline="always")
def log_saltation(p, lw, x, s_before, s_after):
    """log |zdd+ / zdd-| of a crossing of zdot = 0 at x (F jumps from ``F(0^s_before)``
    to ``F(0^s_after)``)."""
    kx = p[K] * x + p[C] * p[V]
    den = kx + edge_force(p, lw, s_before)
    num = kx + edge_force(p, lw, s_after)
    if den == 0.0 or num == 0.0:
        return 0.0
    return math.log(abs(num / den))


@kernel
def first_lyapunov(p, lw, va):
    """First Lyapunov coefficient ``l1`` [1/(s cm^2)] at belt speed va: first-order
    averaging gives ``dA/dt = q A/2 + l1 A^3`` with ``l1 = -omega^2 F'''(-v)/(16 m)``
    (the quadratic term does not enter); ``l1 < 0`` supercritical, ``> 0``
    subcritical."""
    return -p[K] / p[M] * third_derivative(p, lw, va) / (16.0 * p[M])


@kernel
def criticality(p, lw, n, u1):
    """Kind of the lowest Hopf point u1 (n roots): 0 none, 1 supercritical, 2
    subcritical, 3 degenerate, by the sign of F'''(-u1) (l1 can underflow to 0)."""
    if n == 0:
        return 0
    f3 = third_derivative(p, lw, u1)
    if f3 > 0.0:
        return 1
    if f3 < 0.0:
        return 2
    return 3
