"""The size of a sweep before any work: points, bytes of output, memory and disk,
the default chunk, and the rule that refuses a call that cannot fit.

:func:`estimate` is public (``sweepcore.estimate``); :func:`sweepcore.sweep` calls it
and :func:`refuse_if_too_large` before it computes anything, so a refused call leaves
nothing behind. ``python benchmarks/memory.py`` measures the peak memory of streamed
sweeps against these estimates.
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
from .grid import Grid, checked_grid
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
    """A sweep refused before any work: it would not fit in memory (or on disk)."""


def _analytic_sizes(grid: Grid) -> int:
    """Points of the analytic variables together (each over its own dimensions)."""
    total = 0
    for name in variables.ANALYTIC:
        swept = [a for a in law.DERIVED[name][1] if a in grid.swept]
        if grid.mode == "points":
            total += grid.size if swept else 1
        else:
            total += math.prod(len(grid.axis(a)) for a in swept)
    return total


@checked_keywords
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
        in memory without ``path``; chunk, file block and, when ``v`` is swept, 8
        bytes per point for the measured boundaries with ``path``: the regime and
        the reversal mask, and their work arrays); ``disk_bytes`` (with
        ``path``: the working store plus the output's upper bound, else 0);
        ``stored_bytes`` (chunks already in the working store of ``path``);
        ``memory_available`` and ``disk_free`` [bytes] (None when unknown);
        ``directory``, where the file and its store go (None without ``path``).

    Raises
    ------
    TypeError, ValueError
        As :func:`sweepcore.sweep` for the same ``grid``, ``chunks`` and ``path``.
    """
    checked_grid(grid)
    check_chunks(chunks, " (points per chunk)")        # sweep's own rule
    if path is not None:
        path = path_text(path)
    n = grid.size
    chunk = default_chunk(n) if chunks is None else min(int(chunks), n)
    n_obs = len(variables.OBSERVABLES)
    output = n * (8 * n_obs + 3) + 8 * _analytic_sizes(grid)
    boundary = "v" in grid.dims and len(np.atleast_1d(grid.v)) >= 2
    if boundary:
        output += 8 * len(BOUNDARY_VARIABLES) * (n // len(grid.v))
    # one chunk: its kernel rows and results, the result's transpose, dask's copies
    working = 3 * chunk * 8 * (layout.NP + layout.NOBS)
    if path is None:
        memory = n * (8 * layout.NOBS + 4) + 8 * _analytic_sizes(grid) + working
        memory += 8 * n if boundary else 0
        disk = 0
    else:
        block = math.prod(chunk_shape(grid.shape, 8)) if grid.shape else 1
        # a block of one variable read, converted and compressed at a time
        memory = working + 3 * block * 8 + HDF5_CACHE + (8 * n if boundary else 0)
        disk = n * 8 * layout.NOBS + output
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


def size_text(nbytes) -> str:
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
