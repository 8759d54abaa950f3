"""The kernels Python calls, one per method, each compiled on first use.

Every entry point below is made for one method code of ``stepper.METHODS`` (a
compile-time constant of the closure) and compiled for the class of the law data
it is first called with, so a run compiles only the (method, law kind) pairs it
uses; numba's cache keeps each pair apart (its key holds the closure's method
code). ``entry(name, method)`` returns the kernel; the Python side
(``sweepcore.compiled``) groups the rows of a call by law kind and method.
Every entry releases the GIL: Python threads share a call's rows
(``sweepcore.compiled``), and dask's threads its chunks.
"""
import functools

import numpy as np

from . import attractor, cycles, strobe, trajectory
from .excitation import prepare, with_work, work_size
from .jit import kernel, unowned
from .law import borrowed


def _attractor_rows(meth):
    @kernel(entry=True, nogil=True)
    def attractor_rows(P, lw, o, out):
        """The attractor of every row of P (serial: for dask tasks and threads)."""
        P, lw, o, out = unowned(P), borrowed(lw), unowned(o), unowned(out)
        owner = np.empty(attractor.WORKSPACE)
        ws = unowned(owner)
        for i in range(P.shape[0]):
            attractor.attractor_point(meth, P[i], lw, o, out[i], ws)
        owner[0] = 0.0                  # the workspace lives until here
    return attractor_rows


def _slip_cycles_rows(meth):
    @kernel(entry=True, nogil=True)
    def slip_cycles_rows(P, lw, o, out, found):
        """``cycles.slip_cycles`` of every row of P; ``out`` (n, MAX_CYCLES, NOBS),
        ``found`` (n,) the number of cycles of each row."""
        lw = borrowed(lw)
        for i in range(P.shape[0]):
            found[i] = cycles.slip_cycles(meth, P[i], lw, o, out[i])
    return slip_cycles_rows


def _trajectory(meth):
    @kernel(entry=True, nogil=True)
    def run_trajectory(p, lw, ex, o, t_samples, out_x, out_zd, out_mode, ev_t, ev_kind,
                       ev_x, ev_zd, acc):
        """``trajectory.run_trajectory`` of one row under the excitation ``ex``."""
        owner = np.zeros(work_size(ex))
        n = trajectory.run_trajectory(meth, p, borrowed(lw), with_work(ex, unowned(owner)),
                                      o, t_samples, out_x, out_zd, out_mode, ev_t, ev_kind,
                                      ev_x, ev_zd, acc)
        owner[:] = 0.0                  # the work array lives until here
        return n
    return run_trajectory


def _options(meth):
    @kernel(entry=True)
    def options(p, lw, ex, o):
        """The option row of one point (``attractor.resolve_options``) and the
        method's a-priori status (``attractor.method_status``)."""
        lw = borrowed(lw)
        owner = np.zeros(work_size(ex))
        fx = with_work(ex, unowned(owner))
        prepare(fx, p, lw)
        oo = attractor.resolve_options(meth, p, lw, fx, o)
        status = attractor.method_status(meth, p, lw, fx, oo)
        owner[:] = 0.0                  # the work array lives until here
        return oo, status
    return options


def _forced_rows(meth):
    @kernel(entry=True, nogil=True)
    def forced_rows(P, lw, ex, o, out):
        """The steady response of every row of P under the excitation ``ex``
        (``strobe.strobe_point``; ``out`` (n, NFOB))."""
        P, lw, o, out = unowned(P), borrowed(lw), unowned(o), unowned(out)
        owner = np.zeros(work_size(ex))
        fx = with_work(ex, unowned(owner))
        space = np.empty(strobe.WORKSPACE)
        ws = unowned(space)
        for i in range(P.shape[0]):
            strobe.strobe_point(meth, P[i], lw, fx, o, out[i], ws)
        owner[:] = 0.0                  # the work arrays live until here
        space[0] = 0.0
    return forced_rows


def _image_rows(meth):
    @kernel(entry=True, nogil=True)
    def image_rows(P, lw, ex, o, n, out):
        """``strobe.image_point`` of every row of P: P^n of its start, with the
        tangent and the run's observables (``out`` (rows, NFOB + NIM))."""
        P, lw, o, out = unowned(P), borrowed(lw), unowned(o), unowned(out)
        owner = np.zeros(work_size(ex))
        fx = with_work(ex, unowned(owner))
        space = np.empty(strobe.WORKSPACE)
        ws = unowned(space)
        for i in range(P.shape[0]):
            strobe.image_point(meth, P[i], lw, fx, o, n, out[i], ws)
        owner[:] = 0.0                  # the work arrays live until here
        space[0] = 0.0
        space[0] = 0.0
    return image_rows


FACTORIES = {"attractor_rows": _attractor_rows,
             "image_rows": _image_rows,
             "forced_rows": _forced_rows,
             "slip_cycles_rows": _slip_cycles_rows,
             "trajectory": _trajectory,
             "options": _options}


@functools.lru_cache(maxsize=None)
def entry(name: str, method: int):
    """The entry kernel ``name`` (a key of ``FACTORIES``) for method code ``method``."""
    return FACTORIES[name](int(method))
