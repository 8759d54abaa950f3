"""The one hybrid stick/slide driver, for every excitation.

It owns the phases and every rule that switches them; steppers (``stepper.py``) only
advance the smooth sliding field, with time (``fun(t, y)``), and the excitation
(``excitation.py``, its data ``fx`` beside the law's) says what its load adds.
``advance`` moves a point's state row ``st`` (layout in ``layout.py``) to its next
event or to ``t_stop`` and returns ``(event, status)``: everything a point needs to
go on lives in its row.

Rules (eq. numbers of Liu's paper):

* stick: ``xdot = v``; the stick ends where the holding force leaves the static band
  (the excitation's ``stick_exit``: for the autonomous belt the closed-form time of
  eq. (27), under a load the exact first exit of ``holding.py``), never by time
  stepping. The slip state is set there exactly (for the autonomous belt the
  breakaway point ``(x_s, v)``, so every slip after a stick starts from it).
* slide: ``zdot`` returns to 0 (located inside a step on its interpolant, then
  re-stepped to the event so the state is the integrator's own: ``_on_root``); the
  excitation's ``zero_mode`` decides what follows: stick where the holding force is
  inside the band, else slide on (a zero-duration stop, the slide-slide condition
  (22): on in the same direction an abnormal stop (31), reversing a normal stop
  (30)). For the autonomous belt that is the stick band ``[x_lo, x_hi]`` of
  ``|k x + c v| <= r_y`` (``law.stick_band``).
* tangential touches (grazes): ``zdot`` touching 0 with ``zdd = 0`` (the constant-
  friction cycle's abnormal stop) is found at its turning point, not by a sign test,
  and a touch within the graze tolerance of the breakaway point ``x_s`` is snapped to
  it: no stick of finite duration, no chain of zero-length events. Both tolerances
  come from the motion (``touch_tol``): the velocity scale ``|v|`` of the cycle
  relative to the belt, never the offset ``r_y/k``, so tiny belt speeds, tiny
  cycles and stiff springs keep their sticks and their growth.
* after leaving the switching line (slip, stop) the event test is disarmed until
  ``zdot`` turns back towards 0, so the departure itself is never an event.
* with ``st[S_TRACK]`` the tangent ``st[S_J]`` (the derivative of the state with
  respect to a start) rides along: through each step (``variational.py``) and
  through each switch's saltation matrix (``_salt_zero``, ``_salt_release``).
"""
import math

import numpy as np
from .jit import kernel

from . import codes
from .excitation import (capped, end_load, field_accel, load_rate, start_load,
                         stick_exit, top_frequency, zero_mode)
from .law import (accel, certified_rest, constants, friction_force, integrand,
                  step_bound)
from .layout import (A_DT, A_ILAW, A_IX, A_IXD2, A_NSTICK, A_NSTOP, A_TSTICK, A_WF,
                     A_XDMAX, A_XDMIN, A_XMAX, A_XMIN, C, K, M, O_GRAZE, O_LV, O_LX,
                     O_MAX_STEPS, O_METHOD, O_RTOL, S_ARMED, S_H, S_J, S_MODE, S_N,
                     S_SECTIONS, S_T, S_TOUCH, S_TRACK, S_X, S_ZD, V)
from .events import (F_XD, F_XDOT_EXTREMUM, NO_PART, cubic_root, polish, zd_event,
                     zero_in_step)
from .stepper import (ADAPTIVE, EXPONENT, TOUCH_FACTOR, extend, has_dense, proposal,
                      step, step_kept)
from .variational import tangent

EPS = np.finfo(np.float64).eps
# ---------------------------------------------------------------- small pieces
@kernel
def touch_tol(p, o):
    """Velocity tolerance [cm/s] within which ``zdot = 0`` is a touch.

    It is the error of zdot at a touch: for dopri5 at most ~9 rtol lv after a whole
    period (measured on constant-friction circles, whose touch is exact, over
    m, k in [1e-3, 1e3], r_y in [1e-3, 1e2], |v| in [1e-9, 1e2], rtol 1e-6 .. 1e-12),
    so 20 rtol lv (the method table's touch factor); the user's ``graze`` lv for the
    exact and fixed-step methods. The
    floor is the rounding of x near the breakaway point seen as a velocity,
    ``omega eps |x|`` over ~1e3 steps. It scales with the motion (``lv = |v|``, see
    ``dopri5.scales``): a real crossing whose excursion grows by more than this per
    period (a slowly growing cycle, k = 1e10) is a crossing, not a touch reset to the
    breakaway point. Never so wide that sliding at rest (zdot = -v) looks like a
    touch: at most 1e-2 |v|.
    """
    v = p[V]
    omega = math.sqrt(p[K] / p[M])
    g = max(o[O_GRAZE], TOUCH_FACTOR[int(o[O_METHOD])] * o[O_RTOL])
    gtol = g * o[O_LV] + 1e3 * EPS * omega * o[O_LX]
    if v != 0.0:
        gtol = min(gtol, 1e-2 * abs(v))
    return gtol


@kernel
def initial_mode(x0, xd0, p, lw, fx, gtol):
    """Phase of a start (x0, xdot0) at t = 0: slide by the sign of zdot, else as at
    a stop (``gtol``: touch tolerance [cm/s])."""
    zd0 = xd0 - p[V]
    if zd0 > 0.0:
        return codes.SLIDE_POS, x0
    if zd0 < 0.0:
        return codes.SLIDE_NEG, x0
    new, _ev, xn = zero_mode(fx, x0, 0.0, 0.0, p, lw, gtol)
    return new, xn


@kernel(inline="always")
def _note_x(acc, x, xd):
    if x > acc[A_XMAX]:
        acc[A_XMAX] = x
    if x < acc[A_XMIN]:
        acc[A_XMIN] = x
    if xd > acc[A_XDMAX]:
        acc[A_XDMAX] = xd
    if xd < acc[A_XDMIN]:
        acc[A_XDMIN] = xd


@kernel
def init_state(st, x0, xd0, p, lw, fx, o):
    """Fill st for a start at t = 0 (no tangent); returns the start's mode."""
    mode, xs = initial_mode(x0, xd0, p, lw, fx, touch_tol(p, o))
    st[S_T] = 0.0
    st[S_X] = xs
    st[S_ZD] = 0.0 if mode == codes.STICK else xd0 - p[V]
    st[S_MODE] = mode
    st[S_ARMED] = 1.0 if st[S_ZD] != 0.0 else 0.0
    omega = math.sqrt(p[K] / p[M])
    st[S_H] = 0.05 / max(omega, top_frequency(fx))
    st[S_N] = 0.0
    st[S_SECTIONS] = 0.0
    st[S_TRACK] = 0.0
    return mode


# ---------------------------------------------------------------- the phases
@kernel
def stick_until_slip(st, p, lw, fx, acc, t_stop):
    """Stick phase in closed form (x moves with the belt) until the holding force
    leaves the band (the excitation's ``stick_exit``) or t_stop."""
    v = p[V]
    t = st[S_T]
    x = st[S_X]
    dt, slips, mode, xs = stick_exit(fx, t, x, p, lw, t_stop)
    t1 = t + dt if slips else t_stop
    x1 = x + v * dt
    ix = dt * (x + 0.5 * v * dt)
    acc[A_IX] += ix
    acc[A_IXD2] += v * v * dt
    # r_a = -(k x + c v) while stuck (and + e(t) under a load: not booked here)
    acc[A_WF] += -p[K] * v * ix - p[C] * v * v * dt
    acc[A_TSTICK] += dt
    acc[A_DT] += dt
    st[S_T] = t1
    if slips:
        st[S_X] = xs
        st[S_ZD] = 0.0
        st[S_MODE] = mode
        st[S_ARMED] = 0.0
        _note_x(acc, st[S_X], v)
        if st[S_TRACK] > 0.0:
            _salt_release(st, p, lw, fx)
        return codes.EV_SLIP, codes.OK
    st[S_X] = x1
    _note_x(acc, x1, v)
    return codes.EV_STOP_TIME, codes.OK


@kernel(inline="always")
def _book(acc, qx, qv, qw, ql, h):
    """Add a step's quadratures and its duration to the accumulators."""
    acc[A_IX] += qx
    acc[A_IXD2] += qv
    acc[A_WF] += qw
    acc[A_ILAW] += ql
    acc[A_DT] += h


@kernel
def _finish_zero(meth, st, p, lw, fx, o, acc, x0, zd0, s, h, xe, touched, a0, cf, dc, H,
                 part):
    """Book the partial step to a zdot = 0 event at h and apply the stop rules;
    ``touched``: the event is a tangential touch (``st[S_TOUCH]``), whose stop or
    stick the integrator decided within its touch tolerance only. ``a0``: zdd at
    the step's start, for an extremum of xdot before the event (an overshoot past
    the belt speed that turns back and sticks within the step). ``dc``: the
    interpolant of the step ``H`` that holds the event. ``part``: the partial step
    ``(x, zdot, quadratures)`` when already taken (``_confirmed``), else NaNs."""
    t0 = st[S_T]
    xr, zr, qx, qv, qw, ql = part
    if xr != xr:
        xr, zr, qx, qv, qw, ql, _e, _ok, ks = step_kept(meth, t0, x0, zd0, h, s, p, lw, fx,
                                                        o, True)
        st[S_N] += 1.0
        if st[S_TRACK] > 0.0:
            _track(meth, st, p, lw, fx, o, t0, x0, zd0, s, h, xr, zr, ks)
    elif st[S_TRACK] > 0.0:
        _track_partial(meth, st, p, lw, fx, o, t0, x0, zd0, s, h)
    _book(acc, qx, qv, qw, ql, h)
    _velocity_extremum(meth, st, p, lw, fx, o, acc, t0, x0, zd0, s, h, a0,
                       field_accel(fx, t0 + h, xe, 0.0, s, cf, lw, p[K], p[M]), dc, H)
    if has_dense(meth):
        # located on the interpolant: the integrator's state there, and for a
        # crossing its own zero (a touch is placed at its turning point, where the
        # time of zdot = 0 is ill-conditioned)
        xe = xr
        if not touched:
            xe, dt = _on_root(acc, xr, zr, 0.0, s, cf, lw, p, fx, t0 + h)
            h += dt
    st[S_T] += h
    new, ev, xn = zero_mode(fx, xe, st[S_T], s, p, lw, touch_tol(p, o))
    if st[S_TRACK] > 0.0:
        _salt_zero(st, p, lw, fx, xe, s, new)
    st[S_X] = xn
    st[S_ZD] = 0.0
    st[S_MODE] = new
    st[S_ARMED] = 0.0
    st[S_TOUCH] = 1.0 if touched else 0.0
    if new == codes.STICK:
        acc[A_NSTICK] += 1.0
    else:
        acc[A_NSTOP] += 1.0
    _note_x(acc, xn, p[V])
    return ev


@kernel
def _section(meth, st, p, lw, fx, o, acc, x, zd, z1, s, t, h, h_ev, a0, a1, cf, dc):
    """The extremum of x inside the step from (x, zd) (xdot changes sign): if it
    comes before the zdot = 0 event at h_ev (h_ev < 0: none), book the partial step
    to it and stop there, at the Poincare section (xdot = 0 exactly). Returns its
    event, or EV_NONE when the zdot event comes first.

    With ``st[S_SECTIONS]`` 1 (the attractor search) only the section's extremum
    stops the motion (the maximum for v > 0, the minimum for v < 0); the other is
    noted where the interpolant places it, and stops only where the equilibrium
    certificate holds there (the search answers an equilibrium half a period
    sooner); with 2 (the stroboscopic search) none stops, each is noted. A stop
    costs a partial step and a new start: ~2 stepper calls."""
    v = p[V]
    xd0 = zd + v
    h_xe, xx, zx = polish(meth, F_XD, t, x, zd, s, p, lw, fx, o, 0.0, h,
                          1.0 if xd0 > 0.0 else -1.0,
                          h * cubic_root(xd0, z1 + v, a0 * h, a1 * h), st, dc, h)
    if h_ev >= 0.0 and h_xe >= h_ev:
        return codes.EV_NONE
    if st[S_SECTIONS] > 1.0 or (st[S_SECTIONS] > 0.0 and (xd0 > 0.0) != (v > 0.0) and
                                not certified_rest(xx, zx, p, lw)):
        _note_x(acc, xx, 0.0)
        return codes.EV_NONE
    xr, zr, qx, qv, qw, ql, _e, _ok, ks = step_kept(meth, t, x, zd, h_xe, s, p, lw, fx, o,
                                                    True)
    st[S_N] += 1.0
    if st[S_TRACK] > 0.0:
        _track(meth, st, p, lw, fx, o, t, x, zd, s, h_xe, xr, zr, ks)
    _book(acc, qx, qv, qw, ql, h_xe)
    _velocity_extremum(meth, st, p, lw, fx, o, acc, t, x, zd, s, h_xe, a0,
                       field_accel(fx, t + h_xe, xx, -v, s, cf, lw, p[K], p[M]), dc, h)
    dt = 0.0
    if has_dense(meth):         # located on the interpolant: the integrator's root
        xx, dt = _on_root(acc, xr, zr, -v, s, cf, lw, p, fx, t + h_xe)
    st[S_T] = t + h_xe + dt
    st[S_X] = xx
    st[S_ZD] = -v               # xdot = 0 exactly at the section
    _note_x(acc, xx, 0.0)
    return codes.EV_XMAX if xd0 > 0.0 else codes.EV_XMIN


@kernel
def slide_until_event(meth, st, p, lw, fx, o, acc, t_stop):
    """Integrate the sliding phase until zdot = 0, an extremum of x, or t_stop.
    Helpers taking arrays are called only where something happens: numba passes
    each array with a reference count, which on every step would cost more than the
    event scan."""
    v = p[V]
    s = st[S_MODE]
    cf = constants(p, lw, s)
    m = p[M]
    k = p[K]
    adaptive = ADAPTIVE[meth]
    expo = EXPONENT[meth]
    gtol = touch_tol(p, o)
    near = max(gtol, 1e-3 * o[O_LV])
    omega = math.sqrt(k / m)
    while True:
        t = st[S_T]
        if t >= t_stop:
            return codes.EV_STOP_TIME, codes.OK
        if st[S_N] >= o[O_MAX_STEPS]:
            return codes.EV_STOP_TIME, codes.STEP_BUDGET
        x = st[S_X]
        zd = st[S_ZD]
        h, a0 = _capped(proposal(meth, x, zd, s, p, lw, o, st[S_H]), x, zd, s, cf, lw, k,
                        m, v, o, omega, adaptive)
        h = capped(fx, h)
        last = t + h >= t_stop
        if last:
            h = t_stop - t
        if h <= EPS * max(abs(t), 1.0):
            # below the resolution of t: only the remainder up to t_stop may be
            # dropped; a step that cannot advance the clock is a failure, not a jump
            if not last:
                return codes.EV_STOP_TIME, codes.STEP_UNDERFLOW
            st[S_T] = t_stop
            return codes.EV_STOP_TIME, codes.OK
        x1, z1, qx, qv, qw, ql, err, ok, ks = step_kept(meth, t, x, zd, h, s, p, lw, fx, o,
                                                        True)
        st[S_N] += 1.0
        if not ok:                  # GPS denominator guard: halve the step
            ok, h, x1, z1, qx, qv, qw, ql = _halved(meth, st, p, lw, fx, o, t, x, zd, s, h,
                                                    omega)
            if not ok:
                return codes.EV_STOP_TIME, codes.GPS_DENOMINATOR
            last = False
        if adaptive:
            st[S_H] = _next_step(h, err, expo)
            if not (err <= 1.0):
                continue
        if not (abs(x1) < 1e12 * o[O_LX] and abs(z1) < 1e12 * omega * o[O_LX]):
            return codes.EV_STOP_TIME, codes.DIVERGED
        # the load at the step's ends, as its stages took it (the last step_load)
        im = 1.0 / m
        if a0 != a0:                # not taken by the step bound
            a0 = accel(x, zd, s, cf, lw, k, m)
        a0 = start_load(fx, a0, im)
        a1 = end_load(fx, accel(x1, z1, s, cf, lw, k, m), im)
        sec, turns, h_ev, xe, touched, part, dc = _scan(meth, st, p, lw, fx, o, t, x, zd,
                                                        x1, z1, s, h, a0, a1, ks, gtol,
                                                        near, cf)
        # --- extremum of x (Poincare section) inside the step
        if sec:
            ev = _section(meth, st, p, lw, fx, o, acc, x, zd, z1, s, t, h, h_ev, a0, a1,
                          cf, dc)
            if ev != codes.EV_NONE:
                return ev, codes.OK
        if h_ev >= 0.0:
            return _finish_zero(meth, st, p, lw, fx, o, acc, x, zd, s, h_ev, xe,
                                touched, a0, cf, dc, h, part), codes.OK
        if turns:
            _velocity_extremum(meth, st, p, lw, fx, o, acc, t, x, zd, s, h, a0, a1, dc, h)
        if st[S_TRACK] > 0.0:
            _track(meth, st, p, lw, fx, o, t, x, zd, s, h, x1, z1, ks)
        _accept(st, acc, t + h if not last else t_stop, h, x1, z1, v, qx, qv, qw, ql)
        if last:
            return codes.EV_STOP_TIME, codes.OK


@kernel(inline="always")
def _scan(meth, st, p, lw, fx, o, t, x, zd, x1, z1, s, h, a0, a1, ks, gtol, near, cf):
    """What the accepted step h from (x, zd) at t to (x1, z1) holds: ``(sec, turns,
    h_ev, x_ev, touched, part, dc)``: whether x turns (a Poincare section when v != 0)
    and xdot turns inside it, the first zdot = 0 event (crossings, double crossings
    and touches; h_ev < 0: none; ``events.zero_in_step``), and the step's interpolant
    ``dc``, built from the slopes ``ks`` it kept where something is to be located."""
    v = p[V]
    g0 = s * zd
    g1 = s * z1
    kind, ta, tb, tc, armed = zd_event(g0, g1, s * a0 * h, s * a1 * h,
                                       st[S_ARMED] > 0.0, near)
    st[S_ARMED] = 1.0 if armed else 0.0
    h_ev, xe, touched, part = -1.0, x1, False, NO_PART
    sec = v != 0.0 and zd + v != 0.0 and (zd + v > 0.0) != (z1 + v > 0.0)
    turns = a0 != 0.0 and (a0 > 0.0) != (a1 > 0.0)
    ends = _ends_on_touch(g0, g1, s * a1 * h, gtol, armed)
    dc = (0.0,) * 14
    if kind != 0 or sec or turns or ends:
        # something to locate inside the step: its interpolant (no stepper call)
        dc = extend(meth, t, x, zd, h, s, p, lw, fx, x1, z1, ks)
    if kind != 0:
        h_ev, xe, touched, part = zero_in_step(meth, st, p, lw, fx, o, t, x, zd, s, h, a0,
                                               a1, g0, g1, kind, ta, tb, tc, gtol, cf, dc)
    if h_ev < 0.0 and ends:
        h_ev, xe, touched = h, x1, True
    return sec, turns, h_ev, xe, touched, part, dc


@kernel(inline="always")
def _accept(st, acc, t1, h, x1, z1, v, qx, qv, qw, ql):
    """Book a step h that holds no event and move the state to its end (x1, z1) at
    the time t1."""
    _book(acc, qx, qv, qw, ql, h)
    st[S_T] = t1
    st[S_X] = x1
    st[S_ZD] = z1
    _note_x(acc, x1, z1 + v)


@kernel(inline="always")
def _ends_on_touch(g0, g1, a1h, gtol, armed):
    """The step ends on a touch: zdot (as ``g = s zdot``) stopped falling within the
    touch tolerance of 0 (exact arcs end on turning points; also where the step's
    cubic dipped below 0 by rounding just before its end)."""
    return armed and 0.0 < g1 <= gtol and g1 < g0 and a1h >= -gtol


@kernel(inline="always")
def _capped(h, x, zd, s, cf, lw, k, m, v, o, omega, adaptive):
    """An adaptive step at most half a natural time and what the law's own layer
    allows (``law.step_bound``): ``(h, zdd at the step's start)``, zdd NaN where
    the bound did not need it. (The bound also keeps the error of dop853 at tol
    1e-8 below tol: with 1/omega instead, the map takes 4 % fewer stepper calls but
    bSTAB's stick-slip cycles next to the fold are 1e-8 L off, against 2e-10 L.)"""
    a0 = np.nan
    if adaptive:
        h = min(h, 0.5 / omega)
        hb, a0 = step_bound(x, zd, s, cf, lw, k, m, v, o[O_RTOL] * o[O_LV])
        h = min(h, hb)
    return h, a0


@kernel(inline="always")
def _next_step(h, err, expo):
    """The controller's next step [s] after a step h with scaled error err: shrunk
    (at least 5x) after a rejection, grown at most 5x after an acceptance."""
    if not (err <= 1.0):
        return h * (0.2 if not (err < 1e300) else max(0.2, 0.9 * _power(err, expo)))
    return h * min(5.0, max(0.2, 0.9 * _power(err + 1e-300, expo)))


@kernel(inline="always")
def _power(e, expo):
    """``e ** expo`` for e > 0: dop853's -1/8 by three square roots (a call of
    ``pow`` was 5 % of the map's kernel time)."""
    if expo == -0.125:
        return 1.0 / math.sqrt(math.sqrt(math.sqrt(e)))
    return e ** expo


@kernel
def _halved(meth, st, p, lw, fx, o, t, x, zd, s, h, omega):
    """The GPS denominator guard: the step halved until it can be taken, down to
    1e-12/omega: ``(ok, h, x1, z1, qx, qv, qw, ql)``."""
    ok = False
    x1, z1, qx, qv, qw, ql = x, zd, 0.0, 0.0, 0.0, 0.0
    while not ok and h > 1e-12 / omega:
        h *= 0.5
        x1, z1, qx, qv, qw, ql, _err, ok = step(meth, t, x, zd, h, s, p, lw, fx, o, True)
        st[S_N] += 1.0
    return ok, h, x1, z1, qx, qv, qw, ql


@kernel
def _velocity_extremum(meth, st, p, lw, fx, o, acc, t, x, zd, s, h, a0, a1, dc, H):
    """Record an extremum of xdot (zdd = 0) inside [0, h] of the step H from (x, zd)
    at t (interpolant ``dc``)."""
    if a0 != 0.0 and (a0 > 0.0) != (a1 > 0.0):
        _h, xv, zv = polish(meth, F_XDOT_EXTREMUM, t, x, zd, s, p, lw, fx, o, 0.0, h,
                            1.0 if a0 > 0.0 else -1.0, h * a0 / (a0 - a1), st, dc, H)
        _note_x(acc, xv, zv + p[V])


@kernel
def _on_root(acc, xr, zr, zt, s, cf, lw, p, fx, t):
    """From the integrator's state ``(xr, zr)`` at t at a root of ``zdot - zt`` found
    on the interpolant, one Newton step in time to the integrator's own root:
    ``(x there, dt)``, with the quadratures of ``dt`` booked (Taylor to first order;
    dt is the interpolant's error, so what is left is of its square)."""
    v = p[V]
    a = field_accel(fx, t, xr, zr, s, cf, lw, p[K], p[M])
    if a == 0.0:
        return xr, 0.0
    dt = (zt - zr) / a
    xd = zr + v
    _book(acc, xr * dt, xd * xd * dt, friction_force(lw, cf, zr, s) * xd * dt,
          integrand(lw, cf, zr) * dt, dt)
    return xr + dt * (xd + 0.5 * a * dt), dt


# ------------------------------------------------------------- the tangent
@kernel
def _track(meth, st, p, lw, fx, o, t, x, zd, s, h, x1, z1, ks):
    """The tangent through the step h from (x, zd) at t to (x1, z1)."""
    j = (st[S_J], st[S_J + 1], st[S_J + 2], st[S_J + 3])
    n11, n12, n21, n22 = tangent(meth, j, t, x, zd, h, s, p, lw, fx, o, x1, z1, ks, st)
    st[S_J] = n11
    st[S_J + 1] = n12
    st[S_J + 2] = n21
    st[S_J + 3] = n22


@kernel
def _track_partial(meth, st, p, lw, fx, o, t, x, zd, s, h):
    """The tangent through the partial step h to an event (the step taken again
    for the slopes the tangent needs)."""
    x1, z1, _a, _b, _c, _d, _e, _ok, ks = step_kept(meth, t, x, zd, h, s, p, lw, fx, o,
                                                    True)   # one compiled copy
    st[S_N] += 1.0
    _track(meth, st, p, lw, fx, o, t, x, zd, s, h, x1, z1, ks)


@kernel
def _salt_zero(st, p, lw, fx, x, s, new):
    """The saltation of zdot reaching 0 at x while sliding with sign s, into mode
    ``new``: the event surface zdot = 0, so x's row stays and zdot's row is scaled by
    the ratio of the accelerations after and before (0 for a stick: it forgets the
    velocity)."""
    ratio = 0.0
    if new != codes.STICK:
        t = st[S_T]
        before = field_accel(fx, t, x, 0.0, s, constants(p, lw, s), lw, p[K], p[M])
        sn = float(new)
        after = field_accel(fx, t, x, 0.0, sn, constants(p, lw, sn), lw, p[K], p[M])
        ratio = after / before if before != 0.0 else 1.0
    st[S_J + 2] *= ratio
    st[S_J + 3] *= ratio


@kernel
def _salt_release(st, p, lw, fx):
    """The saltation of a release from a stick at the state in st: the event surface
    is ``h(t, x) = e(t) - k x - c v`` at the band's edge, the stick's field (v, 0)
    meets the slide's (v, a+), so zdot's row gains ``-k a+ / h'(t)`` times x's row
    (h' = e' - k v; a+ = 0 where the static limit is the sliding force's own limit)."""
    s = st[S_MODE]
    t = st[S_T]
    a_plus = field_accel(fx, t, st[S_X], 0.0, s, constants(p, lw, s), lw, p[K], p[M])
    rate = load_rate(fx, t) - p[K] * p[V]
    if a_plus != 0.0 and rate != 0.0:
        g = -p[K] * a_plus / rate
        st[S_J + 2] += g * st[S_J]
        st[S_J + 3] += g * st[S_J + 1]


@kernel(inline="always")
def advance(meth, st, p, lw, fx, o, acc, t_stop):
    """Advance to the next event or to t_stop; returns (event, status)."""
    if st[S_MODE] == codes.STICK:
        return stick_until_slip(st, p, lw, fx, acc, t_stop)
    return slide_until_event(meth, st, p, lw, fx, o, acc, t_stop)
