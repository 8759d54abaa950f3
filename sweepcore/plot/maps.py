"""2-D sweeps: the categorical regime map and colour maps of observables, with the
analytic v* and the measured boundaries drawn over them."""
from __future__ import annotations

import warnings

import numpy as np
import xarray as xr
from matplotlib import patheffects
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from .. import law, variables
from ..io import check_flag
from ..options import checked_keywords
from .checks import (checked_dimension, checked_names, checked_result,
                     checked_title, swept)
from .style import (REGIME_COLOURS, SYMBOLS, axis_scale, flag_axis, fmt, is_geometric,
                    label, pretty_units, regime_codes, sweep_title)


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
    dims = swept(ds)
    numeric = [d for d in dims if ds[d].dtype.kind in "iuf"]
    checked_dimension("x", x, numeric)
    checked_dimension("y", y, numeric)
    if x is not None and x == y:
        raise ValueError(f"x and y are both {x!r}: a map needs two different "
                         f"dimensions (swept: {', '.join(numeric)})")
    rest = [d for d in numeric if d not in (x, y)]
    if x is None:
        x = "v" if "v" in rest else rest.pop(0) if rest else None
        rest = [d for d in rest if d != x]
    if y is None:
        y = rest.pop(0) if rest else None
    if x is None or y is None:
        raise ValueError(f"ds must have two swept numeric dimensions for a map; this "
                         f"result has {', '.join(numeric) or 'none'} (plot_result "
                         "draws it)")
    others = [d for d in dims if d not in (x, y)]
    facet = others.pop(0) if others and ds.sizes[others[0]] <= 6 else None
    note = ""
    if others:
        ds = ds.isel({d: 0 for d in others})
        note = "; " + ", ".join(f"${SYMBOLS.get(d, d)}$ = {fmt(ds[d])}"
                                for d in others) + " (first value)"
    return ds, x, y, facet, note


@checked_keywords
def plot_map(ds: xr.Dataset, x: str | None = None, y: str | None = None,
             variables=None, title: str | None = None,
             boundary: bool = True) -> Figure:
    """Maps of a 2-D sweep: categorical regime map and colour maps of observables.

    Parameters
    ----------
    ds : xarray.Dataset
        A result with at least two numeric swept dimensions. A third swept
        dimension of at most six values (e.g. a friction law or a start) gives one
        row per value; further dimensions are reduced to their first value (said in
        the title).
    x, y : str, optional
        Dimensions on the horizontal and vertical axes; default v (if swept) across.
    variables : str or sequence of str, optional
        Panels, left to right: ``"regime"`` (categorical, legend of regime names) or
        any numeric data variable (colour bar with units); a variable over one of
        the two axes only (x_eq over v, v_star over c, ...) is drawn as a line
        against that axis, one that is constant as a line at its value. Default
        regime and amplitude (those the result holds).
    boundary : bool
        Draw the analytic v* curve (and, for the paper's law, the estimate 2
        v*/sqrt(5) of the end of stick-slip; for any law, the Hopf speed v_star the
        file holds over the other axis) and, when x or y is v, the measured Hopf
        boundary and end of stick-slip (:mod:`sweepcore.boundary`).
    """
    checked_result(ds)
    checked_title(title)
    check_flag("boundary", boundary)
    ds, x, y, facet, note = _plane(ds, x, y)
    variables = checked_names("variables", variables, ds, ("regime", "amplitude"))
    if not variables:
        raise ValueError(f"variables: the result holds neither regime nor amplitude; "
                         f"name the panels (has: {', '.join(ds.data_vars)})")
    rows = [ds.isel({facet: i}) for i in range(ds.sizes[facet])] if facet else [ds]
    n = len(variables)
    fig = Figure(figsize=(5.6 * n + 0.6, 5.0 * len(rows) + 0.4), layout="constrained")
    axs = np.atleast_2d(fig.subplots(len(rows), n))
    curves = {}
    shared = _shared_scales(ds, variables, x, y) if facet else {}
    first = None
    for row_axs, sub in zip(axs, rows):
        overlays = _overlays(sub, x, y) if boundary else []
        # the maps first: the line panels share their axes
        for ax, name in sorted(zip(row_axs, variables),
                               key=lambda pair: not _is_map(sub, pair[1], x, y)):
            if not _is_map(sub, name, x, y):
                _line_panel(ax, sub, name, x, y, first)
                continue
            first = _share_axes(ax, first, "xy")
            map_panel(fig, ax, sub, name, x, y, **shared.get(name, {}))
            for draw in overlays:
                # on the regime map the measured boundaries are the colour edges
                if name != "regime" or draw.analytic:
                    draw(ax)
            if ax is not row_axs[0]:
                ax.set_ylabel("")
            if facet:
                ax.set_title(f"{facet} = {fmt(sub[facet])}: {ax.get_title()}",
                             fontsize=10)
        for d in overlays:
            curves.setdefault(d.handle.get_label(), d.handle)
    if curves:    # one legend for the curves of every panel, below them
        fig.legend(handles=list(curves.values()), fontsize=8, loc="outside lower center",
                   ncol=min(len(curves), 2))
    fig.suptitle((title or sweep_title(ds)) + note, fontsize=10)
    return fig


def _is_map(ds, name: str, x: str, y: str) -> bool:
    return {x, y} <= set(ds[name].dims)


def _share_axes(ax, first, which: str):
    """Share ``ax``'s axes ``which`` ("x", "y", "xy") with the first map panel
    ``first`` (None: ``ax`` is the first); returns the first map panel."""
    if first is None:
        return ax if which == "xy" else None
    if "x" in which:
        ax.sharex(first)
    if "y" in which:
        ax.sharey(first)
    return first


def _line_panel(ax, ds, name: str, x: str, y: str, first) -> None:
    """A variable over one of the map's axes (or none) beside the maps: a line
    against that axis, drawn so that the axis lines up with the maps' (over y: the
    value across, y up), shared with the first map panel ``first``."""
    da = ds[name]
    rest = [d for d in da.dims if d not in (x, y)]
    if rest:
        da = da.isel({d: 0 for d in rest})
    along = y if y in da.dims else x
    coord = ds[along].values
    order = np.argsort(coord)
    values = np.broadcast_to(da.values, coord.shape) if da.ndim == 0 else \
        da.transpose(along).values
    style = dict(color="#0072B2", marker=".", ms=4, lw=1.2)
    _share_axes(ax, first, "y" if along == y else "x")
    if along == y:
        ax.plot(values[order], coord[order], **style)
        ax.set_yscale(axis_scale(ds, y))
        ax.set_xlabel(label(da, name))
        ax.set_ylabel(label(ds[y], y))
        flag_axis(ax, da, "x")
    else:
        ax.plot(coord[order], values[order], **style)
        ax.set_xscale(axis_scale(ds, x))
        ax.set_xlabel(label(ds[x], x))
        ax.set_ylabel(label(da, name))
        flag_axis(ax, da, "y")
    over = "constant" if da.ndim == 0 else f"over {along} only"
    ax.set_title(f"{da.attrs.get('long_name', name)} ({over})", fontsize=10)
    ax.grid(alpha=0.3)


def _shared_scales(ds: xr.Dataset, variables, x: str, y: str) -> dict:
    """``{name: {"vmin", "vmax"}}``: one colour scale per variable over every row of
    a faceted map, so that a colour means the same value in each row (a variable
    uniform over the whole map keeps its own "uniform" panel)."""
    out = {}
    for name in variables:
        if name == "regime" or ds[name].dtype.kind not in "iuf" or \
                not _is_map(ds, name, x, y):
            continue
        data = np.ma.masked_invalid(ds[name].values.astype(float))
        if data.count() and _uniform(data, _resolution(name)) is None:
            out[name] = {"vmin": float(data.min()), "vmax": float(data.max())}
    return out


def map_panel(fig: Figure, ax, ds: xr.Dataset, name: str, x: str, y: str,
              colorbar: bool = True, **kwargs):
    """Draw variable ``name`` of a 2-D result on ``ax`` over dimensions (x, y).

    ``"regime"`` is drawn as a categorical map with a legend of regime names and
    shares; any other variable as a colour map (``kwargs`` go to ``pcolormesh``)
    with a colour bar labelled with its units. Geometric axes get a log scale.
    Returns the QuadMesh.
    """
    ds = ds.sortby([x, y]).transpose(y, x, ...)
    xlog, ylog = axis_scale(ds, x) == "log", axis_scale(ds, y) == "log"
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
    values, names = regime_codes(ds)
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


def _resolution(name: str) -> float:
    """The relative spread below which variable ``name`` is drawn "uniform": the
    accuracy of a measured observable (1e-6, an answer's contract), the rounding of
    an analytic one (q, v*, x_eq, ...: closed forms, every digit meant; at large v
    q's Stribeck term is 1e-9 of it and was drawn as one rounded value)."""
    return 1e-12 if name in variables.ANALYTIC else 1e-6


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
    rel = _resolution(name)
    uniform = _uniform(data, rel)
    if uniform is not None and "norm" not in kwargs and "vmin" not in kwargs:
        # a colour scale stretched over rounding noise would invent structure
        c, spread = uniform
        half = max(0.05 * abs(c), 1e-12)
        kwargs.update(vmin=c - half, vmax=c + half)
        digits = 12 if rel < 1e-6 else 6          # every digit the value means
        ax.text(0.5, 0.5, f"uniform: {c:.{digits}g} "
                          f"{pretty_units(da.attrs.get('units'))}\n"
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


def hopf_curves(ds: xr.Dataset, x: str, y: str) -> list:
    """The analytic curves of the (x, y) plane (v* and, for the paper's law, the
    estimate of the stick onset), each a callable drawing it on an axes, with a
    ``handle`` for the legend."""
    return _analytic_curves(ds, x, y)


def _overlays(ds: xr.Dataset, x: str, y: str) -> list:
    out = _analytic_curves(ds, x, y)
    if "v" in (x, y):
        out.extend(_measured_boundaries(ds, x, y))
    return out


# v* and the averaging estimate of the end of stick-slip (sweepcore.law): the small
# cycle has velocity amplitude 2 sqrt(v*^2 - v^2) (first-order averaging of eq. 41
# about x_eq), which reaches the belt speed v when v = 2 v*/sqrt(5); see
# docs/studies.md, "hopf_map".
_ANALYTIC = (
    (lambda src: law.derived("v_star", src), dict(
        color="white", ls="--", lw=2.0,
        label=r"analytic $v^* = \sqrt{\alpha_1/3\alpha_2}$ ($q = 0$)")),
    (law.stick_onset_estimate, dict(
        color="white", ls=":", lw=2.0,
        label=r"estimate: stick-slip below $2v^*/\sqrt{5}$")),
)


def _analytic_curves(ds, x, y) -> list:
    """v* and the averaging estimate of the stick onset in the (x, y) plane.

    Drawn when one axis is v and the other alpha1 or alpha2 (the other fixed);
    with any other law or axis, the Hopf speed v_star the result holds over the
    other axis (:func:`_stored_hopf_curve`).
    """
    other = y if x == "v" else x if y == "v" else None
    if other is None:
        return []
    if other not in ("alpha1", "alpha2"):
        return _stored_hopf_curve(ds, x, y, other)
    fixed = "alpha2" if other == "alpha1" else "alpha1"
    if fixed not in ds.coords or ds[fixed].ndim != 0:
        return []
    ends = ds[other].values[[0, -1]]
    s = np.geomspace(*ends, 400) if is_geometric(ds[other].values) \
        else np.linspace(*ends, 400)
    src = {other: s, fixed: float(ds[fixed])}
    out = []
    for formula, style in _ANALYTIC:
        vv = np.broadcast_to(formula(src), s.shape)
        vv = np.where((vv >= ds.v.values.min()) & (vv <= ds.v.values.max()), vv, np.nan)
        if np.isfinite(vv).any():
            # white on the maps; outlined in grey in the legend, which is on white
            handle = Line2D([], [], **style, path_effects=[
                patheffects.withStroke(linewidth=4, foreground="0.45")])
            out.append(_Overlay(*((vv, s) if x == "v" else (s, vv)), handle,
                                analytic=True))
    return out


def _stored_hopf_curve(ds, x, y, other) -> list:
    """The analytic Hopf speed the result holds (``v_star``, any friction law) as
    a curve over the map's other axis, or a line where it does not depend on it;
    the label says whether the Hopf point is sub- or supercritical where the result
    holds the first Lyapunov coefficient."""
    if "v_star" not in ds or not set(ds["v_star"].dims) <= {other}:
        return []
    s = ds[other].values
    vv = np.broadcast_to(ds["v_star"].transpose(*ds["v_star"].dims).values, s.shape)
    vmin, vmax = float(np.nanmin(ds.v.values)), float(np.nanmax(ds.v.values))
    vv = np.where((vv >= vmin) & (vv <= vmax), vv, np.nan)
    if not np.isfinite(vv).any():
        return []
    kind = ""
    if "first_lyapunov" in ds and set(ds["first_lyapunov"].dims) <= {other}:
        l1 = np.unique(np.sign(ds["first_lyapunov"].values[np.isfinite(
            ds["first_lyapunov"].values)]))
        kind = {1.0: ", subcritical", -1.0: ", supercritical"}.get(
            float(l1[0]), "") if l1.size == 1 else ""
    order = np.argsort(s)
    handle = Line2D([], [], color="white", ls="--", lw=2.0,
                    label=rf"analytic Hopf speed $v^*$ (stored{kind})",
                    path_effects=[patheffects.withStroke(linewidth=4,
                                                         foreground="0.45")])
    xs, ys = vv[order], s[order]
    return [_Overlay(*((xs, ys) if x == "v" else (ys, xs)), handle, analytic=True)]


def _measured_boundaries(ds, x, y) -> list:
    """The measured Hopf boundary and end of stick-slip along v (sweepcore.boundary).

    Taken from the result when the sweep stored them, else measured here.
    """
    names = ("v_hopf_measured", "v_stick_onset", "v_reversal_lower", "v_reversal_upper")
    if all(n in ds for n in names):
        bd = ds
    else:
        try:
            from ..boundary import hopf_boundary
            bd = hopf_boundary(ds, axis="v")
        except Exception as err:  # a picture must not fail for an overlay
            warnings.warn(f"measured boundary not drawn: {err}", stacklevel=3)
            return []
    other = y if x == "v" else x
    styles = {
        "v_hopf_measured": dict(color="black", ls="-", lw=1.3,
                                label="measured boundary: cycle | equilibrium"),
        "v_stick_onset": dict(color="#CC79A7", ls="-", lw=1.3,
                              label="measured stick onset (end of stick-slip)"),
        # one legend entry for both edges (the legend keeps one handle per label)
        **{f"v_reversal_{e}": dict(color="#009E73", ls="--", lw=1.2,
                                   label="measured edges of the slide-slide-reversal "
                                         "band") for e in ("lower", "upper")},
    }
    found = []
    for name in names:
        b = bd[name]
        if b.dims != (other,) or not np.isfinite(b.values).any():
            continue
        b = b.sortby(other)
        vals, coord = b.values, b[other].values
        style = dict(styles[name])
        if coord.size < 5:      # a few values of the other axis: points, not a line
            style.update(ls="", marker="o", ms=5)
        found.append(_Overlay(*((vals, coord) if x == "v" else (coord, vals)),
                              Line2D([], [], **style)))
    return found
