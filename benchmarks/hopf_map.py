"""Section 1: the (v, alpha2) Hopf map of studies/hopf_map.toml, timed, scaled and checked.

Grid: m = 5, k = 50, r_y = 10, alpha1 = 1, every point starts stuck (x0 = 0,
xdot0 = v); v in linspace(0.5, 10, 256), alpha2 in geomspace(1e-3, 0.1, 256).

Measured here:
* warm wall time of the bare kernel (``sweepcore.compiled.attractors``, 2 threads) at
  the default tolerance and a ladder of tolerances, median of repeats, points/s;
* the same through the public ``sweepcore.sweep`` (direct path and dask schedulers:
  threads, processes, a 2-worker LocalCluster), i.e. the dask overhead;
* thread scaling: ``numba.set_num_threads(1)`` against 2;
* cold compile (fresh process, empty ``NUMBA_CACHE_DIR``), warm-cache load, and peak
  resident memory (VmHWM of /proc/self/status) of a fresh process that runs the map;
* the main job, ``sweepcore run studies/hopf_map.toml``, from an empty kernel cache
  and again warm, back to back (``main_job``);
* error of the map on a random subsample against a tight reference (dopri5 at
  tol 1e-12, cross-checked by rk4 at dt = 1e-3 and, on a handful of points, by the
  independent scipy DOP853 event-driven solver of ``peers.py``).
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from . import common
from .common import log
from sweepcore._kernels import layout
from sweepcore._kernels.layout import (NOBS, OB_AMPLITUDE, OB_REGIME, OB_STATUS,
                                       OB_X_MAX)


def _kernels():
    from sweepcore.options import make_options
    run = common.kernel()
    return (lambda P, o, out: run(P, o, out, False),
            lambda P, o, out: run(P, o, out, True), make_options)


def time_kernel(P, o, repeats, parallel=True):
    """Median warm wall time of the kernel over P (after one small warm-up call)."""
    rows_serial, rows_parallel, _ = _kernels()
    fn = rows_parallel if parallel else rows_serial
    out = np.empty((P.shape[0], NOBS))
    fn(P[:4], o, out[:4])                     # compile / load outside the timing
    med, times, _ = common.timed(lambda: fn(P, o, out), repeat=repeats)
    return med, times, out


def thread_scaling(P, o, repeats):
    """Kernel on 1 and on all threads, runs interleaved (1, 2, 1, 2, ...) so that
    drifting load on the shared machine hits both alike; speedup = median of the
    per-pair ratios. Done twice: rows in the map's order (v slow, alpha2 fast) and
    in a random order, which shows how much of the scaling is lost to an uneven
    split of the (clustered) costly points between threads."""
    import numba
    _rs, rows_parallel, _mo = _kernels()
    n_max = numba.config.NUMBA_NUM_THREADS
    counts = sorted({1, min(2, n_max), n_max})
    perm = np.random.default_rng(1).permutation(P.shape[0])
    orders = {"grid order": P, "shuffled rows": np.ascontiguousarray(P[perm])}
    out = np.empty((P.shape[0], NOBS))
    rows_parallel(P[:4], o, out[:4])
    times = {(name, n): [] for name in orders for n in counts}
    try:
        for _ in range(repeats):
            for name, PP in orders.items():
                for n in counts:
                    numba.set_num_threads(n)
                    t0 = time.perf_counter()
                    rows_parallel(PP, o, out)
                    times[name, n].append(time.perf_counter() - t0)
    finally:
        numba.set_num_threads(n_max)
    res = {}
    for name in orders:
        res[name] = {}
        for n in counts:
            pair = [a / b for a, b in zip(times[name, 1], times[name, n])]
            r = {"median_s": common.median(times[name, n]), "min_s": min(times[name, n]),
                 "times_s": times[name, n], "speedup": common.median(pair),
                 "efficiency": common.median(pair) / n}
            res[name][str(n)] = r
            log(f"    {name:<14s} threads={n}: {r['median_s']:.3f} s, speedup "
                f"{r['speedup']:.2f}")
    return res


def compile_probe(nv, na, timeout=900):
    """Cold compile and warm-cache load, each in a fresh interpreter."""
    res = {}
    with tempfile.TemporaryDirectory(prefix="sweepcore-numba-cache-") as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        for label, extra in (("cold", []), ("warm_cache", ["map"])):
            t0 = time.perf_counter()
            cp = subprocess.run([sys.executable, str(common.BENCH / "compile_probe.py"),
                                 str(nv), str(na), *extra], env=env, capture_output=True,
                                text=True, timeout=timeout, cwd=common.ROOT)
            wall = time.perf_counter() - t0
            if cp.returncode != 0:
                res[label] = {"error": cp.stderr[-2000:]}
                log(f"    {label}: probe failed\n{cp.stderr[-2000:]}")
                continue
            r = json.loads(cp.stdout.strip().splitlines()[-1])
            r["process_wall_s"] = wall
            res[label] = r
            log(f"    {label}: first call {r['t_first_call_parallel']:.2f} s "
                f"(+ serial {r['t_first_call_serial']:.2f} s), process {wall:.1f} s")
    return res


def main_job(timeout=1800) -> dict:
    """``sweepcore run studies/hopf_map.toml`` (the README's main job) from an empty
    kernel cache, then again from the filled one, back to back, each in a fresh
    process: wall and CPU seconds (the process and its children: the second
    compiler, ``sweepcore.compiled``), their ratio, and the compile seconds of each
    kernel that the cold run measured (``compile_seconds``: the estimates the
    command prints while it compiles, ``sweepcore/compile_estimates.json``)."""
    import resource
    res = {}
    with tempfile.TemporaryDirectory(prefix="sweepcore-main-job-") as tmp:
        env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
        env["SWEEPCORE_CACHE_DIR"] = tmp
        cmd = [sys.executable, "-m", "sweepcore", "run", "studies/hopf_map.toml", "-o",
               str(Path(tmp) / "map.nc"), "--png", str(Path(tmp) / "map.png"), "-q"]
        for label in ("cold", "warm"):
            r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
            t0 = time.perf_counter()
            cp = subprocess.run(cmd, env=env, cwd=common.ROOT, capture_output=True,
                                text=True, timeout=timeout)
            wall = time.perf_counter() - t0
            r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
            if cp.returncode != 0:
                res[label] = {"error": cp.stderr[-2000:]}
                log(f"    main job {label}: failed\n{cp.stderr[-2000:]}")
                return res
            res[label] = {"wall_s": wall, "cpu_s": (r1.ru_utime - r0.ru_utime)
                          + (r1.ru_stime - r0.ru_stime)}
            log(f"    main job {label}: {wall:.1f} s wall, {res[label]['cpu_s']:.1f} s CPU")
        seconds = {}
        for f in Path(tmp).glob("numba-*/sweepcore_compile_seconds.json"):
            seconds.update(json.loads(f.read_text()))
    res["compile_seconds"] = seconds
    res["ratio_wall"] = res["cold"]["wall_s"] / res["warm"]["wall_s"]
    res["command"] = "sweepcore run studies/hopf_map.toml (empty kernel cache, then warm)"
    log(f"    cold / warm: {res['ratio_wall']:.2f}x (target: at most 3x)")
    return res


def dask_overhead(v, a2, P, o, out, profile):
    """The map through sweepcore.sweep (direct path, dask schedulers) against the bare
    kernel. Each executor run is paired with a kernel run right before it; the
    overhead is the median over pairs of (executor / kernel) - 1."""
    sweep, Grid = common.sweep_api()
    if sweep is None:
        return {"skipped": "sweepcore.sweep not available"}
    _rs, rows_parallel, _mo = _kernels()
    grid = common.map_grid(Grid, v, a2)
    kout = np.empty_like(out)
    res = {"n_points": int(P.shape[0]), "runs": [], "kernel_times_s": []}
    repeats = profile["dask_repeats"]

    def record(label, fn, chunks, extra=None):
        ds = fn()                              # warm-up (workers load the kernels)
        kt, et = [], []
        for _ in range(repeats):
            t0 = time.perf_counter()
            rows_parallel(P, o, kout)
            kt.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            ds = fn()
            et.append(time.perf_counter() - t0)
        res["kernel_times_s"] += kt
        ratio = common.median([e / k for e, k in zip(et, kt)])
        med = common.median(et)
        row = {"executor": label, "chunks": chunks, "median_s": med, "min_s": min(et),
               "times_s": et, "paired_kernel_times_s": kt,
               "overhead_vs_kernel": ratio - 1.0, "points_per_s": P.shape[0] / med,
               **(extra or {})}
        res["runs"].append(row)
        log(f"    {label:<28s} chunks={chunks!s:>6s}: {med:.3f} s "
            f"({100 * row['overhead_vs_kernel']:+.0f} % vs paired kernel runs)")
        return ds

    ds = record("sweep (numba threads)", lambda: sweep(grid, progress=False), "default")
    # the sweep's observables are the kernel's, bit for bit (same points, same order)
    amp = np.asarray(ds["amplitude"].transpose("v", "alpha2").values).ravel()
    res["sweep_matches_kernel"] = bool(np.array_equal(amp, out[:, 0], equal_nan=True))
    for label in profile["dask_schedulers"]:
        for chunks in profile["dask_chunks"]:
            if label in ("threads", "processes"):
                record(f"dask {label}", lambda: sweep(grid, chunks=chunks, scheduler=label,
                                                      progress=False), chunks)
    if "localcluster" in profile["dask_schedulers"]:
        from distributed import Client, LocalCluster
        # env= reaches the workers only. (The dask.config key
        # "distributed.nanny.pre-spawn-environ" would also be written into this
        # process's os.environ and left there, after which numba refuses to compile
        # anything here: "Cannot set NUMBA_NUM_THREADS to a different value".)
        saved = dict(os.environ)
        try:
            t0 = time.perf_counter()
            with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                              host="127.0.0.1", dashboard_address=None,
                              env={"NUMBA_NUM_THREADS": "1"}) as cluster, \
                    Client(cluster) as client:
                startup = time.perf_counter() - t0
                log(f"    LocalCluster(2 workers x 1 thread) up in {startup:.1f} s")
                for chunks in profile["dask_chunks"]:
                    record("dask LocalCluster 2x1", lambda: sweep(
                        grid, chunks=chunks, client=client, progress=False), chunks,
                        {"cluster_startup_s": startup})
        finally:
            res["environ_changed_by_cluster"] = {k: os.environ.get(k) for k in
                                              set(os.environ) ^ set(saved)}
            os.environ.clear()
            os.environ.update(saved)
    res["kernel_median_s"] = common.median(res["kernel_times_s"])
    return res


def scipy_check(Ps, ref, rng, per_regime):
    """Independent check of reference rows by the scipy DOP853 solver of peers.py."""
    from . import peers
    picks = []
    for reg in (2, 1, 0):
        cand = np.flatnonzero((ref[:, 8] == reg) & (ref[:, 9] == 0))
        picks += list(rng.choice(cand, min(per_regime, cand.size), replace=False))
    checks = []
    for i in picks:
        t0 = time.perf_counter()
        s = peers.scipy_attractor(Ps[i], rtol=1e-12, atol=1e-13)
        period_diff = abs(ref[i, 4] - s["period"]) if np.isfinite(ref[i, 4]) else None
        checks.append({"v": Ps[i, 3], "alpha2": Ps[i, 5],
                       "regime_ref": common.REGIMES[int(ref[i, 8])],
                       "regime_scipy": s["regime"], "seconds": time.perf_counter() - t0,
                       "amp_ref": ref[i, 0], "amp_scipy": s["amplitude"],
                       "amp_diff": abs(ref[i, 0] - s["amplitude"]),
                       "mean_diff": abs(ref[i, 1] - s["mean"]), "period_diff": period_diff})
    amp = [c["amp_diff"] for c in checks if np.isfinite(c["amp_diff"])]
    mean = [c["mean_diff"] for c in checks if np.isfinite(c["mean_diff"])]
    return {"scipy_dop853_check": checks,
            "scipy_check_max_amp_diff": max(amp) if amp else None,
            "scipy_check_max_mean_diff": max(mean) if mean else None,
            "scipy_check_regimes_agree": all(c["regime_ref"] == c["regime_scipy"]
                                             for c in checks)}


def accuracy(P, out, profile, tols_out):
    """Errors of the map runs on a random subsample against tight references."""
    _rs, rows_parallel, make_options = _kernels()
    rng = np.random.default_rng(20261122)
    n = min(profile["ref_points"], P.shape[0])
    idx = np.sort(rng.choice(P.shape[0], n, replace=False))
    Ps = P[idx]
    L = common.length_scale(Ps)
    t0 = time.perf_counter()
    ref = np.empty((n, NOBS))
    rows_parallel(Ps, make_options("dopri5", tol=1e-12), ref)
    t_ref = time.perf_counter() - t0
    rk = np.empty((n, NOBS))
    rows_parallel(Ps, make_options("rk4", dt=1e-3, tol=1e-12), rk)
    res = {"n_subsample": n, "seed": 20261122, "reference": "dopri5 tol=1e-12",
           "reference_time_s": t_ref, "reference_regimes": common.regime_counts(ref),
           "rk4_dt1e-3_vs_reference": common.compare(rk, ref, L), "map": {}}
    for tol, full_out in tols_out.items():
        res["map"][f"{tol:g}"] = common.compare(full_out[idx], ref, L)
    # independent scipy DOP853 cross-check on a handful of points, stratified by regime
    res.update(scipy_check(Ps, ref, rng, profile["scipy_per_regime"]))
    return res, idx, ref


def hardest_references(P, base, per_column):
    """The points where waiting for convergence fails and their independent
    references: in every alpha2 column of the map, the ``per_column`` slip-cycle
    points of the run ``base`` nearest below v* (where the cycle's contraction per
    period 1 - mu is smallest), against the scipy shooting solve of
    ``tests/reference.py`` (DOP853 at rtol 1e-13, secant on the return map). The
    reference's own noise is ~1e-13 L / (1 - mu); points where that exceeds 1e-9 L
    are unresolved, and the closest of them are checked against the Hopf normal form
    instead, with its measured second-order term (studies/normal_form.py), whose
    remainder ~10 A (1.2 q/omega)^2 is far below 1e-9 there.

    Returns (picks, refs): row indices into P and {index: dict(amplitude, floquet,
    resolved, source)}.
    """
    from tests.reference import reference_slip_cycle

    m, k, ry, a1 = P[0, 0], P[0, 1], P[0, 2], P[0, 4]
    w = np.sqrt(k / m)
    picks = []
    for a2 in np.unique(P[:, 5]):
        col = np.flatnonzero(P[:, 5] == a2)
        vs = np.sqrt(a1 / (3.0 * a2))
        below = col[(P[col, 3] < vs) & (base[col, OB_REGIME] == 1)]
        below = below[np.argsort(vs - P[below, 3])][:per_column]
        picks += list(below)
    refs = {}
    for i in picks:
        v, a2 = P[i, 3], P[i, 5]
        q = (a1 - 3.0 * a2 * v * v) / m
        L = ry / k + v / w
        c2 = 3.0 * a2 * v / m
        G = c2 * c2 / (a2 / m * w)
        A1 = np.sqrt(4.0 * m * q / (3.0 * a2)) / w
        nf = A1 * (1.0 + 7.0 / 18.0 * G * q / w)
        nf_bound = 10.0 * nf * ((1.0 + G) * q / w) ** 2
        try:
            r = reference_slip_cycle(m, k, ry, v, a1, a2, base[i, OB_X_MAX])
            noise = 1e-13 * L / max(1.0 - r["floquet"], 1e-300)
            refs[i] = dict(amplitude=r["amplitude"], floquet=r["floquet"],
                           resolved=noise <= 1e-9 * L, source="scipy shooting")
            if not refs[i]["resolved"] and nf_bound <= 1e-9 * L:
                refs[i].update(amplitude=nf, resolved=True, source="normal form")
        except (ValueError, IndexError) as err:        # reaches belt speed, no event
            refs[i] = dict(amplitude=np.nan, floquet=np.nan, resolved=False,
                           source=f"scipy failed: {err}")
    return picks, refs


def hardest_errors(P, amplitude, ok, picks, refs):
    """Errors of ``amplitude`` [cm] (where ``ok``) on the picked points against their
    resolved references: the maximum overall, over L and in bands of v / v*."""
    a1 = P[0, 4]
    L = common.length_scale(P)
    errors = []
    for i in picks:
        r = refs[i]
        if not ok[i] or not r["resolved"]:
            continue
        errors.append((P[i, 3] / np.sqrt(a1 / (3.0 * P[i, 5])),
                       abs(amplitude[i] - r["amplitude"]), L[i]))
    bands = {}
    for lo, hi, label in ((0.0, 0.99, "< 0.99 v*"), (0.99, 0.999, "0.99-0.999 v*"),
                          (0.999, 1.0, "0.999-1 v*")):
        sel = [e for x, e, _L in errors if lo <= x < hi]
        bands[label] = {"n": len(sel), "max_amp_err": max(sel) if sel else None}
    errs = [e for _x, e, _L in errors]
    return dict(n_compared=len(errs), max_amp_err=max(errs) if errs else None,
                median_amp_err=float(np.median(errs)) if errs else None,
                max_amp_err_over_L=max(e / L_ for _x, e, L_ in errors) if errs else None,
                bands=bands)


def save_references(outdir, picks, refs):
    """The hardest points' references, for the peers' sections of the same run."""
    np.savez_compressed(Path(outdir) / "hardest_references.npz", picks=np.array(picks, int),
                        amplitude=np.array([refs[i]["amplitude"] for i in picks]),
                        resolved=np.array([refs[i]["resolved"] for i in picks]))


def load_references(outdir):
    """(picks, refs) saved by this run's Hopf-map section, or None."""
    path = Path(outdir) / "hardest_references.npz"
    if not path.exists():
        return None
    f = np.load(path)
    picks = [int(i) for i in f["picks"]]
    return picks, {i: dict(amplitude=float(a), resolved=bool(r))
                   for i, a, r in zip(picks, f["amplitude"], f["resolved"])}


def hardest_points(P, outs, per_column, outdir=None):
    """Errors of every run of ``outs`` on the hardest points (``hardest_references``,
    chosen on the tightest run), and whether every point above v* is at rest."""
    t0 = time.perf_counter()
    picks, refs = hardest_references(P, outs[min(outs)], per_column)
    if outdir is not None:
        save_references(outdir, picks, refs)
    res = {"n_points": len(picks), "per_column": per_column,
           "reference_time_s": time.perf_counter() - t0,
           "reference_sources": {s: sum(r["source"] == s for r in refs.values())
                                 for s in {r["source"] for r in refs.values()}},
           "reference_unresolved": sum(not r["resolved"] for r in refs.values()),
           "by_tol": {}}
    above = P[:, 3] > np.sqrt(P[0, 4] / (3.0 * P[:, 5]))
    for tol, out in outs.items():
        counts = {}
        for i in picks:
            name = common.STATUSES.get(int(out[i, OB_STATUS]), str(int(out[i, OB_STATUS])))
            counts[name] = counts.get(name, 0) + 1
        stat = {"status_counts": counts,
                **hardest_errors(P, out[:, OB_AMPLITUDE], out[:, OB_STATUS] == 0, picks, refs),
                "above_v_star_not_equilibrium": int(((out[:, OB_REGIME] != 0) & above).sum())}
        res["by_tol"][f"{tol:g}"] = stat
        log(f"    hardest points, tol={tol:g}: {stat['n_compared']} compared, max |amp err| "
            f"{stat['max_amp_err'] if stat['n_compared'] else float('nan'):.2e} cm, statuses "
            f"{stat['status_counts']}, above v* not equilibrium: "
            f"{stat['above_v_star_not_equilibrium']}")
    return res


def run(profile, outdir):
    _rs, _rp, make_options = _kernels()
    nv, na = profile["map_shape"]
    v, a2 = common.map_axes(nv, na)
    P = common.rows(v, a2)
    n = P.shape[0]
    res = {"grid": {"nv": nv, "na": na, "n_points": n, "v": list(common.MAP_V),
                    "alpha2": list(common.MAP_A2), "m": 5.0, "k": 50.0, "r_y": 10.0,
                    "alpha1": 1.0, "start": "stuck: x0 = 0, xdot0 = v"},
           "load_before": common.load()}
    log(f"[1] Hopf map {nv} x {na} = {n} points")

    # --- warm wall time at the default tolerance and a ladder
    outs = {}
    res["kernel"] = []
    for tol in profile["map_tols"]:
        reps = profile["map_repeats"] if tol == 1e-8 else profile["map_ladder_repeats"]
        med, times, out = time_kernel(P, make_options("auto", tol=tol), reps)
        outs[tol] = out
        conv = float((out[:, 9] == 0).mean())
        from .cost_model import map_method
        res["kernel"].append({"method": f"auto ({map_method(tol)})", "tol": tol, "median_s": med,
                              "min_s": min(times),
                              "times_s": times, "points_per_s": n / med,
                              "converged_fraction": conv,
                              "regimes": common.regime_counts(out),
                              "steps_total": float(out[:, 10].sum()),
                              "steps_per_point_mean": float(out[:, 10].mean()),
                              "steps_per_point_max": float(out[:, 10].max())})
        log(f"    kernel tol={tol:g}: {med:.3f} s  ({n / med:,.0f} pts/s), "
            f"converged {100 * conv:.3f} %")
    default = next(r for r in res["kernel"] if r["tol"] == 1e-8)
    res["headline"] = {"median_s": default["median_s"], "points_per_s": default["points_per_s"],
                       "converged_fraction": default["converged_fraction"],
                       "regimes": default["regimes"]}
    save_fields(outdir, outs[1e-8])
    from . import regimes
    res["regimes"] = {"this_run": regimes.table(          # rows: v slow, alpha2 fast
        P[:, layout.V], common.PAPER["alpha1"], np.tile(a2, v.size),
        outs[1e-8][:, OB_REGIME], outs[1e-8][:, layout.OB_NSTEPS])}
    if profile.get("regimes_before"):
        log(f"  steps by regime and wall time, this checkout against "
            f"{profile['regimes_before']} (interleaved probes)")
        res["regimes"]["before_after"] = regimes.before_after(
            profile["regimes_before"], profile["regimes_rounds"], profile["map_repeats"])
        ba = res["regimes"]["before_after"]
        if "speedup" in ba:
            log(f"    before {ba['median_s_before']:.3f} s, after {ba['median_s_after']:.3f} s"
                f" (x{ba['speedup']:.2f}); steps {ba['before']['steps_total']:.4g} -> "
                f"{ba['after']['steps_total']:.4g}")

    log("  thread scaling")
    res["threads"] = thread_scaling(P, make_options("auto", tol=1e-8),
                                    profile["scaling_repeats"])
    log("  sweep() and dask")
    res["dask"] = dask_overhead(v, a2, P, make_options("auto", tol=1e-8), outs[1e-8], profile)
    if profile["compile_probe"]:
        log("  compile probe (fresh processes)")
        res["compile"] = compile_probe(nv, na)
        log("  the main job, cold and warm")
        res["main_job"] = main_job()
    log("  accuracy against a tight reference")
    acc, idx, ref = accuracy(P, outs, profile, outs)
    res["accuracy"] = acc
    log("  accuracy on the hardest points (next to v*) against independent solvers")
    res["accuracy_hardest"] = hardest_points(P, outs, profile["hard_per_column"], outdir)
    for tol, r in acc["map"].items():
        log(f"    tol={tol}: max |amp err| {r['amplitude_abs']['max']:.2e} cm on "
            f"{r['n_compared']} points, regime mismatches {r['n_regime_mismatch']}")
    res["load_after"] = common.load()
    plot(v, a2, outs[1e-8], res, outdir)
    return res


def save_fields(outdir, out):
    """Keep what the figure needs (amplitude, regime) small: float32 and int8."""
    np.savez_compressed(outdir / "hopf_map_fields.npz",
                        amplitude=out[:, 0].astype(np.float32),
                        regime=out[:, 8].astype(np.int8))


def replot(outdir, res, peer_res=None, heyoka_res=None):
    """Redraw the map figure from the saved run, with the peers when they ran."""
    path = outdir / "hopf_map_fields.npz"
    if path.exists():
        f = np.load(path)
        out = np.full((f["amplitude"].size, NOBS), np.nan)
        out[:, 0] = f["amplitude"]
        out[:, 8] = f["regime"]
        v, a2 = common.map_axes(res["grid"]["nv"], res["grid"]["na"])
        plot(v, a2, out, res, outdir, peer_res, heyoka_res)


def plot(v, a2, out, res, outdir, peer_res=None, heyoka_res=None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import BoundaryNorm, ListedColormap

    nv, na = v.size, a2.size
    amp = out[:, 0].reshape(nv, na)
    reg = out[:, 8].reshape(nv, na)
    fig, axs = plt.subplots(1, 3, figsize=(16, 4.6), constrained_layout=True)
    ext = [np.log10(a2[0]), np.log10(a2[-1]), v[0], v[-1]]
    im = axs[0].imshow(amp, origin="lower", aspect="auto", extent=ext, cmap="viridis")
    fig.colorbar(im, ax=axs[0], label="amplitude [cm]")
    cmap = ListedColormap(["#4477aa", "#ee6677", "#228833", "#ccbb44", "#66ccee",
                           "#aa3377", "black", "grey"])
    axs[1].imshow(reg, origin="lower", aspect="auto", extent=ext, cmap=cmap,
                  norm=BoundaryNorm(np.arange(-0.5, 8.5), 8), interpolation="nearest")
    for k in np.unique(reg).astype(int):
        axs[1].plot([], [], "s", color=cmap(k), label=common.REGIMES[k])
    axs[1].legend(loc="upper right", fontsize=8)
    vs = np.sqrt(1.0 / (3.0 * a2))
    for ax in axs[:2]:
        ax.plot(np.log10(a2), vs, "w--", lw=1, label="v* (analytic)")
        ax.set_ylim(v[0], v[-1])
        ax.set_xlabel("log10 alpha2 [kN s^3/cm^3]")
        ax.set_ylabel("v [cm/s]")
    axs[0].set_title(f"amplitude, {nv} x {na}, auto tol 1e-8")
    axs[1].set_title("regime (start stuck)")
    # timing bars
    labels, vals, colors = [], [], []
    labels.append("sweepcore kernel\n2 threads")
    sh = res["threads"]["shuffled rows"].get("2")
    vals.append(res["headline"]["median_s"])
    colors.append("#228833")
    t1 = res["threads"]["grid order"].get("1")
    if sh:
        labels.append("kernel, 2 threads,\nrows shuffled")
        vals.append(sh["median_s"])
        colors.append("#228833")
    if t1:
        labels.append("kernel\n1 thread")
        vals.append(t1["median_s"])
        colors.append("#88bb88")
    for r in res["dask"].get("runs", []):
        labels.append(f"{r['executor']}\nchunks {r['chunks']}")
        vals.append(r["median_s"])
        colors.append("#4477aa")
    if peer_res and "numba_peer_map" in peer_res:
        pm = peer_res["numba_peer_map"]
        labels.append("numba RK4 peer dt 0.01\n(rerun here, "
                      + ("measured)" if pm["measured_or_extrapolated"] == "measured"
                         else "extrapolated)"))
        vals.append(pm["map_seconds"])
        colors.append("#ccbb44")
    if heyoka_res and "median" in heyoka_res:
        for mode in ("batch", "scalar"):
            if mode in heyoka_res["median"]:
                labels.append(f"heyoka.py {mode}, tol {heyoka_res['chosen_tol']:g}\n"
                              f"(rerun here, {heyoka_res['processes']} processes)")
                vals.append(heyoka_res["median"][mode]["wall"])
                colors.append("#aa3377")
    ax = axs[2]
    y = np.arange(len(vals))
    ax.barh(y, vals, color=colors)
    ax.set_yticks(y, labels, fontsize=7)
    ax.invert_yaxis()
    ax.axvline(10.0, color="r", ls="--", lw=1, label="target 10 s")
    ax.axvline(1.0, color="orange", ls="--", lw=1, label="aim 1 s")
    ax.set_xscale("log")
    ax.set_xlabel("wall time of the map [s] (median, warm)")
    ax.legend(fontsize=7, loc="lower right")
    ax.set_title("Hopf map wall time")
    fig.savefig(outdir / "hopf_map.png", dpi=110)
    plt.close(fig)
