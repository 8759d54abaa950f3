"""Resumable work with a result path, shared by sweep, basin stability and the cycle
scan: each finished chunk is kept in the working store of the path
(:class:`sweepcore.io.WorkingStore`, keyed and salted by a hash of everything that
fixes the results), a rerun of the same call checks the stored chunks and computes
only the rest, and the result file appears only when complete.

* :func:`open_store`: the locked store of a path for one call's configuration;
* :func:`compute_missing`: run the chunks the store lacks (or holds damaged),
  storing each as it finishes, with a progress bar and a line saying what resumes;
* :func:`write_result`: under the store's lock, remove the temporaries a killed
  write left beside the path, write the file atomically, remove the store.
"""
from __future__ import annotations

import functools
import hashlib
import json
import sys
import time
from pathlib import Path

import numba
import xarray as xr
from tqdm.auto import tqdm

from . import execute, labels
from .io import WorkingStore, write_netcdf
from .io.files import stale_temporaries


@functools.lru_cache(maxsize=1)
def kernel_digest() -> str:
    """SHA-256 of the kernels' source (every module under ``sweepcore/_kernels/``, the
    law kinds' included: ``SOURCE_HASH``): a resume must not mix two kernel
    versions."""
    from ._kernels import SOURCE_HASH
    return hashlib.sha256(numba.__version__.encode() + SOURCE_HASH.encode()).hexdigest()


def open_store(path, fixed: dict, readable: dict, n_points: int, ncols: int | None,
               chunk: int | None, default_chunk: int) -> WorkingStore:
    """The working store of ``path`` (created, or resumed and locked), keyed by the
    SHA-256 of ``fixed`` (what fixes the results: grid, option row, settings), the
    version and the kernels' source; ``readable`` is written beside it for people.
    ``ncols`` None: chunks of any width (a variable-width answer per point)."""
    config = {**fixed, "version": labels.version(), "kernels": kernel_digest()}
    digest = hashlib.sha256(json.dumps(config, sort_keys=True).encode()).hexdigest()
    return WorkingStore.open(path, digest, readable, n_points, ncols, chunk,
                             default_chunk)


def progress_bar(size: int, initial: int, progress, desc: str = "sweep"):
    """A tqdm bar on stderr; ``progress`` None: only on a terminal, after 0.5 s;
    True with stderr not a terminal (a log file) nor a notebook (tqdm's widget):
    :class:`ProgressLines`."""
    from tqdm import autonotebook
    terminal = sys.stderr.isatty()
    if progress and not terminal and autonotebook.tqdm.__module__ == "tqdm.std":
        return ProgressLines(size, initial, desc)
    show = terminal if progress is None else bool(progress)
    return tqdm(total=size, initial=initial, unit="pt", unit_scale=True, desc=desc,
                disable=not show, delay=0.5 if progress is None else 0.0,
                file=sys.stderr)


class ProgressLines:
    """Progress as plain lines on stderr, for a log file where a bar's carriage
    returns would pile up: a line every ``every`` seconds or every tenth of the
    work, whichever comes first, and one at the end, e.g. ``sweep: 6,554 of 65,536
    points (10%), 7 s, about 63 s left``. The same ``update(n)`` as a tqdm bar."""

    def __init__(self, size: int, initial: int = 0, desc: str = "sweep",
                 every: float = 10.0, clock=time.monotonic):
        self.size, self.done, self.desc = size, initial, desc
        self.first, self.every, self.clock = initial, every, clock
        self.start = self.last = clock()
        self.tenth = self._tenth()

    def _tenth(self) -> int:
        return int(10 * self.done / self.size) if self.size else 10

    def update(self, n: int) -> None:
        self.done += n
        now = self.clock()
        if self.done >= self.size or now - self.last >= self.every or \
                self._tenth() > self.tenth:
            self.last, self.tenth = now, self._tenth()
            print(self.line(now), file=sys.stderr, flush=True)

    def line(self, now: float) -> str:
        took = now - self.start
        text = (f"{self.desc}: {self.done:,} of {self.size:,} points "
                f"({100 * self.done // self.size if self.size else 100}%), "
                f"{took:.0f} s")
        if self.first < self.done < self.size:
            left = took / (self.done - self.first) * (self.size - self.done)
            text += f", about {left:.0f} s left"
        return text

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


def compute_in_memory(size: int, chunk: int, kind, target, task, progress,
                      what: str = "sweep", handle=None) -> list | None:
    """Compute every chunk of ``size`` points (:func:`sweepcore.execute.chunk_bounds`)
    with the executor ``(kind, target)``, without a store, ``task(bounds)`` giving
    :func:`sweepcore.execute.run`'s task: the results in chunk order, or each given
    to ``handle(a, b, result)`` (the points ``[a, b)``) as it finishes."""
    bounds = execute.chunk_bounds(size, chunk)
    parts = [None] * len(bounds)
    with progress_bar(size, 0, progress, what) as bar:
        def done(i, result):
            a, b = bounds[i]
            if handle is None:
                parts[i] = result
            else:
                handle(a, b, result)
            bar.update(b - a)

        execute.run(kind, target, range(len(bounds)), task(bounds), done)
    return parts if handle is None else None


def compute_missing(store: WorkingStore, kind, target, task, progress,
                    what: str = "sweep") -> None:
    """Compute the chunks ``store`` lacks (or holds damaged) with the executor
    ``(kind, target)`` (:func:`sweepcore.execute.resolve`), ``task(i)`` giving the
    function and arguments of chunk ``i``; each is stored as it finishes, so
    nothing grid-sized is held here."""
    finished = set(store.verified())
    bounds = [store.bounds(i) for i in range(store.n_chunks)]
    todo = [i for i in range(len(bounds)) if i not in finished]
    initial = sum(bounds[i][1] - bounds[i][0] for i in finished)
    if finished and progress is not False:
        # on stderr (not a log record): an interrupted run's user must see it
        print(f"{what}: resuming {len(finished)} of {store.n_chunks} chunks (already "
              f"stored in {store.directory}); computing the other {len(todo)}",
              file=sys.stderr)
    with progress_bar(store.n_points, initial, progress, what) as bar:
        def handle(i, result):
            store.write(i, result)
            bar.update(bounds[i][1] - bounds[i][0])

        if todo:
            execute.run(kind, target, todo, task, handle)


def stored_chunks(store: WorkingStore) -> list:
    """Every chunk of a complete store, read back and checked (in order)."""
    return [store.read(i) for i in range(store.n_chunks)]


def write_result(store: WorkingStore, ds: xr.Dataset, path: Path) -> None:
    """Write ``ds`` to ``path`` and remove the store (its work is in the file).

    The lock is the caller's: a temporary beside the file is a killed write's
    leftover, removed first. A failed write keeps the store, so that rerunning the
    same call only writes."""
    for tmp in stale_temporaries(path):
        tmp.unlink(missing_ok=True)
    try:
        write_netcdf(ds, path)
    except OSError as err:
        raise OSError(err.errno, f"{err.strerror or err} The working store "
                      f"{store.directory} is kept: free space and rerun the same "
                      "call to finish.") from err
    store.remove()
