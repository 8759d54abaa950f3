"""Sweeps: a :class:`~sweepcore.grid.Grid` -> chunks -> the attractor kernel -> Dataset.

Execution
---------
The flat grid (C order of its dimensions) is cut into chunks of consecutive points;
each chunk's kernel rows are built from the 1-D axes when the chunk runs, so the
full grid is never materialised. Every point is computed independently (fastmath
off), so results are bit-identical whatever the chunk size, scheduler or worker
count.

* no ``client``, no ``scheduler`` (the fast path): chunks run one after the other in
  this process, each by ``attractor_rows_parallel`` (numba threads over the points;
  set ``NUMBA_NUM_THREADS`` before importing numba to change their number; a chunk
  smaller than the threads' lanes is shared out by Python threads instead).
* ``scheduler="threads" | "processes" | "synchronous"``: one dask task per chunk,
  each calling the serial ``attractor_rows`` (it releases the GIL), so dask alone
  provides the parallelism (never nested numba threads).

Either way the chunk goes through :func:`sweepcore.execute.attractors`, the one call
of the attractor kernel that :func:`sweepcore.attractor`, the boundary searches, the
diagrams and the basins make too: the kernel, then the scale rule
(:func:`sweepcore.law.flag_unresolvable`).
* ``client=distributed.Client`` or a scheduler address such as
  ``"tcp://10.0.0.1:8786"`` (also accepted as ``scheduler=``): one task per chunk
  submitted to the cluster, results gathered with ``as_completed``.

The executors are :mod:`sweepcore.execute`'s, shared with the boundary searches;
the size estimate and the refusal rules are :mod:`sweepcore.sizing`'s.

A cluster on several machines::

    dask scheduler                                   # prints tcp://HOST:8786
    NUMBA_NUM_THREADS=1 dask worker tcp://HOST:8786 --nworkers 8 --nthreads 1
    # then: sweep(grid, client="tcp://HOST:8786", path="map.nc")

The workers need sweepcore importable. ``NUMBA_NUM_THREADS=1`` keeps numba from
starting a thread pool per worker process; for a ``LocalCluster`` pass
``env={"NUMBA_NUM_THREADS": "1"}`` (the nanny does not set it by itself; the
``pre-spawn-environ`` config key also writes it into the parent process, whose next
numba compile then fails). The first task
on each worker process compiles the kernel, or loads it from numba's cache.

Size, files and resumable runs
------------------------------
Before any work, :func:`estimate` gives the point count, the bytes of the output
and the memory the call needs; a call that cannot fit in the memory available
(``MemAvailable``, or an address-space limit) is refused with that estimate
(:class:`SweepTooLarge`), leaving nothing behind.

Without ``path`` the result is built in memory (13 float64 columns per point and
the Dataset's variables). With ``path`` memory follows the chunk: each finished
chunk is stored, with its SHA-256 and grid range, in ``<path>.partial/``
(:class:`sweepcore.io.WorkingStore`); at the end the chunks are checked again and
the netCDF file is filled from them block by block (one HDF5 chunk of one variable
at a time) under a temporary name, renamed over ``path``, and returned opened
lazily (dask-backed); the store is then removed. Running the same call again after
an interruption checks the stored chunks and computes only those missing or
damaged. ``python benchmarks/memory.py`` measures the peak memory of streamed
sweeps of 1e6 and 1e7 points and the time of a refusal.
"""
from __future__ import annotations

import logging
import math
import uuid

import numpy as np
import xarray as xr

from . import execute, forced, labels, resumable, variables
from ._kernels import codes, layout
from .boundary import BOUNDARY_VARIABLES, hopf_boundary, reversal_cycles
from .grid import Grid, checked_grid
from .io import WorkingStore, check_flag, chunk_shape, result_path
from .options import check_method, checked_keywords, make_options
from .sizing import SweepTooLarge, default_chunk, estimate, refuse_if_too_large, size_text
from .timing import (MAX_SECONDS, check_max_seconds, left_to_compute, refuse_if_too_long,
                     time_estimate, time_text)

# estimate and SweepTooLarge live in sizing; sweepcore.sweep.estimate is documented
__all__ = ["sweep", "estimate", "SweepTooLarge", "run_chunk", "run_chunk_parallel"]
_log = logging.getLogger(__name__)


# ----------------------------------------------------------------- one chunk
def run_chunk(grid: Grid, start: int, stop: int, o: np.ndarray,
              parallel: bool = False) -> np.ndarray:
    """Observables ``(stop - start, layout.NOBS)`` of flat points [start, stop).

    Serial kernels (they release the GIL): the task that dask schedulers run;
    ``parallel`` (the direct path) uses numba's threads over the points.
    """
    if parallel:
        return run_chunk_parallel(grid, start, stop, o)
    return _observables(grid, start, stop, o, False)


def run_chunk_parallel(grid: Grid, start: int, stop: int, o: np.ndarray) -> np.ndarray:
    """As :func:`run_chunk`, with threads over the points (the no-dask path)."""
    return _observables(grid, start, stop, o, True)


def _observables(grid: Grid, start: int, stop: int, o: np.ndarray,
                 parallel: bool) -> np.ndarray:
    """The kernel and the scale rule on the chunk's rows: the one call that
    :func:`sweepcore.attractor` and the boundary searches make too
    (:func:`sweepcore.execute.attractors`)."""
    out = np.empty((stop - start, width(grid)))
    if grid.forced:
        forced.responses(grid.rows(start, stop), grid.laws, grid.loads, o, out, parallel)
    else:
        execute.attractors(grid.rows(start, stop), grid.laws, o, out, parallel)
    return out


def width(grid: Grid) -> int:
    """Columns of a point's result: the attractor's, or a forced response's."""
    return layout.NFOB if grid.forced else layout.NOBS


# -------------------------------------------------------------------- sweep
@checked_keywords(options=True)
def sweep(grid: Grid, method: str = "auto", tol: float = 1e-8, chunks: int | None = None,
          client=None, path=None, progress: bool | None = None, scheduler=None,
          overwrite: bool = False, max_seconds: float | None = MAX_SECONDS,
          **options) -> xr.Dataset:
    """The attractor of every point of ``grid``, as one labelled Dataset.

    Parameters
    ----------
    grid : Grid
        Validated parameter sets (kN, cm, s).
    method : str
        "auto" or a stepper of ``sweepcore.options.METHODS`` (the method table of
        ``sweepcore._kernels.codes``); "auto" is exact where alpha2 = 0, else dopri5
        at ``tol``. "exact" needs alpha2 = 0 at every point.
    tol : float
        Integration and convergence tolerance (see :func:`sweepcore.attractor`).
    chunks : int, optional
        Points per chunk (task). Default :func:`default_chunk` (2e4 - 5e4 points,
        or the whole grid if smaller). Memory of the computation grows with the
        chunk, not with the grid. Results do not depend on it.
    client : distributed.Client or str, optional
        Run one task per chunk on this cluster (or on the scheduler at this address).
    path : str or os.PathLike, optional
        Write the result to this netCDF4 file and return it opened lazily
        (dask-backed): memory then follows the chunk, not the grid. Finished chunks
        are kept, each with its SHA-256 and grid range, in a working store
        ``<path>.partial/`` (:class:`sweepcore.io.WorkingStore`), from which the
        file is filled block by block at the end, under a temporary name beside
        ``path`` renamed over it once complete. Rerunning the same call after an
        interruption resumes: stored chunks are checked, a damaged one is computed
        again (with a warning naming it). Another call on the same path with
        different arguments raises, naming the store; so does one started while
        another sweep on the same path is running (:class:`sweepcore.io.StoreBusy`).
        Rules, checked before any work (:func:`sweepcore.io.result_path`): an
        existing regular file is replaced atomically; a directory, symbolic link,
        FIFO, device or socket is refused; a read-only file is refused unless
        ``overwrite=True``; a name too long to take the ``.partial`` suffix gets a
        short hashed store name beside it. A write error (disk full) names the
        file, the bytes needed and the space free, and keeps the store resumable.
    progress : bool, optional
        Show a tqdm bar; default: only when stderr is a terminal (and the sweep
        lasts more than half a second). True where stderr is not a terminal (a log
        file): a plain line every 10 s or every tenth of the points.
    scheduler : {"threads", "processes", "synchronous"} or str, optional
        Run one dask task per chunk with this local scheduler (or a scheduler
        address). Default (with no ``client``): numba threads in this process.
    overwrite : bool
        Replace ``path`` even if it is a read-only file.
    max_seconds : float or None
        Refuse the sweep (:class:`sweepcore.timing.SweepTooLong`, before any work)
        when it would take longer on this machine [s]: the time is measured on a
        sample of the grid's own points (:func:`sweepcore.timing.time_estimate`,
        what :func:`estimate` returns as ``seconds``). Default one hour; None: no
        limit (and no sample run). Not applied with a distributed ``client``.
    **options
        dt, max_steps, max_periods, gps_a, graze: see
        :func:`sweepcore.options.make_options`.

    Returns
    -------
    xarray.Dataset
        Dimensions: the swept axes of ``grid`` (or ``point``), with ``units`` and
        ``long_name``; fixed parameters are 0-d coordinates. Variables: every
        observable of :data:`sweepcore.variables.OBSERVABLES` (float64; ``n_steps``
        int64), ``regime``
        and ``status`` (int8 flag variables), ``converged`` (int8, 1 where status is
        ok), the analytic ``q``, ``v_star``, ``x_eq``, ``omega`` over the dimensions
        they depend on, and, when ``v`` is swept with >= 2 values, the measured
        Hopf boundary of :func:`sweepcore.boundary.hopf_boundary`. CF-1.11
        attributes record the call, the version and the resolved options.

    Raises
    ------
    SweepTooLarge
        Before any work, when the memory the call needs (:func:`estimate`) exceeds
        the memory available (or, with ``path``, the working store exceeds the
        free disk space); nothing is written.
    """
    o = _checked_arguments(grid, method, tol, chunks, options, overwrite, progress)
    check_max_seconds(max_seconds)
    target_path = None if path is None else result_path(path, overwrite=overwrite)
    kind, target = execute.resolve(client, scheduler)
    call = _call_repr(grid, method, tol, chunks, client, path, scheduler, options)
    requested = None if chunks is None else min(int(chunks), grid.size)
    chunk = default_chunk(grid.size) if requested is None else requested
    est = estimate(grid, chunk, target_path, time=False)
    _log.info("sweep of %d points: output %s, memory about %s (available %s)",
              est["points"], size_text(est["output_bytes"]),
              size_text(est["memory_bytes"]), "unknown" if est["memory_available"] is None
              else size_text(est["memory_available"]))
    refuse_if_too_large(est)
    if max_seconds is not None and kind != "distributed":
        timing = time_estimate(grid, o, left_to_compute(grid, target_path))
        _log.info("sweep of %d points: %s", grid.size, time_text(timing))
        refuse_if_too_long(f"a sweep of {grid.size:,} points", timing, max_seconds)
    with execute.connected(kind, target) as (kind, target):
        if target_path is None:
            cols = _compute(grid, o, kind, target, chunk, progress)
            return _dataset(grid, lambda col: cols[col].reshape(grid.shape), o,
                            method, call)
        _streamed(grid, o, kind, target, progress, target_path, method, tol, options,
                  requested, call)
    return xr.open_dataset(target_path, engine="netcdf4", chunks={},
                           decode_times=False, decode_timedelta=False)


def _streamed(grid, o, kind, target, progress, target_path, method, tol, options,
              requested, call) -> None:
    """The sweep with a path: chunks into the working store, then the file."""
    with _working_store(target_path, grid, o, method, tol, options, requested) as store:
        bounds = [store.bounds(i) for i in range(store.n_chunks)]
        task = _chunk_task(grid, o, bounds)
        resumable.compute_missing(store, kind, target, task, progress)
        # checked again before use: a chunk damaged meanwhile is computed again
        resumable.compute_missing(store, kind, target, task, False)
        ds = _dataset(grid, _stored_columns(grid, store), o, method, call)
        resumable.write_result(store, ds, target_path)


def _chunk_task(grid, o, bounds):
    """``task(i)`` of :func:`sweepcore.execute.run`: chunk ``i`` with a grid block
    small enough to ship to a worker."""
    return lambda i: (run_chunk, (*grid.block(*bounds[i]), o))


def _compute(grid, o, kind, target, chunk, progress) -> np.ndarray:
    """Observables ``(layout.NOBS, grid.size)``, computed in memory."""
    cols = np.empty((width(grid), grid.size))     # one contiguous row per observable

    def handle(a, b, result):
        cols[:, a:b] = result.T

    resumable.compute_in_memory(grid.size, chunk, kind, target,
                                lambda bounds: _chunk_task(grid, o, bounds), progress,
                                handle=handle)
    return cols


def _stored_columns(grid: Grid, store):
    """``col -> dask array`` of the grid's shape, read from the store block by block.

    The blocks are the HDF5 chunks of a float64 variable (:func:`io.chunk_shape`:
    leading dimensions cut, trailing ones whole), so each covers a contiguous range
    of flat indices; each task reads one column of one block from the chunk files
    it overlaps, so no task holds more than a block of one variable.
    """
    import dask
    import dask.array as dsa

    shape = grid.shape
    block = chunk_shape(shape, 8) if shape else ()
    counts = [math.ceil(n / b) for n, b in zip(shape, block)]
    token = uuid.uuid4().hex
    ranges = {}
    for index in np.ndindex(*counts):
        lo = [i * b for i, b in zip(index, block)]
        extent = tuple(min(b, n - s) for b, n, s in zip(block, shape, lo))
        start = int(np.ravel_multi_index(lo, shape)) if shape else 0
        ranges[index] = (start, start + math.prod(extent), extent)

    def nested(prefix, col):
        if len(prefix) == len(counts):
            start, stop, extent = ranges[prefix]
            key = f"sweepcore-column-{col}-{start}-{token}"
            return dsa.from_delayed(dask.delayed(_read_column)(
                store, col, start, stop, extent, dask_key_name=key),
                shape=extent, dtype=np.float64)
        return [nested(prefix + (i,), col) for i in range(counts[len(prefix)])]

    def columns(col):
        return nested((), col) if not shape else dsa.block(nested((), col))
    return columns


def _read_column(store, col: int, start: int, stop: int, extent) -> np.ndarray:
    """Stored observable ``col`` of flat points [start, stop), shaped ``extent``."""
    parts = []
    for i in range(start // store.chunk, (stop - 1) // store.chunk + 1):
        a, b = store.bounds(i)
        parts.append(store.column(i, col, max(start, a) - a, min(stop, b) - a))
    out = parts[0] if len(parts) == 1 else np.concatenate(parts)
    return out.reshape(extent)


def _checked_arguments(grid, method, tol, chunks, options, overwrite,
                       progress) -> np.ndarray:
    """Validate everything but the path before work starts; return the kernel
    option row."""
    checked_grid(grid)
    # a string would count as true: overwrite="no" would replace a read-only file
    check_flag("overwrite", overwrite)
    check_flag("progress", progress, none=True)
    o = make_options(method, tol=tol, **options)
    if grid.forced:
        forced.check_method(method)
    else:
        check_method(method, grid)
    execute.check_chunks(chunks, " (points per chunk)")
    return o


def _working_store(path, grid, o, method, tol, options, chunk) -> WorkingStore:
    """The resumable store of ``path``, keyed by a hash of what fixes the results."""
    readable = {"grid": repr(grid), "method": method, "tol": tol, **options}
    fixed = {"grid": grid.fingerprint(), "options": o.tolist()}
    return resumable.open_store(path, fixed, readable, grid.size, width(grid), chunk,
                                default_chunk(grid.size))


# ------------------------------------------------------------------ labels
def _call_repr(grid, method, tol, chunks, client, path, scheduler, options) -> str:
    args = [repr(grid), f"method={method!r}", f"tol={tol!r}"]
    if chunks is not None:
        args.append(f"chunks={chunks!r}")
    for name, val in (("path", path), ("scheduler", scheduler), ("client", client)):
        if val is not None:
            args.append(f"{name}={str(val)!r}")
    args += [f"{k}={v!r}" for k, v in options.items()]
    return f"sweepcore.sweep({', '.join(args)})"


def _option_attrs(o: np.ndarray) -> dict:
    """The option row as the kernel saw it, with per-point defaults spelled out."""
    dt = o[layout.O_DT]
    gps_a = o[layout.O_GPS_A]
    return {
        "max_steps": int(o[layout.O_MAX_STEPS]),
        "max_periods": float(o[layout.O_MAX_TIME]),
        "dt": float(dt) if dt > 0 else "per point: 2 pi / omega / 50 s",
        "gps_a": (float(gps_a) if np.isfinite(gps_a)
                  else "per point: r_y/k + |v|/omega cm"),
        "graze": float(o[layout.O_GRAZE]),
    }


def _dataset(grid: Grid, column, o: np.ndarray, method: str,
             call: str) -> xr.Dataset:
    """The labelled result; ``column(col)`` gives observable column ``col`` over the
    grid's shape (a numpy view, or a dask array read from the working store)."""
    dims = grid.dims
    data = {}
    table = variables.FORCED_OBSERVABLES if grid.forced else variables.OBSERVABLES
    for name, (col, *meta) in table.items():
        values = column(col)
        if name in variables.INTEGER:
            fill = variables.INTEGER[name]
            if fill is not None:            # where no attractor was measured
                values = np.where(np.isfinite(values), values, fill)
            values = values.astype(np.int64)
        data[name] = xr.Variable(dims, values, labels.attrs(*meta))
    status = column(layout.OB_STATUS).astype(np.int8)
    regime = column(layout.OB_REGIME).astype(np.int8)
    data["regime"] = xr.Variable(dims, regime, labels.flag_attrs(variables.REGIME))
    data["status"] = xr.Variable(dims, status, labels.flag_attrs(variables.STATUS))
    data["converged"] = xr.Variable(
        dims, (status == codes.OK).astype(np.int8),
        {"units": "1", "long_name": "attractor recognised (status ok)",
         "flag_values": np.array([0, 1], dtype=np.int8),
         "flag_meanings": "not_converged converged"})
    ds = xr.Dataset(data, grid.coords())
    lazy = not isinstance(status, np.ndarray)
    inputs = {a: ds[a] for a in grid.coords()}
    if lazy and grid.shape:
        # analytic variables in blocks too: each coordinate cut like the data
        import dask.array as dsa
        block = dict(zip(dims, chunk_shape(grid.shape, 8)))
        inputs = {a: xr.DataArray(dsa.from_array(c.values, chunks=block[c.dims[0]]),
                                  dims=c.dims) if c.ndim else c.variable
                  for a, c in inputs.items()}
    for name in variables.ANALYTIC:
        da = labels.analytic(name, inputs, dims, grid.laws)   # a Variable where inputs are
        ds[name] = xr.Variable(da.dims, da.data, da.attrs)

    if "v" in ds.dims and ds.sizes["v"] >= 2 and not grid.forced:
        # lazily: the boundary needs the regime of the whole grid, 1 byte per point
        # (and which slip cycles overshoot the belt, 1 byte more)
        src = ds[["regime", "v_star"]].assign(reversal=reversal_cycles(ds)).compute(
            scheduler="synchronous") if lazy else ds
        bd = hopf_boundary(src)
        ds = ds.assign({n: bd[n].variable for n in BOUNDARY_VARIABLES})

    ds.attrs.update({
        **labels.provenance(
            "Attractors of the stick-slip friction oscillator over a parameter grid",
            call, "hybrid stick/slide driver with on-line attractor search (numba "
            "kernels)", "Units kN, cm, s (mass kN s2 cm-1). Each point starts at "
            "(x0, xdot0) and is run until its attractor is recognised; see status and "
            "converged."),
        "method": method,
        "tol": float(o[layout.O_RTOL]),
        **_option_attrs(o),
    })
    if grid.xdot0 is None:
        ds.attrs["initial_velocity"] = "xdot0 = v: every point starts stuck on the belt"
    law_attrs, law_variables = labels.law_labels(grid.laws)
    beyond = labels.beyond_table(ds, grid.laws)
    if beyond is not None:
        law_variables["beyond_table"] = beyond
    ds.attrs.update(law_attrs)
    ds = ds.assign(law_variables)
    if grid.forced:
        load_attrs, load_variables = labels.load_labels(grid.loads,
                                                        isinstance(grid.load, tuple))
        ds.attrs.update(load_attrs)
        ds = ds.assign(load_variables)
    labels.mark_spacing(ds)
    # the belt speed last: xarray's default 2-D plot puts the last dimension on x
    return ds.transpose(..., "v") if "v" in ds.dims else ds
