"""Locating events inside one sliding step: where zdot = 0, where x or xdot turn.

The step's Hermite cubic of ``g = s zdot`` (values and ``zdd`` at both ends) is
split at its critical points into monotone pieces (``zd_event``), so two crossings
inside one step and a touch between two samples are both seen (a sign test at the
step's ends sees neither). A root is then polished by safeguarded Newton
(``polish``) on the step's continuous extension (dop853, dopri5) or on re-steps of
the integrator (the fixed-step methods); the driver then takes the integrator's own
state at the root (``driver.py``).
"""
import math

import numpy as np

from .jit import kernel

from .excitation import field_accel, field_jerk
from .law import constants
from .layout import K, M, O_LV, O_RTOL, S_N, V
from .stepper import has_dense, state_at, step

EPS = np.finfo(np.float64).eps

# functions whose roots are polished on re-steps. Floats, not ints: numba types an
# int constant as a literal and would compile ``polish`` once per value, with every
# branch of ``_fun`` in each copy; a float is an ordinary argument.
F_ZD = 0.0
F_XD = 1.0
F_ZDD = 2.0
F_XDOT_EXTREMUM = 3.0   # zdd, as F_ZDD, for an extremum of xdot that is only noted
# a simple root (x or xdot turning) is taken once Newton's step is below this share
# of the bracket's end: the next step would be of its square (quadratic convergence)
NEWTON_DONE = 1e-8
NO_PART = (np.nan,) * 6        # no partial step taken (``zero_in_step``)


@kernel(inline="always")
def _fun(which, t, x, zd, s, p, lw, fx):
    """The function ``which`` at the state (x, zd) at time t, and its time derivative
    along the slide."""
    v = p[V]
    cf = constants(p, lw, s)
    a = field_accel(fx, t, x, zd, s, cf, lw, p[K], p[M])
    if which == F_ZD:
        return zd, a
    if which == F_XD:
        return zd + v, a
    return a, field_jerk(fx, t, x, zd, s, cf, lw, p[K], p[M], v)


@kernel
def polish(meth, which, t, x, zd, s, p, lw, fx, o, lo, hi, sign_lo, guess, st, dc, H):
    """Root in (lo, hi] of F(h) = fun(state at h into the step H from (x, zd) at t);
    F(lo) has sign ``sign_lo``. The state is the interpolant ``dc`` of the step
    where the method has one, else a re-step (``stepper.state_at``).

    Safeguarded Newton: Newton steps inside the bracket, bisection otherwise.
    Returns (h, x1, zd1). The turning points of x and of a noted xdot (``F_XD``,
    ``F_XDOT_EXTREMUM``) are simple roots: once a Newton step is below
    ``NEWTON_DONE`` of the bracket, it is taken and the state moved to its end to
    first order on the interpolant (both errors of the step's square, ~1e-16 h):
    one evaluation fewer than confirming a step at rounding level. Roots of zdot
    and its turning points near touches (double roots, linear convergence), and
    every root of the methods without an interpolant (re-steps), are polished to
    rounding.
    """
    v = p[V]
    simple = (which == F_XD or which == F_XDOT_EXTREMUM) and has_dense(meth)
    h = guess if lo < guess <= hi else 0.5 * (lo + hi)
    x1 = x
    z1 = zd
    for _ in range(60):
        x1, z1 = state_at(meth, t, x, zd, h, s, p, lw, fx, o, dc, H, st)
        f, df = _fun(which, t + h, x1, z1, s, p, lw, fx)
        if f == 0.0:
            break
        if (f > 0.0) == (sign_lo > 0.0):
            lo = h
        else:
            hi = h
        if hi - lo <= 2.0 * EPS * hi:
            break
        hn = h - f / df if df != 0.0 else 0.5 * (lo + hi)
        if not (lo < hn < hi):
            hn = 0.5 * (lo + hi)
        elif simple and abs(hn - h) <= NEWTON_DONE * hi:
            dh = hn - h
            return hn, x1 + dh * (z1 + v), z1 + dh * (df if which == F_XD else f)
        if abs(hn - h) <= 2.0 * EPS * hi:
            h = hn
            x1, z1 = state_at(meth, t, x, zd, h, s, p, lw, fx, o, dc, H, st)
            break
        h = hn
    return h, x1, z1


@kernel(inline="always")
def cubic(f0, f1, d0, d1, th):
    """Cubic Hermite interpolant on [0, 1] (values f, theta-derivatives d)."""
    a = 2.0 * (f0 - f1) + d0 + d1
    b = 3.0 * (f1 - f0) - 2.0 * d0 - d1
    return ((a * th + b) * th + d0) * th + f0


@kernel(inline="always")
def cubic_root(f0, f1, d0, d1):
    """A root in (0, 1) of the Hermite cubic (values f, theta-derivatives d) whose
    end values differ in sign: the secant's, improved by two Newton steps on the
    cubic where they stay inside (0, 1). A start for ``polish`` within ~h^4 of the
    root where the secant's is within ~h^2."""
    th = f0 / (f0 - f1)
    a = 2.0 * (f0 - f1) + d0 + d1
    b = 3.0 * (f1 - f0) - 2.0 * d0 - d1
    for _ in range(2):
        df = (3.0 * a * th + 2.0 * b) * th + d0
        if df == 0.0:
            break
        tn = th - (((a * th + b) * th + d0) * th + f0) / df
        if not (0.0 < tn < 1.0):
            break
        th = tn
    return th


@kernel
def _critical(f0, f1, d0, d1):
    """Critical points in (0, 1) of the Hermite cubic, sorted; (n, t1, t2)."""
    a = 3.0 * (2.0 * (f0 - f1) + d0 + d1)
    b = 2.0 * (3.0 * (f1 - f0) - 2.0 * d0 - d1)
    c = d0
    r1 = -1.0
    r2 = -1.0
    scale = abs(a) + abs(b) + abs(c)
    if scale == 0.0:
        return 0, 0.0, 0.0
    if abs(a) <= 1e-14 * scale:
        if b != 0.0:
            r1 = -c / b
    else:
        disc = b * b - 4.0 * a * c
        if disc >= 0.0:
            sq = math.sqrt(disc)
            q = -0.5 * (b + (sq if b >= 0.0 else -sq))
            if q != 0.0:
                r1 = q / a
                r2 = c / q
            else:
                r1 = -b / (2.0 * a)
    if r1 > r2:
        r1, r2 = r2, r1
    n = 0
    t1 = 0.0
    t2 = 0.0
    for r in (r1, r2):
        if 0.0 < r < 1.0:
            if n == 0:
                t1 = r
            else:
                t2 = r
            n += 1
    return n, t1, t2



@kernel
def zd_event(g0, g1, d0, d1, armed, near):
    """Scan the Hermite cubic of g = s zdot over a step.

    Returns (kind, th_a, th_b, th_c, armed): kind 0 nothing, 1 crossing bracketed
    in [th_a, th_b], 2 a turning point th_c (local min of g, bracketed by th_a, th_b)
    whose value is within ``near`` of 0 and must be checked on the integrator.
    """
    # The cubic is linear interpolation plus th (1 - th) [A (1 - th) - B th] with
    # A = d0 - (g1 - g0), B = d1 - (g1 - g0): it stays above min(g0, g1) - max|A, B|/4.
    # When that bound is above `near` nothing can be found: skip the scan.
    dg = g1 - g0
    if armed and min(g0, g1) - 0.25 * max(abs(d0 - dg), abs(d1 - dg)) > near:
        return 0, 0.0, 0.0, 0.0, armed
    n, c1, c2 = _critical(g0, g1, d0, d1)
    # candidate points 0 < critical points < 1; g is monotone between neighbours
    if n == 0:
        pts = (0.0, 1.0, 1.0, 1.0)
    elif n == 1:
        pts = (0.0, c1, 1.0, 1.0)
    else:
        pts = (0.0, c1, c2, 1.0)
    k = n + 2
    start = 0
    if not armed:
        # A start on the switching line (g0 = 0) is never itself an event: skip to
        # the first interior maximum of g (zdot turning back towards 0).
        start = -1
        if g0 > 0.0 and d0 <= 0.0:
            start = 0
        else:
            a = 2.0 * (g0 - g1) + d0 + d1
            b = 3.0 * (g1 - g0) - 2.0 * d0 - d1
            for i in range(1, k - 1):
                th = pts[i]
                if 6.0 * a * th + 2.0 * b < 0.0 and cubic(g0, g1, d0, d1, th) > 0.0:
                    start = i
                    break
        if start < 0:
            return 0, 0.0, 0.0, 0.0, g1 > 0.0 and d1 <= 0.0
        armed = True
    for i in range(start, k - 1):
        ta = pts[i]
        tb = pts[i + 1]
        gb = cubic(g0, g1, d0, d1, tb)
        if tb == 1.0:
            gb = g1
        if gb <= 0.0:
            return 1, ta, tb, 0.0, armed
        if i + 1 < k - 1 and gb <= near:
            a = 2.0 * (g0 - g1) + d0 + d1
            b = 3.0 * (g1 - g0) - 2.0 * d0 - d1
            if 6.0 * a * tb + 2.0 * b > 0.0:       # local minimum of g
                return 2, ta, pts[i + 2], tb, armed
    return 0, 0.0, 0.0, 0.0, armed


# ------------------------------------------- zdot = 0 inside a step
@kernel
def zero_in_step(meth, st, p, lw, fx, o, t, x, zd, s, h, a0, a1, g0, g1, kind, ta, tb, tc,
                 gtol, cf, dc):
    """Where zdot = 0 inside the step h from (x, zd), once ``zd_event`` found a
    crossing or a possible touch (``kind``): ``(h_ev, x_ev, touched, part)``, h_ev < 0
    when there is none, ``part`` the partial step to h_ev when it was taken to
    confirm the root (``_confirmed``), else ``NO_PART``. Located on the step's
    interpolant ``dc``; a crossing the integrator does not confirm there (a layer
    of the law at zdot = 0 that the polynomial does not resolve) on re-steps."""
    part = NO_PART
    h_ev, xe, touched = _locate_zero(meth, st, p, lw, fx, o, t, x, zd, s, h, a0, a1, g0,
                                     g1, kind, ta, tb, tc, gtol, cf, dc, h)
    if has_dense(meth) and h_ev >= 0.0 and not touched:
        good, part = _confirmed(meth, st, p, lw, fx, o, t, x, zd, s, h_ev, cf)
        if not good:
            part = NO_PART
            h_ev, xe, touched = _locate_zero(meth, st, p, lw, fx, o, t, x, zd, s, h, a0,
                                             a1, g0, g1, kind, ta, tb, tc, gtol, cf, dc,
                                             0.0)
    return h_ev, xe, touched, part


@kernel
def _crossing_root(meth, st, p, lw, fx, o, t, x, zd, s, h, g0, g1, d0, d1, ta, tb, dc,
                   H):
    """The first root of zdot in the bracket [ta, tb] (fractions of the step h) of
    the Hermite cubic of g = s zdot, if the integrator confirms it: ``(h_ev, x_ev)``
    (h_ev < 0: none). Newton starts from the cubic's own root (bisection on it)."""
    gb = g1
    if tb < 1.0:
        _xb, zb = state_at(meth, t, x, zd, tb * h, s, p, lw, fx, o, dc, H, st)
        gb = s * zb
    if gb > 0.0:
        return -1.0, x
    ca = ta
    cb = tb
    for _ in range(12):     # a start for polish's Newton steps: 2.4e-4 of the bracket
        cm = 0.5 * (ca + cb)
        if cubic(g0, g1, d0, d1, cm) > 0.0:
            ca = cm
        else:
            cb = cm
    h_ev, xe, _ze = polish(meth, F_ZD, t, x, zd, s, p, lw, fx, o, ta * h, tb * h, s,
                           0.5 * (ca + cb) * h, st, dc, H)
    return h_ev, xe


@kernel
def _locate_zero(meth, st, p, lw, fx, o, t, x, zd, s, h, a0, a1, g0, g1, kind, ta, tb, tc,
                 gtol, cf, dc, H):
    """Where zdot = 0 inside the step from (x, zd), once the scan of the step's
    Hermite cubic (``events.zd_event``) found a crossing (kind 1, bracketed in
    [ta, tb]) or a turning point tc that may touch 0 (kind 2). Touches are placed at
    the turning point, where they are well conditioned. Returns ``(h_ev, x_ev,
    touched)``, h_ev < 0 when the integrator does not confirm it. ``dc``: the step's
    interpolant, used for times up to ``H`` (``H = h``; 0: re-steps only).

    A crossing of the cubic that the integrator does not confirm, in a step where
    zdd turns towards 0 and back (g has an interior minimum), is checked at that
    turning point as for kind 2: the cubic's error there can exceed a small
    excursion past 0, and the step would otherwise pass a real stick or touch."""
    v = p[V]
    h_ev = -1.0
    xe = x
    crossing = False
    lo, hi = 0.5 * (ta + tc), 0.5 * (tc + tb)      # the turning point's bracket
    if kind == 1:
        h_ev, xe = _crossing_root(meth, st, p, lw, fx, o, t, x, zd, s, h, g0, g1,
                                  s * a0 * h, s * a1 * h, ta, tb, dc, H)
        crossing = h_ev >= 0.0
        if not crossing and s * a0 < 0.0 < s * a1:
            kind, ta, tc, lo, hi = 2, 0.0, a0 / (a0 - a1), 0.0, 1.0
    if kind == 2:                   # check the turning point on the integrator
        # zdd has the sign -s where g falls towards the touch, +s after it
        hc, xc, zc = polish(meth, F_ZDD, t, x, zd, s, p, lw, fx, o, lo * h, hi * h, -s,
                            tc * h, st, dc, H)
        gc = s * zc
        if abs(gc) <= gtol:         # a touch
            return hc, xc, True
        if gc < 0.0:                # a real double crossing: the first root
            h_ev, xe, _ze = polish(meth, F_ZD, t, x, zd, s, p, lw, fx, o, ta * h, hc, s,
                                   0.5 * (ta * h + hc), st, dc, H)
            crossing = True
    if crossing:
        # A crossing whose excursion past 0 stays within the graze tolerance is a
        # touch: its root is ill-conditioned (error ~ sqrt(eps)), its turning
        # point (zdd = 0) is not, so the touch is placed there.
        gp = s * field_accel(fx, t + h_ev, xe, 0.0, s, cf, lw, p[K], p[M])
        gpp = s * field_jerk(fx, t + h_ev, xe, 0.0, s, cf, lw, p[K], p[M], v)
        if gp < 0.0 and gpp > 0.0 and gp * gp <= 2.0 * gpp * gtol:
            tau = -gp / gpp
            h_ev, xe, _zc = polish(meth, F_ZDD, t, x, zd, s, p, lw, fx, o, h_ev,
                                   h_ev + 2.0 * tau, -s, h_ev + tau, st, dc, H)
            return h_ev, xe, True
    return h_ev, xe, False


@kernel
def _confirmed(meth, st, p, lw, fx, o, t, x, zd, s, h, cf):
    """Whether the integrator confirms a zero of zdot found on the interpolant at
    ``h``: one Newton step in time from its state there lands where the acceleration
    has changed so little that the step's neglected second-order term moves zdot by
    under 1e-3 of its tolerance ``rtol lv``. Returns ``(confirmed, the partial
    step: x, zdot and its quadratures)``, the step kept for ``_finish_zero``."""
    xr, zr, qx, qv, qw, ql, _e, _ok = step(meth, t, x, zd, h, s, p, lw, fx, o, True)
    st[S_N] += 1.0
    part = (xr, zr, qx, qv, qw, ql)
    a = field_accel(fx, t + h, xr, zr, s, cf, lw, p[K], p[M])
    if a == 0.0:
        return False, part
    dt = -zr / a
    a1 = field_accel(fx, t + h + dt, xr + (zr + p[V]) * dt, 0.0, s, cf, lw, p[K], p[M])
    return abs(a1 - a) * abs(dt) <= 1e-3 * o[O_RTOL] * o[O_LV], part
