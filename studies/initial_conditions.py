"""Initial conditions: the same slider from many starts (x0, xdot0).

Does the amplitude depend on the start? The paper says no ("independent to the
initial conditions"). Measured here:

* constant friction (alpha1 = alpha2 = 0), v = 5: it does. A start whose circle about
  (r_y/k, 0) in the (x, xdot/omega) plane has radius R0 <= v/omega never reaches the
  belt speed and keeps R0; any larger start sticks once and ends on the grazing
  cycle of radius v/omega. Closed form: amplitude = min(R0, v/omega).
* speed-dependent friction (40), alpha1 = 1, alpha2 = 0.01: it does not, below v*
  (v = 5: stick-slip; v = 5.5: a slip cycle that never sticks).
* near v*, from three starts: the amplitude vanishes like sqrt(v* - v), the same from
  every start, following the averaging estimate A = 2 sqrt(v*^2 - v^2)/omega: the
  bifurcation measured is supercritical, not subcritical as the paper states.

    python studies/initial_conditions.py [--out out/]
        -> initial_conditions.nc, initial_conditions_vstar.nc, initial_conditions.png
"""
import math

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

import sweepcore as sc
from sweepcore.grid import Grid
from sweepcore.io import write_netcdf
from sweepcore.plot import REGIME_COLOURS, label, map_panel, save
from sweepcore.sweep import sweep

from _common import Timer, output_dir

SLIDER = dict(m=5.0, k=50.0, r_y=10.0)         # kN s^2/cm, kN/cm, kN
CENTRE = SLIDER["r_y"] / SLIDER["k"]           # cm, the sliding circle's centre
N = 81
X0 = np.linspace(CENTRE - 3.2, CENTRE + 3.2, N)      # cm
XDOT0 = np.linspace(-10.0, 10.0, N)                  # cm/s
CASES = {   # name -> (title, friction and speed)
    "constant": ("constant friction, $v$ = 5", dict(alpha1=0.0, alpha2=0.0, v=5.0)),
    "stick_slip": ("friction (40), $v$ = 5 < $v^*$", dict(alpha1=1.0, alpha2=0.01, v=5.0)),
    "slip_cycle": ("friction (40), $v$ = 5.5 < $v^*$",
                   dict(alpha1=1.0, alpha2=0.01, v=5.5)),
}
STARTS = {   # near v*: name -> (x0 [cm], xdot0 [cm/s] or None = stuck)
    "stuck on the belt": (0.0, None),
    "near the equilibrium": (0.13, 0.0),
    "far outside": (-3.0, 0.0),
}


def closed_form(x0, xdot0, v, omega):
    """Constant friction: amplitude min(R0, v/omega) [cm], R0 about (r_y/k, 0)."""
    r0 = np.hypot(x0 - CENTRE, xdot0 / omega)
    return np.minimum(r0, abs(v) / omega)


def run_maps():
    maps = {}
    for name, (_, case) in CASES.items():
        maps[name] = sweep(Grid(**SLIDER, **case, x0=X0, xdot0=XDOT0), tol=1e-8)
    return maps


def run_vstar():
    p = sc.Params(**SLIDER, v=5.0, alpha1=1.0, alpha2=0.01)
    v = np.unique(np.concatenate([p.v_star - np.geomspace(1e-3, 2.0, 40),
                                  p.v_star + np.array([1e-3, 0.01, 0.1])]))
    lines = {}
    for name, (x0, xdot0) in STARTS.items():
        lines[name] = sweep(Grid(**SLIDER, alpha1=1.0, alpha2=0.01, v=v, x0=x0,
                                 xdot0=xdot0), tol=1e-8)
    return p, v, lines


def averaging_amplitude(v, v_star, omega):
    """First-order averaging about x_eq: A = 2 sqrt(v*^2 - v^2)/omega [cm], v < v*."""
    return 2.0 * np.sqrt(np.clip(v_star ** 2 - v ** 2, 0.0, None)) / omega


def figure(maps, p, v, lines):
    fig = Figure(figsize=(17, 10.5), layout="constrained")
    top, bottom = fig.subfigures(2, 1, height_ratios=[1.0, 0.95])
    axs = top.subplots(1, 3, sharey=True)
    vmax = max(float(np.nanmax(ds.amplitude)) for ds in maps.values())
    omega = p.omega
    for ax, (name, ds) in zip(axs, maps.items()):
        mesh = map_panel(top, ax, ds, "amplitude", "x0", "xdot0", vmin=0.0, vmax=vmax,
                         colorbar=False)
        case = CASES[name][1]
        ax.set_title(f"{CASES[name][0]}: amplitude from each start", fontsize=10)
        R = case["v"] / omega
        th = np.linspace(0, 2 * math.pi, 300)
        ax.plot(CENTRE + R * np.cos(th), omega * R * np.sin(th), "w--", lw=1.4,
                label=r"$R_0 = v/\omega$ about $(r_y/k, 0)$")
        ax.axhline(case["v"], color="white", lw=0.8, ls=":", label="belt speed $v$")
        ax.legend(fontsize=8, loc="lower left", facecolor="0.25", labelcolor="white",
                  framealpha=0.85)
        if ax is not axs[0]:
            ax.set_ylabel("")
    top.colorbar(mesh, ax=axs, shrink=0.9, pad=0.01, label=label(maps["constant"].amplitude,
                                                               "amplitude"))
    ax_v, ax_c = bottom.subplots(1, 2)
    _vstar_panel(ax_v, p, v, lines)
    _closed_form_panel(ax_c, maps["constant"], omega)
    fig.suptitle("Initial conditions: $m$ = 5 kN s$^2$/cm, $k$ = 50 kN/cm, $r_y$ = 10 kN;"
                 " friction (40) with $\\alpha_1$ = 1 kN s/cm, $\\alpha_2$ = 0.01 "
                 "kN s$^3$/cm$^3$ ($v^*$ = 5.77 cm/s)", fontsize=12)
    return fig


def _vstar_panel(ax, p, v, lines):
    dv = p.v_star - v
    below = dv > 0
    grid = np.geomspace(dv[below].min(), dv[below].max(), 200)
    ax.plot(grid, averaging_amplitude(p.v_star - grid, p.v_star, p.omega), "k-", lw=1,
            label=r"averaging: $A = 2\sqrt{v^{*2} - v^2}/\omega$")
    markers = iter("osD")
    for name, ds in lines.items():
        reg = ds.regime.values
        amp = ds.amplitude.values
        mk = next(markers)
        ok = ds.converged.values.astype(bool) & below
        ax.scatter(dv[ok], amp[ok], marker=mk, s=26, facecolors="none",
                   edgecolors=[REGIME_COLOURS[int(r)] for r in reg[ok]],
                   label=f"start {name}")
        bad = ~ds.converged.values.astype(bool) & below
        if bad.any():
            ax.scatter(dv[bad], amp[bad], marker="x", s=22, color="0.5",
                       label=f"start {name}: unconverged (growth time 2/q too long)")
    ax.set(xscale="log", yscale="log", xlabel=r"distance below the Hopf speed "
           r"$v^* - v$ [cm/s]", ylabel="vibration amplitude $A$ [cm]",
           title="near $v^*$: amplitude from three starts (marker edge: regime; "
                 "orange slip cycle, red stick-slip)")
    ax.text(0.98, 0.04, "above $v^*$ every start ends at the equilibrium (amplitude 0)",
            transform=ax.transAxes, ha="right", fontsize=8.5)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8, loc="upper left")


def _closed_form_panel(ax, ds, omega):
    X, Y = np.meshgrid(ds.x0.values, ds.xdot0.values, indexing="ij")
    amp = ds.amplitude.transpose("x0", "xdot0").values
    r0 = np.hypot(X - CENTRE, Y / omega)
    ax.scatter(r0.ravel(), amp.ravel(), s=3, color="#0072B2", alpha=0.5,
               label="measured, every start of the constant-friction map")
    r = np.linspace(0, r0.max(), 200)
    ax.plot(r, np.minimum(r, 5.0 / omega), "k--", lw=1,
            label=r"closed form $\min(R_0, v/\omega)$")
    ax.set(xlabel=r"radius of the start $R_0$ about $(r_y/k, 0)$ in the "
                  r"$(x, \dot x/\omega)$ plane [cm]",
           ylabel="vibration amplitude $A$ [cm]",
           title="constant friction: the amplitude depends on the start")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8.5, loc="lower right")


def to_dataset(maps):
    case = xr.IndexVariable("case", list(maps), {"long_name": "case", "units": "1"})
    ds = xr.concat(list(maps.values()), dim=case, coords="different",
                   compat="equals", combine_attrs="override", data_vars="all")
    ds.attrs["title"] = "Amplitude from many starts (x0, xdot0)"
    ds.attrs["cases"] = "; ".join(f"{n}: {c[1]}" for n, c in CASES.items())
    return ds.assign_coords(case=ds.case.astype(str))


def main(out):
    with Timer("initial_conditions"):
        maps = run_maps()
        p, v, lines = run_vstar()
        write_netcdf(to_dataset(maps), out / "initial_conditions.nc")
        start = xr.IndexVariable("start", list(lines), {"long_name": "start",
                                                        "units": "1"})
        near = xr.concat([ds.drop_vars(["x0", "xdot0"], errors="ignore")
                          for ds in lines.values()], dim=start, coords="different",
                         compat="equals", combine_attrs="override", data_vars="all")
        write_netcdf(near.assign_coords(start=near.start.astype(str)),
                     out / "initial_conditions_vstar.nc")
        save(figure(maps, p, v, lines), out / "initial_conditions.png")
    report(maps, p, v, lines)
    return [out / "initial_conditions.nc", out / "initial_conditions_vstar.nc",
            out / "initial_conditions.png"]


def report(maps, p, v, lines):
    ds = maps["constant"]
    X, Y = np.meshgrid(ds.x0.values, ds.xdot0.values, indexing="ij")
    ref = closed_form(X, Y, 5.0, p.omega)
    err = np.abs(ds.amplitude.transpose("x0", "xdot0").values - ref)
    print(f"  constant friction: |A - min(R0, v/omega)| <= {err.max():.3g} cm over "
          f"{err.size} starts; amplitude spans {np.nanmin(ds.amplitude):.3g} .. "
          f"{np.nanmax(ds.amplitude):.4g} cm")
    for name in ("stick_slip", "slip_cycle"):
        a = maps[name].amplitude.values
        regimes = np.unique(maps[name].regime.values)
        print(f"  {name}: amplitude {np.nanmin(a):.6g} .. {np.nanmax(a):.6g} cm from "
              f"{a.size} starts (regime codes {regimes.tolist()})")
    dv = p.v_star - v
    sel = (dv > 0) & (dv < 0.05)
    for name, d in lines.items():
        ok = d.converged.values.astype(bool) & sel
        if ok.any():
            c = d.amplitude.values[ok] / np.sqrt(dv[ok])
            print(f"  near v*, start {name}: A/sqrt(v* - v) = {c.min():.4g} .. "
                  f"{c.max():.4g} (averaging: sqrt(8 v*)/omega = "
                  f"{math.sqrt(8 * p.v_star) / p.omega:.4g}); above v*: "
                  f"{sorted(set(d.regime.values[dv < 0].tolist()))}")


if __name__ == "__main__":
    main(output_dir(__doc__))
