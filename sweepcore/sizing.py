"""The size of a call before any work: points, bytes of output, memory and disk,
the default chunk, and the rule that refuses a call that cannot fit.

:func:`estimate` is public (``sweepcore.estimate``); :func:`sweepcore.sweep` calls it
and :func:`refuse_if_too_large` before it computes anything, so a refused call leaves
nothing behind. ``python benchmarks/memory.py`` measures the peak memory of streamed
sweeps against these estimates.

The other entry points size themselves by the same rule (:func:`refuse_unaffordable`):
basin stability (:func:`basin_need`: points, starts and checks a point), the cycle
scan (:func:`cycles_need`), the boundary searches (:func:`boundary_need`: points and
scan) and the diagrams (:func:`diagram_need`); a study's ``[basins]`` table is sized
with :func:`basin_need` before anything runs. Each is refused, before any work, when
the memory it needs exceeds the memory available, or when one of its arrays would
hold more elements than numpy can index, with the estimate in the message.
"""
from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from . import law
from . import variables
from ._kernels import layout
from .boundary import BOUNDARY_VARIABLES
from ._kernels.cycles import MAX_CYCLES
from .grid import MAX_SIZE, Grid, checked_grid
from .execute import check_chunks
from .io import WorkingStore, chunk_shape, free_bytes, path_text
from .options import checked_keywords

CHUNK_MAX = 50_000        # default chunks hold 20 000 - 50 000 points,
CHUNK_MIN = 20_000        # or the whole grid when it is smaller,
CHUNK_SPLIT = 16          # and mid-size grids are cut in up to 16 (progress, workers)


def default_chunk(size: int) -> int:
    """Points per chunk when ``chunks=None``: 2e4 - 5e4, or the whole grid."""
    n = max(math.ceil(size / CHUNK_MAX), min(CHUNK_SPLIT, math.ceil(size / CHUNK_MIN)))
    return math.ceil(size / n)


class SweepTooLarge(ValueError):
    """A call refused before any work: it would not fit in memory (or on disk), or
    an array of it would hold more elements than numpy can index."""


def _analytic_sizes(grid: Grid) -> int:
    """Points of the analytic variables together (each over its own dimensions)."""
    total = 0
    for name in variables.ANALYTIC:
        # each law of a law dimension has its own (law.DERIVED names the analytic
        # family's parameters only: 1,000 laws were counted as one)
        swept = [a for a in law.DERIVED[name][1] + ("law",) if a in grid.swept]
        if grid.mode == "points":
            total += grid.size if swept else 1
        else:
            total += math.prod(len(grid.axis(a)) for a in swept)
    return total


@checked_keywords(options=True)
def estimate(grid: Grid, chunks: int | None = None, path=None, method: str = "auto",
             tol: float = 1e-8, time: bool = True, **options) -> dict:
    """Size and time of a sweep, before the sweep: points, bytes of output, memory,
    disk, and the seconds it takes on this machine.

    Parameters
    ----------
    grid : Grid
    chunks : int, optional
        Points per chunk (default :func:`default_chunk`).
    path : optional
        The result file: memory then follows the chunk (the result streams to disk).
    method, tol, **options
        As :func:`sweepcore.sweep` (a point's cost depends on them).
    time : bool
        Time the sweep (:func:`sweepcore.timing.time_estimate`: 64 to 4096 of its
        points run, about a
        second; the kernels they need compile first if the cache lacks them,
        untimed). False: sizes only, nothing run.

    Returns
    -------
    dict
        ``points``; ``output_bytes`` (the Dataset's variables, uncompressed: an
        upper bound of the file); ``memory_bytes`` the call will need (the result
        in memory without ``path``; chunk, file block and, when ``v`` is swept, 8
        bytes per point for the measured boundaries with ``path``: the regime and
        the reversal mask, and their work arrays); ``disk_bytes`` (with
        ``path``: the working store plus the output's upper bound, else 0);
        ``stored_bytes`` (chunks already in the working store of ``path``);
        ``memory_available`` and ``disk_free`` [bytes] (None when unknown);
        ``directory``, where the file and its store go (None without ``path``);
        with ``time``: ``seconds`` [s] the kernels take on this machine's threads
        (what :func:`sweepcore.sweep` checks against ``max_seconds``),
        ``seconds_per_point``, ``timed_points``, ``timing_seconds`` (the estimate's
        own cost), ``lower_bound`` (a timed point was cut at ``timing.SAMPLE_STEPS``
        steps: the sweep may take longer) and ``threads``.

    Raises
    ------
    TypeError, ValueError
        As :func:`sweepcore.sweep` for the same ``grid``, ``chunks``, ``path``,
        ``method``, ``tol`` and options.
    """
    checked_grid(grid)
    check_chunks(chunks, " (points per chunk)")        # sweep's own rule
    if path is not None:
        path = path_text(path)
    sizes = _sizes(grid, chunks, path)
    if time is not True and time is not False:
        raise TypeError(f"time must be True or False, got {time!r}")
    if time:
        from .timing import time_estimate
        sizes.update(time_estimate(grid, options_row(grid, method, tol, options)))
    return sizes


def options_row(grid: Grid, method: str, tol: float, options: dict) -> np.ndarray:
    """The kernel option row of a sweep of ``grid`` (its method refused where the
    grid's points cannot use it), as :func:`sweepcore.sweep` validates it."""
    from . import forced
    from .options import check_method, make_options
    o = make_options(method, tol=tol, **options)
    if grid.forced:
        forced.check_method(method)
    else:
        check_method(method, grid)
    return o


def _sizes(grid: Grid, chunks, path) -> dict:
    """:func:`estimate`'s sizes (no time)."""
    n = grid.size
    chunk = default_chunk(n) if chunks is None else min(int(chunks), n)
    # a forced grid's points hold a forced response's columns and variables
    n_obs = len(variables.FORCED_OBSERVABLES if grid.forced else variables.OBSERVABLES)
    width = layout.NFOB if grid.forced else layout.NOBS
    output = n * (8 * n_obs + 3) + 8 * _analytic_sizes(grid)
    boundary = "v" in grid.dims and len(np.atleast_1d(grid.v)) >= 2 and not grid.forced
    if boundary:
        output += 8 * len(BOUNDARY_VARIABLES) * (n // len(grid.v))
    # one chunk: its kernel rows and results, the result's transpose, dask's copies
    working = 3 * chunk * 8 * (layout.NP + width)
    if path is None:
        memory = n * (8 * width + 4) + 8 * _analytic_sizes(grid) + working
        memory += 8 * n if boundary else 0
        disk = 0
    else:
        block = math.prod(chunk_shape(grid.shape, 8)) if grid.shape else 1
        # a block of one variable read, converted and compressed at a time
        memory = working + 3 * block * 8 + HDF5_CACHE + (8 * n if boundary else 0)
        disk = n * 8 * width + output
    return {"points": n, "chunk": chunk, "output_bytes": int(output),
            "memory_bytes": int(memory), "disk_bytes": int(disk),
            "stored_bytes": 0 if path is None else _stored_bytes(path),
            "memory_available": available_memory(),
            "disk_free": None if path is None else free_bytes(Path(path).parent),
            "directory": None if path is None else str(Path(path).parent)}


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


def _digits(n: int) -> int:
    return int(abs(n).bit_length() * math.log10(2))


def size_text(nbytes) -> str:
    if abs(nbytes) >= 2**1000:       # beyond float64 (an integer argument of 1e400)
        return f"about 1e{_digits(nbytes)} B"
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if abs(nbytes) < 1024 or unit == "PiB":
            return f"{nbytes:.3g} {unit}" if unit != "B" else f"{int(nbytes)} B"
        nbytes /= 1024


def refuse_if_too_large(est: dict) -> None:
    """Raise :class:`SweepTooLarge` (nothing written) if the call cannot fit."""
    output = size_text(est["output_bytes"])
    text = (f"a sweep of {est['points']:,} points (output {output} uncompressed) needs "
            f"about {size_text(est['memory_bytes'])} of memory")
    avail = est["memory_available"]
    if avail is not None and est["memory_bytes"] > avail:
        if est["disk_free"] is None:
            raise SweepTooLarge(f"{text}, but {size_text(avail)} is available; pass "
                                "path='map.nc' to stream the result to a file chunk by "
                                "chunk (memory then follows the chunk size), or sweep "
                                "a smaller grid")
        raise SweepTooLarge(f"{text} even streamed to a file (7 bytes per point for "
                            f"the Hopf boundary), but {size_text(avail)} is available; "
                            "sweep a smaller grid or split it along v")
    free = est["disk_free"]
    store = est["disk_bytes"] - est["output_bytes"] - est["stored_bytes"]
    if free is not None and store > free:
        raise SweepTooLarge(f"{text} and {size_text(store)} of disk for its working "
                            f"store (plus up to {output} for the file), but "
                            f"{size_text(free)} is free in {est['directory']} (the "
                            "directory of the path; 0 B: a full disk, or a file system "
                            "that holds no files, such as /proc); choose a path on a "
                            "larger disk or sweep a smaller grid")


# ------------------------------------------------------------ the other entry points
# bytes a grid point's answer holds in memory besides its arrays below (Python
# objects of one chunk's answers and the labelled Dataset's variables, measured
# for two attractors a point): an "about", as the sweep's estimate is
BASIN_POINT_BYTES = 2048
BOUNDARY_POINT_BYTES = 4096
ROW_BYTES = 8 * (layout.NP + layout.NOBS)      # one kernel row and its observables


def _number(n: int) -> str:
    """``1,000`` (a huge integer as its order of magnitude)."""
    return f"{n:,}" if n < 10**18 else f"about 1e{_digits(n)}"


def _count(n: int, what: str) -> str:
    return f"{_number(n)} {what}{'' if n == 1 else 's'}"


def basin_chunk_size(points: int, per_point: int, chunks=None) -> int:
    """Grid points per basin task: ``chunks``, else about 20 000 starts a task."""
    return min(points, chunks or max(1, 20000 // max(1, per_point)))


def basin_need(points: int, samples: int, checks: int, route: str,
               chunks: int | None = None) -> dict:
    """What :func:`sweepcore.basin_stability` needs: ``points`` grid points, each
    with ``samples`` starts (sampled route) or ``2 checks + 3`` runs and ``50
    checks`` candidate starts (exact route; "auto" may take either at any point),
    in tasks of ``chunk`` points (:func:`basin_chunk_size`)."""
    exact = route != "sampled"
    exact_runs = 2 * checks + 3
    runs = {"sampled": samples, "exact": exact_runs}.get(route,
                                                          max(samples, exact_runs))
    chunk = basin_chunk_size(points, samples if route != "exact" else checks, chunks)
    candidates = 50 * checks if exact else 0
    work = 3 * chunk * runs * ROW_BYTES + 16 * candidates + (
        chunk * MAX_CYCLES * layout.NOBS * 8 if exact else 0)
    result = points * (BASIN_POINT_BYTES + (MAX_CYCLES * layout.NOBS * 8 if exact
                                            else 0))
    what = (f"basin stability of {_count(points, 'point')} with samples="
            f"{_number(samples)} starts a point and checks={_number(checks)} (route "
            f"{route!r})")
    return {"what": what, "memory": result + work, "chunk": chunk,
            "elements": max(chunk * runs * layout.NP, 2 * candidates, 2 * samples,
                            points * layout.NOBS),
            "parts": f"the result {size_text(result)}, a task of "
                     f"{_count(chunk, 'point')} {size_text(work)}",
            "advice": "lower samples (or checks), or split the grid"}


def cycles_need(points: int, chunk: int) -> dict:
    """What :func:`sweepcore.slip_cycles` needs: the scan's rows of ``points`` grid
    points (held for the Dataset), twice, and one task of ``chunk`` points."""
    per_point = MAX_CYCLES * layout.NOBS * 8 + 8
    result = 2 * points * per_point
    work = 2 * chunk * (per_point + 8 * layout.NP)
    return {"what": f"the cycle scan of {_count(points, 'point')}",
            "memory": result + work, "elements": points * MAX_CYCLES * layout.NOBS,
            "parts": f"the result {size_text(result)}, a task of "
                     f"{_count(chunk, 'point')} {size_text(work)}",
            "advice": "split the grid"}


def boundary_need(points: int, scan: int, chunk: int) -> dict:
    """What :func:`sweepcore.locate_boundaries` (``points`` searches, one task of
    ``chunk``) or :func:`sweepcore.continue_boundary` needs: each search's coarse
    scan of ``scan`` attractors is one batch of kernel rows."""
    result = points * BOUNDARY_POINT_BYTES
    work = 2 * chunk * scan * ROW_BYTES + 8 * scan
    return {"what": f"boundary searches at {_count(points, 'point')} with scan="
                    f"{_number(scan)}", "memory": result + work,
            "elements": max(chunk * scan * layout.NP, points),
            "parts": f"the result {size_text(result)}, a task of "
                     f"{_count(chunk, 'search')} {size_text(work)}",
            "advice": "lower scan (32 brackets a boundary), pass chunks, or split the "
                      "grid"}


def diagram_need(values: int, branches: int) -> dict:
    """What :func:`sweepcore.bifurcation_diagram` needs along ``values`` points."""
    memory = 3 * branches * values * 8 * layout.NOBS + 8 * values * 16
    return {"what": f"a bifurcation diagram of {_count(values, 'value')} ("
                    f"{_count(branches, 'scan')})",
            "memory": memory, "elements": branches * values * layout.NOBS,
            "parts": "its branches", "advice": "follow fewer values"}


def strobe_need(values: int, periods: int, transient: int) -> dict:
    """What :func:`sweepcore.stroboscopic_diagram` needs: x and xdot of ``periods``
    samples at ``values`` values, and one simulation of ``transient + periods``
    samples at a time (its time, state, phase and the Dataset's seven variables)."""
    samples = transient + periods + 2
    result = 2 * 8 * values * periods
    work = 3 * 8 * 10 * samples
    return {"what": f"a stroboscopic diagram of {_count(values, 'value')} with "
                    f"periods={_number(periods)} (transient={_number(transient)})",
            "memory": result + work, "elements": max(values * periods, samples),
            "parts": f"the samples {size_text(result)}, a simulation of "
                     f"{_count(samples, 'sample')} {size_text(work)}",
            "advice": "keep fewer periods (each is a point of the diagram)"}


def too_large(need: dict) -> str | None:
    """Why the call ``need`` (of :func:`basin_need` and its siblings) cannot run, or
    None: an array beyond numpy's index, or more memory than is available."""
    if need["elements"] > MAX_SIZE:
        return (f"{need['what']} needs arrays of {_number(need['elements'])} elements "
                f"({need['parts']}), more than numpy can index ({MAX_SIZE:.3g}); "
                f"{need['advice']}")
    avail = available_memory()
    if avail is not None and need["memory"] > avail:
        return (f"{need['what']} needs about {size_text(need['memory'])} of memory "
                f"({need['parts']}), but {size_text(avail)} is available; "
                f"{need['advice']}")
    return None


def refuse_unaffordable(need: dict) -> None:
    """Raise :class:`SweepTooLarge` (nothing computed, nothing written) when
    :func:`too_large` says why the call cannot run."""
    why = too_large(need)
    if why is not None:
        raise SweepTooLarge(why)
