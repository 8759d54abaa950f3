"""The stepper contract, the method table, and the dispatch on the method code.

A stepper advances only the smooth sliding equation (friction sign ``s`` frozen),
from the state ``(x, zdot)`` over a step ``h`` [s]:

    step(t, x, zd, h, s, p, lw, fx, o, want_q) -> (x1, zd1, q_x, q_xd2, q_w, q_l, err, ok)

from the time ``t`` [s], with ``p`` the parameter row, ``lw`` the law's data
(``law.py``) and ``fx`` the excitation's (``excitation.py``: its load enters every
stage at the stage's own time, as ``fun(t, y)`` in scipy's solvers; for the
excitation ``none`` the field is the autonomous one, bit for bit).

1. It never sees sticking, events or bookkeeping: the hybrid driver
   (``driver.py``) owns those and is the only caller.
2. ``q_x, q_xd2, q_w, q_l`` are the step's quadratures of ``x``, ``xdot^2``, the
   friction power ``r_a xdot`` and the law's slope term ``law.integrand``
   (computed only when ``want_q``, else zeros), integrated at the stepper's own
   order.
3. ``err`` is the error estimate scaled by the tolerance (``<= 1`` accept); fixed-step
   methods return 0.  ``ok`` is False when the step cannot be taken at this ``h``
   (the GPS denominator guard); the driver then halves ``h``.
4. Dense output: the adaptive pairs carry their continuous extension
   (``extend``: the coefficients of the interpolant over a step just taken, from the
   slopes ``step_kept`` returned with it, no stage taken again; evaluated
   by ``interpolate``; Hairer, Norsett & Wanner, Solving ODEs I, section II.6),
   seventh order for dop853, fourth for dopri5. For the other methods the dense
   output is the stepper itself: the state at ``t + theta h`` is
   ``step(..., theta * h, ...)`` from the step's start. ``state_at`` gives the
   state inside a step by whichever the method has.
5. ``proposal`` gives the next step size to try, by the method's kind (table below).
6. ``tangent`` carries the derivative of the state with respect to a start
   through a step (``variational.py``): the variational equations integrated by
   the method's own stages where it keeps them (dopri5, dop853: the derivative of
   the step map itself), else by differences of re-steps.

The method is a compile-time constant: the entry kernels (``entries.py``) are
compiled per method, and ``step`` and ``proposal`` resolve to the method's own
functions when they are compiled (numba's ``overload`` on the method code), so a
run compiles only the stepper it uses. The dispatching functions are inlined
where they are called (each is a line; as calls they cost a copy of the step's
results and, with arrays, a reference count).

Adding a stepper: its module and one row of ``METHODS`` (its step function, and its
proposal rule).
"""
from numba import types
from numba.core.errors import TypingError
from numba.extending import overload

from .jit import OVERLOAD_OPTIONS, kernel, runtime

from .dop853 import dop853_extend, dop853_step
from .dopri5 import dopri5_extend, dopri5_step
from .exact import exact_proposal, exact_step
from .gps import gps_step
from .rk4 import rk4_step
from .layout import O_DT, S_N

# name, order, adaptive, controller exponent, touch-tolerance factor (of rtol),
# closed form (needs a piecewise-linear law), step function. The code of a method
# is its row.
#   order 0: no truncation error. controller: h_new = h * 0.9 err^exponent.
#   touch factor: an adaptive method's zdot error at a touch is ~9 rtol |v| after a
#   whole period (measured on constant-friction circles, driver.touch_tol), so 20.
METHODS = (
    ("exact", 0, False, 0.0, 0.0, True, exact_step),   # closed-form arcs
    ("gps", 1, False, 0.0, 0.0, False, gps_step),      # Liu's GPS (49)-(50)
    ("rk4", 4, False, 0.0, 0.0, False, rk4_step),      # classical Runge-Kutta
    ("dopri5", 5, True, -0.2, 20.0, False, dopri5_step),  # Dormand-Prince 5(4)
    ("dop853", 8, True, -0.125, 20.0, False, dop853_step),  # Dormand-Prince 8(5,3)
)
EXACT, GPS, RK4, DOPRI5, DOP853 = range(len(METHODS))
# "auto" between the adaptive pairs: dop853 below this tolerance, dopri5 from it up.
# At tol 1e-8 and below dop853 needs under half of dopri5's stepper calls for the
# 256 x 256 map, at 1e-6 its dearer step loses (benchmarks/run.py, "Hopf map";
# right-hand sides per period: benchmarks/pair_choice.py).
AUTO_DOP853_BELOW = 1e-7
# ... and only where the motion is far above float64's rounding of x: where
# eps (r_y/k + |v|/omega) / (|v|/omega), the rounding of x at the breakaway point
# over the size of the cycle, exceeds this, the rounding of dop853's larger stage
# sums shows (stick fraction of the paper's slider at v = 1e-9 cm/s, ratio 1.4e-7:
# 1.3e-6 off with dop853, 4.4e-7 with dopri5; at v = 1e-8, ratio 1.4e-8: 4e-8)
AUTO_DOP853_ROUNDING = 3e-8
METHOD_NAMES = {i: row[0] for i, row in enumerate(METHODS)}
METHOD_CODES = {name: i for i, name in METHOD_NAMES.items()}
METHOD_ORDER = {i: row[1] for i, row in enumerate(METHODS)}
ADAPTIVE = tuple(row[2] for row in METHODS)
EXPONENT = tuple(row[3] for row in METHODS)
TOUCH_FACTOR = tuple(row[4] for row in METHODS)
CLOSED_FORM = tuple(row[5] for row in METHODS)
# the continuous extension of a method, by code (None: re-step from the start),
# built from a step just taken: its end and the slopes its step function returns
# after ``ok``
EXTEND = (None, None, None, dopri5_extend, dop853_extend)


def _method(meth):
    """The method table's row of a compile-time method code."""
    if not isinstance(meth, types.IntegerLiteral) or \
            not 0 <= meth.literal_value < len(METHODS):
        raise TypingError(f"the method must be a compile-time code of METHODS, got {meth}")
    return meth.literal_value


def step(meth, t, x, zd, h, s, p, lw, fx, o, want_q):
    """One step of method ``meth`` (a code of ``METHODS``; module docstring)."""


@overload(step, prefer_literal=True, inline="always",
          jit_options=OVERLOAD_OPTIONS)
def _step(meth, t, x, zd, h, s, p, lw, fx, o, want_q):
    code = _method(meth)
    fn = METHODS[code][6]
    # bool(): want_q is a constant at every call site; as a literal it would compile
    # the stepper once per value, as a plain bool once (the branch costs nothing)
    if EXTEND[code] is None:
        return lambda meth, t, x, zd, h, s, p, lw, fx, o, want_q: fn(
            t, x, zd, h, s, p, lw, fx, o, bool(want_q))

    def without_slopes(meth, t, x, zd, h, s, p, lw, fx, o, want_q):
        x1, z1, qx, qv, qw, ql, err, ok, _ks = fn(t, x, zd, h, s, p, lw, fx, o,
                                                  bool(want_q))
        return x1, z1, qx, qv, qw, ql, err, ok
    return without_slopes


def step_kept(meth, t, x, zd, h, s, p, lw, fx, o, want_q):
    """``step`` and, after its eight results, what ``extend`` and ``tangent`` need
    (the slopes of its stages; an empty tuple for a method that keeps none)."""


@overload(step_kept, prefer_literal=True, inline="always",
          jit_options=OVERLOAD_OPTIONS)
def _step_kept(meth, t, x, zd, h, s, p, lw, fx, o, want_q):
    code = _method(meth)
    fn = METHODS[code][6]
    if EXTEND[code] is not None:
        return lambda meth, t, x, zd, h, s, p, lw, fx, o, want_q: fn(
            t, x, zd, h, s, p, lw, fx, o, bool(want_q))

    def with_nothing(meth, t, x, zd, h, s, p, lw, fx, o, want_q):
        x1, z1, qx, qv, qw, ql, err, ok = fn(t, x, zd, h, s, p, lw, fx, o, bool(want_q))
        return x1, z1, qx, qv, qw, ql, err, ok, ()
    return with_nothing


def proposal(meth, x, zd, s, p, lw, o, h_prev):
    """Next step size [s] of method ``meth``: the arc's for closed forms, the
    controller's for adaptive methods, the fixed ``dt`` otherwise."""


@overload(proposal, prefer_literal=True, inline="always",
          jit_options=OVERLOAD_OPTIONS)
def _proposal(meth, x, zd, s, p, lw, o, h_prev):
    code = _method(meth)
    if code == EXACT:
        return lambda meth, x, zd, s, p, lw, o, h_prev: exact_proposal(x, zd, s, p, lw)
    if ADAPTIVE[code]:
        return lambda meth, x, zd, s, p, lw, o, h_prev: h_prev
    return lambda meth, x, zd, s, p, lw, o, h_prev: o[O_DT]


def extend(meth, t, x, zd, h, s, p, lw, fx, x1, z1, ks):
    """The coefficients of method ``meth``'s interpolant over the step ``h`` from
    ``(x, zd)`` at ``t`` to ``(x1, z1)``, with ``ks`` as ``step_kept`` returned it
    (zeros for a method without one; module docstring, item 4)."""


@overload(extend, prefer_literal=True, inline="always",
          jit_options=OVERLOAD_OPTIONS)
def _extend(meth, t, x, zd, h, s, p, lw, fx, x1, z1, ks):
    fn = EXTEND[_method(meth)]
    if fn is None:
        return lambda meth, t, x, zd, h, s, p, lw, fx, x1, z1, ks: (0.0,) * 14
    return lambda meth, t, x, zd, h, s, p, lw, fx, x1, z1, ks: fn(
        t, x, zd, h, s, p, lw, fx, x1, z1, ks)


@kernel(inline="always")
def interpolate(dc, th, x, zd):
    """The state ``(x, zdot)`` at the fraction ``th`` of a step from ``(x, zd)`` on
    its interpolant ``dc`` (``extend``): y0 + th (F0 + (1 - th) (F1 + th (F2 + ...))),
    the nesting of DOP853's contd8."""
    u = 1.0 - th
    xi = x + th * (dc[0] + u * (dc[1] + th * (dc[2] + u * (dc[3] + th * (
        dc[4] + u * (dc[5] + th * dc[6]))))))
    zi = zd + th * (dc[7] + u * (dc[8] + th * (dc[9] + u * (dc[10] + th * (
        dc[11] + u * (dc[12] + th * dc[13]))))))
    return xi, zi


def state_at(meth, t, x, zd, h, s, p, lw, fx, o, dc, H, st):
    """The state ``(x, zdot)`` a time ``h`` into the step ``H`` from ``(x, zd)`` at
    ``t``: on the interpolant ``dc`` where the method has one, else by a re-step
    (counted in ``st[S_N]``)."""


@overload(state_at, prefer_literal=True, inline="always",
          jit_options=OVERLOAD_OPTIONS)
def _state_at(meth, t, x, zd, h, s, p, lw, fx, o, dc, H, st):
    code = _method(meth)
    if EXTEND[code] is None:
        fn = METHODS[code][6]

        def restep(meth, t, x, zd, h, s, p, lw, fx, o, dc, H, st):
            st[S_N] += 1.0
            x1, z1, _a, _b, _c, _l, _e, _ok = fn(t, x, zd, h, s, p, lw, fx, o,
                                                 runtime(False))
            return x1, z1
        return restep
    fn = METHODS[code][6]

    def on_interpolant(meth, t, x, zd, h, s, p, lw, fx, o, dc, H, st):
        if h <= H:
            return interpolate(dc, h / H, x, zd)
        # past the step (a touch's bracket may reach beyond it): no extrapolation
        st[S_N] += 1.0
        x1, z1, _a, _b, _c, _l, _e, _ok, _ks = fn(t, x, zd, h, s, p, lw, fx, o,
                                                  runtime(False))
        return x1, z1
    return on_interpolant


def has_dense(meth):
    """Whether method ``meth`` has a continuous extension (a compile-time bool)."""


@overload(has_dense, prefer_literal=True, inline="always",
          jit_options=OVERLOAD_OPTIONS)
def _has_dense(meth):
    flag = EXTEND[_method(meth)] is not None
    return lambda meth: flag
