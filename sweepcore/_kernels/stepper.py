"""The stepper contract, and the dispatch on the method code.

A stepper advances only the smooth sliding equation (friction sign ``s`` frozen),
from the state ``(x, zdot)`` over a step ``h`` [s]:

    step(x, zd, h, s, p, o, want_q) -> (x1, zd1, q_x, q_xd2, q_w, err, ok)

1. It never sees sticking, events or bookkeeping: the hybrid driver
   (``driver.py``) owns those and is the only caller.
2. ``q_x, q_xd2, q_w`` are the step's quadratures of ``x``, ``xdot^2`` and the
   friction power ``r_a xdot`` (computed only when ``want_q``; else zeros),
   integrated at the stepper's own order.
3. ``err`` is the error estimate scaled by the tolerance (``<= 1`` accept); fixed-step
   methods return 0.  ``ok`` is False when the step cannot be taken at this ``h``
   (the GPS denominator guard); the driver then halves ``h``.
4. Dense output is the stepper itself: the state at ``t + theta h`` is
   ``step(..., theta * h, ...)`` from the step's start, so an event located there is
   the integrator's own state, not an interpolant's.
5. ``proposal(x, zd, s, p, o, h_prev)`` returns the next step size to try.
"""
from .jit import kernel

from . import codes
from .dopri5 import dopri5_step
from .exact import exact_proposal, exact_step
from .gps import gps_step
from .rk4 import rk4_step
from .layout import O_DT, O_METHOD


@kernel
def step(x, zd, h, s, p, o, want_q):
    """Dispatch one step to the method in ``o[O_METHOD]`` (see module docstring)."""
    meth = int(o[O_METHOD])
    if meth == codes.EXACT:
        return exact_step(x, zd, h, s, p, want_q)
    if meth == codes.RK4:
        return rk4_step(x, zd, h, s, p, want_q)
    if meth == codes.GPS:
        return gps_step(x, zd, h, s, p, o, want_q)
    return dopri5_step(x, zd, h, s, p, o, want_q)


@kernel
def proposal(x, zd, s, p, o, h_prev):
    """Next step size [s]: fixed for gps/rk4, controller's for dopri5, arc for exact."""
    meth = int(o[O_METHOD])
    if meth == codes.EXACT:
        return exact_proposal(x, zd, s, p)
    if meth == codes.DOPRI5:
        return h_prev
    return o[O_DT]
