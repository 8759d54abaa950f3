"""The kernels as the Python rooms call them: compiled on first use.

A call's rows are grouped by the kernels' law kind (``sweepcore._kernels.laws``)
and by method ("auto" resolved per row, :func:`methods_of`), and each group runs on
the entry kernel of its method (``sweepcore._kernels.entries``), compiled for that
(method, law kind) the first time it is used and loaded from numba's cache after
that. While a kernel compiles, :data:`notice` (set by the command line) is told
what is being compiled, an estimate of how long it takes, and the seconds elapsed.
"""
from __future__ import annotations

import atexit
import itertools
import json
import os
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numba
import numpy as np
from numba.core import event

from ._kernels import codes, entries, layout, stepper
from ._kernels import laws as _kernel_laws
from . import law as _law

EPS = np.finfo(np.float64).eps


# ------------------------------------------------------------------ methods
def methods_of(P: np.ndarray, laws, o: np.ndarray) -> np.ndarray:
    """The method code of every row (int array): the option row's, or for "auto"
    (``O_METHOD`` < 0) the closed form where the row's law has one, else dop853
    below tol ``stepper.AUTO_DOP853_BELOW`` where the motion is far above float64's
    rounding of x (``stepper.AUTO_DOP853_ROUNDING``), else dopri5."""
    n = P.shape[0]
    method = int(o[layout.O_METHOD])
    if method >= 0:
        return np.full(n, method, np.intp)
    closed = _law.per_law(P, laws, "closed_form", bool)
    with np.errstate(all="ignore"):
        k, m, v = P[:, layout.K], P[:, layout.M], P[:, layout.V]
        omega = np.sqrt(k / m)
        lx = _law.length_scale(P, laws)
        lx = np.where(lx > 0.0, lx, 1.0)
        lv = np.where(v != 0.0, np.abs(v), omega * lx)
        rounding = EPS * lx * omega / np.maximum(lv, 1e-300)
    pair = np.where((o[layout.O_RTOL] < stepper.AUTO_DOP853_BELOW)
                    & (rounding <= stepper.AUTO_DOP853_ROUNDING),
                    stepper.DOP853, stepper.DOPRI5)
    return np.where(closed, stepper.EXACT, pair).astype(np.intp)


def groups(P: np.ndarray, laws, o: np.ndarray):
    """``[(method, kind, rows, law data)]``: the rows of P (indices) that share a
    method code and a law kind, with the kind's law data."""
    method = methods_of(P, laws, o)
    which = P[:, layout.LAW].astype(np.intp)
    out = []
    for i, law in enumerate(laws):
        mine = np.flatnonzero(which == i)
        if not mine.size:
            continue
        for kind, sub, lw in law.kernel_groups(P[mine]):
            rows = mine[sub]
            for meth in np.unique(method[rows]):
                out.append((int(meth), kind, rows[method[rows] == meth], lw))
    return out


def _sub(a: np.ndarray, rows: np.ndarray, n: int):
    """``a[rows]`` contiguous, or ``a`` itself when the rows are all of it."""
    if rows.size == n:
        return a
    return np.ascontiguousarray(a[rows])


# ------------------------------------------------------------ the entry calls
_POOL = []


def attractors(P: np.ndarray, laws, o: np.ndarray, out: np.ndarray,
               parallel: bool = False) -> None:
    """The attractor of every row of P into ``out`` (n, NOBS), on every numba thread
    if ``parallel`` (:func:`_batched`)."""
    for meth, kind, rows, lw in groups(P, laws, o):
        sub = _sub(out, rows, P.shape[0])
        if parallel:
            _prefetch(meth, kind)
        with compiling("attractor", meth, kind):
            _batched("attractor_rows", meth, _sub(P, rows, P.shape[0]), lw, o, (sub,),
                     parallel)
        if sub is not out:
            out[rows] = sub


def cycles(P: np.ndarray, laws, o: np.ndarray, out: np.ndarray, found: np.ndarray,
           parallel: bool = False) -> None:
    """Every slip cycle of the rows of P (``out`` (n, MAX_CYCLES, NOBS), ``found``
    (n,) int64), shared out as :func:`attractors`."""
    n = P.shape[0]
    for meth, kind, rows, lw in groups(P, laws, o):
        sub_out, sub_found = _sub(out, rows, n), _sub(found, rows, n)
        with compiling("cycle scan", meth, kind):
            _batched("slip_cycles_rows", meth, _sub(P, rows, n), lw, o,
                     (sub_out, sub_found), parallel)
        if sub_out is not out:
            out[rows] = sub_out
            found[rows] = sub_found


def _batched(name: str, meth: int, P, lw, o, outs, parallel: bool) -> None:
    """The entry ``name`` over the rows of P; with ``parallel``, on
    ``numba.get_num_threads()`` Python threads (the kernels release the GIL).

    The threads take blocks of ``BLOCK`` consecutive rows in turn from a shared
    counter, so a thread that drew costly points (slip cycles next to v* cost ~10x
    a stick-slip point) takes fewer blocks: the load balances itself. Rows are
    contiguous in P, so a block is a view, not a copy; every point is computed on
    its own, so the result does not depend on the split. (One compiled kernel
    serves this path, the serial one and dask's.)"""
    n = P.shape[0]
    kernel = entries.entry(name, meth)
    threads = min(numba.get_num_threads(), n) if parallel else 1
    if threads <= 1:
        kernel(P, lw, o, *outs)
        return
    if not _POOL or _POOL[0][0] != threads:
        _POOL[:] = [(threads, ThreadPoolExecutor(threads, thread_name_prefix="sweepcore"))]
    kernel(P[:1], lw, o, *(a[:1] for a in outs))       # compile once, not per thread
    block = max(1, min(BLOCK, (n - 1) // (4 * threads)))
    starts = itertools.count(1, block)
    P = np.ascontiguousarray(P)

    def work(_):
        for a in starts:
            if a >= n:
                return
            b = min(a + block, n)
            kernel(P[a:b], lw, o, *(x[a:b] for x in outs))
    list(_POOL[0][1].map(work, range(threads)))


BLOCK = 32      # rows a thread takes at a time


def trajectory(row: np.ndarray, law, o: np.ndarray, *arrays):
    """One run of the driver (``sweepcore._kernels.trajectory``) from ``row``, with
    the law object ``law``; returns ``(n_events, status, n_steps, method)``."""
    P = row[None, :]
    ((meth, kind, _rows, lw),) = groups(P, (law,), o)
    with compiling("trajectory", meth, kind):
        n_ev, status, n_steps = entries.entry("trajectory", meth)(row, lw, o, *arrays)
    return n_ev, status, n_steps, meth


def options(row: np.ndarray, law, o: np.ndarray):
    """``(option row, a-priori status)`` of one point: "auto" resolved, the default
    dt and GPS shift filled in (``attractor.resolve_options``)."""
    ((meth, _kind, _rows, lw),) = groups(row[None, :], (law,), o)
    return entries.entry("options", meth)(row, lw, o)


# ------------------------------------------------------- a second compiler
PREFETCH = True     # compile half of a cold attractor kernel in a second process
_prefetched = set()


def _prefetch(meth: int, kind: int) -> None:
    """Start ``sweepcore._kernels.prefetch`` for (method, kind) once per process,
    where the cache lacks its search half and a second core is there to run it."""
    if not PREFETCH or (meth, kind) in _prefetched or (os.cpu_count() or 1) < 2:
        return
    _prefetched.add((meth, kind))
    from ._kernels import attractor, prefetch
    name = _kernel_laws.LAWS[kind][0]
    try:
        if prefetch.cached(attractor.on_event, prefetch.search_signature(meth, name)):
            return
        child = subprocess.Popen(
            [sys.executable, "-m", "sweepcore._kernels.prefetch", str(meth), name],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            env={**os.environ, "NUMBA_CACHE_DIR": _cache_dir()})
    except (OSError, ValueError):
        return               # no second process: this one compiles it all
    if not _children:
        atexit.register(_reap)
    _children.append(child)


_children = []


def _reap() -> None:
    """At exit, wait for the second compiler (its work is the cache's, and it must
    not outlive the command that started it)."""
    for child in _children:
        try:
            child.wait(timeout=120)
        except subprocess.TimeoutExpired:
            child.kill()


def _cache_dir() -> str:
    return str(numba.config.CACHE_DIR)


# ------------------------------------------------------- while compiling
notice = None       # callable(str) told about compilations (the command line: stderr)
TICK = 5.0          # seconds between the lines of a long compilation
ESTIMATES = Path(__file__).with_name("compile_estimates.json")


def _what(entry: str, meth: int, kind: int) -> str:
    return (f"the {entry} kernel ({codes.METHOD_NAMES[meth]}, "
            f"{_kernel_laws.LAWS[kind][0]} law)")


def _estimate(key: str) -> str:
    """How long compiling ``key`` took before: on this machine (the last time, kept
    in numba's cache directory), else in the benchmark (``python benchmarks/run.py``,
    shipped with the package); "" where neither measured it."""
    for path, where in ((_local_estimates(), "here"),
                        (ESTIMATES, "by the benchmark run")):
        try:
            seconds = json.loads(Path(path).read_text()).get(key)
        except (OSError, ValueError, TypeError, AttributeError):
            continue
        if seconds:
            return f", about {seconds:g} s measured {where}"
    return ""


def _local_estimates() -> Path:
    return Path(numba.config.CACHE_DIR or ".") / "sweepcore_compile_seconds.json"


def _remember(key: str, seconds: float) -> None:
    path = _local_estimates()
    try:
        known = json.loads(path.read_text()) if path.exists() else {}
        known[key] = round(seconds, 1)
        tmp = path.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_text(json.dumps(known))
        os.replace(tmp, path)
    except (OSError, ValueError, TypeError):
        pass


class compiling:
    """Context of one entry call: if numba compiles during it, tell :data:`notice`
    what, how long it took before (estimate) and, every ``TICK`` s, the seconds
    elapsed; the time is remembered for the next estimate."""

    def __init__(self, entry: str, meth: int, kind: int):
        self.key = f"{entry}/{codes.METHOD_NAMES[meth]}/{_kernel_laws.LAWS[kind][0]}"
        self.what = _what(entry, meth, kind)
        self.started = None
        self.stop = threading.Event()

    def __enter__(self):
        self.listener = _Listener(self)
        self.ctx = event.install_listener("numba:compile", self.listener)
        self.ctx.__enter__()
        return self

    def __exit__(self, *exc):
        self.ctx.__exit__(*exc)
        self.stop.set()
        if self.started is not None:
            took = time.perf_counter() - self.started
            _remember(self.key, took)
            if notice is not None:
                notice(f"sweepcore: compiled in {took:.1f} s (kept in numba's cache "
                       "for later runs)")
        return False

    def begin(self):
        self.started = time.perf_counter()
        if notice is None:
            return
        notice(f"sweepcore: compiling {self.what}: first use in this install"
               f"{_estimate(self.key)}")
        threading.Thread(target=self._tick, daemon=True).start()

    def _tick(self):
        while not self.stop.wait(TICK):
            notice(f"sweepcore: ... compiling, {time.perf_counter() - self.started:.0f} s")


class _Listener(event.Listener):
    def __init__(self, owner: compiling):
        self.owner = owner

    def on_start(self, ev):
        if self.owner.started is None:
            self.owner.begin()

    def on_end(self, ev):
        pass
