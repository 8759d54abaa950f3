"""Frequency-response curves and a stroboscopic diagram of the forced slider, and a
coarse preview of studies/forced_map.toml.

    python studies/forced_response.py [--out out/] [--map N] [--only PART]
    python studies/forced_response.py --check out/forced_map.nc

Writes ``forced_response.{nc,png}``: amplitude, mean and sticks per cycle against
the excitation frequency, swept up and down (each point started from its
neighbour's response), for a damped slider on a belt with a Stribeck law; ``forced_strobe.{nc,png}``: x at t = j T against
Omega for the same slider under a stronger load (locked and beating responses);
with ``--map N``, ``forced_map_N.{nc,png}``: the map of studies/forced_map.toml on
an N x N grid of the same ranges. Prints the wall time of each. ``--check`` compares
a forced_map result with Den Hartog's continuous-motion boundary.
"""
from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent

# a damped slider on a belt (v = 1) with a steep Stribeck drop (static 1, kinetic
# 0.5, v_s = 0.1) under a load F0 = 0.15: the response slides without sticking
# away from resonance and sticks where the linear response's velocity amplitude
# would exceed the belt speed (once a forcing period, or a few times in a response
# of several periods); started sliding slower than the belt
RESPONSE = dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.1, c=0.1, v=1.0, F0=0.15,
                Omega=1.0)
RESPONSE_START = dict(x0=0.5, xdot0=0.9)
RESPONSE_OMEGA = np.linspace(0.7, 1.3, 31)
# the bSTAB friction case (studies/bstab_hysteresis.toml) at a belt speed between
# its subcritical Hopf point and its fold, where stick-slip and steady sliding
# coexist without a load
BSTAB = dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.5, c=0.1, v=1.4, Omega=1.0)
# the same slider under a stronger load, started stuck on the belt: the load locks
# the stick-slip cycle near omega (one dot a value), elsewhere the two frequencies
# beat (a cloud: an aperiodic response)
STROBE = {**BSTAB, "F0": 0.3}
STROBE_OMEGA = np.linspace(0.5, 1.5, 41)


def response_curve(out: Path) -> None:
    import sweepcore as sc
    from sweepcore.plot import plot_frequency_response, save
    ds = sc.frequency_response(sc.Params(**RESPONSE), RESPONSE_OMEGA, **RESPONSE_START)
    sc.write_netcdf(ds, out / "forced_response.nc")
    save(plot_frequency_response(ds, ("amplitude", "mean", "sticks_per_period")),
         out / "forced_response.png")
    band = ds.Omega.values[ds.coexisting.values.astype(bool)]
    both = (ds.status == 0).all("sweep")
    gap = float(abs(ds.amplitude.sel(sweep="up") - ds.amplitude.sel(sweep="down"))
                .where(both).max() / ds.amplitude.max())
    names = dict(zip(np.atleast_1d(ds.status.attrs["flag_values"]).tolist(),
                     ds.status.attrs["flag_meanings"].split()))
    bad = [f"{s} at Omega = {w:g} rad/s ({names[int(c)]})"
           for s in ds.sweep.values for w, c in zip(ds.Omega.values,
                                                    ds.status.sel(sweep=s).values)
           if c != 0]
    print(f"forced_response: not ok: {'; '.join(bad) or 'none'}; sticks: "
          f"{', '.join(stick_bands(ds)) or 'none'}; largest |A_up - A_down| / max A "
          f"where both are ok = {gap:.2g}; coexisting responses: "
          + (f"at Omega = {', '.join(f'{w:g}' for w in band)} rad/s" if band.size
             else "none"))


def stick_bands(ds) -> list[str]:
    """The finite sticks per response period of n forcing periods T, over runs of
    neighbouring frequencies: ``1 per T at Omega in [0.92, 1.06] rad/s``, ``6 per
    13 T at Omega = 1.08 rad/s``; from the ok points of both sweeps (where the
    two disagree: "the sweeps differ")."""
    w = ds.Omega.values
    kinds = []
    for i in range(w.size):
        point = ds.isel(Omega=i)
        seen = {(int(point.sticks_per_period[j]), int(point.multiplicity[j]))
                for j in range(point.sizes["sweep"]) if point.status[j] == 0}
        kinds.append(seen.pop() if len(seen) == 1 else "the sweeps differ" if seen
                     else None)
    out, start = [], 0
    for i in range(1, w.size + 1):
        if i < w.size and kinds[i] == kinds[start]:
            continue
        kind, span = kinds[start], w[start:i]
        where = (f"Omega = {span[0]:g}" if span.size == 1 else
                 f"Omega in [{span[0]:g}, {span[-1]:g}]") + " rad/s"
        if isinstance(kind, str):
            out.append(f"{kind} at {where}")
        elif kind is not None and kind[0] > 0:
            sticks, n = kind
            out.append(f"{sticks} per {'' if n == 1 else f'{n} '}T at {where}")
        start = i
    return out


def strobe(out: Path) -> None:
    import sweepcore as sc
    from sweepcore.plot import plot_stroboscopic, save
    ds = sc.stroboscopic_diagram(sc.Params(**STROBE), "Omega", STROBE_OMEGA, periods=32,
                                 transient=300)
    sc.write_netcdf(ds, out / "forced_strobe.nc")
    save(plot_stroboscopic(ds), out / "forced_strobe.png")


def preview_map(out: Path, n: int) -> None:
    """studies/forced_map.toml on an n x n grid of the same ranges."""
    import sweepcore as sc
    from sweepcore.cli.commands import label_with_study
    from sweepcore.plot import plot_result, save
    from sweepcore.study import load_study
    study = load_study(HERE / "forced_map.toml")
    kw = study.grid_kwargs()
    kw["F0"] = np.linspace(kw["F0"][0], kw["F0"][-1], n)
    kw["Omega"] = np.geomspace(kw["Omega"][0], kw["Omega"][-1], n)
    ds = sc.sweep(sc.Grid(**kw), progress=False, **study.options)
    ds = label_with_study(ds, dataclasses.replace(study, title=study.title
                                                  + f" ({n} x {n} preview)"),
                          f"python studies/forced_response.py --map {n}")
    sc.write_netcdf(ds, out / f"forced_map_{n}.nc")
    save(plot_result(ds, **study.plot), out / f"forced_map_{n}.png")


def boundary_check(path: Path) -> None:
    """How the map's measured edge between no stick and sticking agrees with Den
    Hartog's continuous-motion boundary F0 = r_y / r_b(Omega/omega): in every column
    where the boundary is inside the map, the ok cells above it with a stick and
    those between r_y and it without one, and the largest distance of such a cell
    from the boundary in grid cells."""
    import sweepcore as sc
    from sweepcore.excitations import theory
    ds = sc.open_result(path)
    F0, r = ds.F0.values, float(ds.r_y)
    step = float(np.min(np.diff(F0)))
    omega = float(ds.omega)
    worst, columns, wrong = 0.0, 0, 0
    for j, w in enumerate(ds.Omega.values):
        fb = r / float(theory.continuous_motion_boundary(w / omega))
        if not F0[0] < fb < F0[-1]:
            continue
        columns += 1
        sticks = ds.sticks_per_period.isel(Omega=j).values
        ok = (ds.status.isel(Omega=j).values == 0) & (F0 > r)
        bad = F0[ok & (((F0 > fb) & (sticks != 0)) | ((F0 < fb) & (sticks == 0)))]
        wrong += bad.size
        if bad.size:
            worst = max(worst, float(np.max(np.abs(bad - fb))) / step)
    print(f"boundary check of {path}: {columns} columns cross r_b; {wrong} ok cells on "
          f"the wrong side of it (farthest {worst:.3g} cells)")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("out"),
                        help="output directory (default out/)")
    parser.add_argument("--map", type=int, metavar="N", default=None,
                        help="also the N x N preview of studies/forced_map.toml")
    parser.add_argument("--only", choices=("response", "strobe", "map"), default=None,
                        help="one part only")
    parser.add_argument("--check", type=Path, metavar="MAP.nc", default=None,
                        help="only compare a forced_map result with Den Hartog's "
                             "continuous-motion boundary")
    args = parser.parse_args(argv)
    if args.check:
        boundary_check(args.check)
        return 0
    args.out.mkdir(parents=True, exist_ok=True)
    parts = {"response": lambda: response_curve(args.out),
             "strobe": lambda: strobe(args.out)}
    if args.map:
        parts["map"] = lambda: preview_map(args.out, args.map)
    for name, run in parts.items():
        if args.only and name != args.only:
            continue
        t0 = time.perf_counter()
        run()
        print(f"{name}: {time.perf_counter() - t0:.1f} s", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
