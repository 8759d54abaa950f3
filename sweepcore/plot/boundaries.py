"""Boundary results: the bifurcation diagram, and the located boundary curves
against their second parameter (over a regime map when one is given)."""
from __future__ import annotations


import numpy as np
import xarray as xr
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from .._kernels import codes
from ..options import checked_keywords
from ..params import LONG_NAMES
from .checks import checked_result, checked_title
from .maps import map_panel
from .style import REGIME_COLOURS, axis_scale, fixed_parameters, label

_MARKS = (
    ("v_hopf", dict(color="black", ls="-", lw=1.2, label="Hopf point (located)")),
    ("v_stick_onset", dict(color="#CC79A7", ls="-", lw=1.2,
                           label="stick onset (located)")),
    ("v_star", dict(color="0.4", ls="--", lw=1.0, label=r"analytic $v^*$")),
)


@checked_keywords
def plot_diagram(ds: xr.Dataset, title: str | None = None) -> Figure:
    """A bifurcation diagram (:func:`sweepcore.diagram.bifurcation_diagram`).

    Left: x_max and x_min of the attractor on each branch (up: filled, down: open
    markers), coloured by regime, with the mean as a thin line; the located Hopf
    point and stick onset and the analytic v* as vertical lines. Right: the Floquet
    multiplier of the cycles (0 for stick-slip, < 1 for stable slip cycles).
    """
    checked_result(ds, "bifurcation_diagram")
    checked_title(title)
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


@checked_keywords
def plot_boundaries(ds: xr.Dataset, over: xr.Dataset | None = None,
                    title: str | None = None) -> Figure:
    """Located boundary curves (:func:`sweepcore.locate_boundaries` or
    :func:`sweepcore.continue_boundary`) against their second parameter.

    Left: the Hopf point and the stick onset over the regime map ``over`` (a 2-D
    sweep over v and the same parameter), or alone, with v* and 2 v*/sqrt(5).
    Middle: v_hopf - v* [cm/s] (with the estimated error). Right: the stick-onset
    ratio v_stick_onset/v* against the averaging value sqrt(4/5). A search along
    another parameter than v (no analytic v* to compare with): the left panel
    alone, its axis that parameter with its units.
    """
    checked_result(ds, "boundaries")
    checked_title(title)
    dims = [d for d in ds.dims if d != "transition" and ds.sizes[d] > 1]
    if len(dims) != 1:
        raise ValueError(f"boundary curves need one swept parameter, got {dims}")
    p = dims[0]
    if over is not None:
        checked_result(over, "sweep", name="over")
        if not {"v", p} <= {d for d in over.dims if over.sizes[d] > 1} or \
                "regime" not in over:
            raise ValueError(f"over must be a regime map over v and {p} (a sweep "
                             f"with both swept), got one over "
                             f"{', '.join(over.dims) or 'no dimension'}")
    along = ds.attrs.get("along", "v")
    if along != "v" and over is not None:
        raise ValueError(f"over: a regime map is drawn under boundaries along v; "
                         f"this result was searched along {along!r}")
    if along == "v":
        fig = Figure(figsize=(16.0, 5.0), layout="constrained")
        ax, axh, axs = fig.subplots(1, 3,
                                    gridspec_kw={"width_ratios": [1.6, 1.0, 1.0]})
    else:
        fig = Figure(figsize=(7.5, 5.0), layout="constrained")
        ax = fig.subplots()
    y = ds[p].values
    log = axis_scale(ds, p) == "log"
    if over is not None:
        map_panel(fig, ax, over, "regime", "v", p)
    curves = (("v_star", dict(color="white" if over is not None else "0.4", ls="--",
                              lw=1.6, label=r"analytic $v^*$")),
              ("v_stick_onset_estimate", dict(color="white" if over is not None
                                              else "0.4", ls=":", lw=1.6,
                                              label=r"averaging $2v^*/\sqrt{5}$")),
              ("v_hopf", dict(color="black", lw=1.4, marker=".", ms=4,
                              label="Hopf point (located)")),
              ("v_stick_onset", dict(color="#CC79A7", lw=1.4, marker=".", ms=4,
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
        ax.set_xlabel(label(xr.Variable((), 0.0, {
            "units": ds["v_hopf"].attrs.get("units", "cm s-1"),
            "long_name": LONG_NAMES.get(along, along)}), along))
        ax.set_ylabel(label(ds[p], p))
    # one legend: the curves, then the regime map's colours (its own legend sits
    # below the panel, where this figure's layout has no room for it)
    handles, names = ax.get_legend_handles_labels()
    regimes = ax.get_legend()
    if regimes is not None:
        handles += list(regimes.legend_handles)
        names += [f"regime: {t.get_text()}" for t in regimes.get_texts()]
        regimes.remove()
    ax.legend(handles, names, fontsize=8, loc="upper right", framealpha=0.85)
    ax.set_title("located boundaries" + ("" if along == "v" else
                                         f" along {along} (no analytic v*)"),
                 fontsize=10)
    if along != "v":
        fig.suptitle(title or f"{ds.attrs.get('title', 'boundaries')}: "
                     f"{fixed_parameters(ds)}", fontsize=10)
        return fig
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
    if "v_stick_onset_estimate" in ds:
        axs.plot(y, (ds["v_stick_onset_estimate"] / ds["v_star"]).values, color="0.4",
                 ls=":", label=r"averaging $\sqrt{4/5}$")
    axs.set_ylabel("stick onset / v*")
    axs.legend(fontsize=8)
    axs.set_title("stick onset against the averaging estimate", fontsize=10)
    for a in (axh, axs):
        a.set_xscale("log" if log else "linear")
        a.set_xlabel(label(ds[p], p))
    fig.suptitle(title or f"{ds.attrs.get('title', 'boundaries')}: "
                 f"{fixed_parameters(ds)}", fontsize=10)
    return fig
