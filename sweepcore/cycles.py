"""Slip cycles over a grid, stable and unstable alike, and the polygon of one cycle.

The attractor search (``sweepcore.sweep``) follows the motion, so it only finds what
attracts. The scan of the return map (``sweepcore/_kernels/cycles.py``) finds every
stop-free slip cycle it brackets, whatever its stability: a Floquet multiplier below
1 is a stable cycle (an attractor), above 1 an unstable one. In the plane an
unstable cycle around a stable equilibrium is the boundary between two basins
(docs/physics.md, "Basins of attraction"), which is what ``sweepcore.basins`` uses.

* :func:`slip_cycles`: the cycles of every point of a grid, as a Dataset over the
  grid's dimensions and ``cycle`` (innermost first);
* :func:`cycle_polygon`: one cycle in the (x, xdot) plane, sampled in time;
* :func:`cycle_variables`: the labelled ``cycle_*`` variables of the kernel's output,
  shared by the cycles, basin and diagram files;
* :func:`clipped_area`: the area of a polygon inside a rectangle (the part of a
  cycle's interior in a box of starts), :func:`inside`: which starts a polygon holds.

The scan's reach: amplitudes from 1e-4 of the length scale to twice ``|v|/omega``
on a geometric ladder of 40 rungs; two cycles closer than one rung, or a cycle
smaller than the lowest rung (next to a Hopf point), can be missed.
"""
from __future__ import annotations

import math

import numpy as np
import xarray as xr

from . import compiled, execute, labels, resumable, variables
from ._kernels import codes, layout
from ._kernels.cycles import MAX_CYCLES
from ._kernels.trajectory import fresh_acc
from .grid import Grid, checked_grid
from .io import check_flag, result_path
from .laws import ANALYTIC
from .options import check_method, checked_keywords, make_options
from .sizing import cycles_need, refuse_unaffordable

__all__ = ["slip_cycles", "cycle_polygon", "cycle_variables", "cycles_chunk",
           "clipped_area", "inside",
           "stability", "STABLE", "UNSTABLE", "NONE", "UNDETERMINED"]

# stability of a cycle slot (flag variable cycle_stability)
NONE, STABLE, UNSTABLE, UNDETERMINED = -1, 0, 1, 2
STABILITY_NAMES = {NONE: "none", STABLE: "stable", UNSTABLE: "unstable",
                   UNDETERMINED: "undetermined"}


def stability(rows: np.ndarray) -> np.ndarray:
    """Stability codes of observables rows of the cycle scan (any leading shape):
    none (an unused slot), stable (Floquet multiplier < 1), unstable (> 1),
    undetermined (multiplier 1 or NaN, or a status other than ok)."""
    rows = np.asarray(rows)
    mu = rows[..., layout.OB_FLOQUET]
    found = rows[..., layout.OB_REGIME] == codes.R_SLIP_CYCLE
    ok = rows[..., layout.OB_STATUS] == codes.OK
    code = np.where(mu < 1.0, STABLE, np.where(mu > 1.0, UNSTABLE, UNDETERMINED))
    return np.where(~found, NONE, np.where(ok, code, UNDETERMINED)).astype(np.int8)


# ------------------------------------------------------------------ the kernel
def cycles_chunk(grid: Grid, start: int, stop: int, o: np.ndarray,
                 parallel: bool = False):
    """The task of one chunk: ``(out, found)`` of the cycle scan for the flat points
    [start, stop) (``out`` (n, MAX_CYCLES, NOBS), ``found`` (n,))."""
    P = grid.rows(start, stop)
    out = np.empty((stop - start, MAX_CYCLES, layout.NOBS))
    found = np.zeros(stop - start, np.int64)
    execute.cycles(P, grid.laws, o, out, found, parallel)
    return out, found


def _options(grid, method, tol, options) -> np.ndarray:
    checked_grid(grid)
    if method == "gps":
        raise ValueError("method='gps' follows its own discrete map: the cycles are "
                         "fixed points of the ODE's return map; use 'auto', 'dopri5', "
                         "'dop853' or 'rk4'")
    o = make_options(method, tol=tol, **options)
    check_method(method, grid)
    return o


def _check_no_start(grid: Grid, what: str) -> None:
    for name in ("x0", "xdot0"):
        if isinstance(grid.axis(name), np.ndarray):
            raise ValueError(f"{what} does not depend on the start: give {name} as a "
                             f"scalar (or leave it out), got a swept {name}")


CHUNK_SPLIT, CHUNK_LEAST = 16, 64     # default: up to 16 tasks of >= 64 points


def default_chunk(size: int) -> int:
    """Points per task of the scan when ``chunks=None``: the grid cut in up to 16
    (progress, resumable chunks, workers), at least 64 points a task (the numba
    threads share a task), at most 50,000."""
    return min(size, 50_000, max(CHUNK_LEAST, math.ceil(size / CHUNK_SPLIT)))


def _packed(out: np.ndarray, found: np.ndarray) -> np.ndarray:
    """One float64 row a point: the number of cycles, then the cycle rows."""
    return np.column_stack([found.astype(np.float64), out.reshape(out.shape[0], -1)])


def _unpacked(rows: np.ndarray):
    n = rows.shape[0]
    return rows[:, 1:].reshape(n, MAX_CYCLES, layout.NOBS), rows[:, 0].astype(np.int64)


def packed_chunk(grid: Grid, start: int, stop: int, o: np.ndarray,
                 parallel: bool = False) -> np.ndarray:
    """:func:`cycles_chunk`, packed as the working store keeps it."""
    return _packed(*cycles_chunk(grid, start, stop, o, parallel))


def scan(grid: Grid, o: np.ndarray, chunks=None, client=None, scheduler=None,
         path=None, progress=False):
    """``(out, found)`` of the cycle scan over every point of ``grid`` (flat C
    order), one task per chunk on the executor of ``client``/``scheduler``; with a
    ``path`` (checked by :func:`sweepcore.io.result_path`) the chunks go through
    its working store, so that an interrupted scan resumes (the store is left for
    :func:`sweepcore.resumable.write_result`, returned third)."""
    kind, target = execute.resolve(client, scheduler)
    size = grid.size
    chunk = default_chunk(size) if chunks is None else min(int(chunks), size)

    def task(bounds):
        return lambda i: (packed_chunk, (*grid.block(*bounds[i]), o))
    with execute.connected(kind, target) as (kind, target):
        if path is None:
            parts = resumable.compute_in_memory(size, chunk, kind, target, task, False)
            return (*_unpacked(np.concatenate(parts)), None)
        fixed = {"kind": "cycles", "grid": grid.fingerprint(), "options": o.tolist()}
        store = resumable.open_store(path, fixed, {"grid": repr(grid)}, size,
                                     1 + MAX_CYCLES * layout.NOBS,
                                     None if chunks is None else chunk, chunk)
        try:
            bounds = [store.bounds(i) for i in range(store.n_chunks)]
            resumable.compute_missing(store, kind, target, task(bounds), progress,
                                      "slip_cycles")
            rows = np.concatenate(resumable.stored_chunks(store))
        except BaseException:
            store.close()
            raise
        return (*_unpacked(rows), store)


# ------------------------------------------------------------------ labels
def cycle_variables(out: np.ndarray, found: np.ndarray, dims: tuple, shape: tuple,
                    o: np.ndarray) -> dict:
    """The ``cycle_*`` variables, ``n_cycles`` and ``cycle_search_status`` of the
    scan's output (``out`` (n, MAX_CYCLES, NOBS) in flat order of ``shape``), the
    ``cycle`` dimension cut to the most cycles any point has (at least 1)."""
    n = max(1, int(found.max()) if found.size else 1)
    block = out[:, :n].reshape(shape + (n, layout.NOBS))
    cdims = dims + ("cycle",)
    data = {"n_cycles": xr.Variable(dims, found.reshape(shape).astype(np.int64),
                                    labels.attrs(*variables.N_CYCLES))}
    for name, (col, *meta) in variables.CYCLE_OBSERVABLES.items():
        data[name] = xr.Variable(cdims, block[..., col], labels.attrs(*meta))
    data["cycle_stability"] = xr.Variable(
        cdims, stability(block),
        labels.flags(STABILITY_NAMES, variables.CYCLE_STABILITY))
    data["cycle_status"] = xr.Variable(
        cdims, block[..., layout.OB_STATUS].astype(np.int8),
        {**labels.flag_attrs(variables.STATUS),
         "long_name": "numerical status of the cycle (unused slots: unconverged)"})
    # the scan stops early when its step budget is spent: cycles beyond are missing
    spent = np.nanmax(out[:, :, layout.OB_NSTEPS], axis=1) >= o[layout.O_MAX_STEPS]
    search = np.where(spent, codes.STEP_BUDGET, codes.OK).astype(np.int8)
    data["cycle_search_status"] = xr.Variable(
        dims, search.reshape(shape),
        {**labels.flag_attrs(variables.STATUS),
         "long_name": "status of the cycle scan of the point",
         "comment": "step_budget_exceeded: the scan stopped before its last rung, "
                    "larger cycles may be missing"})
    data["cycle"] = xr.Variable("cycle", np.arange(n), {
        "units": "1", "long_name": "index of the slip cycle, innermost first"})
    return data


@checked_keywords(options=True)
def slip_cycles(grid: Grid, tol: float = 1e-8, method: str = "auto",
                chunks: int | None = None, client=None, scheduler=None, path=None,
                overwrite: bool = False, progress: bool | None = False,
                **options) -> xr.Dataset:
    """Every stop-free slip cycle of every point of ``grid``, stable or unstable.

    Parameters
    ----------
    grid : Grid
        Parameter sets (kN, cm, s); the start (x0, xdot0) plays no role and must
        not be swept.
    tol : float
        Accuracy of the cycles relative to the length scale L = r_y/k + |v|/omega
        (the residual of the fixed point, verified on returns computed at
        ``tol |1 - mu| / 2``, mu the multiplier).
    method : str
        "auto", "dopri5", "dop853", "rk4", or "exact" for a piecewise-linear law; not "gps"
        (its discrete map has its own cycles).
    chunks, client, scheduler
        As :func:`sweepcore.sweep`: one task per chunk of points (default: the
        grid cut in up to 16, at least 64 points a task).
    path : str or os.PathLike, optional
        Also write the result to this netCDF file, with the rules of
        :func:`sweepcore.sweep`'s ``path``: finished chunks are kept in a working
        store ``<path>.partial/``, so that rerunning the same call after an
        interruption computes only the chunks missing; the file appears,
        atomically, only when complete.
    overwrite : bool
        Replace ``path`` even if it is a read-only file.
    progress : bool, optional
        Show a progress bar of a scan with a ``path`` (None: on a terminal).
    **options
        max_steps, max_periods, dt, graze: see :func:`sweepcore.options.make_options`.

    Returns
    -------
    xarray.Dataset
        Over the grid's dimensions and ``cycle`` (innermost first): ``n_cycles``,
        ``cycle_amplitude``, ``cycle_mean``, ``cycle_x_max``, ``cycle_x_min``,
        ``cycle_xdot_max``, ``cycle_period``, ``cycle_floquet`` (> 1: unstable),
        ``cycle_stability`` and ``cycle_status`` (flags), ``cycle_search_status``;
        the analytic q, x_eq, v_star over the grid's coordinates (docs/variables.md).

    Raises
    ------
    SweepTooLarge
        Before any work, when the grid's cycles need more memory than is available
        (:func:`sweepcore.sizing.cycles_need`, the estimate in the message).
    """
    check_flag("overwrite", overwrite)
    check_flag("progress", progress, none=True)
    o = _options(grid, method, tol, options)
    _check_no_start(grid, "the cycle scan")
    execute.check_chunks(chunks)
    target = None if path is None else result_path(path, overwrite=overwrite)
    chunk = default_chunk(grid.size) if chunks is None else min(int(chunks), grid.size)
    refuse_unaffordable(cycles_need(grid.size, chunk))
    out, found, store = scan(grid, o, chunks, client, scheduler, target, progress)
    try:
        ds = _labelled(grid, out, found, o, tol, method)
        if store is not None:
            resumable.write_result(store, ds, target)
    finally:
        if store is not None:       # the lock (the store itself is gone if written)
            store.close()
    return ds


def _labelled(grid: Grid, out, found, o, tol, method) -> xr.Dataset:
    """The Dataset of :func:`slip_cycles` from the scan's output."""
    data = cycle_variables(out, found, grid.dims, grid.shape, o)
    coords = {k: v for k, v in grid.coords().items() if k not in ("x0", "xdot0")}
    ds = xr.Dataset({k: v for k, v in data.items() if k != "cycle"},
                    {**coords, "cycle": data["cycle"]})
    for name in ("q", "x_eq", "v_star"):
        da = labels.analytic(name, {k: ds[k] for k in coords}, grid.dims, grid.laws)
        ds[name] = xr.Variable(da.dims, da.data, da.attrs)
    ds.attrs.update({
        **labels.provenance(
            "Slip cycles of the stick-slip friction oscillator, stable and unstable",
            f"sweepcore.slip_cycles({grid!r}, tol={tol!r}, method={method!r})",
            "fixed points of the return map of the x maxima, bracketed by a scan of "
            "amplitudes and refined by Newton's method (numba kernels)",
            "Units kN, cm, s. cycle_floquet > 1: an unstable cycle (a basin "
            "boundary in the plane)."),
        "sweepcore_kind": "cycles", "method": method, "tol": float(tol)})
    return ds


# ------------------------------------------------------------------ polygon
def cycle_polygon(row: np.ndarray, cycle: np.ndarray, o: np.ndarray, points: int,
                  law=ANALYTIC):
    """One slip cycle in the (x, xdot) plane: ``(x, xdot, gap, ok)``.

    The motion is started on the cycle's section point (x_max at rest; x_min for
    v < 0) and sampled at ``points`` times equally spaced over one period (the
    driver stops exactly there); ``gap`` is the distance in the plane between the
    state after one period and the start (the closing error: the section point's
    error, amplified at most by the multiplier over one period, plus the
    integration error). ``ok`` is False where the run fails or meets a phase event
    (a stop-free cycle has none).

    Parameters
    ----------
    row : kernel parameter row of the point (layout M ... XD0).
    cycle : observables row of the cycle (from the scan).
    o : option row (make_options); resolved here for the point.
    law : the row's law (a law object, or the analytic family).
    points : samples of the polygon (the repeated end point not included).
    """
    p = np.array(row, dtype=np.float64)
    v = p[layout.V]
    p[layout.X0] = cycle[layout.OB_X_MAX] if v > 0.0 else cycle[layout.OB_X_MIN]
    p[layout.XD0] = 0.0
    period = cycle[layout.OB_PERIOD]
    if not (math.isfinite(period) and period > 0.0 and math.isfinite(p[layout.X0])):
        nan = np.full(points, np.nan)
        return nan, nan, math.nan, False
    oo, _status = compiled.options(p, law, None, o)
    t = np.linspace(0.0, period, points + 1)
    x = np.empty(points + 1)
    zd = np.empty(points + 1)
    mode = np.empty(points + 1, np.int64)
    ev = [np.empty(4), np.empty(4, np.int64), np.empty(4), np.empty(4)]
    n_ev, status, _n, _m = compiled.trajectory(p, law, None, oo, t, x, zd, mode, *ev,
                                               fresh_acc())
    xd = zd + v
    gap = float(np.hypot(x[-1] - x[0], xd[-1] - xd[0]))
    ok = status == codes.OK and n_ev == 0 and bool(np.isfinite(x).all())
    return x[:-1], xd[:-1], gap, ok


# ------------------------------------------------------------------ areas
def _clip(x, y, d):
    """Sutherland-Hodgman step: the part of the closed polygon (x, y) where the
    linear function with vertex values ``d`` is >= 0. Each edge i -> i+1 gives its
    crossing of d = 0 (if it crosses) and then its end vertex (if kept); a concave
    polygon may come out with zero-width bridges along the line, which add no area."""
    xn, yn, dn = np.roll(x, -1), np.roll(y, -1), np.roll(d, -1)
    keep_end = dn >= 0.0
    cross = (d >= 0.0) != keep_end
    t = d / np.where(cross, d - dn, 1.0)
    px = np.stack([x + t * (xn - x), xn], axis=1)
    py = np.stack([y + t * (yn - y), yn], axis=1)
    keep = np.stack([cross, keep_end], axis=1)
    return px[keep], py[keep]                 # C order: edge by edge


def clipped_area(x, y, box):
    """``(area, perimeter)`` of the closed polygon (x, y) inside the rectangle
    ``box = ((xl, xh), (yl, yh))``: clipped at the four sides in turn (a convex
    window), area by the shoelace formula."""
    (xl, xh), (yl, yh) = box
    x, y = np.asarray(x, float), np.asarray(y, float)
    for side in (lambda x, y: x - xl, lambda x, y: xh - x,
                 lambda x, y: y - yl, lambda x, y: yh - y):
        if x.size == 0:
            return 0.0, 0.0
        x, y = _clip(x, y, side(x, y))
    if x.size < 3:
        return 0.0, 0.0
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    return (0.5 * abs(float(np.sum(x * yn - xn * y))),
            float(np.sum(np.hypot(xn - x, yn - y))))


def inside(x, y, px, py):
    """Starts (px, py) inside the closed polygon (x, y) (even-odd rule)."""
    from matplotlib.path import Path
    return Path(np.column_stack([x, y])).contains_points(np.column_stack([px, py]))
