"""The kernels as the Python rooms call them: compiled on first use.

A call's rows are grouped by the kernels' law kind (``sweepcore._kernels.laws``)
and by method ("auto" resolved per row, :func:`methods_of`), and each group runs on
the entry kernel of its method (``sweepcore._kernels.entries``), compiled for that
(method, law kind) the first time it is used and loaded from numba's cache after
that. Every compilation of a kernel, whichever room calls it first, is announced on
stderr (:class:`_Announcer`): what compiles, how long it took before and how long it
took, as warnings of the logger ``sweepcore.compile`` (or to :data:`notice`, which the
command line sets). :func:`compile` compiles ahead of time.
"""
from __future__ import annotations

import atexit
import itertools
import json
import logging
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
from ._kernels import excitations as _kernel_excitations
from ._kernels import laws as _kernel_laws
from . import law as _law
from .options import checked_keywords

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


def forced_methods(P: np.ndarray, laws, o: np.ndarray) -> np.ndarray:
    """The method code of every forced row: the option row's, dop853 for "auto" (the
    stroboscopic search's Newton needs tight periods: the eighth-order pair)."""
    method = int(o[layout.O_METHOD])
    return np.full(P.shape[0], method if method >= 0 else stepper.DOP853, np.intp)


def groups(P: np.ndarray, laws, o: np.ndarray, forced: bool = False):
    """``[(method, kind, rows, law data)]``: the rows of P (indices) that share a
    method code and a law kind, with the kind's law data (``forced``: the methods of
    forced rows)."""
    method = forced_methods(P, laws, o) if forced else methods_of(P, laws, o)
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


def _by_load(P: np.ndarray, laws, loads, o: np.ndarray, out: np.ndarray):
    """The forced rows of P by method, law kind and load (``layout.LOAD`` indexes
    ``loads``): yields (method, kind, law data, the group's rows of P, its rows of
    ``out``, the load's kernel data); the group's results are written back into
    ``out`` when the caller asks for the next group."""
    which = P[:, layout.LOAD].astype(np.intp)
    for meth, kind, rows, lw in groups(P, laws, o, forced=True):
        for j in np.unique(which[rows]):
            mine = rows[which[rows] == j]
            sub = _sub(out, mine, P.shape[0])
            yield meth, kind, lw, _sub(P, mine, P.shape[0]), sub, loads[j].data()
            if sub is not out:
                out[mine] = sub


def responses(P: np.ndarray, laws, loads, o: np.ndarray, out: np.ndarray,
              parallel: bool = False) -> None:
    """The steady forced response of every row of P into ``out`` (n, NFOB): the
    rows grouped by method, law kind and load (``layout.LOAD`` indexes ``loads``),
    each group on the method's ``forced_rows`` entry, shared out as
    :func:`attractors`."""
    for meth, kind, lw, Pj, sub, data in _by_load(P, laws, loads, o, out):
        with compiling("forced response", meth, kind):
            _batched("forced_rows", meth, Pj, lw, o, (sub,), parallel, (data,))


def images(P: np.ndarray, laws, loads, o: np.ndarray, n: int, out: np.ndarray) -> None:
    """P^n of every forced row's start (``layout.X0``, ``XD0`` at t = 0) with its
    tangent and the run's observables into ``out`` (rows, NFOB + NIM): the
    stroboscopic map's image (``sweepcore._kernels.strobe.image_point``), grouped as
    :func:`responses`."""
    for meth, kind, lw, Pj, sub, data in _by_load(P, laws, loads, o, out):
        with compiling("stroboscopic image", meth, kind):
            entries.entry("image_rows", meth)(Pj, lw, data, o, int(n), sub)


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


def _batched(name: str, meth: int, P, lw, o, outs, parallel: bool, extra=()) -> None:
    """The entry ``name`` over the rows of P; with ``parallel``, on
    ``numba.get_num_threads()`` Python threads (the kernels release the GIL).

    The threads take blocks of ``BLOCK`` consecutive rows in turn from a shared
    counter, so a thread that drew costly points (slip cycles next to v* cost ~10x
    a stick-slip point) takes fewer blocks: the load balances itself. Rows are
    contiguous in P, so a block is a view, not a copy; every point is computed on
    its own, so the result does not depend on the split. (One compiled kernel
    serves this path, the serial one and dask's.) ``extra``: the arguments the
    entry takes between the law data and the options (a forced entry's
    excitation data)."""
    n = P.shape[0]
    kernel = entries.entry(name, meth)
    threads = min(numba.get_num_threads(), n) if parallel else 1
    if threads <= 1:
        kernel(P, lw, *extra, o, *outs)
        return
    if not _POOL or _POOL[0][0] != threads:
        _POOL[:] = [(threads, ThreadPoolExecutor(threads, thread_name_prefix="sweepcore"))]
    kernel(P[:1], lw, *extra, o, *(a[:1] for a in outs))   # compile once, not per thread
    block = max(1, min(BLOCK, (n - 1) // (4 * threads)))
    starts = itertools.count(1, block)
    P = np.ascontiguousarray(P)

    def work(_):
        for a in starts:
            if a >= n:
                return
            b = min(a + block, n)
            kernel(P[a:b], lw, *extra, o, *(x[a:b] for x in outs))
    list(_POOL[0][1].map(work, range(threads)))


BLOCK = 32      # rows a thread takes at a time


def trajectory(row: np.ndarray, law, load, o: np.ndarray, *arrays):
    """One run of the driver (``sweepcore._kernels.trajectory``) from ``row``, with
    the law object ``law`` and the excitation ``load`` (a
    :class:`~sweepcore.PeriodicLoad`, or None: none); returns ``(n_events, status,
    n_steps, method)``."""
    P = row[None, :]
    ex = _excitation(row, load)
    ((meth, kind, _rows, lw),) = groups(P, (law,), o, forced=ex is not None)
    ex = _UNFORCED if ex is None else ex
    with compiling("trajectory", meth, kind):
        n_ev, status, n_steps = entries.entry("trajectory", meth)(row, lw, ex, o, *arrays)
    return n_ev, status, n_steps, meth


def options(row: np.ndarray, law, load, o: np.ndarray):
    """``(option row, a-priori status)`` of one point: "auto" resolved, the default
    dt and GPS shift filled in (``attractor.resolve_options``)."""
    ex = _excitation(row, load)
    ((meth, kind, _rows, lw),) = groups(row[None, :], (law,), o, forced=ex is not None)
    ex = _UNFORCED if ex is None else ex
    with compiling("options", meth, kind):
        return entries.entry("options", meth)(row, lw, ex, o)


_UNFORCED = _kernel_excitations.UNFORCED


def _excitation(row: np.ndarray, load):
    """The kernel excitation data of one forced row (its load's), None unforced."""
    from . import excitations
    return excitations.kernel_data(row, load)


# ------------------------------------------------------- a second compiler
PREFETCH = True     # compile half of a cold attractor kernel in a second process
_prefetched = set()


def _prefetch(meth: int, kind: int) -> None:
    """Start ``sweepcore._kernels.prefetch`` for (method, kind) once per process,
    where the cache lacks its search half and a second core is there to run it."""
    if not PREFETCH or (meth, kind) in _prefetched or (os.cpu_count() or 1) < 2:
        return
    _prefetched.add((meth, kind))
    try:        # a cache it cannot write to would take nothing from a second compiler
        Path(_cache_dir()).mkdir(parents=True, exist_ok=True)
    except OSError:
        return
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
# Every compilation of a sweepcore kernel is announced: a line naming what compiles
# and how long it took before, and one with the time it took. By default the lines
# are warnings of the logger "sweepcore.compile" (on stderr where logging is not
# configured: Python's last-resort handler), and a line every TICK s while it lasts,
# from Python as from the command line; silence them with
# ``logging.getLogger("sweepcore.compile").setLevel(logging.ERROR)``. The command
# line sets ``notice`` instead (stderr).
log = logging.getLogger("sweepcore.compile")
notice = None       # callable(str) told instead of the logger (the command line)
TICK = 5.0          # seconds between the lines of a long compilation
ESTIMATES = Path(__file__).with_name("compile_estimates.json")
_PACKAGE = str(Path(__file__).resolve().parent)


def _say(line: str) -> None:
    if notice is not None:
        notice(line)
    else:
        log.warning(line)


def _what(entry: str, meth, kind) -> str:
    of = [codes.METHOD_NAMES[meth]] if meth is not None else []
    of += [f"{_kernel_laws.LAWS[kind][0]} law"] if kind is not None else []
    return f"the {entry} kernel" + (f" ({', '.join(of)})" if of else "")


def _key(entry: str, meth, kind) -> str:
    return "/".join([entry] + ([codes.METHOD_NAMES[meth]] if meth is not None else [])
                    + ([_kernel_laws.LAWS[kind][0]] if kind is not None else []))


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


_calling = threading.local()     # the entry call a thread is in: [(key, what)]


class compiling:
    """Context of one entry call (``entry`` of method code ``meth`` and law kind
    ``kind``, either None for a kernel of every one): a compilation during it is
    announced by that name (:class:`_Announcer`), and its time remembered for the
    next estimate."""

    def __init__(self, entry: str, meth, kind: int):
        self.name = (_key(entry, meth, kind), _what(entry, meth, kind))
        self.took = None        # seconds, where it compiled

    def __enter__(self):
        if not hasattr(_calling, "stack"):
            _calling.stack = []
        _calling.stack.append(self)
        return self

    def __exit__(self, *exc):
        _calling.stack.pop()
        return False


class _Announcer(event.Listener):
    """numba's compile events, process-wide: the outermost compilation of a
    sweepcore kernel is announced (numba compiles under one lock: one at a time;
    the kernels it compiles on the way are nested events)."""

    def __init__(self):
        self.depth = 0
        self.top = False

    def on_start(self, ev):
        self.depth += 1
        if self.depth == 1:
            self.top = self._begin(ev.data.get("dispatcher"))

    def on_end(self, ev):
        self.depth -= 1
        if self.depth == 0 and self.top:
            self._finish()

    def _begin(self, dispatcher) -> bool:
        owner = (getattr(_calling, "stack", None) or [None])[-1]
        if owner is not None:
            self.key, self.what = owner.name
        else:           # a kernel compiled outside an entry call (derived quantities)
            fn = getattr(dispatcher, "py_func", None)
            code = getattr(fn, "__code__", None)
            if code is None or not code.co_filename.startswith(_PACKAGE):
                return False            # a user's own numba function
            self.key, self.what = fn.__name__, f"the {fn.__name__} kernel"
        self.owner = owner
        self.started = time.perf_counter()
        self.stop = threading.Event()
        _say(f"sweepcore: compiling {self.what}, not in the kernel cache yet"
             f"{_estimate(self.key)}")
        threading.Thread(target=self._tick, args=(self.stop, self.started),
                         daemon=True).start()
        return True

    def _finish(self):
        self.stop.set()
        took = time.perf_counter() - self.started
        _remember(self.key, took)
        if self.owner is not None:
            self.owner.took = (self.owner.took or 0.0) + took
        _say(f"sweepcore: compiled {self.what} in {took:.1f} s (kept in numba's "
             "cache for later runs)")

    @staticmethod
    def _tick(stop, started):
        while not stop.wait(TICK):
            _say(f"sweepcore: ... compiling, {time.perf_counter() - started:.0f} s")


ANNOUNCER = _Announcer()    # told by sweepcore._kernels, whichever room compiles


# ------------------------------------------------------- ahead of time
# the entry kernels of a (method, kind), by the name their calls announce them
ENTRIES = {"attractor_rows": "attractor", "slip_cycles_rows": "cycle scan",
           "trajectory": "trajectory", "options": "options",
           "forced_rows": "forced response", "image_rows": "stroboscopic image"}
FORCED_ENTRIES = ("forced_rows", "image_rows")      # a forced kind's only
EXCITED_ENTRIES = ("trajectory", "options")         # every kind's, none included


def _arguments(name: str, lw, ex=_UNFORCED) -> tuple:
    """Arrays of the types the Python rooms call entry ``name`` with (only their
    types matter: the kernel is compiled for them, not run); ``ex``: the
    excitation's data of the entries that take one."""
    from ._kernels.cycles import MAX_CYCLES
    P = np.zeros((1, layout.NP))
    o = np.zeros(layout.NO)
    f, i = np.zeros(1), np.zeros(1, np.int64)
    return {"attractor_rows": (P, lw, o, np.zeros((1, layout.NOBS))),
            "slip_cycles_rows": (P, lw, o, np.zeros((1, MAX_CYCLES, layout.NOBS)), i),
            "trajectory": (P[0], lw, ex, o, f, f, f, i, f, i, f, f, np.zeros(layout.NA)),
            "options": (P[0], lw, ex, o),
            "forced_rows": (P, lw, ex, o, np.zeros((1, layout.NFOB))),
            "image_rows": (P, lw, ex, o, 1,
                           np.zeros((1, layout.NFOB + layout.NIM)))}[name]


def compile_kernels(law=None, method=None) -> list:
    """Compile the kernels of law kind(s) ``law`` and method(s) ``method`` into the
    cache ahead of time (what a first use would compile); see
    :func:`sweepcore.compile`. Returns ``[(what, seconds)]``, seconds None where
    the cache had it."""
    from numba import typeof
    from ._kernels import derived, trajectory as _trajectory
    from .options import did_you_mean
    kinds = [row[0] for row in _kernel_laws.LAWS]
    methods = list(codes.METHOD_CODES)
    law_list = kinds if law in (None, "all") else [law]
    meth_list = ["dop853"] if method is None else methods if method == "all" \
        else [method]
    for label, given, known in (("law", law_list, kinds), ("method", meth_list, methods)):
        bad = [g for g in given if not isinstance(g, str) or g not in known]
        if bad:
            raise ValueError(f"{label} must be one of {', '.join(known)} or 'all', got "
                             f"{bad[0]!r}{did_you_mean(str(bad[0]), known)}")
    done = []

    def build(dispatcher, args, ctx):
        with ctx:
            dispatcher.compile(tuple(typeof(a) for a in args))
        done.append((ctx.name[1], ctx.took))

    build(_trajectory.fresh_acc, (), compiling("accumulator", None, None))
    for kind_name in law_list:
        kind = _kernel_laws.KIND_CODES[kind_name]
        lw = _kernel_laws.SAMPLES[kind_name]
        build(derived.derived_rows, (np.zeros((1, layout.NP)), lw, 0, np.zeros(1)),
              compiling("derived quantities", None, kind))
        for meth_name in meth_list:
            meth = codes.METHOD_CODES[meth_name]
            for name, label in ENTRIES.items():
                for ex in _excitations_of(name, meth_name):
                    build(entries.entry(name, meth), _arguments(name, lw, ex),
                          compiling(label, meth, kind))
    return done


def _excitations_of(name: str, meth_name: str) -> list:
    """The excitations' data entry ``name`` is compiled for: none for the autonomous
    entries, every forced kind's for the forced ones (not for the closed-form arcs,
    which a load makes not applicable), both for the trajectory and the options."""
    from ._kernels import excitations as kinds
    forced = [row[3] for row in kinds.EXCITATIONS[1:]] if meth_name != "exact" else []
    if name in FORCED_ENTRIES:
        return forced
    if name in EXCITED_ENTRIES:
        return [_UNFORCED] + forced
    return [None]


@checked_keywords
def compile(law=None, method=None, quiet=False):
    """Compile the kernels ahead of time into the cache (what a first use compiles).

    Parameters
    ----------
    law : str, optional
        A law kind of the kernels' law table (``"polynomial"``: eq. 40,
        ``"stribeck"``: with the Stribeck term, ``"table"``, ``"leine"``), or
        ``"all"``; default: every kind.
    method : str, optional
        A method (``"exact"``, ``"gps"``, ``"rk4"``, ``"dopri5"``, ``"dop853"``) or
        ``"all"``; default ``"dop853"`` ("auto" at the default tolerance).
    quiet : bool
        No line per kernel (the logger ``"sweepcore.compile"``).

    Returns
    -------
    list of (str, float or None)
        What was compiled and how long it took [s]; None where the cache had it.

    Notes
    -----
    Compiled kernels are kept per install location (numba keys its cache on each
    source file's path and modification time) in ``$SWEEPCORE_CACHE_DIR`` or
    ``~/.cache/sweepcore``; an attractor kernel of one method and kind takes
    tens of seconds of CPU.
    """
    logger = log
    level = logger.level
    if quiet:
        logger.setLevel(logging.ERROR)
    try:
        return compile_kernels(law, method)
    finally:
        logger.setLevel(level)
