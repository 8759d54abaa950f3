"""The friction law's derived quantities, for the Python side (one home).

Every Python room (Params, Grid, sweep, simulate, boundaries, plot, benchmarks)
reads q, x_eq, the Hopf speeds and the friction force from here, and this module
evaluates them with the kernels' law interface (``sweepcore/_kernels/law.py``): one
definition, the same compiled code in the kernels and in Python.

A *source* is anything that holds the parameters by name: a
:class:`sweepcore.Params`, a mapping (dict of numbers or arrays), an
``xarray.Dataset`` (its coordinates broadcast by dimension name) or a kernel row
(``from_row``). Missing optional parameters take their defaults (no damping, no
Stribeck term). Its law is the analytic family (parameters r_y, alpha1, alpha2,
r_k, v_s: :mod:`sweepcore.laws.analytic`), or the law object under ``"law"``
(:mod:`sweepcore.laws`), whose own data replace those parameters.
"""
from __future__ import annotations

import numpy as np

from ._kernels import derived as _derived
from ._kernels import layout
from .laws import ANALYTIC, FrictionLaw
from .laws import analytic as _analytic

# the slider's parameters; a law's come after them in the API's order
SLIDER = ("m", "k", "v", "c")
PARAMETERS = ("m", "k", "r_y", "v", "alpha1", "alpha2", "c", "r_k", "v_s")
COLUMNS = {"m": layout.M, "k": layout.K, "v": layout.V, "c": layout.C,
           **_analytic.COLUMNS}
# optional parameters: None means "the default" (sweepcore.laws.analytic.DEFAULTS);
# law None: the analytic family
DEFAULTS = {"c": 0.0, **_analytic.DEFAULTS, "law": None}

# name -> (kernel column, the parameters it depends on). A sweep stores each over the
# dimensions of those parameters only (q does not vary along k); a law object stands
# for the analytic parameters (and adds the law's dimension, where there is one). The
# Hopf speeds are those of a belt moving forwards (v > 0): for v < 0 they are the
# mirrored law's, the same for a law odd in the relative speed.
_Q = ("m", "v", "alpha1", "alpha2", "c", "r_y", "r_k", "v_s")
_HOPF = ("alpha1", "alpha2", "c", "r_y", "r_k", "v_s")
DERIVED = {
    "omega": (_derived.D_OMEGA, ("m", "k")),
    "q": (_derived.D_Q, _Q),
    "x_eq": (_derived.D_XEQ, ("k", "v", "alpha1", "alpha2", "r_y", "r_k", "v_s")),
    "v_star": (_derived.D_VSTAR, _HOPF),
    "v_star_2": (_derived.D_VSTAR2, _HOPF),
    "first_lyapunov": (_derived.D_LYAP, ("m", "k") + _HOPF),
    "x_s": (_derived.D_XS, ("k", "v", "r_y", "c")),
    # a code of CRITICALITY: the sign of the third derivative of F at v_star
    "criticality": (_derived.D_CRIT, _HOPF),
}
CRITICALITY = {0: "none", 1: "supercritical", 2: "subcritical", 3: "degenerate"}


def value(source, name: str):
    """Parameter ``name`` of ``source`` (mapping, Dataset or attributes); a missing
    optional parameter gives its default (None for r_k, v_s and law)."""
    try:
        got = source[name]
    except (KeyError, TypeError, IndexError):
        got = getattr(source, name, None)
    if got is not None:
        return got
    if name in DEFAULTS:
        return DEFAULTS[name]
    raise KeyError(f"the friction law needs parameter {name!r}, which "
                   f"{type(source).__name__} does not hold")


def law_of(source) -> FrictionLaw:
    """The law of ``source``: its law object, or the analytic family."""
    try:
        got = value(source, "law")
    except KeyError:
        got = None
    if got is None:
        return ANALYTIC
    if hasattr(got, "dims"):                      # a Dataset's law coordinate
        raise TypeError("a source with a law dimension holds law names, not laws: "
                        "pass the laws (laws=) where the function takes them")
    return got


def names_of(name: str, source) -> tuple[str, ...]:
    """The parameters ``DERIVED[name]`` depends on for the law of ``source``."""
    names = DERIVED[name][1]
    if law_of(source) is ANALYTIC:
        return names
    return tuple(n for n in names if n in SLIDER)


def from_row(row, law=None) -> dict:
    """A source made of a kernel parameter row (layout ``sweepcore._kernels.layout``)
    and its law object (None: the analytic family)."""
    names = PARAMETERS if law is None or law is ANALYTIC else SLIDER
    out = {name: float(row[COLUMNS[name]]) for name in names}
    if law is not None and law is not ANALYTIC:
        out["law"] = law
    return out


def row_law(row, laws=(ANALYTIC,)) -> FrictionLaw:
    """The law of a kernel row: ``laws[row[LAW]]``."""
    return laws[int(row[layout.LAW])]


def per_law(P: np.ndarray, laws, name: str, dtype=np.float64) -> np.ndarray:
    """``law.<name>(rows)`` of every row of the kernel rows P, each row by its own law
    (``laws[row[LAW]]``)."""
    which = P[:, layout.LAW].astype(np.intp)
    out = np.zeros(P.shape[0], dtype)
    for i, law in enumerate(laws):
        rows = which == i
        if rows.any():
            out[rows] = getattr(law, name)(P[rows])
    return out


def length_scale(P: np.ndarray, laws=(ANALYTIC,)) -> np.ndarray:
    """The kernels' length scale of each row [cm] (``_kernels.law.length_scale``):
    the static bound over k plus ``|v|/omega``."""
    P = np.atleast_2d(P)
    static = per_law(P, laws, "static_bound")
    k, m = P[:, layout.K], P[:, layout.M]
    return static / k + np.abs(P[:, layout.V]) / np.sqrt(k / m)


def rows_of(arrays: dict, shape, law=None) -> np.ndarray:
    """Kernel rows (n, layout.NP) of parameter arrays (broadcast to ``shape``)."""
    P = np.zeros((int(np.prod(shape)), layout.NP))
    for n, a in arrays.items():
        P[:, COLUMNS[n]] = np.broadcast_to(np.asarray(a, np.float64), shape).ravel()
    if law is None or law is ANALYTIC:
        if "r_k" in arrays and "r_y" not in arrays:
            P[:, layout.RY] = P[:, layout.RK]
    return P


def evaluate(name: str, *arrays, law=None) -> np.ndarray:
    """Quantity ``name`` from the arrays of its parameters (``names_of``: for the
    analytic family ``DERIVED[name][1]``, in that order; for a law object the
    slider's among them), numpy broadcasting (None for r_k: r_y, for v_s: not
    given)."""
    law = ANALYTIC if law is None else law
    which, names = DERIVED[name]
    if law is not ANALYTIC:
        names = tuple(n for n in names if n in SLIDER)
    args = dict(zip(names, arrays))
    if "r_k" in args and args["r_k"] is None:
        args["r_k"] = args["r_y"]
    if "v_s" in args and args["v_s"] is None:
        args["v_s"] = np.nan
    arrs = {n: np.asarray(a, np.float64) for n, a in args.items()}
    shape = np.broadcast_shapes(*(a.shape for a in arrs.values()))
    P = rows_of(arrs, shape, law)
    out = np.empty(P.shape[0])
    for _code, rows, lw in law.kernel_groups(P):
        sub = np.empty(rows.size)
        _derived.derived_rows(np.ascontiguousarray(P[rows]), lw, which, sub)
        out[rows] = sub
    return out.reshape(shape)


def derived(name: str, source):
    """Derived quantity ``name`` (a key of ``DERIVED``) of ``source``: a float for
    numbers, a numpy array for arrays (broadcast), a DataArray over the dimensions of
    the parameters it depends on for an ``xarray.Dataset`` or DataArrays."""
    law = law_of(source)
    names = names_of(name, source)
    no_stribeck = "r_k" in names and value(source, "r_k") is None
    vals = [_r_y_or_zero(source) if n == "r_y" and no_stribeck else value(source, n)
            for n in names]
    if any(hasattr(x, "dims") for x in vals):
        import xarray as xr
        given = [i for i, x in enumerate(vals) if x is not None]

        def fn(*arrs):
            full = [None] * len(names)
            for i, a in zip(given, arrs):
                full[i] = a
            return evaluate(name, *full, law=law)
        return xr.apply_ufunc(fn, *(vals[i] for i in given), dask="parallelized",
                              output_dtypes=[np.float64])
    out = evaluate(name, *vals, law=law)
    return float(out) if out.ndim == 0 else out


def _r_y_or_zero(source):
    """r_y, which a quantity without a Stribeck term does not need (0 if absent)."""
    try:
        return value(source, "r_y")
    except KeyError:
        return 0.0


def criticality_code(source):
    """Flag codes of ``CRITICALITY`` (int8) of ``source``: none without a Hopf speed,
    else the kind of the lowest one by the sign of F'''(-v*) (the sign of the first
    Lyapunov coefficient, which its value can lose to underflow)."""
    got = derived("criticality", source)
    if hasattr(got, "astype"):
        return got.astype(np.int8)
    return np.int8(got)


def friction(zdot, source, phase=None):
    """Friction force r_a on the slider while sliding [kN] (the kernels' law,
    vectorised). ``phase`` is the sign of zdot (+1, -1); by default ``sign(zdot)``."""
    law = law_of(source)
    if law is ANALYTIC:
        return _analytic.force(zdot, source, value, phase)
    return law.force(zdot, phase)


def stick_force(x, source):
    """Friction force on the slider while stuck [kN]: ``-(k x + c v)`` (it holds the
    slider at belt speed while it lies between the law's static limits)."""
    return -(value(source, "k") * np.asarray(x, np.float64)
             + value(source, "c") * value(source, "v"))


def stick_onset_estimate(source):
    """First-order averaging estimate ``2 v*/sqrt(5)`` of the belt speed [cm/s] below
    which a slip cycle of the polynomial law reaches belt speed (sticks): the
    averaged cycle's velocity amplitude ``2 sqrt(v*^2 - v^2)`` reaches v (v_s = 0
    too: a slip cycle never sees the jump). NaN for a law with a Stribeck term or a
    law object (no such closed form)."""
    est = 2.0 / np.sqrt(5.0) * derived("v_star", source)
    if law_of(source) is not ANALYTIC:
        return est * np.nan
    r_k = value(source, "r_k")
    if r_k is None:
        return est
    # no Stribeck term: r_k = r_y, or v_s = 0 (the jump: its slides are the
    # polynomial law's with the level r_k)
    polynomial = (r_k == value(source, "r_y")) | (value(source, "v_s") == 0.0)
    if hasattr(est, "where"):
        return est.where(polynomial)
    return np.where(polynomial, est, np.nan)


# ------------------------------------------------------- resolvable magnitudes
# The natural time 1/omega [s] beyond which a point is not trusted: changes of units
# of the paper's slider (m = 5, k = 50, r_y = 10, alpha1 = 1, alpha2 = 0.01, v = 2
# and 5; time unit 1e-10 .. 1e100 s, length and force units 1e-100 .. 1e100) give
# the same period and amplitude to 1e-15 up to 1/omega = 3.2e80 s, and a wrong
# regime (slip_cycle for stick_slip, period off by 2e-4) from 3.2e81 s on (the same
# edges with dopri5 and with dop853, both thresholds below).
TIME_SCALE_MAX = 1e78
# pi zeta at most this many touch tolerances: too weak a law to resolve. Measured on
# the paper's slider with m raised (v = 7, where the equilibrium is the attractor):
# tol 1e-8 (touch tolerance 2e-7) right at pi zeta = 4.4e-7 (m = 1e12), a touching
# circle of amplitude v/omega reported as a slip cycle at 1.4e-7 (m = 1e13); tol
# 1e-10 right at 4.4e-8 (m = 1e14).
WEAK = 2.0


def unresolvable(P: np.ndarray, o: np.ndarray, laws=(ANALYTIC,),
                 weak: bool = True) -> np.ndarray:
    """Rows of the parameter rows ``P`` (layout ``_kernels.layout``; their laws are
    ``laws[P[:, LAW]]``) whose attractor the kernels cannot resolve with the option
    row ``o``, as a bool array.

    Two magnitudes: (1) the friction law changes a motion by less per natural
    period than the driver's touch tolerance ``g`` (``driver.touch_tol``: 20 tol
    for the adaptive pairs dopri5 and dop853, ``graze`` for the others), so a slowly
    growing or decaying motion that touches the belt is taken for a reset cycle:
    ``0 < pi zeta <= WEAK g`` with ``zeta = max(|c|, S) / (m omega)``, S the law's
    bound of ``|F'|`` at the row's speeds (``slope_scale``; for the analytic family
    ``max(|alpha1|, 3 alpha2 v^2, |r_y - r_k|/v_s)``, the last for v_s > 0), an
    upper bound of the law's slope per ``m omega`` (``|q|/omega`` is one value of it). ``zeta = 0`` (constant
    friction, no damping: neutral circles) is resolved exactly, and so is a
    conservative field (the law's ``conservative``: for the analytic family c =
    alpha1 without a cubic or Stribeck term, taken as zeta = 0); a static belt
    (``v = 0``) has no cycle through the breakaway point to mistake. (2)
    ``1/omega > TIME_SCALE_MAX``. ``weak=False`` leaves (1) out: a forced slider's
    search decides on the stroboscopic map, not on touches at the breakaway point.
    """
    from ._kernels.stepper import ADAPTIVE, TOUCH_FACTOR
    from ._kernels import codes

    P = np.atleast_2d(np.asarray(P, np.float64))
    m, k, v = P[:, layout.M], P[:, layout.K], P[:, layout.V]
    slope = per_law(P, laws, "slope_scale")
    linear = per_law(P, laws, "closed_form", bool)
    conservative = per_law(P, laws, "conservative", bool)
    with np.errstate(all="ignore"):
        root_m, root_k = np.sqrt(m), np.sqrt(k)
        zeta = np.maximum(np.abs(P[:, layout.C]), slope) / (root_m * root_k)
        # a conservative field (kernel law.conservative) changes no motion at all:
        # its circles are exact, as for zeta = 0
        zeta = np.where(conservative, 0.0, zeta)
        method = int(o[layout.O_METHOD])
        if method < 0:          # auto: the closed form, else one of the adaptive pairs
            pairs = max(f for f, a in zip(TOUCH_FACTOR, ADAPTIVE) if a)
            factor = np.where(linear, TOUCH_FACTOR[codes.EXACT], pairs)
        else:
            factor = TOUCH_FACTOR[method]
        g = np.maximum(o[layout.O_GRAZE], factor * o[layout.O_RTOL])
        weak_friction = (zeta > 0.0) & (v != 0.0) & (np.pi * zeta <= WEAK * g)
        slow = root_m / root_k > TIME_SCALE_MAX
    return (weak_friction & weak) | slow


def flag_unresolvable(P: np.ndarray, o: np.ndarray, out: np.ndarray,
                      laws=(ANALYTIC,), weak: bool = True) -> None:
    """Give the observable rows ``out`` (n, ..., NOBS: every slot of a row) of
    :func:`unresolvable` points the status ``unresolvable_scale`` and the regime
    ``failed`` (their numbers are kept, as the search returned them: estimates
    without digits to trust)."""
    from ._kernels import codes

    bad = unresolvable(P, o, laws, weak)
    if bad.any():
        out[bad, ..., layout.OB_STATUS] = codes.SCALE
        out[bad, ..., layout.OB_REGIME] = codes.R_FAILED
