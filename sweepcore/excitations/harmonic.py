"""A harmonic load on the slider and a harmonic motion of the anchor: both enter the
slider's equation as one harmonic force (``sweepcore/_kernels/excitations/harmonic.py``),
solved by the forced kernels (``sweepcore/_kernels/forced_attractor.py``) with the
eighth-order pair (its step with time, ``sweepcore/_kernels/forced_step.py``)."""
import numpy as np

from .._kernels import entries, layout, stepper
from .._kernels.excitations import harmonic as _kernel

NAME = "harmonic"
DATA = _kernel.Harmonic()
METHOD = stepper.DOP853


def run(P: np.ndarray, laws, o: np.ndarray, out: np.ndarray, parallel: bool) -> None:
    """The steady response of every row into ``out`` (n, NFOB), one group of rows per
    law kind on the forced entry kernel (compiled on first use)."""
    from .. import compiled
    o = o.copy()
    o[layout.O_METHOD] = METHOD
    kernel = entries.entry("forced_rows", METHOD)
    which = P[:, layout.LAW].astype(np.intp)
    for i, law in enumerate(laws):
        mine = np.flatnonzero(which == i)
        if not mine.size:
            continue
        for kind, sub, lw in law.kernel_groups(P[mine]):
            rows = mine[sub]
            block = np.ascontiguousarray(P[rows])
            res = np.empty((rows.size, layout.NFOB))
            with compiled.compiling("forced response", METHOD, kind):
                _threads(kernel, block, lw, o, res, parallel)
            out[rows] = res
    _flag_neutral(P, laws, out)


def _flag_neutral(P: np.ndarray, laws, out: np.ndarray) -> None:
    """Den Hartog's slider (constant friction, c = 0, v = 0) at Omega/omega = 1/(2 n):
    a neutral family of responses (``theory.neutral_family``), whose member a start
    picks only on the time scale of a multiplier 1; its numbers are flagged, never a
    confident amplitude (regime neutral, status unresolved). The search's own
    multiplier there is 1 to the accuracy of its Jacobian, not exactly."""
    from .. import law
    from .._kernels import codes
    from .theory import neutral_family
    with np.errstate(all="ignore"):
        family = neutral_family(P[:, layout.M], P[:, layout.K], P[:, layout.OMEGA],
                                P[:, layout.C], P[:, layout.V])
    family = np.asarray(family) & law.per_law(P, laws, "closed_form", bool)
    family &= out[:, layout.OB_REGIME] != codes.R_STUCK
    family &= out[:, layout.OB_STATUS] == codes.OK
    out[family, layout.OB_REGIME] = codes.R_NEUTRAL
    out[family, layout.OB_STATUS] = codes.UNRESOLVED


def trajectory(row: np.ndarray, lw, kind: int, o: np.ndarray, *arrays):
    """One run of the forced driver from ``row``: ``(n_events, status, n_steps)``."""
    from .. import compiled
    o = o.copy()
    o[layout.O_METHOD] = METHOD
    with compiled.compiling("forced trajectory", METHOD, kind):
        return entries.entry("forced_trajectory", METHOD)(row, lw, DATA, o, *arrays)


def _threads(kernel, P, lw, o, out, parallel):
    """The kernel over the rows, on numba's thread count of Python threads when
    ``parallel`` (the kernels release the GIL; blocks of rows taken in turn, so a
    thread that drew costly points takes fewer)."""
    import itertools
    from concurrent.futures import ThreadPoolExecutor

    import numba
    n = P.shape[0]
    threads = min(numba.get_num_threads(), n) if parallel else 1
    if threads <= 1:
        kernel(P, lw, DATA, o, out)
        return
    kernel(P[:1], lw, DATA, o, out[:1])         # compile once, not per thread
    block = max(1, min(8, (n - 1) // (4 * threads)))
    starts = itertools.count(1, block)

    def work(_):
        for a in starts:
            if a >= n:
                return
            b = min(a + block, n)
            kernel(P[a:b], lw, DATA, o, out[a:b])
    with ThreadPoolExecutor(threads) as pool:
        list(pool.map(work, range(threads)))


def load(params, t: np.ndarray) -> np.ndarray:
    """``F0 cos(Omega t + phi) + k Y0 cos(Omega t) - c Omega Y0 sin(Omega t)`` [kN]."""
    w = params.Omega * np.asarray(t, np.float64)
    return (params.F0 * np.cos(w + params.phi) + params.k * params.Y0 * np.cos(w)
            - params.c * params.Omega * params.Y0 * np.sin(w))
