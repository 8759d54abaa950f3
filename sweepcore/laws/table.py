"""A friction law known as a table of force against speed (measured), or as any
function of the speed: represented by a quintic spline.

Measured force-speed tables are how friction is known in practice; Modelica's
``SupportFriction`` and ``BearingFriction`` take such a table ``f_pos[:, 2]`` with a
``peak`` factor for the static force, interpolated linearly. sweepcore needs more
than a continuous F: the Hopf speeds are roots of ``c + F'``, the first Lyapunov
coefficient (sub- or supercritical) needs ``F'''`` and the equilibrium certificate a
bound of ``F'``. The representation is therefore a quintic spline (degree 5, C4):
F, F', F'' and F''' are continuous, the interpolant of smooth data converges at
order 6, and the kernels evaluate it as a piecewise polynomial (scipy's
``make_interp_spline``/``make_splrep`` and ``PPoly.from_spline`` build it; why a
quintic: docs/methods.md, "Tabulated friction laws"). Past the last speed of a
branch the law continues linearly with the end's value and slope.

Every result of a table law records ``deviation``: the largest distance of the
representation from the given points (from the function, for
:meth:`TableLaw.from_function`), the representation's error with respect to what
the user gave. The accuracy contract of the engine holds for the law as represented.
"""
from __future__ import annotations

import csv
import math
import numbers
import re
from pathlib import Path

import numpy as np

from .._kernels.laws.table import Table, pack
from .base import FrictionLaw

DEGREE = 5                    # quintic: F''' continuous
MIN_POINTS = DEGREE + 1       # an interpolating spline of degree k needs k + 1 points
ZERO = 1e-300                 # where from_function asks f for its limits at 0
# units a CSV header may state, and their factor to the model's units (cm/s, kN)
SPEED_UNITS = {"cm/s": 1.0, "cm s-1": 1.0, "m/s": 100.0, "m s-1": 100.0,
               "mm/s": 0.1, "mm s-1": 0.1}
FORCE_UNITS = {"kN": 1.0, "N": 1e-3}


def _finite_1d(name: str, values) -> np.ndarray:
    if isinstance(values, (str, bytes)) or not hasattr(values, "__len__"):
        raise TypeError(f"{name} must be a 1-D sequence of real numbers, got "
                        f"{type(values).__name__}")
    for i, x in enumerate(values):
        if isinstance(x, (bool, np.bool_)) or not isinstance(x, numbers.Real):
            raise TypeError(f"{name} must hold real numbers, got {x!r} of type "
                            f"{type(x).__name__} (element {i})")
    a = np.array(values, dtype=np.float64)
    if a.ndim != 1:
        raise ValueError(f"{name} must be 1-D, got shape {a.shape}")
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        raise ValueError(f"{name} must be finite, got {float(a[bad[0]])!r} (element "
                         f"{int(bad[0])})")
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
        one (``F(0+)``).
    force : 1-D sequence of float
        The sliding friction force F [kN] at each speed: >= 0 for s >= 0, <= 0 for
        s <= 0 (friction opposes the relative motion).
    static : float, optional
        The largest force sticking holds [kN], on either side; default ``F(0+)``
        (and ``-F(0-)`` on the negative side). Larger values give stiction, as
        Modelica's ``peak``; it must be at least ``F(0+)`` and ``-F(0-)``.
    name : str, optional
        The law's label (the ``law`` coordinate of a sweep over laws); default
        ``"table"``.
    smoothing : float, optional
        Noise of the measured forces [kN] (a standard deviation). None (default)
        interpolates every point; a value fits the smoothest quintic spline whose
        residual sum of squares is at most ``n smoothing^2`` (FITPACK's criterion,
        ``scipy.interpolate.make_splrep``): use it for noisy data, whose
        interpolant's F''' is noise. The residual is recorded in ``deviation``.

    Attributes
    ----------
    deviation : float
        Largest ``|F_represented(s_i) - F_i|`` over the given points [kN] (for
        :meth:`from_function`: over the check points between the samples).
    """

    kind = "table"
    STUDY_KEYS = {"table": "path, required", "static": "number", "smoothing": "number"}

    @classmethod
    def from_study(cls, values: dict):
        values = dict(values)
        return cls.from_csv(values.pop("table"), **values)

    def __init__(self, speed, force, static=None, name=None, smoothing=None):
        s = _finite_1d("speed", speed)
        f = _finite_1d("force", force)
        if s.shape != f.shape:
            raise ValueError(f"speed and force must have equal lengths, got {s.size} "
                             f"speeds and {f.size} forces")
        if name is None:
            name = "table"
        if not isinstance(name, str) or not name.strip() or "\x00" in name:
            raise ValueError(f"name must be a non-empty string, got {name!r}")
        if smoothing is not None and (isinstance(smoothing, bool) or not isinstance(
                smoothing, numbers.Real) or not (math.isfinite(smoothing) and
                                                 smoothing > 0)):
            raise ValueError(f"smoothing must be a finite number > 0 [kN] (the "
                             f"forces' noise) or None, got {smoothing!r}")
        self.name = name
        self.speed = s
        self.force_values = f
        self.smoothing = None if smoothing is None else float(smoothing)
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
            if isinstance(static, bool) or not isinstance(static, numbers.Real) or \
                    not math.isfinite(static):
                raise ValueError(f"static must be a finite number [kN] or None, got "
                                 f"{static!r}")
            if static < max(f0p, f0n):
                raise ValueError(
                    f"static must be at least F(0+) = {f0p!r}"
                    + (f" and -F(0-) = {f0n!r}" if neg else "")
                    + f" [kN] (the largest force sticking holds cannot be below the "
                      f"sliding force at zero speed), got {static!r}")
            limits = (float(static), float(static))
        self.static = None if static is None else float(static)
        self._limits = limits
        self._pos = _fit(*pos, self.smoothing)
        self._neg = self._pos if neg is None else _fit(*neg, self.smoothing)
        dev = [float(np.max(np.abs(_evaluate(self._pos, pos[0]) - pos[1])))]
        if neg is not None:
            dev.append(float(np.max(np.abs(_evaluate(self._neg, neg[0]) - neg[1]))))
        self.deviation = max(dev)

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
        for label, val in (("speed_max", speed_max), ("tol", tol)):
            if isinstance(val, bool) or not isinstance(val, numbers.Real) or \
                    not (math.isfinite(val) and val > 0):
                raise ValueError(f"{label} must be a finite number > 0, got {val!r}")
        if speed_min is not None and (isinstance(speed_min, bool) or not isinstance(
                speed_min, numbers.Real) or not (math.isfinite(speed_min) and speed_min < 0)):
            raise ValueError(f"speed_min must be a finite number < 0 or None, got "
                             f"{speed_min!r}")

        def call(s):
            try:
                out = np.asarray(f(s), np.float64)
                if out.shape != np.shape(s):
                    raise ValueError
            except (TypeError, ValueError):
                out = np.array([float(f(float(x))) for x in np.ravel(s)])
            return out

        pos = _samples(float(speed_max))
        neg = None if speed_min is None else -_samples(-float(speed_min))[::-1]
        while True:
            speed = pos if neg is None else np.concatenate([neg, pos])
            # f at 0: its limit from the side (a law written with sign(s) is 0 there)
            at = np.where(speed == 0.0, np.where(np.signbit(speed), -ZERO, ZERO), speed)
            force = call(at)
            law = cls(speed, force, static=static, name=name or "function")
            scale = float(np.max(np.abs(force)))
            worst = 0.0
            refined = []
            for branch in (pos,) if neg is None else (pos, neg):
                mids = 0.5 * (branch[1:] + branch[:-1])
                err = np.abs(law.force(mids) - call(mids))
                worst = max(worst, float(err.max()))
                refined.append(np.union1d(branch, mids[err > tol * scale]))
            if worst <= tol * scale:
                law.deviation = max(worst, law.deviation)
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
        path = Path(path)
        try:
            with open(path, newline="") as fh:
                rows = [r for r in csv.reader(fh) if r and any(c.strip() for c in r)]
        except OSError as err:
            raise OSError(f"cannot read the friction table {str(path)!r}: "
                          f"{err.strerror or err}") from None
        except UnicodeDecodeError:
            raise ValueError(f"{str(path)!r} is not a text CSV file") from None
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
        slopes = [np.abs(self._pos[2]).max(), np.abs(_end_slopes(self._pos)).max()]
        if not self.odd:
            slopes += [np.abs(self._neg[2]).max(), np.abs(_end_slopes(self._neg)).max()]
        bound = float(max(slopes + [np.abs(_max_slopes(self._pos)).max(),
                                    np.abs(_max_slopes(self._neg)).max()]))
        return np.full(P.shape[0], bound)

    def attrs(self):
        out = {"law": self.name, "law_kind": self.kind,
               "law_representation": "quintic spline (C4), linear past the table",
               "law_deviation": self.deviation,
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


def _fit(s, f, smoothing):
    """``(x, c, dmin, d2)``: breakpoints, ascending coefficients (n, 6), and on each
    piece the least F' and the largest |F''|, of the quintic spline through (or,
    smoothing, near) the points."""
    from scipy.interpolate import PPoly, make_interp_spline, make_splrep
    if smoothing is None:
        spl = make_interp_spline(s, f, k=DEGREE)
    else:
        spl = make_splrep(s, f, k=DEGREE, s=s.size * smoothing ** 2)
    pp = PPoly.from_spline(spl)
    x = np.asarray(pp.x, np.float64)
    c = np.asarray(pp.c, np.float64)
    keep = np.flatnonzero(np.diff(x) > 0.0)      # drop empty pieces at repeated knots
    x = np.append(x[keep], x[keep[-1] + 1])
    c = np.ascontiguousarray(c[::-1, keep].T)     # ascending powers, a row per piece
    return x, c, _least_slopes(x, c), _largest_curvatures(x, c)


def _least_slopes(x, c):
    """The least F' on each piece: at its ends or where F'' = 0 inside (the real
    parts of the roots of a cubic: a near-double real root can come out of
    ``np.roots`` as a complex pair; an extra sample can only lower the least value),
    lowered by a rounding margin (the certificate must not rest on rounding)."""
    h = np.diff(x)
    out = np.empty(h.size)
    d1 = c[:, 1:] * np.arange(1, DEGREE + 1)         # F' coefficients (degree 4)
    d2 = d1[:, 1:] * np.arange(1, DEGREE)            # F'' coefficients (degree 3)
    for i in range(h.size):
        ts = [0.0, h[i]]
        roots = np.roots(d2[i, ::-1]) if np.any(d2[i] != 0.0) else []
        ts += [r.real for r in roots if 0 < r.real < h[i]]   # a near-double root may
        vals = np.polynomial.polynomial.polyval(np.array(ts), d1[i])   # come out complex
        size = np.abs(d1[i]) @ (h[i] ** np.arange(DEGREE))
        out[i] = vals.min() - 1e-12 * size
    return out


def _largest_curvatures(x, c):
    """The largest |F''| on each piece: at its ends or where F''' = 0 inside (roots
    of a quadratic), raised by a rounding margin."""
    h = np.diff(x)
    out = np.empty(h.size)
    d2 = c[:, 2:] * np.array([2.0, 6.0, 12.0, 20.0])     # F'' coefficients (degree 3)
    d3 = d2[:, 1:] * np.arange(1, 4)                     # F''' coefficients (degree 2)
    for i in range(h.size):
        ts = [0.0, h[i]]
        roots = np.roots(d3[i, ::-1]) if np.any(d3[i] != 0.0) else []
        ts += [r.real for r in roots if 0 < r.real < h[i]]   # (extra points: safe)
        vals = np.abs(np.polynomial.polynomial.polyval(np.array(ts), d2[i]))
        size = np.abs(d2[i]) @ (h[i] ** np.arange(4))
        out[i] = vals.max() + 1e-12 * size
    return out


def _max_slopes(branch):
    """The largest |F'| on each piece (for the slope scale): a bound from the
    coefficients' sizes."""
    x, c, _dmin, _d2 = branch
    h = np.diff(x)
    d1 = np.abs(c[:, 1:] * np.arange(1, DEGREE + 1))
    return (d1 * h[:, None] ** np.arange(DEGREE)).sum(axis=1)


def _end_slopes(branch):
    x, c, _dmin, _d2 = branch
    return np.array([c[0, 1], np.polynomial.polynomial.polyval(
        x[-1] - x[-2], c[-1, 1:] * np.arange(1, DEGREE + 1))])


def _evaluate(branch, s):
    """F of one branch at speeds s (numpy; linear past the ends), as the kernels."""
    x, c, _dmin, _d2 = branch
    s = np.asarray(s, np.float64)
    i = np.clip(np.searchsorted(x, s, side="right") - 1, 0, x.size - 2)
    t = s - x[i]
    inside = (s >= x[0]) & (s <= x[-1])
    f = np.zeros_like(s)
    for j in range(DEGREE, -1, -1):
        f = f * t + c[i, j]
    # linear continuation past the ends, with the end's value and slope
    lo_f = c[0, 0]
    lo_d = c[0, 1]
    hi_t = x[-1] - x[-2]
    hi_f = np.polynomial.polynomial.polyval(hi_t, c[-1])
    hi_d = np.polynomial.polynomial.polyval(hi_t, c[-1, 1:] * np.arange(1, DEGREE + 1))
    f = np.where(inside, f, np.where(s < x[0], lo_f + lo_d * (s - x[0]),
                                     hi_f + hi_d * (s - x[-1])))
    return f
