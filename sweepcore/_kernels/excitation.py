"""The excitation's interface: what the driver, the steppers and the searches know of
the external excitation.

The slider under a load and a moving anchor (the paper's eq. 4 carries the load):

    m x'' + c (x' - y') + k (x - y) + F(x' - v) = F0 p(Omega t + phi),

enters the kernels as one force ``e(t)`` on the slider beside the friction law: the
sliding field is the autonomous one plus ``e(t)/m`` (``plus_load``), and the force
that holds a stuck slider is ``h(t) = e(t) - k x - c v``. Which excitation is a
*kind* of the excitation table (``excitations/__init__.py``); its data ``fx`` is a
namedtuple whose class names the kind, carried beside the law's data ``lw`` and
resolved by its class as the law is (``law.py``): each function below resolves,
when it is compiled, to the kind module's function of that name, or to the generic
form written here. Nothing outside the excitation modules tests the kind or reads an
excitation column (a test checks it).

The generic forms are those of a periodic load, a trigonometric polynomial of time
held in the work array ``fx.xc`` (``trig.py``): a kind of that family defines only
its data class, ``work_size`` and ``with_work`` (its data with a work array of
the caller's, one per call and thread) and ``coefficients`` (alpha_n, beta_n of one point, from the row). The
kind ``none`` (the autonomous belt) defines every function: no load, the closed
form of the stick's end (eq. 27) and the autonomous stop rules, so its kernels are
the autonomous ones, bit for bit.
"""
import math

import numpy as np
from . import codes
from .holding import critical_phases, trig_exit as _trig_exit
from .jit import kernel, resolved_by, runtime
from .law import accel, field_slope, static_limits
from .layout import C, K, OMEGA, V
from .trig import (XC_END, XC_FTOL, XC_HEAD, XC_N, XC_NCRIT, XC_OMEGA, XC_PERIOD, XC_PHASE,
                   XC_STAGE, XC_START, XC_STEP, XC_TOP, bound, crit_at, derivative,
                   stage_loads)

EPS = np.finfo(np.float64).eps


def _modules():
    from .excitations import MODULES
    return MODULES


interface = resolved_by("fx", _modules, "excitation")


# ------------------------------------------------------------ every kind defines
@interface(required=True)
def work_size(fx):
    """Floats of the work array the kind's data needs (``with_work``)."""


@interface(required=True)
def with_work(fx, work):
    """The kind's data as the kernels of one call and thread use it: with the work
    array ``work`` (at least ``work_size`` floats, the caller's, which keeps it alive
    for the call), every array a view without reference count (``jit.unowned``: the
    many kernels the data pass through count none)."""


@interface(required=True)
def coefficients(fx, p):
    """Write the point's harmonics (alpha_n, beta_n of ``trig.py``) into ``fx.xc``."""


# -------------------------------------------------------- per point (generic)
@interface()
def prepare(fx, p, lw):
    """Resolve the excitation of the point p: its harmonics, period, the force
    tolerance of the stop rules and the critical phases of the holding force.
    Returns False where they cannot be resolved."""
    coefficients(fx, p)
    return _resolve(fx.xc, p, lw)


@kernel
def _resolve(xc, p, lw):
    """The generic ``prepare`` after the kind's ``coefficients``."""
    om = p[OMEGA]
    xc[XC_OMEGA] = om
    xc[XC_PERIOD] = 2.0 * math.pi / om
    xc[XC_PHASE] = np.nan                # no phase kept yet (trig.phase)
    xc[XC_STEP + 1] = -1.0               # no step yet (trig.derivative)
    top = 0
    n_h = int(xc[XC_N])
    for i in range(n_h):
        if xc[XC_HEAD + i] != 0.0 or xc[XC_HEAD + n_h + i] != 0.0:
            top = i + 1
    xc[XC_TOP] = max(top, 1)
    r_pos, r_neg = static_limits(p, lw)
    xc[XC_FTOL] = 1e3 * EPS * (max(r_pos, r_neg) + bound(xc, runtime(0)))
    return critical_phases(xc, p[K] * p[V])


@interface(inline=True)
def forced(fx):
    """Whether the kind excites the slider (a compile-time fact of the kind)."""
    return True


@interface(inline=True)
def period(fx):
    """The forcing period [s] (inf: none)."""
    return fx.xc[XC_PERIOD]


@interface(inline=True)
def top_frequency(fx):
    """The highest frequency of the load [rad/s] (0: none)."""
    return fx.xc[XC_TOP] * fx.xc[XC_OMEGA]


@interface(inline=True)
def load_bound(fx):
    """A bound of |e(t)| over all t [kN]."""
    return bound(fx.xc, runtime(0))


@interface(inline=True)
def load(fx, t):
    """e(t) [kN]."""
    return derivative(fx.xc, t, runtime(0))


@interface(inline=True)
def load_rate(fx, t):
    """e'(t) [kN/s]."""
    return derivative(fx.xc, t, runtime(1))


@interface(inline=True)
def plus_load(fx, t, a, m):
    """``a + e(t)/m``: an acceleration of the autonomous field [cm/s^2] with the load."""
    return a + derivative(fx.xc, t, runtime(0)) / m


@interface(inline=True)
def plus_rate(fx, t, j, m):
    """``j + e'(t)/m``: a jerk of the autonomous field [cm/s^3] with the load's."""
    return j + derivative(fx.xc, t, runtime(1)) / m


@interface()
def step_load(fx, t, h, cs):
    """The load at the stages ``t + c h`` (c in ``cs``, a stepper's fractions) of the
    step h [s] from t [s], kept for ``with_stage`` (``trig.stage_loads``)."""
    stage_loads(fx.xc, t, h, cs)
    return 0.0


@interface(inline=True)
def start_load(fx, a, im):
    """``a + e(t) im`` at the start t of the step of the last ``step_load``."""
    return a + fx.xc[XC_START] * im


@interface(inline=True)
def end_load(fx, a, im):
    """``a + e(t + h) im`` at the end of the step of the last ``step_load``."""
    return a + fx.xc[XC_END] * im


@interface(inline=True)
def with_stage(fx, i, a, im):
    """``a + e(t + c_i h) im``: stage i's acceleration [cm/s^2] with its load (the
    stage's fraction c_i of the step of the last ``step_load``)."""
    return a + fx.xc[XC_STAGE + i] * im


@interface(inline=True)
def capped(fx, h):
    """A step [s] at most half the time of the load's highest frequency (a step
    that turns the load's phase further is not resolved by the error estimate)."""
    return min(h, 0.5 / top_frequency(fx))


@interface()
def stick_exit(fx, t, x, p, lw, t_stop):
    """``(dt, slips, mode, x_slip)``: a stick entered at (t, x) lasts dt [s] until
    the holding force leaves the static band (``holding.py``) or t_stop; ``slips``,
    the slide it starts and the position there."""
    return _trig_exit(fx.xc, t, x, p, lw, t_stop)


@interface()
def rest_band(fx, p, lw):
    """``(x_lo, x_hi)`` [cm]: on fixed ground (v = 0) the positions where a stuck
    slider stays stuck for ever, ``-r_neg <= e(t) - k x <= r_pos`` at every t
    (empty where x_lo > x_hi), from the load's extremes at its critical phases
    (``prepare``: with v = 0 the roots of e'). NaN on a moving belt."""
    return _rest_band(fx.xc, p, lw)


@kernel
def _rest_band(xc, p, lw):
    """The generic ``rest_band``."""
    if p[V] != 0.0:
        return np.nan, np.nan
    at = crit_at(xc)
    lo = derivative(xc, 0.0, runtime(0))
    hi = lo
    for i in range(int(xc[XC_NCRIT])):
        e = derivative(xc, xc[at + i], runtime(0))
        lo = min(lo, e)
        hi = max(hi, e)
    r_pos, r_neg = static_limits(p, lw)
    return (hi - r_pos) / p[K], (lo + r_neg) / p[K]


@interface()
def zero_mode(fx, x, t, s, p, lw, gtol):
    """``(mode, event, x)`` after zdot reached 0 at (x, t) while sliding with sign s:
    stick while the holding force is in the band (within the force tolerance of an
    edge it slides on), else slide on by the sign of the force that exceeds it (a
    zero-duration stop: eq. 30 reversing, eq. 31 on in the same direction)."""
    r_pos, r_neg = static_limits(p, lw)
    h = derivative(fx.xc, t, runtime(0)) - p[K] * x - p[C] * p[V]
    over_pos = h - r_pos
    over_neg = -r_neg - h
    if max(over_pos, over_neg) < -fx.xc[XC_FTOL]:
        return codes.STICK, codes.EV_STICK, x
    new = codes.SLIDE_POS if over_pos >= over_neg else codes.SLIDE_NEG
    if new == s:
        return new, codes.EV_ABNORMAL_STOP, x
    return new, codes.EV_NORMAL_STOP, x


# ------------------------------------------- the field with the load (not per kind)
@kernel(inline="always")
def field_accel(fx, t, x, zd, s, cf, lw, k, m):
    """Sliding acceleration [cm/s^2] at (x, zd, t): eq. (41) with the load."""
    return plus_load(fx, t, accel(x, zd, s, cf, lw, k, m), m)


@kernel(inline="always")
def field_jerk(fx, t, x, zd, s, cf, lw, k, m, v):
    """Time derivative of the sliding acceleration along the flow [cm/s^3], with the
    load's (for the excitation none: ``law.jerk``)."""
    a = field_accel(fx, t, x, zd, s, cf, lw, k, m)
    return plus_rate(fx, t, (-k * (zd + v) + field_slope(lw, cf, zd) * a) / m, m)
