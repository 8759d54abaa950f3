"""Design maps: amplitude and mean over (k, m) and (v, r_y), for both friction laws.

The paper's design advice (conclusions), drawn from the constant-friction cycle of
eq. (39), amplitude v/omega = v sqrt(m/k) and mean r_y/k:

* to reduce the amplitude, decrease v, increase k or decrease m;
* r_y moves the mean, not the amplitude; a stiffer spring lowers the mean.

Each plane is swept for constant friction (alpha1 = alpha2 = 0) and for the
speed-dependent law (40) with alpha1 = 1, alpha2 = 0.01, every point started stuck.
The closed forms v/omega and r_y/k are drawn as contours over the measured maps.

    python studies/design_map.py [--out out/]
        -> design_km.nc, design_km.png, design_ryv.nc, design_ryv.png
"""
import numpy as np
import xarray as xr
from matplotlib.colors import LogNorm
from matplotlib.figure import Figure

from sweepcore.grid import Grid
from sweepcore.io import write_netcdf
from sweepcore.plot import fixed_parameters, map_panel, save
from sweepcore.sweep import sweep

from _common import Timer, output_dir

N = 64
LAWS = {"constant": dict(alpha1=0.0, alpha2=0.0),
        "speed-dependent": dict(alpha1=1.0, alpha2=0.01)}
TITLES = {"constant": "constant friction ($\\alpha_1 = \\alpha_2$ = 0)",
          "speed-dependent": "speed-dependent friction (40), $\\alpha_1$ = 1, "
                             "$\\alpha_2$ = 0.01"}
PLANES = {   # name -> (axes, x, y)
    "km": (dict(m=np.geomspace(0.5, 50.0, N), k=np.geomspace(5.0, 500.0, N),
                r_y=10.0, v=5.0), "k", "m"),
    "ryv": (dict(m=5.0, k=50.0, r_y=np.linspace(0.5, 20.0, N),
                 v=np.linspace(0.5, 10.0, N)), "v", "r_y"),
}


def run_plane(name, out):
    axes, x, y = PLANES[name]
    results = {}
    for law, alphas in LAWS.items():
        ds = sweep(Grid(**axes, **alphas), method="auto", tol=1e-8)
        if name == "km":
            for d in ("m", "k"):
                ds[d].attrs["spacing"] = "geometric"
        results[law] = ds
    combined = xr.concat(list(results.values()), dim=xr.IndexVariable(
        "friction_law", list(results), {"long_name": "friction law", "units": "1"}),
        coords="different", compat="equals", combine_attrs="override",
        data_vars="all")
    combined.attrs["title"] = f"Design map over ({x}, {y})"
    write_netcdf(_netcdf_ready(combined), out / f"design_{name}.nc")
    save(figure(results, x, y), out / f"design_{name}.png")
    return results


def _netcdf_ready(ds):
    # string coordinate for netCDF4; v_star = inf (alpha2 = 0) stays as is
    ds = ds.assign_coords(friction_law=ds.friction_law.astype(str))
    return ds


def figure(results, x, y):
    fig = Figure(figsize=(21, 9.8), layout="constrained")
    axs = fig.subplots(2, 4)
    for row, (law, ds) in zip(axs, results.items()):
        map_panel(fig, row[0], ds, "regime", x, y)
        _amplitude(fig, row[1], ds, x, y)
        _ratio(fig, row[2], ds, x, y)
        _mean(fig, row[3], ds, x, y)
        row[0].set_title("")
        row[0].set_title(f"{TITLES[law]}: regime", fontsize=10, loc="left")
    fig.suptitle(f"Design maps over ({x}, {y}): "
                 f"{fixed_parameters(ds.drop_vars(['alpha1', 'alpha2']))}; "
                 "dashed contours: the paper's closed forms (eq. 39)", fontsize=12)
    return fig


def _closed(ds, x, y, expr):
    d = ds.sortby([x, y])
    X, Y = np.meshgrid(d[x].values, d[y].values)
    p = {n: (X if n == x else Y if n == y else float(d[n])) for n in ("m", "k", "r_y", "v")}
    return X, Y, np.broadcast_to(expr(**p), X.shape).astype(float)


def _amplitude(fig, ax, ds, x, y):
    amp = ds["amplitude"].values
    norm = LogNorm(*np.nanpercentile(amp[amp > 0], [0, 100])) \
        if ds[x].attrs.get("spacing") == "geometric" and (amp > 0).all() else None
    map_panel(fig, ax, ds, "amplitude", x, y, norm=norm)
    X, Y, ref = _closed(ds, x, y, lambda m, k, r_y, v: v * np.sqrt(m / k))
    levels = _levels(ref, log=norm is not None)
    cs = ax.contour(X, Y, ref, levels=levels, colors="white", linewidths=1.0,
                    linestyles="--")
    ax.clabel(cs, fontsize=7.5, fmt="%.3g")
    ax.set_title(r"amplitude; contours: $v/\omega = v\sqrt{m/k}$", fontsize=10)


def _ratio(fig, ax, ds, x, y):
    d = ds.copy()
    d["ratio"] = d["amplitude"] * d["omega"] / np.abs(d["v"])
    d["ratio"].attrs = {"units": "1", "long_name": "amplitude / (v/omega)"}
    mesh = map_panel(fig, ax, d, "ratio", x, y, cmap="RdBu_r", vmin=0.0, vmax=2.0,
                     colorbar=False)
    fig.colorbar(mesh, ax=ax, shrink=0.9, pad=0.01, extend="max",
                 label=r"amplitude / $(v/\omega)$ (red beyond 2)")
    ax.set_title(r"amplitude / $(v/\omega)$: 1 where the paper's formula holds",
                 fontsize=10)


def _mean(fig, ax, ds, x, y):
    map_panel(fig, ax, ds, "mean", x, y, cmap="cividis")
    X, Y, ref = _closed(ds, x, y, lambda m, k, r_y, v: r_y / k)
    cs = ax.contour(X, Y, ref, levels=_levels(ref, log=False), colors="white",
                    linewidths=1.0, linestyles="--")
    ax.clabel(cs, fontsize=7.5, fmt="%.3g")
    ax.set_title(r"mean position; contours: $r_y/k$", fontsize=10)


def _levels(ref, log):
    lo, hi = np.nanmin(ref), np.nanmax(ref)
    if log:
        return np.geomspace(lo, hi, 7)[1:-1]
    return np.linspace(lo, hi, 7)[1:-1]


def report(name, results):
    axes, x, y = PLANES[name]
    for law, ds in results.items():
        d = ds.sortby([x, y]).transpose(y, x)
        _, _, amp_ref = _closed(ds, x, y, lambda m, k, r_y, v: v * np.sqrt(m / k))
        _, _, mean_ref = _closed(ds, x, y, lambda m, k, r_y, v: r_y / k)
        amp, mean = d.amplitude.values, d["mean"].values
        cyc = amp > 0
        regimes = ", ".join(f"{n} {c}" for n, c in _counts(d.regime))
        print(f"  {name}, {law} friction: {regimes}")
        print(f"    amplitude / (v/omega) on cycles: {np.min(amp[cyc] / amp_ref[cyc]):.4g}"
              f" .. {np.max(amp[cyc] / amp_ref[cyc]):.4g}; |mean - r_y/k| <= "
              f"{np.nanmax(np.abs(mean - mean_ref)):.3g} cm")
        if "r_y" in (x, y):
            a = d.amplitude.values
            along = np.nanmax(a, axis=0 if y == "r_y" else 1) - \
                np.nanmin(a, axis=0 if y == "r_y" else 1)
            print(f"    amplitude range along r_y at fixed v: up to {np.max(along):.3g} cm"
                  f" (median {np.median(along):.3g} cm)")
        # the advice, as monotonicity along each axis of the map
        for axis, want in ((x, _advice(x)), (y, _advice(y))):
            if want is None:
                continue
            step = np.diff(d.amplitude.values, axis=1 if axis == x else 0)
            frac = np.mean(np.sign(step) == want) if step.size else np.nan
            print(f"    amplitude {'rises' if want > 0 else 'falls'} with {axis} "
                  f"between {100 * frac:.1f} % of neighbouring points")


def _advice(axis):
    return {"v": +1, "k": -1, "m": +1}.get(axis)


def _counts(regime):
    values = np.atleast_1d(regime.attrs["flag_values"])
    names = regime.attrs["flag_meanings"].split()
    return [(n, int((regime.values == v).sum())) for v, n in zip(values, names)
            if (regime.values == v).any()]


def main(out):
    written = []
    for name in PLANES:
        with Timer(f"design_map ({name})"):
            results = run_plane(name, out)
        report(name, results)
        written += [out / f"design_{name}.nc", out / f"design_{name}.png"]
    return written


if __name__ == "__main__":
    main(output_dir(__doc__))
