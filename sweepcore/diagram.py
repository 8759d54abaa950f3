"""Bifurcation diagrams: attractors followed along one parameter, up and down.

Each point starts from the previous point's attractor, so a branch is followed as
long as it exists: a slip cycle or the equilibrium from its largest ``x``, at rest
(``x0 = x_max``, ``xdot0 = 0``); a stick-slip cycle from the belt (stuck at its
``x_min``): every state on the belt lies outside the slip cycles, which stay below
belt speed, so the stick-slip branch is kept up to its very end (the fold where it
meets the unstable slip cycle). The down scan starts from the last attractor of the
up scan (``sweep="both"``). Coexisting attractors show up as branches that differ
between the two directions (hysteresis: with a subcritical Hopf point the up scan
stays on stick-slip up to the fold, the down scan on steady sliding down to the
Hopf point); with the supercritical Hopf point of Liu's model (docs/physics.md)
they coincide. The unstable slip cycles between the two (the boundary of the
equilibrium's basin) come from the cycle scan (``_kernels/cycles.py``) and are
stored as their own branch, the ``unstable_*`` variables.
"""
from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import xarray as xr

from . import execute, labels, law, variables
from ._kernels import codes, layout
from .boundaries import locate_boundaries
from .grid import AXES, COLUMNS, Grid, checked_grid
from .options import MAX_STEPS_CAP, checked_keywords, did_you_mean, make_options
from .io import check_flag
from .params import LONG_NAMES, UNITS
from .sizing import diagram_need, refuse_unaffordable

BRANCHES = ("up", "down")
SWEEPS = {"up": ("up",), "down": ("down",), "both": BRANCHES}
DIAGRAM_VARIABLES = ("x_max", "x_min", "mean", "amplitude", "floquet", "xdot_max",
                     "period", "stick_fraction")
UNSTABLE_VARIABLES = ("x_max", "x_min", "mean", "amplitude", "floquet", "xdot_max",
                      "period")


# A point whose budget runs out is retried with the budget its linear dynamics need
# (slow_periods), at most this many times the one asked for.
RETRY_CAP = 100.0
SPENT = (codes.UNCONVERGED, codes.STEP_BUDGET)


def slow_periods(row: np.ndarray, tol: float, laws) -> float:
    """Natural periods 2 pi/omega the motion linearised about steady sliding needs
    from the start of the kernel row ``row``: ``(2/|q|) n / T``, q of eq. (46) (the
    amplitude grows or decays as exp(q t/2)), n the e-folds from the start's
    distance ``delta`` from (x_eq, 0) in the (x, xdot/omega) plane to the length
    scale L (q > 0: growing away from an unstable focus, the down scan next to a
    Hopf point) or down to tol L (q < 0), at least 1. A start exactly on x_eq counts
    as 1e-16 L away (rounding is all that moves it). inf where q = 0."""
    src = law.from_row(row, law.row_law(row, laws))
    q, w, x_eq = (float(law.derived(n, src)) for n in ("q", "omega", "x_eq"))
    L = float(law.length_scale(row, laws)[0])
    delta = max(math.hypot(row[layout.X0] - x_eq, row[layout.XD0] / w), 1e-16 * L)
    n = math.log(L / delta) if q > 0.0 else math.log(delta / (tol * L))
    return 2.0 / abs(q) * max(n, 1.0) * w / (2.0 * math.pi) if q != 0.0 else math.inf


def _attractor(row: np.ndarray, laws, o: np.ndarray, out: np.ndarray) -> float:
    """One point into ``out`` (1, NOBS); where its budget runs out, once more with the
    budget :func:`slow_periods` says it needs (twice that, at most RETRY_CAP times
    the one asked for; max_steps raised in proportion). Returns the periods the
    point would need where it still ends unconverged, else 0."""
    execute.attractors(row, laws, o, out, parallel=False)
    if int(out[0, layout.OB_STATUS]) not in SPENT:
        return 0.0
    need = 2.0 * slow_periods(row[0], float(o[layout.O_RTOL]), laws)
    if need > o[layout.O_MAX_TIME]:
        o2 = o.copy()
        o2[layout.O_MAX_TIME] = min(need, RETRY_CAP * o[layout.O_MAX_TIME])
        o2[layout.O_MAX_STEPS] = min(o[layout.O_MAX_STEPS] * o2[layout.O_MAX_TIME]
                                     / o[layout.O_MAX_TIME], MAX_STEPS_CAP)
        execute.attractors(row, laws, o2, out, parallel=False)
    return 0.0 if int(out[0, layout.OB_STATUS]) not in SPENT else max(
        need, o[layout.O_MAX_TIME] * RETRY_CAP)


def _follow(base: np.ndarray, col: int, values, start, o, laws,
            short: list) -> np.ndarray:
    """Observables (len(values), NOBS) along ``values``, each point started from the
    previous attractor (x_max, at rest; stick-slip: stuck on the belt at x_min);
    ``start`` (x0, xdot0 or NaN) for the first and after a point without an
    attractor. ``short`` collects (value, periods needed) of points still
    unconverged after their retry (:func:`_attractor`)."""
    out = np.empty((len(values), layout.NOBS))
    x0, xd0 = start
    row = base.copy()[None, :]
    for i, u in enumerate(values):
        row[0, col] = u
        row[0, layout.X0] = x0
        row[0, layout.XD0] = row[0, layout.V] if np.isnan(xd0) else xd0
        need = _attractor(row, laws, o, out[i:i + 1])
        if need:
            short.append((float(u), need))
        x0, xd0 = _next_start(out[i], start)
    return out


def _warn_short(short, along: str, o) -> None:
    """One warning naming the budget the still-unconverged points need."""
    if not short:
        return
    where = [u for u, _n in short]
    need = max(n for _u, n in short)
    hint = (f"pass max_periods={need:.3g} (and max_steps in proportion)"
            if math.isfinite(need) else "the Hopf point itself (q = 0) converges "
            "algebraically: no budget is enough there")
    warnings.warn(
        f"bifurcation_diagram: {len(short)} point(s) still unconverged at {along} in "
        f"[{min(where):.6g}, {max(where):.6g}] after a retry with up to "
        f"{RETRY_CAP * float(o[layout.O_MAX_TIME]):.3g} periods: the motion "
        f"linearised about steady sliding needs that long (growth or decay at q/2 of "
        f"eq. (46), slow next to the Hopf point); {hint}", RuntimeWarning, stacklevel=3)


def _next_start(obs: np.ndarray, start):
    """The start of the next point from the observables of this one."""
    if int(obs[layout.OB_STATUS]) != codes.OK or not np.isfinite(obs[layout.OB_X_MAX]):
        return start
    if int(obs[layout.OB_REGIME]) == codes.R_STICK_SLIP:
        return obs[layout.OB_X_MIN], math.nan
    return obs[layout.OB_X_MAX], 0.0


def _unstable(base: np.ndarray, along: str, values, o, laws) -> np.ndarray:
    """Observables (len(values), NOBS) of the largest unstable slip cycle at each
    value (NaN where none): :func:`sweepcore.boundaries.fold.unstable_cycles`."""
    from .boundaries.fold import unstable_cycles
    from .boundaries.point import _Point
    return unstable_cycles(_Point(base, along, laws=laws), values, o)


@checked_keywords(options=True)
def bifurcation_diagram(grid: Grid, along: str = "v", boundaries: bool = True,
                        tol: float = 1e-10, method: str = "auto", sweep: str = "both",
                        unstable: bool = True, **options) -> xr.Dataset:
    """Attractors along ``along``, followed up and down (hysteresis scan).

    Parameters
    ----------
    grid : Grid
        ``along`` swept (its values, in any order, are sorted), every other
        parameter fixed; x0 and xdot0 give the start of the first point of the up
        scan (default: stuck on the belt).
    along : str
        The parameter of the diagram, default the belt speed v.
    boundaries : bool
        Also locate the Hopf point and the stick onset inside the range
        (:func:`sweepcore.locate_boundaries`) and store them, to mark them.
    sweep : {"both", "up", "down"}
        Direction of the scan: "up" (increasing ``along``, from the grid's start
        at the lowest value), "down" (decreasing, from that start at the highest
        value) or "both" (up, then down from the up scan's last attractor).
    unstable : bool
        Also store the unstable slip cycles (the ``unstable_*`` variables; not with
        ``method="gps"``, whose discrete map has its own cycles).
    tol, method, **options
        As :func:`sweepcore.attractor`. A point whose budget (``max_periods``,
        ``max_steps``) runs out is retried once with the budget that the motion
        linearised about steady sliding needs from its start (:func:`slow_periods`:
        next to a Hopf point the down scan starts beside a weakly unstable focus),
        up to 100 times ``max_periods``; a point still unconverged then is kept as
        such and a warning names the ``max_periods`` it would need.

    Returns
    -------
    xarray.Dataset
        Dimensions ``branch`` (the scans of ``sweep``) and ``along``: x_max,
        x_min, mean, amplitude, floquet, xdot_max, period, stick_fraction (units
        from :data:`sweepcore.variables.OBSERVABLES`), regime and status flags;
        with ``unstable``, ``unstable_x_max`` ... ``unstable_period`` over
        ``along`` (NaN where there is none); the analytic ``v_star`` and
        ``hopf_criticality``; with ``boundaries``, ``v_hopf``, ``v_stick_onset``,
        ``v_hopf_subcritical`` and ``v_fold``.
    """
    if sweep not in SWEEPS:
        raise ValueError(f"sweep must be one of {tuple(SWEEPS)}, got {sweep!r}")
    if along not in AXES[:6]:
        raise ValueError(f"along must be one of {AXES[:6]}, got {along!r}"
                         f"{did_you_mean(along, AXES[:6])}")
    checked_grid(grid)
    check_flag("boundaries", boundaries)
    check_flag("unstable", unstable)
    swept = [n for n in grid.swept if n != along]
    values = grid.axis(along)
    if not isinstance(values, np.ndarray) or values.size < 2 or swept:
        raise ValueError(f"a diagram needs {along!r} swept with >= 2 values and every "
                         f"other parameter fixed; swept: {grid.swept}")
    if method == "gps" and unstable:
        raise ValueError("unstable=True needs the ODE's return map (the unstable slip "
                         "cycles are its fixed points); method='gps' follows its own "
                         "discrete map: pass unstable=False, or another method")
    o = make_options(method, tol=tol, **options)
    refuse_unaffordable(diagram_need(values.size, len(SWEEPS[sweep])))
    values = np.sort(values)
    at_first = dataclasses.replace(grid, **{along: float(values[0])})
    base = at_first.rows(0, 1)[0]
    x0, xd0 = grid.axis("x0"), grid.axis("xdot0")
    start = (x0, math.nan if xd0 is None else xd0)
    col = COLUMNS[along]
    scans, short = [], []
    if sweep != "down":
        scans.append(_follow(base, col, values, start, o, grid.laws, short))
    if sweep != "up":
        first = _next_start(scans[0][-1], start) if scans else start
        scans.append(_follow(base, col, values[::-1], first, o, grid.laws, short)[::-1])
    _warn_short(short, along, o)
    cols = np.stack(scans)                      # (branch, along, NOBS)

    dims = ("branch", along)
    data = {}
    for name in DIAGRAM_VARIABLES:
        c, *meta = variables.OBSERVABLES[name]
        data[name] = (dims, cols[:, :, c], labels.attrs(*meta))
    for name, meta in (("regime", variables.REGIME), ("status", variables.STATUS)):
        c = layout.OB_REGIME if name == "regime" else layout.OB_STATUS
        data[name] = (dims, cols[:, :, c].astype(np.int8), labels.flag_attrs(meta))
    coords = {n: v for n, v in at_first.coords().items()
              if n not in (along, "x0", "xdot0")}
    coords[along] = xr.Variable(along, values, {"units": UNITS[along],
                                                "long_name": LONG_NAMES[along]})
    coords["branch"] = xr.Variable("branch", np.array(SWEEPS[sweep]), {
        "units": "1", "long_name": "direction of the scan (each point started "
                                   "from the previous attractor)"})
    if unstable:
        cyc = _unstable(base, along, values, o, grid.laws)
        for name in UNSTABLE_VARIABLES:
            c, units, long_name, *rest = variables.OBSERVABLES[name]
            data["unstable_" + name] = ((along,), cyc[:, c], labels.attrs(
                units, long_name.replace("the attractor", "the cycle")
                + " (unstable slip cycle)",
                "largest slip cycle with Floquet multiplier > 1 (cycle scan of the "
                "return map); NaN where there is none"))
    ds = xr.Dataset(data, coords)
    ds["v_star"] = labels.analytic("v_star", ds, laws=grid.laws).variable
    kind = labels.criticality(ds, grid.laws)
    ds["hopf_criticality"] = xr.Variable(kind.dims, kind.values, labels.flags(
        law.CRITICALITY, "kind of the Hopf point v_star (sign of F''' there: of the "
                         "first Lyapunov coefficient)"))
    if boundaries:
        found = locate_boundaries(dataclasses.replace(grid, **{along: values}), along=along,
                                  tol=min(tol, 1e-10), method=method, **options)
        for name in ("v_hopf", "v_stick_onset", "v_hopf_subcritical", "v_fold"):
            ds[name] = xr.Variable((), float(found[name].values), found[name].attrs)
    ds.attrs.update({
        **labels.provenance(
            f"Bifurcation diagram of the stick-slip friction oscillator along {along}",
            f"sweepcore.bifurcation_diagram({grid!r}, along={along!r}, tol={tol!r}, "
            f"method={method!r}, sweep={sweep!r}, unstable={unstable!r})",
            "attractors followed up and/or down, each started from the previous one "
            "(x0 = x_max, xdot0 = 0; stick-slip: stuck on the belt at x_min)",
            "Units kN, cm, s."),
        "sweepcore_kind": "bifurcation_diagram",
        "along": along,
        "tol": float(tol),
        "sweep": sweep,
    })
    return ds
