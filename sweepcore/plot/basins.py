"""Basin stability: the share of the box of starts that ends on each attractor, as
curves against one parameter or as maps over two."""
from __future__ import annotations

import numpy as np
import xarray as xr
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from .._kernels import codes
from ..options import checked_keywords
from .maps import _plane, map_panel
from .style import REGIME_COLOURS, SYMBOLS, axis_scale, fmt, label, sweep_title

_DASHES = ("-", "--", ":", "-.")


def _style(ds, j: int) -> dict:
    """Colour of the attractor's regime; a further attractor of the same regime
    (``stick_slip_2``) dashed."""
    regime = int(ds["attractor_regime"].values[j])
    name = str(ds["attractor"].values[j])
    rank = int(name.rsplit("_", 1)[1]) - 1 if name[-1].isdigit() and "_" in name else 0
    return dict(color=REGIME_COLOURS.get(regime, "k"), ls=_DASHES[rank % 4])


@checked_keywords
def plot_basins(ds: xr.Dataset, x: str | None = None, y: str | None = None,
                title: str | None = None, reference=None) -> Figure:
    """The basin fractions of a :func:`sweepcore.basin_stability` result.

    One swept dimension: the fraction of each attractor against it, with a band of
    two errors (``basin_fraction_error``), points of the sampled route marked.
    Two: one map of the fraction per attractor (at most four). ``reference``:
    ``{label: (x, fraction, error)}`` drawn as points with error bars (a published
    table, say) on the curves' panel.
    """
    dims = [d for d in ds.dims if d != "attractor" and ds.sizes[d] > 1]
    if not dims:
        raise ValueError("the basin result has a single point: nothing to plot against")
    head = title or sweep_title(ds)
    box = "starts uniform in " + ", ".join(
        f"${SYMBOLS[n]}$ in [{fmt(r[0])}, {fmt(r[1])}]" for n, r in
        (("x0", np.atleast_1d(ds.attrs.get("x0_range", [np.nan] * 2))),
         ("xdot0", np.atleast_1d(ds.attrs.get("xdot0_range", [np.nan] * 2)))))
    if len(dims) >= 2:
        return _maps(ds, x, y, f"{head}\n{box}")
    dim = dims[0]
    ds = ds.isel({d: 0 for d in ds.dims if d not in (dim, "attractor")
                  and ds.sizes[d] > 1})
    order = np.argsort(ds[dim].values)
    xs = ds[dim].values[order]
    sampled = ds["basin_route"].values[order] == 1 if "basin_route" in ds else \
        np.zeros(xs.size, bool)
    fig = Figure(figsize=(8, 4.6), layout="constrained")
    ax = fig.subplots()
    handles = []
    for j, name in enumerate(ds["attractor"].values):
        f = ds["basin_fraction"].isel(attractor=j).values[order]
        e = ds["basin_fraction_error"].isel(attractor=j).values[order]
        st = _style(ds, j)
        handles += ax.plot(xs, f, lw=1.4, label=str(name).replace("_", " "), **st)
        ax.fill_between(xs, f - 2 * e, f + 2 * e, color=st["color"], alpha=0.25, lw=0)
        if sampled.any():
            ax.plot(xs[sampled], f[sampled], "o", ms=3, mfc="none", color=st["color"])
    if sampled.any():
        handles.append(Line2D([], [], marker="o", mfc="none", ls="", color="0.3",
                              label="sampled route (band: 2 standard errors)"))
    vstar = ds["v_star"] if dim == "v" and "v_star" in ds else None
    if vstar is not None and vstar.ndim == 0 and np.isfinite(float(vstar)):
        handles.append(ax.axvline(float(vstar), color="0.4", ls=":", lw=1.0,
                                  label=f"Hopf point $v^*$ = {float(vstar):.4g} "
                                        "(analytic)"))
    for k, (name, (rx, rf, re)) in enumerate((reference or {}).items()):
        handles.append(ax.errorbar(rx, rf, yerr=re, fmt="sk"[k % 2], ms=4, mfc="none",
                                   color="k", capsize=2, lw=0.8, label=name))
    ax.set_ylim(-0.02, 1.02)
    ax.set_xscale(axis_scale(ds, dim))
    ax.set_xlabel(label(ds[dim], dim))
    ax.set_ylabel(label(ds["basin_fraction"], "basin_fraction"))
    ax.grid(alpha=0.3)
    fig.legend(handles=handles, fontsize=8, loc="outside lower center",
               ncol=min(len(handles), 3))
    fig.suptitle(f"{head}\n{box}", fontsize=10)
    return fig


def _maps(ds, x, y, head):
    names = [str(n) for n in ds["attractor"].values
             if not n.startswith(tuple(codes.REGIME_NAMES[r] for r in
                                       (codes.R_UNCONVERGED, codes.R_FAILED)))][:4]
    flat = ds.drop_dims("attractor")
    fig = Figure(figsize=(5.6 * len(names) + 0.6, 5.0), layout="constrained")
    axs = np.atleast_1d(fig.subplots(1, len(names), sharex=True, sharey=True))
    note = ""
    for ax, name in zip(axs, names):
        one = flat.assign(basin_fraction=ds["basin_fraction"].sel(attractor=name,
                                                                  drop=True))
        sub, x, y, _facet, note = _plane(one, x, y)
        map_panel(fig, ax, sub, "basin_fraction", x, y, vmin=0.0, vmax=1.0)
        ax.set_title(f"basin fraction: {name.replace('_', ' ')}", fontsize=10)
    fig.suptitle(head + note, fontsize=10)
    return fig
