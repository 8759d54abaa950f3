"""One slider over time: the hybrid driver sampled on a time axis, as xarray."""
from __future__ import annotations

import math

import numpy as np
import xarray as xr

from . import compiled, excitations, forced, labels, law
from ._kernels import codes, layout
from ._kernels.trajectory import fresh_acc
from .options import check_method, checked_keywords, make_options
from .params import LONG_NAMES, UNITS, Params, check_real


def start_row(params: Params, x0: float, xdot0: float | None) -> np.ndarray:
    """Validated kernel row for a start; ``xdot0=None`` starts stuck (xdot0 = v)."""
    if not isinstance(params, Params):
        raise TypeError(f"params must be a sweepcore.Params, got {type(params).__name__}")
    x0 = check_real("x0", x0)
    xdot0 = params.v if xdot0 is None else check_real("xdot0", xdot0)
    return params.row(x0, xdot0)


@checked_keywords
def simulate(params: Params, t_end: float, x0: float = 0.0, xdot0: float | None = None,
             method: str = "auto", output_dt: float | None = None, tol: float = 1e-10,
             dt: float | None = None, max_steps: int = 10_000_000,
             max_events: int = 1_000_000, gps_a: float | None = None,
             graze: float = 1e-10) -> xr.Dataset:
    """Simulate one slider from (x0, xdot0) to ``t_end`` [s].

    Parameters
    ----------
    params : Params
        The slider (units kN, cm, s).
    t_end : float
        End time [s], > 0.
    x0, xdot0 : float
        Start [cm], [cm/s]. ``xdot0=None`` starts stuck on the belt (xdot0 = v), as
        in the paper's figures.
    method : str
        "auto" or a stepper of ``sweepcore.options.METHODS`` (the method table of
        ``sweepcore._kernels.stepper``); "exact" (closed-form arcs) needs a
        piecewise-linear law (alpha2 = 0, no Stribeck term); "auto" picks it then,
        else dop853 (tol < 1e-7) or dopri5.
    output_dt : float, optional
        Sampling interval [s]; default 2 pi / omega / 100 (at most 10^6 samples).
    tol, dt, max_steps, gps_a, graze :
        As in :func:`sweepcore.options.make_options`. ``tol`` defaults to 1e-10,
        tighter than the 1e-8 of :func:`sweepcore.sweep` and
        :func:`sweepcore.attractor`: a time history carries the error of every step
        (and of every located event) to ``t_end``, while an attractor's observables
        are measured on the attractor itself, within about ``tol L``.
    max_events : int
        Size of the event log; a longer log raises (nothing is silently dropped).

    Returns
    -------
    xarray.Dataset
        On ``time``: x, xdot, z, zdot, friction force r_a, restoring force r and
        phase (0 stick, -1/+1 slide with zdot < 0 / > 0); the samples are the
        driver's own state at those times (exact for method "exact"). On ``event``:
        event_time, event_kind (flag variable), event_x, event_xdot. Attribute
        ``status`` is "ok" or the failure; after a failure samples are NaN.
    """
    row = start_row(params, x0, xdot0)
    t_end = check_real("t_end", t_end, positive=True)
    if output_dt is None:
        output_dt = 2.0 * math.pi / params.omega / 100.0
    output_dt = check_real("output_dt", output_dt, positive=True)
    ratio = t_end / output_dt
    if not ratio < 10_000_000:      # also inf: output_dt tiny against t_end
        raise ValueError(f"output_dt={output_dt!r} gives {ratio:.3g} samples over "
                         f"t_end={t_end!r}; use a larger output_dt (at most 10^7 "
                         "samples)")
    n = int(math.floor(ratio + 1e-9)) + 1
    if isinstance(max_events, bool) or not isinstance(max_events, (int, np.integer)) \
            or max_events < 1:
        raise ValueError(f"max_events must be an integer >= 1, got {max_events!r}")
    if params.forced:
        forced.check_method(method)
    else:
        check_method(method, params)
    o, _status = compiled.options(row, params.friction_law, params.load, make_options(
        method, tol=tol, dt=dt, max_steps=max_steps, gps_a=gps_a, graze=graze))
    t = np.arange(n) * output_dt
    if t[-1] < t_end:
        t = np.append(t, t_end)
    cap = 1024
    while True:
        xs = np.empty_like(t)
        zds = np.empty_like(t)
        mode = np.empty(t.shape, np.int64)
        ev = [np.empty(cap), np.empty(cap, np.int64), np.empty(cap), np.empty(cap)]
        acc = fresh_acc()
        n_ev, status, n_steps, _meth = compiled.trajectory(
            row, params.friction_law, params.load, o, t, xs, zds, mode, *ev, acc)
        if n_ev <= cap or cap >= max_events:
            break
        cap = min(max_events, 2 * n_ev)
    if n_ev > cap:
        raise RuntimeError(f"more than max_events={max_events} events before t_end; "
                           "raise max_events or shorten t_end")
    ds = _dataset(params, row, o, t, xs, zds, mode, [e[:n_ev] for e in ev],
                  int(status), int(n_steps))
    ds["time_stuck"] = ((), float(acc[layout.A_TSTICK]), TIME_STUCK)
    if params.forced:       # the load does work too: no energy balance of these two
        return ds
    ds["friction_work"] = ((), float(acc[layout.A_WF]), FRICTION_WORK)
    ds["damping_work"] = ((), params.c * float(acc[layout.A_IXD2]), DAMPING_WORK)
    return ds


# CF tools take a coordinate named "time" for a date: they need standard_name and
# "<unit> since <epoch>". The epoch is a placeholder: t counts seconds from the start
# of the run (sweepcore.open_result reads it as float seconds).
TIME = {"units": "seconds since 1970-01-01 00:00:00", "standard_name": "time",
        "long_name": "time", "calendar": "standard",
        "comment": "seconds from the start of the run; the epoch is a placeholder"}
DAMPING_WORK = {"units": "kN cm", "long_name": "work of the viscous damper on the slider",
                "comment": "integral of c xdot^2 dt over the run"}
FRICTION_WORK = {"units": "kN cm", "long_name": "work of the friction force on the slider",
                 "comment": "integral of r_a xdot dt over the run; the slider's energy "
                            "k x^2/2 + m xdot^2/2 changes by -(friction_work + damping_work)"}
LOAD = {"units": "kN", "long_name": "external force on the slider",
        "comment": "F0 p(Omega t + phi) + k y + c y' with y = Y0 cos(Omega t): the "
                   "load and the anchor's motion as one force"}
TIME_STUCK = {"units": "s", "long_name": "time stuck on the belt during the run"}


def _dataset(params, row, o, t, x, zd, mode, ev, status, n_steps):
    v = params.v
    xd = zd + v
    stick = mode == codes.STICK
    # while sliding the law F on the side the phase says; stuck, the force that
    # holds the slider, -(k x + c v)
    load = excitations.load(params, t)
    ra = np.where(stick, law.stick_force(x, params) + load,
                  law.friction(zd, params, phase=mode))
    method = codes.METHOD_NAMES[int(o[layout.O_METHOD])]
    ev_t, ev_kind, ev_x, ev_zd = ev
    kinds = sorted(k for k in codes.EVENT_NAMES if k <= codes.EV_ABNORMAL_STOP)
    ds = xr.Dataset(
        {
            "x": ("time", x, {"units": "cm", "long_name": "slider position"}),
            "xdot": ("time", xd, {"units": "cm s-1", "long_name": "slider velocity"}),
            "z": ("time", x - v * t, {"units": "cm",
                                      "long_name": "displacement relative to the belt",
                                      "comment": "z = x - v t, eq. (1)"}),
            "zdot": ("time", zd, {"units": "cm s-1", "long_name": "relative velocity",
                                  "comment": "zdot = xdot - v, eq. (2)"}),
            "r_a": ("time", ra, {"units": "kN", "long_name": "friction force on the slider",
                                 "comment": "eq. (40) while sliding, -k x while stuck"}),
            "r": ("time", params.k * (x - v * t) + ra + params.k * v * t + params.c * xd
                  - load,
                  {"units": "kN", "long_name": "restoring force",
                   "comment": "r = k x + c xdot + r_a = -m xddot (eqs. 3, 11; c: the "
                              "damper)"}),
            "phase": ("time", mode.astype(np.int8),
                      {"units": "1", "long_name": "phase",
                       "flag_values": np.array([-1, 0, 1], np.int8),
                       "flag_meanings": "slide_slower_than_belt stick slide_faster_than_belt"}),
            "event_time": ("event", ev_t, {"units": "s", "long_name": "event time"}),
            "event_kind": ("event", ev_kind.astype(np.int8),
                           {"units": "1", "long_name": "event kind",
                            "flag_values": np.array(kinds, np.int8),
                            "flag_meanings": " ".join(codes.EVENT_NAMES[k] for k in kinds)}),
            "event_x": ("event", ev_x, {"units": "cm", "long_name": "position at the event"}),
            "event_xdot": ("event", ev_zd + v,
                           {"units": "cm s-1", "long_name": "velocity at the event"}),
        },
        coords={"time": ("time", t, TIME),
                # the slider and its start: scalar coordinates with units, as in a sweep
                **{name: ((), value, {"units": UNITS[name], "long_name": LONG_NAMES[name]})
                   for name, value in {**params.values(), "x0": row[layout.X0],
                                       "xdot0": row[layout.XD0],
                                       **(params.excitation_values() if params.forced
                                          else {})}.items()
                   if value is not None and name != "law"}},
        attrs={
            **labels.provenance("sweepcore single-slider simulation",
                                "sweepcore.simulate()",
                                f"hybrid stick/slide driver (method {method})",
                                "Units kN, cm, s (mass kN s2 cm-1)."),
            "method": method,
            "status": codes.STATUS_NAMES[status],
            "n_steps": n_steps,
            **params.friction_law.attrs(),
        },
    )
    if params.forced:
        ds["external_force"] = ("time", load, LOAD)
        ds.attrs.update(params.loads[0].attrs())
    if status != codes.OK:
        ds.attrs["comment"] += (" The run stopped with status "
                                f"{codes.STATUS_NAMES[status]}; samples after it are NaN.")
    return ds

