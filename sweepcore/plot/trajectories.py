"""Single sliders over time: the paper's Fig. 3 (one run: histories and both phase
planes) and Fig. 5 (several runs, one row each)."""
from __future__ import annotations

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

from ..labels import parameter, slider_parameters
from ..options import checked_keywords
from .checks import checked_result, checked_title
from .style import EXCITATION_UNITS, SYMBOLS, excitation_text, label

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


@checked_keywords
def plot_trajectory(ds: xr.Dataset, title: str | None = None) -> Figure:
    """Fig. 3 of the paper for one simulation: histories and both phase planes.

    Panels: (a) z(t), (b) zdot(t), (c) phase plane (z, zdot); (d) x(t), (e) xdot(t),
    (f) phase plane (x, xdot), with the belt speed and the events (slip, stick,
    normal and abnormal stops) marked. On fixed ground (v = 0) z is x, and the top
    row draws the forces instead (:func:`_force_row`).
    """
    checked_result(ds, "simulation")
    checked_title(title)
    fig = Figure(figsize=(13, 7.2), layout="constrained")
    axs = fig.subplots(2, 3)
    v = parameter(ds, "v")
    t = ds.time.values
    events = _events(ds)
    rows = (("z", "zdot", True), ("x", "xdot", False))
    for r, (pos, vel, relative) in enumerate(rows):
        if relative and v == 0.0:     # z = x - v t: the row would repeat x
            _force_row(axs[r], ds)
            continue
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


def _force_row(axs, ds: xr.Dataset) -> None:
    """The top row of a run on fixed ground (v = 0, where z = x): (a) the load and
    the friction force against time, (b) the friction force against the slider's
    velocity (the law as the run traverses it, sticking at xdot = 0), (c) the load
    against x, whose loop encloses the work it does a cycle (unforced: the restoring
    force against x)."""
    t = ds.time.values
    a_t, a_v, a_x = axs
    load = "external_force" in ds
    if load:
        a_t.plot(t, ds.external_force.values, lw=1.0, color="#D55E00", label="load")
    a_t.plot(t, ds.r_a.values, lw=1.0, color="#0072B2", label="friction $r_a$")
    a_t.set(xlabel=label(ds.time, "time"), ylabel="force [kN]")
    a_t.legend(fontsize=7.5, loc="upper right")
    a_v.plot(ds.xdot.values, ds.r_a.values, lw=0.9, color="#0072B2")
    a_v.set(xlabel=label(ds.xdot, "xdot"), ylabel=label(ds.r_a, "r_a"))
    other = "external_force" if load else "r"
    a_x.plot(ds.x.values, ds[other].values, lw=0.9, color="#D55E00" if load
             else "#0072B2")
    a_x.set(xlabel=label(ds.x, "x"), ylabel=label(ds[other], other))
    a_t.annotate("v = 0: z = x, forces drawn", (0.0, 1.0), xycoords="axes fraction",
                 xytext=(30, 4), textcoords="offset points", fontsize=8, color="0.3")


def _trajectory_title(ds: xr.Dataset) -> str:
    p = ", ".join(f"${SYMBOLS[n]}$ = {value:.4g}" for n, value in
                  slider_parameters(ds))
    load = excitation_text({n: parameter(ds, n) for n in EXCITATION_UNITS})
    start = (f"start ($x_0$, $\\dot{{x}}_0$) = ({parameter(ds, 'x0'):.4g}, "
             f"{parameter(ds, 'xdot0'):.4g})")
    return (f"Single slider: {p}; {'excitation ' + load + '; ' if load else ''}"
            f"{start}; method {ds.attrs.get('method', '?')}")


@checked_keywords
def plot_cases(runs, labels, title: str | None = None,
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
    if isinstance(runs, xr.Dataset) or not isinstance(runs, (list, tuple)) or not runs:
        raise TypeError(f"runs must be a non-empty list of simulations (xarray "
                        f"Datasets), got {type(runs).__name__}")
    for i, run in enumerate(runs):
        checked_result(run, "simulation", name=f"runs[{i}]")
    if isinstance(labels, str) or len(labels) != len(runs):
        raise ValueError(f"labels must be a list of {len(runs)} row titles, one per "
                         f"run, got {labels!r}")
    checked_title(title)
    n = len(runs)
    fig = Figure(figsize=(13, 3.3 * n + 0.6), layout="constrained")
    axs = np.atleast_2d(fig.subplots(n, 3))
    letters = iter("abcdefghijklmnopqrstuvwxyz")
    for i, (ds, text) in enumerate(zip(runs, labels)):
        v = parameter(ds, "v")
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
