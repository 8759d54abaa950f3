"""Grids of parameter sets for :func:`sweepcore.sweep`, validated before any work.

A :class:`Grid` is either the outer product of its 1-D axes (``Grid(...)``) or a list
of scattered parameter sets (``Grid.points(...)``). It never materialises the full
grid: :meth:`Grid.rows` builds the kernel rows (layout ``layout.M ... layout.XD0``) of
one range of flat indices at a time, from the 1-D axes.
"""
from __future__ import annotations

import hashlib
import math
import numbers
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from . import excitations, law
from ._kernels import layout
from .excitations import LOAD_DIM
from .laws import ANALYTIC, LAW_DIM
from .laws import analytic as _analytic
from .options import checked_keywords
from .params import (LONG_NAMES, PHASE_MAX, RULES, UNITS, check_derived, check_forcing,
                     check_law, check_real, law_ranges)

# axes in dimension order, with their kernel column (check_real rules: params.RULES)
AXES = law.PARAMETERS + excitations.KEYWORDS + ("x0", "xdot0")
COLUMNS = {**law.COLUMNS, **excitations.COLUMNS, "x0": layout.X0, "xdot0": layout.XD0}
# axes that may be None: xdot0 (start stuck: xdot0 = v), r_k (= r_y: no Stribeck
# term) and v_s (not used without a Stribeck term: NaN in the kernel rows)
OPTIONAL = ("xdot0", "r_k", "v_s", "Omega")
POINT_DIM = "point"
# flat indices (len, rows, chunk bounds) are numpy intp: a larger grid has none
MAX_SIZE = int(np.iinfo(np.intp).max)


def _check_scalar(name: str, value) -> float:
    return check_real(name, value, **RULES[name])


def _first_non_real(value: np.ndarray) -> int | None:
    """Index of the first element that is not a real number (bools are not), or None.

    Object arrays of Python numbers (what pandas hands out) are checked element by
    element.
    """
    if value.dtype.kind in "iuf":
        return None
    if value.dtype.kind != "O":
        return 0
    return next((i for i, x in enumerate(value) if isinstance(x, (bool, np.bool_))
                 or not isinstance(x, numbers.Real)), None)


def _check_array(name: str, value: np.ndarray, unique: bool) -> np.ndarray:
    """Validate one 1-D axis; errors name the axis, the element and its value."""
    if value.ndim != 1:
        raise ValueError(f"{name} must be a scalar or a 1-D array, got an array of "
                         f"shape {value.shape}")
    if value.size == 0:
        raise ValueError(f"{name} axis is empty: give at least one value")
    i = _first_non_real(value)
    if i is not None:
        bad = value[i].item() if isinstance(value[i], np.generic) else value[i]
        raise TypeError(f"{name} must hold real numbers, got {bad!r} of type "
                        f"{type(bad).__name__} (array dtype {value.dtype})")
    rule = RULES[name]
    try:
        a = np.array(value, dtype=np.float64)
    except OverflowError:           # a Python integer beyond float64
        for i, x in enumerate(value):
            try:
                check_real(name, x, **rule)
            except ValueError as err:
                raise ValueError(f"{err} (element {i} of the {name} axis)") from None
        raise
    ok = np.isfinite(a)
    if rule.get("positive"):
        ok &= a > 0.0
    if rule.get("nonnegative"):
        ok &= a >= 0.0
    if rule.get("phase"):
        ok &= np.abs(a) <= PHASE_MAX
    if not ok.all():
        i = int(np.flatnonzero(~ok)[0])
        try:
            check_real(name, value[i].item(), **rule)
        except (TypeError, ValueError) as err:
            raise type(err)(f"{err} (element {i} of the {name} axis)") from None
    if unique:
        vals, counts = np.unique(a, return_counts=True)
        if (counts > 1).any():
            dup = float(vals[counts > 1][0])
            raise ValueError(f"{name} axis has the duplicated value {dup!r}: the values "
                             "of a swept axis must be distinct (they become a "
                             "coordinate)")
    a.setflags(write=False)
    return a


def _check_axis(name: str, value, unique: bool):
    """A validated scalar (float), 1-D array (read-only float64) or None (OPTIONAL)."""
    if value is None and name in OPTIONAL:
        return None
    if isinstance(value, (list, tuple)):
        # np.asarray would silently turn True into 1.0 beside other numbers
        for i, x in enumerate(value):
            if isinstance(x, (bool, np.bool_)):
                raise TypeError(f"{name} must hold real numbers, got {x!r} of type "
                                f"{type(x).__name__} (element {i} of the {name} axis)")
    if isinstance(value, (list, tuple, np.ndarray)):
        try:
            arr = np.asarray(value)
        except ValueError as err:   # ragged nested lists
            raise ValueError(f"{name} must be a scalar or a 1-D array: {err}") from None
        if arr.ndim == 0:
            return _check_scalar(name, arr[()])
        return _check_array(name, arr, unique)
    return _check_scalar(name, value)


@dataclass(frozen=True, eq=False)
class Grid:
    """Parameter sets of a sweep: the outer product of 1-D axes, or scattered points.

    Each axis is a scalar (fixed parameter) or a 1-D array (swept parameter). Units
    are the paper's: kN, cm, s.

    Parameters
    ----------
    m : float or 1-D array
        Mass [kN s^2/cm], > 0.
    k : float or 1-D array
        Stiffness [kN/cm], > 0.
    r_y : float or 1-D array
        Friction bound [kN], >= 0.
    v : float or 1-D array
        Belt speed [cm/s].
    alpha1 : float or 1-D array
        Linear friction-speed coefficient of eq. (40) [kN s/cm].
    alpha2 : float or 1-D array
        Cubic friction-speed coefficient of eq. (40) [kN s^3/cm^3], >= 0.
    x0 : float or 1-D array
        Initial position [cm].
    xdot0 : float, 1-D array or None
        Initial velocity [cm/s]; None starts every point stuck on the belt
        (xdot0 = v), as in the paper's figures.
    c : float or 1-D array
        Viscous damping on the slider [kN s/cm], >= 0.
    r_k : float, 1-D array or None
        Kinetic friction level of the exponential Stribeck law [kN], >= 0; None
        (default): r_k = r_y, no Stribeck term (the paper's law).
    v_s : float, 1-D array or None
        Stribeck speed [cm/s], >= 0; required when r_k is given. 0 is the limit
        v_s -> 0+: a jump from the static bound r_y to the sliding level r_k at zero
        speed (static above kinetic Coulomb friction).
    law : law object or list of them, optional
        A friction law given as an object (:mod:`sweepcore.laws`) instead of the
        analytic parameters r_y, alpha1, alpha2, r_k, v_s (which are then not
        given); a list of them is a dimension ``law``, first, labelled by the laws'
        names (distinct).
    F0, Omega, phi, Y0 : float or 1-D array
        The excitation (:class:`sweepcore.Params`): the load ``F0 p(Omega t + phi)``
        [kN] (phi in radians) and the anchor's motion ``Y0 cos(Omega t)`` [cm].
    load : PeriodicLoad or list of them, optional
        The load's shape p (default one cosine); a list of them is a dimension
        ``load``, after ``law``, labelled by the shapes' names (distinct).
    mode : {"product", "points"}
        "product" (default): the array axes span an outer product, one dimension per
        array axis in the order of the parameters above. "points": the array axes
        have equal lengths and are read together, one parameter set per index
        (dimension ``point``); use :meth:`Grid.points`.

    Notes
    -----
    Everything is validated here, before a sweep starts: finite values, m > 0,
    k > 0, r_y >= 0, alpha2 >= 0, 1-D non-empty axes of real numbers, distinct values
    along a product axis, equal lengths of point axes, and magnitudes whose derived
    quantities (omega, q, x_eq, the length scale) stay finite over the axes' ranges
    (:func:`sweepcore.params.check_derived`); an excitation the forced kernels
    resolve (:func:`sweepcore.params.check_forcing`: Omega/omega, the forcing
    period, the excitation's magnitude), phi in radians (``|phi| <= 2 pi``), and a
    swept Omega or phi only where it acts (Omega with F0 or Y0, phi with F0).
    Errors name the axis and the offending value. Arrays are copied and frozen
    (read-only float64).
    """

    m: object
    k: object
    r_y: object = None
    v: object = None
    alpha1: object = None
    alpha2: object = None
    x0: object = 0.0
    xdot0: object = None
    c: object = 0.0
    r_k: object = None
    v_s: object = None
    law: object = None
    F0: object = 0.0
    Omega: object = None
    phi: object = 0.0
    Y0: object = 0.0
    load: object = None
    mode: str = field(default="product", kw_only=True)

    def __post_init__(self):
        if self.mode not in ("product", "points"):
            raise ValueError(f"mode must be 'product' or 'points', got {self.mode!r}")
        if self.v is None:
            raise TypeError("Grid() missing the belt speed v [cm s-1]")
        if self.law is not None:
            object.__setattr__(self, "law", self._checked_laws())
        elif self.r_y is None:
            raise TypeError("r_y must be a real number, got None: the friction bound "
                            "[kN] is required (or law objects: law=)")
        else:
            for name in ("alpha1", "alpha2"):
                if getattr(self, name) is None:
                    object.__setattr__(self, name, 0.0)
        for name in AXES:
            if self.law is not None and name in _analytic.PARAMETERS:
                continue
            value = _check_axis(name, getattr(self, name), unique=self.mode == "product")
            object.__setattr__(self, name, value)
        excitations.check("Grid", {n: getattr(self, n) for n in excitations.KEYWORDS})
        object.__setattr__(self, "load", excitations.check_loads("Grid", self.load))
        if self.load is not None and not np.any(np.asarray(self.F0) != 0.0):
            raise ValueError("Grid: load given but F0 = 0 at every point: the load's "
                             "amplitude F0 [kN] is needed")
        if isinstance(self.load, tuple) and self.mode == "points":
            raise ValueError("Grid.points takes one load; sweep several loads with "
                             "Grid(..., load=[...]) (a load dimension)")
        self._check_excitation()
        if self.mode == "points":
            lengths = {n: len(self.axis(n)) for n in self.swept}
            if len(set(lengths.values())) > 1:
                shown = ", ".join(f"{n}: {n_}" for n, n_ in lengths.items())
                raise ValueError("the array axes of Grid.points must have equal "
                                 f"lengths, got {shown}")
        if self.size > MAX_SIZE:
            shown = " x ".join(f"{n}: {k}" for n, k in zip(self.dims, self.shape))
            raise ValueError(f"Grid of {self.size:.3g} points ({shown}): more than a "
                             f"flat index counts ({MAX_SIZE:.3g}, numpy's intp); sweep "
                             "fewer values per axis")
        if self.v_s is None and self.r_k is not None and not (
                isinstance(self.r_k, float) and self.r_k == self.r_y):
            raise ValueError("v_s (Stribeck speed [cm s-1]) is required when r_k is "
                             f"given; got r_k={self.r_k!r} and no v_s")
        ranges = {}
        for name in law.PARAMETERS:
            val = self.axis(name)
            if val is None:
                continue
            val = np.atleast_1d(val)
            if name == "v_s":           # the Stribeck slope's bound: the least v_s > 0
                val = val[val > 0.0] if (val > 0.0).any() else np.array([np.inf])
            ranges[name] = (float(val.min()), float(val.max()))
        if self.law is None:
            check_derived("Grid", ranges)
        for one in (self.laws if self.law is not None else ()):
            check_derived("Grid", law_ranges(one, ranges))

    def _check_excitation(self) -> None:
        """Refuse a swept excitation axis that changes nothing (Omega without F0 or
        Y0, phi without F0: the load's phase), and an excitation the forced kernels
        cannot resolve (:func:`sweepcore.params.check_forcing`)."""
        def swept(name):
            return isinstance(getattr(self, name), np.ndarray)

        def zero(name):
            return not np.any(getattr(self, name))
        unused = [("Omega", "nothing excites the slider (F0 = Y0 = 0)", "F0 or Y0")
                  ] if not self.forced else []
        unused.append(("phi", "phi is the phase of the load F0 p(Omega t + phi), "
                              "and F0 = 0", "F0"))
        for name, why, give in unused:
            if swept(name) and (name == "Omega" or zero("F0")):
                vals = getattr(self, name)
                raise ValueError(f"Grid: {name} is swept ({vals.size} values in "
                                 f"[{vals.min():g}, {vals.max():g}] "
                                 f"{UNITS[name]}) but {why}: every value would "
                                 f"give the same result; give {give}, or leave "
                                 f"{name} out")
        if self.forced:
            check_forcing("Grid", *(getattr(self, n) for n in
                                    ("m", "k", "c", "F0", "Omega", "Y0")),
                          paired=self.mode == "points")

    def _checked_laws(self):
        """The law given: one law object, or a tuple of them (a dimension)."""
        analytic = {n: getattr(self, n) for n in _analytic.PARAMETERS}
        many = isinstance(self.law, (list, tuple))
        laws = tuple(self.law) if many else (self.law,)
        if many and not laws:
            raise ValueError("law is an empty list: give at least one law")
        for one in laws:
            check_law("Grid", one, analytic)
        names = [one.name for one in laws]
        if len(set(names)) < len(names):
            dup = next(n for n in names if names.count(n) > 1)
            raise ValueError(f"the laws of a Grid must have distinct names (they label "
                             f"the law dimension), got {dup!r} twice")
        if many and self.mode == "points":
            raise ValueError("Grid.points takes one law; sweep several laws with "
                             "Grid(..., law=[...]) (a law dimension)")
        return laws if many else laws[0]

    @property
    def laws(self) -> tuple:
        """The laws of the grid's rows (``layout.LAW`` indexes them): the analytic
        family, one law object, or the law dimension's."""
        if self.law is None:
            return (ANALYTIC,)
        return self.law if isinstance(self.law, tuple) else (self.law,)

    @property
    def loads(self) -> tuple:
        """The load shapes of the grid's rows (``layout.LOAD`` indexes them): one
        cosine, the one given, or the load dimension's."""
        if self.load is None:
            return (excitations.HARMONIC,)
        return self.load if isinstance(self.load, tuple) else (self.load,)

    @property
    def forced(self) -> bool:
        """Whether any point is excited (F0 or Y0 not 0): the grid's result is a
        forced response's (``sweepcore.variables.FORCED_OBSERVABLES``)."""
        return excitations.given({n: getattr(self, n) for n in excitations.KEYWORDS})

    @property
    def _axes(self) -> tuple[str, ...]:
        """The axes a result labels: the excitation's only where it is given."""
        if self.forced:
            return AXES
        return tuple(n for n in AXES if n not in excitations.KEYWORDS)

    @classmethod
    def points(cls, m, k, r_y=None, v=None, alpha1=None, alpha2=None, x0=0.0, xdot0=None,
               c=0.0, r_k=None, v_s=None, law=None, F0=0.0, Omega=None, phi=0.0,
               Y0=0.0, load=None) -> Grid:
        """Scattered parameter sets: equal-length 1-D arrays, read index by index.

        Scalars are shared by every point. The result has one dimension, ``point``.
        """
        return cls(m, k, r_y, v, alpha1, alpha2, x0, xdot0, c, r_k, v_s, law, F0, Omega,
                   phi, Y0, load, mode="points")

    # ------------------------------------------------------------------ shape
    def axis(self, name: str):
        """The validated value of one axis: float, read-only 1-D array or None (the
        law dimension: its tuple of laws)."""
        if name == LAW_DIM and isinstance(self.law, tuple):
            return self.law
        if name == LOAD_DIM and isinstance(self.load, tuple):
            return self.load
        if name not in AXES:
            raise KeyError(f"unknown axis {name!r}; axes are {AXES}")
        return getattr(self, name)

    @property
    def swept(self) -> tuple[str, ...]:
        """Names of the array axes, in dimension order (``law`` first, then
        ``load``)."""
        laws = (LAW_DIM,) if isinstance(self.law, tuple) else ()
        loads = (LOAD_DIM,) if isinstance(self.load, tuple) else ()
        return laws + loads + tuple(n for n in self._axes
                                    if isinstance(self.axis(n), np.ndarray))

    @property
    def fixed(self) -> tuple[str, ...]:
        """Names of the scalar axes (None axes excluded)."""
        return tuple(n for n in self._axes if isinstance(self.axis(n), float))

    @property
    def dims(self) -> tuple[str, ...]:
        """Dimension names of the sweep's Dataset."""
        if self.mode == "points":
            return (POINT_DIM,)
        return self.swept

    @property
    def shape(self) -> tuple[int, ...]:
        if self.mode == "points":
            swept = self.swept
            return (len(self.axis(swept[0])) if swept else 1,)
        return tuple(len(self.axis(n)) for n in self.swept)

    @property
    def size(self) -> int:
        """Number of parameter sets (grid points)."""
        return math.prod(self.shape)

    def __len__(self) -> int:
        return self.size

    def __repr__(self) -> str:
        parts = []
        if self.law is not None:
            parts.append(f"law={[one.name for one in self.laws]!r}"
                         if isinstance(self.law, tuple) else f"law={self.law!r}")
        if self.load is not None:
            parts.append(f"load={[one.name for one in self.loads]!r}"
                         if isinstance(self.load, tuple) else f"load={self.load!r}")
        for name in self._axes:
            if self.law is not None and name in _analytic.PARAMETERS:
                continue
            val = self.axis(name)
            if isinstance(val, np.ndarray):
                parts.append(f"{name}=<{val.size} values in [{val.min():.6g}, "
                             f"{val.max():.6g}]>")
            else:
                parts.append(f"{name}={val!r}")
        kind = "Grid.points" if self.mode == "points" else "Grid"
        return f"{kind}({', '.join(parts)})"

    # ------------------------------------------------------------------- rows
    def rows(self, start: int, stop: int) -> np.ndarray:
        """Kernel rows of the flat (C-order) indices ``start <= i < stop``.

        Returns
        -------
        numpy.ndarray
            float64, C-contiguous, shape ``(stop - start, layout.NP)``, columns
            ``layout.M ... layout.XD0``; ``xdot0=None`` gives xdot0 = v,
            ``r_k=None`` r_k = r_y, ``v_s=None`` NaN (not used).
        """
        if not 0 <= start <= stop <= self.size:
            raise IndexError(f"flat index range [{start}, {stop}) outside the grid "
                             f"of {self.size} points")
        if self.mode == "points":
            return self._rows({name: slice(start, stop) for name in self.swept},
                              stop - start)
        return self.rows_at(np.arange(start, stop))

    def rows_at(self, flat: np.ndarray) -> np.ndarray:
        """Kernel rows of the flat (C-order) indices ``flat`` (any order), as
        :meth:`rows` gives them."""
        flat = np.asarray(flat, np.intp)
        if self.mode == "points":
            return self._rows({name: flat for name in self.swept}, flat.size)
        multi = np.unravel_index(flat, self.shape) if self.shape else ()
        return self._rows(dict(zip(self.swept, multi)), flat.size)

    def _rows(self, index: dict, n: int) -> np.ndarray:
        """The rows of ``n`` points, each swept axis indexed by ``index[name]``."""
        P = np.empty((n, layout.NP))
        for name in AXES:
            val = self.axis(name)
            col = COLUMNS[name]
            if val is None and name == "Omega":     # no excitation
                P[:, col] = np.nan
            elif val is None:   # start stuck on the belt; a law's parameter left out
                P[:, col] = P[:, layout.V] if name == "xdot0" else \
                    self.laws[0].missing_column(name, P)
            elif isinstance(val, np.ndarray):
                P[:, col] = val[index[name]]
            else:
                P[:, col] = val
        P[:, layout.LAW] = index[LAW_DIM] if LAW_DIM in index else 0.0
        P[:, layout.LOAD] = index[LOAD_DIM] if LOAD_DIM in index else 0.0
        return P

    def block(self, start: int, stop: int) -> tuple[Grid, int, int]:
        """``(grid, lo, hi)`` with ``grid.rows(lo, hi) == self.rows(start, stop)``,
        small enough to ship with one task.

        A product grid is its 1-D axes (small): itself. A points grid is cut down to
        the points of the range.
        """
        if self.mode == "product":
            return self, start, stop
        cut = {n: self.axis(n)[start:stop] if n in self.swept else self.axis(n)
               for n in AXES}
        return Grid.points(**cut, law=self.law, load=self.load), 0, stop - start

    # ---------------------------------------------------------------- labels
    def coords(self) -> dict[str, xr.Variable]:
        """Coordinates of the sweep's Dataset, with CF ``units`` and ``long_name``.

        Swept axes are 1-D coordinates (dimension coordinates in product mode,
        coordinates along ``point`` in points mode); fixed ones are 0-d.
        """
        out = {}
        if self.mode == "points":
            out[POINT_DIM] = xr.Variable(
                POINT_DIM, np.arange(self.size),
                {"units": "1", "long_name": "parameter set index"})
        if isinstance(self.law, tuple):
            out[LAW_DIM] = xr.Variable(LAW_DIM, np.array([one.name for one in self.law]),
                                       {"long_name": "friction law (sweepcore.laws)"})
        if isinstance(self.load, tuple):
            out[LOAD_DIM] = xr.Variable(
                LOAD_DIM, np.array([one.name for one in self.load]),
                {"long_name": "shape of the load (sweepcore.PeriodicLoad)"})
        for name in self._axes:
            val = self.axis(name)
            attrs = {"units": UNITS[name], "long_name": LONG_NAMES[name]}
            if val is None and name == "r_k" and self.law is None:   # = r_y
                val = self.axis("r_y")
                attrs["comment"] = "r_k = r_y: no Stribeck term (eq. 40)"
            if val is None:
                continue
            if isinstance(val, np.ndarray):
                dim = POINT_DIM if self.mode == "points" else (
                    "r_y" if self.r_k is None and name == "r_k" else name)
                out[name] = xr.Variable(dim, np.array(val), attrs)
            else:
                out[name] = xr.Variable((), val, attrs)
        return out

    def fingerprint(self) -> str:
        """SHA-256 of the grid's exact values (for matching a resumed sweep)."""
        h = hashlib.sha256(self.mode.encode())
        for one in (self.laws if self.law is not None else ()):
            h.update(b"law")
            h.update(one.fingerprint())
        for one in (self.loads if self.load is not None else ()):
            h.update(b"load")
            h.update(one.fingerprint())
        for name in self._axes:
            val = self.axis(name)
            h.update(name.encode())
            if isinstance(val, np.ndarray):
                h.update(b"array")
                h.update(val.astype("<f8").tobytes())
            else:
                h.update(repr(val).encode())
        return h.hexdigest()


Grid.__init__ = checked_keywords(Grid.__init__)


def checked_grid(grid) -> Grid:
    """``grid`` itself, refused with a TypeError naming its type unless it is a
    :class:`Grid` (the first check of every function that takes one)."""
    if not isinstance(grid, Grid):
        raise TypeError(f"grid must be a sweepcore.Grid, got {type(grid).__name__}")
    return grid
