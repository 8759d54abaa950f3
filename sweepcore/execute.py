"""Where the kernels run: one executor for sweeps, boundary searches and diagrams.

A caller cuts its work into independent tasks, each ``function(*args)`` returning
one chunk's result, and hands them to :func:`run`, which runs them

* directly in this process (no ``client``, no ``scheduler``): one after the other,
  each called with ``parallel=True``, so that it may use numba's threads;
* as one dask task per chunk with a local scheduler (``"threads"``, ``"processes"``,
  ``"synchronous"``): each called serially (the kernels release the GIL), so dask
  alone provides the parallelism, never nested numba threads;
* as one future per chunk on a distributed cluster (a ``distributed.Client`` or a
  scheduler address ``"tcp://host:port"``).

Every point is computed independently (fastmath off), so results do not depend on
the executor, the chunk size or the worker count. Results are handed back as each
task finishes (``handle(i, result)``), so a caller can store them and hold no more
than it needs.

:func:`attractors` is the one call of the attractor kernel on a batch of rows, for
callers that batch their own requests (the boundary solvers, the diagrams, the
basins); :func:`cycles` the same for the slip-cycle search (stable and unstable
cycles, ``sweepcore/_kernels/cycles.py``).
"""
from __future__ import annotations

import contextlib
import uuid

import numpy as np

from . import compiled, law
from .options import did_you_mean

LOCAL_SCHEDULERS = {"threads": "threads", "processes": "processes",
                    "synchronous": "synchronous", "sync": "synchronous",
                    "single-threaded": "synchronous"}


def chunk_bounds(size: int, chunk: int) -> list[tuple[int, int]]:
    """Flat ranges ``[start, stop)`` of ``chunk`` consecutive points (the last may be
    shorter) covering ``size`` points."""
    return [(a, min(a + chunk, size)) for a in range(0, size, chunk)]


def check_chunks(chunks, what: str = "") -> None:
    """Refuse a chunk size that is not an integer >= 1 (None: the default)."""
    if chunks is not None and (isinstance(chunks, bool) or not isinstance(
            chunks, (int, np.integer)) or chunks < 1):
        raise ValueError(f"chunks must be an integer >= 1{what}, got {chunks!r}")


# ------------------------------------------------------------------ executors
def resolve(client, scheduler):
    """("direct", None) | ("local", name) | ("distributed", Client or address).

    A refusal names the argument given (``client`` or ``scheduler``) and its value."""
    if client is not None and scheduler is not None:
        raise ValueError("give client or scheduler, not both")
    name, target = ("scheduler", scheduler) if client is None else ("client", client)
    if target is None:
        return "direct", None
    if isinstance(target, str):
        if name == "scheduler" and target in LOCAL_SCHEDULERS:
            return "local", LOCAL_SCHEDULERS[target]
        if ":" in target:
            return "distributed", target
    else:
        from distributed import Client
        if isinstance(target, Client):
            return "distributed", target
    if name == "scheduler":
        raise _refused(name, target, f"one of {sorted(LOCAL_SCHEDULERS)} or a "
                                     "scheduler address 'tcp://host:port'",
                       did_you_mean(target, LOCAL_SCHEDULERS)
                       if isinstance(target, str) else "")
    hint = " (a local scheduler goes in scheduler=)" if isinstance(target, str) and \
        target in LOCAL_SCHEDULERS else ""
    raise _refused(name, target, "a distributed.Client or a scheduler address "
                                 "'tcp://host:port'", hint)


def _refused(name: str, value, what: str, hint: str = "") -> Exception:
    if isinstance(value, str):
        return ValueError(f"{name} must be {what}, got {value!r}{hint}")
    return TypeError(f"{name} must be {what}, got {value!r} of type "
                     f"{type(value).__name__}{hint}")


CONNECT_TIMEOUT = 10.0    # seconds a scheduler address has to answer (dask's: 30)


@contextlib.contextmanager
def connected(kind: str, target):
    """``(kind, target)`` with a scheduler address replaced by a Client connected to
    it (closed on exit), so that a wrong address is refused before any work, after
    :data:`CONNECT_TIMEOUT` seconds at most, naming the address."""
    if kind != "distributed" or not isinstance(target, str):
        yield kind, target
        return
    from distributed import Client
    try:
        client = Client(target, set_as_default=False, timeout=CONNECT_TIMEOUT)
    except (OSError, TimeoutError) as err:
        raise ConnectionError(
            f"no dask scheduler answered at {target!r} within {CONNECT_TIMEOUT:g} s "
            f"(sweepcore's connect timeout; {err}): start one (`dask scheduler`) or "
            "check the address") from None
    with client:
        yield kind, client


def run(kind: str, target, todo, task, handle) -> None:
    """Run the tasks ``todo`` with the executor ``(kind, target)`` of :func:`resolve`.

    Parameters
    ----------
    kind, target
        From :func:`resolve`.
    todo : iterable of int
        Indices of the tasks to run.
    task : callable
        ``task(i) -> (function, args)``; ``args`` are shipped to a worker as they
        are (keep them small: a grid block, not the grid's rows). The direct path
        builds each task only when it runs.
    handle : callable
        ``handle(i, result)``, called in this process as each task finishes (in
        any order).
    """
    if kind == "direct":
        for i in todo:
            function, args = task(i)
            handle(i, function(*args, parallel=True))
    elif kind == "local":
        _run_dask_local(target, todo, task, handle)
    elif isinstance(target, str):
        with connected(kind, target) as (_kind, client):
            _run_distributed(client, todo, task, handle)
    else:
        _run_distributed(target, todo, task, handle)


def _run_dask_local(scheduler, todo, task, handle):
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
        function, args = task(i)
        key = f"sweepcore-chunk-{i}-{token}"
        keys[key] = i
        # each argument as it is: dask would otherwise walk into a Grid (a dataclass)
        args = [dask.delayed(a, name=f"sweepcore-arg-{i}-{j}-{token}", traverse=False)
                for j, a in enumerate(args)]
        tasks.append(dask.delayed(function, pure=True)(*args, dask_key_name=key))

    def posttask(key, result, dsk, state, worker_id):
        if key in keys:
            handle(keys[key], result)

    with Callback(posttask=posttask):
        dask.compute(*tasks, scheduler=scheduler)


def _run_distributed(client, todo, task, handle):
    """One future per chunk, each carrying its own (small) arguments: data scattered
    to a worker would be lost with it, a task's arguments are not."""
    from distributed import as_completed

    token = uuid.uuid4().hex
    futures = {}
    for i in todo:
        function, args = task(i)
        futures[client.submit(function, *args, pure=False,
                              key=f"sweepcore-chunk-{i}-{token}")] = i
    pending = set(futures)
    try:
        for fut in as_completed(futures, loop=client.loop):
            handle(futures[fut], fut.result())
            pending.discard(fut)
            fut.release()
    finally:
        if pending:
            client.cancel(list(pending))


# ------------------------------------------------------- one batch of attractors
def attractors(P: np.ndarray, laws, o: np.ndarray, out: np.ndarray,
               parallel: bool) -> None:
    """The attractor of every row of P (its law ``laws[P[:, LAW]]``) into ``out``,
    on every numba thread if ``parallel`` (:func:`sweepcore.compiled.attractors`),
    with the points the kernels cannot resolve flagged
    (:func:`sweepcore.law.flag_unresolvable`)."""
    compiled.attractors(P, laws, o, out, parallel)
    law.flag_unresolvable(P, o, out, laws)


def cycles(P: np.ndarray, laws, o: np.ndarray, out: np.ndarray, found: np.ndarray,
           parallel: bool) -> None:
    """Every slip cycle of the rows of P (``out`` of shape (n, MAX_CYCLES, NOBS),
    ``found`` (n,) int64), as :func:`attractors`."""
    compiled.cycles(P, laws, o, out, found, parallel)
    law.flag_unresolvable(P, o, out, laws)     # every cycle slot of the point
