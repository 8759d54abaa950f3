"""1-D sweeps: observables against the swept parameter, points coloured by regime,
with the paper's reference curves."""
from __future__ import annotations

import numpy as np
import xarray as xr
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from .. import labels
from .._kernels import codes
from ..options import checked_keywords
from .checks import (checked_dimension, checked_names, checked_result,
                     checked_title, swept)
from .style import (REGIME_COLOURS, axis_scale, flag_axis, fmt, label, regime_codes,
                    sweep_title)


def _observable_reference(ds: xr.Dataset, dim: str, name: str):
    """Paper's reference curve for ``name`` along ``dim``: (values, label) or None."""
    if name == "amplitude" and "v" in ds and "omega" in ds:
        ref = np.abs(ds["v"]) / ds["omega"]
        return ref, r"$v/\omega$ (paper, eq. 39)"
    if name == "mean" and "x_eq" in ds:
        return ds["x_eq"], r"equilibrium $x_{eq}$ (eq. 43)"
    return None


_MARKERS = "osD^vP"


@checked_keywords
def plot_lines(ds: xr.Dataset, dim: str, variables=None,
               title: str | None = None, series: str | None = None) -> Figure:
    """Observables of a 1-D sweep against ``dim``, points coloured by regime.

    The paper's reference curves are drawn beside the measurement: v/omega for the
    amplitude (eq. 39), x_eq for the mean (eq. 43); v* as a vertical line when ``dim``
    is v and alpha1, alpha2 are fixed. ``series``: a second dimension (e.g. several
    starts), one marker per value (at most six; further dimensions at their first
    value). ``variables``: a name or a sequence of names (default amplitude and
    mean, those the result holds).
    """
    checked_result(ds)
    checked_title(title)
    dims = swept(ds)
    if not isinstance(dim, str):
        raise TypeError(f"dim must be a dimension name (str), got {dim!r}")
    checked_dimension("dim", dim, [d for d in dims if ds[d].dtype.kind in "iuf"])
    checked_dimension("series", series, [d for d in dims if d != dim])
    variables = checked_names("variables", variables, ds, ("amplitude", "mean"))
    if not variables:
        raise ValueError(f"variables: the result holds neither amplitude nor mean; "
                         f"name the panels (has: {', '.join(ds.data_vars)})")
    keep = (dim, series) if series else (dim,)
    ds = ds.isel({d: 0 for d in dims if d not in keep})
    ds = ds.isel({series: slice(0, len(_MARKERS))}) if series else ds
    # a measured law (its samples on law_point) gets a panel of its own
    table = "law_speed" in ds and ds["law_speed"].dims == ("law_point",)
    fig = Figure(figsize=(8, 2.9 * (len(variables) + table) + 0.8), layout="constrained")
    axs = np.atleast_1d(fig.subplots(len(variables) + table, 1))
    if table:
        _friction_panel(axs[-1], ds)
        axs = axs[:-1]
    for ax in axs[1:]:
        ax.sharex(axs[0])
    for ax in axs[:-1]:
        ax.tick_params(labelbottom=False)
    x = ds[dim].values
    order = np.argsort(x)
    handles = {}
    for ax, name in zip(axs, variables):
        for k, sub in enumerate(_series(ds, series)):
            _regime_points(ax, sub, dim, name, x, order, _MARKERS[k], handles)
            if series:
                handles[f"s{k}"] = Line2D([], [], color="0.35", marker=_MARKERS[k],
                                          ls="-", mfc="none",
                                          label=f"{series} = {fmt(sub[series])}")
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
        ax.set_xscale(axis_scale(ds, dim))
    axs[-1].set_xlabel(label(ds[dim], dim))
    regimes = [h for k, h in handles.items() if k in codes.REGIME_NAMES.values()]
    rest = [h for k, h in handles.items() if k not in codes.REGIME_NAMES.values()]
    # beside the panels, never over the data
    fig.legend(handles=regimes + rest, fontsize=8, loc="outside lower center",
               ncol=3)
    fig.suptitle(title or sweep_title(ds), fontsize=10)
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
    values, names = regime_codes(ds)
    for val, rname in zip(values, names):
        sel = regime == val
        if sel.any():
            handles[rname] = ax.scatter(x[sel], y[sel], s=14, zorder=2, marker=marker,
                                        color=REGIME_COLOURS.get(val, "k"),
                                        label=rname.replace("_", " "))


def _law_object(ds) -> bool:
    """Whether the result's law is an object (a table, Leine's ...), not the
    analytic family: it records the law's name."""
    return "law" in ds.attrs or "law" in ds.dims


def _vstar_line(ax, ds, dim, handles):
    """v* as a vertical line where it is one value inside the axis' range (a line
    off the range would name in the legend what the picture does not show)."""
    if dim != "v" or "v_star" not in ds:
        return
    vs = np.unique(ds["v_star"].values)
    v = ds["v"].values
    if vs.size == 1 and v.min() <= vs[0] <= v.max():
        what = "Hopf speed" if _law_object(ds) else "analytic"
        handles["v*"] = ax.axvline(vs[0], color="#D55E00", ls=":", lw=1.2,
                                   label=f"{what} $v^*$ = {vs[0]:.3g}")


def _friction_panel(ax, ds):
    """The measured law the sweep ran on: its table's samples, force against
    relative speed, with the Hopf speed v* (where c + F'(-v) = 0)."""
    s, f = ds["law_speed"].values, ds["law_force"].values
    ax.plot(s, f, "o-", color="0.35", ms=4, lw=0.8, label="measured table (samples)")
    vs = np.unique(ds["v_star"].values) if "v_star" in ds else np.array([])
    if vs.size == 1 and np.isfinite(vs[0]):
        ax.axvline(vs[0], color="#D55E00", ls=":", lw=1.2)
    ax.set_xlabel(label(ds["law_speed"], "law_speed"))
    ax.set_ylabel(label(ds["law_force"], "law_force"))
    name = ds.attrs.get("law")
    ax.set_title(f"friction law{f' {name!r}' if name else ''}: the table the sweep ran "
                 "on", fontsize=9)
    ax.grid(alpha=0.3)


def _small_cycle(ax, ds, dim, handles):
    """Averaging estimate A = 2 sqrt(v*^2 - v^2)/omega between the estimated stick
    onset (2 v*/sqrt(5), :func:`sweepcore.law.stick_onset_estimate`) and v*.

    First-order averaging of eq. (41) about x_eq gives the velocity amplitude
    2 sqrt(v*^2 - v^2) of the small slip cycle; it reaches the belt speed (and the
    cycle starts to stick) at v = 2 v*/sqrt(5). See docs/studies.md.
    """
    if dim != "v" or "v_star" not in ds or "omega" not in ds or _law_object(ds):
        return
    vs, om = np.unique(ds["v_star"].values), np.unique(ds["omega"].values)
    onset = np.unique(labels.stick_onset_estimate(ds).values)
    if vs.size != 1 or om.size != 1 or onset.size != 1 or not np.isfinite(vs[0]):
        return
    v = np.linspace(onset[0], vs[0], 200)
    v = v[(v >= ds.v.values.min()) & (v <= ds.v.values.max())]
    if v.size:
        handles["small"] = ax.plot(v, 2 * np.sqrt(vs[0] ** 2 - v ** 2) / om[0],
                                   color="k", lw=1.2, ls=":", zorder=3,
                                   label=r"averaging: $2\sqrt{v^{*2} - v^2}/\omega$")[0]
