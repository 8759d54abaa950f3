"""Section 3: points per second against grid size (linear cost).

Square grids over the Hopf map's box (v in [0.5, 10], alpha2 in [1e-3, 0.1]
geometric), from ~1e2 to ~1e6 points, each timed warm with the bare kernel on 2
numba threads and through ``sweepcore.sweep`` (direct path), median of repeats.
Finer grids sample the same box, so the mix of regimes (and the cost per point)
stays about the same: constant points/s means linear cost.
"""
from __future__ import annotations

import numpy as np

from . import common
from .common import log
from sweepcore._kernels.layout import NOBS


def run(profile, outdir):
    run = common.kernel()
    attractor_rows_parallel = lambda P, o, out: run(P, o, out, True)  # noqa: E731
    from sweepcore.options import make_options
    sweep, Grid = common.sweep_api()
    o = make_options("auto", tol=1e-8)
    log("[3] throughput against grid size")
    res = {"load_before": common.load(), "runs": []}
    for side in profile["tp_sides"]:
        v, a2 = common.map_axes(side, side)
        P = common.rows(v, a2)
        n = P.shape[0]
        reps = profile["tp_repeats_small"] if n <= 1e5 else profile["tp_repeats_large"]
        out = np.empty((n, NOBS))
        attractor_rows_parallel(P[:4], o, out[:4])
        med, times, _ = common.timed(lambda: attractor_rows_parallel(P, o, out), repeat=reps)
        row = {"side": side, "n_points": n, "kernel_median_s": med, "kernel_times_s": times,
               "kernel_points_per_s": n / med, "steps_per_point": float(out[:, 10].mean()),
               "converged_fraction": float((out[:, 9] == 0).mean())}
        msg = f"    {n:>9,d} points: kernel {med:8.3f} s ({n / med:>10,.0f} pts/s)"
        if sweep is not None:
            grid = common.map_grid(Grid, v, a2)
            smed, stimes, _ = common.timed(lambda: sweep(grid, progress=False), repeat=reps)
            row.update({"sweep_median_s": smed, "sweep_times_s": stimes,
                        "sweep_points_per_s": n / smed})
            msg += f" | sweep() {smed:8.3f} s ({n / smed:>10,.0f} pts/s)"
        res["runs"].append(row)
        log(msg)
    res["load_after"] = common.load()
    plot(res, outdir)
    return res


def plot(res, outdir):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    runs = res["runs"]
    n = np.array([r["n_points"] for r in runs], float)
    fig, axs = plt.subplots(1, 2, figsize=(12, 4.5), constrained_layout=True)
    axs[0].loglog(n, [r["kernel_median_s"] for r in runs], "o-", label="kernel (2 threads)")
    if "sweep_median_s" in runs[0]:
        axs[0].loglog(n, [r["sweep_median_s"] for r in runs], "s-", label="sweep() direct")
    ref = runs[-1]["kernel_median_s"] * n / n[-1]
    axs[0].loglog(n, ref, "k:", label="linear (through the largest)")
    axs[0].set_xlabel("grid points")
    axs[0].set_ylabel("wall time [s]")
    axs[0].legend()
    axs[0].grid(True, alpha=0.3)
    axs[1].semilogx(n, [r["kernel_points_per_s"] for r in runs], "o-", label="kernel")
    if "sweep_points_per_s" in runs[0]:
        axs[1].semilogx(n, [r["sweep_points_per_s"] for r in runs], "s-", label="sweep()")
    axs[1].axhline(65536 / 10.0, color="r", ls="--", lw=1, label="10 s per 256^2 map")
    axs[1].axhline(65536 / 35.0, color="k", ls=":", lw=1, label="best peer, quoted (35 s)")
    axs[1].set_xlabel("grid points")
    axs[1].set_ylabel("points / s")
    axs[1].set_ylim(bottom=0)
    axs[1].legend(fontsize=8)
    axs[1].grid(True, alpha=0.3)
    fig.suptitle("Throughput on the Hopf-map box, auto tol 1e-8, 2 cores")
    fig.savefig(outdir / "throughput.png", dpi=110)
    plt.close(fig)
