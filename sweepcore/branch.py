"""One branch of forced responses: the fixed points of the stroboscopic map P^n
followed in one parameter by pseudo-arclength continuation, with the points where
it bifurcates located on it (the engine of :func:`sweepcore.follow_response` and of
the forced boundary searches, :mod:`sweepcore.boundaries.forced`).

The unknowns are ``y = (x, xdot, lam)``: the state at t = 0 mod n T (where the map is
taken) and the parameter, scaled by ``S = (L, Lv, Lambda)`` (the length scale, the
speed scale and the parameter's). A point of the branch solves
``F(y) = (P^n(x, xdot; lam) - (x, xdot)) / (L, Lv) = 0``. ``P^n`` and its Jacobian
``J = d(x, zdot)/d(x0, zdot0)`` come from the kernels (``sweepcore.compiled.images``:
the variational equations with a saltation matrix at every switch); a start that is
stuck is one number (x: the stick forgets the velocity), so J's second column is 0
there, which makes ``F`` one continuous, piecewise-smooth map on either side of a
stick's end through the section. ``dP^n/dlam`` is a central difference of two more
images (``DIFF`` of the parameter's scale; one-sided next to a bound the parameter
may not cross). The predictor steps along the tangent (the null vector of ``DF``,
the cross product of its two rows, oriented along the secant); the corrector is
Newton's method on ``F = 0`` and ``t . (y - y_k) = sigma`` (Keller's
pseudo-arclength condition, after Dankowicz & Schilder's COCO), to ``|F| <= tol``,
each step halved until the residual decreases.

* A step whose point has another pattern (finite sticks, zero-duration stops per
  response period) than its base is halved until the parameter moves less than
  ``xtol`` times its value over it: the change lies between the two points. Next to
  a grazing the arms of the two patterns run a few degrees apart, and a corrector
  started between them lands on either: halving from the last point of the old
  pattern keeps to its arm. The new arm is then followed ahead, or backwards where
  no step finds it ahead; an arm that ends with nothing ahead (a non-smooth fold)
  turns onto the other arm behind its tip (:func:`turn`).
* Between two points of one pattern (parametrised by sigma on the hyperplanes of
  the first), a sign change of a test function is solved by the Illinois method:
  ``det(J - I)`` (a multiplier through +1: a fold if the tangent's parameter
  component changes sign too, else a branch point), ``det(J + I)`` (through -1:
  period doubling), ``det(J) - 1`` between complex multipliers (through the unit
  circle: torus).
"""
from __future__ import annotations

import math

import numpy as np

from . import compiled
from ._kernels import codes, layout

# labels of a point (the Dataset's ``special``)
REGULAR, START, END, FOLD, BRANCH_POINT, PERIOD_DOUBLING, TORUS, STICK_ONSET, \
    GRAZING, STOPS_CHANGE = range(10)
SPECIAL_NAMES = {REGULAR: "regular", START: "start", END: "end", FOLD: "fold",
                 BRANCH_POINT: "branch_point", PERIOD_DOUBLING: "period_doubling",
                 TORUS: "torus", STICK_ONSET: "stick_onset", GRAZING: "grazing",
                 STOPS_CHANGE: "stops_change"}
PATTERN_EVENTS = (STICK_ONSET, GRAZING, STOPS_CHANGE)
# a point the corrector could not solve at the smallest step (beside the kernels'
# status codes, which an image that failed reports)
CORRECTOR_FAILED = 64

DIFF = 1e-6         # step of the parameter's differences, of its scale
MAX_NEWTON = 10     # corrector iterations
MAX_JUMP = 0.5      # a Newton step longer than this (scaled) is a failure
MAX_HALVINGS = 8    # of a Newton step whose residual does not decrease
COS_MIN = 0.9       # consecutive tangents at least this aligned (else a smaller step)
KINK = 1e-3         # ... unless the step is below KINK of max_step: a kink (a switch)
RESTART = 0.02      # the step after a located change, of max_step
FLIP = 1e-4         # past a change, the new arm is taken backwards where no step of
                    # FLIP max_step finds it ahead (the change was a non-smooth fold)
MAX_ROOT = 80       # iterations of one event's root or bisection


class Point:
    """One corrected point: ``w`` (scaled unknowns), ``F`` (scaled residual), ``DF``
    (2 x 3, scaled), ``J`` (2 x 2, unscaled), ``obs`` (the image's observables row,
    ``layout.NFOB`` columns), ``mode0`` (the start's phase), ``sigma`` (its place
    on the segment it was solved on), ``iterations``."""

    __slots__ = ("w", "F", "DF", "J", "obs", "mode0", "sigma", "iterations")

    def pattern(self) -> tuple:
        return (int(self.obs[layout.OB_STICKS_PER_PERIOD]),
                int(self.obs[layout.OB_STOPS_PER_PERIOD]))

    def tests(self) -> np.ndarray:
        """``det(J - I)``, ``det(J + I)``, ``det J - 1`` (NaN for real multipliers)."""
        (a, b), (c, d) = self.J
        det, tr = a * d - b * c, a + d
        torus = det - 1.0 if tr * tr < 4.0 * det else math.nan
        return np.array([det - tr + 1.0, det + tr + 1.0, torus])

    def multipliers(self) -> np.ndarray:
        mu = np.linalg.eigvals(self.J)
        return mu[np.argsort(-np.abs(mu), kind="stable")]


class Failed(Exception):
    """A correction that did not converge: ``status`` says why (a kernel status of
    an image, or ``CORRECTOR_FAILED``)."""

    def __init__(self, status: int, w):
        super().__init__(status)
        self.status, self.w = status, w


class Problem:
    """P^n of one forced kernel row with the parameter of columns ``cols`` free.

    ``scales`` = (L [cm], Lv [cm/s], Lambda [units of the parameter]); ``lower``:
    a bound the parameter's differences may not cross (None: none)."""

    def __init__(self, row, law, load, cols, n: int, o, tol: float, scales,
                 lower=None):
        self.base = np.array(row, float)
        self.laws, self.loads = (law,), (load,)
        self.base[layout.LAW] = 0.0
        self.base[layout.LOAD] = 0.0
        self.cols, self.n, self.o, self.tol = tuple(cols), int(n), o, float(tol)
        self.S = np.asarray(scales, float)
        self.lower = lower
        self.images = 0

    def lam(self, w) -> float:
        return float(w[2] * self.S[2])

    def scaled(self, x, xdot, lam) -> np.ndarray:
        return np.array([x, xdot, lam]) / self.S

    def _run(self, x, xdot, lams):
        P = np.repeat(self.base[None, :], len(lams), axis=0)
        P[:, layout.X0], P[:, layout.XD0] = x, xdot
        for c in self.cols:
            P[:, c] = lams
        out = np.empty((len(lams), layout.NFOB + layout.NIM))
        compiled.images(P, self.laws, self.loads, self.o, self.n, out)
        self.images += len(lams)
        return out

    def evaluate(self, w) -> Point:
        """The residual, its derivative and the observables at ``w``; raises
        :class:`Failed` where an image fails."""
        x, xdot, lam = w * self.S
        h = DIFF * self.S[2]
        central = self.lower is None or lam - h >= self.lower
        out = self._run(x, xdot, [lam, lam + h, lam - h] if central
                        else [lam, lam + h, lam + 2.0 * h])
        status = out[:, layout.OB_STATUS]
        if not (status == codes.OK).all():
            raise Failed(int(status[status != codes.OK][0]), w)
        im = out[:, layout.NFOB:]
        img = np.stack([im[:, layout.IM_X], im[:, layout.IM_XDOT]], axis=1)
        if central:
            dlam = (img[1] - img[2]) / (2.0 * h)
        else:
            dlam = (-3.0 * img[0] + 4.0 * img[1] - img[2]) / (2.0 * h)
        J = im[0, layout.IM_J:layout.IM_J + 4].reshape(2, 2).copy()
        if int(im[0, layout.IM_MODE0]) == codes.STICK:
            J[:, 1] = 0.0                   # a stuck start is its position alone
        pt = Point()
        pt.w = np.array(w, float)
        pt.F = (img[0] - (x, xdot)) / self.S[:2]
        A = np.empty((2, 3))
        A[:, :2] = (J - np.eye(2)) * self.S[None, :2] / self.S[:2, None]
        A[:, 2] = dlam * self.S[2] / self.S[:2]
        pt.DF, pt.J, pt.obs = A, J, out[0, :layout.NFOB].copy()
        pt.mode0 = int(im[0, layout.IM_MODE0])
        pt.sigma, pt.iterations = math.nan, 0
        return pt

    def correct(self, w0, row, rhs, deflate=None) -> Point:
        """Newton's method on ``F(w) = 0`` and ``row . w = rhs`` from ``w0`` (which
        satisfies the second); raises :class:`Failed`. ``deflate``: a root to keep
        away from (deflated Newton, Farrell, Birkisson & Funke, SIAM J. Sci.
        Comput. 37 (2015): the residual times ``1/|w - root|^2 + 1``)."""
        pt = self.evaluate(np.array(w0, float))
        for it in range(MAX_NEWTON):
            if np.max(np.abs(pt.F)) <= self.tol:
                pt.iterations = it
                return pt
            res = np.append(pt.F, row @ pt.w - rhs)
            try:
                d = np.linalg.solve(np.vstack([pt.DF, row]), -res)
            except np.linalg.LinAlgError:
                raise Failed(CORRECTOR_FAILED, pt.w) from None
            if deflate is not None:
                M, grad = _deflation(pt.w, deflate)
                d = d / (1.0 - grad @ d / M)
            if not np.all(np.isfinite(d)) or np.max(np.abs(d)) > MAX_JUMP:
                raise Failed(CORRECTOR_FAILED, pt.w)
            pt = self._descend(pt, d, res, row, rhs, deflate)
        raise Failed(CORRECTOR_FAILED, pt.w)

    def _descend(self, pt: Point, d, res, row, rhs, deflate=None) -> Point:
        """The Newton step d from pt, halved until the residual decreases (a
        switch between w and w + d changes the Jacobian: a full step from one
        side can overshoot into the other and cycle)."""
        norm, alpha = np.linalg.norm(res) * _deflation(pt.w, deflate)[0], 1.0
        for _ in range(MAX_HALVINGS):
            try:
                trial = self.evaluate(pt.w + alpha * d)
            except Failed:
                alpha *= 0.5
                continue
            new = np.linalg.norm(np.append(trial.F, row @ trial.w - rhs))
            if new <= self.tol or new * _deflation(trial.w, deflate)[0] <= \
                    (1.0 - 1e-4 * alpha) * norm:
                return trial
            alpha *= 0.5
        raise Failed(CORRECTOR_FAILED, pt.w)

    def at_parameter(self, w0, lam: float) -> Point:
        """The point of the branch at the parameter ``lam``, from ``w0``."""
        w = np.array(w0, float)
        w[2] = lam / self.S[2]
        return self.correct(w, np.array([0.0, 0.0, 1.0]), w[2])

    def on_segment(self, base: Point, t, sigma: float, guess) -> Point:
        """The point ``t . (w - base.w) = sigma`` of the branch, from ``guess``
        moved onto that hyperplane."""
        g = np.asarray(guess, float)
        g = g + (sigma - t @ (g - base.w)) * t
        pt = self.correct(g, t, sigma + t @ base.w)
        pt.sigma = sigma
        return pt


def _deflation(w, root):
    """The deflation factor ``M = 1/|w - root|^2 + 1`` and its gradient (1, 0
    without a root)."""
    if root is None:
        return 1.0, 0.0
    r = w - root
    q = max(float(r @ r), 1e-300)
    return 1.0 / q + 1.0, -2.0 * r / (q * q)


def tangent(pt: Point, orient=None) -> np.ndarray:
    """The unit null vector of ``DF`` at ``pt``, with ``t . orient >= 0``."""
    t = np.cross(pt.DF[0], pt.DF[1])
    norm = np.linalg.norm(t)
    if not (math.isfinite(norm) and norm > 0.0):     # DF of rank < 2: no direction
        raise Failed(CORRECTOR_FAILED, pt.w)
    t = t / norm
    return -t if orient is not None and t @ orient < 0.0 else t


# ------------------------------------------------------------------ the events
def pattern_kind(a: tuple, b: tuple) -> int:
    """The label of a change of (sticks, stops) per response period from a to b."""
    if a[0] != b[0]:
        return STICK_ONSET
    return GRAZING if (a[1] - b[1]) % 2 == 0 else STOPS_CHANGE


def _xtol(prob: Problem, xtol: float, lam: float) -> float:
    """The bracket an event is located to in the parameter [its units]."""
    return xtol * max(abs(lam), 1e-3 * prob.S[2])


def _event_step(prob: Problem, base: Point, t, xtol: float) -> float:
    """The step below which a pattern change beyond ``base`` is located: the
    parameter moves less than the event's bracket over it."""
    return min(max(_xtol(prob, xtol, prob.lam(base.w)) / prob.S[2]
                   / max(abs(t[2]), 1e-6), 1e-13), 1e-4)


def _root(prob, base, t, a, b, which: int, xtol):
    """The point between a and b (sigma a < b on the segment from base along t)
    where test ``which`` (of ``Point.tests``) is 0: the Illinois method on sigma.
    Returns (point, its error in the parameter, status): the error is the
    secant's, |g| over the slope of g in the parameter across the last bracket."""
    ga, gb = a.tests()[which], b.tests()[which]
    best = a if abs(ga) < abs(gb) else b
    side = 0
    for _ in range(MAX_ROOT):
        if b.sigma - a.sigma <= 1e-14 * max(1.0, abs(b.sigma)):
            break
        s = (a.sigma * gb - b.sigma * ga) / (gb - ga)
        lo, hi = a.sigma + 1e-3 * (b.sigma - a.sigma), b.sigma - 1e-3 * (b.sigma - a.sigma)
        s = min(max(s, lo), hi)
        f = (s - a.sigma) / (b.sigma - a.sigma)
        try:
            m = prob.on_segment(base, t, s, a.w + f * (b.w - a.w))
        except Failed as e:
            return best, abs(prob.lam(b.w) - prob.lam(a.w)), e.status
        gm = m.tests()[which]
        if abs(gm) < abs(best.tests()[which]):
            best = m
        if gm == 0.0 or not math.isfinite(gm) or abs(gm) <= 1e-13:
            break
        if (gm > 0) == (ga > 0):
            a, ga = m, gm
            if side == -1:
                gb *= 0.5
            side = -1
        else:
            b, gb = m, gm
            if side == 1:
                ga *= 0.5
            side = 1
    raw_a, raw_b = a.tests()[which], b.tests()[which]
    slope = abs(raw_b - raw_a) / max(abs(prob.lam(b.w) - prob.lam(a.w)), 1e-300)
    error = min(abs(best.tests()[which]) / slope if slope > 0 else math.inf,
                abs(prob.lam(b.w) - prob.lam(a.w)))
    ok = error <= _xtol(prob, xtol, prob.lam(best.w))
    return best, error, codes.OK if ok else CORRECTOR_FAILED


def smooth_events(prob, base: Point, t, new: Point, xtol: float) -> list:
    """``[(point, kind, width, status)]``: the test-function events between
    ``base`` (sigma 0) and ``new`` (one pattern, solved on the segment from base
    along t), in order along it."""
    base.sigma = 0.0
    out = []
    ga, gb = base.tests(), new.tests()
    for which, kind in ((0, FOLD), (1, PERIOD_DOUBLING), (2, TORUS)):
        if not (math.isfinite(ga[which]) and math.isfinite(gb[which])) or \
                (ga[which] > 0) == (gb[which] > 0) or ga[which] == 0.0:
            continue
        pt, width, status = _root(prob, base, t, base, new, which, xtol)
        if kind == FOLD:        # the branch turns back, or another branch crosses it
            ta, tb = tangent(base, t), tangent(new, t)
            kind = FOLD if (ta[2] > 0) != (tb[2] > 0) else BRANCH_POINT
        out.append((pt, kind, width, status))
    return sorted(out, key=lambda e: e[0].sigma)


TURN_STEPS = (1e-6, 1e-5, 1e-4, 1e-3)   # behind a tip, where the other arm is sought


def turn(prob: Problem, tip: Point, t):
    """The other arm at the end ``tip`` of an arm followed along t (a non-smooth
    fold: both arms leave the switch on the same side): a point of another pattern
    on a hyperplane ``t . (w - tip) = -delta`` behind the tip, by deflated Newton
    away from the followed arm's own point there; None where none is found."""
    n1 = np.cross(t, [1.0, 0.0, 0.0] if abs(t[0]) < 0.9 else [0.0, 1.0, 0.0])
    n1 /= np.linalg.norm(n1)
    n2 = np.cross(t, n1)
    for delta in TURN_STEPS:
        try:
            old = prob.on_segment(tip, t, -delta, tip.w - delta * t)
        except Failed:
            continue
        if old.pattern() != tip.pattern():      # the corrector fell on the other arm
            old.sigma = -delta
            return old
        for e in (n1, -n1, n2, -n2):
            try:
                new = prob.correct(old.w + delta * e, t, t @ tip.w - delta, old.w)
            except Failed:
                continue
            if new.pattern() != tip.pattern() and \
                    np.linalg.norm(new.w - old.w) > 1e3 * prob.tol:
                try:
                    tangent(new)
                except Failed:
                    continue
                new.sigma = -delta
                return new
    return None


# ------------------------------------------------------------------ the branch
class Record:
    """A point of the followed branch as the Dataset shows it: ``point`` (None where
    the correction failed: then ``w`` is where it was tried), ``special``,
    ``at`` (an event's parameter: the middle of its bracket, or its test
    function's root), ``width`` (how far the event may lie from ``at``),
    ``status``, ``change`` (of a pattern event: the patterns before and after)."""

    __slots__ = ("point", "special", "width", "status", "w", "at", "change")

    def __init__(self, point, special, width=0.0, status=codes.OK, w=None, at=None,
                 change=None):
        self.point, self.special, self.width, self.status = point, special, width, status
        self.w = point.w if point is not None else w
        self.at, self.change = at, change


# why a branch ended
REACHED, LEFT, BUDGET, FAILED, CLOSED = "reached", "left", "budget", "failed", "closed"


class _Walk:
    """The state of one continuation (:func:`follow`)."""

    def __init__(self, prob, first, to, window, max_step, xtol):
        self.prob, self.to, self.window, self.xtol = prob, to, window, xtol
        self.max_step = max_step
        self.records = [Record(first, START)]
        t = tangent(first)
        if t[2] == 0.0 or (t[2] > 0.0) != (to > prob.lam(first.w)):
            t = -t
        self.first, self.t_first, self.base, self.t = first, t.copy(), first, t

    def step(self, h: float):
        """One step of length h from the base: the new point, or raises Failed."""
        prob, base, t = self.prob, self.base, self.t
        pred = base.w + h * t
        new = prob.on_segment(base, t, h, pred)
        t_new = tangent(new, new.w - base.w)
        if (t_new @ t < COS_MIN or np.linalg.norm(new.w - pred) > 0.3 * h) \
                and h > KINK * self.max_step:
            raise Failed(CORRECTOR_FAILED, new.w)
        return new

    def window_end(self, new: Point):
        """The branch's point at the window's edge where ``new`` lies beyond it
        (None inside), with how it ended."""
        prob, base = self.prob, self.base
        lo, hi = self.window
        lam = prob.lam(new.w)
        if lo <= lam <= hi:
            return None, None
        edge = hi if lam > hi else lo
        lb = prob.lam(base.w)
        end = prob.at_parameter(base.w + (edge - lb) / (lam - lb) * (new.w - base.w),
                                edge)
        end.sigma = float(self.t @ (end.w - base.w))
        if not end.sigma > 0.0:
            raise Failed(CORRECTOR_FAILED, end.w)
        return end, (REACHED if edge == self.to else LEFT)

    def advance(self, new: Point, special=REGULAR, width=0.0, status=codes.OK,
                at=None, change=None):
        """Record ``new`` and move the base to it, the tangent along the secant."""
        self.records.append(Record(new, special, width, status, at=at, change=change))
        self.t = tangent(new, new.w - self.base.w)
        self.base = new


def _prune(records: list, chase: list) -> None:
    """Drop the regular points recorded while a change ahead shortened the steps,
    but the last (a geometric sequence towards the change); ``chase`` holds the
    index of the first, and is emptied."""
    if chase:
        keep = records[:chase[0]] + [r for r in records[chase[0]:-1]
                                     if r.special != REGULAR] + records[-1:]
        records[:] = keep
        chase.clear()


def follow(prob: Problem, first: Point, to: float, window, step: float,
           max_step: float, max_points: int, xtol: float):
    """The branch from ``first`` towards the parameter value ``to`` while the
    parameter stays inside ``window`` = (lo, hi): ``(records, ended)``, ``ended``
    one of REACHED (at ``to``), LEFT (at the window's other end, the branch having
    turned back), BUDGET (``max_points`` steps), FAILED (no correction at the
    smallest step), CLOSED (back at the start: an isola).

    A step whose point has another pattern of sticks and stops is halved until
    the parameter moves less than the event's bracket over it: the change is then
    located, and the branch goes on from that point. An arm that ends at a switch
    with no continuation ahead (every smaller step fails) turns onto the arm of
    the other pattern behind it (:func:`turn`): a non-smooth fold."""
    walk = _Walk(prob, first, to, window, max_step, xtol)
    h, steps = float(step), 0
    came = None     # the pattern before a change just located (the base is its point)
    flipped = False  # ... and the new arm is followed backwards (see below)
    chase = []      # records of steps shortened by a change ahead (kept: the last)
    while steps < max_points:
        base = walk.base
        small = _event_step(prob, base, walk.t, xtol)
        try:
            new = walk.step(h)
            if came is not None and new.pattern() == came:
                raise Failed(CORRECTOR_FAILED, new.w)   # back over the change
        except Failed as e:
            ahead = came is not None and not flipped
            if h > (FLIP * max_step if ahead else small):
                h *= 0.5
                continue
            if ahead:
                # the new arm does not go on ahead: it leaves the switch backwards
                # (a non-smooth fold whose point was found just past the tip)
                walk.t, flipped, h = -walk.t, True, RESTART * max_step
                continue
            other = None if came is not None else turn(prob, base, walk.t)
            if other is None:
                walk.records.append(Record(None, END, math.nan, e.status, e.w))
                return walk.records, FAILED
            _prune(walk.records, chase)
            walk.records[-1].special = pattern_kind(base.pattern(), other.pattern())
            walk.records[-1].width = small * prob.S[2] * abs(walk.t[2])
            walk.records[-1].at = prob.lam(base.w)
            walk.records[-1].change = (base.pattern(), other.pattern())
            walk.advance(other)
            came, flipped, h = base.pattern(), True, RESTART * max_step
            continue
        if new.pattern() != base.pattern():
            if h > small:
                h *= 0.5
                chase = chase or [len(walk.records)]
                continue
            _prune(walk.records, chase)
            kind = pattern_kind(base.pattern(), new.pattern())
            came, flipped = base.pattern(), False
            la, lb = prob.lam(base.w), prob.lam(new.w)
            walk.advance(new, kind, 0.5 * abs(lb - la), at=0.5 * (la + lb),
                         change=(base.pattern(), new.pattern()))
            walk.t = tangent(new, walk.t)       # ahead, as the arm before it
            h = RESTART * max_step
            lo, hi = walk.window
            if not lo <= prob.lam(new.w) <= hi:
                return walk.records, (REACHED if abs(prob.lam(new.w) - to) <
                                      abs(prob.lam(new.w) - prob.lam(first.w)) else LEFT)
            continue
        came, flipped = None, False
        try:
            end, ended = walk.window_end(new)
        except Failed:
            h *= 0.5
            continue
        if end is not None:
            if end.pattern() != base.pattern():
                h *= 0.5
                continue
            new = end
        for pt, kind, width, status in smooth_events(prob, base, walk.t, new, xtol):
            walk.records.append(Record(pt, kind, width, status, at=prob.lam(pt.w)))
        steps += 1
        walk.advance(new, END if ended else REGULAR)
        if ended:
            return walk.records, ended
        if steps > 3 and np.linalg.norm(new.w - first.w) < 0.5 * h and \
                walk.t @ walk.t_first > 0.0:
            walk.records[-1].special = END
            return walk.records, CLOSED
        if chase and h >= 0.25 * max_step:
            chase = []              # no change ahead after all
        if new.iterations <= 2:
            h = min(2.0 * h, max_step)
        elif new.iterations >= 5:
            h *= 0.5
    walk.records[-1].special = END
    return walk.records, BUDGET
