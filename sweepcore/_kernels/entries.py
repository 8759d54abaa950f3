"""The kernels Python calls, one per method, each compiled on first use.

Every entry point below is made for one method code of ``stepper.METHODS`` (a
compile-time constant of the closure) and compiled for the class of the law data
it is first called with, so a run compiles only the (method, law kind) pairs it
uses; numba's cache keeps each pair apart (its key holds the closure's method
code). ``entry(name, method)`` returns the kernel; the Python side
(``sweepcore.compiled``) groups the rows of a call by law kind and method.

The parallel variants deal the rows into ``LANES`` interleaved lanes (lane b: rows
b, b + LANES, ...) and prange splits the lanes, so every thread gets a sample of
every region of a grid (cost is clustered: slip cycles next to v* cost ~10x a
stick-slip point); many more lanes than threads, and prime, so that a lane never
lines up with a grid axis (256 lanes on a 256 x 256 map put one alpha2 in each
lane, and split the threads by alpha2, the costly direction).
"""
import functools

from numba import prange

from . import attractor, cycles, trajectory
from .jit import kernel

LANES = 1021


def _attractor_rows(meth):
    @kernel(nogil=True)
    def attractor_rows(P, lw, o, out):
        """The attractor of every row of P (serial: for dask tasks and threads)."""
        for i in range(P.shape[0]):
            attractor.attractor_point(meth, P[i], lw, o, out[i])
    return attractor_rows


def _attractor_rows_parallel(meth):
    @kernel(parallel=True)
    def attractor_rows_parallel(P, lw, o, out):
        """The attractor of every row of P on numba's threads (module docstring)."""
        n = P.shape[0]
        lanes = min(LANES, n)
        for b in prange(lanes):
            for i in range(b, n, lanes):
                attractor.attractor_point(meth, P[i], lw, o, out[i])
    return attractor_rows_parallel


def _slip_cycles_rows(meth):
    @kernel(nogil=True)
    def slip_cycles_rows(P, lw, o, out, found):
        """``cycles.slip_cycles`` of every row of P; ``out`` (n, MAX_CYCLES, NOBS),
        ``found`` (n,) the number of cycles of each row."""
        for i in range(P.shape[0]):
            found[i] = cycles.slip_cycles(meth, P[i], lw, o, out[i])
    return slip_cycles_rows


def _slip_cycles_rows_parallel(meth):
    @kernel(parallel=True)
    def slip_cycles_rows_parallel(P, lw, o, out, found):
        """``slip_cycles_rows`` on numba's threads, in interleaved lanes."""
        n = P.shape[0]
        lanes = min(LANES, n)
        for b in prange(lanes):
            for i in range(b, n, lanes):
                found[i] = cycles.slip_cycles(meth, P[i], lw, o, out[i])
    return slip_cycles_rows_parallel


def _trajectory(meth):
    @kernel(nogil=True)
    def run_trajectory(p, lw, o, t_samples, out_x, out_zd, out_mode, ev_t, ev_kind,
                       ev_x, ev_zd, acc):
        """``trajectory.run_trajectory`` of one row."""
        return trajectory.run_trajectory(meth, p, lw, o, t_samples, out_x, out_zd,
                                         out_mode, ev_t, ev_kind, ev_x, ev_zd, acc)
    return run_trajectory


def _options(meth):
    @kernel
    def options(p, lw, o):
        """The option row of one point (``attractor.resolve_options``) and the
        method's a-priori status (``attractor.method_status``)."""
        oo = attractor.resolve_options(meth, p, lw, o)
        return oo, attractor.method_status(meth, p, lw, oo)
    return options


FACTORIES = {"attractor_rows": _attractor_rows,
             "attractor_rows_parallel": _attractor_rows_parallel,
             "slip_cycles_rows": _slip_cycles_rows,
             "slip_cycles_rows_parallel": _slip_cycles_rows_parallel,
             "trajectory": _trajectory,
             "options": _options}


@functools.lru_cache(maxsize=None)
def entry(name: str, method: int):
    """The entry kernel ``name`` (a key of ``FACTORIES``) for method code ``method``."""
    return FACTORIES[name](int(method))
