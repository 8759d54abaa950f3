"""No excitation: the autonomous belt (Liu's slider), its closed forms and stop rules.

The driver (``driver.py``) asks every excitation for the load in the field, the end of
a stick and the mode after zdot reaches 0; here they are the autonomous belt's:

* no load: every field function returns the autonomous value unchanged, so the
  kernels compiled for this kind are the autonomous ones, bit for bit;
* stick: ``xdot = v``, slip when the holding force ``|k x + c v|`` reaches the static
  limit, at the closed-form time of eq. (27); the slip starts at the breakaway point
  ``(x_s, v)`` (``law.breakaway``) exactly, so every slip after a stick starts from
  the same point;
* zdot = 0 while sliding: with the stick band ``[x_lo, x_hi]`` (``law.stick_band``)
  and v > 0, ``x >= x_hi`` slides on with zdot < 0 (the slide-slide condition (22)),
  ``x < x_lo`` slides on with zdot > 0, else the slider sticks; on in the same
  direction is an abnormal stop (31), reversing a normal stop (30); v < 0 is the
  mirror image, and for v = 0 the slider sticks inside the band. A zero within the
  touch tolerance of the breakaway point is snapped to it (``zero_mode``).
"""
import math
from collections import namedtuple

import numpy as np

from .. import codes
from ..jit import kernel
from ..law import breakaway, stick_band
from ..layout import K, M, V

EPS = np.finfo(np.float64).eps

Unforced = namedtuple("Unforced", ())


@kernel(inline="always")
def work_size(fx):
    return 0


@kernel(inline="always")
def with_work(fx, work):
    return fx


@kernel(inline="always")
def coefficients(fx, p):
    return None


@kernel(inline="always")
def prepare(fx, p, lw):
    return True


@kernel(inline="always")
def forced(fx):
    return False


@kernel(inline="always")
def period(fx):
    return np.inf


@kernel(inline="always")
def top_frequency(fx):
    return 0.0


@kernel(inline="always")
def load_bound(fx):
    return 0.0


@kernel(inline="always")
def load(fx, t):
    return 0.0


@kernel(inline="always")
def load_rate(fx, t):
    return 0.0


@kernel(inline="always")
def plus_load(fx, t, a, m):
    return a


@kernel(inline="always")
def plus_rate(fx, t, j, m):
    return j


@kernel(inline="always")
def step_load(fx, t, h, cs):
    return 0.0


@kernel(inline="always")
def with_stage(fx, i, a, im):
    return a


@kernel(inline="always")
def start_load(fx, a, im):
    return a


@kernel(inline="always")
def end_load(fx, a, im):
    return a


@kernel(inline="always")
def capped(fx, h):
    return h


@kernel
def stick_exit(fx, t, x, p, lw, t_stop):
    """The stick in closed form: x moves with the belt to the breakaway point x_s
    (eq. 27), or to t_stop; the duration is computed as a duration, not as a
    difference of times (absolute times may be large)."""
    v = p[V]
    xs = breakaway(p, lw)
    if v > 0.0:
        dt_slip = max(xs - x, 0.0) / v
    elif v < 0.0:
        dt_slip = min(xs - x, 0.0) / v
    else:
        dt_slip = np.inf
    slips = dt_slip <= t_stop - t
    if not slips:
        return t_stop - t, False, codes.STICK, xs
    return dt_slip, True, codes.SLIDE_NEG if v > 0.0 else codes.SLIDE_POS, xs


@kernel
def zero_mode(fx, x, t, s, p, lw, gtol):
    """Mode after zdot reached 0 while sliding with sign s, and the event kind.

    ``gtol`` is the touch tolerance [cm/s] (``driver.touch_tol``). Returns
    (new_mode, event, x_new): x_new is x, or the breakaway point when a zero within
    ``tolx = gtol / omega`` of it is snapped there. Snapping skips a stick of at most
    ``gtol / (omega |v|)``, a few rtol of a natural period (the state after it is the
    same: the slip restarts from ``x_s``). That is a motion scale: ``r_y/k`` does not
    enter (tiny v: a stick 1e-11 of ``x_s`` long is a stick). The floor is the
    rounding of the band's edges.
    """
    v = p[V]
    x_lo, x_hi = stick_band(p, lw)
    tolx = gtol / math.sqrt(p[K] / p[M]) + 4.0 * EPS * max(abs(x_lo), abs(x_hi))
    new = codes.STICK
    xn = x
    if v > 0.0:
        if x >= x_hi - tolx:
            new = codes.SLIDE_NEG
            if x <= x_hi + tolx:
                xn = x_hi
        elif x < x_lo - tolx:
            new = codes.SLIDE_POS
    elif v < 0.0:
        if x <= x_lo + tolx:
            new = codes.SLIDE_POS
            if x >= x_lo - tolx:
                xn = x_lo
        elif x > x_hi + tolx:
            new = codes.SLIDE_NEG
    else:
        if x > x_hi + tolx:
            new = codes.SLIDE_NEG
        elif x < x_lo - tolx:
            new = codes.SLIDE_POS
    if new == codes.STICK:
        return new, codes.EV_STICK, xn
    if new == s:
        return new, codes.EV_ABNORMAL_STOP, xn
    return new, codes.EV_NORMAL_STOP, xn
