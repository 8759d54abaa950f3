"""An independent reference for the forced slider: scipy integration with exact sticks.

Shares no code with sweepcore (nothing here imports it); the friction family is
``reference.friction``'s. Units kN, cm, s, rad.

Model::

    m x'' + c (x' - y') + k (x - y) + F(x' - v) = F0 p(Omega t + phi),
    y = Y0 cos(Omega t),
    p(theta) = sum_n a_n cos(n theta) + b_n sin(n theta)   (default: cos theta),

F the friction law of the relative speed s = x' - v: the family
``F(s) = sgn(s) (r_k + (r_y - r_k) exp(-|s|/v_s)) - alpha1 s + alpha2 s^3`` (static
limits r_pos = r_neg = r_y), or any callable F(s) (s != 0) with static limits
(r_pos, r_neg). v = 0 (fixed ground) is allowed.

* Slide (s != 0): DOP853 at rtol on the branch of F of the slide's side (continued
  smoothly past s = 0, so that trial stages beyond the switch see no jump), with a
  terminal event at s = 0 and events at the extrema of x (x' = 0) and of x'
  (x'' = 0). A crossing of s = 0 inside one step shows as an extremum of x' on the
  wrong side of v; it is then located by Brent's method between that extremum and
  the one before (x' is monotone there).
* Stick (x' = v): the holding force ``h(t) = e(t) - k x(t) - c v`` with
  ``e(t) = F0 p(Omega t + phi) + k y + c y'`` and ``x(t) = x_s + v (t - t_s)``
  stays in [-r_neg, r_pos]. Breakaway is the first time h reaches a bound: h' =
  e'(t) - k v is a trigonometric polynomial of degree N, whose roots are those of a
  polynomial of degree 2 N in z = exp(i Omega t) on the unit circle (the eigenvalues
  of its companion matrix, numpy.roots: J. P. Boyd, J. Eng. Math. 56 (2006)
  203-219), polished by Newton's method; h is monotone between them, and each
  monotone piece is bracketed, then solved by Brent's method: no short excursion of h
  beyond a bound is stepped over.
* s reaching 0 while sliding: stick if h is inside the band, else slide on (a
  zero-duration stop, 'normal_stop' if the side reverses, 'abnormal_stop' if not).

``forced_steady`` returns the steady response a long simulation from the start
reaches: it iterates the stroboscopic map P (over T = 2 pi/Omega), detects the
smallest period n <= n_max, then refines the fixed point of P^n by Newton's method on
a section placed in the middle of the orbit's longest slide (where P^n is smooth:
the section never sits on a stick, whose map has rank 1), and takes the multipliers
from central differences of P^n there.
"""
import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from reference import friction

__all__ = ["Forced", "forced_run", "forced_steady", "lyapunov"]


class Forced:
    """Parameters, the external load and the sliding field of the forced slider.

    ``law`` = (F, r_pos, r_neg) replaces the family's parameters by a callable F(s)
    [kN] of the relative speed (s != 0) and its static limits [kN]."""

    def __init__(self, m, k, c=0.0, v=0.0, F0=0.0, Omega=1.0, phi=0.0, Y0=0.0,
                 r_y=1.0, r_k=None, v_s=1.0, alpha1=0.0, alpha2=0.0, law=None, cos=None,
                 sin=None):
        self.m, self.k, self.c, self.v = float(m), float(k), float(c), float(v)
        a = np.atleast_1d(np.asarray([1.0] if cos is None and sin is None else
                                     (cos if cos is not None else []), float))
        b = np.atleast_1d(np.asarray(sin if sin is not None else [], float))
        n = max(a.size, b.size, 1)
        self.a_n, self.b_n = np.pad(a, (0, n - a.size)), np.pad(b, (0, n - b.size))
        self.F0, self.Omega, self.phi, self.Y0 = float(F0), float(Omega), float(phi), \
            float(Y0)
        if not (self.m > 0 and self.k > 0 and self.c >= 0 and self.Omega > 0):
            raise ValueError("need m, k, Omega > 0 and c >= 0")
        if law is None:
            r_k = r_y if r_k is None else r_k
            self.F = lambda s: friction(s, r_y, r_k, v_s, alpha1, alpha2)
            self.r_pos = self.r_neg = float(r_y)
        else:
            self.F, self.r_pos, self.r_neg = law[0], float(law[1]), float(law[2])
        self.omega = math.sqrt(self.k / self.m)
        self.T = 2.0 * math.pi / self.Omega
        # the bound of |e|: the amplitudes of the load's harmonics and the anchor's
        self.A = abs(self.F0) * float(np.sum(np.hypot(self.a_n, self.b_n))) + \
            abs(self.Y0) * math.hypot(self.k, self.c * self.Omega)
        bound = max(self.r_pos, self.r_neg)
        self.L = (self.A + bound) / self.k + abs(self.v) / self.omega   # length scale
        self.Lv = self.omega * self.L + abs(self.v)                     # speed scale
        # the branch's slope at 0 for continuing it past s = 0
        self.ds = 1e-9 * self.Lv

    def load(self, t):
        """e(t) = F0 p(Omega t + phi) + k y + c y' [kN]."""
        w = self.Omega
        th = (w * t + self.phi) * np.arange(1, self.a_n.size + 1)
        p = float(np.sum(self.a_n * np.cos(th) + self.b_n * np.sin(th)))
        return self.F0 * p + self.k * self.Y0 * math.cos(w * t) \
            - self.c * self.Y0 * w * math.sin(w * t)

    def load_rate(self, t):
        """e'(t) [kN/s]."""
        w = self.Omega
        n = np.arange(1, self.a_n.size + 1)
        th = (w * t + self.phi) * n
        dp = float(np.sum(n * w * (self.b_n * np.cos(th) - self.a_n * np.sin(th))))
        return self.F0 * dp - self.k * self.Y0 * w * math.sin(w * t) \
            - self.c * self.Y0 * w * w * math.cos(w * t)

    def rate_coefficients(self):
        """h'(t) + k v = e'(t) = sum_n (p_n cos(n Omega t) + q_n sin(n Omega t))."""
        n = np.arange(1, self.a_n.size + 1)
        w = self.Omega
        # F0 (a_n cos(n phi) + b_n sin(n phi)) cos(n Omega t) + ... : e's own harmonics
        al = self.F0 * (self.a_n * np.cos(n * self.phi) + self.b_n * np.sin(n * self.phi))
        be = self.F0 * (self.b_n * np.cos(n * self.phi) - self.a_n * np.sin(n * self.phi))
        al[0] += self.k * self.Y0
        be[0] -= self.c * w * self.Y0
        return n * w * be, -n * w * al

    def branch(self, s, sgn):
        """F on the side sgn, continued past s = 0 by its tangent at s = sgn ds."""
        if sgn * s >= self.ds:
            return self.F(s)
        s1, s2 = sgn * self.ds, sgn * 2.0 * self.ds
        f1 = self.F(s1)
        return f1 + (self.F(s2) - f1) / (s2 - s1) * (s - s1)

    def acc(self, t, x, xd, sgn):
        return (self.load(t) - self.k * x - self.c * xd - self.branch(xd - self.v, sgn)) \
            / self.m

    def hold(self, t, x):
        """h = e(t) - k x - c v: the friction force a stick must supply [kN]."""
        return self.load(t) - self.k * x - self.c * self.v

    def side(self, t, x):
        """0 (stick), +1 or -1 (slide on that side) with x' = v at (t, x)."""
        h = self.hold(t, x)
        if h > self.r_pos:
            return 1
        if h < -self.r_neg:
            return -1
        return 0


def load_extreme(mod, which):
    """The load's min or max over a period (``which`` is ``min`` or ``max``) [kN]: on
    401 phases, then on 2001 between the neighbours of the best (spacing T/4e5: the
    quadratic error (T/4e5)^2 |e''|/8 is at rounding for the loads of the tests)."""
    ph = np.linspace(0.0, mod.T, 401)
    i = int((np.argmin if which is min else np.argmax)([mod.load(s) for s in ph]))
    fine = np.linspace(ph[max(i - 1, 0)], ph[min(i + 1, 400)], 2001)
    return which(mod.load(s) for s in fine)


# ------------------------------------------------------------------------ stick
def _critical_phases(mod):
    """The times in [0, T) at which h'(t) = e'(t) - k v vanishes: with z =
    exp(i Omega t), ``sum_n p_n cos(n Omega t) + q_n sin(n Omega t) - k v`` times
    z^N is a polynomial of degree 2 N in z whose roots on the unit circle are the
    zeros (Boyd 2006); numpy.roots takes the companion matrix's eigenvalues. Roots
    within 1e-6 of the circle are kept (a double root splits by ~sqrt(eps)) and
    polished by Newton's method."""
    p, q = mod.rate_coefficients()
    N = p.size
    c = np.zeros(2 * N + 1, complex)      # coefficients of z^-N .. z^N
    c[N] = -mod.k * mod.v
    for n in range(1, N + 1):
        c[N + n] += 0.5 * (p[n - 1] - 1j * q[n - 1])
        c[N - n] += 0.5 * (p[n - 1] + 1j * q[n - 1])
    nz = np.flatnonzero(np.abs(c) > 1e-300)
    if nz.size < 2:
        return []
    roots = np.roots(c[nz[0]:nz[-1] + 1][::-1])
    out = []
    for z in roots:
        if abs(abs(z) - 1.0) > 1e-6:
            continue
        t = (np.angle(z) % (2.0 * np.pi)) / mod.Omega
        for _ in range(3):          # Newton on h' with h'' = e''
            d = mod.load_rate(t) - mod.k * mod.v
            dd = (mod.load_rate(t + 1e-7 * mod.T) - mod.load_rate(t - 1e-7 * mod.T)) \
                / (2e-7 * mod.T)
            if dd == 0.0:
                break
            t -= d / dd
        out.append(t % mod.T)
    return sorted(out)


def _critical_times(mod, t0, t1):
    """Zeros of h'(t) = e'(t) - k v in (t0, t1), sorted; cut every period where
    h is monotone (no zeros) to keep the pieces short."""
    phases = _critical_phases(mod)
    if not phases:
        return list(np.arange(t0, t1, mod.T)[1:])
    out = []
    j = math.floor(t0 / mod.T) - 1
    while True:
        base = j * mod.T
        if base > t1:
            break
        out += [base + ph for ph in phases if t0 < base + ph < t1]
        j += 1
    return sorted(out)


def _breakaway(mod, t_s, x_s, t_end):
    """First time in (t_s, t_end] where the stick entered at (t_s, x_s) ends, and the
    side of the slide (+1, -1); (None, 0) if it holds to t_end."""
    def h(t):
        return mod.hold(t, x_s + mod.v * (t - t_s))
    cuts = _critical_times(mod, t_s, t_end) + [t_end]
    ta = t_s
    for tb in cuts:
        hb = h(tb)
        for bound, sgn in ((mod.r_pos, 1), (-mod.r_neg, -1)):
            if sgn * (hb - bound) > 0.0:
                tc = brentq(lambda t: h(t) - bound, ta, tb, xtol=1e-15 * (1 + abs(tb)),
                            rtol=8.9e-16)
                return tc, sgn
        ta = tb
    return None, 0


# ------------------------------------------------------------------------ slide
def _slide(mod, t0, y0, sgn, t_end, rtol):
    """Slide on side sgn from t0, y = [x, x', int x dt], until s = 0 or t_end.
    Returns (t1, y1, crossed, sol, extrema_x [(t, x)], extrema_xd [(t, xd)])."""
    v = mod.v

    def rhs(t, y):
        return [y[1], mod.acc(t, y[0], y[1], sgn), y[0]]

    def cross(t, y):
        # s/(t - t0): a slide that starts at s = 0 must not stop at its own start (a
        # short slide returns to s = 0 inside its first step)
        return (y[1] - v) / (t - t0) if t > t0 else float(sgn)
    cross.terminal = True
    cross.direction = -sgn

    def still(_t, y):
        return y[1]

    def turn(t, y):
        return mod.acc(t, y[0], y[1], sgn)

    atol = rtol * 1e-2 * np.array([mod.L, mod.Lv, mod.L * mod.T])
    sol = solve_ivp(rhs, (t0, t_end), list(y0), method="DOP853", rtol=rtol, atol=atol,
                    events=[cross, still, turn], dense_output=True)
    if sol.status < 0:
        raise RuntimeError(sol.message)
    t1, y1, crossed = float(sol.t[-1]), np.array(sol.y[:, -1]), sol.status == 1
    turns = [(float(t), np.array(y)) for t, y in zip(sol.t_events[2], sol.y_events[2])
             if t0 < t <= t1]
    tol = 1e-13 * mod.Lv
    prev = t0
    for t, y in turns:            # a crossing hidden in one step: x' beyond v at a turn
        if sgn * (y[1] - v) < -tol:
            t1 = brentq(lambda tt: sol.sol(tt)[1] - v, prev, t,
                        xtol=1e-15 * (1 + abs(t)), rtol=8.9e-16)
            y1, crossed = np.array(sol.sol(t1)), True
            break
        prev = t
    if crossed:
        y1[1] = v
    ext_x = [(float(t), float(y[0])) for t, y in zip(sol.t_events[1], sol.y_events[1])
             if t0 < t <= t1]
    ext_v = [(t, float(y[1])) for t, y in turns if t <= t1]
    return t1, y1, crossed, sol, ext_x, ext_v


# ----------------------------------------------------------------------- a run
def forced_run(mod, x0, xd0, t0, t_end, rtol=1e-12, t_eval=None):
    """The motion from (x0, x'(t0) = xd0) at t0 to t_end.

    Returns a dict: ``x1``, ``xd1`` (state at t_end), ``events`` [(t, kind, x)] with
    kind 'slip+' / 'slip-' (breakaway to that side), 'stick', 'normal_stop',
    'abnormal_stop'; ``x_ext`` and ``xd_ext`` (every value of x and x' at an extremum,
    a switch or an end: their max and min are the motion's); ``integral`` (int x dt),
    ``stick_time``; with ``t_eval`` (sorted, in [t0, t_end]) also ``x`` and ``xd``
    there."""
    v = mod.v
    t, x, xd = float(t0), float(x0), float(xd0)
    s = (1 if xd > v else -1) if xd != v else mod.side(t, x)
    events, x_ext, xd_ext = [], [x], [xd]
    integral = stick_time = 0.0
    te = None if t_eval is None else np.asarray(t_eval, float)
    xo = None if te is None else np.full(te.shape, np.nan)
    xdo = None if te is None else np.full(te.shape, np.nan)
    while t < t_end:
        if len(events) > 100000:      # sticks and slides without end (Zeno)
            raise RuntimeError(f"more than 100000 switches before t = {t!r}")
        if s == 0:
            tb, side = _breakaway(mod, t, x, t_end)
            t1 = t_end if tb is None else tb
            tau = t1 - t
            integral += x * tau + 0.5 * v * tau * tau
            stick_time += tau
            if te is not None:
                sel = (te >= t) & (te <= t1)
                xo[sel], xdo[sel] = x + v * (te[sel] - t), v
            x, t = x + v * tau, t1
            x_ext.append(x)
            xd_ext.append(v)
            if tb is None:
                break
            events.append((t, "slip+" if side > 0 else "slip-", x))
            s = side
            continue
        t1, y1, crossed, sol, ex, ev = _slide(mod, t, [x, xd, 0.0], s, t_end, rtol)
        if te is not None:
            sel = (te >= t) & (te <= t1)
            if sel.any():
                y = sol.sol(te[sel])
                xo[sel], xdo[sel] = y[0], y[1]
        integral += float(y1[2])
        x_ext += [e[1] for e in ex] + [float(y1[0])]
        xd_ext += [e[1] for e in ev] + [float(y1[1])]
        t, x, xd = t1, float(y1[0]), float(y1[1])
        if not crossed:
            break
        new = mod.side(t, x)
        kind = "stick" if new == 0 else ("abnormal_stop" if new == s else "normal_stop")
        events.append((t, kind, x))
        s = new
    out = dict(x1=x, xd1=xd, events=events, x_ext=x_ext, xd_ext=xd_ext,
               integral=integral, stick_time=stick_time)
    if te is not None:
        out.update(x=xo, xd=xdo)
    return out


# ------------------------------------------------------------------ steady state
def _period_of(points, scale, n_max, tol):
    """Smallest n <= n_max with the last stroboscopic point within tol (scaled) of
    the one n periods before it, else 0."""
    last = points[-1]
    for n in range(1, n_max + 1):
        if len(points) > n and np.max(np.abs(last - points[-1 - n]) / scale) < tol:
            return n
    return 0


def _map(mod, z, t0, n, rtol):
    r = forced_run(mod, z[0], z[1], t0, t0 + n * mod.T, rtol)
    return np.array([r["x1"], r["xd1"]]), r


def _jacobian(mod, z, t0, n, rtol, scale, h=1e-6):
    """D P^n at z by central differences with steps h * scale."""
    J = np.empty((2, 2))
    for j in range(2):
        dz = np.zeros(2)
        dz[j] = h * scale[j]
        up, down = _map(mod, z + dz, t0, n, rtol)[0], _map(mod, z - dz, t0, n, rtol)[0]
        J[:, j] = (up - down) / (2 * dz[j])
    return J


def _newton(mod, z, t0, n, rtol, scale, J, steps=40):
    """The fixed point of P^n (from t0) near z by the chord method: Newton's steps
    with the fixed Jacobian J of P^n (P^n is smooth near z: no switch at the
    section), until a step is below 1e-11 of the scales. Returns (z, run from the
    last iterate, status)."""
    A = J - np.eye(2)
    for _ in range(steps):
        P, run = _map(mod, z, t0, n, rtol)
        dz = np.linalg.solve(A, P - z)
        z = z - dz
        if np.max(np.abs(dz) / scale) < 1e-11:
            return z, run, "ok"
    return z, run, "no_convergence"


def _section(mod, z, t, n, rtol):
    """A time in the middle of the longest slide of the n periods from (t, z)."""
    r = forced_run(mod, z[0], z[1], t, t + n * mod.T, rtol)
    marks = [t] + [e[0] for e in r["events"]] + [t + n * mod.T]
    stuck = [z[1] == mod.v and mod.side(t, z[0]) == 0] + \
        [e[1] == "stick" for e in r["events"]]
    best, ts = -1.0, t
    for i in range(len(marks) - 1):
        if not stuck[i] and marks[i + 1] - marks[i] > best:
            best, ts = marks[i + 1] - marks[i], 0.5 * (marks[i] + marks[i + 1])
    return ts


def lyapunov(mod, z, t0, periods, rtol=1e-12, d=1e-6, batches=5):
    """Largest Lyapunov exponent [1/s] of the motion from z = (x, x') at t0, by two
    trajectories (Benettin): a neighbour d away (in units of the scales L and
    L omega + |v|) is set back to distance d along their difference after every
    period, and the exponent is the mean of ln(distance/d)/T. Returns (exponent,
    standard error of the means of ``batches`` equal batches)."""
    scale = np.array([mod.L, mod.Lv])
    z = np.asarray(z, float)
    u = np.array([1.0, 1.0]) / math.sqrt(2.0)
    logs, t = [], float(t0)
    for _ in range(periods):
        z1 = _map(mod, z, t, 1, rtol)[0]
        w1 = _map(mod, z + d * u * scale, t, 1, rtol)[0]
        diff = (w1 - z1) / scale
        dist = float(np.hypot(*diff))
        logs.append(math.log(dist / d))
        u, z, t = diff / dist, z1, t + mod.T
    means = np.array([np.mean(b) for b in np.array_split(logs, batches)]) / mod.T
    return float(np.mean(logs) / mod.T), float(np.std(means, ddof=1) / math.sqrt(batches))


def forced_steady(mod, x0=0.0, xd0=0.0, t0=0.0, n_max=16, max_periods=2000,
                  rtol=1e-12, settle_rtol=1e-8, detect_tol=1e-4, multipliers=True):
    """The steady response that the motion from (x0, xd0) at t0 reaches.

    Iterates P at ``settle_rtol`` until the last stroboscopic point repeats, within
    ``detect_tol`` of the scales (L, L omega + |v|), the one n <= n_max periods
    earlier; then the chord method on P^n(z) - z at ``rtol`` from a section in the
    middle of the orbit's longest slide, to 1e-11 of the scales; a fixed point of
    P^n that is one of P^d (d a divisor of n) is taken with the smaller period.
    With ``multipliers`` the multipliers of P^n come from central differences (steps
    1e-5 of the scales, at rtol: error ~ rtol/1e-5 + 1e-10).

    Returns a dict: status ('ok'; 'rest': stuck for ever on fixed ground;
    'aperiodic': no period up to n_max within ``max_periods``, or with ``multipliers``
    only a period whose orbit repels, largest modulus above 1 + 1e-3, given as
    ``repelling_orbit`` (n, modulus); 'no_convergence'),
    multiplicity n, period n T [s], amplitude, mean, x_max, x_min [cm], xdot_max,
    xdot_min, velocity_amplitude [cm/s], sticks_per_period, stops_per_period,
    stick_fraction, multipliers (largest modulus first; NaN without
    ``multipliers``), floquet (the largest modulus), lyapunov = ln(floquet)/(n T)
    [1/s], section (t, x, x'), events [(t, kind, x)] of one response period. An
    aperiodic response has its ``lyapunov`` (and ``lyapunov_error``) from
    ``lyapunov`` over 200 periods and no other observable."""
    scale = np.array([mod.L, mod.Lv])
    z, t = np.array([x0, xd0], float), float(t0)
    points, n = [z], 0
    for _ in range(max_periods):
        z, r = _map(mod, z, t, 1, settle_rtol)
        t += mod.T
        points.append(z)
        if mod.v == 0.0 and not r["events"] and r["stick_time"] >= (1 - 1e-12) * mod.T:
            return dict(status="rest", multiplicity=1, period=mod.T, amplitude=0.0,
                        mean=z[0], x_max=z[0], x_min=z[0], xdot_max=0.0, xdot_min=0.0,
                        velocity_amplitude=0.0, sticks_per_period=1, stops_per_period=0,
                        stick_fraction=1.0, floquet=0.0, multipliers=np.zeros(2),
                        events=[])
        n = _period_of(points, scale, n_max, detect_tol)
        if n:
            break
    if not n:
        lam, err = lyapunov(mod, z, t, 200, rtol)
        return dict(status="aperiodic", multiplicity=0, lyapunov=lam, lyapunov_error=err)
    ts = _section(mod, z, t, n, settle_rtol)
    rs = forced_run(mod, z[0], z[1], t, ts, settle_rtol)
    zs = np.array([rs["x1"], rs["xd1"]])
    J = _jacobian(mod, zs, ts, n, settle_rtol, scale, h=1e-4)
    zs, orbit, status = _newton(mod, zs, ts, n, rtol, scale, J)
    for d in range(1, n):       # a fixed point of P^n may be one of P^d, d | n
        if n % d == 0 and np.max(np.abs(_map(mod, zs, ts, d, rtol)[0] - zs)
                                  / scale) < 1e-8:
            n = d
            zs, orbit, status = _newton(mod, zs, ts, n, rtol, scale, J)
            break
    mu = np.full(2, np.nan + 0j)
    if multipliers:
        mu = np.linalg.eigvals(_jacobian(mod, zs, ts, n, rtol, scale, h=1e-5))
        mu = mu[np.argsort(-np.abs(mu))]
        if abs(mu[0]) > 1.0 + 1e-3:
            # the chord method found an orbit that repels (inside a chaotic motion
            # the iterates pass near unstable ones): not where the motion settles
            lam, err = lyapunov(mod, z, t, 200, rtol)
            return dict(status="aperiodic", multiplicity=0, lyapunov=lam,
                        lyapunov_error=err, repelling_orbit=(n, float(abs(mu[0]))))
    span = n * mod.T
    ev = orbit["events"]
    xe, xde = orbit["x_ext"], orbit["xd_ext"]
    return dict(status=status, multiplicity=n, period=span,
                amplitude=0.5 * (max(xe) - min(xe)), mean=orbit["integral"] / span,
                x_max=max(xe), x_min=min(xe), xdot_max=max(xde), xdot_min=min(xde),
                velocity_amplitude=0.5 * (max(xde) - min(xde)),
                sticks_per_period=sum(1 for e in ev if e[1] == "stick"),
                stops_per_period=sum(1 for e in ev if e[1].endswith("_stop")),
                stick_fraction=orbit["stick_time"] / span, multipliers=mu,
                floquet=float(np.abs(mu[0])), lyapunov=np.log(np.abs(mu[0])) / span,
                section=(ts, zs[0], zs[1]), events=ev)
