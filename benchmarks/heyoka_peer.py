"""The heyoka.py peer of the Hopf map, written as an expert would for the map job.

heyoka.py (https://bluescarni.github.io/heyoka.py/) integrates ODEs by Taylor's method,
compiled for the system by LLVM, and locates events by polynomial root finding on
each step's Taylor series; in batch mode one integrator advances several systems at
once in SIMD lanes. This peer computes what sweepcore's map computes, each point's
attractor from a start stuck on the belt, for the paper's law (eq. 40, r_k = r_y,
c = 0), with everything the library offers and everything the physics gives away:

* the sliding field as one heyoka system, the sign of the relative speed
  ``z = x' - v`` a runtime parameter ``s`` (one compiled integrator for every point
  and both slide directions; ``z*z*z``, since heyoka's ``pow(z, 3)`` has NaN
  derivatives at z = 0) and the integral of x a third state (the mean);
* a terminal event at ``s z = 0`` with direction (the slide ends where z returns to
  0, never where it leaves 0), then the stick in closed form (x moves with the belt
  to the breakaway point r_y/k) or a reversal (s flips when |k x| >= r_y);
* a start stuck on the belt means every stick ends at the same breakaway point: the
  first stick closes a stick-slip cycle, exact in one period (amplitude from the
  extremes of x, events at x' = 0, mean from the integral);
* otherwise the attractor is the fixed point of the return map on the section
  x' = 0 (maxima of x), found by Aitken extrapolation of successive returns over a
  lag that grows with their count (lag n // 3: the first third, the transient, is
  never used), accepted when three successive extrapolations, their spread times
  the lag, agree to ``xtol``; then one period from the extrapolated point gives
  amplitude, mean and period (a plain "successive returns agree" test stops far
  too early next to v*, where the returns creep);
* equilibria by decay: the extrapolated fixed point within ``eps_eq`` of the
  analytic x_eq (eq. 43), or no extremum of x for ``at_rest`` = 20 s (the
  oscillation has decayed below what events resolve).

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
COLUMNS = ("amplitude", "mean", "period", "regime", "steps", "t_end", "returns")
STOP, XMAX, XMIN = 0, 1, 2            # event indices (the section integrator has 0, 1)
TIME_LIMIT, FAILED, NO_EVENT = -1, -2, -3   # a batch lane stopped by another's event


def system():
    """The sliding field: state (x, z, int x), parameters (s, k/m, r_y/m, v,
    alpha1/m, alpha2/m); z = x' - v [cm/s], eq. (40) with sgn(z) = s frozen."""
    import heyoka as hy
    x, z, q = hy.make_vars("x", "z", "q")
    s, km, rm, v, a1, a2 = (hy.par[i] for i in range(6))
    return [(x, z + v), (z, -km * x - rm * s + a1 * z - a2 * z * z * z), (q, x)], (s, z, v)


def integrators(tol, batch=None):
    """(full, section): Taylor integrators at ``tol`` with the events [slide ends,
    maximum of x, minimum of x] and [slide ends, maximum of x]; ``batch`` lanes
    (heyoka's batch mode) or scalar."""
    import heyoka as hy
    sys, (s, z, v) = system()
    neg, pos = hy.event_direction.negative, hy.event_direction.positive
    ev = hy.t_event if batch is None else hy.t_event_batch
    stop = ev(s * z, direction=neg)              # z back to 0 from the slide's side
    xmax = ev(z + v, direction=neg)              # x' = 0 falling: a maximum of x
    xmin = ev(z + v, direction=pos)
    pars = [-1.0, 10.0, 2.0, 1.0, 0.2, 0.01]
    out = []
    for events in ([stop, xmax, xmin], [stop, xmax]):
        if batch is None:
            out.append(hy.taylor_adaptive(sys, [0.0, 0.0, 0.0], tol=tol, t_events=events,
                                          pars=pars, compact_mode=False))
        else:
            out.append(hy.taylor_adaptive_batch(
                sys, np.zeros((3, batch)), tol=tol, t_events=events,
                pars=np.repeat(np.array(pars)[:, None], batch, axis=1), compact_mode=False))
    return tuple(out)


def aitken(seq, lag):
    """Aitken's extrapolation of the limit of ``seq`` from its last element and the
    ones ``lag`` and ``2 lag`` before (the last element if the differences vanish)."""
    a, b, c = seq[-1 - 2 * lag], seq[-1 - lag], seq[-1]
    d1, d0 = c - b, b - a
    den = d1 - d0
    return c if den == 0.0 else c - d1 * d1 / den


class Extrapolation:
    """Successive returns to the section and their Aitken limits over a growing lag
    (lag n // 3 at the n-th return: the first third, the transient, is never used);
    converged when the last three limits, their spread multiplied by the lag, agree
    to ``xtol`` [cm]: next to v* the returns converge algebraically for long (the
    cubic term of the law outweighs q), and the limit drifts by a little each
    return for many returns; over a lag the drift is what is left."""

    def __init__(self, xtol):
        self.xtol = xtol
        self.x = []
        self.l0 = self.l1 = self.l2 = math.nan      # the last three limits
        self.n_limits = 0

    def add(self, x):
        xs = self.x
        xs.append(x)
        n = len(xs) - 1
        if n < 2:
            return False
        lag = n // 3 or 1
        self.l2, self.l1 = self.l1, self.l0
        self.l0 = aitken(xs, lag)
        self.n_limits += 1
        return (self.n_limits >= 3 and lag * (max(self.l0, self.l1, self.l2)
                                              - min(self.l0, self.l1, self.l2)) <= self.xtol)

    @property
    def limit(self):
        return self.l0 if self.n_limits else (self.x[-1] if self.x else math.nan)


class Track:
    """One point from its breakaway: what each event of its slide means.

    The drivers (scalar, batch) advance the integrator to the next terminal event
    and hand it here; ``s`` is the sign the slide goes on with, ``result`` is set
    when the attractor is known (``ONE_PERIOD``: the slip cycle through
    ``ex.limit``; ``REDO``: it stuck after its extremes stopped being tracked).
    """

    def __init__(self, peer, k, r_y, v, alpha1, alpha2, x0):
        self.peer, self.k, self.r_y, self.v = peer, k, r_y, v
        self.xs, self.x_eq = r_y / k, (r_y - alpha1 * v + alpha2 * v ** 3) / k
        self.t_b = (self.xs - x0) / v                # breakaway at the end of the stick
        self.s = -1.0
        self.xmax = self.xmin = self.xs
        self.ex = Extrapolation(peer.xtol)
        self.last = self.t_b
        self.tracking = True                         # extremes tracked (full integrator)
        self.result = None
        self.steps = 0

    def event(self, ev, t, x, q, n_full):
        """Take event ``ev`` at time t [s], x [cm], int x [cm s]."""
        peer = self.peer
        if ev == FAILED or t - self.t_b > peer.t_max:
            self.result = (math.nan, math.nan, math.nan, UNCONVERGED)
        elif ev == TIME_LIMIT:                       # no extremum for at_rest seconds
            self.result = (0.0, self.x_eq, math.nan, EQUILIBRIUM)
        elif ev == STOP:
            self.last = t
            if abs(self.k * x) < self.r_y:           # sticks: back to breakaway
                if not self.tracking:
                    self.result = REDO
                    return
                self.xmin = min(self.xmin, x)
                t_stick = (self.xs - x) / self.v
                T = t - self.t_b + t_stick
                self.result = (0.5 * (self.xmax - self.xmin),
                               (q + 0.5 * (x + self.xs) * t_stick) / T, T, STICK_SLIP)
            else:
                self.s = -self.s                     # slide-slide reversal
        elif ev == XMIN:
            self.last = t
            self.xmin = min(self.xmin, x)
        else:                                        # a maximum of x: the section
            self.last = t
            self.xmax = max(self.xmax, x)
            done = self.ex.add(x)
            if len(self.ex.x) >= n_full:
                self.tracking = False
            if x - self.x_eq <= peer.eps_eq or (done and self.ex.limit - self.x_eq
                                                <= peer.eps_eq):
                self.result = (0.0, self.x_eq, math.nan, EQUILIBRIUM)
            elif done:
                self.result = ONE_PERIOD


ONE_PERIOD, REDO = "one period", "redo"


class Peer:
    """Attractors of the paper's slider by heyoka, one point at a time (scalar mode),
    or many in the lanes of a batch integrator (``batch_size``).

    Parameters
    ----------
    tol : float
        heyoka's tolerance (relative and absolute, per step).
    xtol : float
        agreement of successive Aitken limits of the section returns [cm].
    eps_eq : float
        an extrapolated section point within this of x_eq is the equilibrium [cm].
    at_rest : float
        no extremum of x for this long means the slider is at rest [s].
    t_max : float
        simulated time after which a point is left unconverged [s].
    batch_size : int or None
        lanes of heyoka's batch mode for the section returns (None: scalar mode).
    """

    def __init__(self, tol, xtol=1e-8, eps_eq=1e-6, at_rest=20.0, t_max=2e6,
                 batch_size=None):
        import heyoka as hy
        self.tol, self.xtol, self.eps_eq, self.at_rest, self.t_max = \
            tol, xtol, eps_eq, at_rest, t_max
        self.batch_size = batch_size
        self._outcomes = {int(hy.taylor_outcome.time_limit): TIME_LIMIT,
                          int(hy.taylor_outcome.success): NO_EVENT}
        t0 = time.perf_counter()
        self.full, self.section = integrators(tol)
        self.lanes = self._lane_integrator(tol, batch_size) if batch_size else None
        self.compile_s = time.perf_counter() - t0

    def _code(self, oc):
        """Event index of a propagation's outcome (heyoka writes -1 - index for a
        terminal event), TIME_LIMIT, NO_EVENT or FAILED (a non-finite state)."""
        code = int(oc)
        if -4 < code < 0:
            return -code - 1
        return self._outcomes.get(code, FAILED)

    def _next(self, ta, t_limit, tr):
        """Propagate ta to its next terminal event (or t_limit) for track tr."""
        t_start = ta.time
        while True:
            oc, _h0, _h1, n = ta.propagate_until(t_limit)[:4]
            tr.steps += n
            ev = self._code(oc)
            if n == 0 and ev >= 0 and ta.time == t_start:     # the event it started on
                continue
            return ev

    @staticmethod
    def _set(ta, t, state, pars):
        ta.time = t
        ta.state[:] = state
        ta.pars[:] = pars
        ta.reset_cooldowns()

    @staticmethod
    def _pars(tr, m, alpha1, alpha2):
        return [tr.s, tr.k / m, tr.r_y / m, tr.v, alpha1 / m, alpha2 / m]

    def _slide(self, tr, pars, n_full, t0, state, ta):
        """Run track tr on the scalar integrator ta until it has a result (or, in
        batch mode, until it leaves the full integrator)."""
        self._set(ta, t0, state, pars)
        while tr.result is None:
            ev = self._next(ta, tr.last + self.at_rest, tr)
            tr.event(ev, ta.time, ta.state[0], ta.state[2], n_full)
            ta.pars[0] = tr.s
            if not tr.tracking and ta is self.full and tr.result is None:
                if self.batch_size:
                    return ta.time, ta.state.copy()
                self._set(self.section, ta.time, ta.state, ta.pars)
                ta = self.section
        return None

    def _finish(self, tr, pars, m, alpha1, alpha2):
        """The observables of a track with a result (one period, or a redo)."""
        if tr.result is REDO:
            tr.tracking, tr.result = True, None
            tr.xmax = tr.xmin = tr.xs
            tr.ex = Extrapolation(self.xtol)
            tr.s, tr.last = -1.0, tr.t_b
            pars[0] = -1.0
            self._slide(tr, pars, math.inf, tr.t_b, [tr.xs, 0.0, 0.0], self.full)
        if tr.result is ONE_PERIOD:
            tr.result = self._one_period(tr, tr.ex.limit, pars)
        return tr.result + (tr.steps, tr.last, len(tr.ex.x))

    def _one_period(self, tr, x_star, pars):
        """Amplitude, mean and period of the slip cycle through the section point
        (x_star, x' = 0): one period with every extremum."""
        ta, pars = self.full, list(pars)
        pars[0] = -1.0
        self._set(ta, 0.0, [x_star, -tr.v, 0.0], pars)
        xmin = x_star
        while True:
            ev = self._next(ta, 10.0 * self.at_rest, tr)
            if ev == XMIN:
                xmin = min(xmin, ta.state[0])
            elif ev == STOP:
                ta.pars[0] = -ta.pars[0]
            elif ev == XMAX:
                T = ta.time
                return 0.5 * (max(x_star, ta.state[0]) - xmin), ta.state[2] / T, T, SLIP_CYCLE
            else:
                return math.nan, math.nan, math.nan, UNCONVERGED

    def point(self, m, k, r_y, v, alpha1, alpha2, x0=0.0):
        """The attractor of one slider started stuck at x0 (xdot0 = v > 0), scalar mode.

        Returns
        -------
        tuple
            the columns of ``COLUMNS``: amplitude [cm], mean [cm], period [s], regime
            code, Taylor steps, simulated time [s], section returns
        """
        tr = Track(self, k, r_y, v, alpha1, alpha2, x0)
        pars = self._pars(tr, m, alpha1, alpha2)
        self._slide(tr, pars, 2, tr.t_b, [tr.xs, 0.0, 0.0], self.full)
        return self._finish(tr, pars, m, alpha1, alpha2)

    def points(self, P):
        """Attractors of the rows of P (m, k, r_y, v, alpha1, alpha2): scalar mode, or
        in batch mode the first two returns of each point scalar (a stick-slip cycle
        is over by then) and the section returns in the lanes."""
        out = np.full((len(P), len(COLUMNS)), np.nan)
        if not self.batch_size:
            for i, p in enumerate(P):
                out[i] = self.point(*p)
            return out
        waiting = []                        # (index, track, pars, time, state)
        for i, p in enumerate(P):
            m, k, r_y, v, a1, a2 = p
            tr = Track(self, k, r_y, v, a1, a2, 0.0)
            pars = self._pars(tr, m, a1, a2)
            left = self._slide(tr, pars, 2, tr.t_b, [tr.xs, 0.0, 0.0], self.full)
            if left is None:
                out[i] = self._finish(tr, pars, m, a1, a2)
            else:
                waiting.append((i, tr, pars, p) + left)
        self._lanes(waiting, out)
        return out

    def _to_scalar(self, lane, out):
        """Finish the tracks left in the lanes on the scalar section integrator."""
        ta = self.lanes
        for j, L in enumerate(lane):
            if L is None:
                continue
            i, tr, pars, p = L
            if tr.result is None:
                pars = list(pars)
                pars[0] = tr.s
                self._slide(tr, pars, 0, ta.time[j], ta.state[:, j].copy(), self.section)
            out[i] = self._finish(tr, pars, p[0], p[4], p[5])

    def _lane_integrator(self, tol, B):
        """The batch integrator of the section returns: the slide's end a terminal
        event, the maxima of x a non-terminal one whose callback records (lane,
        time, x) from heyoka's dense output, so that no lane stops the others."""
        import heyoka as hy
        sys, (s, z, v) = system()
        hits = self._hits = []
        at = np.empty(B)

        def on_max(ta, t, _d_sgn, j):
            at[:] = ta.time
            at[j] = t
            hits.append((j, t, ta.update_d_output(at)[0, j]))

        neg = hy.event_direction.negative
        return hy.taylor_adaptive_batch(
            sys, np.zeros((3, B)), tol=tol, pars=np.ones((6, B)), compact_mode=False,
            t_events=[hy.t_event_batch(s * z, direction=neg)],
            nt_events=[hy.nt_event_batch(z + v, on_max, direction=neg)])

    def _lanes(self, waiting, out, horizon=4.0):
        """The section returns of the waiting tracks, batch_size at a time; every
        lane is propagated ``horizon`` seconds a call, its returns taken from the
        callback's record."""
        ta, B, hits = self.lanes, self.batch_size, self._hits
        queue = list(reversed(waiting))
        lane = [None] * B
        t_load = np.zeros(B)
        t_lim = np.array(ta.time, dtype=float)

        def load(j):
            i, tr, pars, p, t0, state = queue.pop()
            lane[j] = (i, tr, pars, p)
            times = np.array(ta.time, dtype=float)
            times[j] = t_load[j] = t0
            ta.set_time(times)
            ta.state[:, j] = state
            ta.pars[:, j] = pars
            ta.pars[0, j] = tr.s
            ta.reset_cooldowns(j)
            t_lim[j] = t0 + horizon

        def next_point(j):
            if queue:
                load(j)
            else:
                lane[j] = None
                t_lim[j] = ta.time[j]

        for j in range(B):
            next_point(j)
        while any(L is not None for L in lane):
            if not queue and sum(L is not None for L in lane) <= B // 4:
                self._to_scalar(lane, out)          # the tail: lanes would idle
                return
            hits.clear()
            ta.propagate_until(t_lim)
            now = ta.time
            for j, t, x in hits:
                L = lane[j]
                if L is not None and L[1].result is None and t > t_load[j]:
                    L[1].event(XMAX, t, x, math.nan, 0)
            for j, (oc, _h0, _h1, n) in enumerate(ta.propagate_res):
                if lane[j] is None:
                    continue
                i, tr, pars, p = lane[j]
                tr.steps += n
                if tr.result is None:
                    ev = self._code(oc)
                    if ev == STOP:
                        tr.event(STOP, now[j], ta.state[0, j], math.nan, 0)
                        ta.pars[0, j] = tr.s
                    elif ev == FAILED or now[j] - tr.last >= self.at_rest:
                        tr.event(ev if ev == FAILED else TIME_LIMIT, now[j], math.nan,
                                 math.nan, 0)
                    t_lim[j] = now[j] + horizon
                if tr.result is not None:
                    out[i] = self._finish(tr, pars, p[0], p[4], p[5])
                    next_point(j)


_PEERS = {}


def _work(tol, batch_size, points):
    """One task of a worker process: (out, CPU seconds) of ``points``; the process's
    integrators for (tol, batch_size) are compiled on its first task."""
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
        out (n, 7) in the order of ``points``; wall_s of the whole call; cpu_s, the
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
        out: array (n, 7) with the columns of ``COLUMNS``; cpu_s: this process's CPU
        time for the points [s] (the integrators' compilation excluded).
    """
    peer = Peer(tol, batch_size=batch_size, **kw)
    c0 = time.process_time()
    out = peer.points(np.asarray(points, dtype=float))
    return out, time.process_time() - c0
