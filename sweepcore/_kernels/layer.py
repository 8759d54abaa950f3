"""The Stribeck layer's bound on the sliding step: a quantity of the law (its
exponential Stribeck term, law.py), in a module of its own for law.py's size.

``exp(-|zdot|/v_s)`` varies on the width v_s, which can be far below the motion's
scale, and inside the layer the law's slope ``-(d/v_s) exp(-|zdot|/v_s)`` (d = r_y -
r_k) makes the sliding field unstable at the rate ``lam = (|d|/(m v_s))
exp(-|zdot|/v_s)``. A step that crosses the layer between two stages, or spans many
e-folds of that instability (the release from the breakaway point, where zdd = 0 and
zdot leaves 0 like t^2 until the layer takes over), is accepted by an error estimate
that never saw it: v_s = 1e-3 |v| put the stick-slip amplitude 4e-6 L off at tol
1e-8; and a layer narrower than any step is one stage's jump of the force by d at
the release, which dop853's estimate weighs 7 times too lightly (1.5e-7 L at v_s =
1e-8 |v|).
"""
import math

import numpy as np

from .jit import kernel
from .law import jerk

LAYER_WIDTHS = 40.0   # beyond 40 v_s from the belt the Stribeck term is below e^-40 of
                      # the drop r_y - r_k: no step needs to see it
LAYER_STEP = 4.0      # inside, a step moves zdot by at most 4 v_s (or half its distance
                      # to the belt): the 12 stages of dop853 sample e^(-|zdot|/v_s)
                      # at least every third of an e-fold


@kernel(inline="always")
def layer_step(x, zd, s, cf, d, m, v, dz, a):
    """Largest step [s] that keeps the Stribeck layer ``|zdot| < 40 v_s`` resolved
    (for the driver's step control; ``d`` not None; module docstring).

    Inside the layer a step is at most ``1/lam``, or where that is shorter, the time
    in which the force's jump ``|d|`` moves zdot by ``dz`` (the velocity tolerance
    rtol |v|: a layer that narrow is crossed at once, and one such step keeps its
    jump within the tolerance). A layer wider than ``dz`` is also approached
    resolved: a step moves zdot by at most ``max(4 v_s, |zdot|/2, |zdot| - 40 v_s)``,
    reckoned from zdd (``a``, at the step's start) and its time derivative (outside
    the layer a bound of it, without the exponential) (a narrower layer changes the
    motion by less than the tolerance on the way in: at second order in v_s)."""
    vs = cf[6]
    u = abs(zd)
    h = np.inf
    wide = vs > dz
    aa = abs(a)
    j = 0.0
    if u < LAYER_WIDTHS * vs:
        h = m / abs(d) * max(vs * math.exp(u / vs), dz)
        if wide:
            j = abs(jerk(x, zd, s, cf, d, m, v))
    elif wide:          # |jerk| <= (k |zdot + v| + |g| |zdd|)/m, e^(-|zdot|/v_s) < e^-40
        k, f0, f1, a1, a2, ry, vs_, c = cf
        j = (k * abs(zd + v) + (abs(f1) + 3.0 * a2 * zd * zd + abs(d) / vs * 4.3e-18)
             * aa) / m
    if wide:
        room = max(LAYER_STEP * vs, 0.5 * u, u - LAYER_WIDTHS * vs)
        h = min(h, 2.0 * room / (aa + math.sqrt(aa * aa + 2.0 * j * room)))
    return h
