"""The cost of a forced response map against the Hopf map, per point, in one run,
beside the independent scipy reference on a sample of the same points.

    python benchmarks/forced.py [--side 64] [--repeats 3] [--sample 6]

Two forced maps (m = k = 1, r_y = 1, c = 0.05; Omega/omega in [0.3, 3] and F0/r_y in
[0.2, 4]; started at rest at x = 0): on fixed ground (v = 0, Den Hartog's case) and
on a belt (v = 0.5 cm/s). The Hopf map is the paper's (m = 5, k = 50, r_y = 10,
alpha1 = 1, v in [0.5, 10], alpha2 in [1e-3, 0.1], started stuck on the belt) on the
same side. Each runs through the kernels a sweep runs (``sweepcore.forced.responses``
and ``sweepcore.execute.attractors``: no xarray), on one thread, interleaved, warm;
CPU seconds per point, medians over the repeats; the ratio is forced / Hopf. The
reference (``tests/reference_forced.py``: scipy DOP853 with exact sticks, a Python
loop over points) runs on ``--sample`` points of each forced map, and its answers are
compared with sweepcore's (amplitude, mean, counts). Saves
``benchmarks/results/forced.json``.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks import common  # noqa: E402


def grids(side):
    import sweepcore as sc
    om = np.linspace(0.3, 3.0, side)
    f0 = np.linspace(0.2, 4.0, side)
    forced = {f"v={v:g}": sc.Grid(m=1.0, k=1.0, r_y=1.0, v=v, c=0.05, Omega=om, F0=f0,
                                  x0=0.0, xdot0=0.0) for v in (0.0, 0.5)}
    hopf = sc.Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, v=np.linspace(0.5, 10.0, side),
                   alpha2=np.geomspace(1e-3, 0.1, side))
    return forced, hopf


def run(grid, o):
    """The kernels of a sweep on every row of ``grid``: (CPU seconds, rows out)."""
    from sweepcore import execute, forced
    from sweepcore._kernels import layout
    P = grid.rows(0, grid.size)
    t = time.process_time()
    if grid.forced:
        out = np.empty((grid.size, layout.NFOB))
        forced.responses(P, grid.laws, grid.loads, o, out, False)
    else:
        out = np.empty((grid.size, layout.NOBS))
        execute.attractors(P, grid.laws, o, out, False)
    return time.process_time() - t, out


def reference_sample(grid, out, count, seed=1):
    """The scipy reference at ``count`` random points of a forced grid: its seconds
    a point and the largest differences from sweepcore's answers."""
    sys.path.insert(0, str(common.ROOT / "tests"))
    from reference_forced import Forced, forced_steady
    from sweepcore._kernels import layout
    rng = np.random.default_rng(seed)
    P = grid.rows(0, grid.size)
    rows = rng.choice(grid.size, count, replace=False)
    worst = {"amplitude_L": 0.0, "mean_L": 0.0, "counts_differ": 0, "skipped": 0}
    seconds = []
    for i in rows:
        p = P[i]
        mod = Forced(m=p[layout.M], k=p[layout.K], c=p[layout.C], v=p[layout.V],
                     F0=p[layout.F0], Omega=p[layout.OMEGA], r_y=float(grid.r_y))
        t = time.process_time()
        ref = forced_steady(mod, x0=0.0, xd0=0.0, multipliers=False)
        seconds.append(time.process_time() - t)
        mine = out[i]
        if ref["status"] != "ok" or mine[layout.OB_STATUS] != 0:
            worst["skipped"] += 1
            continue
        worst["amplitude_L"] = max(worst["amplitude_L"],
                                   abs(mine[layout.OB_AMPLITUDE] - ref["amplitude"]) / mod.L)
        worst["mean_L"] = max(worst["mean_L"], abs(mine[layout.OB_MEAN] - ref["mean"]) / mod.L)
        worst["counts_differ"] += int(
            (mine[layout.OB_MULTIPLICITY], mine[layout.OB_STICKS_PER_PERIOD],
             mine[layout.OB_STOPS_PER_PERIOD]) != (ref["multiplicity"],
                                                   ref["sticks_per_period"],
                                                   ref["stops_per_period"]))
    return float(np.median(seconds)), worst


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--side", type=int, default=64, help="points per axis (default 64)")
    ap.add_argument("--repeats", type=int, default=3, help="interleaved repeats")
    ap.add_argument("--sample", type=int, default=6,
                    help="reference points per forced map (default 6)")
    ap.add_argument("--json", default=str(common.RESULTS / "forced.json"))
    args = ap.parse_args(argv)
    import numba
    from sweepcore._kernels import codes, layout
    from sweepcore.options import make_options
    numba.set_num_threads(1)
    forced, hopf = grids(args.side)
    o = make_options("auto", tol=1e-8)
    everything = {**forced, "hopf": hopf}
    for grid in everything.values():        # compile (or load) and warm
        run(grid, o)
    cpu = {name: [] for name in everything}
    outs = {}
    for _ in range(args.repeats):
        for name, grid in everything.items():
            seconds, outs[name] = run(grid, o)
            cpu[name].append(seconds / grid.size)
    result = {"machine": common.machine(), "side": args.side, "repeats": args.repeats,
              "tol": 1e-8, "threads": 1, "maps": {}}
    hopf_pt = float(np.median(cpu["hopf"]))
    for name, grid in everything.items():
        out = outs[name]
        per = float(np.median(cpu[name]))
        entry = {"cpu_us_per_point": per * 1e6,
                 "ratio_to_hopf": per / hopf_pt,
                 "stepper_calls_mean": float(out[:, layout.OB_NSTEPS].mean()),
                 "stepper_calls_median": float(np.median(out[:, layout.OB_NSTEPS])),
                 "regimes": {codes.REGIME_NAMES[int(k)]: int(c) for k, c in
                             zip(*np.unique(out[:, layout.OB_REGIME], return_counts=True))},
                 "statuses": {codes.STATUS_NAMES[int(k)]: int(c) for k, c in
                              zip(*np.unique(out[:, layout.OB_STATUS], return_counts=True))}}
        if grid.forced:
            entry["stops_per_period"] = {int(k): int(c) for k, c in zip(*np.unique(
                out[:, layout.OB_STOPS_PER_PERIOD][np.isfinite(
                    out[:, layout.OB_STOPS_PER_PERIOD])], return_counts=True))}
            ref_s, worst = reference_sample(grid, out, args.sample)
            entry["reference"] = {"cpu_s_per_point": ref_s,
                                  "sweepcore_speedup": ref_s / per, **worst}
        result["maps"][name] = entry
        common.log(f"{name}: {per * 1e6:.1f} us/point CPU, x{per / hopf_pt:.2f} the Hopf "
                   f"map, {entry['stepper_calls_mean']:.0f} stepper calls a point"
                   + (f"; reference {entry['reference']['cpu_s_per_point']:.2f} s/point "
                      f"(x{entry['reference']['sweepcore_speedup']:.0f}), worst amplitude "
                      f"{entry['reference']['amplitude_L']:.1e} L" if grid.forced else ""))
    common.save_json(result, args.json)
    common.log(f"saved {args.json}")


if __name__ == "__main__":
    main()
