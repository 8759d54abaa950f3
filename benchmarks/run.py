"""Run sweepcore's benchmarks and regenerate every figure, table and JSON file.

    python benchmarks/run.py            # full mode (duration: in benchmarks/README.md)
    python benchmarks/run.py --quick    # a few minutes, smaller ladders and samples
    python benchmarks/run.py --quick --sections hopf,peers,cost
    python benchmarks/run.py --sections heyoka,pybasin    # the strongest peers only

Results go to ``benchmarks/results/<mode>/`` (one JSON file per section, PNG figures).
A full run then rewrites ``benchmarks/README.md`` and the generated speed block of the
top-level ``README.md`` from ``benchmarks/results/full/``; a quick run writes its
summary to ``benchmarks/results/quick/README.md`` and never touches the full-mode
tables (its folder is not tracked by git). The pybasin section runs pybasin in its own
Python >= 3.12 environment ($PYBASIN_PYTHON, else ../pybasin-venv/bin/python beside
the repository; benchmarks/pybasin_compare.py says how to make it) or, without it,
reads pybasin's saved results. Numba kernels are compiled into
a private, fresh ``NUMBA_CACHE_DIR`` for the run (a stale cache of kernels edited
since it was written can never be timed), removed at the end.
"""
from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

SECTIONS = ("hopf", "wp", "throughput", "peers", "cost", "heyoka", "pybasin", "laws")

PROFILES = {
    # end-to-end check on a handful of points (tests/test_benchmarks_smoke.py)
    "smoke": dict(
        map_shape=(12, 12), map_tols=[1e-8], map_repeats=1, map_ladder_repeats=1,
        scaling_repeats=1, dask_schedulers=["threads"], dask_chunks=[50], dask_repeats=1,
        compile_probe=False, ref_points=16, scipy_per_regime=1, hard_per_column=1,
        wp_const_points=3, wp_per_regime=1, wp_gps_dt=[0.01], wp_rk4_dt=[0.01],
        wp_dopri5_tol=[1e-8], wp_dop853_tol=[1e-8], wp_repeats=1, wp_boundary_iters=4,
        tp_sides=[4, 8], tp_repeats_small=1, tp_repeats_large=1,
        peer_points=2, peer_ref_tol=1e-10, peer_rk45_tols=[1e-6], peer_rk4_dt=[0.01],
        peer_numba_repeats=1, peer_map_points=8,
        heyoka_map_shape=(12, 12), heyoka_tols=[1e-13], heyoka_repeats=1,
        heyoka_processes=2, heyoka_batch=8,
        pybasin_speeds=[1.5], pybasin_samples=200, pybasin_repeats=1, pybasin_curve=False,
        laws_shape=(8, 4), laws_repeats=1),
    "quick": dict(
        map_shape=(256, 256), map_tols=[1e-8, 1e-10], map_repeats=3, map_ladder_repeats=1,
        scaling_repeats=3, dask_schedulers=["threads", "processes", "localcluster"],
        dask_chunks=[16384], dask_repeats=3, compile_probe=True, ref_points=200,
        hard_per_column=1,
        scipy_per_regime=2,
        wp_const_points=16, wp_per_regime=8, wp_gps_dt=[0.02, 0.005, 0.001, 2e-4],
        wp_rk4_dt=[0.05, 0.01, 0.002], wp_dopri5_tol=[1e-5, 1e-8, 1e-11],
        wp_dop853_tol=[1e-5, 1e-8, 1e-11], wp_repeats=3,
        wp_boundary_iters=20,
        tp_sides=[10, 32, 100, 316], tp_repeats_small=3, tp_repeats_large=1,
        peer_points=6, peer_ref_tol=1e-12, peer_rk45_tols=[1e-8],
        peer_rk4_dt=[0.02, 0.01, 0.005], peer_numba_repeats=1, peer_map_points=4096,
        heyoka_map_shape=(64, 64), heyoka_tols=[1e-12, 1e-13], heyoka_repeats=1,
        heyoka_processes=2, heyoka_batch=8,
        pybasin_speeds=[1.175, 1.5], pybasin_samples=5000, pybasin_repeats=3,
        laws_shape=(64, 16), laws_repeats=5),
    "full": dict(
        map_shape=(256, 256), map_tols=[1e-6, 1e-8, 1e-10, 1e-12], map_repeats=5,
        map_ladder_repeats=2, scaling_repeats=3,
        dask_schedulers=["threads", "processes", "localcluster"],
        dask_chunks=[10000, 16384], dask_repeats=3, compile_probe=True, ref_points=500,
        hard_per_column=3,
        scipy_per_regime=3,
        wp_const_points=32, wp_per_regime=16,
        wp_gps_dt=[0.02, 0.01, 0.005, 0.002, 0.001, 5e-4, 2e-4, 1e-4],
        wp_rk4_dt=[0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001],
        wp_dopri5_tol=[1e-4, 1e-6, 1e-8, 1e-10, 1e-12],
        wp_dop853_tol=[1e-4, 1e-6, 1e-7, 1e-8, 1e-10, 1e-12], wp_repeats=3, wp_boundary_iters=25,
        tp_sides=[10, 32, 100, 316, 1000], tp_repeats_small=3, tp_repeats_large=2,
        peer_points=17, peer_ref_tol=1e-13, peer_rk45_tols=[1e-6, 1e-8, 1e-10],
        peer_rk4_dt=[0.04, 0.02, 0.01, 0.005, 0.0025, 0.001], peer_numba_repeats=1,
        peer_map_points=65536, regimes_before="23b2570", regimes_rounds=3,
        heyoka_map_shape=(256, 256), heyoka_tols=[1e-10, 1e-11, 1e-12, 1e-13],
        heyoka_repeats=2,
        heyoka_processes=2, heyoka_batch=8,
        pybasin_speeds=[1.175, 1.25, 1.5], pybasin_samples=5000, pybasin_repeats=3,
        laws_shape=(128, 32), laws_repeats=7),
}


def parse(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="a few-minute run")
    ap.add_argument("--smoke", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--sections", default=",".join(SECTIONS),
                    help=f"comma-separated subset of {','.join(SECTIONS)}")
    ap.add_argument("--outdir", type=Path, default=None,
                    help="results directory (default benchmarks/results/<mode>)")
    ap.add_argument("--readme", type=Path, default=None,
                    help="summary to write (default: full mode benchmarks/README.md and "
                         "the README's speed block; other modes <outdir>/README.md; "
                         "'none' to skip)")
    ap.add_argument("--keep-numba-cache", action="store_true",
                    help="use the usual numba cache instead of a fresh private one")
    args = ap.parse_args(argv)
    args.mode = "smoke" if args.smoke else ("quick" if args.quick else "full")
    args.sections = [s.strip() for s in args.sections.split(",") if s.strip()]
    bad = set(args.sections) - set(SECTIONS)
    if bad:
        ap.error(f"unknown sections {sorted(bad)}; choose from {SECTIONS}")
    return args


def main(argv=None):
    args = parse(argv)
    private_cache = None
    if not args.keep_numba_cache and "NUMBA_CACHE_DIR" not in os.environ:
        if "numba" in sys.modules:
            print("warning: numba already imported; NUMBA_CACHE_DIR not changed")
        else:
            private_cache = tempfile.mkdtemp(prefix="sweepcore-bench-numba-")
            os.environ["NUMBA_CACHE_DIR"] = private_cache
    try:
        return _run(args)
    finally:
        if private_cache:
            shutil.rmtree(private_cache, ignore_errors=True)


def _run(args):
    import json

    from benchmarks import common, report
    profile = PROFILES[args.mode]
    outdir = args.outdir or (common.RESULTS / args.mode)
    outdir.mkdir(parents=True, exist_ok=True)
    t_start = time.perf_counter()
    info = common.machine()
    common.log(f"sweepcore benchmarks, mode {args.mode}, sections {args.sections}")
    common.log(f"  {info['cpu_model']} {info['cpu_mhz']:.0f} MHz x {info['cores']} cores, "
               f"numba {info['numba']} ({info['numba_threading_layer']}), numpy "
               f"{info['numpy']}, python {info['python']}, commit {info['git_commit']}"
               f"{' (+ uncommitted sweepcore changes)' if info['sweepcore_dirty'] else ''}")
    meta = {"machine": info, "mode": args.mode, "profile": profile,
            "numba_cache": "private fresh NUMBA_CACHE_DIR" if not args.keep_numba_cache
            else "default"}

    def save(name, res, t0):
        res = {**meta, "section": name, "section_seconds": time.perf_counter() - t0, **res}
        common.save_json(res, outdir / f"{name}.json")
        return res

    def load(name):
        p = outdir / f"{name}.json"
        return json.loads(p.read_text()) if p.exists() else None

    results = {}
    if "hopf" in args.sections:
        from benchmarks import hopf_map
        t0 = time.perf_counter()
        results["hopf_map"] = save("hopf_map", hopf_map.run(profile, outdir), t0)
    if "wp" in args.sections:
        from benchmarks import work_precision
        t0 = time.perf_counter()
        results["work_precision"] = save("work_precision", work_precision.run(profile, outdir), t0)
    if "throughput" in args.sections:
        from benchmarks import throughput
        t0 = time.perf_counter()
        results["throughput"] = save("throughput", throughput.run(profile, outdir), t0)
    if "peers" in args.sections:
        from benchmarks import peer_compare
        t0 = time.perf_counter()
        results["peers"] = save("peers", peer_compare.run(
            profile, outdir, results.get("hopf_map") or load("hopf_map")), t0)
    if "cost" in args.sections:
        from benchmarks import cost_model
        hopf = results.get("hopf_map") or load("hopf_map")
        if hopf is None:
            common.log("[5] cost model skipped: no hopf_map results")
        else:
            t0 = time.perf_counter()
            results["cost_model"] = save("cost_model", cost_model.run(
                profile, outdir, hopf, results.get("peers") or load("peers")), t0)
    if "heyoka" in args.sections:
        from benchmarks import heyoka_compare
        t0 = time.perf_counter()
        results["heyoka"] = save("heyoka", heyoka_compare.run(
            profile, outdir, results.get("hopf_map") or load("hopf_map")), t0)
    if "pybasin" in args.sections:
        from benchmarks import pybasin_compare
        t0 = time.perf_counter()
        official = summary_targets(args.mode, outdir, args.outdir, args.readme)[1]
        results["pybasin"] = save("pybasin", pybasin_compare.run(profile, outdir, official),
                                  t0)
    if "laws" in args.sections:
        from benchmarks import laws
        t0 = time.perf_counter()
        results["laws"] = save("laws", laws.run(profile, outdir), t0)
    # the map's and the work-precision figures show the peers next to sweepcore
    hopf = results.get("hopf_map") or load("hopf_map")
    if hopf is not None:
        from benchmarks import hopf_map
        hopf_map.replot(outdir, hopf, results.get("peers") or load("peers"),
                        results.get("heyoka") or load("heyoka"))
    wp = results.get("work_precision") or load("work_precision")
    if wp is not None:
        from benchmarks import work_precision
        work_precision.plot(wp, results.get("peers") or load("peers"), outdir)
    total = time.perf_counter() - t_start
    common.log(f"done in {total:.0f} s; results in {outdir}")
    readme, top = summary_targets(args.mode, outdir, args.outdir, args.readme)
    if readme is not None:
        report.write_readme(outdir, readme, args.mode, total)
        common.log(f"summary written to {readme}")
    if top and report.update_block(common.ROOT / "README.md", report.readme_block(outdir)):
        common.log(f"speed block of {common.ROOT / 'README.md'} regenerated")
    if top and report.compile_estimates(outdir):
        common.log("compile estimates written to sweepcore/compile_estimates.json")
    return results


def summary_targets(mode, outdir, outdir_arg=None, readme_arg=None):
    """(summary file or None, whether to regenerate the top-level README's block).

    Only a full run into the default folder speaks for the project: it rewrites
    benchmarks/README.md and the README's speed block. Any other run (quick, smoke,
    another folder) writes its summary beside its own results and touches neither.
    """
    from benchmarks import common
    official = mode == "full" and outdir_arg is None and readme_arg is None
    if readme_arg is not None:
        readme = None if str(readme_arg).lower() == "none" else Path(readme_arg)
    else:
        readme = common.BENCH / "README.md" if official else Path(outdir) / "README.md"
    return readme, official


if __name__ == "__main__":
    main()
