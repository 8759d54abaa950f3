"""The analytic friction family: constant Coulomb, Liu's eq. (40), exponential Stribeck.

    F(s) = sgn(s) (r_k + (r_y - r_k) exp(-|s|/v_s)) - alpha1 s + alpha2 s^3

(s = zdot, the relative speed), with viscous damping c on the slider
(``m x'' + c x' + k x + F = 0``). Its parameters are columns of the kernel row
(``RY, A1, A2, RK, VS`` of ``layout.py``): they vary from point to point of a grid,
and only this module reads them. ``r_k = r_y`` is the paper's law, eq. (40) (v_s
does not enter); ``alpha1 = alpha2 = 0`` with it the constant Coulomb law (5)-(10).
``v_s = 0`` is the family's limit v_s -> 0+: sliding at ``sgn(s) r_k - alpha1 s +
alpha2 s^3`` (``F(0^s) = r_k s``, the sliding limits), sticking up to the static
bound r_y (Coulomb friction with static above kinetic: Shaw, J. Sound Vib. 108,
1986). Its sliding field is the polynomial law's with the level r_k, so such rows
run the ``Polynomial`` kind: no exponential, no division by v_s; the jump from r_y
to r_k is the stick band's (``static_limits``) against the sliding limits
(``edge_force``).
The exponential Stribeck term is the law of Stender, Hoffmann & Papangelo, "The
Basin Stability of Bi-Stable Friction-Excited Oscillators", Lubricants 8(12):105
(2020) and of the bSTAB friction case; Modelica's friction elements use the same
exponential form.

Two kinds of the law table (``laws/__init__.py``) share this module: ``Polynomial``
(r_k = r_y or v_s = 0 at every point of a call: the Stribeck branches, calls to
``exp``, are pruned before they are typed, since the drop ``d`` is None there) and
``Stribeck``.
The hot functions take the drop as an argument (``d``: None or ``r_y - r_k``) so
that numba compiles the polynomial version without the branch; a call on a cold
branch still makes the compiler save every live register around it, which on
dopri5's chain of stages cost ~10 % of a step.

Floating-point notes: every expression reduces to the one of the cubic law bit for
bit when r_k = r_y; the damping is written into the sliding force (``f0 = r_0 s +
c v``, ``f1 = c - alpha1``) so that it adds no operation to the chain of dependent
stages of a Runge-Kutta step.
"""
import math
from collections import namedtuple

import numpy as np
from numba import types
from numba.extending import overload

from ..jit import OVERLOAD_OPTIONS, kernel, runtime
from ..law import damping_root, rest_radius
from ..layout import A1, A2, C, K, M, RK, RY, V, VS

EPS = np.finfo(np.float64).eps

# the kinds' kernel data: no data beyond the row's columns
Polynomial = namedtuple("Polynomial", ())
Stribeck = namedtuple("Stribeck", ())


def drop(lw, p):
    """The Stribeck drop ``r_y - r_k`` [kN] of the row, or None for ``Polynomial``."""


@overload(drop, inline="always", jit_options=OVERLOAD_OPTIONS)
def _drop(lw, p):
    if isinstance(lw, types.NamedTuple) and lw.instance_class is Polynomial:
        return lambda lw, p: None
    return lambda lw, p: p[RY] - p[RK]


@kernel(inline="always")
def stribeck_drop(p):
    """The row's Stribeck drop ``r_y - r_k`` [kN] where it has a Stribeck term, else 0
    (r_k = r_y, whose v_s is NaN, or v_s = 0: the jump, no slope)."""
    if p[VS] == 0.0:
        return 0.0
    return p[RY] - p[RK]


@kernel(inline="always")
def zero_level(p):
    """``|F(0+)|`` of the form the sliding force is written in [kN]: r_y with a
    Stribeck term (``r_y + d expm1(...)``), else the sliding level r_k (= r_y for
    the paper's law, bit for bit; below r_y for v_s = 0)."""
    if p[VS] > 0.0:
        return p[RY]
    return p[RK]


# ------------------------------------------------------------------ the law F(s)
@kernel(inline="always")
def level(zd, p):
    """``|F|`` of the Coulomb-Stribeck part at relative speed zd != 0 [kN]:
    ``r_y + d expm1(-|zd|/v_s)``, r_y at zd -> 0 and r_k at high speed; r_k for
    v_s = 0."""
    d = stribeck_drop(p)
    if d == 0.0:
        return p[RK]
    return p[RY] + d * math.expm1(-abs(zd) / p[VS])


@kernel(inline="always")
def constants(p, lw, s):
    """``(k, f0, f1, a1, a2, r_0, v_s, c, d, g0, gx, g1, g3)`` for a slide with sign
    s, with ``f0 = r_0 s + c v`` (r_0: ``zero_level``) and ``f1 = c - alpha1`` (the
    damping folded in),
    the drop d (None for ``Polynomial``) and the acceleration's coefficients
    ``zdd = g0 + gx x + g1 zd + g3 zd^3`` of the polynomial law (``zdd_of``)."""
    r0 = zero_level(p)
    f0 = r0 * s + p[C] * p[V]
    f1 = p[C] - p[A1]
    im = 1.0 / p[M]
    return (p[K], f0, f1, p[A1], p[A2], r0, p[VS], p[C], drop(lw, p),
            -f0 * im, -p[K] * im, -f1 * im, -p[A2] * im)


@kernel
def _force(zd, s, cf, d):
    """``F(zd) + c (zd + v)`` [kN] from the constants ``cf``; ``d`` the drop."""
    k, f0, f1, a1, a2, ry, vs, c, _d, _g0, _gx, _g1, _g3 = cf
    if d is not None:
        f0 += d * math.expm1(-abs(zd) / vs) * s
    return f0 + f1 * zd + a2 * zd * zd * zd


@kernel
def _friction(zd, s, cf, d):
    """The friction force F(zd) [kN] alone (no damping): eq. (40) for d None."""
    k, f0, f1, a1, a2, ry, vs, c, _d, _g0, _gx, _g1, _g3 = cf
    lev = ry
    if d is not None:
        lev = ry + d * math.expm1(-abs(zd) / vs)
    return lev * s - a1 * zd + a2 * zd * zd * zd


@kernel(inline="always")
def force(lw, cf, zd, s):
    return _friction(zd, s, cf, cf[8])


@kernel(inline="always")
def derivatives(p, lw, zd):
    """``(F', F'', F''')`` at zd != 0 (the Stribeck term's sign follows zd)."""
    f1 = slope(p, lw, zd)
    f2 = 6.0 * p[A2] * zd
    f3 = 6.0 * p[A2]
    d = stribeck_drop(p)
    if d != 0.0:
        e = d * math.exp(-abs(zd) / p[VS])
        sg = 1.0 if zd > 0.0 else -1.0
        f2 += sg * e / (p[VS] * p[VS])
        f3 -= e / p[VS] ** 3
    return f1, f2, f3


@kernel
def slope_bound(p, lw, lo, hi):
    """The least F' on [lo, hi]: the polynomial part's ``-alpha1 + 3 alpha2 s^2``
    (alpha2 >= 0) is least where |s| is, the Stribeck part's ``-(d/v_s)
    exp(-|s|/v_s)`` where |s| is least for d > 0, greatest for d < 0."""
    near = 0.0 if lo <= 0.0 <= hi else min(abs(lo), abs(hi))
    far = max(abs(lo), abs(hi))
    least = -p[A1] + 3.0 * p[A2] * near * near
    d = stribeck_drop(p)
    if d != 0.0:
        least -= d / p[VS] * math.exp(-(near if d > 0.0 else far) / p[VS])
    return least


@kernel(inline="always")
def sliding_force(lw, cf, zd, s):
    return _force(zd, s, cf, cf[8])


@kernel(inline="always")
def zdd_of(x, zd, s, cf, lw, k, im):
    return _zdd(x, zd, s, cf, k, im, cf[8])


@kernel(inline="always")
def _zdd(x, zd, s, cf, k, im, d):
    """The sliding acceleration [cm/s^2]. Polynomial law: ``(g0 + gx x + g1 zd) +
    (g3 zd) (zd zd)``, whose longest path from zd is three operations (the generic
    ``(-k x - F(zd)) / m`` has six): a step's stages wait on it one after another.
    It is v -> -v symmetric bit for bit (g0 changes sign, nothing else)."""
    if d is not None:
        return (-k * x - _force(zd, s, cf, d)) * im
    return (cf[9] + cf[10] * x + cf[11] * zd) + (cf[12] * zd) * (zd * zd)


@kernel(inline="always")
def friction_force(lw, cf, zd, s):
    return _friction(zd, s, cf, cf[8])


@kernel
def _slope_term(zd, cf, d):
    g = cf[3] - 3.0 * cf[4] * zd * zd - cf[7]
    if d is not None:
        g += d / cf[6] * math.exp(-abs(zd) / cf[6])
    return g


@kernel(inline="always")
def field_slope(lw, cf, zd):
    return _slope_term(zd, cf, cf[8])


@kernel(inline="always")
def _integrand(zd, cf, d):
    if d is None:
        return 0.0
    return math.exp(-abs(zd) / cf[6])


@kernel(inline="always")
def integrand(lw, cf, zd):
    """``exp(-|zd|/v_s)``: the slope's non-polynomial term (0 for the polynomial law,
    whose slope the driver's quadrature of zdot^2 covers)."""
    return _integrand(zd, cf, cf[8])


@kernel(inline="always")
def slope(p, lw, zd):
    f1 = -p[A1] + 3.0 * p[A2] * zd * zd
    d = stribeck_drop(p)
    if d != 0.0:
        f1 -= d / p[VS] * math.exp(-abs(zd) / p[VS])
    return f1


@kernel(inline="always")
def static_limits(p, lw):
    return p[RY], p[RY]


@kernel(inline="always")
def edge_force(p, lw, s):
    """``F(0^s)`` [kN]: r_y s, or r_k s for v_s = 0 (below the static bound r_y)."""
    return zero_level(p) * s


@kernel(inline="always")
def log_jacobian(p, lw, T, izd2, ilaw):
    lj = p[A1] * T - 3.0 * p[A2] * izd2 - p[C] * T
    d = stribeck_drop(p)
    if d != 0.0:
        lj += d / p[VS] * ilaw
    return lj / p[M]


@kernel(inline="always")
def conservative(p, lw):
    """No cubic or Stribeck term and c = alpha1 (the constant law: 0): ``m x'' + k x
    = -(r_k s + c v)`` (v_s = 0 too: the jump at zero speed is no term of a slide)."""
    return p[A2] == 0.0 and stribeck_drop(p) == 0.0 and p[C] == p[A1]


@kernel(inline="always")
def anti_damped(p, lw):
    """No cubic term and alpha1 > c: at high speed ``c + F' -> c - alpha1 < 0``."""
    return p[A2] == 0.0 and p[C] - p[A1] < 0.0


# ---------------------------------------------------------- the equilibrium
@kernel(inline="always")
def x_eq(p, lw):
    v = p[V]
    if v == 0.0:
        return 0.0
    va = abs(v)
    sg = 1.0 if v > 0.0 else -1.0
    return sg * (level(va, p) - p[A1] * va + p[A2] * va ** 3) / p[K]


@kernel(inline="always")
def damping_at(p, lw, va):
    g = p[C] - p[A1] + 3.0 * p[A2] * (va * va)
    d = stribeck_drop(p)
    if d != 0.0:
        g -= d / p[VS] * math.exp(-va / p[VS])
    return g


@kernel(inline="always")
def q(p, lw):
    va = abs(p[V])
    qq = p[A1] - 3.0 * p[A2] * va * va - p[C]
    d = stribeck_drop(p)
    if d != 0.0:
        qq += d / p[VS] * math.exp(-va / p[VS])
    return qq / p[M]


@kernel(inline="always")
def third_derivative(p, lw, va):
    f3 = 6.0 * p[A2]
    d = stribeck_drop(p)
    if d != 0.0:
        f3 -= d / p[VS] ** 3 * math.exp(-va / p[VS])
    return f3


@kernel
def _upper_bracket(p):
    """A speed where ``damping_at`` is positive (it grows like 3 alpha2 u^2 > 0)."""
    u = max(p[VS], 1.0)
    while not damping_at(p, None, u) > 0.0 and u < 1e300:
        u *= 2.0
    return u


@kernel
def _argmin(p, hi):
    """Minimiser in [0, hi] of the convex ``damping_at`` (golden section)."""
    lo = 0.0
    r = 0.5 * (math.sqrt(5.0) - 1.0)
    a = hi - r * hi
    b = r * hi
    fa = damping_at(p, None, a)
    fb = damping_at(p, None, b)
    for _ in range(2200):
        if hi - lo <= 4.0 * EPS * hi:
            break
        if fa < fb:
            hi, b, fb = b, a, fa
            a = hi - r * (hi - lo)
            fa = damping_at(p, None, a)
        else:
            lo, a, fa = a, b, fb
            b = lo + r * (hi - lo)
            fb = damping_at(p, None, b)
    return 0.5 * (lo + hi)


@kernel
def hopf_speeds(p, lw):
    """``g(u) = c + F'(-u) = c - alpha1 + 3 alpha2 u^2 - (d/v_s) exp(-u/v_s)``
    (d = r_y - r_k) is increasing for d >= 0 and convex for d < 0, so it has at most
    two roots. Closed forms: the polynomial law, ``u = sqrt((alpha1 - c)/(3
    alpha2))`` (v* below eq. 51 for c = 0); no cubic term, ``u = v_s ln(d / (v_s
    (c - alpha1)))`` (ln(10)/2 for the bSTAB case)."""
    d = stribeck_drop(p)
    a2 = p[A2]
    lin = p[C] - p[A1]
    if d == 0.0:
        if a2 == 0.0:
            return 0, (np.inf if lin < 0.0 else np.nan), np.nan
        if lin > 0.0:
            return 0, np.nan, np.nan
        return 1, math.sqrt(-lin / (3.0 * a2)), np.nan
    g0 = damping_at(p, lw, 0.0)
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
        return 1, damping_root(p, lw, 0.0, hi, runtime(True)), np.nan
    umin = _argmin(p, hi)
    if damping_at(p, lw, umin) >= 0.0:
        return 0, np.nan, np.nan
    if g0 <= 0.0:
        return 1, damping_root(p, lw, umin, hi, runtime(True)), np.nan
    return 2, damping_root(p, lw, 0.0, umin, runtime(False)), \
        damping_root(p, lw, umin, hi, runtime(True))


# --------------------------------------------------------------- normal form
@kernel(inline="always")
def nf_coefficients(p, lw):
    m = p[M]
    v = p[V]
    va = abs(v)
    omega = math.sqrt(p[K] / m)
    qq = q(p, lw)
    s2 = 3.0 * p[A2] * va
    s3 = p[A2]
    d = stribeck_drop(p)
    if d != 0.0:
        e = d * math.exp(-va / p[VS])
        s2 += e / (2.0 * p[VS] * p[VS])
        s3 -= e / (6.0 * p[VS] ** 3)
    c2 = s2 / m
    c3 = s3 / m
    beta = 3.0 * s3 / m * omega * omega / 8.0
    sg = 1.0 if v > 0.0 else -1.0
    return omega, qq, c2, c3, beta, sg, x_eq(p, lw)


@kernel(inline="always")
def normal_form_valid(p, lw):
    """The polynomial law (the normal form's second-order term was measured on it; a
    Stribeck term adds quintic and higher terms of the same order) with a
    supercritical Hopf point (alpha2 > 0)."""
    return stribeck_drop(p) == 0.0 and p[A2] > 0.0 and p[V] != 0.0


# ------------------------------------------------------- the Stribeck layer
LAYER_WIDTHS = 40.0   # beyond 40 v_s from the belt the Stribeck term is below e^-40 of
                      # the drop r_y - r_k: no step needs to see it
LAYER_STEP = 4.0      # inside, a step moves zdot by at most 4 v_s (or half its distance
                      # to the belt): the 12 stages of dop853 sample e^(-|zdot|/v_s)
                      # at least every third of an e-fold


@kernel(inline="always")
def step_bound(x, zd, s, cf, lw, k, m, v, dz):
    return _layer_step(x, zd, s, cf, cf[8], k, m, v, dz)


@kernel
def _layer_step(x, zd, s, cf, d, k, m, v, dz):
    """Largest step [s] that keeps the Stribeck layer ``|zdot| < 40 v_s`` resolved,
    and zdd at the state (for the driver's step control; none without the layer).

    ``exp(-|zdot|/v_s)`` varies on the width v_s, which can be far below the
    motion's scale, and inside the layer the law's slope ``-(d/v_s)
    exp(-|zdot|/v_s)`` makes the sliding field unstable at the rate ``lam =
    (|d|/(m v_s)) exp(-|zdot|/v_s)``. A step that crosses the layer between two
    stages, or spans many e-folds of that instability (the release from the
    breakaway point, where zdd = 0 and zdot leaves 0 like t^2 until the layer takes
    over), is accepted by an error estimate that never saw it: v_s = 1e-3 |v| put
    the stick-slip amplitude 4e-6 L off at tol 1e-8; and a layer narrower than any
    step is one stage's jump of the force by d at the release, which dop853's
    estimate weighs 7 times too lightly (1.5e-7 L at v_s = 1e-8 |v|).

    Inside the layer a step is at most ``1/lam``, or where that is shorter, the time
    in which the force's jump ``|d|`` moves zdot by ``dz`` (the velocity tolerance
    rtol |v|: a layer that narrow is crossed at once, and one such step keeps its
    jump within the tolerance). A layer wider than ``dz`` is also approached
    resolved: a step moves zdot by at most ``max(4 v_s, |zdot|/2, |zdot| - 40 v_s)``,
    reckoned from zdd and its time derivative (outside the layer a bound of it,
    without the exponential); a narrower layer changes the motion by less than the
    tolerance on the way in (at second order in v_s)."""
    if d is None:
        return np.inf, np.nan
    a = (-k * x - _force(zd, s, cf, d)) / m
    vs = cf[6]
    u = abs(zd)
    h = np.inf
    wide = vs > dz
    aa = abs(a)
    j = 0.0
    if u < LAYER_WIDTHS * vs:
        h = m / abs(d) * max(vs * math.exp(u / vs), dz)
        if wide:
            j = abs((-k * (zd + v) + _slope_term(zd, cf, d) * a) / m)
    elif wide:          # |jerk| <= (k |zdot + v| + |g| |zdd|)/m, e^(-|zdot|/v_s) < e^-40
        f1, a2 = cf[2], cf[4]
        j = (k * abs(zd + v) + (abs(f1) + 3.0 * a2 * zd * zd + abs(d) / vs * 4.3e-18)
             * aa) / m
    if wide:
        room = max(LAYER_STEP * vs, 0.5 * u, u - LAYER_WIDTHS * vs)
        h = min(h, 2.0 * room / (aa + math.sqrt(aa * aa + 2.0 * j * room)))
    return h, a


# ------------------------------------------------------ equilibrium certificate
@kernel
def certified_rest(x, zd, p, lw):
    """The polynomial part of the secant slope S is exact, ``-alpha1 + alpha2 (3 v^2 -
    3 v w + w^2)``, least at ``w = sgn(v) W`` for alpha2 >= 0 (its minimum in w lies
    at 1.5 v, outside ``|w| <= W``; Params and Grid refuse alpha2 < 0); the Stribeck
    term's slope is monotone, least at one end of ``|s + |v|| <= W``. A margin of
    1e-12 of the terms summed keeps rounding from deciding (the Stribeck slope at the
    set's end, ``smin``, with its exponent's rounding ``eps |v|/v_s``; not ``d/v_s``)."""
    vel = rest_radius(x, zd, p, lw)     # sqrt(2E/m); NaN: no certificate applies
    va = abs(p[V])
    if not vel < va:
        return False
    poly = p[A2] * (3.0 * va * (va - vel) + vel * vel)
    size = abs(p[C]) + abs(p[A1]) + 3.0 * p[A2] * va * va
    d = stribeck_drop(p)
    smin = 0.0
    if d != 0.0:
        s_end = -va + vel if d > 0.0 else -va - vel  # where the Stribeck slope is least
        smin = -d / p[VS] * math.exp(s_end / p[VS])
        size += abs(smin) * (1.0 + va / p[VS])
    return p[C] - p[A1] + poly + smin > 1e-12 * size


# ------------------------------------------------- closed forms (linear laws)
@kernel(inline="always")
def piecewise_linear(p, lw):
    """No cubic and no Stribeck term (r_k = r_y, or v_s = 0): the sliding field is
    linear."""
    return p[A2] == 0.0 and stribeck_drop(p) == 0.0


@kernel(inline="always")
def arc_constants(s, p, lw):
    """Sliding centre [cm], growth rate sigma [1/s] and beta^2 [1/s^2] of the linear
    field: ``m x'' - (alpha1 - c) x' + k x = -r_k s - alpha1 v`` (r_k = r_y but for
    v_s = 0)."""
    cen = (-zero_level(p) * s - p[A1] * p[V]) / p[K]
    sig = (p[A1] - p[C]) / (2.0 * p[M])
    b2 = p[K] / p[M] - sig * sig
    return cen, sig, b2
