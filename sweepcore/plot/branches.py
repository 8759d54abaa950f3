"""Hysteresis: the stable branches of the up and down scans of a bifurcation
diagram as solid lines, the unstable slip cycles dashed, the jumps as arrows."""
from __future__ import annotations

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

from .._kernels import codes
from ..options import checked_keywords
from .checks import checked_names, checked_result, checked_title
from .style import fixed_parameters, label

# per scan: colour, marker, and the side of the jump arrow
SCANS = {"up": dict(color="#0072B2", marker="o", markersize=4.0),
         "down": dict(color="#D55E00", marker="s", markersize=4.0,
                      markerfacecolor="none")}
UNSTABLE = dict(color="0.25", ls="--", lw=1.4)
_MARKS = (("v_hopf_subcritical", "subcritical Hopf point", ":"),
          ("v_fold", "fold (stick-slip ends)", "-."),
          ("v_hopf", "Hopf point", ":"),
          ("v_stick_onset", "stick onset", "-."))


def _runs(regime: np.ndarray):
    """(start, stop) index ranges of equal regime along the scan."""
    edges = np.flatnonzero(np.diff(regime) != 0) + 1
    bounds = np.r_[0, edges, regime.size]
    return list(zip(bounds[:-1], bounds[1:]))


@checked_keywords
def plot_hysteresis(ds: xr.Dataset, variable: str = "amplitude",
                    title: str | None = None) -> Figure:
    """Stable and unstable branches of a diagram
    (:func:`sweepcore.bifurcation_diagram`): ``variable`` (default the amplitude)
    of each scan's attractor as solid lines, one segment per regime (up: filled
    circles, down: open squares, in their own colours), the jumps between
    regimes as arrows in the scan's direction, the unstable slip cycles
    (``unstable_<variable>``) dashed, and the located boundaries as vertical
    lines."""
    checked_result(ds, "bifurcation_diagram")
    checked_title(title)
    if not isinstance(variable, str):
        raise TypeError(f"variable must be a variable name (str), got {variable!r}")
    (variable,) = checked_names("variable", variable, ds)
    along = ds.attrs.get("along", [d for d in ds.dims if d != "branch"][0])
    if set(ds[variable].dims) != {"branch", along}:
        scanned = [n for n, v in ds.data_vars.items()
                   if set(v.dims) == {"branch", along} and v.dtype.kind == "f"]
        raise ValueError(f"variable={variable!r} is not over the scans (branch, "
                         f"{along}); choose one of {', '.join(scanned)}")
    fig = Figure(figsize=(9.0, 5.0), layout="constrained")
    ax = fig.subplots()
    x = ds[along].values
    for branch in ds.branch.values:
        b = ds.sel(branch=branch)
        style = SCANS.get(str(branch), dict(color="k", marker="."))
        y = b[variable].values
        reg = b.regime.values.astype(int)
        ok = reg != codes.R_UNCONVERGED
        first = True
        for i0, i1 in _runs(reg):
            if reg[i0] in (codes.R_UNCONVERGED, codes.R_FAILED):
                continue
            ax.plot(x[i0:i1], y[i0:i1], ls="-", lw=1.6, **style,
                    label=f"{branch} scan (stable)" if first else None)
            first = False
        order = range(len(x) - 1) if branch != "down" else range(len(x) - 1, 0, -1)
        step = 1 if branch != "down" else -1
        for i in order:
            j = i + step
            if ok[i] and ok[j] and reg[i] != reg[j]:
                ax.annotate("", xy=(x[j], y[j]), xytext=(x[j], y[i]),
                            arrowprops=dict(arrowstyle="->", color=style["color"],
                                            lw=1.0))
    name = "unstable_" + variable
    if name in ds and np.isfinite(ds[name].values).any():
        ax.plot(x, ds[name].values, label="unstable slip cycle", **UNSTABLE)
    for key, text, ls in _MARKS:
        if key in ds and np.isfinite(float(ds[key])) and \
                x.min() <= float(ds[key]) <= x.max():
            ax.axvline(float(ds[key]), color="0.5", lw=0.9, ls=ls,
                       label=f"{text} {float(ds[key]):.6f}")
    ax.set_xlabel(label(ds[along], along))
    ax.set_ylabel(label(ds[variable], variable))
    ax.legend(fontsize=8, loc="best", framealpha=0.85)
    fig.suptitle(title or f"hysteresis: stable branches (solid), unstable slip cycle "
                          f"(dashed); {fixed_parameters(ds)}", fontsize=10)
    return fig
