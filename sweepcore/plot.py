"""Pictures of results: time histories, phase planes, regime and amplitude maps.

Every function builds a :class:`matplotlib.figure.Figure` directly (no pyplot, no
global state, no display needed) and returns it; :func:`save` writes a PNG
atomically. :func:`figure_for` picks the natural picture of any result:

* a simulation (has a ``time`` dimension): the paper's Fig. 3 layout, time histories
  of z, zdot, x, xdot and the phase planes (z, zdot) and (x, xdot);
* a 1-D sweep: amplitude and mean against the swept parameter (a second axis of at
  most four values, or a categorical one, gives one series per value);
* a 2-D sweep: the regime as a categorical map with a legend, the amplitude map, the
  analytic Hopf speed v* = sqrt(alpha1/(3 alpha2)) drawn over both, and the measured
  boundaries of :mod:`sweepcore.boundary` when they can be computed; a third swept
  axis of at most six values gives one row of maps per value;
* simulations stacked along a parameter: one row of x(t), xdot(t), (x, xdot) each
  (the paper's Fig. 5 layout); any other 1-D file: its variables against its axis.

Axis labels carry the units of the data (kN, cm, s); geometric axes are drawn on a
log scale.
"""
from __future__ import annotations

import math
import os
import uuid
import warnings
from pathlib import Path

import numpy as np
import xarray as xr
from matplotlib import patheffects
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from ._kernels import codes

# colour-blind-safe (Okabe-Ito) colours, one per regime code
REGIME_COLOURS = {
    codes.R_EQUILIBRIUM: "#56B4E9",    # sky blue: steady sliding
    codes.R_SLIP_CYCLE: "#E69F00",     # orange: cycle that never sticks
    codes.R_STICK_SLIP: "#D55E00",     # vermillion: stick-slip cycle
    codes.R_NEUTRAL: "#009E73",        # green: neutral circle (constant friction)
    codes.R_STUCK: "#999999",          # grey
    codes.R_UNBOUNDED: "#CC79A7",      # purple
    codes.R_UNCONVERGED: "#F0E442",    # yellow
    codes.R_FAILED: "#000000",         # black
}

SYMBOLS = {
    "m": "m", "k": "k", "r_y": "r_y", "v": "v", "alpha1": r"\alpha_1",
    "alpha2": r"\alpha_2", "x0": "x_0", "xdot0": r"\dot{x}_0", "x": "x",
    "xdot": r"\dot{x}", "z": "z", "zdot": r"\dot{z}", "time": "t", "r_a": "r_a",
    "amplitude": "A", "mean": r"\bar{x}", "velocity_amplitude": r"A_{\dot{x}}",
    "cycle_size": "R", "period": "T", "q": "q", "v_star": "v^*", "x_eq": "x_{eq}",
    "omega": r"\omega",
}

DPI = 150


# ------------------------------------------------------------------- labels
def pretty_units(units: str | None) -> str:
    """UDUNITS string to a label: ``"kN s3 cm-3"`` -> ``kN s$^3$/cm$^3$``.

    ``"1"`` and empty units give ``""`` (dimensionless); a CF time unit
    ``"seconds since <epoch>"`` gives ``s`` (a simulation's elapsed time).
    """
    if not units or units.strip() == "1":
        return ""
    if " since " in units:
        return "s" if units.split()[0] in ("s", "sec", "second", "seconds") else \
            units.split()[0]
    num, den = [], []
    for tok in units.split():
        base = tok.rstrip("-0123456789")
        power = tok[len(base):]
        p = int(power) if power not in ("", "-") else 1
        (num if p > 0 else den).append(base + (f"$^{abs(p)}$" if abs(p) != 1 else ""))
    text = " ".join(num) if num else "1"
    if den:
        text += "/" + (den[0] if len(den) == 1 else "(" + " ".join(den) + ")")
    return text


def label(var, name: str | None = None) -> str:
    """Axis label ``long name $symbol$ [units]`` of a DataArray or Variable."""
    name = name if name is not None else getattr(var, "name", None)
    attrs = getattr(var, "attrs", {})
    text = attrs.get("long_name", str(name))
    if name in SYMBOLS:
        text += f" ${SYMBOLS[name]}$"
    units = pretty_units(attrs.get("units"))
    return f"{text} [{units}]" if units else text


def flag_axis(ax, var, axis: str = "y") -> bool:
    """Label a categorical (flag) variable's axis with its names, not its codes.

    Every code of the variable's ``flag_values`` gets a tick named by its
    ``flag_meanings`` word (underscores as spaces), so that regime and status axes
    read "stick slip", "equilibrium", ... Returns False (axis untouched) for a
    variable that is not a flag variable.
    """
    attrs = getattr(var, "attrs", {})
    if "flag_values" not in attrs or "flag_meanings" not in attrs:
        return False
    values = [int(v) for v in np.atleast_1d(attrs["flag_values"])]
    names = [w.replace("_", " ") for w in str(attrs["flag_meanings"]).split()]
    set_ticks = ax.set_yticks if axis == "y" else ax.set_xticks
    set_lim = ax.set_ylim if axis == "y" else ax.set_xlim
    set_ticks(values, names[:len(values)])
    set_lim(min(values) - 0.5, max(values) + 0.5)
    return True


def is_geometric(values) -> bool:
    """True when ``values`` (> 0, 3 or more) are evenly spaced in log, not linearly."""
    a = np.asarray(values, dtype=float)
    if a.ndim != 1 or a.size < 3 or not np.all(a > 0):
        return False
    dl, d = np.diff(np.log(a)), np.diff(a)
    log_even = np.allclose(dl, dl[0], rtol=1e-6, atol=0)
    lin_even = np.allclose(d, d[0], rtol=1e-6, atol=0)
    return bool(log_even and not lin_even)


def _axis_scale(ds: xr.Dataset, dim: str) -> str:
    spacing = ds[dim].attrs.get("spacing")
    if spacing is not None:
        return "log" if spacing == "geometric" else "linear"
    return "log" if is_geometric(ds[dim].values) else "linear"


def fixed_parameters(ds: xr.Dataset) -> str:
    """``m = 5, k = 50, ...`` for the 0-d coordinates (the fixed parameters)."""
    parts = []
    for name in ("m", "k", "r_y", "v", "alpha1", "alpha2", "x0", "xdot0"):
        if name in ds.coords and ds[name].ndim == 0:
            parts.append(f"${SYMBOLS[name]}$ = {float(ds[name]):.4g}")
    if "xdot0" not in ds.coords and "x0" in ds.coords:
        parts.append("start stuck")
    return ", ".join(parts)


# --------------------------------------------------------------------- save
def save(fig: Figure, path, dpi: int = DPI) -> Path:
    """Write ``fig`` as PNG to ``path`` atomically (temporary file, then rename)."""
    path = Path(path)
    tmp = path.parent / f".{path.name}.{uuid.uuid4().hex}.tmp.png"
    try:
        fig.savefig(tmp, dpi=dpi, format="png")
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)
    return path


def figure_for(ds: xr.Dataset, **kwargs) -> Figure:
    """The natural picture of a result Dataset (simulation, 1-D or 2-D sweep).

    Keyword arguments go to :func:`trajectory_figure`, :func:`line_figure` or
    :func:`map_figure`.
    """
    kind = ds.attrs.get("sweepcore_kind")
    if kind == "bifurcation_diagram":
        return diagram_figure(ds)
    if kind == "boundaries":
        # drawn over the map named by the study ([boundary] over), when it exists
        over = ds.attrs.get("over")
        return boundaries_figure(ds, over=xr.open_dataset(over)
                                 if over and Path(over).is_file() else None)
    if "time" in ds.dims:
        if ds.attrs.get("status", "ok") != "ok":
            raise ValueError(f"a failed simulation (status {ds.attrs['status']}): its "
                             "samples after the failure are NaN, nothing to draw")
        extra = [d for d in ds.dims if d not in ("time", "event") and ds.sizes[d] > 1]
        if extra:          # several runs stacked along a parameter: one row each
            d = extra[0]
            runs = [ds.isel({d: i}) for i in range(ds.sizes[d])]
            return cases_figure(runs, [f"${SYMBOLS.get(d, d)}$ = {_fmt(r[d])}"
                                       for r in runs], title=ds.attrs.get("title"))
        return trajectory_figure(ds, **kwargs)
    dims = [d for d in ds.dims if ds.sizes[d] > 1]
    if not dims:
        raise ValueError("the result has a single point: nothing to plot against")
    if "amplitude" not in ds and "regime" not in ds:
        return generic_figure(ds)
    numeric = [d for d in dims if ds[d].dtype.kind in "iuf"]
    few = [d for d in numeric if ds.sizes[d] <= 4]
    if len(numeric) == 2 and len(few) == 1 and not ("x" in kwargs or "y" in kwargs):
        numeric.remove(few[0])   # a map 2-4 cells wide reads better as a few lines
    if len(numeric) == 1:
        kwargs = {k: v for k, v in kwargs.items() if k not in ("x", "y")}
        series = [d for d in dims if d != numeric[0]]
        return line_figure(ds, numeric[0], series=series[0] if series else None,
                           **kwargs)
    return map_figure(ds, **kwargs)


def _fmt(value) -> str:
    """A coordinate value for a title: numbers with 4 digits, strings as they are."""
    v = np.asarray(value).item()
    return f"{v:.4g}" if isinstance(v, (int, float)) else str(v)


def generic_figure(ds: xr.Dataset, max_panels: int = 6) -> Figure:
    """Every numeric 1-D data variable against the result's one dimension."""
    dims = [d for d in ds.dims if ds.sizes[d] > 1]
    if len(dims) != 1:
        raise ValueError("no picture for this result: it is neither a simulation nor "
                         "a sweep, and it has more than one dimension")
    dim = dims[0]
    names = [n for n, v in ds.data_vars.items()
             if v.dims == (dim,) and v.dtype.kind in "iuf"][:max_panels]
    if not names:
        raise ValueError(f"no numeric variable along {dim!r} to draw")
    fig = Figure(figsize=(8, 2.9 * len(names) + 0.8), layout="constrained")
    axs = np.atleast_1d(fig.subplots(len(names), 1, sharex=True))
    for ax, name in zip(axs, names):
        ax.plot(ds[dim].values, ds[name].values, ".", ms=3, color="#0072B2")
        ax.set_ylabel(label(ds[name], name))
        flag_axis(ax, ds[name])
        ax.grid(alpha=0.3)
    axs[-1].set_xlabel(label(ds[dim], dim))
    fig.suptitle(ds.attrs.get("title", ""), fontsize=10)
    return fig


# ---------------------------------------------------------- trajectories
_EVENT_STYLE = {
    "slip": dict(marker="^", color="#009E73", label="slip (eq. 27)"),
    "stick": dict(marker="s", color="#0072B2", label="stick"),
    "normal_stop": dict(marker="v", color="#CC79A7", label="normal stop (eq. 30)"),
    "abnormal_stop": dict(marker="o", color="#D55E00", label="abnormal stop (eq. 31)"),
}


def _events(ds: xr.Dataset) -> dict:
    """``{kind name: (t, x, xdot)}`` of the simulation's event log."""
    if "event_kind" not in ds or ds.sizes.get("event", 0) == 0:
        return {}
    values = np.atleast_1d(ds.event_kind.attrs["flag_values"])
    names = ds.event_kind.attrs["flag_meanings"].split()
    kind = ds.event_kind.values
    out = {}
    for val, name in zip(values, names):
        sel = kind == val
        if sel.any():
            out[name] = (ds.event_time.values[sel], ds.event_x.values[sel],
                         ds.event_xdot.values[sel])
    return out


def _mark_events(ax, events: dict, v: float, relative: bool) -> None:
    for name, (t, x, xd) in events.items():
        style = _EVENT_STYLE.get(name)
        if style is None:
            continue
        px, py = (x - v * t, xd - v) if relative else (x, xd)
        ax.plot(px, py, linestyle="none", markersize=5, markeredgecolor="white",
                markeredgewidth=0.5, zorder=3, **{**style, "label": f"{style['label']}"
                                                  f" \u00d7{len(t)}"})


def trajectory_figure(ds: xr.Dataset, title: str | None = None) -> Figure:
    """Fig. 3 of the paper for one simulation: histories and both phase planes.

    Panels: (a) z(t), (b) zdot(t), (c) phase plane (z, zdot); (d) x(t), (e) xdot(t),
    (f) phase plane (x, xdot), with the belt speed and the events (slip, stick,
    normal and abnormal stops) marked.
    """
    fig = Figure(figsize=(13, 7.2), layout="constrained")
    axs = fig.subplots(2, 3)
    v = _param(ds, "v")
    t = ds.time.values
    events = _events(ds)
    rows = (("z", "zdot", True), ("x", "xdot", False))
    for r, (pos, vel, relative) in enumerate(rows):
        a_pos, a_vel, a_phase = axs[r]
        a_pos.plot(t, ds[pos].values, lw=1.0, color="#0072B2")
        a_vel.plot(t, ds[vel].values, lw=1.0, color="#0072B2")
        a_phase.plot(ds[pos].values, ds[vel].values, lw=0.9, color="#0072B2",
                     label="orbit")
        belt = 0.0 if relative else v
        for ax in (a_vel, a_phase):
            ax.axhline(belt, color="0.5", lw=0.8, ls="--",
                       label=("$\\dot{z} = 0$ (sticking)" if relative
                              else f"belt speed $v$ = {v:g}"))
        _mark_events(a_phase, events, v, relative)
        a_pos.set(xlabel=label(ds.time, "time"), ylabel=label(ds[pos], pos))
        a_vel.set(xlabel=label(ds.time, "time"), ylabel=label(ds[vel], vel))
        a_phase.set(xlabel=label(ds[pos], pos), ylabel=label(ds[vel], vel))
        a_phase.legend(fontsize=7.5, loc="upper left", bbox_to_anchor=(1.02, 1.0),
                       borderaxespad=0)   # beside the plane, off the orbit
    for ax, letter in zip(axs.flat, "abcdef"):
        ax.set_title(f"({letter})", loc="left", fontsize=10)
        ax.grid(alpha=0.3)
    fig.suptitle(title or _trajectory_title(ds), fontsize=11)
    return fig


def _param(ds: xr.Dataset, name: str) -> float:
    """A simulation's parameter: its scalar coordinate (files of older versions: the
    global attribute), NaN when absent."""
    if name in ds.coords and ds[name].ndim == 0:
        return float(ds[name])
    return float(ds.attrs.get(name, np.nan))


def _trajectory_title(ds: xr.Dataset) -> str:
    p = ", ".join(f"${SYMBOLS[n]}$ = {_param(ds, n):.4g}" for n in
                  ("m", "k", "r_y", "v", "alpha1", "alpha2")
                  if np.isfinite(_param(ds, n)))
    start = (f"start ($x_0$, $\\dot{{x}}_0$) = ({_param(ds, 'x0'):.4g}, "
             f"{_param(ds, 'xdot0'):.4g})")
    return f"Single slider: {p}; {start}; method {ds.attrs.get('method', '?')}"


def cases_figure(runs, labels, title: str | None = None,
                 equilibria=None) -> Figure:
    """Fig. 5 of the paper: x(t), xdot(t) and (x, xdot) for several runs (one row each).

    Parameters
    ----------
    runs : sequence of xarray.Dataset
        Simulations (:func:`sweepcore.simulate`).
    labels : sequence of str
        Row titles.
    equilibria : sequence of float, optional
        Equilibrium x_eq of each run [cm], marked in the phase plane.
    """
    n = len(runs)
    fig = Figure(figsize=(13, 3.3 * n + 0.6), layout="constrained")
    axs = np.atleast_2d(fig.subplots(n, 3))
    letters = iter("abcdefghijklmnopqrstuvwxyz")
    for i, (ds, text) in enumerate(zip(runs, labels)):
        v = _param(ds, "v")
        t = ds.time.values
        ax_x, ax_v, ax_p = axs[i]
        ax_x.plot(t, ds.x.values, lw=0.9, color="#0072B2")
        ax_v.plot(t, ds.xdot.values, lw=0.9, color="#0072B2")
        ax_p.plot(ds.x.values, ds.xdot.values, lw=0.8, color="#0072B2", label="orbit")
        ax_p.plot(ds.x.values[-1], ds.xdot.values[-1], "o", color="#0072B2", ms=4,
                  label=f"state at t = {t[-1]:g} s")
        for ax in (ax_v, ax_p):
            ax.axhline(v, color="0.5", lw=0.8, ls="--", label=f"belt speed $v$ = {v:g}")
        if equilibria is not None:
            ax_p.plot(equilibria[i], 0.0, "x", color="#D55E00", ms=8, mew=2,
                      label="equilibrium $x_{eq}$ (eq. 43)")
            ax_p.annotate(f"$x_{{eq}}$ = {equilibria[i]:.3g}", (equilibria[i], 0.0),
                          xytext=(6, 6), textcoords="offset points", fontsize=8,
                          color="#D55E00")
        ax_x.set(xlabel=label(ds.time, "time"), ylabel=label(ds.x, "x"))
        ax_v.set(xlabel=label(ds.time, "time"), ylabel=label(ds.xdot, "xdot"))
        ax_p.set(xlabel=label(ds.x, "x"), ylabel=label(ds.xdot, "xdot"))
        for ax in axs[i]:
            ax.set_title(f"({next(letters)}) {text}" if ax is ax_x
                         else f"({next(letters)})", loc="left", fontsize=10)
            ax.grid(alpha=0.3)
    handles, names = axs[0, 2].get_legend_handles_labels()
    names = [f"state at the end, t = {t[-1]:g} s" if n.startswith("state") else n
             for n in names]
    fig.legend(handles, names, loc="outside lower center", ncol=len(names), fontsize=9)
    if title:
        fig.suptitle(title, fontsize=11)
    return fig


def friction_figure(r_y: float, alpha1: float, alpha2: float,
                    zdot_max: float | None = None) -> Figure:
    """Fig. 4 of the paper: the friction law r_a(zdot) of eq. (40), with v* marked.

    r_a = r_y sgn(zdot) - alpha1 zdot + alpha2 zdot^3 while sliding; at zdot = 0 the
    force is anywhere in [-r_y, r_y] (eq. 6), drawn as a vertical segment. The slope
    is negative for |zdot| < v* = sqrt(alpha1/(3 alpha2)), where r_a has its
    minimum r_y - (2/3) alpha1 v*.
    """
    v_star = math.sqrt(alpha1 / (3 * alpha2)) if alpha2 > 0 and alpha1 > 0 else math.nan
    if zdot_max is None:
        zdot_max = 2.2 * v_star if math.isfinite(v_star) else 10.0
    fig = Figure(figsize=(7.5, 5.2), layout="constrained")
    ax = fig.subplots()
    for sgn in (1, -1):
        zd = sgn * np.linspace(1e-9, zdot_max, 400)
        ra = r_y * sgn - alpha1 * zd + alpha2 * zd ** 3
        ax.plot(zd, ra, color="#0072B2", lw=2,
                label=(r"$r_a = r_y\,\mathrm{sgn}(\dot z) - \alpha_1\dot z "
                       r"+ \alpha_2\dot z^3$ (eq. 40)") if sgn == 1 else None)
    ax.plot([0, 0], [-r_y, r_y], color="#0072B2", lw=2, ls=":",
            label=r"sticking: $r_a \in [-r_y, r_y]$ (eq. 6)")
    if math.isfinite(v_star):
        r_min = r_y - 2 * alpha1 * v_star / 3
        for sgn in (1, -1):
            ax.plot(sgn * v_star, sgn * r_min, "o", color="#D55E00", ms=7, zorder=3)
            ax.axvline(sgn * v_star, color="#D55E00", lw=0.8, ls="--")
        ax.annotate(f"$v^* = \\sqrt{{\\alpha_1/3\\alpha_2}}$ = {v_star:.3g} cm/s\n"
                    f"min $r_a$ = {r_min:.3g} kN",
                    (v_star, r_min), xytext=(12, -34), textcoords="offset points",
                    fontsize=9, color="#D55E00")
        ax.axvspan(-v_star, v_star, color="#D55E00", alpha=0.07,
                   label=r"negative slope $|\dot z| < v^*$: energy input")
    ax.axhline(0, color="0.6", lw=0.6)
    ax.axvline(0, color="0.6", lw=0.6)
    ax.set(xlabel=r"relative velocity $\dot z$ [cm/s]",
           ylabel="friction force $r_a$ [kN]",
           title=f"Friction-speed law: $r_y$ = {r_y:g} kN, $\\alpha_1$ = {alpha1:g} "
                 f"kN s/cm, $\\alpha_2$ = {alpha2:g} kN s$^3$/cm$^3$")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8.5, loc="upper left")
    return fig


# ------------------------------------------------------------------ sweeps
def _observable_reference(ds: xr.Dataset, dim: str, name: str):
    """Paper's reference curve for ``name`` along ``dim``: (values, label) or None."""
    if name == "amplitude" and "v" in ds and "omega" in ds:
        ref = np.abs(ds["v"]) / ds["omega"]
        return ref, r"$v/\omega$ (paper, eq. 39)"
    if name == "mean" and "x_eq" in ds:
        return ds["x_eq"], r"equilibrium $x_{eq}$ (eq. 43)"
    return None


def _regime_codes(ds: xr.Dataset) -> tuple[list, list]:
    attrs = ds["regime"].attrs
    values = [int(x) for x in np.atleast_1d(attrs.get("flag_values",
                                                      sorted(codes.REGIME_NAMES)))]
    names = attrs.get("flag_meanings", " ".join(codes.REGIME_NAMES[k] for k in values))
    return values, names.split()


_MARKERS = "osD^vP"


def line_figure(ds: xr.Dataset, dim: str, variables=("amplitude", "mean"),
                title: str | None = None, series: str | None = None) -> Figure:
    """Observables of a 1-D sweep against ``dim``, points coloured by regime.

    The paper's reference curves are drawn beside the measurement: v/omega for the
    amplitude (eq. 39), x_eq for the mean (eq. 43); v* as a vertical line when ``dim``
    is v and alpha1, alpha2 are fixed. ``series``: a second dimension (e.g. several
    starts), one marker per value (at most six; further dimensions at their first
    value).
    """
    variables = [v for v in variables if v in ds]
    if not variables:
        raise ValueError(f"none of the variables {variables} is in the result")
    keep = (dim, series) if series else (dim,)
    ds = ds.isel({d: 0 for d in ds.dims if d not in keep and ds.sizes[d] > 1})
    ds = ds.isel({series: slice(0, len(_MARKERS))}) if series else ds
    fig = Figure(figsize=(8, 2.9 * len(variables) + 0.8), layout="constrained")
    axs = np.atleast_1d(fig.subplots(len(variables), 1, sharex=True))
    x = ds[dim].values
    order = np.argsort(x)
    handles = {}
    for ax, name in zip(axs, variables):
        for k, sub in enumerate(_series(ds, series)):
            _regime_points(ax, sub, dim, name, x, order, _MARKERS[k], handles)
            if series:
                handles[f"s{k}"] = Line2D([], [], color="0.35", marker=_MARKERS[k],
                                          ls="-", mfc="none",
                                          label=f"{series} = {_fmt(sub[series])}")
        ref = _observable_reference(ds, dim, name)
        if ref is not None and series in ref[0].dims:
            same = (ref[0] == ref[0].isel({series: 0})).all()
            # drawn only when it is the same for every series
            ref = (ref[0].isel({series: 0}), ref[1]) if bool(same) else None
        if ref is not None:
            ref_vals = np.broadcast_to(ref[0].values, x.shape) if ref[0].ndim else \
                np.full(x.shape, float(ref[0]))
            style = dict(ls="--", color="#0072B2") if name == "amplitude" else \
                dict(ls="-.", color="#009E73")
            handles[ref[1]] = ax.plot(x[order], ref_vals[order], lw=1.1, zorder=1,
                                      label=ref[1], **style)[0]
        _vstar_line(ax, ds, dim, handles)
        if name == "amplitude":
            _small_cycle(ax, ds, dim, handles)
        ax.set_ylabel(label(ds[name], name))
        flag_axis(ax, ds[name])
        ax.grid(alpha=0.3)
        ax.set_xscale(_axis_scale(ds, dim))
    axs[-1].set_xlabel(label(ds[dim], dim))
    regimes = [h for k, h in handles.items() if k in codes.REGIME_NAMES.values()]
    rest = [h for k, h in handles.items() if k not in codes.REGIME_NAMES.values()]
    # beside the panels, never over the data
    fig.legend(handles=regimes + rest, fontsize=8, loc="outside lower center",
               ncol=3)
    fig.suptitle(title or _sweep_title(ds), fontsize=10)
    return fig


def _series(ds, series):
    if series is None:
        return [ds]
    return [ds.isel({series: i}) for i in range(ds.sizes[series])]


def _regime_points(ax, ds, dim, name, x, order, marker, handles):
    """One series: a grey line through the points, each point coloured by regime."""
    y = ds[name].values
    ax.plot(x[order], y[order], color="0.35", lw=1, zorder=1)
    if "regime" not in ds:
        return
    regime = ds["regime"].values
    values, names = _regime_codes(ds)
    for val, rname in zip(values, names):
        sel = regime == val
        if sel.any():
            handles[rname] = ax.scatter(x[sel], y[sel], s=14, zorder=2, marker=marker,
                                        color=REGIME_COLOURS.get(val, "k"),
                                        label=rname.replace("_", " "))


def _sweep_title(ds: xr.Dataset) -> str:
    """Study title (or the file's title) over the fixed parameters."""
    head = ds.attrs.get("study_title") or ds.attrs.get("title", "sweep")
    return f"{head}\n{fixed_parameters(ds)}"


def _vstar_line(ax, ds, dim, handles):
    if dim != "v" or "v_star" not in ds:
        return
    vs = np.unique(ds["v_star"].values)
    if vs.size == 1 and np.isfinite(vs[0]):
        handles["v*"] = ax.axvline(vs[0], color="#D55E00", ls=":", lw=1.2,
                                   label=f"analytic $v^*$ = {vs[0]:.3g}")


def _small_cycle(ax, ds, dim, handles):
    """Averaging estimate A = 2 sqrt(v*^2 - v^2)/omega for 2 v*/sqrt(5) < v < v*.

    First-order averaging of eq. (41) about x_eq gives the velocity amplitude
    2 sqrt(v*^2 - v^2) of the small slip cycle; it reaches the belt speed (and the
    cycle starts to stick) at v = 2 v*/sqrt(5). See docs/studies.md.
    """
    if dim != "v" or "v_star" not in ds or "omega" not in ds:
        return
    vs, om = np.unique(ds["v_star"].values), np.unique(ds["omega"].values)
    if vs.size != 1 or om.size != 1 or not np.isfinite(vs[0]):
        return
    v = np.linspace(2 * vs[0] / math.sqrt(5), vs[0], 200)
    v = v[(v >= ds.v.values.min()) & (v <= ds.v.values.max())]
    if v.size:
        handles["small"] = ax.plot(v, 2 * np.sqrt(vs[0] ** 2 - v ** 2) / om[0],
                                   color="k", lw=1.2, ls=":", zorder=3,
                                   label=r"averaging: $2\sqrt{v^{*2} - v^2}/\omega$")[0]


def _edges(values: np.ndarray, log: bool) -> np.ndarray:
    """Cell edges around sorted centres (geometric midpoints on a log axis)."""
    c = np.log(values) if log else values
    if c.size == 1:
        e = np.array([c[0] - 0.5, c[0] + 0.5])
    else:
        mid = 0.5 * (c[1:] + c[:-1])
        e = np.concatenate([[2 * c[0] - mid[0]], mid, [2 * c[-1] - mid[-1]]])
    return np.exp(e) if log else e


def _plane(ds: xr.Dataset, x: str | None, y: str | None):
    """Choose the map's axes (numeric swept dimensions; v across by default), a
    facet dimension for rows (the first other swept one, at most six values), and
    reduce any further dimensions to their first value (said in ``note``)."""
    dims = [d for d in ds.dims if ds.sizes[d] > 1]
    numeric = [d for d in dims if ds[d].dtype.kind in "iuf"]
    rest = [d for d in numeric if d not in (x, y)]
    if x is None:
        x = "v" if "v" in rest else rest.pop(0) if rest else None
        rest = [d for d in rest if d != x]
    if y is None:
        y = rest.pop(0) if rest else None
    for d in (x, y):
        if d is None or d not in numeric:
            raise ValueError(f"{d!r} is not a numeric swept dimension of the result "
                             f"(numeric swept: {', '.join(numeric) or 'none'})")
    others = [d for d in dims if d not in (x, y)]
    facet = others.pop(0) if others and ds.sizes[others[0]] <= 6 else None
    note = ""
    if others:
        ds = ds.isel({d: 0 for d in others})
        note = "; " + ", ".join(f"${SYMBOLS.get(d, d)}$ = {_fmt(ds[d])}"
                                for d in others) + " (first value)"
    return ds, x, y, facet, note


def map_figure(ds: xr.Dataset, x: str | None = None, y: str | None = None,
               variables=("regime", "amplitude"), title: str | None = None,
               boundary: bool = True) -> Figure:
    """Maps of a 2-D sweep: categorical regime map and colour maps of observables.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep result with at least two numeric swept dimensions. A third swept
        dimension of at most six values (e.g. a friction law or a start) gives one
        row per value; further dimensions are reduced to their first value (said in
        the title).
    x, y : str, optional
        Dimensions on the horizontal and vertical axes; default v (if swept) across.
    variables : sequence of str
        Panels, left to right: ``"regime"`` (categorical, legend of regime names) or
        any numeric data variable (colour bar with units).
    boundary : bool
        Draw the analytic v* curve (and the estimate 2 v*/sqrt(5) of the end of
        stick-slip) and, when x or y is v, the measured Hopf boundary and end of
        stick-slip (:mod:`sweepcore.boundary`).
    """
    ds, x, y, facet, note = _plane(ds, x, y)
    variables = [v for v in variables if v in ds]
    if not variables:
        raise ValueError("none of the requested variables is in the result")
    rows = [ds.isel({facet: i}) for i in range(ds.sizes[facet])] if facet else [ds]
    n = len(variables)
    fig = Figure(figsize=(5.6 * n + 0.6, 5.0 * len(rows) + 0.4), layout="constrained")
    axs = np.atleast_2d(fig.subplots(len(rows), n, sharex=True, sharey=True))
    curves = {}
    for row_axs, sub in zip(axs, rows):
        overlays = _overlays(sub, x, y) if boundary else []
        for ax, name in zip(row_axs, variables):
            map_panel(fig, ax, sub, name, x, y)
            for draw in overlays:
                # on the regime map the measured boundaries are the colour edges
                if name != "regime" or draw.analytic:
                    draw(ax)
            if ax is not row_axs[0]:
                ax.set_ylabel("")
            if facet:
                ax.set_title(f"{facet} = {_fmt(sub[facet])}: {ax.get_title()}",
                             fontsize=10)
        for d in overlays:
            curves.setdefault(d.handle.get_label(), d.handle)
    if curves:    # one legend for the curves of every panel, below them
        fig.legend(handles=list(curves.values()), fontsize=8, loc="outside lower center",
                   ncol=min(len(curves), 2))
    fig.suptitle((title or _sweep_title(ds)) + note, fontsize=10)
    return fig


def map_panel(fig: Figure, ax, ds: xr.Dataset, name: str, x: str, y: str,
              colorbar: bool = True, **kwargs):
    """Draw variable ``name`` of a 2-D result on ``ax`` over dimensions (x, y).

    ``"regime"`` is drawn as a categorical map with a legend of regime names and
    shares; any other variable as a colour map (``kwargs`` go to ``pcolormesh``)
    with a colour bar labelled with its units. Geometric axes get a log scale.
    Returns the QuadMesh.
    """
    ds = ds.sortby([x, y]).transpose(y, x, ...)
    xlog, ylog = _axis_scale(ds, x) == "log", _axis_scale(ds, y) == "log"
    xe, ye = _edges(ds[x].values, xlog), _edges(ds[y].values, ylog)
    if name == "regime":
        mesh = _regime_panel(fig, ax, ds, xe, ye)
    else:
        mesh = _value_panel(fig, ax, ds, name, xe, ye, colorbar, **kwargs)
    ax.set_xscale("log" if xlog else "linear")
    ax.set_yscale("log" if ylog else "linear")
    ax.set_xlim(xe[0], xe[-1])
    ax.set_ylim(ye[0], ye[-1])
    ax.set_xlabel(label(ds[x], x))
    ax.set_ylabel(label(ds[y], y))
    return mesh


def _regime_panel(fig, ax, ds, xe, ye):
    values, names = _regime_codes(ds)
    data = ds["regime"].values.astype(int)
    cmap = ListedColormap([REGIME_COLOURS.get(v, "k") for v in values])
    norm = BoundaryNorm(np.arange(len(values) + 1) - 0.5, len(values))
    index = np.searchsorted(values, data)
    mesh = ax.pcolormesh(xe, ye, index, cmap=cmap, norm=norm, rasterized=True)
    total = data.size
    patches = [Patch(facecolor=REGIME_COLOURS.get(v, "k"), edgecolor="0.3", lw=0.5,
                     label=f"{nm.replace('_', ' ')} ({_share(np.sum(data == v), total)})")
               for v, nm in zip(values, names) if (data == v).any()]
    # under the panel, off the map
    ax.legend(handles=patches, title=f"regime ({total} points)", fontsize=8,
              title_fontsize=8.5, loc="upper center", bbox_to_anchor=(0.5, -0.13),
              ncol=2, frameon=False)
    ax.set_title("attractor regime", fontsize=10)
    return mesh


def _share(count: int, total: int) -> str:
    """``"38.4 %"``, or the count itself when it is under 0.1 %."""
    if 1000 * count < total:
        return f"{count} point{'s' if count > 1 else ''}"
    return f"{100 * count / total:.3g} %"


def _uniform(data, rel: float = 1e-6):
    """(value, spread) when ``data`` is constant up to ``rel``, else None."""
    if data.count() == 0:
        return None
    lo, hi = float(data.min()), float(data.max())
    scale = max(abs(lo), abs(hi))
    if hi - lo <= rel * scale or scale == 0.0:
        return 0.5 * (lo + hi), hi - lo
    return None


def _value_panel(fig, ax, ds, name, xe, ye, colorbar=True, **kwargs):
    da = ds[name]
    data = np.ma.masked_invalid(da.values.astype(float))
    kwargs.setdefault("cmap", "viridis")
    uniform = _uniform(data)
    if uniform is not None and "norm" not in kwargs and "vmin" not in kwargs:
        # a colour scale stretched over rounding noise would invent structure
        c, spread = uniform
        half = max(0.05 * abs(c), 1e-12)
        kwargs.update(vmin=c - half, vmax=c + half)
        ax.text(0.5, 0.5, f"uniform: {c:.6g} {pretty_units(da.attrs.get('units'))}\n"
                          f"(spread {spread:.2g})", transform=ax.transAxes,
                ha="center", va="center", fontsize=10,
                bbox=dict(facecolor="white", alpha=0.8, edgecolor="0.5"))
    mesh = ax.pcolormesh(xe, ye, data, shading="flat", rasterized=True, **kwargs)
    if colorbar:
        cb = fig.colorbar(mesh, ax=ax, shrink=0.9, pad=0.01)
        cb.set_label(label(da, name))
    ax.set_title(da.attrs.get("long_name", name), fontsize=10)
    return mesh


class _Overlay:
    """A curve drawn on every panel, with one legend handle."""

    def __init__(self, xs, ys, handle: Line2D, analytic: bool = False):
        self.xs, self.ys, self.handle, self.analytic = xs, ys, handle, analytic

    def __call__(self, ax):
        ax.plot(self.xs, self.ys, color=self.handle.get_color(),
                ls=self.handle.get_linestyle(), lw=self.handle.get_linewidth(),
                marker=self.handle.get_marker(), ms=self.handle.get_markersize(),
                markerfacecolor=self.handle.get_markerfacecolor(), zorder=4)


def _overlays(ds: xr.Dataset, x: str, y: str) -> list:
    out = _analytic_curves(ds, x, y)
    if "v" in (x, y):
        out.extend(_measured_boundaries(ds, x, y))
    return out


# v* and the averaging estimate of the end of stick-slip, 2 v*/sqrt(5): the small
# cycle has velocity amplitude 2 sqrt(v*^2 - v^2) (first-order averaging of eq. 41
# about x_eq), which reaches the belt speed v when v = 2 v*/sqrt(5); see
# docs/studies.md, "hopf_map".
_ANALYTIC = (
    (1.0, dict(color="white", ls="--", lw=2.0,
               label=r"analytic $v^* = \sqrt{\alpha_1/3\alpha_2}$ ($q = 0$)")),
    (2.0 / math.sqrt(5.0), dict(color="white", ls=":", lw=2.0,
                                label=r"estimate: stick-slip below $2v^*/\sqrt{5}$")),
)


def _analytic_curves(ds, x, y) -> list:
    """v* = sqrt(alpha1/(3 alpha2)) and 2 v*/sqrt(5) in the (x, y) plane.

    Drawn when one axis is v and the other alpha1 or alpha2 (the other fixed).
    """
    other = y if x == "v" else x if y == "v" else None
    if other not in ("alpha1", "alpha2"):
        return []
    fixed = "alpha2" if other == "alpha1" else "alpha1"
    if fixed not in ds.coords or ds[fixed].ndim != 0:
        return []
    ends = ds[other].values[[0, -1]]
    s = np.geomspace(*ends, 400) if is_geometric(ds[other].values) \
        else np.linspace(*ends, 400)
    a1, a2 = (s, float(ds[fixed])) if other == "alpha1" else (float(ds[fixed]), s)
    with np.errstate(divide="ignore", invalid="ignore"):
        vs = np.sqrt(np.asarray(a1) / (3 * np.asarray(a2)))
    out = []
    for factor, style in _ANALYTIC:
        vv = factor * vs
        vv = np.where((vv >= ds.v.values.min()) & (vv <= ds.v.values.max()), vv, np.nan)
        if np.isfinite(vv).any():
            # white on the maps; outlined in grey in the legend, which is on white
            handle = Line2D([], [], **style, path_effects=[
                patheffects.withStroke(linewidth=4, foreground="0.45")])
            out.append(_Overlay(*((vv, s) if x == "v" else (s, vv)), handle,
                                analytic=True))
    return out


def _measured_boundaries(ds, x, y) -> list:
    """The measured Hopf boundary and end of stick-slip along v (sweepcore.boundary).

    Taken from the result when the sweep stored them, else measured here.
    """
    names = ("v_hopf_measured", "v_stick_onset")
    if all(n in ds for n in names):
        bd = ds
    else:
        try:
            from .boundary import hopf_boundary
            bd = hopf_boundary(ds, axis="v")
        except Exception as err:  # a picture must not fail for an overlay
            warnings.warn(f"measured boundary not drawn: {err}", stacklevel=3)
            return []
    other = y if x == "v" else x
    styles = {
        "v_hopf_measured": dict(color="black", ls="-", lw=1.3,
                                label="measured boundary: cycle | equilibrium"),
        "v_stick_onset": dict(color="#CC79A7", ls="-", lw=1.3,
                              label="measured end of stick-slip"),
    }
    found = []
    for name in names:
        b = bd[name]
        if b.dims != (other,) or not np.isfinite(b.values).any():
            continue
        b = b.sortby(other)
        vals, coord = b.values, b[other].values
        found.append(_Overlay(*((vals, coord) if x == "v" else (coord, vals)),
                              Line2D([], [], **styles[name])))
    return found


# ------------------------------------------------- diagrams and boundary curves
_MARKS = (
    ("v_hopf", dict(color="black", ls="-", lw=1.2, label="Hopf point (located)")),
    ("v_stick_onset", dict(color="#CC79A7", ls="-", lw=1.2,
                           label="stick onset (located)")),
    ("v_star", dict(color="0.4", ls="--", lw=1.0, label=r"analytic $v^*$")),
)


def diagram_figure(ds: xr.Dataset, title: str | None = None) -> Figure:
    """A bifurcation diagram (:func:`sweepcore.diagram.bifurcation_diagram`).

    Left: x_max and x_min of the attractor on each branch (up: filled, down: open
    markers), coloured by regime, with the mean as a thin line; the located Hopf
    point and stick onset and the analytic v* as vertical lines. Right: the Floquet
    multiplier of the cycles (0 for stick-slip, < 1 for stable slip cycles).
    """
    along = ds.attrs.get("along", [d for d in ds.dims if d != "branch"][0])
    fig = Figure(figsize=(12.0, 4.8), layout="constrained")
    ax, axf = fig.subplots(1, 2, gridspec_kw={"width_ratios": [2.2, 1.0]})
    x = ds[along].values
    handles = []
    for branch, style in (("up", dict(marker="o", s=16)),
                          ("down", dict(marker="o", s=42, facecolors="none"))):
        if branch not in ds.branch.values:
            continue
        b = ds.sel(branch=branch)
        reg = b.regime.values
        colours = [REGIME_COLOURS.get(int(r), "k") for r in reg]
        for name in ("x_max", "x_min"):
            kw = dict(style)
            if "facecolors" in kw:
                kw["edgecolors"] = colours
            else:
                kw["c"] = colours
            ax.scatter(x, b[name].values, zorder=3, linewidths=0.8, **kw)
        ax.plot(x, b["mean"].values, color="0.5", lw=0.6,
                ls="-" if branch == "up" else ":")
        axf.scatter(x, b["floquet"].values, zorder=3, linewidths=0.8,
                    **({**style, "edgecolors": colours} if "facecolors" in style
                       else {**style, "c": colours}))
        handles.append(Line2D([], [], marker="o", ls="", color="0.3",
                              markerfacecolor="0.3" if branch == "up" else "none",
                              label=f"{branch} scan"))
    present = sorted({int(r) for r in np.ravel(ds.regime.values)})
    handles += [Patch(facecolor=REGIME_COLOURS.get(r, "k"),
                      label=codes.REGIME_NAMES.get(r, str(r)).replace("_", " "))
                for r in present]
    for a in (ax, axf):
        for name, style in _MARKS:
            if name in ds and np.isfinite(float(ds[name])) and \
                    x.min() <= float(ds[name]) <= x.max():
                a.axvline(float(ds[name]), **style)
    handles += [Line2D([], [], **style) for name, style in _MARKS
                if name in ds and np.isfinite(float(ds[name]))]
    ax.set_xlabel(label(ds[along], along))
    ax.set_ylabel("extremes of x on the attractor [cm]")
    ax.legend(handles=handles, fontsize=8, loc="best", framealpha=0.85)
    ax.set_title("x_max (upper) and x_min (lower) per branch", fontsize=10)
    axf.set_xlabel(label(ds[along], along))
    axf.set_ylabel(label(ds["floquet"], "floquet"))
    if not np.isfinite(ds["floquet"].values).any():
        axf.text(0.5, 0.5, "no Floquet multiplier in the file", ha="center",
                 transform=axf.transAxes, fontsize=9)
    axf.set_title("Floquet multiplier (return map at the x maxima)", fontsize=10)
    fig.suptitle(title or f"{ds.attrs.get('title', 'bifurcation diagram')}: "
                 f"{fixed_parameters(ds)}", fontsize=10)
    return fig


def boundaries_figure(ds: xr.Dataset, over: xr.Dataset | None = None,
                      title: str | None = None) -> Figure:
    """Located boundary curves (:func:`sweepcore.locate_boundaries` or
    :func:`sweepcore.continue_boundary`) against their second parameter.

    Left: the Hopf point and the stick onset over the regime map ``over`` (a 2-D
    sweep over v and the same parameter), or alone, with v* and 2 v*/sqrt(5).
    Middle: v_hopf - v* [cm/s] (with the estimated error). Right: the stick-onset
    ratio v_stick_onset/v* against the averaging value sqrt(4/5).
    """
    dims = [d for d in ds.dims if d != "transition" and ds.sizes[d] > 1]
    if len(dims) != 1:
        raise ValueError(f"boundary curves need one swept parameter, got {dims}")
    p = dims[0]
    fig = Figure(figsize=(16.0, 5.0), layout="constrained")
    ax, axh, axs = fig.subplots(1, 3, gridspec_kw={"width_ratios": [1.6, 1.0, 1.0]})
    y = ds[p].values
    log = _axis_scale(ds, p) == "log"
    if over is not None:
        map_panel(fig, ax, over, "regime", "v", p)
    curves = (("v_star", dict(color="white" if over is not None else "0.4", ls="--",
                              lw=1.6, label=r"analytic $v^*$")),
              ("v_stick_onset_estimate", dict(color="white" if over is not None
                                              else "0.4", ls=":", lw=1.6,
                                              label=r"averaging $2v^*/\sqrt{5}$")),
              ("v_hopf", dict(color="black", lw=1.4, label="Hopf point (located)")),
              ("v_stick_onset", dict(color="#CC79A7", lw=1.4,
                                     label="stick onset (located)")))
    for name, style in curves:
        if name in ds:
            ax.plot(ds[name].values, y, **style)
    if "transition_value" in ds:
        t = ds["transition_value"]
        known = ds["v_hopf"].values[:, None], ds["v_stick_onset"].values[:, None]
        other = ~(np.isclose(t.values, known[0]) | np.isclose(t.values, known[1]))
        xs = np.where(other, t.values, np.nan)
        ax.plot(xs.ravel(), np.repeat(y, xs.shape[1]), ls="", marker=".", ms=3,
                color="0.15", label="other regime changes (labels)")
    if over is None:
        ax.set_yscale("log" if log else "linear")
        ax.set_xlabel(label(xr.Variable((), 0.0, {"units": "cm s-1",
                                                   "long_name": "belt speed"}), "v"))
        ax.set_ylabel(label(ds[p], p))
    regimes = ax.get_legend()          # the regime map's own legend, kept
    ax.legend(fontsize=8, loc="upper right", framealpha=0.85)
    if regimes is not None:
        ax.add_artist(regimes)
    ax.set_title("located boundaries", fontsize=10)
    if "v_star" not in ds:     # searched along another parameter than v
        raise ValueError("boundary curves are drawn for boundaries along v; this "
                         f"result was searched along {ds.attrs.get('along')!r}")
    dv = (ds["v_hopf"] - ds["v_star"]).values
    axh.plot(y, dv, color="black", lw=1.0, marker=".", ms=3, label=r"$v_{hopf} - v^*$")
    if "v_hopf_error" in ds:
        e = ds["v_hopf_error"].values
        axh.fill_between(y, -e, e, color="0.8", label="estimated error")
    axh.axhline(0.0, color="0.4", lw=0.8, ls="--")
    axh.set_ylabel("v_hopf - v* [cm/s]")
    axh.legend(fontsize=8)
    axh.set_title("Hopf point against the analytic v*", fontsize=10)
    axs.plot(y, (ds["v_stick_onset"] / ds["v_star"]).values, color="#CC79A7",
             marker=".", ms=3, lw=1.0, label=r"$v_{stick}/v^*$ (located)")
    axs.axhline(math.sqrt(0.8), color="0.4", ls=":", label=r"averaging $\sqrt{4/5}$")
    axs.set_ylabel("stick onset / v*")
    axs.legend(fontsize=8)
    axs.set_title("stick onset against the averaging estimate", fontsize=10)
    for a in (axh, axs):
        a.set_xscale("log" if log else "linear")
        a.set_xlabel(label(ds[p], p))
    fig.suptitle(title or f"{ds.attrs.get('title', 'boundaries')}: "
                 f"{fixed_parameters(ds)}", fontsize=10)
    return fig
