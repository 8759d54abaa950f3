"""Is a measured cycle resolved by float64 at its position?

x is stored to ``eps |x|``; near the breakaway point ``|x| ~ r_y/k``, which can exceed
the cycle's size by many orders (tiny belt speeds, soft springs: ``r_y/k = 1e10`` cm
with a cycle of ``v/omega = 1e-6`` cm). The spring force ``k x`` then carries a
rounding of ``eps k |x|`` against the cycle's ``k A``, and every observable of the
cycle inherits a relative error of about ``u/A`` with ``u = eps max|x|`` (measured
on stick-slip cycles against the v -> 0 limit solved in scaled variables:
period error 0.02 .. 0.25 u/A, amplitude 0.3 .. 1.5 u/A, for u/A from 1e-10 to 0.4).
The same holds for xdot, stored as ``zdot + v`` to ``eps (|v| + V)`` against the
velocity amplitude ``V``.

A cycle is resolved when both ratios are at most ``RESOLUTION = 1e-6``, the relative
accuracy an answer with status ok promises, and its period and mean are finite (a
subnormal belt speed loads the spring across the static band only after more than the
largest float64 of seconds); otherwise its observables carry fewer digits than that
and the point is flagged ``below_resolution``.
"""
import numpy as np

from .jit import kernel

from . import codes
from .layout import (OB_AMPLITUDE, OB_MEAN, OB_PERIOD, OB_REGIME, OB_STATUS,
                     OB_VAMPLITUDE, OB_X_MAX, OB_X_MIN, V)

EPS = np.finfo(np.float64).eps
RESOLUTION = 1e-6


@kernel
def cycle_resolved(out, p):
    """True when the cycle written in ``out`` (layout OB_*) is resolved (module doc)."""
    amp = out[OB_AMPLITUDE]
    vamp = out[OB_VAMPLITUDE]
    u = EPS * max(abs(out[OB_X_MAX]), abs(out[OB_X_MIN]))
    w = EPS * (abs(p[V]) + vamp)
    return (amp * RESOLUTION >= u and vamp * RESOLUTION >= w
            and np.isfinite(out[OB_PERIOD]) and np.isfinite(out[OB_MEAN]))


@kernel
def check_cycle(out, p):
    """Set the status of a measured cycle: ok, or below_resolution (regime failed,
    observables kept as the measured estimates)."""
    if cycle_resolved(out, p):
        out[OB_STATUS] = codes.OK
    else:
        out[OB_STATUS] = codes.BELOW_RESOLUTION
        out[OB_REGIME] = codes.R_FAILED
