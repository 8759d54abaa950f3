"""Basin stability: the share of the box of starts that ends on each attractor, as
curves against one parameter or as maps over two."""
from __future__ import annotations

import numpy as np
import xarray as xr
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from matplotlib.colors import BoundaryNorm, ListedColormap

from .._kernels import codes
from ..options import checked_keywords
from .checks import checked_dimension, checked_reference, checked_result, checked_title
from .maps import _plane, hopf_curves, map_panel
from .style import REGIME_COLOURS, SYMBOLS, axis_scale, fmt, label, sweep_title

# the number of attractors a point: 0 grey, 1 light, 2 and more strong (Okabe-Ito)
COEXIST = ("#56B4E9", "#D55E00", "#CC79A7", "#000000")

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
    Two: one map of the number of attractors found (where they coexist) and one
    map of the fraction per attractor (at most four), with the analytic Hopf speed
    the result holds. ``reference``: ``{label: (x, fraction, error)}``, three
    sequences of equal length, drawn as points with error bars (a published table,
    say) on the curves' panel.
    """
    checked_result(ds, "basins")
    checked_title(title)
    reference = checked_reference(reference)
    dims = [d for d in ds.dims if d not in ("attractor", "cycle") and ds.sizes[d] > 1]
    if not dims:
        raise ValueError("ds: the basin result has a single point: nothing to plot "
                         "against")
    head = title or sweep_title(ds)
    box = "starts uniform in " + ", ".join(
        f"${SYMBOLS[n]}$ in [{fmt(r[0])}, {fmt(r[1])}]" for n, r in
        (("x0", np.atleast_1d(ds.attrs.get("x0_range", [np.nan] * 2))),
         ("xdot0", np.atleast_1d(ds.attrs.get("xdot0_range", [np.nan] * 2)))))
    if len(dims) >= 2:
        return _maps(ds, x, y, f"{head}\n{box}")
    checked_dimension("x", x, dims)
    checked_dimension("y", y, ())
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
    for k, (name, (rx, rf, re)) in enumerate(reference.items()):
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
    """Where attractors coexist (their number a point), then the fraction of each
    attractor (at most four), with the Hopf speed the result holds drawn over."""
    names = [str(n) for n in ds["attractor"].values
             if not n.startswith(tuple(codes.REGIME_NAMES[r] for r in
                                       (codes.R_UNCONVERGED, codes.R_FAILED)))
             and str(n) != "none"][:4]
    flat = ds.drop_dims([d for d in ("attractor", "cycle") if d in ds.dims])
    fig = Figure(figsize=(5.6 * (len(names) + 1) + 0.6, 5.0), layout="constrained")
    axs = np.atleast_1d(fig.subplots(1, len(names) + 1, sharex=True, sharey=True))
    sub, x, y, _facet, note = _plane(flat, x, y)
    top = max(2, int(np.nanmax(sub["n_attractors"].values)))
    cmap = ListedColormap(["0.85", *COEXIST[:top]])
    mesh = map_panel(fig, axs[0], sub, "n_attractors", x, y, colorbar=False,
                     cmap=cmap, norm=BoundaryNorm(np.arange(top + 2) - 0.5, top + 1))
    fig.colorbar(mesh, ax=axs[0], shrink=0.9, pad=0.01, ticks=range(top + 1),
                 label="attractors found in the box")
    axs[0].set_title("attractors found: where they coexist (2 and more)", fontsize=10)
    curves = {}
    for ax, name in zip(axs, [None, *names]):
        if name is not None:
            one = flat.assign(basin_fraction=ds["basin_fraction"].sel(
                attractor=name, drop=True))
            sub, x, y, _facet, note = _plane(one, x, y)
            map_panel(fig, ax, sub, "basin_fraction", x, y, vmin=0.0, vmax=1.0)
            ax.set_title(f"basin fraction: {name.replace('_', ' ')}", fontsize=10)
        for draw in hopf_curves(sub, x, y):
            draw(ax)
            curves.setdefault(draw.handle.get_label(), draw.handle)
    if curves:
        fig.legend(handles=list(curves.values()), fontsize=8,
                   loc="outside lower center")
    fig.suptitle(head + note, fontsize=10)
    return fig
