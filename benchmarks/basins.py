"""Basin stability of the published friction case: sweepcore's exact and sampled routes
against a scipy Monte-Carlo estimate of one point, as speed ratios.

* exact route: the whole curve of ``studies/bstab_basins.toml`` (256 belt speeds in
  [1, 2], every fraction to ftol = 1e-6, checked by 19 starts a point), warm, median
  of ``--repeats``;
* sampled route: one point (v = 1.5) from 5,000 uniform starts (the published count)
  on the attractor kernel, warm, median of ``--repeats``;
* the baseline: the scipy solve_ivp Monte-Carlo estimate of one point the way bSTAB /
  pybasin do it (``benchmarks/basin_peer.py``: exact sticking, RK45 at rtol 1e-6, t in
  [0, 500], 5,000 samples extrapolated from the median time of one sample). With
  ``--peer-samples N`` it is timed in this run on N samples (same machine, same
  load); with 0 the saved ``benchmarks/results/basin_peer.json`` is used.

Ratios: scipy's 5,000-sample point over sweepcore's whole 256-speed curve, over one
exact point, and over one sampled point of 5,000 starts.

    python benchmarks/basins.py [--repeats 3] [--peer-samples 20] [--write]

``--write`` saves ``benchmarks/results/basins.json``.
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks.common import RESULTS, load, log, machine, save_json  # noqa: E402

OUT = RESULTS / "basins.json"
PEER = RESULTS / "basin_peer.json"
STUDY = ROOT / "studies" / "bstab_basins.toml"
SAMPLES = 5000
V_SAMPLED = 1.5


def _timed(fn, repeats):
    times, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), times, out


def peer_per_sample(n: int):
    """Median seconds of one scipy sample (``n`` starts timed here, or the saved
    result for n = 0) and where it came from."""
    if n == 0:
        saved = json.loads(PEER.read_text())
        return saved["per_sample_median_s"], dict(source=str(PEER.relative_to(ROOT)),
                                                  n_timed=saved["settings"]["n_timed"],
                                                  date=saved["machine"]["date"])
    from benchmarks import basin_peer as bp
    rng = np.random.default_rng(bp.SEED)
    (xl, xh), (yl, yh) = bp.BOX
    bp.run_one(0.1, 0.1)                              # warm-up
    times = []
    for x0, xd0 in zip(rng.uniform(xl, xh, n), rng.uniform(yl, yh, n)):
        t0 = time.perf_counter()
        bp.run_one(x0, xd0)
        times.append(time.perf_counter() - t0)
    return statistics.median(times), dict(source="timed in this run", n_timed=n,
                                          times=times)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--peer-samples", type=int, default=0,
                    help="scipy samples to time in this run (0: the saved result)")
    ap.add_argument("--write", action="store_true",
                    help=f"write {OUT.relative_to(ROOT)}")
    args = ap.parse_args(argv)
    import sweepcore as sc
    from sweepcore.study import load_study

    info = machine()
    load0 = load()
    study = load_study(STUDY)
    b = study.basins
    box = dict(x0=b["x0"], xdot0=b["xdot0"])
    grid = study.grid()
    point = sc.Grid(**{**study.grid_kwargs(), "v": np.array([V_SAMPLED])})

    def curve():
        return sc.basin_stability(grid, **box, route="exact", ftol=b["ftol"],
                                  progress=False)

    def sampled():
        return sc.basin_stability(point, **box, route="sampled", samples=SAMPLES,
                                  progress=False)

    sc.basin_stability(point, **box, route="exact", progress=False)   # compile / load
    sc.basin_stability(point, **box, route="sampled", samples=16, progress=False)
    t_curve, curve_times, ds = _timed(curve, args.repeats)
    log(f"exact route: {grid.size} speeds in {t_curve:.2f} s "
        f"({1e3 * t_curve / grid.size:.1f} ms a point)")
    t_mc, mc_times, mc = _timed(sampled, args.repeats)
    log(f"sampled route: {SAMPLES} starts at v = {V_SAMPLED} in {t_mc:.2f} s")
    per, peer = peer_per_sample(args.peer_samples)
    peer_point = per * SAMPLES
    log(f"scipy Monte-Carlo: {per:.4f} s a sample, {peer_point:.0f} s for {SAMPLES} "
        f"({peer['source']})")
    errors = ds.basin_fraction_error.values
    res = dict(
        machine=info, load_before=load0, load_after=load(),
        settings=dict(study=str(STUDY.relative_to(ROOT)), points=grid.size,
                      ftol=b["ftol"], samples=SAMPLES, v_sampled=V_SAMPLED,
                      repeats=args.repeats),
        exact=dict(curve_s=t_curve, curve_times_s=curve_times,
                   per_point_s=t_curve / grid.size,
                   routes_exact=int((ds.basin_route.values == 0).sum()),
                   largest_error=float(np.nanmax(errors))),
        sampled=dict(point_s=t_mc, times_s=mc_times,
                     fraction=float(mc.basin_fraction.sel(attractor="equilibrium")[0]),
                     error=float(mc.basin_fraction_error.sel(
                         attractor="equilibrium")[0])),
        peer=dict(per_sample_s=per, point_5000_s=peer_point, **peer),
        ratios=dict(peer_point_over_exact_curve=peer_point / t_curve,
                    peer_point_over_exact_point=peer_point / (t_curve / grid.size),
                    peer_point_over_sampled_point=peer_point / t_mc))
    if args.peer_samples:          # the saved baseline too, for comparison
        saved, _ = peer_per_sample(0)
        res["ratios"]["saved_peer_point_over_exact_curve"] = saved * SAMPLES / t_curve
        res["peer"]["saved_per_sample_s"] = saved
    r = res["ratios"]
    log(f"scipy's one point / sweepcore's {grid.size}-speed curve: "
        f"{r['peer_point_over_exact_curve']:.0f}x; per point: exact "
        f"{r['peer_point_over_exact_point']:.3g}x, sampled "
        f"{r['peer_point_over_sampled_point']:.0f}x")
    if args.write:
        save_json(res, OUT)
        log(f"wrote {OUT.relative_to(ROOT)}")
    return res


if __name__ == "__main__":
    main()
