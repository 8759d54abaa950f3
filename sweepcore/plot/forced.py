"""Pictures of forced responses: the response map over (Omega, F0) with Hong & Liu's
classes (zero-duration stops and finite sticks per response period), the
frequency-response curve swept up and down, and the stroboscopic diagram."""
from __future__ import annotations

import numpy as np
import xarray as xr
from matplotlib.colors import BoundaryNorm, ListedColormap, LogNorm
from matplotlib.figure import Figure
from matplotlib.patches import Patch

from ..options import checked_keywords
from .._kernels import codes
from .checks import checked_result
from .maps import _edges
from .style import REGIME_COLOURS, axis_scale, fixed_parameters, label

FORCED_MAP_VARIABLES = ("stops_per_period", "sticks_per_period", "multiplicity",
                        "amplitude")
CLASS_VARIABLES = ("stops_per_period", "sticks_per_period", "multiplicity")
# the excitation's axes, labelled short (their long names are sentences)
SHORT = {"F0": "$F_0$", "Omega": r"$\Omega$", "phi": r"$\varphi$", "Y0": "$Y_0$"}
# classes drawn apart from the counts: a response not measured (regime) or not ok
SPECIAL_COLOURS = {"stuck": REGIME_COLOURS[codes.R_STUCK],
                   "unbounded": REGIME_COLOURS[codes.R_UNBOUNDED],
                   "aperiodic": "#000000", "not ok": "#F0E442"}
COUNT_COLOURS = ("#FFFFFF", "#56B4E9", "#009E73", "#E69F00", "#0072B2", "#D55E00",
                 "#CC79A7", "#882255", "#44AA99", "#117733", "#332288", "#AA4499",
                 "#DDCC77", "#88CCEE", "#661100", "#6699CC")


def _classes(ds: xr.Dataset, name: str) -> tuple[np.ndarray, list[str]]:
    """Integer class of every cell of count variable ``name`` and the class names:
    the count where the response is ok and measured, else its regime (stuck,
    unbounded, aperiodic) or "not ok" (a status other than ok)."""
    val = ds[name].values.astype(float)
    val = np.where(np.isfinite(val), val, -1).astype(int)     # multiplicity: NaN
    regime = ds["regime"].values
    ok = ds["status"].values == codes.OK
    names = np.where(ok & (val >= 0), val.astype(str), "not ok").astype(object)
    for code in (codes.R_STUCK, codes.R_UNBOUNDED, codes.R_APERIODIC):
        names[ok & (regime == code)] = codes.REGIME_NAMES[code]
    counts = sorted({int(n) for n in names.ravel() if n.lstrip("-").isdigit()})
    order = [str(n) for n in counts] + [s for s in SPECIAL_COLOURS
                                        if (names == s).any()]
    index = {s: i for i, s in enumerate(order)}
    return np.vectorize(index.get, otypes=[int])(names), order


def _class_panel(fig, ax, ds, name, xe, ye):
    cls, order = _classes(ds, name)
    colours = [SPECIAL_COLOURS[s] if s in SPECIAL_COLOURS else
               COUNT_COLOURS[int(s) % len(COUNT_COLOURS)] for s in order]
    cmap = ListedColormap(colours)
    norm = BoundaryNorm(np.arange(len(order) + 1) - 0.5, len(order))
    ax.pcolormesh(xe, ye, cls, cmap=cmap, norm=norm, shading="flat", rasterized=True)
    total = cls.size
    patches = [Patch(facecolor=c, edgecolor="0.3", lw=0.5,
                     label=f"{s} ({100 * (cls == i).sum() / total:.0f} %)")
               for i, (s, c) in enumerate(zip(order, colours))]
    ax.legend(handles=patches, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1),
              title=ds[name].attrs.get("long_name", name), title_fontsize=7)
    ax.set_title(ds[name].attrs.get("long_name", name), fontsize=10)


def continuous_motion_boundary(ds: xr.Dataset, Omega: np.ndarray):
    """F0 [kN] on the continuous-motion boundary at each Omega [rad/s]:
    F0 = r / r_b(Omega/omega), above which Den Hartog's motion has no stick
    (``sweepcore.excitations.theory.continuous_motion_boundary``), where the map is
    Den Hartog's case (v = 0, c = 0, Coulomb friction, no base motion); None
    elsewhere or where that module is not installed."""
    try:
        from ..excitations import theory
        r_b = theory.continuous_motion_boundary
    except (ImportError, AttributeError):   # the closed forms are not installed
        return None
    def scalar(n, default=0.0):     # a fixed parameter (a swept one: None)
        if n not in ds:
            return default
        return float(ds[n]) if ds[n].ndim == 0 else None
    v, c, y0 = scalar("v"), scalar("c"), scalar("Y0")
    a1, a2 = scalar("alpha1"), scalar("alpha2")
    r_y, r_k = scalar("r_y", None), scalar("r_k", None)
    omega = scalar("omega", None)
    if None in (v, c, y0, a1, a2, r_y, omega) or (v, c, y0, a1, a2) != (0,) * 5 \
            or (r_k is not None and r_k != r_y):
        return None
    return r_y / r_b(np.asarray(Omega) / omega)


def _boundary_lines(ax, bds: xr.Dataset, x: str) -> None:
    """A forced boundary file's curves over ``x`` (its one dimension): the stick
    onset solid, the stops change dotted where it differs, Den Hartog's boundary
    dashed where it applies."""
    along = bds.attrs["along"]
    u = bds[x].values
    onset = bds[f"{along}_stick_onset"].values
    ax.plot(u, onset, "-", color="k", lw=1.6, marker=".", ms=4,
            label=f"{along} stick onset (located)")
    stops = bds[f"{along}_stops_change"].values
    if not np.allclose(stops, onset, rtol=1e-6, equal_nan=True):
        ax.plot(u, stops, ":", color="#882255", lw=1.4, label=f"{along} stops change")
    if f"{along}_den_hartog" in bds:
        ax.plot(u, bds[f"{along}_den_hartog"].values, "--", color="#E69F00", lw=1.2,
                label="Den Hartog r / r_b(Omega/omega)")


@checked_keywords
def plot_forced_boundaries(ds: xr.Dataset) -> Figure:
    """A forced boundary file (``locate_boundaries`` / ``continue_boundary`` of a
    forced grid over one axis): the stick onset and the stops change against that
    axis, Den Hartog's boundary beside them where it applies."""
    checked_result(ds)
    along = ds.attrs.get("along")
    if ds.attrs.get("sweepcore_kind") != "boundaries" or "sticks_below" not in ds:
        raise ValueError("ds must be a forced boundary file (locate_boundaries of a "
                         "forced grid)")
    dims = [d for d in ds[f"{along}_stick_onset"].dims]
    if len(dims) != 1:
        raise ValueError(f"a forced boundary file over one axis is drawn, this one is "
                         f"over {dims}")
    fig = Figure(figsize=(7, 4), layout="constrained")
    ax = fig.subplots()
    _boundary_lines(ax, ds, dims[0])
    ax.set_xlabel(_axis_label(ds, dims[0]))
    ax.set_ylabel(_axis_label(ds, along) if along in ds.coords else
                  f"{along} [{ds[f'{along}_stick_onset'].attrs.get('units', '')}]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.suptitle(f"{ds.attrs.get('title', '')}\n{fixed_parameters(ds)}", fontsize=9)
    return fig


@checked_keywords
def plot_forced_map(ds: xr.Dataset, x: str = "Omega", y: str = "F0",
                    variables=FORCED_MAP_VARIABLES, boundaries=None) -> Figure:
    """A forced response map: the count variables (``stops_per_period``,
    ``sticks_per_period``) as categorical maps, any other as a colour map (the
    amplitude on a log scale), over (x, y); with Den Hartog's continuous-motion
    boundary F0 = r / r_b(Omega/omega) drawn over each panel where it applies.

    Parameters
    ----------
    ds : xarray.Dataset
        A forced sweep (``sweepcore.sweep`` of a Grid with F0 or Y0).
    x, y : str
        Its swept dimensions across and up (default Omega and F0).
    variables : sequence of str
        One panel each.
    boundaries : xarray.Dataset, optional
        A forced boundary file along ``y`` over ``x`` (``locate_boundaries`` of the
        same slider): its stick onset drawn over each panel.
    """
    checked_result(ds, "sweep")
    for n in (x, y):
        if n not in ds.dims:
            raise ValueError(f"{n!r} is not a dimension of the map (has "
                             f"{', '.join(ds.dims)})")
    ds = ds.sortby([x, y]).transpose(y, x, ...)
    xlog, ylog = axis_scale(ds, x) == "log", axis_scale(ds, y) == "log"
    xe, ye = _edges(ds[x].values, xlog), _edges(ds[y].values, ylog)
    variables = list(variables)
    cols = 2 if len(variables) > 2 else 1
    rows = -(-len(variables) // cols)
    fig = Figure(figsize=(6.6 * cols, 4.2 * rows + 0.6), layout="constrained")
    axs = np.atleast_1d(fig.subplots(rows, cols)).ravel()
    for ax in axs[len(variables):]:
        ax.set_visible(False)
    # the boundary on a fine grid of the map's frequencies (a smooth curve)
    fine = (np.geomspace if xlog else np.linspace)(ds[x].values.min(),
                                                   ds[x].values.max(), 400)
    boundary = continuous_motion_boundary(ds, fine) if (x, y) == ("Omega", "F0") \
        else None
    for ax, name in zip(axs, variables):
        if name not in ds:
            raise ValueError(f"{name!r} is not a variable of the map")
        if name in CLASS_VARIABLES:
            _class_panel(fig, ax, ds, name, xe, ye)
            extra = []
        else:
            extra = _value_panel(fig, ax, ds, name, xe, ye)
        if boundary is not None:
            ax.plot(fine, boundary, "k--", lw=1.2,
                    label="F0 = r / r_b(Omega/omega): no stick above (Den Hartog)")
        if boundaries is not None and f"{y}_stick_onset" in boundaries:
            ax.plot(boundaries[x].values, boundaries[f"{y}_stick_onset"].values, "-",
                    color="#CC79A7", lw=1.6, label=f"{y} stick onset (located)")
        handles = ax.get_legend_handles_labels()[0] + extra
        if name not in CLASS_VARIABLES and handles:
            ax.legend(handles=handles, loc="lower right", fontsize=7)
        ax.set_xscale("log" if xlog else "linear")
        ax.set_yscale("log" if ylog else "linear")
        ax.set_xlim(xe[0], xe[-1])
        ax.set_ylim(ye[0], ye[-1])
        ax.set_xlabel(_axis_label(ds, x))
        ax.set_ylabel(_axis_label(ds, y))
    names = [ds[n].attrs.get("long_name", n) for n in variables]
    drawn = ", ".join(names[:-1]) + " and " + names[-1] if len(names) > 1 else names[0]
    source = ds.attrs.get("study_title") or ds.attrs.get("title")
    fig.suptitle(f"{drawn} over ({_symbol(x)}, {_symbol(y)})\n"
                 + (f"from: {source}\n" if source else "")
                 + fixed_parameters(ds), fontsize=9)
    return fig


def _symbol(name: str) -> str:
    return SHORT.get(name, name)


def _value_panel(fig, ax, ds, name, xe, ye) -> list:
    """A variable that is not a count, as a colour map of its ok points (the
    amplitude on a log scale where it spans a decade); stuck points have no
    response to measure (no multiplier, no period: their floquet of 1 or amplitude
    of 0 is not a value), so they are drawn grey, with a legend handle saying so
    (returned)."""
    ok = ds["status"].values == codes.OK
    stuck = ok & (ds["regime"].values == codes.R_STUCK)
    data = np.ma.masked_invalid(np.where(ok & ~stuck, ds[name].values.astype(float),
                                         np.nan))
    pos = data[data > 0]
    norm = LogNorm(pos.min(), pos.max()) if name == "amplitude" and \
        pos.size and pos.max() > 10 * pos.min() else None
    mesh = ax.pcolormesh(xe, ye, np.ma.masked_where(data <= 0, data) if norm
                         else data, norm=norm, shading="flat", rasterized=True)
    fig.colorbar(mesh, ax=ax, shrink=0.9, pad=0.01).set_label(label(ds[name], name))
    ax.set_title(ds[name].attrs.get("long_name", name) + " (ok points"
                 + ("; stuck: grey" if stuck.any() else "") + ")", fontsize=10)
    if not stuck.any():
        return []
    grey = SPECIAL_COLOURS["stuck"]
    ax.pcolormesh(xe, ye, np.ma.masked_where(~stuck, np.zeros(stuck.shape)),
                  cmap=ListedColormap([grey]), shading="flat", rasterized=True)
    return [Patch(facecolor=grey, edgecolor="0.3", lw=0.5,
                  label=f"stuck: no motion, no {name} "
                        f"({100 * stuck.sum() / stuck.size:.0f} %)")]


def _axis_label(ds, name: str) -> str:
    if name in SHORT:
        return f"{SHORT[name]} [{ds[name].attrs.get('units', '')}]".replace(
            "rad s-1", "rad/s")
    return label(ds[name], name)


@checked_keywords
def plot_frequency_response(ds: xr.Dataset, variables=("amplitude", "mean")) -> Figure:
    """A frequency-response curve (``sweepcore.frequency_response``): each variable
    against Omega, the up sweep solid with upward triangles, the down sweep dashed
    with downward ones; points whose status is not ok hollow; the band where the two
    sweeps differ (two coexisting responses, between the jumps) shaded; with its
    branches (``branches=True``) those too, grey, stable solid and unstable
    dashed, their special points marked (:func:`plot_branch`). A count
    per response period (sticks, stops) is marked ``6 per 13 T`` where the response
    repeats only after n > 1 forcing periods T."""
    checked_result(ds)
    if ds.attrs.get("sweepcore_kind") != "frequency_response":
        raise ValueError("ds must be a frequency-response curve "
                         "(sweepcore.frequency_response)")
    variables = list(variables)
    fig = Figure(figsize=(7, 3.2 * len(variables) + 0.6), layout="constrained")
    axs = np.atleast_1d(fig.subplots(len(variables), 1, sharex=True))
    w = ds["Omega"].values
    style = {"up": ("-", "^", "#0072B2"), "down": ("--", "v", "#D55E00")}
    for ax, name in zip(axs, variables):
        for s in ds["sweep"].values:
            line, marker, colour = style[str(s)]
            val = ds[name].sel(sweep=s).values.astype(float)
            ok = ds["status"].sel(sweep=s).values == codes.OK
            ax.plot(w, np.where(ok, val, np.nan), line, color=colour, lw=1.2,
                    marker=marker, ms=4, label=f"sweep {s}")
            if (~ok).any():
                ax.plot(w[~ok], val[~ok], marker, mfc="none", color="0.5", ms=5,
                        label=f"{s}: status not ok")
        if "coexisting" in ds and ds["coexisting"].values.any():
            for i in np.flatnonzero(ds["coexisting"].values):
                lo = w[max(i - 1, 0)] if i else w[i]
                ax.axvspan(0.5 * (lo + w[i]), 0.5 * (w[i] + w[min(i + 1, w.size - 1)]),
                           color="0.85", lw=0, zorder=0)
        if f"branch_{name}" in ds:
            shown = set()
            index = ds["branch_index"].values
            for b in np.unique(index):
                _draw_branch(ax, *_branch_arrays(ds, "branch_", "Omega", name,
                                                 index == b), shown)
        ax.set_ylabel(label(ds[name], name))
        if name in CLASS_VARIABLES[:2]:
            _mark_multiplicity(ax, ds, name)
            ax.set_ylabel(label(ds[name], name).replace(" per period",
                                                        " per response period"))
        ax.grid(alpha=0.3)
    axs[0].legend(fontsize=8, title="shaded: two coexisting responses"
                  if "coexisting" in ds and ds["coexisting"].values.any() else None,
                  title_fontsize=8)
    axs[-1].set_xlabel(_axis_label(ds, "Omega"))
    fig.suptitle(f"{ds.attrs.get('title', '')}\n{fixed_parameters(ds)}", fontsize=9)
    return fig


# the special points of a branch: marker and colour (start, end, regular: none)
SPECIAL_MARKS = {"fold": ("o", "#D55E00"), "branch_point": ("D", "#CC79A7"),
                 "period_doubling": ("s", "#009E73"), "torus": ("*", "#E69F00"),
                 "stick_onset": ("^", "#0072B2"), "grazing": ("v", "#56B4E9"),
                 "stops_change": ("<", "#882255")}


def _draw_branch(ax, x, y, stable, special, ok, meanings: dict, shown: set,
                 colour="0.15") -> None:
    """One branch: stable stretches solid, unstable dashed (a stretch shares its
    last point with the next, so the line is unbroken), failed points left out,
    special points marked once per kind in the legend (``shown``)."""
    n = len(x)
    i = 0
    while i < n:
        if not ok[i]:
            i += 1
            continue
        j = i
        while j + 1 < n and ok[j + 1] and stable[j + 1] == stable[i]:
            j += 1
        end = j + 2 if j + 1 < n and ok[j + 1] else j + 1
        key = "stable" if stable[i] else "unstable"
        ax.plot(x[i:end], y[i:end], "-" if stable[i] else "--", color=colour,
                lw=1.3 if stable[i] else 1.0,
                label=f"{key} branch" if key not in shown else None)
        shown.add(key)
        i = j + 1
    for code, name in meanings.items():
        if name not in SPECIAL_MARKS:
            continue
        sel = (special == code) & ok
        if sel.any():
            marker, c = SPECIAL_MARKS[name]
            ax.plot(x[sel], y[sel], marker, color=c, ms=7, mec="k", mew=0.5,
                    label=name.replace("_", " ") if name not in shown else None,
                    zorder=5)
            shown.add(name)


def _branch_arrays(ds: xr.Dataset, prefix: str, x: str, name: str, sel=None):
    def get(v):
        a = ds[prefix + v].values
        return a if sel is None else a[sel]
    meta = ds[prefix + "special"].attrs
    meanings = dict(zip(np.atleast_1d(meta["flag_values"]).tolist(),
                        str(meta["flag_meanings"]).split()))
    return (get(x).astype(float), get(name).astype(float),
            get("stable").astype(bool), get("special"),
            get("status") == codes.OK, meanings)


@checked_keywords
def plot_branch(ds: xr.Dataset, variables=("amplitude",)) -> Figure:
    """A branch of responses (``sweepcore.follow_response``): each variable against
    the parameter followed, stable stretches solid, unstable dashed, the special
    points marked (folds, period doublings, tori, stick onsets, grazings)."""
    checked_result(ds)
    if ds.attrs.get("sweepcore_kind") != "response_branch":
        raise ValueError("ds must be a branch of responses (sweepcore.follow_response)")
    over = ds.attrs["over"]
    variables = list(variables)
    for name in variables:
        if name not in ds:
            raise ValueError(f"{name!r} is not a variable of the branch")
    fig = Figure(figsize=(7, 3.2 * len(variables) + 0.6), layout="constrained")
    axs = np.atleast_1d(fig.subplots(len(variables), 1, sharex=True))
    for ax, name in zip(axs, variables):
        shown = set()
        _draw_branch(ax, *_branch_arrays(ds, "", over, name), shown)
        ax.set_ylabel(label(ds[name], name))
        ax.grid(alpha=0.3)
    axs[0].legend(fontsize=8)
    axs[-1].set_xlabel(_axis_label(ds, over) if over in SHORT else label(ds[over], over))
    fig.suptitle(f"{ds.attrs.get('title', '')}\n{fixed_parameters(ds)}", fontsize=9)
    return fig


def _mark_multiplicity(ax, ds: xr.Dataset, name: str) -> None:
    """A count per response period means per n forcing periods T: where n > 1 the
    point says so (``6 per 13 T``), once where both sweeps agree."""
    if "multiplicity" not in ds:
        return
    w = ds["Omega"].values
    for i in range(w.size):
        said = set()
        for s in ds["sweep"].values:
            point = ds.sel(sweep=s).isel(Omega=i)
            n, count = float(point["multiplicity"]), int(point[name])
            if int(point["status"]) != codes.OK or not n > 1 or (count, n) in said:
                continue
            said.add((count, n))
            ax.annotate(f"{count} per {n:.0f} T", (w[i], count), xytext=(6, -3),
                        textcoords="offset points", fontsize=8, color="0.25")


@checked_keywords
def plot_stroboscopic(ds: xr.Dataset) -> Figure:
    """A stroboscopic diagram (``sweepcore.stroboscopic_diagram``): x at t = j T
    against the parameter, one dot per sample."""
    checked_result(ds)
    if ds.attrs.get("sweepcore_kind") != "stroboscopic_diagram":
        raise ValueError("ds must be a stroboscopic diagram "
                         "(sweepcore.stroboscopic_diagram)")
    along = ds.attrs["along"]
    fig = Figure(figsize=(7, 4), layout="constrained")
    ax = fig.subplots()
    u = np.repeat(ds[along].values[:, None], ds.sizes["sample"], axis=1)
    ax.plot(u.ravel(), ds["x"].values.ravel(), ".", ms=2, color="#0072B2")
    ax.set_xlabel(label(ds[along], along))
    ax.set_ylabel("x(j T) [cm]")
    ax.grid(alpha=0.3)
    fig.suptitle(f"{ds.attrs.get('title', '')}\n{fixed_parameters(ds)}", fontsize=9)
    return fig
