"""The heyoka.py peer of the Hopf map, written as an expert would for the map job.

heyoka.py (https://bluescarni.github.io/heyoka.py/) integrates ODEs by Taylor's method,
compiled for the system by LLVM, and locates events by polynomial root finding on
each step's Taylor series; in batch mode one integrator advances several systems at
once in SIMD lanes, each lane stopping at its own terminal event. This peer computes
what sweepcore's map computes, each point's attractor from a start stuck on the belt,
for the paper's law (eq. 40, r_k = r_y, c = 0), with what the library offers
(events, batch mode, the variational equations as extra states) and what the physics
gives away:

* the sliding field as a heyoka system, the sign of the relative speed
  ``z = x' - v`` a runtime parameter ``s`` (one compiled integrator for every point
  and both slide directions; ``z*z*z``, since heyoka's ``pow(z, 3)`` has NaN
  derivatives at z = 0);
* a terminal event at ``s z = 0`` with direction (the slide ends where z returns to
  0, never where it leaves 0), then the stick in closed form (x moves with the belt
  to the breakaway point r_y/k) or a reversal (s flips when |k x| >= r_y);
* a start stuck on the belt means every stick ends at the same breakaway point: the
  orbit from breakaway that sticks again is the stick-slip cycle, exact in one
  period (measured with every extremum from breakaway);
* otherwise the attractor is a fixed point of the return map P on the section
  x' = 0, x'' < 0 (maxima of x, which lie above the equilibrium x_eq, eq. 43), found
  by Newton's method on P(x) - x from the second maximum after breakaway. P'(x) is
  the first variational state dx/dx0 at the next maximum (there x' = 0, so the
  section adds no term), carried by the integrator beside (x, z) and multiplied in
  its z-row by zdot+/zdot- at a reversal (the saltation of the jump in the field
  across z = 0). Next to v* the map contracts by only 1 - 1e-5 a period: Newton
  needs a handful of periods where iterating the map needs 1e5 or more;
* the iteration is kept on the attractor the orbit from breakaway reaches: a
  bracket [lo, hi] with P(lo) > lo (the orbit grows) and P(hi) < hi (it decays),
  lo starting at x_eq; a Newton step that leaves it, or where the map is locally
  expanding, is replaced by halving towards the bracket. A return that sticks
  bounds the bracket from above; one from a point of the true orbit (the second
  maximum and its plain iterates) proves the orbit sticks: the stick-slip cycle is
  then measured from breakaway. Converged when a Newton step is below ``xtol``;
  the equilibrium when the iterate is within ``eps_eq`` of x_eq, or no maximum of x
  comes for ``at_rest`` = 20 s;
* one period from the fixed point with every extremum gives amplitude, mean and
  period. The mean's running integral of x is a state reset at every extremum (heyoka's
  error control is relative to the largest state component: an integral left to grow
  loosens the tolerance on x and x'); the variational states are 0 (and stay 0)
  outside Newton's returns.

Each point's search is a generator that asks for one flight to the next event at a
time; the same code runs on the scalar integrator or in the lanes of the batch one
(every lane refilled with the next point as its point is done), so Python handles
each event once (the ``events`` column counts them) and never a section return it
does not use.

Units: kN, cm, s (the package's). Written from heyoka.py's documented API; shares no
code with sweepcore (the workers import neither sweepcore nor numba).
"""
from __future__ import annotations

import math
import time

import numpy as np

# sweepcore's regime codes (docs/variables.md, "Regime codes"), written out so that
# the worker processes import neither sweepcore nor numba
EQUILIBRIUM, SLIP_CYCLE, STICK_SLIP, UNCONVERGED = 0, 1, 2, 6
COLUMNS = ("amplitude", "mean", "period", "regime", "steps", "t_end", "returns", "events")
STOP, XMAX, XMIN = 0, 1, 2            # the integrator's terminal events
TIME_LIMIT, FAILED = -1, -2
# the state: x [cm], z [cm/s], q = int x [cm s] since the last extremum, and the
# variational states p = dx/dx0 [1], w = dz/dx0 [1/s]
X, Z, Q, P, W = range(5)
ON = 6                                # the parameter that switches the minima on


def integrator(tol, batch=None):
    """Taylor integrator of (x, z, q, p, w) at ``tol`` with ``batch`` lanes (None:
    scalar) and the terminal events [slide ends, maximum of x, minimum of x if
    par[6] = 1]; parameters (s, k/m, r_y/m, v, alpha1/m, alpha2/m, on)."""
    import heyoka as hy
    x, z, q, p, w = hy.make_vars("x", "z", "q", "p", "w")
    s, km, rm, v, a1, a2, on = (hy.par[i] for i in range(7))
    sys = [(x, z + v), (z, -km * x - rm * s + a1 * z - a2 * z * z * z), (q, x),
           (p, w), (w, -km * p + (a1 - 3.0 * a2 * z * z) * w)]
    ev = hy.t_event if batch is None else hy.t_event_batch
    neg, pos = hy.event_direction.negative, hy.event_direction.positive
    events = [ev(s * z, direction=neg),               # z back to 0 from the slide's side
              ev(z + v, direction=neg),               # x' = 0 falling: a maximum of x
              ev(on * (z + v) + (1.0 - on), direction=pos)]   # a minimum (rootless off)
    pars = [-1.0, 10.0, 2.0, 1.0, 0.2, 0.01, 1.0]
    if batch is None:
        return hy.taylor_adaptive(sys, [0.0] * 5, tol=tol, t_events=events, pars=pars,
                                  compact_mode=False)
    return hy.taylor_adaptive_batch(
        sys, np.zeros((5, batch)), tol=tol, t_events=events,
        pars=np.repeat(np.array(pars)[:, None], batch, axis=1), compact_mode=False)


class Point:
    """One slider started stuck at x = 0: its parameters and counters."""

    def __init__(self, m, k, r_y, v, alpha1, alpha2):
        self.k, self.r_y, self.v = k, r_y, v
        self.km, self.rm = k / m, r_y / m
        self.pars = [-1.0, k / m, r_y / m, v, alpha1 / m, alpha2 / m, 1.0]
        self.xs, self.x_eq = r_y / k, (r_y - alpha1 * v + alpha2 * v ** 3) / k
        self.t_b = self.xs / v                   # breakaway at the end of the stick
        self.steps, self.returns, self.t_end, self.events = 0, 0, 0.0, 0

    def row(self, amplitude, mean, period, regime):
        return (amplitude, mean, period, regime, self.steps, self.t_end, self.returns,
                self.events)

    def equilibrium(self):
        return self.row(0.0, self.x_eq, math.nan, EQUILIBRIUM)

    def failed(self):
        return self.row(math.nan, math.nan, math.nan, UNCONVERGED)


class Peer:
    """Attractors of the paper's slider by heyoka, on the scalar integrator or in the
    lanes of a batch one.

    Parameters
    ----------
    tol : float
        heyoka's tolerance (relative and absolute, per step).
    xtol : float
        a Newton step on the section below this ends the search [cm].
    eps_eq : float
        a section point within this of x_eq is the equilibrium [cm].
    at_rest : float
        no event for this long means the slider is at rest [s].
    t_max : float
        simulated time after which a point is left unconverged [s].
    max_iter : int
        Newton iterations after which a point is left unconverged.
    batch_size : int or None
        lanes of heyoka's batch mode (None: scalar mode).
    """

    def __init__(self, tol, xtol=1e-9, eps_eq=1e-7, at_rest=20.0, t_max=2e6,
                 max_iter=80, batch_size=None):
        import heyoka as hy
        self.tol, self.xtol, self.eps_eq, self.at_rest, self.t_max, self.max_iter = \
            tol, xtol, eps_eq, at_rest, t_max, max_iter
        self.batch_size = batch_size
        self._codes = {int(hy.taylor_outcome.time_limit): TIME_LIMIT}
        self._success = int(hy.taylor_outcome.success)
        t0 = time.perf_counter()
        self.ta = integrator(tol, batch_size)
        self.compile_s = time.perf_counter() - t0

    def _code(self, oc):
        """Event index of an outcome (heyoka writes -1 - index for a terminal event),
        TIME_LIMIT or FAILED (a non-finite state)."""
        oc = int(oc)
        return -oc - 1 if -4 < oc < 0 else self._codes.get(oc, FAILED)

    # ------------------------------------------------ a point's search
    # A flight is asked for by yielding (state, s, on, reload) and answered with
    # (event, t, state), t the time since the flight's start [s]; ``reload`` False
    # goes on from where the integrator stopped (a new s, or q or w changed). Time
    # runs on through a point's flights, never back: heyoka's cooldown of the event
    # just found keeps it from firing again at once, and a stale one (of an event at
    # another time) can never hide an event. The integrator's time and cooldowns are
    # reset for each point.

    def _flight(self, pt, state, on, n_max, s=-1.0):
        """Every extremum from (state, s) until a stick or ``n_max`` maxima;
        (kind, t, x, result): kind "max" (x the n_max-th maximum, result the smallest
        x and the integral of x since t), "stick" (result the stick-slip cycle's row,
        for a flight from breakaway), "rest" or "fail"."""
        xmax = xmin = state[X]
        total, n, reload = 0.0, 0, True
        while True:
            ev, t, state = yield (state, s, on, reload)
            reload = False
            pt.t_end = t
            total += state[Q]
            state[Q] = 0.0                       # the integral's scale stays the state's
            if ev == FAILED or t > self.t_max:
                return "fail", t, math.nan, None
            if ev == TIME_LIMIT:
                return "rest", t, math.nan, None
            x = state[X]
            if ev == STOP:
                if abs(pt.k * x) < pt.r_y:       # sticks: back to breakaway
                    xmin = min(xmin, x)
                    t_stick = (pt.xs - x) / pt.v
                    T = t + t_stick
                    return "stick", t, x, pt.row(
                        0.5 * (xmax - xmin), (total + 0.5 * (x + pt.xs) * t_stick) / T, T,
                        STICK_SLIP)
                s = -s                           # slide-slide reversal
            elif ev == XMIN:
                xmin = min(xmin, x)
            elif t > 0.0:                        # a maximum (not the one it starts on)
                xmax = max(xmax, x)
                n += 1
                pt.returns += 1
                if n >= n_max:
                    return "max", t, x, (xmin, total)

    def _return(self, pt, x0):
        """The next maximum of x from the section point x0 [cm]: (kind, P(x0),
        P'(x0)), kind "max", "stick", "rest" or "fail"."""
        state = np.array([x0, -pt.v, 0.0, 1.0, 0.0])
        s, reload = -1.0, True
        while True:
            ev, t, state = yield (state, s, 0.0, reload)
            reload = False
            if ev == XMAX and t > 0.0:
                pt.returns += 1
                return "max", state[X], state[P]
            if ev == STOP:
                x = state[X]
                if abs(pt.k * x) < pt.r_y:
                    return "stick", math.nan, math.nan
                before = -pt.km * x - pt.rm * s  # zdot on either side of the reversal
                s = -s
                state[W] *= (-pt.km * x - pt.rm * s) / before
            elif ev == TIME_LIMIT:
                return "rest", math.nan, math.nan
            elif ev == FAILED:
                return "fail", math.nan, math.nan

    def _newton(self, pt, x):
        """Newton's method on P(x) - x from the true orbit's maximum x [cm]: ("cycle",
        x*), ("equilibrium",), ("sticks",) (the orbit from breakaway sticks) or
        ("fail",)."""
        lo, hi, hi_sticks = pt.x_eq, math.inf, False
        true = True                              # x lies on the orbit from breakaway
        for _ in range(self.max_iter):
            if x - pt.x_eq <= self.eps_eq:
                return ("equilibrium",)
            kind, px, dp = yield from self._return(pt, x)
            if kind == "rest":
                return ("equilibrium",)
            if kind == "fail":
                return ("fail",)
            if kind == "stick":
                if true:
                    return ("sticks",)
                hi, hi_sticks = x, True
                new = 0.5 * (lo + hi)
            else:
                f, d = px - x, 1.0 - dp
                if f > 0.0:
                    lo = max(lo, x)
                elif x < hi:
                    hi, hi_sticks = x, False
                if d > 0.0:                      # Newton's step
                    new, true = x + f / d, False
                elif f < 0.0:                    # locally expanding: the orbit's next
                    new = px                     # maximum
                else:                            # growing slowly: double the amplitude
                    new, true = pt.x_eq + 2.0 * (x - pt.x_eq), False
                if not lo < new < hi:            # off the bracket: halve it
                    new, true = 0.5 * (lo + hi) if hi < math.inf else \
                        pt.x_eq + 2.0 * (x - pt.x_eq), False
            if abs(new - x) <= self.xtol or hi - lo <= self.xtol:
                if hi_sticks and hi - lo <= self.xtol:
                    return ("sticks",)
                return ("cycle", new) if new - pt.x_eq > self.eps_eq \
                    else ("equilibrium",)
            x = new
        return ("fail",)

    def _search(self, pt):
        """The attractor of point pt: its row of ``COLUMNS``."""
        zero = np.array([pt.xs, 0.0, 0.0, 0.0, 0.0])
        kind, t, x, result = yield from self._flight(pt, zero.copy(), 1.0, 2)
        if kind == "stick":
            return result
        if kind == "rest":
            return pt.equilibrium()
        if kind == "fail":
            return pt.failed()
        found = yield from self._newton(pt, x)
        if found[0] == "equilibrium":
            return pt.equilibrium()
        if found[0] == "sticks":                 # the stick-slip cycle, every extremum
            kind, t, x, result = yield from self._flight(pt, zero.copy(), 1.0, math.inf)
            return result if kind == "stick" else pt.failed()
        if found[0] == "fail":
            return pt.failed()
        x_star = found[1]                        # one period from the fixed point
        kind, T, x1, res = yield from self._flight(
            pt, np.array([x_star, -pt.v, 0.0, 0.0, 0.0]), 1.0, 1)
        if kind != "max":
            return pt.failed()
        xmin, total = res
        return pt.row(0.5 * (max(x_star, x1) - xmin), total / T, T, SLIP_CYCLE)

    # ------------------------------------------------ the drivers
    def _scalar(self, gen, pt):
        """Run a point's search on the scalar integrator; its row."""
        ta, state_view, pars = self.ta, self.ta.state, self.ta.pars   # views, kept
        pars[:] = pt.pars
        ta.time = 0.0
        ta.reset_cooldowns()
        req, t0 = next(gen), 0.0
        while True:
            state, s, on, reload = req
            if reload:
                t0 = ta.time
            if state is not state_view:
                state_view[:] = state
            pars[0], pars[ON] = s, on
            oc, _h0, _h1, n = ta.propagate_until(ta.time + self.at_rest)[:4]
            pt.steps += n
            pt.events += 1
            try:                                 # the generator may edit the view
                req = gen.send((self._code(oc), ta.time - t0, state_view))
            except StopIteration as stop:
                return stop.value

    def _batch(self, P, out):
        """Every point of P in the lanes, each lane refilled as its point is done.

        A terminal event in one lane ends the batch step for every lane (heyoka's
        rule); a lane stopped so (outcome ``success``) goes on with its flight."""
        ta, B = self.ta, self.batch_size
        queue = list(range(len(P)))[::-1]
        lanes = [None] * B                       # [row, point, generator, request]
        t0, limits = np.zeros(B), np.zeros(B)

        def fill(j):
            if queue:
                i = queue.pop()
                pt = Point(*P[i])
                gen = self._search(pt)
                ta.pars[:, j] = pt.pars
                times = ta.time.copy()
                times[j] = 0.0
                ta.set_time(times)
                ta.reset_cooldowns(j)
                lanes[j] = [i, pt, gen, next(gen)]
            else:
                lanes[j] = None

        for j in range(B):
            fill(j)
        while any(lanes):
            now = ta.time
            for j, lane in enumerate(lanes):
                if lane is None:
                    limits[j] = now[j]           # parked: stops at once
                elif lane[3] is not None:        # a new flight
                    state, s, on, reload = lane[3]
                    if reload:
                        t0[j] = now[j]
                    ta.state[:, j] = state
                    ta.pars[0, j], ta.pars[ON, j] = s, on
                    limits[j] = now[j] + self.at_rest
                    lane[3] = None
            ta.propagate_until(limits)
            now = ta.time
            for j, (lane, res) in enumerate(zip(lanes, ta.propagate_res)):
                if lane is None:
                    continue
                lane[1].steps += res[3]
                if int(res[0]) == self._success:
                    continue
                lane[1].events += 1
                try:
                    lane[3] = lane[2].send((self._code(res[0]), float(now[j] - t0[j]),
                                            ta.state[:, j].copy()))
                except StopIteration as stop:
                    out[lane[0]] = stop.value
                    fill(j)

    def points(self, P):
        """Attractors of the rows of P (m, k, r_y, v, alpha1, alpha2), each started
        stuck on the belt at x = 0.

        Returns
        -------
        array (n, 8)
            the columns of ``COLUMNS``: amplitude [cm], mean [cm], period [s], regime
            code, Taylor steps, simulated time of the last flight [s], returns to the
            section integrated, events handled in Python (flights to an event)
        """
        P = np.asarray(P, dtype=float)
        out = np.full((len(P), len(COLUMNS)), np.nan)
        if self.batch_size:
            self._batch(P, out)
            return out
        for i, p in enumerate(P):
            pt = Point(*p)
            out[i] = self._scalar(self._search(pt), pt)
        return out

    def point(self, m, k, r_y, v, alpha1, alpha2):
        """The attractor of one slider started stuck at x = 0: the row of ``points``."""
        return self.points(np.array([[m, k, r_y, v, alpha1, alpha2]]))[0]


_PEERS = {}


def _work(tol, batch_size, points):
    """One task of a worker process: (out, CPU seconds) of ``points``; the process's
    integrator for (tol, batch_size) is compiled on its first task."""
    key = (tol, batch_size)
    if key not in _PEERS:
        _PEERS[key] = Peer(tol, batch_size=batch_size)
    c0 = time.process_time()
    out = _PEERS[key].points(points)
    return out, time.process_time() - c0, _PEERS[key].compile_s


def pool(processes):
    """Worker processes (spawned: the parent's numba threads are never forked)."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor
    return ProcessPoolExecutor(processes, mp_context=multiprocessing.get_context("spawn"))


def run_map(executor, points, tol, batch_size=None, chunk=256, seed=7):
    """Attractors of every row of ``points`` on the workers of ``executor``, in
    chunks of a random order (the map's costly points cluster next to v*).

    Returns
    -------
    dict
        out (n, 8) in the order of ``points``; wall_s of the whole call; cpu_s, the
        workers' CPU time summed over the tasks (compilation excluded); compile_s,
        the largest first-task compilation of the integrators [s].
    """
    points = np.asarray(points, dtype=float)
    order = np.random.default_rng(seed).permutation(len(points))
    parts = [order[i:i + chunk] for i in range(0, len(order), chunk)]
    out = np.empty((len(points), len(COLUMNS)))
    t0 = time.perf_counter()
    futures = [executor.submit(_work, tol, batch_size, points[idx]) for idx in parts]
    cpu, compile_s = 0.0, 0.0
    for idx, f in zip(parts, futures):
        o, c, comp = f.result()
        out[idx] = o
        cpu += c
        compile_s = max(compile_s, comp)
    return dict(out=out, wall_s=time.perf_counter() - t0, cpu_s=cpu, compile_s=compile_s)


def solve(points, tol, batch_size=None, **kw):
    """Attractors of ``points`` (rows m, k, r_y, v, alpha1, alpha2).

    Returns
    -------
    (out, cpu_s)
        out: array (n, 8) with the columns of ``COLUMNS``; cpu_s: this process's CPU
        time for the points [s] (the integrator's compilation excluded).
    """
    peer = Peer(tol, batch_size=batch_size, **kw)
    c0 = time.process_time()
    out = peer.points(np.asarray(points, dtype=float))
    return out, time.process_time() - c0
