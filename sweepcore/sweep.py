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
  set ``NUMBA_NUM_THREADS`` before importing numba to change their number).
* ``scheduler="threads" | "processes" | "synchronous"``: one dask task per chunk,
  each calling the serial ``attractor_rows`` (it releases the GIL), so dask alone
  provides the parallelism (never nested numba threads).
* ``client=distributed.Client`` or a scheduler address such as
  ``"tcp://10.0.0.1:8786"`` (also accepted as ``scheduler=``): one task per chunk
  submitted to the cluster, results gathered with ``as_completed``.

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

Resumable runs
--------------
With ``path``, each finished chunk is stored in ``<path>.partial/``
(:class:`sweepcore.io.WorkingStore`); the netCDF file is written once at the end
(atomically) and the store removed. Running the same call again after an
interruption computes only the chunks not yet stored.
"""
from __future__ import annotations

import datetime
import functools
import hashlib
import json
import math
import sys
import uuid
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import numba
import numpy as np
import xarray as xr
from tqdm.auto import tqdm

from . import grid as _grid
from . import variables
from ._kernels import codes, layout
from ._kernels.attractor import attractor_rows, attractor_rows_parallel
from .boundary import BOUNDARY_VARIABLES, hopf_boundary
from .grid import Grid
from .io import WorkingStore, write_netcdf
from .options import make_options

CHUNK_MAX = 50_000        # default chunks hold 20 000 - 50 000 points,
CHUNK_MIN = 20_000        # or the whole grid when it is smaller,
CHUNK_SPLIT = 16          # and mid-size grids are cut in up to 16 (progress, workers)
LOCAL_SCHEDULERS = {"threads": "threads", "processes": "processes",
                    "synchronous": "synchronous", "sync": "synchronous",
                    "single-threaded": "synchronous"}
REFERENCE = ('C.-S. Liu, "Coulomb friction applied to analyze the cutting vibration '
             'of tool on workpiece"')


def _version() -> str:
    try:
        return version("sweepcore")
    except PackageNotFoundError:   # source tree without install
        return "0.1.0"


def default_chunk(size: int) -> int:
    """Points per chunk when ``chunks=None``: 2e4 - 5e4, or the whole grid."""
    n = max(math.ceil(size / CHUNK_MAX), min(CHUNK_SPLIT, math.ceil(size / CHUNK_MIN)))
    return math.ceil(size / n)


# ----------------------------------------------------------------- one chunk
def _observables(kernel, grid: Grid, start: int, stop: int, o: np.ndarray) -> np.ndarray:
    out = np.empty((stop - start, layout.NOBS))
    kernel(grid.rows(start, stop), o, out)
    return out


def run_chunk(grid: Grid, start: int, stop: int, o: np.ndarray) -> np.ndarray:
    """Observables ``(stop - start, layout.NOBS)`` of flat points [start, stop).

    Serial kernel (releases the GIL): the task that dask schedulers run.
    """
    return _observables(attractor_rows, grid, start, stop, o)


def run_chunk_parallel(grid: Grid, start: int, stop: int, o: np.ndarray) -> np.ndarray:
    """As :func:`run_chunk`, with numba threads over the points (no-dask path)."""
    return _observables(attractor_rows_parallel, grid, start, stop, o)


# ----------------------------------------------------------------- executors
def _run_direct(grid, o, bounds, todo, handle):
    for i in todo:
        handle(i, run_chunk_parallel(grid, *bounds[i], o))


def _run_dask_local(scheduler, grid, o, bounds, todo, handle):
    """One dask task per chunk; results are handled as they finish (posttask).

    dask returns all results at the end as well, so this path holds the output
    twice at its peak; the direct path and distributed do not.
    """
    import dask
    from dask.callbacks import Callback

    token = uuid.uuid4().hex
    keys = {}
    tasks = []
    for i in todo:
        key = f"sweepcore-chunk-{i}-{token}"
        keys[key] = i
        block, a, b = grid.block(*bounds[i])
        block = dask.delayed(block, name=f"sweepcore-grid-{i}-{token}", traverse=False)
        tasks.append(dask.delayed(run_chunk, pure=True)(block, a, b, o,
                                                         dask_key_name=key))

    def posttask(key, result, dsk, state, worker_id):
        if key in keys:
            handle(keys[key], result)

    with Callback(posttask=posttask):
        dask.compute(*tasks, scheduler=scheduler)


def _run_distributed(client, grid, o, bounds, todo, handle):
    """One future per chunk, each carrying its own (small) grid block: data
    scattered to a worker would be lost with it, a task's arguments are not."""
    from distributed import as_completed

    token = uuid.uuid4().hex
    futures = {client.submit(run_chunk, *grid.block(*bounds[i]), o, pure=False,
                             key=f"sweepcore-chunk-{i}-{token}"): i for i in todo}
    pending = set(futures)
    try:
        for fut in as_completed(futures, loop=client.loop):
            handle(futures[fut], fut.result())
            pending.discard(fut)
            fut.release()
    finally:
        if pending:
            client.cancel(list(pending))


def _executor(client, scheduler):
    """("direct", None) | ("local", name) | ("distributed", Client or address)."""
    if client is not None and scheduler is not None:
        raise ValueError("give client or scheduler, not both")
    target = scheduler if client is None else client
    if target is None:
        return "direct", None
    if isinstance(target, str):
        if client is None and target in LOCAL_SCHEDULERS:
            return "local", LOCAL_SCHEDULERS[target]
        if ":" in target:
            return "distributed", target
        raise ValueError(f"scheduler must be one of {sorted(LOCAL_SCHEDULERS)} or a "
                         f"scheduler address 'tcp://host:port', got {target!r}")
    from distributed import Client
    if isinstance(target, Client):
        return "distributed", target
    raise TypeError("client must be a distributed.Client or a scheduler address, got "
                    f"{target!r} of type {type(target).__name__}")


def _execute(kind, target, grid, o, bounds, todo, handle):
    if kind == "direct":
        _run_direct(grid, o, bounds, todo, handle)
    elif kind == "local":
        _run_dask_local(target, grid, o, bounds, todo, handle)
    elif isinstance(target, str):
        from distributed import Client
        with Client(target, set_as_default=False) as client:
            _run_distributed(client, grid, o, bounds, todo, handle)
    else:
        _run_distributed(target, grid, o, bounds, todo, handle)


# -------------------------------------------------------------------- sweep
def sweep(grid: Grid, method: str = "auto", tol: float = 1e-8, chunks: int | None = None,
          client=None, path=None, progress: bool | None = None, scheduler=None,
          **options) -> xr.Dataset:
    """The attractor of every point of ``grid``, as one labelled Dataset.

    Parameters
    ----------
    grid : Grid
        Validated parameter sets (kN, cm, s).
    method : {"auto", "exact", "gps", "rk4", "dopri5"}
        Stepper; "auto" is exact where alpha2 = 0, else dopri5 at ``tol``.
        "exact" needs alpha2 = 0 at every point.
    tol : float
        Integration and convergence tolerance (see :func:`sweepcore.attractor`).
    chunks : int, optional
        Points per chunk (task). Default :func:`default_chunk` (2e4 - 5e4 points,
        or the whole grid if smaller). Memory of the computation grows with the
        chunk, not with the grid. Results do not depend on it.
    client : distributed.Client or str, optional
        Run one task per chunk on this cluster (or on the scheduler at this address).
    path : str or path-like, optional
        Write the result to this netCDF4 file (atomically, at the end) and keep
        finished chunks in ``<path>.partial/`` meanwhile; rerunning the same call
        after an interruption resumes from there. Another call on the same path
        with different arguments raises, naming the store; so does one started
        while another sweep on the same path is running
        (:class:`sweepcore.io.StoreBusy`).
    progress : bool, optional
        Show a tqdm bar; default: only when stderr is a terminal (and the sweep
        lasts more than half a second).
    scheduler : {"threads", "processes", "synchronous"} or str, optional
        Run one dask task per chunk with this local scheduler (or a scheduler
        address). Default (with no ``client``): numba threads in this process.
    **options
        dt, max_steps, max_periods, gps_a, graze: see
        :func:`sweepcore.options.make_options`.

    Returns
    -------
    xarray.Dataset
        Dimensions: the swept axes of ``grid`` (or ``point``), with ``units`` and
        ``long_name``; fixed parameters are 0-d coordinates. Variables: every
        observable of :data:`sweepcore.variables.OBSERVABLES` (float64), ``regime``
        and ``status`` (int8 flag variables), ``converged`` (int8, 1 where status is
        ok), the analytic ``q``, ``v_star``, ``x_eq``, ``omega`` over the dimensions
        they depend on, and, when ``v`` is swept with >= 2 values, the measured
        Hopf boundary of :func:`sweepcore.boundary.hopf_boundary`. CF-1.11
        attributes record the call, the version and the resolved options.
    """
    o = _checked_arguments(grid, method, tol, chunks, path, options)
    kind, target = _executor(client, scheduler)
    call = _call_repr(grid, method, tol, chunks, client, path, scheduler, options)
    requested = None if chunks is None else min(int(chunks), grid.size)
    if path is None:
        chunk = default_chunk(grid.size) if requested is None else requested
        cols = _compute(grid, o, kind, target, chunk, None, progress)
        return _dataset(grid, cols, o, method, call)
    with _working_store(path, grid, o, method, tol, options, requested) as store:
        cols = _compute(grid, o, kind, target, store.chunk, store, progress)
        ds = _dataset(grid, cols, o, method, call)
        write_netcdf(ds, path)
        store.remove()
    return ds


def _compute(grid, o, kind, target, chunk, store, progress) -> np.ndarray:
    """Observables ``(layout.NOBS, grid.size)``: stored chunks read back, the others
    computed (and stored as they finish when there is a store)."""
    size = grid.size
    bounds = [(a, min(a + chunk, size)) for a in range(0, size, chunk)]
    cols = np.empty((layout.NOBS, size))     # one contiguous row per observable
    finished = store.done(len(bounds)) if store is not None else []
    for i in finished:
        a, b = bounds[i]
        cols[:, a:b] = store.read(i, b - a).T
    todo = sorted(set(range(len(bounds))) - set(finished))

    show = sys.stderr.isatty() if progress is None else bool(progress)
    with tqdm(total=size, initial=sum(bounds[i][1] - bounds[i][0] for i in finished),
              unit="pt", unit_scale=True, desc="sweep", disable=not show,
              delay=0.5 if progress is None else 0.0, file=sys.stderr) as bar:
        def handle(i, result):
            a, b = bounds[i]
            cols[:, a:b] = result.T
            if store is not None:
                store.write(i, result)
            bar.update(b - a)

        if todo:
            _execute(kind, target, grid, o, bounds, todo, handle)
    return cols


def _checked_arguments(grid, method, tol, chunks, path, options) -> np.ndarray:
    """Validate everything before work starts; return the kernel option row."""
    if not isinstance(grid, Grid):
        raise TypeError(f"grid must be a sweepcore.Grid, got {type(grid).__name__}")
    o = make_options(method, tol=tol, **options)
    alpha2 = np.atleast_1d(grid.alpha2)
    if method == "exact" and (alpha2 != 0.0).any():
        raise ValueError("method='exact' needs alpha2 == 0 at every point; got "
                         f"alpha2={float(alpha2[alpha2 != 0.0][0])!r}")
    if chunks is not None and (isinstance(chunks, bool) or not isinstance(
            chunks, (int, np.integer)) or chunks < 1):
        raise ValueError(f"chunks must be an integer >= 1 (points per chunk), "
                         f"got {chunks!r}")
    if path is not None:
        target = Path(path)
        if str(path) == "" or target.is_dir():
            raise ValueError(f"path={str(path)!r} is a directory; give the name of "
                             "the result file (e.g. 'map.nc')")
        if not target.parent.is_dir():
            raise FileNotFoundError(f"path={str(path)!r}: directory {target.parent} "
                                    "does not exist")
    return o


@functools.lru_cache(maxsize=1)
def _kernel_digest() -> str:
    """SHA-256 of the kernels' source: a resume must not mix two kernel versions."""
    h = hashlib.sha256(numba.__version__.encode())
    for src in sorted(Path(layout.__file__).parent.glob("*.py")):
        h.update(src.name.encode() + src.read_bytes())
    return h.hexdigest()


def _working_store(path, grid, o, method, tol, options, chunk) -> WorkingStore:
    """The resumable store of ``path``, keyed by a hash of what fixes the results."""
    config = {"grid": grid.fingerprint(), "options": o.tolist(), "version": _version(),
              "kernels": _kernel_digest()}
    digest = hashlib.sha256(json.dumps(config, sort_keys=True).encode()).hexdigest()
    readable = {"grid": repr(grid), "method": method, "tol": tol, **options}
    return WorkingStore.open(path, digest, readable, grid.size, layout.NOBS, chunk,
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


def _flag_attrs(meta: dict) -> dict:
    return {**meta, "flag_values": np.array(meta["flag_values"], dtype=np.int8)}


def _attrs(units: str, long_name: str, comment: str) -> dict:
    attrs = {"units": units, "long_name": long_name}
    return {**attrs, "comment": comment} if comment else attrs


def _dataset(grid: Grid, cols: np.ndarray, o: np.ndarray, method: str,
             call: str) -> xr.Dataset:
    dims, shape = grid.dims, grid.shape
    data = {}
    for name, (col, *meta) in variables.OBSERVABLES.items():
        data[name] = xr.Variable(dims, cols[col].reshape(shape), _attrs(*meta))
    status = cols[layout.OB_STATUS].astype(np.int8).reshape(shape)
    regime = cols[layout.OB_REGIME].astype(np.int8).reshape(shape)
    data["regime"] = xr.Variable(dims, regime, _flag_attrs(variables.REGIME))
    data["status"] = xr.Variable(dims, status, _flag_attrs(variables.STATUS))
    data["converged"] = xr.Variable(
        dims, (status == codes.OK).astype(np.int8),
        {"units": "1", "long_name": "attractor recognised (status ok)",
         "flag_values": np.array([0, 1], dtype=np.int8),
         "flag_meanings": "not_converged converged"})
    ds = xr.Dataset(data, grid.coords())

    for name, (func, args) in _grid.ANALYTIC.items():
        da = xr.apply_ufunc(func, *(ds[a] for a in args), keep_attrs=False)
        da = da.transpose(*(d for d in dims if d in da.dims))
        ds[name] = xr.Variable(da.dims, da.data, _attrs(*variables.ANALYTIC[name]))

    if "v" in ds.dims and ds.sizes["v"] >= 2:
        bd = hopf_boundary(ds)
        ds = ds.assign({n: bd[n].variable for n in BOUNDARY_VARIABLES})

    now = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    ds.attrs.update({
        "Conventions": "CF-1.11",
        "title": "Attractors of the stick-slip friction oscillator over a parameter grid",
        "history": f"{now} sweepcore {_version()}: {call}",
        "source": f"sweepcore {_version()}: hybrid stick/slide driver with on-line "
                  "attractor search (numba kernels)",
        "references": REFERENCE,
        "comment": "Units kN, cm, s (mass kN s2 cm-1). Each point starts at "
                   "(x0, xdot0) and is run until its attractor is recognised; see "
                   "status and converged.",
        "method": method,
        "tol": float(o[layout.O_RTOL]),
        **_option_attrs(o),
    })
    if grid.xdot0 is None:
        ds.attrs["initial_velocity"] = "xdot0 = v: every point starts stuck on the belt"
    return ds
