"""Boundaries of a forced slider's map beyond its grid: the load (or any parameter
``along``) where the response's sticks appear or vanish, and where its stops per
period change, located to ``xtol`` by following the response.

At each point of the grid's other axes, the response the grid's start reaches at
the bracket's lower end (the stroboscopic search, as the map's own point there) is
followed up to its upper end by :mod:`sweepcore.branch` (pseudo-arclength
continuation of the fixed point of P^n, through folds); the first change along the
branch from no stick to finite sticks or back is ``<along>_stick_onset``, the first
change of the stops per period ``<along>_stops_change``, each the middle of a bracket
narrower than ``xtol`` times its value (the half-width is returned). With c = 0,
v = 0, Coulomb friction and one cosine, the stick onset in F0 is Den Hartog's
continuous-motion boundary ``r_y / r_b(Omega/omega)`` (also returned, as
``<along>_den_hartog``, where it applies). :func:`continue_forced` follows it along a
second parameter, each step's bracket narrowed around the extrapolation of the
previous two.
"""
from __future__ import annotations

import math

import numpy as np
import xarray as xr

from .. import branch, continuation, execute, forced, labels, law
from .._kernels import codes, layout
from ..excitations import HARMONIC, theory
from ..grid import Grid, checked_grid
from ..options import make_options
from ..params import LONG_NAMES, UNITS
from .locate import checked_bracket
from .point import ABSENT, FAILED, INCONSISTENT, LOCATED, SEARCH_NAMES

NARROW = 0.05       # half-width of a continued step's bracket, of its prediction
SUCCESS = (branch.REACHED, branch.LEFT, branch.CLOSED)


def _bracket(grid: Grid, along: str, bracket):
    """(lo, hi) of the search, checked (``locate.checked_bracket``), each end a
    slider the grid accepts; the grid's ``along`` range by default."""
    lo, hi = checked_bracket(grid, along, bracket)
    import dataclasses
    for name, value in (("bracket[0]", lo), ("bracket[1]", hi)):
        try:        # every slider of the bracket's ends, checked as a Grid checks them
            dataclasses.replace(grid, **{along: value})
        except (TypeError, ValueError) as e:
            raise ValueError(f"{name} = {value!r} for {along!r}: {e}") from None
    return lo, hi


def _other(grid: Grid, along: str, lo: float) -> Grid:
    import dataclasses
    checked_grid(grid)
    if grid.mode != "product":
        raise ValueError("locate_boundaries needs a product Grid (Grid(...)), not "
                         "Grid.points")
    if grid.law is not None and along in continuation.ANALYTIC_ONLY:
        raise ValueError(f"along={along!r} is a parameter of the analytic law; the "
                         "grid's law is an object")
    x0, xd0 = grid.axis("x0"), grid.axis("xdot0")
    if isinstance(x0, np.ndarray) or isinstance(xd0, np.ndarray):
        raise ValueError("x0 and xdot0 must be scalars (one start for every search)")
    return dataclasses.replace(grid, **{along: lo})


# ------------------------------------------------------------------ one point
def _empty() -> dict:
    out = {"evaluations": 0, "multiplicity": -1}
    for key in ("stick", "stops"):
        out.update({f"{key}_value": math.nan, f"{key}_width": math.nan,
                    f"{key}_status": ABSENT, f"{key}_below": -1, f"{key}_above": -1})
    return out


def _events(records) -> dict:
    """The first stick onset and the first change of stops along the records:
    ``{key: (at, width, status, before, after)}``."""
    out = {}
    for r in records:
        if r.change is None:
            continue
        (sb, pb), (sa, pa) = r.change
        status = LOCATED if r.status == codes.OK else INCONSISTENT
        if (sb > 0) != (sa > 0) and "stick" not in out:
            out["stick"] = (r.at, r.width, status, sb, sa)
        if pb != pa and "stops" not in out:
            out["stops"] = (r.at, r.width, status, pb, pa)
    return out


def locate_point(row, law_object, load, along: str, lo: float, hi: float, o, tol: float,
                 xtol: float) -> dict:
    """The stick onset and the stops change of one kernel row along ``along`` in
    [lo, hi] (the row's start: the grid's), as a dict of the Dataset's fields."""
    res = _empty()
    row = np.array(row, float)
    row[layout.LAW] = row[layout.LOAD] = 0.0
    cols = continuation.columns(row, along)
    for c in cols:
        row[c] = lo
    out = np.empty((1, layout.NFOB))
    forced.responses(row[None, :], (law_object,), (load,), o, out)
    n = out[0, layout.OB_MULTIPLICITY]
    if int(out[0, layout.OB_STATUS]) not in (codes.OK, codes.UNRESOLVED) or \
            not math.isfinite(n):
        res["stick_status"] = res["stops_status"] = FAILED
        return res
    prob = continuation.problem(row, law_object, load, along, int(n), o, tol,
                                max(abs(lo), abs(hi)))
    try:
        first = prob.at_parameter(prob.scaled(out[0, layout.OB_X_SECTION],
                                              out[0, layout.OB_XDOT_SECTION], lo), lo)
    except branch.Failed:
        res["stick_status"] = res["stops_status"] = FAILED
        return res
    records, ended = branch.follow(prob, first, hi, (lo, hi), 0.01, 0.05, 2000, xtol)
    res["multiplicity"] = int(n)
    found = _events(records)
    for key in ("stick", "stops"):
        if key in found:
            at, width, status, below, above = found[key]
            res.update({f"{key}_value": at, f"{key}_width": width,
                        f"{key}_status": status, f"{key}_below": below,
                        f"{key}_above": above})
        elif ended not in SUCCESS:
            res[f"{key}_status"] = FAILED
    res["evaluations"] = prob.images
    return res


def locate_chunk(rows, laws, loads, along, lo, hi, o, tol, xtol, parallel=False):
    """The searches of one chunk of rows (a task of :func:`locate_forced`)."""
    return [locate_point(r, laws[int(r[layout.LAW])], loads[int(r[layout.LOAD])],
                         along, lo, hi, o, tol, xtol) for r in rows]


# ------------------------------------------------------------------ public
def locate_forced(grid: Grid, along: str, bracket, xtol: float, tol: float,
                  method: str, chunks, client, scheduler, options) -> xr.Dataset:
    """:func:`sweepcore.locate_boundaries` of a forced grid (module docstring)."""
    continuation.check_parameter(along, what="along")
    lo, hi = _bracket(grid, along, bracket)
    other = _other(grid, along, lo)
    forced.check_method(method)
    o = make_options(method, tol=tol, **options)
    kind, target = execute.resolve(client, scheduler)
    execute.check_chunks(chunks)
    chunk = other.size if chunks is None else min(int(chunks), other.size)
    bounds = execute.chunk_bounds(other.size, chunk)
    parts = [None] * len(bounds)

    def task(i):
        return locate_chunk, (other.rows(*bounds[i]), other.laws, other.loads, along,
                              lo, hi, o, tol, xtol)
    execute.run(kind, target, range(len(bounds)), task, parts.__setitem__)
    results = [r for part in parts for r in part]
    call = (f"sweepcore.locate_boundaries({grid!r}, along={along!r}, "
            f"bracket={(lo, hi)!r}, xtol={xtol!r}, tol={tol!r}, method={method!r})")
    return forced_dataset(other, along, results, tol, method, call)


def continue_forced(grid: Grid, over: str, along: str, bracket, xtol: float,
                    tol: float, method: str, options) -> xr.Dataset:
    """:func:`sweepcore.continue_boundary` of a forced grid: the stick onset along
    ``over``, each step searched in a bracket of +-``NARROW`` of its prediction
    (linear through the previous two), the whole bracket where that finds none."""
    continuation.check_parameter(along, what="along")
    lo, hi = _bracket(grid, along, bracket)
    other = _other(grid, along, lo)
    if other.swept != (over,):
        raise ValueError(f"over={over!r}: continue_boundary needs {over!r} swept and "
                         f"every other parameter fixed (apart from {along!r}); swept: "
                         f"{other.swept}")
    forced.check_method(method)
    o = make_options(method, tol=tol, **options)
    xs = np.asarray(other.axis(over))
    rows = other.rows(0, other.size)
    results, found = [], []
    for i, row in enumerate(rows):
        law_object, load = other.laws[int(row[layout.LAW])], other.loads[int(row[layout.LOAD])]
        res = None
        if len(found) >= 2:
            (x1, y1), (x2, y2) = found[-2:]
            guess = y2 + (y2 - y1) * (xs[i] - x2) / (x2 - x1)
            a, b = max(lo, guess * (1 - NARROW)), min(hi, guess * (1 + NARROW))
            if a < b:
                res = locate_point(row, law_object, load, along, a, b, o, tol, xtol)
                if res["stick_status"] != LOCATED:
                    res = None
        continued = res is not None
        if res is None:
            res = locate_point(row, law_object, load, along, lo, hi, o, tol, xtol)
        res["continued"] = int(continued)
        if res["stick_status"] == LOCATED:
            found.append((xs[i], res["stick_value"]))
        else:
            found = []
        results.append(res)
    call = (f"sweepcore.continue_boundary({grid!r}, over={over!r}, along={along!r}, "
            f"bracket={(lo, hi)!r}, xtol={xtol!r}, tol={tol!r}, method={method!r})")
    ds = forced_dataset(other, along, results, tol, method, call)
    ds["continued"] = xr.Variable(other.dims, np.array(
        [r["continued"] for r in results], np.int8),
        {"units": "1", "long_name": "step searched around its prediction",
         "flag_values": np.array([0, 1], np.int8),
         "flag_meanings": "whole_bracket continued"})
    return ds


# ------------------------------------------------------------------ the Dataset
def den_hartog(rows, laws, loads, along: str) -> np.ndarray:
    """Den Hartog's continuous-motion boundary in F0, r_y / r_b(Omega/omega) [kN],
    at each row where it applies (the analytic law with Coulomb friction, c = 0,
    v = 0, one cosine, no base motion); NaN elsewhere."""
    out = np.full(len(rows), np.nan)
    if along != "F0":
        return out
    for i, r in enumerate(rows):
        src = law.from_row(r, laws[int(r[layout.LAW])])
        ex = continuation.excitation(r)
        if "law" in src or loads[int(r[layout.LOAD])] != HARMONIC or ex["Y0"] or \
                src["c"] or src["v"] or src["alpha1"] or src["alpha2"] or \
                src["r_k"] != src["r_y"]:
            continue
        out[i] = src["r_y"] / float(theory.continuous_motion_boundary(
            ex["Omega"] / math.sqrt(src["k"] / src["m"])))
    return out


def forced_dataset(other: Grid, along: str, results, tol, method, call) -> xr.Dataset:
    """The labelled result of the forced searches, over the grid's other axes."""
    dims, shape = other.dims, other.shape
    units = UNITS[along]

    def field(key, dtype=np.float64):
        return np.array([r[key] for r in results], dtype).reshape(shape)

    status = labels.flags(SEARCH_NAMES, "outcome of the search")
    name = LONG_NAMES[along]
    data = {
        f"{along}_stick_onset": (field("stick_value"), labels.attrs(
            units, f"{name} where the response's finite sticks appear or vanish",
            "the first change along the bracket between responses without and with "
            "sticks of finite duration, on the branch followed from the bracket's "
            "lower end (the middle of the final bracket)")),
        f"{along}_stick_onset_width": (field("stick_width"), labels.attrs(
            units, "half-width of the stick onset's final bracket")),
        "stick_status": (field("stick_status", np.int8),
                         {**status, "long_name": "outcome of the stick-onset search"}),
        "sticks_below": (field("stick_below", np.int64), labels.attrs(
            "1", "finite sticks per period below the stick onset", "-1: none found")),
        "sticks_above": (field("stick_above", np.int64), labels.attrs(
            "1", "finite sticks per period above the stick onset", "-1: none found")),
        f"{along}_stops_change": (field("stops_value"), labels.attrs(
            units, f"{name} where the stops per period change",
            "the first change of the zero-duration stops per response period along "
            "the branch (the middle of the final bracket)")),
        f"{along}_stops_change_width": (field("stops_width"), labels.attrs(
            units, "half-width of the stops change's final bracket")),
        "stops_status": (field("stops_status", np.int8),
                         {**status, "long_name": "outcome of the stops-change search"}),
        "stops_below": (field("stops_below", np.int64), labels.attrs(
            "1", "zero-duration stops per period below the change", "-1: none found")),
        "stops_above": (field("stops_above", np.int64), labels.attrs(
            "1", "zero-duration stops per period above the change", "-1: none found")),
        "multiplicity": (field("multiplicity", np.int64), labels.attrs(
            "1", "multiplicity n of the branch followed", "-1: no periodic response "
                                                          "at the bracket's lower end")),
        "evaluations": (field("evaluations", np.int64), labels.attrs(
            "1", "images of the stroboscopic map computed for the point")),
    }
    ds = xr.Dataset({k: (dims, v, a) for k, (v, a) in data.items()}, other.coords())
    ds = ds.drop_vars([n for n in (along, "x0", "xdot0") if n in ds.coords])
    dh = den_hartog(other.rows(0, other.size), other.laws, other.loads, along)
    if np.isfinite(dh).any():
        ds[f"{along}_den_hartog"] = (dims, dh.reshape(shape), labels.attrs(
            units, "Den Hartog's continuous-motion boundary r_y / r_b(Omega/omega)",
            "c = 0, v = 0, Coulomb friction: no stick above it "
            "(sweepcore.excitations.theory.continuous_motion_boundary)"))
    ds.attrs.update({
        **labels.provenance(
            "Boundaries of the forced friction oscillator's responses", call,
            "the response followed along the bracket by pseudo-arclength continuation "
            "(sweepcore.branch), its changes of sticks and stops located",
            "Units kN, cm, s. Status flags say where a boundary was not located and "
            "why."),
        "along": along, "method": method, "tol": float(tol),
        "sweepcore_kind": "boundaries",
    })
    return ds
