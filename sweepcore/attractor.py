"""The attractor of one point: observables reduced on line, with their status."""
from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from . import execute, forced
from ._kernels import codes, layout
from .options import check_method, checked_keywords, make_options
from .params import Params
from .simulate import start_row
from .variables import OBSERVABLES


@dataclass(frozen=True)
class Attractor:
    """Observables of one attractor (units: cm, s; see ``sweepcore.variables``).

    ``converged`` is True only when the attractor was recognised (status "ok");
    otherwise the numbers are the last measured period's estimates (unconverged) or
    NaN (failed), and ``regime``/``status`` say which.
    """

    amplitude: float
    mean: float
    velocity_amplitude: float
    cycle_size: float
    period: float
    stick_fraction: float
    sticks_per_period: float
    t_settle: float
    x_max: float
    x_min: float
    xdot_max: float
    floquet: float
    n_steps: int
    regime: str
    status: str
    converged: bool
    q: float
    v_star: float
    x_eq: float
    eigenvalues: tuple

    def to_dict(self) -> dict:
        return asdict(self)


@checked_keywords(options=True)
def attractor(params: Params, x0: float = 0.0, xdot0: float | None = None,
              method: str = "auto", tol: float = 1e-8, **options) -> Attractor:
    """Find the attractor reached from (x0, xdot0) and measure it on line.

    Parameters
    ----------
    params : Params
    x0, xdot0 : float
        Start [cm], [cm/s]; ``xdot0=None`` starts stuck on the belt.
    method : str
        "auto" or a stepper of ``sweepcore.options.METHODS`` (the method table of
        ``sweepcore._kernels.codes``).
    tol : float
        Accuracy asked of the observables, relative to the point's length scale
        L = r_y/k + |v|/omega: the adaptive stepper's tolerance, tightened per cycle where the
        cycle's weak contraction amplifies the integration error.
    **options
        dt, max_steps, max_periods, gps_a, graze (see ``make_options``).

    Returns
    -------
    Attractor, or sweepcore.forced.Response for a forced slider (F0 or Y0 given):
    the steady response the start settles on, a fixed point of the stroboscopic map
    (``periods``: the largest multiplicity sought).

    Notes
    -----
    The search (``sweepcore/_kernels/attractor.py``) stops at the first whole period
    after a reset to the breakaway point (stick-slip), at the fixed point of the return
    map solved by Newton's method with a verified residual (slip cycles; ``floquet``
    is the map's slope there), or when an energy certificate or the Hopf normal form
    proves decay to x_eq (equilibrium). Observables are accurate to about
    ``tol * L`` (L = r_y/k + |v|/omega). A cycle next to v* that float64 integration
    cannot resolve to ``tol`` and the normal form cannot either has status
    ``"unresolved"`` (its numbers are estimates). A point whose magnitudes no search
    resolves has status ``"unresolvable_scale"``, as in :func:`sweepcore.sweep`: both
    run the kernel through :func:`sweepcore.execute.attractors`, which applies the
    rule of :func:`sweepcore.law.flag_unresolvable`.
    """
    row = start_row(params, x0, xdot0)
    if params.forced:
        forced.check_method(method)
        return forced.response(params, row, make_options(method, tol=tol, **options))
    check_method(method, params)
    out = np.empty((1, layout.NOBS))
    # the one call of the kernel that sweep, the boundaries and the diagrams share:
    # the kernel, then the scale rule (sweepcore.law.flag_unresolvable)
    execute.attractors(row[None, :], (params.friction_law,),
                       make_options(method, tol=tol, **options), out, parallel=False)
    out = out[0]
    status = int(out[layout.OB_STATUS])
    vals = {name: float(out[col]) for name, (col, *_rest) in OBSERVABLES.items()}
    vals["n_steps"] = int(vals["n_steps"])
    return Attractor(**vals, regime=codes.REGIME_NAMES[int(out[layout.OB_REGIME])],
                     status=codes.STATUS_NAMES[status], converged=status == codes.OK,
                     q=params.q, v_star=params.v_star, x_eq=params.x_eq,
                     eigenvalues=params.eigenvalues)
