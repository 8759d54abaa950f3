"""An independent reference: the hybrid belt oscillator integrated with scipy, from the physics.

Shares no code with sweepcore (nothing here imports it). Units kN, cm, s.

Model (sweepcore's sign conventions). A slider of mass m on a belt moving at speed v,
spring k, viscous damper c on the slider, friction force r_a:

    m x'' + c x' + k x + r_a = 0,        zdot = x' - v   (relative velocity)

* sliding (zdot != 0): r_a = F(zdot) with the friction-law family
  ``F(s) = sgn(s) (r_k + (r_y - r_k) exp(-|s|/v_s)) - alpha1 s + alpha2 s^3``;
  r_k = r_y is the cubic law (then v_s plays no role), alpha1 = alpha2 = 0 and
  r_k = r_y the constant Coulomb law;
* sticking (zdot = 0, x' = v): r_a = -(k x + c v), held while |k x + c v| <= r_y;
  for v > 0 it ends at the breakaway point x_s = (r_y - c v)/k, where sliding starts
  with zdot < 0;
* zdot reaching 0 while sliding: stick if |k x + c v| < r_y, else slide on with
  zdot < 0 if k x + c v >= r_y, with zdot > 0 if k x + c v <= -r_y.

Method. Sliding arcs: DOP853 (rtol 1e-12 .. 1e-13) on the smooth branch of F of the
arc's side, with a terminal event at zdot = 0 (approached from the arc's side), and
non-terminal events at the extrema of x (x' = 0) and of x' (x'' = 0). Sticking: closed
form (x moves with the belt until k x + c v = r_y). v < 0 is served by the exact mirror
symmetry x -> -x, v -> -v (F is odd).

Grazing. Sign-change event detection cannot see a tangential touch of zdot = 0, nor a
crossing whose excursion beyond 0 fits inside one step. Therefore every arc also checks
its extrema of zdot (x'' = 0, a transversal event): an extremum on the wrong side of 0
means a crossing was missed, and it is then located by root finding on the dense output
between the previous extremum and that one (zdot is monotone there). A touch from below
that stays below 0 by less than the integration error cannot be told from a true touch;
such a touch can only happen at the breakaway point (x'' = 0 at zdot = 0- means
k x + c v = r_y), where sticking and sliding on are the same motion, so it does no harm,
and the cycle functions treat it as a return to the breakaway point (``graze_tol``).
"""
import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

__all__ = ["reference_run", "reference_stick_slip_cycle", "reference_slip_cycle",
           "reference_return", "reference_find_slip_cycles", "reference_equilibrium",
           "reference_hopf", "reference_cycle_polygon", "reference_basin_fraction",
           "clip_polygon_to_box", "polygon_area", "reference_fold",
           "reference_breakaway_peak", "friction"]


def friction(s, r_y, r_k=None, v_s=1.0, alpha1=0.0, alpha2=0.0):
    """The sliding friction force F(s) at relative speed s != 0 [kN]; v_s = 0 is the
    limit v_s -> 0+: a jump from the static bound r_y to the kinetic level r_k."""
    r_k = r_y if r_k is None else r_k
    sg = math.copysign(1.0, s)
    decay = math.exp(-abs(s) / v_s) if v_s > 0 else 0.0
    return sg * (r_k + (r_y - r_k) * decay) - alpha1 * s + alpha2 * s ** 3


class _Model:
    """The parameters and the sliding vector field of one branch (side) of F."""

    def __init__(self, m, k, r_y, v, alpha1, alpha2, c=0.0, r_k=None, v_s=1.0):
        self.m, self.k, self.r_y, self.v = float(m), float(k), float(r_y), float(v)
        self.a1, self.a2, self.c = float(alpha1), float(alpha2), float(c)
        self.r_k = self.r_y if r_k is None else float(r_k)
        self.v_s = float(v_s)
        if not (self.m > 0 and self.k > 0 and self.r_y > 0 and self.v_s >= 0
                and self.r_k >= 0):
            raise ValueError("need m, k, r_y > 0 and v_s, r_k >= 0")
        if self.v_s == 0.0 or self.r_k == self.r_y:
            self.dr, self.v_s = 0.0, 1.0        # no Stribeck term (v_s = 0: a jump)
        else:
            self.dr = self.r_y - self.r_k
        self.omega = math.sqrt(self.k / self.m)
        self.x_s = (self.r_y - self.c * self.v) / self.k      # breakaway point (v > 0)

    def force(self, s, sgn):
        """F on the branch of side sgn (+1 or -1), continued analytically past s = 0
        (the exponent is capped at 60 only to keep trial stages of tiny v_s finite)."""
        f = sgn * (self.r_k + self.dr * math.exp(min(-sgn * s / self.v_s, 60.0))) \
            - self.a1 * s
        return f + self.a2 * s ** 3 if self.a2 else f

    def dforce(self, s, sgn):
        """dF/ds on the branch of side sgn (analytic; used for Liouville's formula)."""
        return -self.dr / self.v_s * math.exp(min(-sgn * s / self.v_s, 60.0)) - self.a1 \
            + 3.0 * self.a2 * s * s

    def acc(self, x, zd, sgn):
        """x'' = zdot' while sliding on side sgn."""
        return (-self.k * x - self.c * (zd + self.v) - self.force(zd, sgn)) / self.m

    def stick_load(self, x):
        """k x + c v: the force sticking has to hold (|.| <= r_y)."""
        return self.k * x + self.c * self.v

    def side_after_stop(self, x):
        """0 (stick), -1 or +1 (slide on that side) at zdot = 0, position x."""
        load = self.stick_load(x)
        if load >= self.r_y:
            return -1
        if load <= -self.r_y:
            return 1
        return 0


# ------------------------------------------------------------------ hybrid motion
def _slip_window(mod, t0, y0, sgn, t_end, rtol, atol):
    """Slide on side sgn from t0, state y0 = [x, zdot, int x dt], until zdot reaches 0
    (from side sgn) or t_end. Returns a dict: t0, t1, sol (dense), y1 (state at t1),
    crossed (bool), turns [(t, x, zdot, 'min' or 'max')] (extrema of zdot) and stills
    [(t, x)] (x' = 0),
    both restricted to (t0, t1]."""
    v = mod.v

    def rhs(_t, y):
        return [y[1] + v, mod.acc(y[0], y[1], sgn), y[0]]

    def cross(_t, y):
        return y[1]
    cross.terminal = True
    cross.direction = -sgn

    def tmin(_t, y):              # x'' = 0 rising: a minimum of zdot
        return mod.acc(y[0], y[1], sgn)
    tmin.direction = 1

    def tmax(_t, y):              # x'' = 0 falling: a maximum of zdot
        return mod.acc(y[0], y[1], sgn)
    tmax.direction = -1

    def still(_t, y):
        return y[1] + v

    sol = solve_ivp(rhs, (t0, t_end), list(y0), method="DOP853", rtol=rtol, atol=atol,
                    events=[cross, tmin, tmax, still], dense_output=True)
    if sol.status < 0:
        raise RuntimeError(sol.message)
    t1, y1, crossed = float(sol.t[-1]), np.array(sol.y[:, -1]), sol.status == 1
    if crossed:
        y1[1] = 0.0
    # a crossing hidden inside one step shows as an extremum of zdot on the wrong side
    scale = 1e-14 * (abs(v) + abs(y0[1]) + mod.r_y / math.sqrt(mod.k * mod.m))
    turns = sorted([(float(te), float(ye[0]), float(ye[1]), kind)
                    for i, kind in ((1, "min"), (2, "max"))
                    for te, ye in zip(sol.t_events[i], sol.y_events[i]) if te > t0])
    prev = t0
    for te, _xe, zde, _kind in turns:
        if te >= t1:
            break
        if sgn * zde < -scale:
            tc = brentq(lambda t: sol.sol(t)[1], prev, te, xtol=1e-15 * (1 + abs(te)),
                        rtol=8.9e-16)
            t1, y1, crossed = tc, np.array(sol.sol(tc)), True
            y1[1] = 0.0
            break
        prev = te
    turns = [tu for tu in turns if tu[0] <= t1]
    stills = [(float(te), float(ye[0]))
              for te, ye in zip(sol.t_events[3], sol.y_events[3]) if t0 < te <= t1]
    return dict(t0=t0, t1=t1, sol=sol, y1=y1, crossed=crossed, turns=turns,
                stills=stills, sgn=sgn)


def _hybrid(mod, t0, x0, zd0, t_end, rtol, side=None, stop_at_breakaway=False,
            graze_tol=None):
    """Follow the hybrid motion (v > 0) from (x0, zdot0) at t0 until t_end.

    ``side`` forces the initial mode (-1, 0, +1) where zdot0 = 0 (e.g. -1 at the
    breakaway point). With ``stop_at_breakaway`` the motion stops at the first
    breakaway after t0, or at a grazing return (a maximum of zdot within graze_tol of
    0 from below, which is the breakaway point). Returns (segments, events, closed),
    segments being dicts of kind 'stick' (t0, t1, x0) or 'slip' (windows, from
    ``_slip_window``), events [(t, kind, x)], closed = stopped at a breakaway."""
    assert mod.v > 0
    v = mod.v
    atol = rtol * 1e-2 * (mod.r_y / mod.k + v / mod.omega)
    window = 2.0 * math.pi / mod.omega            # integrate at most one period per call
    if zd0 > 0:
        s = 1
    elif zd0 < 0:
        s = -1
    else:
        s = mod.side_after_stop(x0) if side is None else side
    t, x, zd = float(t0), float(x0), float(zd0)
    segments, events = [], []
    while t < t_end:
        if s == 0:
            t_slip = t + (mod.x_s - x) / v
            segments.append(dict(kind="stick", t0=t, t1=min(t_slip, t_end), x0=x))
            if t_slip >= t_end:
                return segments, events, False
            t, x, zd, s = t_slip, mod.x_s, 0.0, -1
            events.append((t, "slip", x))
            if stop_at_breakaway:
                return segments, events, True
            continue
        seg = dict(kind="slip", sgn=s, windows=[])
        segments.append(seg)
        y = [x, zd, 0.0]
        seen_min = False
        while True:
            w = _slip_window(mod, t, y, s, min(t + window, t_end), rtol, atol)
            seg["windows"].append(w)
            if stop_at_breakaway and s == -1 and graze_tol is not None:
                graze = []
                for tu in w["turns"]:
                    if tu[3] == "min":
                        seen_min = True
                    elif seen_min and -graze_tol <= tu[2] <= 0.0:
                        graze.append(tu)
                if graze:
                    tg = graze[0][0]
                    w["t1"] = tg
                    w["y1"] = np.array(w["sol"].sol(tg))
                    w["turns"] = [tu for tu in w["turns"] if tu[0] <= tg]
                    w["stills"] = [st for st in w["stills"] if st[0] <= tg]
                    events.append((tg, "graze", float(w["y1"][0])))
                    return segments, events, True
            t, y = w["t1"], w["y1"]
            if w["crossed"] or t >= t_end:
                break
        if t >= t_end and not w["crossed"]:
            return segments, events, False
        x, zd = float(y[0]), 0.0
        new = mod.side_after_stop(x)
        kind = "stick" if new == 0 else ("abnormal_stop" if new == s else "normal_stop")
        events.append((t, kind, x))
        s = new
    return segments, events, False


def _run_positive(mod, x0, xd0, t_eval, rtol):
    t_eval = np.asarray(t_eval, float)
    xo = np.full(t_eval.shape, np.nan)
    xdo = np.full(t_eval.shape, np.nan)
    segments, events, _ = _hybrid(mod, 0.0, x0, float(xd0) - mod.v, t_eval[-1], rtol)
    for seg in segments:
        if seg["kind"] == "stick":
            sel = (t_eval >= seg["t0"]) & (t_eval <= seg["t1"])
            xo[sel] = seg["x0"] + mod.v * (t_eval[sel] - seg["t0"])
            xdo[sel] = mod.v
        else:
            for w in seg["windows"]:
                sel = (t_eval >= w["t0"]) & (t_eval <= w["t1"])
                if sel.any():
                    y = w["sol"].sol(t_eval[sel])
                    xo[sel] = y[0]
                    xdo[sel] = y[1] + mod.v
    return xo, xdo, events


def reference_run(m, k, r_y, v, alpha1, alpha2, x0, xd0, t_eval, rtol=1e-12,
                  c=0.0, r_k=None, v_s=1.0):
    """The trajectory from (x0, x'(0) = xd0) sampled at t_eval (t_eval[0] = 0 is the
    start, increasing): returns (x(t_eval), x'(t_eval), events), events being
    [(t, kind, x)] with kind 'slip' (breakaway), 'stick', 'normal_stop' (zdot reverses
    sign: slide-slide) or 'abnormal_stop' (zdot returns to 0 and slides on, same side).

    Exact sticking (closed form), sliding by DOP853 at rtol; v > 0 directly, v < 0 by
    the mirror x -> -x (events keep their kind, positions are mirrored). Grazing: see
    the module docstring."""
    if v > 0:
        return _run_positive(_Model(m, k, r_y, v, alpha1, alpha2, c, r_k, v_s),
                             x0, xd0, t_eval, rtol)
    if v < 0:
        xo, xdo, ev = _run_positive(_Model(m, k, r_y, -v, alpha1, alpha2, c, r_k, v_s),
                                    -x0, -xd0, t_eval, rtol)
        return -xo, -xdo, [(t, kind, -x) for (t, kind, x) in ev]
    raise ValueError("v = 0: no belt motion, not supported")


# ------------------------------------------------------------- stick-slip cycle
def _observe(mod, segments):
    """x_max, x_min, xdot_max, xdot_min, int x dt, stick time over the segments."""
    xs, xds, q, stick = [], [], 0.0, 0.0
    for seg in segments:
        if seg["kind"] == "stick":
            tau = seg["t1"] - seg["t0"]
            stick += tau
            q += seg["x0"] * tau + 0.5 * mod.v * tau * tau
            xs += [seg["x0"], seg["x0"] + mod.v * tau]
            xds.append(mod.v)
            continue
        for w in seg["windows"]:
            y0 = w["sol"].y[:, 0]
            xs += [y0[0], w["y1"][0]] + [xe for (_t, xe) in w["stills"]]
            xds += [y0[1] + mod.v, w["y1"][1] + mod.v] + \
                [zde + mod.v for (_t, _x, zde, _kind) in w["turns"]]
            q += w["y1"][2] - y0[2]
    return (float(max(xs)), float(min(xs)), float(max(xds)), float(min(xds)), float(q),
            float(stick))


def reference_stick_slip_cycle(m, k, r_y, v, alpha1, alpha2, c=0.0, r_k=None, v_s=1.0,
                               rtol=1e-12, max_periods=20.0, graze_tol=None):
    """The stick-slip cycle (v != 0), one period from the breakaway point.

    Every stick phase ends at the breakaway point x_s = (r_y - c v)/k, so the cycle is
    the motion from there (sliding with zdot < 0) to the next breakaway; its
    nontrivial Floquet multiplier is 0. A return that grazes belt speed (a maximum of
    zdot within ``graze_tol``, default 100 rtol (|v| + r_y/sqrt(k m)), of 0) is the
    breakaway point itself (module docstring) and closes the cycle with no stick.

    Returns dict(amplitude = (x_max - x_min)/2, x_max, x_min, mean (time average of x
    over the period), period, stick_time, slip_time, xdot_max, xdot_min, events: the
    (t, kind, x) of the period, the last a 'slip' (breakaway) or a 'graze').
    Raises ValueError if the motion does not come back to the breakaway point within
    ``max_periods`` natural periods 2 pi/omega (no stick-slip cycle: it goes to
    steady sliding or to a slip cycle)."""
    if v < 0:
        r = reference_stick_slip_cycle(m, k, r_y, -v, alpha1, alpha2, c, r_k, v_s, rtol,
                                       max_periods, graze_tol)
        r.update(x_max=-r["x_min"], x_min=-r["x_max"], mean=-r["mean"],
                 xdot_max=-r["xdot_min"], xdot_min=-r["xdot_max"],
                 events=[(t, kind, -x) for (t, kind, x) in r["events"]])
        return r
    mod = _Model(m, k, r_y, v, alpha1, alpha2, c, r_k, v_s)
    if graze_tol is None:
        graze_tol = 100.0 * rtol * (v + mod.r_y / math.sqrt(mod.k * mod.m))
    horizon = max_periods * 2.0 * math.pi / mod.omega
    segments, events, closed = _hybrid(mod, 0.0, mod.x_s, 0.0, horizon, rtol, side=-1,
                                       stop_at_breakaway=True, graze_tol=graze_tol)
    if not closed:
        raise ValueError(f"no stick-slip cycle: no return to the breakaway point within "
                         f"{max_periods} periods (v = {v})")
    period = events[-1][0]
    x_max, x_min, xd_max, xd_min, q, stick = _observe(mod, segments)
    return dict(amplitude=0.5 * (x_max - x_min), x_max=x_max, x_min=x_min,
                mean=q / period, period=period, stick_time=stick,
                slip_time=period - stick, xdot_max=xd_max, xdot_min=xd_min,
                events=events)


# ------------------------------------------------------------------ slip cycles
def reference_return(m, k, r_y, v, alpha1, alpha2, a, rtol=1e-13, c=0.0, r_k=None,
                     v_s=1.0, dense=False):
    """One return of a stop-free slide (v > 0) from x = a, x' = 0 (a maximum of x: a
    must lie above the equilibrium) to the next maximum of x.

    Two legs, each ended by a terminal event: to the minimum of x (x' = 0 rising),
    then to the maximum (x' = 0 falling), so that the start is never taken for the
    end. Returns dict(a1 = the next maximum, x_max = a, x_min, period, mean (time
    average of x), xdot_max, xdot_min, cycle_size = sqrt(int x'^2 dt / (pi omega)),
    log_floquet = int div dt = -(1/m) int (c + F'(zdot)) dt (Liouville: the return
    map's slope at a fixed point is its exponential), reaches_belt (x' reached v
    somewhere: then it is not a slip cycle), and with dense=True the legs'
    solutions ``legs`` [(t_offset, OdeSolution, t_len)]).
    """
    assert v > 0
    mod = _Model(m, k, r_y, v, alpha1, alpha2, c, r_k, v_s)
    if mod.acc(a, -v, -1) >= 0.0:
        raise ValueError("a is not a maximum of x (a <= x_eq)")
    atol = rtol * 1e-3

    def rhs(_t, y):
        zd = y[1]
        return [zd + v, mod.acc(y[0], zd, -1), (zd + v) ** 2, y[0],
                -(mod.c + mod.dforce(zd, -1)) / mod.m]

    def belt(_t, y):              # x' = v: sticking or reversal, not a slip cycle
        return y[1]
    belt.terminal = True
    belt.direction = 1

    def turn(_t, y):              # x'' = 0: extrema of x'
        return mod.acc(y[0], y[1], -1)

    horizon = 4.0 * math.pi / mod.omega
    y = [float(a), -v, 0.0, 0.0, 0.0]
    t_total, xd, legs, touched = 0.0, [], [], False
    x_min = None
    for direction in (1, -1):
        def still(_t, yy):
            return yy[1] + v
        still.terminal = True
        still.direction = direction
        for _ in range(8):        # slowly turning orbits: extend the horizon
            sol = solve_ivp(rhs, (0.0, horizon), y, method="DOP853", rtol=rtol,
                            atol=atol, events=[still, belt, turn], dense_output=dense)
            if sol.status < 0:
                raise RuntimeError(sol.message)
            xd += [float(ye[1] + v) for ye in sol.y_events[2]]
            if dense:
                legs.append((t_total, sol.sol, float(sol.t[-1])))
            t_total += float(sol.t[-1])
            y = list(sol.y[:, -1])
            if sol.status == 1:
                break
        else:
            raise RuntimeError("no turn of the orbit within 32 periods")
        if sol.t_events[1].size:
            touched = True
            break
        if direction == 1:
            x_min = float(y[0])
    touched = touched or (bool(xd) and max(xd) >= v)
    out = dict(a1=float(y[0]), x_max=float(a), x_min=x_min, period=t_total,
               mean=float(y[3]) / t_total if t_total > 0 else float("nan"),
               xdot_max=max(xd) if xd else float("nan"),
               xdot_min=min(xd) if xd else float("nan"),
               cycle_size=math.sqrt(y[2] / (math.pi * mod.omega)),
               log_floquet=float(y[4]), reaches_belt=touched)
    if dense:
        out["legs"] = legs
    return out


def reference_slip_cycle(m, k, r_y, v, alpha1, alpha2, a_guess, rtol=1e-13, c=0.0,
                         r_k=None, v_s=1.0, bracket=None):
    """A slip cycle without stops (v > 0), stable or unstable, by shooting.

    The return map of the x maxima, ``a -> P(a)`` (``reference_return``), is solved
    for P(a) = a by the secant method from a_guess, or by Brent's method on
    ``bracket = (a_lo, a_hi)`` where P(a) - a changes sign (the root does not care
    about stability); there a start whose orbit reaches belt speed counts as
    P(a) > a (it lies outside an unstable outermost cycle, the case near a fold).
    The Floquet multiplier is P'(a) by a central difference (``floquet``; one-sided
    of second order where a + d reaches belt speed); ``floquet_liouville`` is
    exp(int div dt) along the cycle, an independent estimate of the same number.
    Returns dict(amplitude, x_max, x_min, mean, period, floquet, floquet_liouville,
    xdot_max, xdot_min, cycle_size, a1 = P(a)); raises ValueError if the orbit
    reaches belt speed (it would stop: not a slip cycle) or if the iteration ends
    where |P(a) - a| > 1e-9 (x_max - x_min + |a|) (no fixed point)."""
    assert v > 0
    kw = dict(c=c, r_k=r_k, v_s=v_s)

    def ret(a, full=False):
        r = reference_return(m, k, r_y, v, alpha1, alpha2, a, rtol, **kw)
        if r["reaches_belt"] and not full:
            raise ValueError("the orbit reaches belt speed: not a slip cycle")
        return r if full else r["a1"]

    if bracket is not None:
        lo, hi = map(float, bracket)

        def g(a):       # a start that reaches belt speed counts as outward (g > 0)
            r = reference_return(m, k, r_y, v, alpha1, alpha2, a, rtol, **kw)
            return hi - lo if r["reaches_belt"] else r["a1"] - a
        a1 = brentq(g, lo, hi, xtol=1e-15 * max(abs(lo), abs(hi)), rtol=8.9e-16,
                    maxiter=200)
    else:
        a0 = float(a_guess)
        a1 = ret(a0)
        f0 = a1 - a0
        for _ in range(60):
            f1 = ret(a1) - a1
            if f1 == f0:
                break
            a2 = a1 - f1 * (a1 - a0) / (f1 - f0)
            a0, f0, a1 = a1, f1, a2
            if abs(a1 - a0) <= 1e-15 * abs(a1) + 1e-300:
                break
    out = ret(a1, full=True)
    if out["reaches_belt"] or not out["xdot_max"] < v:
        raise ValueError("the orbit reaches belt speed: not a slip cycle")
    if not abs(out["a1"] - a1) <= 1e-9 * (abs(out["x_max"] - out["x_min"]) + abs(a1)):
        # e.g. Brent closing in on the edge of the starts that reach belt speed
        raise ValueError(f"no fixed point of the return map (P(a) - a = "
                         f"{out['a1'] - a1:.3g})")
    d = 1e-5 * abs(out["x_max"] - out["x_min"])
    try:
        out["floquet"] = (ret(a1 + d) - ret(a1 - d)) / (2.0 * d)
    except ValueError:      # a1 + d reaches belt speed (next to a fold): one-sided
        out["floquet"] = (3.0 * out["a1"] - 4.0 * ret(a1 - d) + ret(a1 - 2 * d)) / (2 * d)
    out["floquet_liouville"] = math.exp(out.pop("log_floquet"))
    out["amplitude"] = 0.5 * (out["x_max"] - out["x_min"])
    del out["reaches_belt"]
    return out


def reference_find_slip_cycles(m, k, r_y, v, alpha1, alpha2, c=0.0, r_k=None, v_s=1.0,
                               n_scan=40, rtol=1e-13, max_steps=None):
    """Every slip cycle found by scanning the return map outward from the equilibrium:
    a = x_eq + j dA, dA = v/(omega n_scan), j = 1, 2, ... until the orbit from a
    reaches belt speed (at most ``max_steps``, default 4 n_scan). A start that reaches
    belt speed counts as P(a) > a (outward: an unstable outermost cycle next to the
    belt speed is bracketed that way). Each sign change of P(a) - a is refined by
    ``reference_slip_cycle(bracket=...)``. Returns a list of cycle dicts, innermost
    first. Cycles closer than dA to each other or to the equilibrium can be missed."""
    eq = reference_equilibrium(m, k, r_y, v, alpha1, alpha2, c, r_k, v_s)
    dA = v / math.sqrt(k / m) / n_scan
    prev, cycles = None, []
    for j in range(1, (4 * n_scan if max_steps is None else max_steps) + 1):
        a = eq["x_eq"] + j * dA
        r = reference_return(m, k, r_y, v, alpha1, alpha2, a, rtol, c, r_k, v_s)
        g = 1.0 if r["reaches_belt"] else r["a1"] - a
        if prev is not None and (g > 0) != (prev[1] > 0):
            try:
                cycles.append(reference_slip_cycle(m, k, r_y, v, alpha1, alpha2, None,
                                                   rtol, c, r_k, v_s,
                                                   bracket=(prev[0], a)))
            except ValueError:
                if not r["reaches_belt"]:
                    raise
                # no cycle: P(a) < a right up to the starts that reach belt speed
        if r["reaches_belt"]:
            break
        prev = (a, g)
    return cycles


# ------------------------------------------------------------------ equilibrium
def reference_equilibrium(m, k, r_y, v, alpha1, alpha2, c=0.0, r_k=None, v_s=1.0):
    """Steady sliding (v != 0): x' = 0, so zdot = -v and the force balance
    k x + F(-v) = 0 (c x' = 0) is solved for x by Brent's method on the sliding
    acceleration (not by the closed form). The linearised damping c + F'(-v) (the
    coefficient of xi' in m xi'' + (c + F'(-v)) xi' + k xi = 0) uses a central
    difference of F; the third derivative F'''(-v) a five-point difference.

    Returns dict(x_eq, damping, stable (damping > 0), f3 = F'''(-v) and criticality:
    with g(y) = -(c y + F(y - v) - F(-v)) the Hopf point of x'' + x = g(x') type has
    first Lyapunov coefficient g'''/16 ~ -F'''(-v), so 'subcritical' if F'''(-v) < 0,
    'supercritical' if > 0 (meaningful where damping = 0))."""
    if v < 0:
        r = reference_equilibrium(m, k, r_y, -v, alpha1, alpha2, c, r_k, v_s)
        r.update(x_eq=-r["x_eq"], f3=-r["f3"])
        return r
    mod = _Model(m, k, r_y, v, alpha1, alpha2, c, r_k, v_s)

    def acc(x):
        return mod.acc(x, -v, -1)

    span = (abs(mod.force(-v, -1)) + mod.r_y) / mod.k + 1.0
    lo, hi = -span, span
    while acc(lo) * acc(hi) > 0:
        lo, hi = 2 * lo, 2 * hi
    x_eq = brentq(acc, lo, hi, xtol=1e-300, rtol=8.9e-16)

    def F(s):
        return friction(s, r_y, r_k, v_s, alpha1, alpha2)

    scale = min(mod.v_s, v) if mod.dr != 0 else v
    h = 6e-6 * scale
    d1 = (F(-v + h) - F(-v - h)) / (2 * h)
    h3 = 2e-3 * scale
    d3 = (F(-v + 2 * h3) - 2 * F(-v + h3) + 2 * F(-v - h3) - F(-v - 2 * h3)) / (2 * h3 ** 3)
    damping = c + d1
    return dict(x_eq=x_eq, damping=damping, stable=damping > 0, f3=d3,
                criticality="subcritical" if d3 < 0 else "supercritical")


def reference_hopf(m, k, r_y, alpha1, alpha2, v_lo, v_hi, c=0.0, r_k=None, v_s=1.0):
    """The belt speed in (v_lo, v_hi) where the linearised damping c + F'(-v) of
    ``reference_equilibrium`` changes sign (Brent's method), with its criticality."""
    def damping(v):
        return reference_equilibrium(m, k, r_y, v, alpha1, alpha2, c, r_k, v_s)["damping"]
    vh = brentq(damping, v_lo, v_hi, xtol=1e-13, rtol=8.9e-16)
    eq = reference_equilibrium(m, k, r_y, vh, alpha1, alpha2, c, r_k, v_s)
    return dict(v_hopf=vh, criticality=eq["criticality"], f3=eq["f3"])


# ------------------------------------------------------------ basins (areas)
def reference_cycle_polygon(m, k, r_y, v, alpha1, alpha2, a, n=20001, c=0.0, r_k=None,
                            v_s=1.0, rtol=1e-13):
    """The slip cycle through the maximum x = a (from ``reference_slip_cycle``) as n
    points (t, x, x') equally spaced in time over one period, the last equal to the
    first up to the cycle's closing error. Returns (t, x, xdot) arrays."""
    r = reference_return(m, k, r_y, v, alpha1, alpha2, a, rtol, c, r_k, v_s, dense=True)
    if r["reaches_belt"]:
        raise ValueError("the orbit reaches belt speed: not a slip cycle")
    t = np.linspace(0.0, r["period"], n)
    x = np.empty(n)
    xd = np.empty(n)
    for off, fn, length in r["legs"]:
        sel = (t >= off) & (t <= off + length)
        y = fn(t[sel] - off)
        x[sel] = y[0]
        xd[sel] = y[1] + v
    return t, x, xd


def _clip_half_plane(px, py, inside_val):
    """Sutherland-Hodgman step: keep the part of the closed polygon (px, py) where
    inside_val >= 0 (inside_val: a linear function's values at the vertices)."""
    n = px.size
    if n == 0:
        return px, py
    j = np.roll(np.arange(n), -1)
    a, b = inside_val, inside_val[j]
    ins_a, ins_b = a >= 0, b >= 0
    with np.errstate(divide="ignore", invalid="ignore"):
        f = np.where(ins_a != ins_b, a / (a - b), 0.0)
    ix = px + f * (px[j] - px)
    iy = py + f * (py[j] - py)
    # per edge i -> j emit: (in, in): [j]; (in, out): [cut]; (out, in): [cut, j]
    emit_cut = ins_a != ins_b
    emit_end = ins_b
    ox = np.stack([np.where(emit_cut, ix, np.nan), np.where(emit_end, px[j], np.nan)], 1)
    oy = np.stack([np.where(emit_cut, iy, np.nan), np.where(emit_end, py[j], np.nan)], 1)
    ox, oy = ox.ravel(), oy.ravel()
    keep = ~np.isnan(ox)
    return ox[keep], oy[keep]


def clip_polygon_to_box(x, y, box):
    """The closed polygon (x, y) (repeated last point allowed) clipped to the box
    ((x_lo, x_hi), (y_lo, y_hi)) by Sutherland-Hodgman (exact for a convex clip
    region; a concave subject polygon may leave zero-area edges, which do not change
    the area)."""
    (xl, xh), (yl, yh) = box
    px, py = np.asarray(x, float), np.asarray(y, float)
    for val in (lambda: px - xl, lambda: xh - px, lambda: py - yl, lambda: yh - py):
        px, py = _clip_half_plane(px, py, val())
    return px, py


def polygon_area(x, y):
    """Area of the closed polygon (shoelace formula, absolute value)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    if x.size < 3:
        return 0.0
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y)))


def reference_basin_fraction(m, k, r_y, v, alpha1, alpha2, a,
                             box=((-2.0, 2.0), (0.0, 2.0)), c=0.0, r_k=None, v_s=1.0,
                             n=20001, rtol=1e-13):
    """Area of the interior of the slip cycle through the maximum x = a, inside the box
    ((x_lo, x_hi), (xdot_lo, xdot_hi)) of start states (x, absolute velocity x'),
    divided by the box area.

    This is the basin fraction of steady sliding for uniformly distributed starts
    when the cycle is unstable, the equilibrium inside it is stable and no other
    cycle lies inside (a planar flow cannot cross the cycle, which never reaches the
    belt speed, so the interior is exactly the equilibrium's basin); checking that is
    the caller's job. Polygon of n points equally spaced in time (area error
    ~ (2 pi/n)^2/6 relative). Returns dict(fraction, area, box_area, polygon_area)."""
    _t, x, xd = reference_cycle_polygon(m, k, r_y, v, alpha1, alpha2, a, n, c, r_k, v_s,
                                        rtol)
    x, xd = x[:-1], xd[:-1]                      # the last point repeats the first
    cx, cy = clip_polygon_to_box(x, xd, box)
    area = polygon_area(cx, cy)
    (xl, xh), (yl, yh) = box
    box_area = (xh - xl) * (yh - yl)
    return dict(fraction=area / box_area, area=area, box_area=box_area,
                polygon_area=polygon_area(x, xd))


# ------------------------------------------------------------------------ fold
def reference_breakaway_peak(m, k, r_y, v, alpha1, alpha2, c=0.0, r_k=None, v_s=1.0,
                             rtol=1e-12):
    """From the breakaway point (v > 0), slide with zdot < 0 on the branch F(s < 0)
    continued smoothly past s = 0 (no switching), through the next minimum of zdot to
    the next maximum of zdot (both transversal events x'' = 0). Returns dict(peak =
    zdot there (inf if zdot = 0 was crossed on the way: the arc is stopped there),
    t_peak, x_peak, t_cross, x_cross (first zdot = 0, NaN if peak < 0), sticks = the
    motion sticks at that crossing).

    The breakaway point is itself a maximum of zdot (zdot = 0, x'' = 0). On the section
    x'' = 0 the successive maxima move monotonically (planar flow), so the slip arc
    from the breakaway point comes back to belt speed in its first turn iff peak >= 0,
    with no reliance on detecting a possibly tangential crossing of zdot = 0."""
    assert v > 0
    mod = _Model(m, k, r_y, v, alpha1, alpha2, c, r_k, v_s)
    atol = rtol * 1e-2 * (mod.r_y / mod.k + v / mod.omega)

    def rhs(_t, y):
        return [y[1] + v, mod.acc(y[0], y[1], -1)]

    def cross(_t, yy):
        return yy[1]
    cross.terminal = True
    cross.direction = 1

    y, t_off, sols = [mod.x_s, 0.0], 0.0, []
    horizon = 4.0 * math.pi / mod.omega
    for direction in (1, -1):
        def turn(_t, yy):
            return mod.acc(yy[0], yy[1], -1)
        turn.terminal = True
        turn.direction = direction
        events = [turn] if direction == 1 else [turn, cross]
        sol = solve_ivp(rhs, (0.0, horizon), y, method="DOP853", rtol=rtol, atol=atol,
                        events=events, dense_output=True)
        if sol.status != 1:
            raise RuntimeError("no extremum of zdot within two periods")
        sols.append((t_off, sol))
        t_off += float(sol.t[-1])
        y = list(sol.y[:, -1])
    crossed = sol.t_events[1].size > 0
    # past a crossing the continued branch is not the motion (and may run away): the
    # peak is then only known to be >= 0
    peak = float("inf") if crossed else float(y[1])
    out = dict(peak=peak, t_peak=float("nan") if crossed else t_off,
               x_peak=float("nan") if crossed else float(y[0]), t_cross=float("nan"),
               x_cross=float("nan"), sticks=False)
    if peak >= 0.0:
        off, sol = sols[1]
        if crossed:
            tc = float(sol.t_events[1][0])
        else:            # a crossing inside one step: zdot rises monotonically to peak
            tc = brentq(lambda t: sol.sol(t)[1], 0.0, float(sol.t[-1]), xtol=1e-15,
                        rtol=8.9e-16)
        xc = float(sol.sol(tc)[0])
        out.update(t_cross=off + tc, x_cross=xc,
                   sticks=abs(mod.stick_load(xc)) < mod.r_y)
    return out


def reference_fold(m, k, r_y, alpha1, alpha2, v_lo, v_hi, c=0.0, r_k=None, v_s=1.0,
                   xtol=1e-10, rtol=1e-12):
    """The largest belt speed with a stick-slip cycle, by bisection in (v_lo, v_hi) on
    'the slip arc from the breakaway point returns to zdot = 0 at a point where it
    sticks' (``reference_breakaway_peak``: true at v_lo, false at v_hi). At the fold
    the returning arc grazes belt speed at the breakaway point: the stick-slip cycle
    meets the unstable slip cycle. Returns dict(v_fold, v_lo, v_hi, iterations)."""
    def sticks(v):
        return reference_breakaway_peak(m, k, r_y, v, alpha1, alpha2, c, r_k, v_s,
                                        rtol)["sticks"]

    if not sticks(v_lo) or sticks(v_hi):
        raise ValueError("need a stick-slip cycle at v_lo and none at v_hi")
    it = 0
    while v_hi - v_lo > xtol:
        mid = 0.5 * (v_lo + v_hi)
        if sticks(mid):
            v_lo = mid
        else:
            v_hi = mid
        it += 1
    return dict(v_fold=0.5 * (v_lo + v_hi), v_lo=v_lo, v_hi=v_hi, iterations=it)
