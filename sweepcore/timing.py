"""The time a call takes, before it runs: measured on a sample of the call's own
points, and the limit that refuses what would take longer (``max_seconds``, the
command line's ``--max-time``).

The time a call takes is measured, not modelled: a point's cost spans three decades
(a stick-slip point of the paper's map ~0.01 ms, a slip cycle next to v* ~10x that,
a forced point 0.2-0.6 ms, one far below its natural frequency 0.2 s and more), so
a per-machine calibration of one point says little about a grid. The call's own
points are timed instead: a deterministic stratified sample (one point drawn in
each of ``count`` equal ranges of the flat index, seed 0) run by the kernels the
call runs, on every thread, larger while it took less than TIMING_SECONDS (a shared
machine's noise). The kernels the sample needs are first compiled or loaded by a
run of one step a point (not timed: compile time is not a point's cost), and each
timed point may take at most SAMPLE_STEPS steps, so that the estimate costs about a
second at most; a point cut there makes the estimate a lower bound (said so).
"""
from __future__ import annotations

import math
import time

import numpy as np

from ._kernels import layout
from .grid import Grid
from .sizing import SweepTooLarge, _stored_bytes

SAMPLE_POINTS = 64          # points timed first; four times more while they took
TIMING_SECONDS = 0.25       # less than this, up to SAMPLE_MAX points
SAMPLE_MAX = 4096
SAMPLE_SHARE = 16           # and at most one in 16 of the call's points
SAMPLE_STEPS = 200_000      # stepper calls a timed point may take (0.06 s of dop853)
MAX_SECONDS = 3600.0        # the default limit of sweep (max_seconds) and the CLI


class SweepTooLong(SweepTooLarge):
    """A call refused before any work: its estimated time exceeds the limit the
    caller allowed (``max_seconds``, ``--max-time``)."""


def duration_text(seconds: float) -> str:
    """``42 s``, ``12 min``, ``3.1 h``, ``2.5 days``."""
    for unit, size, above in (("days", 86400.0, 172800.0), ("h", 3600.0, 7200.0),
                              ("min", 60.0, 100.0)):
        if seconds >= above:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds:.2g} s" if seconds < 10 else f"{seconds:.0f} s"


def check_max_seconds(max_seconds) -> float | None:
    """``max_seconds`` as a float (None: no limit), or a ValueError naming it."""
    if max_seconds is None:
        return None
    if isinstance(max_seconds, bool) or not isinstance(max_seconds, (int, float)) \
            or not (math.isfinite(max_seconds) and max_seconds > 0):
        raise ValueError(f"max_seconds must be a number of seconds > 0 or None (no "
                         f"limit), got {max_seconds!r}")
    return float(max_seconds)


def sample_indices(size: int, count: int) -> np.ndarray:
    """``count`` flat indices of ``size`` points, one drawn (seed 0) in each of
    ``count`` equal ranges: deterministic, spread over every axis, no aliasing with
    the grid's shape as a regular stride has."""
    rng = np.random.default_rng(0)
    edges = [i * size // count for i in range(count + 1)]
    return np.array([lo + int(rng.integers(0, hi - lo)) for lo, hi in
                     zip(edges[:-1], edges[1:]) if hi > lo], np.int64)


def _points(grid: Grid, P: np.ndarray, o: np.ndarray) -> np.ndarray:
    """The sweep's kernels on the rows P, on every thread: forced responses or
    attractors (``sweepcore.sweep``'s chunk, on chosen points)."""
    from . import execute, forced
    out = np.empty((P.shape[0], layout.NFOB if grid.forced else layout.NOBS))
    if grid.forced:
        forced.responses(P, grid.laws, grid.loads, o, out, True)
    else:
        execute.attractors(P, grid.laws, o, out, True)
    return out


_TIMED = {}     # (grid fingerprint, option row) -> seconds a point, points, cut


def time_estimate(grid: Grid, o: np.ndarray, runs: float = 1.0) -> dict:
    """The time the sweep of ``grid`` with the option row ``o`` takes on this
    machine, measured on a sample of its own points (see the note above).

    ``runs``: kernel runs a point costs (basin stability's starts, a boundary
    search's runs), each taken as a sampled point's. Returns ``seconds`` (wall time
    of the kernels, every thread), ``seconds_per_point``, ``timed_points``,
    ``timing_seconds`` (what the sample took), ``lower_bound`` (a timed point took
    SAMPLE_STEPS steps: it may take up to max_steps) and ``threads``. The timing of
    a grid and options is kept for the process (the CLI's estimate and the sweep's
    are one)."""
    import numba
    key = (grid.fingerprint(), o.tobytes())
    if key not in _TIMED:
        if len(_TIMED) > 8:
            _TIMED.clear()
        _TIMED[key] = _timed_sample(grid, o)
    per_point, count, cut, took = _TIMED[key]
    return {"seconds": per_point * runs * grid.size, "seconds_per_point": per_point,
            "timed_points": count, "timing_seconds": took, "lower_bound": cut,
            "threads": numba.get_num_threads()}


CALL_POINTS = 4             # points of a call timed whole (time_call)


def sample_grid(grid: Grid, count: int) -> Grid | None:
    """``count`` points of ``grid`` (:func:`sample_indices`) as a ``Grid.points``,
    or None for a grid with a law dimension (a points grid takes one law)."""
    if isinstance(grid.law, tuple):
        return None
    idx = sample_indices(grid.size, min(count, grid.size))
    if grid.mode == "points":
        at = {name: idx for name in grid.swept}
    else:
        at = dict(zip(grid.swept, np.unravel_index(idx, grid.shape))) if grid.shape \
            else {}
    from .grid import AXES
    from .laws import analytic
    values = {n: grid.axis(n)[at[n]] if n in at else grid.axis(n) for n in AXES
              if grid.law is None or n not in analytic.PARAMETERS}
    return Grid.points(**values, law=grid.law)


def time_call(grid: Grid, call, count: int = CALL_POINTS) -> dict | None:
    """The time ``call(grid)`` takes on this machine, from ``call`` on ``count``
    points of the grid (:func:`sample_grid`), after ``call`` on one of them (which
    compiles or loads the kernels: untimed); as :func:`time_estimate`'s answer.
    For calls whose points run more than a sweep's kernels (basin stability's
    exact route: a scan of the return map, its cycles, the checks). None for a grid
    with a law dimension."""
    import numba
    sample = sample_grid(grid, count)
    if sample is None:
        return None
    call(sample_grid(grid, 1))
    started = time.perf_counter()
    call(sample)
    took = time.perf_counter() - started
    return {"seconds": took / sample.size * grid.size,
            "seconds_per_point": took / sample.size, "timed_points": sample.size,
            "timing_seconds": took, "lower_bound": False,
            "threads": numba.get_num_threads()}


def left_to_compute(grid: Grid, path) -> float:
    """The share of a sweep's points still to compute: a resumed sweep with
    ``path`` computes only what its working store lacks (1 without ``path``)."""
    if path is None:
        return 1.0
    width = layout.NFOB if grid.forced else layout.NOBS
    return 1.0 - min(1.0, _stored_bytes(path) / max(1, grid.size * 8 * width))


def _timed_sample(grid: Grid, o: np.ndarray) -> tuple:
    """``(seconds a point, points timed, cut, seconds spent)`` of
    :func:`time_estimate`: SAMPLE_POINTS points first, four times more while the
    sample took less than TIMING_SECONDS (a cheap point's time is too short to
    read alone), up to SAMPLE_SHARE's share of the grid."""
    most = min(SAMPLE_MAX, max(1, math.ceil(grid.size / SAMPLE_SHARE)))
    count, spent = min(SAMPLE_POINTS, most), 0.0
    timed = o.copy()
    timed[layout.O_MAX_STEPS] = min(o[layout.O_MAX_STEPS], SAMPLE_STEPS)
    warm = o.copy()
    warm[layout.O_MAX_STEPS] = 1.0      # compiles / loads the kernels: untimed
    while True:
        idx = sample_indices(grid.size, count)
        P = grid.rows_at(idx)
        _points(grid, P, warm)
        started = time.perf_counter()
        out = _points(grid, P, timed)
        took = time.perf_counter() - started
        spent += took
        if took >= TIMING_SECONDS or count >= most:
            break
        count = min(most, 4 * count)
    cut = bool(timed[layout.O_MAX_STEPS] < o[layout.O_MAX_STEPS] and np.any(
        out[:, layout.OB_NSTEPS] >= timed[layout.O_MAX_STEPS]))
    return took / idx.size, idx.size, cut, spent


def time_text(timing: dict) -> str:
    """``about 3.1 h (64 points timed here: 2.9 ms a point on 2 threads)``."""
    bound = "at least" if timing["lower_bound"] else "about"
    cut = (f"; a timed point reached the sample's {SAMPLE_STEPS:,} steps, so it may "
           "take longer") if timing["lower_bound"] else ""
    return (f"{bound} {duration_text(timing['seconds'])} "
            f"({timing['timed_points']} points timed here in "
            f"{duration_text(timing['timing_seconds'])}: "
            f"{timing['seconds_per_point'] * 1e3:.3g} ms a point on "
            f"{timing['threads']} threads{cut})")


def refuse_if_too_long(what: str, timing: dict, max_seconds,
                       command_line: bool = False) -> None:
    """Raise :class:`SweepTooLong` (nothing computed, nothing written) when the
    call ``what`` would take longer than ``max_seconds`` (None: no limit), naming
    the limit as the caller gave it (``--max-time`` on the ``command_line``)."""
    limit = check_max_seconds(max_seconds)
    if limit is not None and timing["seconds"] > limit:
        name, none, cluster = (("--max-time ", "'none'", "--scheduler tcp://HOST:PORT")
                               if command_line else ("max_seconds=", "None", "client="))
        raise SweepTooLong(
            f"{what} would take {time_text(timing)}, more than {name}{limit:g} "
            f"({duration_text(limit)}); allow more ({name}{none}: no limit), compute "
            f"a smaller grid, or run it on a cluster ({cluster}: no limit applies)")
