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

import datetime
import functools
import hashlib
import json
import logging
import math
import os
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
from .io import WorkingStore, chunk_shape, free_bytes, result_path, write_netcdf
from .options import make_options

CHUNK_MAX = 50_000        # default chunks hold 20 000 - 50 000 points,
CHUNK_MIN = 20_000        # or the whole grid when it is smaller,
CHUNK_SPLIT = 16          # and mid-size grids are cut in up to 16 (progress, workers)
LOCAL_SCHEDULERS = {"threads": "threads", "processes": "processes",
                    "synchronous": "synchronous", "sync": "synchronous",
                    "single-threaded": "synchronous"}
_log = logging.getLogger(__name__)
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
          overwrite: bool = False, **options) -> xr.Dataset:
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
        lasts more than half a second).
    scheduler : {"threads", "processes", "synchronous"} or str, optional
        Run one dask task per chunk with this local scheduler (or a scheduler
        address). Default (with no ``client``): numba threads in this process.
    overwrite : bool
        Replace ``path`` even if it is a read-only file.
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

    Raises
    ------
    SweepTooLarge
        Before any work, when the memory the call needs (:func:`estimate`) exceeds
        the memory available (or, with ``path``, the working store exceeds the
        free disk space); nothing is written.
    """
    o = _checked_arguments(grid, method, tol, chunks, options)
    target_path = None if path is None else result_path(path, overwrite=overwrite)
    kind, target = _executor(client, scheduler)
    call = _call_repr(grid, method, tol, chunks, client, path, scheduler, options)
    requested = None if chunks is None else min(int(chunks), grid.size)
    chunk = default_chunk(grid.size) if requested is None else requested
    est = estimate(grid, chunk, target_path)
    _log.info("sweep of %d points: output %s, memory about %s (available %s)",
              est["points"], _size(est["output_bytes"]), _size(est["memory_bytes"]),
              "unknown" if est["memory_available"] is None
              else _size(est["memory_available"]))
    _refuse_if_too_large(est)
    if target_path is None:
        cols = _compute(grid, o, kind, target, chunk, progress)
        return _dataset(grid, lambda col: cols[col].reshape(grid.shape), o, method,
                        call)
    with _working_store(target_path, grid, o, method, tol, options, requested) as store:
        _compute_to_store(grid, o, kind, target, store, progress)
        # checked again before use: a chunk damaged meanwhile is computed again
        _compute_to_store(grid, o, kind, target, store, False)
        ds = _dataset(grid, _stored_columns(grid, store), o, method, call)
        try:
            write_netcdf(ds, target_path)
        except OSError as err:
            raise OSError(err.errno, f"{err.strerror or err} The working store "
                          f"{store.directory} is kept: free space and rerun the same "
                          "call to finish.") from err
        store.remove()
    return xr.open_dataset(target_path, engine="netcdf4", chunks={},
                           decode_times=False, decode_timedelta=False)


def _progress_bar(size, initial, progress):
    show = sys.stderr.isatty() if progress is None else bool(progress)
    return tqdm(total=size, initial=initial, unit="pt", unit_scale=True, desc="sweep",
                disable=not show, delay=0.5 if progress is None else 0.0,
                file=sys.stderr)


def _compute(grid, o, kind, target, chunk, progress) -> np.ndarray:
    """Observables ``(layout.NOBS, grid.size)``, computed in memory."""
    size = grid.size
    bounds = [(a, min(a + chunk, size)) for a in range(0, size, chunk)]
    cols = np.empty((layout.NOBS, size))     # one contiguous row per observable
    with _progress_bar(size, 0, progress) as bar:
        def handle(i, result):
            a, b = bounds[i]
            cols[:, a:b] = result.T
            bar.update(b - a)

        _execute(kind, target, grid, o, bounds, range(len(bounds)), handle)
    return cols


def _compute_to_store(grid, o, kind, target, store, progress) -> None:
    """Compute the chunks the store lacks (or holds damaged), storing each as it
    finishes; nothing grid-sized is held in memory."""
    finished = set(store.verified())
    bounds = [store.bounds(i) for i in range(store.n_chunks)]
    todo = [i for i in range(len(bounds)) if i not in finished]
    initial = sum(bounds[i][1] - bounds[i][0] for i in finished)
    with _progress_bar(grid.size, initial, progress) as bar:
        def handle(i, result):
            store.write(i, result)
            bar.update(bounds[i][1] - bounds[i][0])

        if todo:
            _execute(kind, target, grid, o, bounds, todo, handle)


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


def _checked_arguments(grid, method, tol, chunks, options) -> np.ndarray:
    """Validate everything but the path before work starts; return the kernel
    option row."""
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
    return o


# ------------------------------------------------------------- size estimate
class SweepTooLarge(ValueError):
    """A sweep refused before any work: it would not fit in memory (or on disk)."""


def _analytic_sizes(grid: Grid) -> int:
    """Points of the analytic variables together (each over its own dimensions)."""
    total = 0
    for _func, args in _grid.ANALYTIC.values():
        swept = [a for a in args if a in grid.swept]
        if grid.mode == "points":
            total += grid.size if swept else 1
        else:
            total += math.prod(len(grid.axis(a)) for a in swept)
    return total


def estimate(grid: Grid, chunks: int | None = None, path=None) -> dict:
    """Size of a sweep, before any work: points, bytes of output, memory and disk.

    Parameters
    ----------
    grid : Grid
    chunks : int, optional
        Points per chunk (default :func:`default_chunk`).
    path : optional
        The result file: memory then follows the chunk (the result streams to disk).

    Returns
    -------
    dict
        ``points``; ``output_bytes`` (the Dataset's variables, uncompressed: an
        upper bound of the file); ``memory_bytes`` the call will need (the result
        in memory without ``path``; chunk, file block and, when ``v`` is swept, 7
        bytes per point for the Hopf boundary with ``path``); ``disk_bytes`` (with
        ``path``: the working store plus the output's upper bound, else 0);
        ``stored_bytes`` (chunks already in the working store of ``path``);
        ``memory_available`` and ``disk_free`` [bytes] (None when unknown).
    """
    n = grid.size
    chunk = default_chunk(n) if chunks is None else min(int(chunks), n)
    n_obs = len(variables.OBSERVABLES)
    output = n * (8 * n_obs + 3) + 8 * _analytic_sizes(grid)
    boundary = "v" in grid.dims and len(np.atleast_1d(grid.v)) >= 2
    if boundary:
        output += 8 * 4 * (n // len(grid.v))
    # one chunk: its kernel rows and results, the result's transpose, dask's copies
    working = 3 * chunk * 8 * (layout.NP + layout.NOBS)
    if path is None:
        memory = n * (8 * layout.NOBS + 4) + 8 * _analytic_sizes(grid) + working
        memory += 7 * n if boundary else 0
        disk = 0
    else:
        block = math.prod(chunk_shape(grid.shape, 8)) if grid.shape else 1
        # a block of one variable read, converted and compressed at a time
        memory = working + 3 * block * 8 + HDF5_CACHE + (7 * n if boundary else 0)
        disk = n * 8 * layout.NOBS + output
    return {"points": n, "chunk": chunk, "output_bytes": int(output),
            "memory_bytes": int(memory), "disk_bytes": int(disk),
            "stored_bytes": 0 if path is None else _stored_bytes(path),
            "memory_available": available_memory(),
            "disk_free": None if path is None else free_bytes(Path(path).parent)}


def _stored_bytes(path) -> int:
    """Bytes of chunk files already in the working store of ``path`` (a resume
    needs only the rest)."""
    try:
        with os.scandir(WorkingStore.location(path)) as entries:
            return sum(e.stat().st_size for e in entries if e.name.startswith("chunk-")
                       and e.is_file(follow_symlinks=False))
    except OSError:
        return 0


HDF5_CACHE = 64 * 2**20      # netCDF's chunk caches while the file is written


def available_memory() -> int | None:
    """Bytes this process may still allocate: ``MemAvailable`` of /proc/meminfo,
    lowered by an address-space limit (``RLIMIT_AS``) if one is set; None if
    neither is known."""
    limits = []
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    limits.append(int(line.split()[1]) * 1024)
    except (OSError, ValueError, IndexError):
        pass
    try:
        import resource
        soft, _hard = resource.getrlimit(resource.RLIMIT_AS)
        if soft != resource.RLIM_INFINITY:
            with open("/proc/self/status") as f:
                used = next(int(line.split()[1]) * 1024 for line in f
                            if line.startswith("VmSize:"))
            limits.append(max(0, soft - used))
    except (ImportError, OSError, ValueError, StopIteration):
        pass
    return min(limits) if limits else None


def _size(nbytes) -> str:
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if abs(nbytes) < 1024 or unit == "PiB":
            return f"{nbytes:.3g} {unit}" if unit != "B" else f"{int(nbytes)} B"
        nbytes /= 1024


def _refuse_if_too_large(est: dict) -> None:
    """Raise :class:`SweepTooLarge` (nothing written) if the call cannot fit."""
    text = (f"a sweep of {est['points']:,} points (output {_size(est['output_bytes'])}"
            f" uncompressed) needs about {_size(est['memory_bytes'])} of memory")
    avail = est["memory_available"]
    if avail is not None and est["memory_bytes"] > avail:
        if est["disk_free"] is None:
            raise SweepTooLarge(f"{text}, but {_size(avail)} is available; pass "
                                "path='map.nc' to stream the result to a file chunk by "
                                "chunk (memory then follows the chunk size), or sweep "
                                "a smaller grid")
        raise SweepTooLarge(f"{text} even streamed to a file (7 bytes per point for "
                            f"the Hopf boundary), but {_size(avail)} is available; "
                            "sweep a smaller grid or split it along v")
    free = est["disk_free"]
    store = est["disk_bytes"] - est["output_bytes"] - est["stored_bytes"]
    if free is not None and store > free:
        raise SweepTooLarge(f"{text} and {_size(store)} of disk for its working store "
                            f"(plus up to {_size(est['output_bytes'])} for the file), "
                            f"but {_size(free)} is free there; choose a path on a "
                            "larger disk or sweep a smaller grid")


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


def _dataset(grid: Grid, column, o: np.ndarray, method: str,
             call: str) -> xr.Dataset:
    """The labelled result; ``column(col)`` gives observable column ``col`` over the
    grid's shape (a numpy view, or a dask array read from the working store)."""
    dims = grid.dims
    data = {}
    for name, (col, *meta) in variables.OBSERVABLES.items():
        data[name] = xr.Variable(dims, column(col), _attrs(*meta))
    status = column(layout.OB_STATUS).astype(np.int8)
    regime = column(layout.OB_REGIME).astype(np.int8)
    data["regime"] = xr.Variable(dims, regime, _flag_attrs(variables.REGIME))
    data["status"] = xr.Variable(dims, status, _flag_attrs(variables.STATUS))
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

    for name, (func, args) in _grid.ANALYTIC.items():
        given = tuple(a for a in args if a in inputs)
        da = xr.apply_ufunc(functools.partial(func, given), *(inputs[a] for a in given),
                            keep_attrs=False, dask="parallelized",
                            output_dtypes=[np.float64])
        da = da.transpose(*(d for d in dims if d in da.dims))
        ds[name] = xr.Variable(da.dims, da.data, _attrs(*variables.ANALYTIC[name]))

    if "v" in ds.dims and ds.sizes["v"] >= 2:
        # lazily: the boundary needs the regime of the whole grid, 1 byte per point
        bd = hopf_boundary(ds[["regime"]].compute(scheduler="synchronous") if lazy
                           else ds)
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
