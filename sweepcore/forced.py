"""The forced response: the steady motion of an excited slider, on the forced kernels.

Rows whose excitation is ``none`` (F0 = Y0 = 0) run on the autonomous attractor
kernel exactly as without an excitation (``sweepcore.execute.attractors``); the
others on ``sweepcore/_kernels/forced_attractor.py`` (the stroboscopic map's fixed
point of least period n <= ``periods``), compiled for the (law kind, excitation
kind) a call uses and only then. Both fill rows of the forced layout
(``layout.NFOB``): the autonomous columns first, then multiplicity, stops per
period and the Lyapunov exponent with its error (NaN for an unforced row).
"""
from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from . import compiled, execute, excitations, variables
from ._kernels import codes, entries, layout, stepper
from ._kernels.excitations import EXCITATIONS as _KERNEL_EXCITATIONS

# the forced kernels integrate with the eighth-order pair (its step with time)
METHOD = stepper.DOP853
METHODS = ("auto", "dop853")


def check_method(method: str) -> None:
    """Refuse a method the forced kernels do not have, by name."""
    if method not in METHODS:
        raise ValueError(f"method {method!r} is not available for a forced slider "
                         f"(F0 or Y0 given): its response is integrated with dop853 "
                         f"(method 'auto' or 'dop853')")


def responses(P: np.ndarray, laws, o: np.ndarray, out: np.ndarray,
              parallel: bool = False) -> None:
    """The steady response of every row of P into ``out`` (n, NFOB)."""
    kind = excitations.kinds(P)
    out[:, layout.NOBS:] = np.nan
    still = np.flatnonzero(kind == 0)
    if still.size:
        sub = np.empty((still.size, layout.NOBS))
        execute.attractors(np.ascontiguousarray(P[still]), laws, o, sub, parallel)
        out[still, :layout.NOBS] = sub
    moved = np.flatnonzero(kind != 0)
    if not moved.size:
        return
    Pm = np.ascontiguousarray(P[moved])
    sub = np.empty((moved.size, layout.NFOB))
    o_forced = o.copy()
    o_forced[layout.O_METHOD] = METHOD
    which = Pm[:, layout.LAW].astype(np.intp)
    ex = _KERNEL_EXCITATIONS[1][3]
    kernel = entries.entry("forced_rows", METHOD)
    for i, law in enumerate(laws):
        mine = np.flatnonzero(which == i)
        if not mine.size:
            continue
        for lkind, rows_, lw in law.kernel_groups(Pm[mine]):
            rows = mine[rows_]
            block = np.ascontiguousarray(Pm[rows])
            res = np.empty((rows.size, layout.NFOB))
            with compiled.compiling("forced response", METHOD, lkind):
                _run(kernel, block, lw, ex, o_forced, res, parallel)
            sub[rows] = res
    out[moved] = sub


def _run(kernel, P, lw, ex, o, out, parallel):
    """The kernel over the rows, on numba's thread count of Python threads when
    ``parallel`` (the kernels release the GIL; blocks of rows taken in turn)."""
    import numba
    from concurrent.futures import ThreadPoolExecutor
    n = P.shape[0]
    threads = min(numba.get_num_threads(), n) if parallel else 1
    if threads <= 1:
        kernel(P, lw, ex, o, out)
        return
    kernel(P[:1], lw, ex, o, out[:1])       # compile once, not per thread
    block = 8
    starts = list(range(1, n, block))

    def work(a):
        b = min(a + block, n)
        kernel(P[a:b], lw, ex, o, out[a:b])
    with ThreadPoolExecutor(threads) as pool:
        list(pool.map(work, starts))


def trajectory(row: np.ndarray, law, o: np.ndarray, *arrays):
    """One run of the forced driver from ``row``: ``(n_events, status, n_steps,
    method)``, as ``sweepcore.compiled.trajectory``."""
    P = row[None, :]
    ((_meth, lkind, _rows, lw),) = compiled.groups(P, (law,), o)
    o_forced = o.copy()
    o_forced[layout.O_METHOD] = METHOD
    ex = _KERNEL_EXCITATIONS[1][3]
    with compiled.compiling("forced trajectory", METHOD, lkind):
        n_ev, status, n_steps = entries.entry("forced_trajectory", METHOD)(
            row, lw, ex, o_forced, *arrays)
    return n_ev, status, n_steps, METHOD


@dataclass(frozen=True)
class Response:
    """The steady response of one forced slider (units: cm, s; the variables of
    ``sweepcore.variables.FORCED_OBSERVABLES``).

    ``converged`` is True only for status "ok": the numbers are within the asked
    tolerance of the response a long simulation from the start settles on. An
    aperiodic response has NaN multiplicity and period, and its Lyapunov exponent
    with an error. ``omega``, ``v_star`` and ``x_eq`` are the unforced slider's.
    """

    multiplicity: float
    period: float
    amplitude: float
    mean: float
    x_max: float
    x_min: float
    xdot_max: float
    velocity_amplitude: float
    sticks_per_period: float
    stops_per_period: float
    stick_fraction: float
    floquet: float
    lyapunov: float
    lyapunov_error: float
    t_settle: float
    n_steps: int
    regime: str
    status: str
    converged: bool
    omega: float
    v_star: float
    x_eq: float

    def to_dict(self) -> dict:
        return asdict(self)


def response(params, row: np.ndarray, o: np.ndarray) -> Response:
    """The steady response from the start in ``row`` (``sweepcore.attractor`` for a
    forced slider)."""
    out = np.empty((1, layout.NFOB))
    responses(row[None, :], (params.friction_law,), o, out, parallel=False)
    out = out[0]
    status = int(out[layout.OB_STATUS])
    vals = {name: float(out[col]) for name, (col, *_r) in
            variables.FORCED_OBSERVABLES.items()}
    vals["n_steps"] = int(vals["n_steps"])
    return Response(**vals, regime=codes.REGIME_NAMES[int(out[layout.OB_REGIME])],
                    status=codes.STATUS_NAMES[status], converged=status == codes.OK,
                    omega=params.omega, v_star=params.v_star, x_eq=params.x_eq)
