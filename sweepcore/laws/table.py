"""A friction law known as a table of force against speed (measured), or as any
function of the speed: represented by a shape-preserving quintic spline.

Measured force-speed tables are how friction is known in practice; Modelica's
``SupportFriction`` and ``BearingFriction`` take such a table ``f_pos[:, 2]`` with a
``peak`` factor for the static force, interpolated linearly. sweepcore needs more
than a continuous F: the Hopf speeds are roots of ``c + F'``, the first Lyapunov
coefficient (sub- or supercritical) needs ``F'''`` and the equilibrium certificate a
bound of ``F'``. The representation is therefore a quintic Hermite spline (C2, F'''
defined on each piece) that keeps the data's shape: monotone where the samples are,
never beyond the range of the two samples of such a piece (no overshoot after a
step), convex with one extremum between samples where they turn smoothly (a
Stribeck minimum), accurate to order 6 on smooth data (:mod:`sweepcore.laws.spline`;
why: docs/methods.md, "Tabulated friction laws"). Past the last speed of a branch a
runout piece brings the slope to 0 (the last piece keeps its accuracy), then the
force is held (F' = 0; the join is C2).

Every result of a table law records ``deviation`` [kN]: an estimate of how far the
representation may be from the curve the samples came from (``TableLaw``'s
attributes), or, with ``smoothing``, the largest residual at the given points; for
:meth:`TableLaw.from_function`, the distance from the function. The accuracy
contract of the engine holds for the law as represented.
"""
from __future__ import annotations

import csv
import io
import math
import numbers
import os
import re
import stat
from pathlib import Path

import numpy as np

from .._kernels.laws.table import Table, pack
from . import spline
from .base import WINDOW, FrictionLaw, check_name, magnitude_window, real

DEGREE = spline.DEGREE
MIN_POINTS = DEGREE + 1       # the slope estimates are polynomials through 6 or 7 points
MAX_POINTS = 1_000_000        # a table's size rule: 72 MB of kernel data (9 floats a piece)
MAX_BYTES = 64 * MAX_POINTS   # and its CSV file's, checked before a byte is read
DEVIATION_TOL = 1e-9          # largest excess over the data's range, x max |F| (rounding)
CLOSEST = 1e-12               # least step between speeds, x the branch's span
ZERO = 1e-300                 # where from_function asks f for its limits at 0
# units a CSV header may state, and their factor to the model's units (cm/s, kN)
SPEED_UNITS = {"cm/s": 1.0, "cm s-1": 1.0, "m/s": 100.0, "m s-1": 100.0,
               "mm/s": 0.1, "mm s-1": 0.1}
FORCE_UNITS = {"kN": 1.0, "N": 1e-3}


def _finite_1d(name: str, values) -> np.ndarray:
    if isinstance(values, (str, bytes)) or not hasattr(values, "__len__") or \
            np.ndim(values) == 0:
        raise TypeError(f"{name} must be a 1-D sequence of real numbers, got "
                        f"{type(values).__name__}" + (" of 0 dimensions" if hasattr(
                            values, "__len__") else ""))
    if len(values) > MAX_POINTS:
        raise ValueError(f"{name} has {len(values)} points; a table holds at most "
                         f"{MAX_POINTS} (sample the law more coarsely)")
    if not (isinstance(values, np.ndarray) and values.dtype.kind in "iuf"):
        for i, x in enumerate(values):
            if isinstance(x, (bool, np.bool_)) or not isinstance(x, numbers.Real):
                raise TypeError(f"{name} must hold real numbers, got {x!r} of type "
                                f"{type(x).__name__} (element {i})")
    try:
        a = np.array(values, dtype=np.float64)
    except OverflowError:
        raise ValueError(f"{name} must be finite, got an integer beyond float64") from None
    if a.ndim != 1:
        raise ValueError(f"{name} must be 1-D, got shape {a.shape}")
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        raise ValueError(f"{name} must be finite, got {float(a[bad[0]])!r} (element "
                         f"{int(bad[0])})")
    magnitude_window(name, a, "cm/s" if name == "speed" else "kN")
    return a


class TableLaw(FrictionLaw):
    """A friction law given by a table of sliding force against relative speed.

    Parameters
    ----------
    speed : 1-D sequence of float
        Relative speeds ``s = xdot - v`` [cm/s], strictly increasing. From 0 upwards
        for a law odd in s (``F(-s) = -F(s)``; the first speed must be 0, its force
        ``F(0+)``); spanning both signs for an asymmetric law, with 0 twice: the
        last point of the negative branch (``F(0-)``) and the first of the positive
        one (``F(0+)``). At most ``MAX_POINTS`` (1e6).
    force : 1-D sequence of float
        The sliding friction force F [kN] at each speed: >= 0 for s >= 0, <= 0 for
        s <= 0 (friction opposes the relative motion). Beyond the last speed of a
        branch its last force is held.
    static : float, optional
        The largest force sticking holds [kN], on either side; default ``F(0+)``
        (and ``-F(0-)`` on the negative side). Larger values give stiction, as
        Modelica's ``peak``; it must be at least ``F(0+)`` and ``-F(0-)``.
    name : str, optional
        The law's label (the ``law`` coordinate of a sweep over laws); default
        ``"table"``.
    smoothing : float, optional
        Noise of the measured forces [kN] (a standard deviation), below the largest
        force. None (default) interpolates every point; a value replaces the forces
        by the smoothest quintic spline whose residual sum of squares is at most
        ``n smoothing^2`` (FITPACK's criterion, ``scipy.interpolate.make_splrep``)
        at the given speeds, and represents those: use it for noisy data, whose
        interpolant's F''' is noise. Refused where the smoothed force changes sign.

    Attributes
    ----------
    deviation : float
        [kN] How far the representation may be from the curve the samples came
        from, on the table: an estimate (:mod:`sweepcore.laws.spline`), the bound of
        its distance from the unconstrained order-6 interpolant (what keeping the
        shape cost) plus that interpolant's distance from an order-4 one (its
        error's estimate from above on smooth data); rounding for samples of a
        smooth curve the spline reproduces (a cubic), large where the data jump.
        With smoothing, the largest residual at the given points; for
        :meth:`from_function`, the largest distance from the function at the
        check points. (A piece kept monotone that leaves the range of its two
        samples by more than ``DEVIATION_TOL`` times max |F|, rounding, is
        refused.)
    """

    kind = "table"
    STUDY_KEYS = {"table": "path, required", "static": "number", "smoothing": "number"}

    @classmethod
    def from_study(cls, values: dict):
        values = dict(values)
        return cls.from_csv(values.pop("table"), **values)

    def __init__(self, speed, force, static=None, name=None, smoothing=None):
        self._build(speed, force, static, name, smoothing, sampled=False)

    def _build(self, speed, force, static, name, smoothing, sampled):
        """The law's checks and representation; ``sampled``: the samples of a
        function (``from_function``), whose representation is checked against the
        function (deviation set there)."""
        s = _finite_1d("speed", speed)
        f = _finite_1d("force", force)
        if s.shape != f.shape:
            raise ValueError(f"speed and force must have equal lengths, got {s.size} "
                             f"speeds and {f.size} forces")
        name = check_name("table" if name is None else name)
        if smoothing is not None:
            smoothing = real("smoothing", smoothing, "kN", positive=True)
        self.name = name
        self.speed = s
        self.force_values = f
        self.smoothing = smoothing
        zeros = np.flatnonzero(s == 0.0)
        if s.size and s[0] == 0.0 and zeros.size == 1:
            self.odd = True
            neg = None
            pos = (s, f)
        elif s.size and s[0] < 0.0 and zeros.size == 2 and zeros[1] == zeros[0] + 1:
            self.odd = False
            neg = (s[:zeros[0] + 1], f[:zeros[0] + 1])
            pos = (s[zeros[1]:], f[zeros[1]:])
        else:
            raise ValueError(
                "speed must start at 0 for a law odd in s (the force at 0 is F(0+)), "
                "or span both signs with 0 given twice (F(0-), then F(0+)); got "
                f"speeds from {float(s.min()) if s.size else 'none'!r} with 0 "
                f"{zeros.size} time(s)")
        for label, (bs, bf) in (("positive", pos),) + ((("negative", neg),) if neg else ()):
            self._check_branch(label, bs, bf)
        f0p = float(pos[1][0])
        f0n = float(-neg[1][-1]) if neg else f0p
        if static is None:
            limits = (f0p, f0n)
        else:
            static = real("static", static, "kN")
            if static < max(f0p, f0n):
                raise ValueError(
                    f"static must be at least F(0+) = {f0p!r}"
                    + (f" and -F(0-) = {f0n!r}" if neg else "")
                    + f" [kN] (the largest force sticking holds cannot be below the "
                      f"sliding force at zero speed), got {static!r}")
            limits = (float(static), float(static))
        self.static = None if static is None else float(static)
        self._limits = limits
        scale = float(np.abs(f).max())
        if smoothing is not None and not smoothing < scale:
            raise ValueError(f"smoothing must be below the largest force {scale!r} kN "
                             f"(noise that large leaves no data to fit), got "
                             f"{smoothing!r}")
        fits = [_fit("positive", *pos, smoothing)]
        if neg is not None:
            fits.append(_fit("negative", *neg, smoothing))
        self._pos, self._pos_slopes, dev_pos, excess = fits[0]
        self._neg, self._neg_slopes, dev_neg, excess_neg = fits[-1]
        self.deviation = max(dev_pos, dev_neg)
        excess = max(excess, excess_neg)
        if not sampled and smoothing is None and not excess <= DEVIATION_TOL * scale:
            raise ValueError(
                f"the table {name!r} is not represented within its data's range: "
                f"departure {excess:.3g} kN, more than {DEVIATION_TOL:g} of "
                f"the largest force (speeds or forces too close to resolve)")

    @staticmethod
    def _check_branch(label, s, f):
        if s.size < MIN_POINTS:
            raise ValueError(f"the {label} branch has {s.size} point(s); a quintic "
                             f"spline (F''' continuous) needs at least {MIN_POINTS}")
        step = np.diff(s)
        if (step <= 0.0).any():
            i = int(np.flatnonzero(step <= 0.0)[0])
            what = "repeated" if step[i] == 0.0 else "unsorted"
            raise ValueError(f"speed must be strictly increasing: {what} speeds "
                             f"{float(s[i])!r} and {float(s[i + 1])!r} on the {label} "
                             "branch")
        span = float(s[-1] - s[0])
        if step.min() < CLOSEST * span:
            i = int(np.argmin(step))
            raise ValueError(f"speed steps must be at least {CLOSEST:g} of the "
                             f"{label} branch's span {span!r} cm/s (float64 resolves "
                             f"no finer slope), got {float(s[i])!r} and "
                             f"{float(s[i + 1])!r}")
        sign = 1.0 if label == "positive" else -1.0
        wrong = np.flatnonzero(sign * f < 0.0)
        if wrong.size:
            i = int(wrong[0])
            raise ValueError(
                f"force must be {'>= 0' if sign > 0 else '<= 0'} on the {label} branch "
                f"(friction opposes the relative motion), got {float(f[i])!r} at speed "
                f"{float(s[i])!r}")

    # ------------------------------------------------------------ alternatives
    @classmethod
    def from_function(cls, f, speed_max, tol=1e-10, static=None, name=None,
                      speed_min=None, max_points=20000):
        """Sample ``f(s)`` (F in kN at relative speed s in cm/s, vectorised or not) to
        a stated accuracy.

        ``f`` is sampled on ``[0, speed_max]`` (odd law), or on ``[speed_min, 0]``
        and ``[0, speed_max]`` when ``speed_min`` < 0 is given (``f(-0.0)`` and
        ``f(+0.0)`` are the limits at 0: f is called at ``+-1e-300`` there, so that a
        law written with ``sign(s)`` gives its limits). Samples are doubled, geometrically
        spaced near 0 where friction laws change fastest, until the representation
        is within ``tol`` times ``max |f|`` of f at the midpoints between samples;
        ``deviation`` records that distance [kN].
        """
        if not callable(f):
            raise TypeError(f"f must be a callable of the speed, got {type(f).__name__}")
        speed_max = real("speed_max", speed_max, "cm/s", positive=True, window=True)
        tol = real("tol", tol, "", positive=True)
        if speed_min is not None:
            speed_min = -real("speed_min", -speed_min if isinstance(
                speed_min, numbers.Real) and not isinstance(speed_min, bool) else
                speed_min, "cm/s", positive=True, window=True, shown=speed_min,
                rule="a finite number < 0 or None")
        max_points = int(real("max_points", max_points, "", positive=True))

        def call(s):
            # a copy, read-only: f may not change the speeds it was asked about
            s = np.array(s)
            s.setflags(write=False)
            try:
                out = np.asarray(f(s), np.float64)
                if out.shape != np.shape(s):
                    raise ValueError
            except (TypeError, ValueError):
                out = np.array([float(f(float(x))) for x in np.ravel(s)])
            bad = np.flatnonzero(~(np.abs(out) <= WINDOW[1]))     # NaN too
            if bad.size:            # 1/s at 0 (asked at ZERO), log(s), a pole
                at, got = float(np.ravel(s)[bad[0]]), float(out[bad[0]])
                raise ValueError(f"f({at!r} cm/s) = {got!r} kN: f must be finite, at "
                                 f"most {WINDOW[1]:g} kN ({ZERO:g} cm/s stands for 0); "
                                 "infinite at 0 (as 1/s)? Sample it from a small speed "
                                 "s0: from_function(lambda s: f(np.maximum(s, s0)), ...)")
            try:
                magnitude_window("f", out, "kN")
            except ValueError as err:
                raise ValueError(f"{err} (f sampled at {float(s.min())!r} .. "
                                 f"{float(s.max())!r} cm/s)") from None
            return out

        pos = _samples(float(speed_max))
        neg = None if speed_min is None else -_samples(-float(speed_min))[::-1]
        while True:
            speed = pos if neg is None else np.concatenate([neg, pos])
            # f at 0: its limit from the side (a law written with sign(s) is 0 there)
            at = np.where(speed == 0.0, np.where(np.signbit(speed), -ZERO, ZERO), speed)
            force = call(at)
            law = cls.__new__(cls)
            law._build(speed, force, static, name or "function", None, sampled=True)
            scale = float(np.max(np.abs(force)))
            worst = 0.0
            refined = []
            for branch in (pos,) if neg is None else (pos, neg):
                mids = 0.5 * (branch[1:] + branch[:-1])
                err = np.abs(law.force(mids) - call(mids))
                worst = max(worst, float(err.max()))
                refined.append(np.union1d(branch, mids[err > tol * scale]))
            if worst <= tol * scale:
                law.deviation = worst            # from the function, not the samples
                law.tol = tol
                return law
            if sum(b.size for b in refined) > max_points:
                raise ValueError(
                    f"f is not represented to tol={tol:g} (relative) with "
                    f"max_points={max_points} samples: deviation {worst:.3g} kN; a "
                    "discontinuity or a kink of f inside the range? Represent it "
                    "piecewise, or raise tol")
            pos = refined[0]
            if neg is not None:
                neg = refined[1]

    @classmethod
    def from_csv(cls, path, static=None, name=None, smoothing=None):
        """Read a two-column CSV file: a header naming the columns with their units,
        such as ``speed [cm/s],force [kN]`` (speed in cm/s, m/s or mm/s; force in kN
        or N), then one row per point. A header without units is refused."""
        rows = _csv_rows(path)      # before Path(path): Path("") is ".", a directory
        path = Path(path)
        if len(rows) < 2:
            raise ValueError(f"{str(path)!r}: a header and at least one row are needed")
        header = rows[0]
        if len(header) != 2:
            raise ValueError(f"{str(path)!r}: two columns (speed, force) are needed, "
                             f"the header has {len(header)}")
        factors = []
        for col, (what, table) in zip(header, (("speed", SPEED_UNITS),
                                               ("force", FORCE_UNITS))):
            m = re.fullmatch(r"\s*(\w+)\s*\[\s*([^\]]+?)\s*\]\s*", col)
            if not m:
                raise ValueError(
                    f"{str(path)!r}: the header must state units, such as "
                    f"'speed [cm/s],force [kN]'; got {','.join(header)!r}")
            if m.group(2) not in table:
                raise ValueError(f"{str(path)!r}: unknown {what} unit {m.group(2)!r} "
                                 f"(allowed: {', '.join(table)})")
            factors.append(table[m.group(2)])
        values = []
        for i, r in enumerate(rows[1:], start=2):
            try:
                values.append([float(r[0]), float(r[1])])
            except (ValueError, IndexError):
                raise ValueError(f"{str(path)!r} line {i}: two numbers expected, got "
                                 f"{','.join(r)!r}") from None
        a = np.array(values)
        law = cls(a[:, 0] * factors[0], a[:, 1] * factors[1], static=static,
                  name=name or path.stem, smoothing=smoothing)
        law.source = str(path)
        return law

    # ------------------------------------------------------------ kernels' view
    def data(self):
        return Table(pack(self._pos, self._neg, *self._limits, self.odd))

    # ------------------------------------------------------------ Python's view
    def force(self, zdot, phase=None):
        zdot = np.asarray(zdot, np.float64)
        s = np.sign(zdot) if phase is None else np.asarray(phase, np.float64)
        s = np.broadcast_to(s, zdot.shape)
        positive = (zdot > 0.0) | ((zdot == 0.0) & (s > 0.0))
        if self.odd:
            mag = _evaluate(self._pos, np.abs(zdot))
            return np.where(positive, mag, -mag)
        return np.where(positive, _evaluate(self._pos, zdot), _evaluate(self._neg, zdot))

    def static_limits(self):
        return self._limits

    def table(self):
        return self.speed, self.force_values

    def slope_scale(self, P):
        bound = max(float(self._pos_slopes.max()), float(self._neg_slopes.max()))
        return np.full(P.shape[0], bound)

    def speed_span(self):
        """``(lo, hi)`` [cm/s]: the relative speeds the table covers (beyond them its
        end forces are held)."""
        hi = float(self.speed[-1])
        return (-hi, hi) if self.odd else (float(self.speed[0]), hi)

    def attrs(self):
        lo, hi = self.speed_span()
        out = {"law": self.name, "law_kind": self.kind,
               "law_representation": "shape-preserving quintic Hermite spline (C2): "
                                     "monotone pieces, convex at smooth turns, a "
                                     "runout then the end force held past the table",
               "law_deviation": self.deviation,
               "law_speed_span": f"{lo:.17g}, {hi:.17g}",
               "law_static": ", ".join(f"{x:.17g}" for x in self._limits)}
        if self.smoothing is not None:
            out["law_smoothing"] = self.smoothing
        if getattr(self, "source", None):
            out["law_source"] = self.source
        return out

    def describe(self):
        span = f"{self.speed.min():g}..{self.speed.max():g} cm/s"
        return (f"table law {self.name!r}: {self.speed.size} points, {span}, static "
                f"{max(self._limits):g} kN, deviation {self.deviation:.2g} kN")

    def __eq__(self, other):
        return isinstance(other, TableLaw) and self.name == other.name and \
            np.array_equal(self.speed, other.speed) and \
            np.array_equal(self.force_values, other.force_values) and \
            self._limits == other._limits and self.smoothing == other.smoothing

    __hash__ = None

    def fingerprint(self) -> bytes:
        """Bytes that identify the law exactly (a resumed sweep's grid match)."""
        return b"".join([self.name.encode(), self.speed.astype("<f8").tobytes(),
                         self.force_values.astype("<f8").tobytes(),
                         np.array(self._limits + (self.smoothing or 0.0,)).tobytes()])




# ------------------------------------------------------------------ the spline
def _samples(hi: float) -> np.ndarray:
    """The first speeds of ``from_function`` on [0, hi]: 32 uniform and 16 geometric
    from 1e-6 hi (friction laws change fastest at small speeds)."""
    return np.unique(np.concatenate([np.linspace(0.0, hi, 33),
                                     hi * np.geomspace(1e-6, 1.0 / 32, 16)]))


def _fit(label, s, f, smoothing):
    """``(branch, largest |F'| of each piece, deviation, excess)`` of one branch: the
    kernels' ``(x, c, dmin, d2)`` of the shape-preserving spline through the points
    (with ``smoothing``: through FITPACK's smoothing spline at the same speeds, with
    its slopes), its deviation (docstring of ``TableLaw``) and how far its pieces
    kept monotone leave their samples' range (rounding)."""
    far_last = label == "positive"          # the far end: the largest |s|
    slopes = None
    if smoothing is not None:
        from scipy.interpolate import make_splrep
        try:
            spl = make_splrep(s, f, k=DEGREE, s=s.size * smoothing ** 2)
        except (ValueError, ArithmeticError, np.linalg.LinAlgError) as err:
            raise ValueError(f"smoothing={smoothing!r}: FITPACK cannot fit the "
                             f"{label} branch ({err})") from None
        fitted = spl(s)
        sign = 1.0 if far_last else -1.0
        wrong = np.flatnonzero(sign * fitted < 0.0)
        if wrong.size:
            i = int(wrong[0])
            raise ValueError(
                f"smoothing={smoothing!r} kN changes the sign of the force on the "
                f"{label} branch ({float(fitted[i]):.3g} kN at speed {float(s[i])!r}): "
                "friction must oppose the motion; give a smaller smoothing")
        slopes = (spl(s, 1), spl(s, 2))
        deviation = float(np.abs(fitted - f).max())
        f = fitted
    branch, dmax, excess, estimate = spline.fit(s, f, far_last, slopes)
    parts = (branch[1], branch[2], branch[3], dmax)
    if not all(np.isfinite(a).all() for a in parts):
        raise ValueError(f"the {label} branch's slopes overflow float64 (speeds "
                         f"{float(s[0])!r} .. {float(s[-1])!r} cm/s, forces up to "
                         f"{float(np.abs(f).max())!r} kN): choose units in which the "
                         "magnitudes are moderate")
    if smoothing is None:
        deviation = estimate
    return branch, dmax, deviation, excess


def _evaluate(branch, s):
    """F of one branch at speeds s (numpy), as the kernels: past the far end the
    end force is held (speeds beyond either end are taken at that end)."""
    x, c, _dmin, _d2 = branch
    s = np.clip(np.asarray(s, np.float64), x[0], x[-1])
    i = np.clip(np.searchsorted(x, s, side="right") - 1, 0, x.size - 2)
    t = s - x[i]
    f = np.zeros_like(s)
    for j in range(DEGREE, -1, -1):
        f = f * t + c[i, j]
    return f


def _csv_rows(path: Path) -> list:
    """The non-empty rows of a CSV file (a UTF-8 byte-order mark, as Excel writes,
    skipped), at most ``MAX_POINTS + 1``; anything but a regular file refused before
    it is read (opened without blocking: a FIFO never holds the call)."""
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError as err:
        raise OSError(f"cannot read the friction table {str(path)!r}: "
                      f"{err.strerror or err}") from None
    mode, size = os.fstat(fd).st_mode, os.fstat(fd).st_size
    if not stat.S_ISREG(mode) or size > MAX_BYTES:      # refused before it is read
        os.close(fd)
        what = ("a directory" if stat.S_ISDIR(mode) else "a FIFO" if stat.S_ISFIFO(mode)
                else "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode)
                else "a socket" if stat.S_ISSOCK(mode) else "not a regular file")
        raise ValueError(f"the friction table {str(path)!r} is " + (
            f"{what}; a CSV file is needed" if not stat.S_ISREG(mode) else f"{size:,} "
            f"bytes; a table's file holds at most {MAX_BYTES:,} ({MAX_POINTS:,} rows of "
            "64 characters): sample the law more coarsely"))
    os.set_blocking(fd, True)
    rows = []
    try:
        with io.open(fd, encoding="utf-8-sig", newline="") as fh:
            for r in csv.reader(fh):
                if r and any(c.strip() for c in r):
                    rows.append(r)
                    if len(rows) > MAX_POINTS + 1:
                        raise ValueError(f"{str(path)!r} has more than {MAX_POINTS} "
                                         "rows; a table holds at most that many")
    except UnicodeDecodeError:
        raise ValueError(f"{str(path)!r} is not a text CSV file (UTF-8)") from None
    except csv.Error as err:
        raise ValueError(f"{str(path)!r} is not a CSV file: {err}") from None
    return rows
