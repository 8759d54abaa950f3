"""Numerical options, validated once and packed into the kernels' option row."""
from __future__ import annotations

import math

import numpy as np

from ._kernels import codes, layout, stepper
# names a user types, in their own room (no numba there); re-exported here
from .keywords import checked_keywords, did_you_mean, suggestion  # noqa: F401

# every method of the kernels' table (stepper.METHODS), and "auto"
METHODS = ("auto", *codes.METHOD_CODES)
CLOSED_FORM = tuple(row[0] for row in stepper.METHODS if row[5])
AUTO = -1.0   # resolved per point before the kernels run: a closed form where the
              # law allows one (no cubic and no Stribeck term), else dop853 below
              # tol 1e-7 where the motion is far above float64's rounding of x,
              # else dopri5 (sweepcore.compiled.methods_of)
MAX_STEPS_CAP = 2**53   # largest integer a float64 option row holds exactly
# Largest touch tolerance: the accuracy of an answer (1e-6 relative). A touch reset to
# the breakaway point drops the excursion of zdot past 0; above this it can drop a
# real stick or a growing cycle.
GRAZE_MAX = 1e-6


def check_method(method: str, where) -> None:
    """Refuse a closed-form method where a point's law has none: ``where`` is a
    ``Params`` or a ``Grid``; the law's own rule decides (``closed_form_grid``) and
    names what stands in the way."""
    if method not in CLOSED_FORM:
        return
    law = where.friction_law if hasattr(where, "friction_law") else None
    laws = (law,) if law is not None else where.laws
    for one in laws:
        why = one.closed_form_grid(where)
        if why:
            raise ValueError(f"method={method!r} needs a piecewise-linear law at "
                             f"every point (the sliding phase has a closed form only "
                             f"then); {why}")


def _finite(val) -> bool:
    """math.isfinite, False for an integer beyond float64 (10**400)."""
    try:
        return math.isfinite(val)
    except OverflowError:
        return False


def _shown(val) -> str:
    """``repr`` of a value, or the size of an integer too long to print usefully."""
    if isinstance(val, int) and not isinstance(val, bool) and \
            abs(val).bit_length() > 128:
        digits = int(abs(val).bit_length() * math.log10(2))
        return f"an integer of about {'-' if val < 0 else ''}1e{digits}"
    return repr(val)


# the largest multiplicity a forced response search keeps history for
# (forced_attractor.NH = 40 stroboscopic states: 2 n + 2 of them)
MAX_PERIODS_SOUGHT = 19

def make_options(method: str = "auto", tol: float = 1e-8, dt: float | None = None,
                 max_steps: int = 2_000_000, max_periods: float = 2000.0,
                 gps_a: float | None = None, graze: float = 1e-10,
                 periods: int = 16) -> np.ndarray:
    """Validate numerical options and return the kernel option row.

    Parameters
    ----------
    method : {"auto", "exact", "gps", "rk4", "dopri5", "dop853"}
        Stepper (the kernels' method table). "auto" is exact where the law is
        piecewise linear (alpha2 = 0, no Stribeck term), else dop853 for
        ``tol < 1e-7`` and dopri5 from 1e-7 up (the faster pair there).
    tol : float
        Relative tolerance of the adaptive steppers, and of convergence detection
        of attractors.
    dt : float, optional
        Fixed step of gps and rk4 [s]; default 2 pi / omega / 50 per point.
    max_steps : int
        Stepper calls allowed for one run or one grid point, 1 ... 2**53 (the
        option row is float64, exact for integers up to 2**53).
    max_periods : float
        Time budget of one attractor search, in natural periods 2 pi / omega.
    gps_a : float, optional
        GPS shift constant a [cm]; default the point's length scale r_y/k + |v|/omega.
    graze : float
        Relative tolerance that decides a tangential touch of zdot = 0 (of the
        motion's velocity scale |v|), in (0, 1e-6]; the adaptive steppers use at
        least 20 tol.
    periods : int
        A forced response (``F0`` or ``Y0`` given): the largest multiplicity n
        sought, 1 ... 19 (a response of period n T, T = 2 pi / Omega; none up to
        it: aperiodic).
    """
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}"
                         f"{did_you_mean(method, METHODS)}")
    for name, val in (("tol", tol), ("graze", graze)):
        if isinstance(val, bool) or not isinstance(val, (int, float)) or \
                not (_finite(val) and 0.0 < val < 1.0):
            raise ValueError(f"{name} must be a number in (0, 1), got {_shown(val)}")
    if not graze <= GRAZE_MAX:
        raise ValueError(
            f"graze must be <= {GRAZE_MAX:g}, got {graze!r}: a wider touch tolerance "
            "reads a real crossing of zdot = 0 as a touch and changes the topology of "
            "the orbit (a stick-slip cycle becomes a slip cycle); it is meant for "
            "rounding and integration error, not as a model parameter")
    if dt is not None and (isinstance(dt, bool) or not isinstance(dt, (int, float))
                           or not (_finite(dt) and dt > 0.0)):
        raise ValueError(f"dt must be a finite number > 0 [s], got {_shown(dt)}")
    if isinstance(max_steps, bool) or not isinstance(max_steps, (int, np.integer)) \
            or not 1 <= max_steps <= MAX_STEPS_CAP:
        raise ValueError(f"max_steps must be an integer in [1, 2**53], got "
                         f"{_shown(max_steps)} (it travels in a float64 option row, "
                         "exact up to 2**53)")
    if isinstance(max_periods, bool) or not isinstance(max_periods, (int, float)) or \
            not (_finite(max_periods) and max_periods > 0):
        raise ValueError(f"max_periods must be a finite number > 0, got "
                         f"{_shown(max_periods)}")
    if gps_a is not None and (isinstance(gps_a, bool) or not isinstance(gps_a, (int, float))
                              or not _finite(gps_a)):
        raise ValueError(f"gps_a must be a finite number [cm], got {_shown(gps_a)}")
    if isinstance(periods, bool) or not isinstance(periods, (int, np.integer)) or \
            not 1 <= periods <= MAX_PERIODS_SOUGHT:
        raise ValueError(f"periods must be an integer in [1, {MAX_PERIODS_SOUGHT}], "
                         f"got {_shown(periods)}")
    o = np.zeros(layout.NO)
    o[layout.O_PERIODS] = periods
    o[layout.O_METHOD] = AUTO if method == "auto" else codes.METHOD_CODES[method]
    o[layout.O_RTOL] = tol
    o[layout.O_DT] = -1.0 if dt is None else dt
    o[layout.O_MAX_STEPS] = max_steps
    o[layout.O_MAX_TIME] = max_periods
    o[layout.O_GPS_A] = np.nan if gps_a is None else gps_a
    o[layout.O_GRAZE] = graze
    return o

