"""Frequency-response curves and stroboscopic bifurcation diagrams of a forced slider.

A frequency-response curve follows the steady response (``sweepcore.attractor`` of a
forced slider) along the excitation frequency Omega, up and down, each point started
from its neighbour's response: from the state the slider has at a whole number of
forcing periods once it has settled (a point of the stroboscopic map's cycle, at the
forcing phase t = 0 every point shares). A branch is so kept as long as it exists;
where two steady responses coexist the up and down sweeps differ over a band and
jump at its two ends (hysteresis), as ``sweepcore.bifurcation_diagram`` shows for
the belt speed v.

The stroboscopic diagram samples x at t = j T, T = 2 pi/Omega, for the last
``periods`` forcing periods of a long simulation at each value of a parameter: one
dot for a response of period T, n dots for period n T, a cloud for an aperiodic one.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import xarray as xr

from . import excitations, labels, variables
from .grid import Grid, _check_axis
from .options import checked_keywords, did_you_mean
from .params import LONG_NAMES, UNITS, Params, check_real
from .sizing import refuse_unaffordable, strobe_need

DIRECTIONS = {"up": ("up",), "down": ("down",), "both": ("up", "down")}
# relative difference of the two sweeps' amplitudes that marks two coexisting
# responses: far above the 1e-6 accuracy contract of an ok response
COEXIST_REL = 1e-4
# forcing periods a start is settled for at most (settled_state)
SETTLE_CAP = 4000
# samples of one simulation (sweepcore.simulate's output_dt rule: below 10^7)
STROBE_SAMPLES = 10_000_000


def _checked(params, name: str, values, x0, xdot0) -> np.ndarray:
    """The values along ``name`` (sorted) of the forced slider ``params``, checked
    as ``Grid`` checks an axis (real numbers, finite, in the parameter's range,
    distinct; then every slider, as ``Grid.points``), and the start (x0, xdot0),
    before any work; a refusal names the argument and the value."""
    if not isinstance(params, Params):
        raise TypeError(f"params must be a sweepcore.Params, got {type(params).__name__}")
    if not params.forced:
        raise ValueError("params must be a forced slider: give F0 or Y0 (and Omega)")
    fields = [f.name for f in dataclasses.fields(Params) if f.name != "law"]
    if not isinstance(name, str) or name not in fields:
        raise ValueError(f"name must be a parameter of Params, got {name!r}"
                         f"{did_you_mean(str(name), fields)}")
    check_real("x0", x0)
    if xdot0 is not None:
        check_real("xdot0", xdot0)
    if isinstance(values, (str, bytes)) or not isinstance(values, (list, tuple,
                                                                   np.ndarray)):
        raise TypeError(f"{name} must be a 1-D array of >= 2 values, got {values!r} of "
                        f"type {type(values).__name__}")
    checked = _check_axis(name, values, unique=True)
    if not isinstance(checked, np.ndarray) or checked.size < 2:
        raise ValueError(f"{name} must be a 1-D array of >= 2 values, got {values!r}")
    # every slider along the values, checked at once as a Grid checks its axes
    Grid(**{**params.values(), **params.excitation_values(), name: checked},
         mode="points")
    return np.sort(checked)


def _checked_direction(direction) -> None:
    if not isinstance(direction, str) or direction not in DIRECTIONS:
        hint = did_you_mean(direction, list(DIRECTIONS)) if isinstance(direction, str) \
            else f" of type {type(direction).__name__}"
        raise ValueError(f"direction must be one of {tuple(DIRECTIONS)}, got "
                         f"{direction!r}{hint}")


def _fixed(params: Params, along: str) -> dict:
    """The slider's parameters and excitation but ``along``, as scalar coordinates
    with units."""
    values = {**params.values(), **params.excitation_values()}
    return {n: xr.Variable((), float(v), {"units": UNITS[n], "long_name": LONG_NAMES[n]})
            for n, v in values.items() if v is not None and n not in ("law", along)}


def settled_state(params: Params, response, x0: float, xdot0) -> tuple[float, float]:
    """The state (x [cm], xdot [cm/s]) at a whole number of forcing periods T on the
    trajectory from (x0, xdot0) once it has settled on ``response``: a point of the
    stroboscopic cycle, at forcing phase 0.

    The search finds the response by Newton before the trajectory has settled on it,
    so the run goes on past ``t_settle`` for the periods the response's largest
    multiplier ``floquet`` needs to shrink the remaining distance by 1e-9
    (ln 1e-9 / ln floquet response periods; one where a stick makes it 0; at most
    ``SETTLE_CAP`` forcing periods)."""
    from .simulate import simulate
    T = 2.0 * math.pi / params.Omega
    # an aperiodic response: any state on it after the settling time will do
    period = response.period if math.isfinite(response.period) else T
    if not math.isfinite(response.t_settle):
        return math.nan, math.nan
    mu = response.floquet
    more = 1 if mu == 0.0 else (math.ceil(math.log(1e-9) / math.log(mu))
                                if 0.0 < mu < 1.0 else SETTLE_CAP)
    n = int(round(response.t_settle / T)) + min(more * round(period / T), SETTLE_CAP)
    ds = simulate(params, t_end=max(n, 1) * T, x0=x0, xdot0=xdot0, output_dt=T,
                  tol=1e-10)
    if ds.attrs["status"] != "ok":
        return math.nan, math.nan
    return float(ds.x.values[-1]), float(ds.xdot.values[-1])


def _follow(params, values, start, tol, method, options):
    """Responses along Omega ``values`` in the given order, each started from the
    previous one's settled state (``start`` after a point without a response)."""
    rows, starts = [], []
    x0, xd0 = start
    from .attractor import attractor
    for w in values:
        p = dataclasses.replace(params, Omega=float(w))
        res = attractor(p, x0=x0, xdot0=xd0, method=method, tol=tol, **options)
        rows.append(res)
        starts.append((x0, math.nan if xd0 is None else xd0))
        nxt = settled_state(p, res, x0, xd0) if res.status == "ok" else \
            (math.nan, math.nan)
        x0, xd0 = nxt if math.isfinite(nxt[0]) else start
    return rows, starts


def coexisting(ds: xr.Dataset) -> np.ndarray:
    """Over Omega: whether the up and down sweeps found two different steady
    responses, both ok: of different regimes or multiplicities, or both periodic
    with amplitudes more than ``COEXIST_REL`` apart (relative). Two aperiodic
    responses are not told apart: their amplitudes are samples'."""
    ok = (ds.status.values == 0).all(axis=0)
    reg, mult, a = ds.regime.values, ds.multiplicity.values, ds.amplitude.values
    periodic = np.isfinite(mult).all(axis=0)
    scale = np.maximum(np.abs(a).max(axis=0), 1e-300)
    differ = (reg[0] != reg[1]) | (periodic & ((mult[0] != mult[1]) | (
        np.abs(a[0] - a[1]) > COEXIST_REL * scale)))
    return ok & differ


MAX_BRANCHES = 4     # branches followed from a curve's responses at most
# responses of higher multiplicity start no branch: subharmonic responses live in
# narrow tongues whose branches fold many times (follow one with follow_response)
BRANCH_MULTIPLICITY = 2
# a response nearer a followed branch's polyline than this (scaled), or than this
# fraction of the segment's length (the chord's sag), is on it
SAME_BRANCH = 1e-3
SAG = 0.1


def _near(branch_ds, x, xd, w, scale) -> bool:
    """Whether (x, xd) at Omega = w lies on the branch's polyline in the scaled
    unknowns (x/L, xdot/Lv, Omega/Lambda), within SAME_BRANCH or SAG of a segment's
    length."""
    pts = np.stack([branch_ds.x_section.values, branch_ds.xdot_section.values,
                    branch_ds.Omega.values], axis=1) / scale
    pts = pts[np.isfinite(pts).all(axis=1)]
    q = np.array([x, xd, w]) / scale
    if len(pts) < 2:
        return len(pts) == 1 and np.linalg.norm(pts[0] - q) < SAME_BRANCH
    a, b = pts[:-1], pts[1:]
    d = b - a
    f = np.clip(np.einsum("ij,ij->i", q - a, d) / np.maximum(
        np.einsum("ij,ij->i", d, d), 1e-300), 0.0, 1.0)
    dist = np.linalg.norm(a + f[:, None] * d - q, axis=1)
    return bool(np.any(dist < np.maximum(SAME_BRANCH, SAG * np.linalg.norm(d, axis=1))))


def _branches(params, values, scans, tol, method, options) -> list:
    """The branches (``sweepcore.follow_response``) through the curve's periodic
    ok responses, each followed both ways over the curve's Omega range; a response
    already on a followed branch starts none."""
    import warnings
    from .continuation import follow_response, scales
    lo, hi = float(values[0]), float(values[-1])
    L, Lv = scales(params.row(0.0, 0.0), params.friction_law, params.loads[0])
    scale = np.array([L, Lv, max(abs(lo), abs(hi))])
    out = []
    # in each sweep's own order (the scans are stored along ascending Omega)
    seeds = [(w, r) for i, rows in enumerate(scans)
             for w, r in (zip(values, rows) if i == 0 else
                          zip(values[::-1], rows[::-1]))]
    for w, r in seeds:
        if len(out) >= MAX_BRANCHES:
            break
        if r.status != "ok" or not r.multiplicity <= BRANCH_MULTIPLICITY or \
                any(_near(b, r.x_section, r.xdot_section, w, scale) for b in out):
            continue
        p = dataclasses.replace(params, Omega=float(w))
        halves = []
        for to in (lo, hi):
            if to == w:
                continue
            try:
                halves.append(follow_response(
                    p, "Omega", to=to, x0=r.x_section, xdot0=r.xdot_section,
                    multiplicity=int(r.multiplicity), bounds=(lo, hi), tol=tol,
                    method=method, **options))
            except ValueError as e:
                warnings.warn(f"frequency_response: no branch from the response at "
                              f"Omega = {w:g}: {e}", RuntimeWarning, stacklevel=3)
                break
        else:
            parts = [halves[0].isel(point=slice(None, None, -1))] + \
                [h.isel(point=slice(1, None)) for h in halves[1:]]
            one = xr.concat(parts, dim="point", data_vars="all")
            out.append(one.assign_coords(point=np.arange(one.sizes["point"])))
    return out


def _with_branches(ds: xr.Dataset, branches: list) -> xr.Dataset:
    """``ds`` with the branches' variables along ``point`` (prefix ``branch_``) and
    ``branch_index``, which branch each point is on."""
    if not branches:
        ds.attrs["branches"] = 0
        return ds
    joined = xr.concat(branches, dim="point", data_vars="all", coords="minimal",
                       compat="override")
    npt = joined.sizes["point"]
    index = np.concatenate([np.full(b.sizes["point"], i) for i, b in enumerate(branches)])
    data = {f"branch_{n}": v for n, v in joined.data_vars.items()}
    data["branch_index"] = xr.Variable("point", index.astype(np.int64), {
        "units": "1", "long_name": "index of the branch the point is on"})
    ds = ds.assign(data).assign_coords(
        point=xr.Variable("point", np.arange(npt), {
            "units": "1", "long_name": "index of the point along the branches"}),
        multiplier=joined["multiplier"])
    ds.attrs["branches"] = len(branches)
    return ds


@checked_keywords(options=True)
def frequency_response(params: Params, Omega, direction: str = "both",
                       x0: float = 0.0, xdot0: float | None = None, tol: float = 1e-8,
                       method: str = "auto", branches: bool = False,
                       **options) -> xr.Dataset:
    """Steady responses of a forced slider along the excitation frequency, swept up
    and down, each point started from its neighbour's response.

    Parameters
    ----------
    params : Params
        The forced slider (F0 or Y0 given; its Omega is replaced by each value).
    Omega : array_like
        Excitation frequencies [rad/s], > 0, >= 2 distinct values (sorted).
    direction : {"both", "up", "down"}
        "up" from the lowest Omega, "down" from the highest, "both": up, then down
        from the up sweep's last response.
    x0, xdot0 : float
        Start of the first point [cm], [cm/s] (default at rest at 0 on fixed ground:
        xdot0 None is stuck on the belt, xdot0 = v).
    tol, method, **options
        As :func:`sweepcore.attractor` (``periods``: the largest multiplicity).
    branches : bool
        Also follow, by :func:`sweepcore.follow_response` over the Omega range,
        the branch of every distinct periodic ok response of the sweeps of
        multiplicity up to ``BRANCH_MULTIPLICITY`` (at most ``MAX_BRANCHES``
        branches): their unstable stretches, folds and pattern changes, which a
        sweep jumps over. Default False (the sweeps alone).

    Returns
    -------
    xarray.Dataset
        Dimensions ``sweep`` (the directions) and ``Omega``: every variable of
        ``sweepcore.variables.FORCED_OBSERVABLES`` with its units, ``regime``,
        ``status``, ``converged``, the start of each point (``start_x`` [cm],
        ``start_xdot`` [cm/s]) and, with both directions, ``coexisting`` over Omega
        (:func:`coexisting`: two steady responses at that frequency). With
        ``branches``: every variable of :func:`sweepcore.follow_response` with the
        prefix ``branch_`` along ``point`` (the branches one after the other,
        ``branch_index`` saying which), and the attribute ``branches`` (how many).
    """
    _checked_direction(direction)
    values = _checked(params, "Omega", Omega, x0, xdot0)
    start = (float(x0), None if xdot0 is None else float(xdot0))
    scans, starts = [], []
    if direction != "down":
        rows, st = _follow(params, values, start, tol, method, options)
        scans.append(rows)
        starts.append(st)
    if direction != "up":
        first = start
        if scans and scans[0][-1].status == "ok":
            p = dataclasses.replace(params, Omega=float(values[-1]))
            sx, sxd = starts[0][-1]
            s = settled_state(p, scans[0][-1], sx, None if math.isnan(sxd) else sxd)
            first = s if math.isfinite(s[0]) else start
        rows, st = _follow(params, values[::-1], first, tol, method, options)
        scans.append(rows[::-1])
        starts.append(st[::-1])
    dims = ("sweep", "Omega")
    data = {}
    for name, (_c, *meta) in variables.FORCED_OBSERVABLES.items():
        vals = np.array([[getattr(r, name) for r in rows] for rows in scans], float)
        if name in variables.INTEGER:       # counts, stored as a sweep stores them
            fill = variables.INTEGER[name]
            vals = np.where(np.isfinite(vals), vals, -1 if fill is None else fill)
            vals = vals.astype(np.int64)
        data[name] = (dims, vals, labels.attrs(*meta))
    for name, meta in (("regime", variables.REGIME), ("status", variables.STATUS)):
        codes = {v: k for k, v in zip(meta["flag_values"], meta["flag_meanings"].split())}
        vals = np.array([[codes[getattr(r, name)] for r in rows] for rows in scans],
                        np.int8)
        data[name] = (dims, vals, labels.flag_attrs(meta))
    data["converged"] = (dims, np.array([[r.converged for r in rows] for rows in scans],
                                        np.int8),
                         {"units": "1", "long_name": "status is ok: within tol of the "
                                                    "steady response",
                          "flag_values": np.array([0, 1], np.int8),
                          "flag_meanings": "not_converged converged"})
    st = np.array(starts, float)
    data["start_x"] = (dims, st[..., 0], labels.attrs("cm", "start position of the point",
                                                      "the previous point's settled "
                                                      "state (x at t = j T)"))
    data["start_xdot"] = (dims, st[..., 1], labels.attrs(
        "cm s-1", "start velocity of the point", "NaN: stuck on the belt (xdot0 = v)"))
    coords = _fixed(params, "Omega")
    coords["Omega"] = xr.Variable("Omega", values, {"units": UNITS["Omega"],
                                                    "long_name": LONG_NAMES["Omega"]})
    coords["sweep"] = xr.Variable("sweep", np.array(DIRECTIONS[direction]), {
        "units": "1", "long_name": "direction of the sweep (each point started from "
                                   "its neighbour's response)"})
    ds = xr.Dataset(data, coords)
    if direction == "both":
        ds["coexisting"] = ("Omega", coexisting(ds), {
            "units": "1", "long_name": "two steady responses coexist (the sweeps "
                                       "found different ones)"})
    ds.attrs.update({
        **labels.provenance(
            "Frequency-response curve of the forced friction oscillator",
            f"sweepcore.frequency_response({params!r}, Omega=<{values.size} values in "
            f"[{values[0]:g}, {values[-1]:g}]>, direction={direction!r}, tol={tol!r})",
            "steady responses followed along Omega, each started from its neighbour's "
            "settled state", "Units kN, cm, s."),
        "sweepcore_kind": "frequency_response", "direction": direction, "tol": float(tol),
        "omega": float(params.omega)})
    if branches:
        ds = _with_branches(ds, _branches(params, values, scans, tol, method, options))
    return ds


@checked_keywords(options=True)
def stroboscopic_diagram(params: Params, name: str, values, periods: int = 32,
                         transient: int = 400, x0: float = 0.0,
                         xdot0: float | None = None, tol: float = 1e-10) -> xr.Dataset:
    """x and xdot at t = j T (T = 2 pi/Omega) over the last ``periods`` forcing
    periods of a simulation, at each value of the parameter ``name``.

    Each value starts from the previous value's last state (a diagram swept up);
    the first from (x0, xdot0).

    Parameters
    ----------
    params : Params
        A forced slider.
    name : str
        A parameter of Params (e.g. "Omega", "F0", "r_y", "c", "v").
    values : array_like
        >= 2 distinct values of it (sorted).
    periods : int
        Stroboscopic samples kept at each value, after ``transient`` forcing periods.
    tol : float
        Tolerance of the simulation (``sweepcore.simulate``).

    Returns
    -------
    xarray.Dataset
        ``x`` [cm] and ``xdot`` [cm/s] over (``name``, ``sample``), and ``status`` of
        each simulation (a failed one leaves NaN samples).
    """
    from .simulate import simulate
    values = _checked(params, name, values, x0, xdot0)
    for key, n, least in (("periods", periods, 1), ("transient", transient, 0)):
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < least:
            raise ValueError(f"{key} must be an integer >= {least}, got {n!r}")
    if transient + periods >= STROBE_SAMPLES:
        raise ValueError(
            f"transient + periods = {transient:,} + {periods:,} forcing periods: each "
            f"value's simulation samples every one of them, at most "
            f"{STROBE_SAMPLES:,}; lower transient (default 400) or periods")
    refuse_unaffordable(strobe_need(values.size, periods, transient))
    xs = np.full((values.size, periods), np.nan)
    vs = np.full_like(xs, np.nan)
    status = []
    start = (float(x0), None if xdot0 is None else float(xdot0))
    for i, u in enumerate(values):
        p = dataclasses.replace(params, **{name: float(u)})
        T = 2.0 * math.pi / p.Omega
        ds = simulate(p, t_end=(transient + periods) * T, x0=start[0], xdot0=start[1],
                      output_dt=T, tol=tol)
        status.append(ds.attrs["status"])
        x, xd = ds.x.values, ds.xdot.values
        # samples at whole periods only (the last sample is t_end itself, also one)
        keep = np.isclose(ds.time.values / T, np.round(ds.time.values / T), atol=1e-9)
        x, xd = x[keep][-periods:], xd[keep][-periods:]
        xs[i, :x.size], vs[i, :xd.size] = x, xd
        if ds.attrs["status"] == "ok":
            start = (float(x[-1]), float(xd[-1]))
    st = {v: k for k, v in zip(variables.STATUS["flag_values"],
                               variables.STATUS["flag_meanings"].split())}
    dims = (name, "sample")
    ds = xr.Dataset(
        {"x": (dims, xs, labels.attrs("cm", "position at t = j T", "the last "
                                      f"{periods} forcing periods T = 2 pi/Omega")),
         "xdot": (dims, vs, labels.attrs("cm s-1", "velocity at t = j T")),
         "status": ((name,), np.array([st[s] for s in status], np.int8),
                    labels.flag_attrs(variables.STATUS))},
        {**_fixed(params, name),
         name: xr.Variable(name, values, {"units": UNITS[name],
                                          "long_name": LONG_NAMES[name]}),
         "sample": xr.Variable("sample", np.arange(periods), {
             "units": "1", "long_name": "forcing period j, counted from the first kept one"})})
    ds.attrs.update({
        **labels.provenance(
            f"Stroboscopic bifurcation diagram of the forced friction oscillator along "
            f"{name}", f"sweepcore.stroboscopic_diagram({params!r}, {name!r}, "
            f"<{values.size} values>, periods={periods}, transient={transient})",
            "x sampled at t = j T after a transient, each value started from the "
            "previous value's last state", "Units kN, cm, s."),
        "sweepcore_kind": "stroboscopic_diagram", "along": name})
    return ds
