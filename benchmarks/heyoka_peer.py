"""The heyoka.py peer of the Hopf map, written as an expert would for the map job.

heyoka.py (https://bluescarni.github.io/heyoka.py/) integrates ODEs by Taylor's method,
compiled for the system by LLVM, and locates events by polynomial root finding on
each step's Taylor series; in batch mode one integrator advances several systems at
once in SIMD lanes. This peer computes what sweepcore's map computes, each point's
attractor from a start stuck on the belt, for the paper's law (eq. 40, r_k = r_y,
c = 0), with everything the library offers and everything the physics gives away:

* the sliding field as a heyoka system, the sign of the relative speed
  ``z = x' - v`` a runtime parameter ``s`` (one compiled integrator for every point
  and both slide directions; ``z*z*z``, since heyoka's ``pow(z, 3)`` has NaN
  derivatives at z = 0);
* a terminal event at ``s z = 0`` with direction (the slide ends where z returns to
  0, never where it leaves 0), then the stick in closed form (x moves with the belt
  to the breakaway point r_y/k) or a reversal (s flips when |k x| >= r_y);
* a start stuck on the belt means every stick ends at the same breakaway point: the
  first stick closes a stick-slip cycle, exact in one period;
* otherwise the attractor is the fixed point of the return map on the section
  x' = 0 (maxima of x), found by Aitken extrapolation of the returns over a lag that
  grows with their count (the first third, the transient, is never used), accepted
  when three successive extrapolations, their spread times the lag, agree to
  ``xtol``; then one period from the extrapolated point gives amplitude, mean and
  period (a plain "successive returns agree" test stops far too early next to v*,
  where the returns creep);
* equilibria by decay: a section point (or the extrapolated fixed point, or the last
  three extrapolations) within ``eps_eq`` of the analytic x_eq (eq. 43), or no
  maximum of x for ``at_rest`` = 20 s while the section is on.

Two integrators, so that heyoka's error control (relative to the largest state
component) sees the state the job measures:

* the *measure* integrator, (x, z, int x) with terminal events at the slide's end
  and at both extrema of x, for what needs every extremum: the first two returns of
  a point (a stick-slip cycle is over by then), one period through the fixed point,
  and a slide that sticks after a long transient. The running integral of x (the
  mean's quadrature) is added to a sum and reset to 0 at every extremum, so it never
  exceeds about x times half a period;
* the *lane* integrator, (x, z) and a clock c in [-1, 0], in batch mode (or
  scalar), for the transient's section returns. The section event is compiled with
  a per-lane switch ``on``, ``on x' + 1 - on`` (rootless when off), and the clock's
  zero is a timer event that turns it on again: once the returns of a point
  outnumber ``2 keep``, every other one is dropped and only every K-th return (K
  doubling) is sampled, the section off for K - 1/2 periods in between, so Python
  handles O(keep log N) events of a point that needs N returns. Each terminal event
  stops every lane of the batch (heyoka's rule); the lane whose point is done is
  refilled with the next point at once.

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
STOP, XMAX, XMIN = 0, 1, 2            # events of the measure integrator
SECTION, TIMER = 1, 2                 # the lane integrator's (STOP is 0 in both)
TIME_LIMIT, FAILED, NO_EVENT = -1, -2, -3   # NO_EVENT: a lane stopped by another's event
FAR = 1e15                            # s: a propagation ends on an event, never here
ONE_PERIOD, REDO = "one period", "redo"


def field():
    """The sliding field: state (x, z), parameters (s, k/m, r_y/m, v, alpha1/m,
    alpha2/m); z = x' - v [cm/s], eq. (40) with sgn(z) = s frozen."""
    import heyoka as hy
    x, z = hy.make_vars("x", "z")
    s, km, rm, v, a1, a2 = (hy.par[i] for i in range(6))
    return x, [(x, z + v), (z, -km * x - rm * s + a1 * z - a2 * z * z * z)], s * z, z + v


def measure_integrator(tol):
    """Scalar Taylor integrator of (x, z, int x) at ``tol`` with the terminal events
    [slide ends, maximum of x, minimum of x]."""
    import heyoka as hy
    x, sys, sz, xdot = field()
    q = hy.make_vars("q")
    neg, pos = hy.event_direction.negative, hy.event_direction.positive
    events = [hy.t_event(sz, direction=neg),         # z back to 0 from the slide's side
              hy.t_event(xdot, direction=neg),       # x' = 0 falling: a maximum of x
              hy.t_event(xdot, direction=pos)]
    return hy.taylor_adaptive(sys + [(q, x)], [0.0, 0.0, 0.0], tol=tol, t_events=events,
                              pars=[-1.0, 10.0, 2.0, 1.0, 0.2, 0.01], compact_mode=False)


def lane_integrator(tol, batch=None):
    """Taylor integrator of (x, z, c) at ``tol``, ``batch`` lanes (None: scalar), with
    the terminal events [slide ends, maximum of x if par[6] = 1, c = 0].

    c is a clock that runs from -1 to 0 at the rate par[7] [1/s]. The section's
    switch and the clock are both of the state's size: heyoka's step control heeds
    the event functions, and an event of ``time`` (which grows to 1e5 s) or a large
    constant added to x' (to move its root away) loosens the tolerance on x, x' as an
    unreset integral does (measured: a decaying oscillation of 1e-5 cm next to v*
    held at 4e-5 cm).
    """
    import heyoka as hy
    _x, sys, sz, xdot = field()
    c = hy.make_vars("c")
    on, rate = hy.par[6], hy.par[7]
    neg, pos = hy.event_direction.negative, hy.event_direction.positive
    ev = hy.t_event if batch is None else hy.t_event_batch
    events = [ev(sz, direction=neg), ev(on * xdot + (1.0 - on), direction=neg),
              ev(c, direction=pos)]
    sys = sys + [(c, rate)]
    pars = [-1.0, 10.0, 2.0, 1.0, 0.2, 0.01, 0.0, 0.0]
    if batch is None:
        return Scalar(hy.taylor_adaptive(sys, [0.0, 0.0, -1.0], tol=tol, t_events=events,
                                         pars=pars, compact_mode=False))
    return Batch(hy.taylor_adaptive_batch(
        sys, np.repeat([[0.0], [0.0], [-1.0]], batch, axis=1), tol=tol, t_events=events,
        pars=np.repeat(np.array(pars)[:, None], batch, axis=1), compact_mode=False))


class Batch:
    """The lane integrator in batch mode: what the driver asks of it."""

    def __init__(self, ta):
        self.ta, self.lanes = ta, ta.batch_size

    def propagate(self, t):
        """Propagate every lane towards t [s] until a terminal event in any lane;
        (outcome code, steps) of each lane."""
        self.ta.propagate_until(t)
        return [(int(r[0]), r[3]) for r in self.ta.propagate_res]

    def time(self, j):
        return float(self.ta.time[j])

    def x(self, j):
        return float(self.ta.state[0, j])

    def get(self, j):
        """(time, state, pars) of lane j."""
        ta = self.ta
        return float(ta.time[j]), ta.state[:, j].copy(), ta.pars[:, j].copy()

    def put(self, j, t, state, pars):
        ta = self.ta
        times = np.array(ta.time, dtype=float)
        times[j] = t
        ta.set_time(times)
        ta.state[:, j] = state
        ta.pars[:, j] = pars
        ta.reset_cooldowns(j)

    def par(self, j, i, value):
        self.ta.pars[i, j] = value

    def wind(self, j, rate):
        """Restart lane j's clock at -1, to reach 0 after 1/rate seconds."""
        self.ta.state[2, j] = -1.0
        self.ta.pars[7, j] = rate


class Scalar(Batch):
    """The lane integrator in scalar mode, seen as one lane."""

    def __init__(self, ta):
        self.ta, self.lanes = ta, 1

    def propagate(self, t):
        oc, _h0, _h1, n = self.ta.propagate_until(t)[:4]
        return [(int(oc), n)]

    def time(self, j):
        return self.ta.time

    def x(self, j):
        return float(self.ta.state[0])

    def get(self, j):
        return self.ta.time, self.ta.state.copy(), self.ta.pars.copy()

    def put(self, j, t, state, pars):
        ta = self.ta
        ta.time = t
        ta.state[:] = state
        ta.pars[:] = pars
        ta.reset_cooldowns()

    def par(self, j, i, value):
        self.ta.pars[i] = value

    def wind(self, j, rate):
        self.ta.state[2] = -1.0
        self.ta.pars[7] = rate


def aitken(seq, lag):
    """Aitken's extrapolation of the limit of ``seq`` from its last element and the
    ones ``lag`` and ``2 lag`` before (the last element if the differences vanish)."""
    a, b, c = seq[-1 - 2 * lag], seq[-1 - lag], seq[-1]
    d1, d0 = c - b, b - a
    den = d1 - d0
    return c if den == 0.0 else c - d1 * d1 / den


class Returns:
    """Returns to the section, every K-th one kept, and their Aitken limits.

    The kept returns are equally spaced, K returns apart: when they reach ``2 keep``
    every other one is dropped and K doubles. Aitken's limit over a lag of a third of
    the kept returns (the first third, the transient, is never used); converged when
    the last three limits, their spread multiplied by the lag, agree to ``xtol``
    [cm]: next to v* the returns converge algebraically for long (the cubic term of
    the law outweighs q), and the limit drifts by a little each return for many
    returns; over a lag the drift is what is left. A sampled return that is not the
    K-th (the period changed) restarts the record.
    """

    def __init__(self, xtol, keep):
        self.xtol, self.keep = xtol, keep
        self.x, self.t = [], []
        self.K, self.period, self.count = 1, math.nan, 0
        self.limits = []

    def add(self, t, x):
        """Record a return at time t [s], x [cm]; True when converged."""
        if self.t:
            n = max(1, round((t - self.t[-1]) / self.period)) if self.K > 1 else 1
            if n != self.K:
                self.x, self.t, self.limits = [], [], []
            else:
                self.period = (t - self.t[-1]) / self.K
            self.count += n
        else:
            self.count += 1
        self.x.append(x)
        self.t.append(t)
        if len(self.x) >= 2 * self.keep:            # keep the last one and every other
            self.x, self.t = self.x[1::2], self.t[1::2]
            self.K *= 2
            self.limits = []
        n = len(self.x) - 1
        if n < 2:
            return False
        lag = n // 3 or 1
        self.limits = self.limits[-2:] + [aitken(self.x, lag)]
        return len(self.limits) == 3 and lag * (max(self.limits) - min(self.limits)) \
            <= self.xtol

    @property
    def limit(self):
        return self.limits[-1] if self.limits else (self.x[-1] if self.x else math.nan)


class Track:
    """One point from its breakaway: its parameters, its section returns, the sign of
    its slide and, once known, its result (a tuple of observables, ``ONE_PERIOD``:
    the slip cycle through ``ret.limit``, or ``REDO``: it stuck after its extremes
    stopped being tracked)."""

    def __init__(self, peer, m, k, r_y, v, alpha1, alpha2, x0):
        self.peer, self.k, self.r_y, self.v = peer, k, r_y, v
        self.pars = [-1.0, k / m, r_y / m, v, alpha1 / m, alpha2 / m]
        self.xs, self.x_eq = r_y / k, (r_y - alpha1 * v + alpha2 * v ** 3) / k
        self.t_b = (self.xs - x0) / v                # breakaway at the end of the stick
        self.ret = Returns(peer.xtol, peer.keep)
        self.s, self.last, self.result, self.steps = -1.0, self.t_b, None, 0
        self.section_on = True

    def section(self, t, x):
        """A sampled maximum of x at time t [s]: the equilibrium (this point, or the
        last three extrapolated limits, within ``eps_eq`` of x_eq: next to v* the
        limits reach x_eq long before they agree to ``xtol``), the slip cycle, or
        nothing yet."""
        self.last = t
        done = self.ret.add(t, x)
        eps, lims = self.peer.eps_eq, self.ret.limits
        near = len(lims) == 3 and max(abs(l - self.x_eq) for l in lims) <= eps
        if x - self.x_eq <= eps or near or (done and self.ret.limit - self.x_eq <= eps):
            self.result = (0.0, self.x_eq, math.nan, EQUILIBRIUM)
        elif done:
            self.result = ONE_PERIOD

    def failed(self):
        self.result = (math.nan, math.nan, math.nan, UNCONVERGED)

    def at_rest(self):
        self.result = (0.0, self.x_eq, math.nan, EQUILIBRIUM)


class Peer:
    """Attractors of the paper's slider by heyoka, the transients in the lanes of a
    batch integrator (``batch_size``) or on a scalar one (None).

    Parameters
    ----------
    tol : float
        heyoka's tolerance (relative and absolute, per step).
    xtol : float
        agreement of successive Aitken limits of the section returns [cm].
    eps_eq : float
        a section point within this of x_eq is the equilibrium [cm].
    at_rest : float
        no maximum of x for this long, the section on, means the slider is at rest [s].
    t_max : float
        simulated time after which a point is left unconverged [s].
    keep : int
        returns kept per point before every other one is dropped (K doubles).
    k_lanes : int
        in batch mode, a point goes to the lanes once every K-th return is sampled,
        K >= k_lanes (sooner, the lanes' events are too frequent for them to pay).
    batch_size : int or None
        lanes of heyoka's batch mode for the transients (None: scalar mode).
    """

    def __init__(self, tol, xtol=1e-7, eps_eq=1e-6, at_rest=20.0, t_max=2e6, keep=8,
                 k_lanes=16, batch_size=None):
        import heyoka as hy
        self.tol, self.xtol, self.eps_eq, self.at_rest, self.t_max, self.keep = \
            tol, xtol, eps_eq, at_rest, t_max, keep
        self.batch_size, self.k_lanes = batch_size, k_lanes
        self._codes = {int(hy.taylor_outcome.time_limit): TIME_LIMIT,
                       int(hy.taylor_outcome.success): NO_EVENT}
        t0 = time.perf_counter()
        self.measure = measure_integrator(tol)
        self.scalar = lane_integrator(tol)
        self.lanes = lane_integrator(tol, batch_size) if batch_size else self.scalar
        self.compile_s = time.perf_counter() - t0

    def _code(self, oc):
        """Event index of an outcome (heyoka writes -1 - index for a terminal event),
        TIME_LIMIT, NO_EVENT or FAILED (a non-finite state)."""
        if -4 < oc < 0:
            return -oc - 1
        return self._codes.get(oc, FAILED)

    # ------------------------------------------------ the measure integrator
    def _measure(self, tr, t0, state, s, n_returns):
        """Every extremum of track tr from (t0, state, s) on the measure integrator,
        until its result or ``n_returns`` maxima of x; (t, (x, z), s) where it left
        off, or None. A stick sets the stick-slip cycle's result."""
        ta = self.measure
        ta.time = t0
        ta.state[:] = [state[0], state[1], 0.0]
        ta.pars[:] = tr.pars
        ta.pars[0] = s
        ta.reset_cooldowns()
        xmax = xmin = state[0]
        total, n = 0.0, 0                  # int x [cm s] before the last reset
        while tr.result is None:
            oc, _h0, _h1, steps = ta.propagate_until(tr.last + self.at_rest)[:4]
            tr.steps += steps
            ev, t, x = self._code(int(oc)), ta.time, ta.state[0]
            total += ta.state[2]
            ta.state[2] = 0.0              # the integral's scale stays the state's
            if ev == FAILED or t - tr.t_b > self.t_max:
                tr.failed()
            elif ev == TIME_LIMIT:
                tr.at_rest()
            elif ev == STOP:
                tr.last = t
                if abs(tr.k * x) < tr.r_y:           # sticks: back to breakaway
                    if not math.isinf(n_returns):
                        tr.result = REDO
                        break
                    xmin = min(xmin, x)
                    t_stick = (tr.xs - x) / tr.v
                    T = t - tr.t_b + t_stick
                    tr.result = (0.5 * (xmax - xmin), (total + 0.5 * (x + tr.xs) * t_stick)
                                 / T, T, STICK_SLIP)
                else:
                    ta.pars[0] = -ta.pars[0]         # slide-slide reversal
            elif ev == XMIN:
                tr.last = t
                xmin = min(xmin, x)
            elif ev == XMAX:
                xmax = max(xmax, x)
                tr.section(t, x)
                n += 1
                if n >= n_returns and tr.result is None:
                    return t, ta.state[:2].copy(), float(ta.pars[0])
        return None

    def _start(self, tr):
        """The first two returns of track tr from its breakaway (a stick-slip cycle
        is over by then)."""
        return self._measure(tr, tr.t_b, (tr.xs, 0.0), -1.0, 2)

    def _finish(self, tr):
        """The observables of a track with a result (a redo, one period)."""
        if tr.result is REDO:
            tr.result, tr.last, tr.s = None, tr.t_b, -1.0
            tr.ret = Returns(self.xtol, self.keep)
            self._measure(tr, tr.t_b, (tr.xs, 0.0), -1.0, math.inf)
        if tr.result is ONE_PERIOD:
            tr.result = self._one_period(tr, tr.ret.limit)
        return tr.result + (tr.steps, tr.last, tr.ret.count)

    def _one_period(self, tr, x_star):
        """Amplitude, mean and period of the slip cycle through the section point
        (x_star, x' = 0): one period with every extremum."""
        ta = self.measure
        ta.time = 0.0
        ta.state[:] = [x_star, -tr.v, 0.0]
        ta.pars[:] = tr.pars
        ta.reset_cooldowns()
        xmin, total = x_star, 0.0
        while True:
            oc, _h0, _h1, steps = ta.propagate_until(10.0 * self.at_rest)[:4]
            tr.steps += steps
            ev = self._code(int(oc))
            total += ta.state[2]
            ta.state[2] = 0.0
            if ev == XMIN:
                xmin = min(xmin, ta.state[0])
            elif ev == STOP:
                ta.pars[0] = -ta.pars[0]
            elif ev == XMAX and ta.time == 0.0:     # the point it started on
                continue
            elif ev == XMAX:
                T = ta.time
                return 0.5 * (max(x_star, ta.state[0]) - xmin), total / T, T, SLIP_CYCLE
            else:
                return math.nan, math.nan, math.nan, UNCONVERGED

    # ------------------------------------------------ the lanes
    def _lane_event(self, la, j, tr, ev):
        """Take the terminal event ``ev`` of lane j (track tr); True when done."""
        t = la.time(j)
        if ev == FAILED or ev == TIME_LIMIT or t - tr.t_b > self.t_max:
            tr.failed()
        elif ev == STOP:
            tr.last = t
            if abs(tr.k * la.x(j)) < tr.r_y:
                tr.result = REDO                    # stuck after the first returns
            else:
                tr.s = -tr.s
                la.par(j, 0, tr.s)
        elif ev == SECTION:
            if t == tr.ret.t[-1]:
                return False                        # the return it was loaded at
            tr.section(t, la.x(j))
            ret = tr.ret
            if tr.result is None and ret.K > 1:     # off until the K-th return is near
                tr.section_on = False
                la.par(j, 6, 0.0)
                la.wind(j, 1.0 / ((ret.K - 0.5) * ret.period))
            elif tr.result is None:
                la.wind(j, 1.0 / self.at_rest)
        elif ev == TIMER:
            if tr.section_on:                       # no maximum for at_rest seconds
                tr.at_rest()
            else:
                tr.section_on = True
                la.par(j, 6, 1.0)
                la.wind(j, 1.0 / self.at_rest)
        return tr.result is not None

    def _run_lanes(self, la, waiting, out):
        """The transients of the waiting tracks [(index, track, t, state, pars)] on the
        lanes of ``la``, each lane refilled as its point is done; the last tracks (a
        quarter of the lanes or fewer) go on alone on the scalar integrator, where
        they would otherwise leave the other lanes idle."""
        B = la.lanes
        queue = list(reversed(waiting))
        lane = [None] * B

        def fill(j):
            if not queue:                           # parked: a harmonic oscillator
                lane[j] = None                      # whose events never fire
                la.put(j, la.time(j), [0.3, -1.0, -1.0],
                       [-1.0, 10.0, 2.0, 1.0, 0.0, 0.0, 0.0, 0.0])
                return
            i, tr, t, state, pars = queue.pop()
            lane[j] = (i, tr)
            la.put(j, t, state, pars)

        for j in range(B):
            fill(j)
        while True:
            active = [j for j in range(B) if lane[j] is not None]
            if not queue and len(active) <= B // 4:
                for i, tr, t, state, pars in [lane[j] + la.get(j) for j in active]:
                    self._run_one(i, tr, t, state, pars, out)
                return
            for j, res in enumerate(la.propagate(FAR)):
                if lane[j] is not None and self._lane_step(la, j, lane[j][1], res):
                    out[lane[j][0]] = self._finish(lane[j][1])
                    fill(j)

    def _run_one(self, i, tr, t, state, pars, out, sparse=False):
        """Track tr (row i) alone on the scalar lane integrator from (t, state, pars)
        until its result, or with ``sparse`` until its section is sampled (the
        lanes' work); None, or (i, tr, t, state, pars) where it left off."""
        la = self.scalar
        la.put(0, t, state, pars)
        while not self._lane_step(la, 0, tr, la.propagate(FAR)[0]):
            if sparse and tr.ret.K >= self.k_lanes:
                return (i, tr) + la.get(0)
        out[i] = self._finish(tr)
        return None

    def _lane_step(self, la, j, tr, res):
        """Count the steps of lane j's propagation and take its event; True when its
        track is done."""
        oc, steps = res
        tr.steps += steps
        ev = self._code(oc)
        return ev != NO_EVENT and self._lane_event(la, j, tr, ev)

    def points(self, P):
        """Attractors of the rows of P (m, k, r_y, v, alpha1, alpha2), each started
        stuck on the belt at x = 0: the first two returns on the measure integrator,
        every return on the scalar lane integrator until they are sampled, then (in
        batch mode) the transient in the lanes, where events are rare enough that
        heyoka's rule (one lane's terminal event stops all) costs little.

        Returns
        -------
        array (n, 7)
            the columns of ``COLUMNS``: amplitude [cm], mean [cm], period [s], regime
            code, Taylor steps, simulated time [s], section returns
        """
        out = np.full((len(P), len(COLUMNS)), np.nan)
        waiting = []
        for i, p in enumerate(P):
            tr = Track(self, *p, 0.0)
            left = self._start(tr)
            if left is None:
                out[i] = self._finish(tr)
                continue
            t, state, tr.s = left
            pars = [tr.s] + tr.pars[1:] + [1.0, 1.0 / self.at_rest]
            left = self._run_one(i, tr, t, [state[0], state[1], -1.0], pars, out,
                                 sparse=self.lanes is not self.scalar)
            if left is not None:
                waiting.append(left)
        if waiting:
            self._run_lanes(self.lanes, waiting, out)
        return out

    def point(self, m, k, r_y, v, alpha1, alpha2):
        """The attractor of one slider started stuck at x = 0: the row of ``points``."""
        return self.points(np.array([[m, k, r_y, v, alpha1, alpha2]]))[0]


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
