"""The forced response: the steady motion of an excited slider.

Rows whose excitation is ``none`` (F0 = Y0 = 0) run on the autonomous attractor
search exactly as without an excitation (``sweepcore.execute.attractors``); the
others on the stroboscopic search (``sweepcore/_kernels/strobe.py``: the fixed point
of least period n <= ``periods`` of the stroboscopic map), both over the one driver,
compiled for the (method, law kind) a call uses and only then (a new load shape is
data). Both fill rows of the forced layout (``layout.NFOB``): the autonomous columns
first, then multiplicity, stops per period, the Lyapunov exponent with its error and
the periodic point (NaN for an unforced row).
"""
from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from . import excitations, variables
from ._kernels import codes, layout

# every method but the closed-form arcs, whose law is autonomous ("auto": dop853)
METHODS = tuple(m for m in ("auto",) + tuple(codes.METHOD_CODES) if m != "exact")


def check_method(method: str) -> None:
    """Refuse a method the forced slider cannot use, by name."""
    if method not in METHODS:
        raise ValueError(f"method {method!r} is not available for a forced slider "
                         f"(F0 or Y0 given): the closed-form arcs need the autonomous "
                         f"field; use one of {', '.join(METHODS)}")


def responses(P: np.ndarray, laws, loads, o: np.ndarray, out: np.ndarray,
              parallel: bool = False) -> None:
    """The steady response of every row of P into ``out`` (n, NFOB): each
    excitation kind's rows by its module (``sweepcore.excitations``); ``loads``: the
    call's load shapes (``layout.LOAD`` indexes them)."""
    for module, rows in excitations.groups(P):
        block = np.ascontiguousarray(P[rows]) if rows.size < P.shape[0] else P
        res = np.empty((rows.size, layout.NFOB))
        module.run(block, laws, loads, o, res, parallel)
        out[rows] = res


@dataclass(frozen=True)
class Response:
    """The steady response of one forced slider (units: cm, s; the variables of
    ``sweepcore.variables.FORCED_OBSERVABLES``).

    ``converged`` is True only for status "ok": the numbers are within the asked
    tolerance of the response a long simulation from the start settles on. An
    aperiodic response has NaN multiplicity and period, and its Lyapunov exponent
    with an error. ``x_section``, ``xdot_section`` are the periodic point: the state
    at t = 0 mod n T (the stroboscopic map's fixed point, to check with any
    integrator). ``omega``, ``v_star`` and ``x_eq`` are the unforced slider's.
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
    x_section: float
    xdot_section: float
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
    responses(row[None, :], (params.friction_law,), params.loads, o, out, parallel=False)
    out = out[0]
    status = int(out[layout.OB_STATUS])
    vals = {name: float(out[col]) for name, (col, *_r) in
            variables.FORCED_OBSERVABLES.items()}
    vals["n_steps"] = int(vals["n_steps"])
    return Response(**vals, regime=codes.REGIME_NAMES[int(out[layout.OB_REGIME])],
                    status=codes.STATUS_NAMES[status], converged=status == codes.OK,
                    omega=params.omega, v_star=params.v_star, x_eq=params.x_eq)
