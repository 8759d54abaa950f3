"""The natural picture of any result file: :func:`plot_result` picks it."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

from ..labels import run_dims, run_statuses
from ..options import checked_keywords
from .basins import plot_basins
from .boundaries import plot_boundaries, plot_diagram
from .branches import plot_hysteresis
from .checks import checked_result, swept
from .forced import (plot_branch, plot_forced_boundaries, plot_forced_map,
                     plot_frequency_response, plot_stroboscopic)
from .lines import plot_lines
from .maps import plot_map
from .style import SYMBOLS, flag_axis, fmt, label
from .trajectories import plot_cases, plot_trajectory


@checked_keywords(also=(plot_trajectory, plot_lines, plot_map))
def plot_result(ds: xr.Dataset, **kwargs) -> Figure:
    """The natural picture of a result Dataset (simulation, 1-D or 2-D sweep).

    Keyword arguments go to :func:`plot_trajectory`, :func:`plot_lines` or
    :func:`plot_map`.
    """
    checked_result(ds)
    kind = ds.attrs.get("sweepcore_kind")
    if kind == "basins":
        return plot_basins(ds, **kwargs)
    if kind == "bifurcation_diagram":
        if "unstable_amplitude" in ds and np.isfinite(ds.unstable_amplitude).any():
            return plot_hysteresis(ds)     # coexisting attractors
        return plot_diagram(ds)
    if kind == "boundaries" and "sticks_below" in ds:
        return plot_forced_boundaries(ds)      # a forced grid's
    if kind == "boundaries":
        along_v = ds.attrs.get("along", "v") == "v"   # a map under curves along v
        return plot_boundaries(ds, over=over_map(ds) if along_v else None)
    if kind == "frequency_response":
        return plot_frequency_response(ds)
    if kind == "stroboscopic_diagram":
        return plot_stroboscopic(ds)
    if kind == "response_branch":
        return plot_branch(ds)
    if "time" in ds.dims:
        statuses = run_statuses(ds)
        if all(s != "ok" for s in statuses):
            raise ValueError(f"a failed simulation (status {' '.join(statuses)}): its "
                             "samples after the failure are NaN, nothing to draw")
        extra = run_dims(ds)
        if extra:          # several runs stacked along a parameter: one row each
            d = extra[0]
            runs = [ds.isel({d: i}) for i in range(ds.sizes[d])]
            if len(statuses) != len(runs):
                statuses = ["ok"] * len(runs)
            eqs = ds["x_eq"].values if "x_eq" in ds and ds["x_eq"].dims == (d,) \
                else None
            return plot_cases(runs, [f"${SYMBOLS.get(d, d)}$ = {fmt(r[d])}"
                                     + ("" if s == "ok" else f" (status {s})")
                                     for r, s in zip(runs, statuses)],
                              title=ds.attrs.get("title"), equilibria=eqs)
        return plot_trajectory(ds, **kwargs)
    dims = swept(ds)
    if not dims:
        raise ValueError("the result has a single point: nothing to plot against")
    if "amplitude" not in ds and "regime" not in ds:
        return _plot_variables(ds)
    numeric = [d for d in dims if ds[d].dtype.kind in "iuf"]
    few = [d for d in numeric if ds.sizes[d] <= 4]
    if len(numeric) == 2 and len(few) == 1 and not ("x" in kwargs or "y" in kwargs):
        numeric.remove(few[0])   # a map 2-4 cells wide reads better as a few lines
    if len(numeric) == 2 and "stops_per_period" in ds:     # a forced response map
        x = kwargs.get("x") or ("Omega" if "Omega" in numeric else numeric[-1])
        y = kwargs.get("y") or next(d for d in numeric if d != x)
        return plot_forced_map(ds, x=x, y=y, **{k: v for k, v in kwargs.items()
                                                if k == "variables"})
    if len(numeric) == 1:
        kwargs = {k: v for k, v in kwargs.items() if k not in ("x", "y")}
        series = [d for d in dims if d != numeric[0]]
        return plot_lines(ds, numeric[0], series=series[0] if series else None,
                          **kwargs)
    return plot_map(ds, **kwargs)


def over_map(ds: xr.Dataset) -> xr.Dataset | None:
    """The map a boundaries result is drawn over (its ``over`` attribute, the
    study's ``[boundary] over`` or ``sweepcore boundary --over``), when it exists:
    the path as recorded (relative to where the command runs), else a file of that
    name beside the result file. None without one."""
    over = ds.attrs.get("over")
    if not over:
        return None
    candidates = [Path(over)]
    source = ds.encoding.get("source")
    if source:
        candidates.append(Path(source).parent / Path(over).name)
    for path in candidates:
        if path.is_file():
            from ..io import open_result
            return open_result(path)
    return None


def _plot_variables(ds: xr.Dataset, max_panels: int = 6) -> Figure:
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
