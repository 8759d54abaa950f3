"""Write the benchmark reports from the saved JSON: ``benchmarks/README.md`` (the
command, what is measured, every table) and the generated block between
``<!-- bench:start -->`` and ``<!-- bench:end -->`` in the top-level ``README.md``.

    python -m benchmarks.report          # both, from benchmarks/results/full/

``benchmarks/run.py`` calls it at the end of a full run; a quick run writes its own
report into its results folder (``benchmarks/results/quick/README.md``) and leaves
both of these alone. Nothing in either is typed by hand.
"""
from __future__ import annotations

import json
import math
import os
from pathlib import Path

from . import common


def _load(outdir, name):
    p = Path(outdir) / f"{name}.json"
    return json.loads(p.read_text()) if p.exists() else None


def g(x, digits=3):
    """Compact number: 3 significant digits, '-' for missing."""
    if x is None:
        return "-"
    if isinstance(x, str):
        return x
    if x == 0:
        return "0"
    if not math.isfinite(x):
        return "-"
    a = abs(x)
    if 1e-3 <= a < 1e5:
        return f"{x:.{digits}g}"
    return f"{x:.{max(digits - 1, 1)}e}"


def s(x):
    """Seconds, readable."""
    if x is None:
        return "-"
    if x < 1e-3:
        return f"{x * 1e6:.3g} us"
    if x < 1:
        return f"{x * 1e3:.3g} ms"
    return f"{x:.3g} s"


def table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


STATIC_HEAD = """# sweepcore benchmarks

Scripts that time sweepcore against its targets and its peers, and save what they
measure (JSON with the commit, the machine and the date; PNG figures). Every number in
the tables below was produced by the command below; nothing is typed in by hand.

## Command

```bash
python benchmarks/run.py --quick      # smaller ladders and samples, a few minutes
python benchmarks/run.py              # full mode (its duration: "Results" below)
python benchmarks/run.py --quick --sections hopf,peers,cost   # a subset (hopf, wp, throughput, peers, cost)
```

Needs the package's `bench` extra (scipy) besides the runtime dependencies. Results go to
`benchmarks/results/<mode>/` (`hopf_map.json`, `work_precision.json`, `throughput.json`,
`peers.json`, `cost_model.json`, `hopf_map.png`, `work_precision.png`,
`throughput.png`). A full run rewrites this README and the speed block of the
top-level README from `benchmarks/results/full/` (`python -m benchmarks.report` does
the same from the saved JSON without rerunning); a `--quick` run writes only into
`benchmarks/results/quick/` (not tracked by git), its summary in
`benchmarks/results/quick/README.md`. The numba kernels
are compiled into a fresh private `NUMBA_CACHE_DIR` for the run (removed at the end), so
a stale cache of kernels edited since it was written is never timed.
`tests/test_benchmarks_smoke.py` runs the whole pipeline on a handful of points (no
timing assertions).

The machine is shared and noisy: every time is the median of repeats (the count is in
the JSON, with every individual time), the 1-minute load average is stored before and
after each section, and comparisons are given as ratios measured in the same run.

## What each section measures

1. **Hopf map** (`hopf_map.py`), the map of `studies/hopf_map.toml`: m = 5, k = 50, r_y = 10,
   alpha1 = 1, start stuck (x0 = 0, xdot0 = v), v in linspace(0.5, 10, 256), alpha2 in
   geomspace(1e-3, 0.1, 256). Warm wall time of the bare kernel
   `attractor_rows_parallel` on 2 numba threads at the default tolerance (auto = dopri5,
   tol = 1e-8) and a ladder of tolerances; points/s; fraction converged and regimes;
   thread scaling (`numba.set_num_threads(1)` vs 2); `sweepcore.sweep` on its direct
   path and on dask (threads, processes, a 2-worker `LocalCluster` on 127.0.0.1)
   against the bare kernel; cold compile (fresh process, empty `NUMBA_CACHE_DIR`) and
   warm-cache load; peak memory = peak resident set size (VmHWM of /proc/self/status)
   of a fresh process, so it includes the interpreter, numpy, numba and LLVM
   (`getrusage` `ru_maxrss` is not used: on Linux it carries the parent's peak across
   fork and exec).
   Error: a seeded random subsample of the map recomputed with dopri5 at tol = 1e-12
   (the reference), cross-checked by rk4 at dt = 1e-3, and on a few points per regime
   by an independent scipy DOP853 event-driven solver (`peers.scipy_attractor`, written
   from the physics, no sweepcore code). Errors are taken where both runs converged to
   the same regime; regime disagreements are counted apart.
2. **Work-precision** (`work_precision.py`): error against time per point (serial kernel,
   one core) for every method and a ladder of settings (dt for gps and rk4, tol for
   dopri5): (a) constant friction, alpha1 = alpha2 = 0, start stuck, where the attractor
   is exact (amplitude v/omega, mean r_y/k, period 2 pi/omega); (b) alpha2 > 0 on
   16 test points (v in {0.5, 2, 5, 10} x alpha2 in {0.002, 0.01, 0.05, 0.1}) plus
   random map points stratified by regime
   (stick-slip, slip cycle, equilibrium), against dopri5 at tol = 1e-13 (cross-checked by
   scipy DOP853); (c) the Hopf boundary along v at alpha2 = 0.01 as a map sees it (the
   midpoint between the largest v with a cycle and the next larger v at equilibrium,
   `sweepcore.boundary`'s definition), located by bisection for each setting.
3. **Throughput** (`throughput.py`): points/s against grid size, ~1e2 to 1e6 points
   (1e5 in `--quick`), square grids over the same (v, alpha2) box.
4. **Peers** (`peer_compare.py`, solvers in `peers.py`), rerun here on the same points:
   scipy `solve_ivp` RK45 looped over points with terminal events at zdot = 0 and
   restarts (stick phase in closed form), and a hand-written numba RK4 at a fixed step
   (events located by Illinois on the step's polynomial, prange), the fastest peer we
   wrote. They solve a fixed-horizon protocol (to t = 200 s, amplitude from samples
   on [150, 200]); their error is measured against the same protocol solved by scipy
   DOP853 at a tight tolerance, with "events right" = same number of events. Points:
   17 (the 4 x 4 test points plus v = 5, alpha2 = 1/75 at v*), starting stuck like
   the map.
5. **Cost model** (`cost_model.py`): flops per dopri5 stepper call counted from the
   source with `ast` (every + - * / is one flop, a square root one, negation, abs,
   max, min none; the RHS zdd = 10 flops: friction law (40) 7, eq. (41) 3; 7 stages),
   times the stepper calls the kernel reports (`OB_NSTEPS`, column 10) over the map,
   divided by the map's wall time; against a peak of cores x clock (from
   /proc/cpuinfo) x 16 flops/cycle (AVX2: two 256-bit FMA pipes x 4 doubles x 2) or
   x 4 flops/cycle (scalar FMA code). The driver's own work per step (event scan,
   bookkeeping) is not counted: the achieved rate is a lower bound.

Every peer figure is measured on this machine, in the same run (section 4).
"""


def write_readme(outdir, readme, mode, total):
    outdir = Path(outdir)
    readme = Path(readme)
    rel = os.path.relpath(outdir, readme.parent)
    H = _load(outdir, "hopf_map")
    W = _load(outdir, "work_precision")
    T = _load(outdir, "throughput")
    Pe = _load(outdir, "peers")
    C = _load(outdir, "cost_model")
    anyres = next((r for r in (H, W, T, Pe, C) if r), None)
    parts = [STATIC_HEAD]
    if anyres is None:
        readme.write_text("\n".join(parts))
        return
    m = anyres["machine"]
    sections = {n: r for n, r in zip(("hopf_map", "work_precision", "throughput", "peers",
                                      "cost_model"), (H, W, T, Pe, C)) if r}
    stamps = {(r["machine"]["git_commit"], r["machine"]["sweepcore_dirty"])
              for r in sections.values()}
    mixed = ""
    if len(stamps) > 1:
        mixed = ("\n**The sections come from different code states:** " + "; ".join(
            f"{n}: `{r['machine']['git_commit'][:10]}`"
            f"{' + uncommitted changes' if r['machine']['sweepcore_dirty'] else ''}"
            f" ({r['machine']['date']})" for n, r in sections.items()) + ".\n")
    parts.append(f"""## Results ({mode} mode)

Run {m['date']} (sections took {sum(r.get('section_seconds', 0) for r in (H, W, T, Pe, C) if r) / 60:.1f} min) on {m['cpu_model']} ({m['cpu_mhz']:.0f} MHz, {m['cores']} cores,
SIMD {', '.join(m['simd'])}, {m['memory_gib']} GiB), Python {m['python']}, numpy
{m['numpy']}, numba {m['numba']} (threading layer `{m['numba_threading_layer']}`),
scipy {m['scipy']}, dask {m['dask']}; commit `{m['git_commit']}`
{'with uncommitted changes under sweepcore/' if m['sweepcore_dirty'] else '(clean sweepcore/)'}.
Files: `{rel}/`.
{mixed}""")
    if H:
        parts.append(_hopf(H, Pe, rel))
    if W:
        parts.append(_wp(W, Pe, rel))
    if T:
        parts.append(_tp(T, rel))
    if Pe:
        parts.append(_peers(Pe, H))
    if C:
        parts.append(_cost(C))
    from benchmarks import boundaries, memory     # their own scripts' results
    parts.append(boundaries.stored_section())
    parts.append(memory.stored_section())
    readme.write_text("\n".join(parts))


def _hopf(H, Pe, rel):
    hd = H["headline"]
    n = H["grid"]["n_points"]
    acc = H["accuracy"]
    out = [f"### 1. Hopf map ({H['grid']['nv']} x {H['grid']['na']} = {n} points)\n",
           f"![Hopf map]({rel}/hopf_map.png)\n"]
    rows = []
    for k in H["kernel"]:
        a = acc["map"].get(f"{k['tol']:g}", {})
        same = f"{k['tol']:g}" == acc["reference"].split("tol=")[-1]
        rows.append([f"auto (dopri5) tol={k['tol']:g}" + (" (= the reference: error 0 by "
                                                          "construction)" if same else ""),
                     s(k["median_s"]), g(k["points_per_s"]),
                     f"{100 * k['converged_fraction']:.3f} %",
                     g(a.get("amplitude_abs", {}).get("max")),
                     g(a.get("amplitude_rel_cycle", {}).get("max")),
                     g(a.get("mean_abs", {}).get("max")),
                     a.get("n_regime_mismatch", "-"), g(k["steps_per_point_mean"])])
    out.append(f"Bare kernel, 2 numba threads, warm, median of repeats. Errors: max over the "
               f"{acc['n_subsample']} subsample points where map and reference "
               f"({acc['reference']}) converged to the same regime.\n")
    out.append(table(["setting", "wall time", "points/s", "converged", "max abs amp err [cm]",
                      "max rel amp err (cycles)", "max abs mean err [cm]",
                      "regime mismatches", "steps/point"], rows))
    ok = [k for k in H["kernel"] if f"{k['tol']:g}" != acc["reference"].split("tol=")[-1]
          and (acc["map"].get(f"{k['tol']:g}", {}).get("amplitude_abs", {}).get("max")
               or 1.0) <= 1e-6 and acc["map"][f"{k['tol']:g}"]["n_regime_mismatch"] == 0]
    best = None
    if ok:
        best = min(ok, key=lambda k: k["median_s"])
        out.append(f"\n**Cheapest tolerance of the ladder with amplitude error <= 1e-6 cm on the "
                   f"subsample: tol = {best['tol']:g}, {s(best['median_s'])} for the map** "
                   f"(target <= 10 s, aim <= 1 s). The default tol = 1e-8 "
                   f"({s(hd['median_s'])}) has max error "
                   f"{g(acc['map'].get('1e-08', {}).get('amplitude_abs', {}).get('max'))} cm.\n")
    hard = H.get("accuracy_hardest")
    if hard:
        out.append(f"\n**The hardest points.** A random subsample is mostly easy points. "
                   f"In every alpha2 column, the {hard['per_column']} slip cycles nearest "
                   f"below v* ({hard['n_points']} points, where the cycle's contraction "
                   f"per period is weakest) against independent references: scipy DOP853 "
                   f"shooting at rtol 1e-13 (secant on the return map; "
                   f"tests/reference.py), or the Hopf normal form with its measured "
                   f"second-order term where the shooting's own noise exceeds 1e-9 L "
                   f"(sources: " + ", ".join(f"{v} {k}" for k, v in
                                             sorted(hard["reference_sources"].items()))
                   + f"; {hard['reference_unresolved']} without a resolved reference, "
                   f"left out):\n")
        hrows = []
        for tol, h in hard["by_tol"].items():
            bands = "; ".join(f"{k}: {g(v['max_amp_err'])} ({v['n']})"
                              for k, v in h["bands"].items())
            hrows.append([f"tol={tol}", ", ".join(f"{v} {k}" for k, v in
                                                  sorted(h["status_counts"].items())),
                          h["n_compared"], g(h["max_amp_err"]), g(h["max_amp_err_over_L"]),
                          bands, h["above_v_star_not_equilibrium"]])
        out.append(table(["setting", "statuses", "compared", "max abs amp err [cm]",
                          "max err / L", "by v / v* (max err, points)",
                          "points above v* not at rest"], hrows))
    reg = hd["regimes"]
    out.append(f"\nRegimes at tol = 1e-8: " + ", ".join(f"{k} {v} ({100 * v / n:.1f} %)"
                                                      for k, v in reg.items()) + ".\n")
    rk = acc["rk4_dt1e-3_vs_reference"]
    out.append(f"Reference cross-checks: rk4 dt = 1e-3 vs the reference, max |amp| diff "
               f"{g(rk['amplitude_abs']['max'])} cm ({rk['n_regime_mismatch']} regime "
               f"mismatches); independent scipy DOP853 (1e-12) on "
               f"{len(acc['scipy_dop853_check'])} points, max |amp| diff "
               f"{g(acc['scipy_check_max_amp_diff'])} cm, max |mean| diff "
               f"{g(acc.get('scipy_check_max_mean_diff'))} cm, regimes agree: "
               f"{acc['scipy_check_regimes_agree']}.\n")
    # targets side by side
    e8 = acc["map"].get("1e-08", {}).get("amplitude_abs", {}).get("max")
    trows = [[f"**sweepcore kernel, default tol 1e-8 (measured; max amp err {g(e8)} cm)**",
              f"**{s(hd['median_s'])}**", g(hd["points_per_s"])]]
    if best is not None and best["tol"] != 1e-8:
        eb = acc["map"][f"{best['tol']:g}"]["amplitude_abs"]["max"]
        trows.append([f"**sweepcore kernel, tol {best['tol']:g} (measured; max amp err "
                      f"{g(eb)} cm)**", f"**{s(best['median_s'])}**", g(best["points_per_s"])])
    if Pe and "numba_peer_map" in Pe:
        pm = Pe["numba_peer_map"]
        trows.append([f"numba RK4 peer dt = 0.01, rerun here ({pm['measured_or_extrapolated']})",
                      s(pm["map_seconds"]), g(n / pm["map_seconds"])])
    if Pe and "ratios" in Pe and "scipy_map_hours_2cores_ideal" in Pe["ratios"]:
        r = Pe["ratios"]
        trows.append([f"scipy RK45 loop {r['scipy_setting']}, rerun here (per-point time x "
                      f"points / 2 cores)", f"{r['scipy_map_hours_2cores_ideal']:.2g} h",
                      g(r["map_points_per_s_scipy_2cores_ideal"])])
    trows += [["target (first step)", "<= 10 s", g(n / 10)], ["aim", "<= 1 s", g(n / 1)]]
    out.append("Side by side with the targets:\n")
    out.append(table(["", "map wall time", "points/s"], trows))
    th = H["threads"]
    out.append("\nThread scaling (same kernel, `numba.set_num_threads`, runs interleaved; "
               "speedup = median of paired ratios):\n")
    out.append(table(["row order", "threads", "wall time", "speedup", "efficiency"],
                     [[order, k, s(v["median_s"]), g(v["speedup"]), g(v["efficiency"])]
                      for order in ("grid order", "shuffled rows") if order in th
                      for k, v in th[order].items()]))
    if "shuffled rows" in th and "2" in th["shuffled rows"] and "2" in th.get("grid order", {}):
        out.append(f"\nThe same rows in a random order scale by "
                   f"{g(th['shuffled rows']['2']['speedup'])} against "
                   f"{g(th['grid order']['2']['speedup'])} in grid order: the difference is "
                   "what the kernel's split of the rows between threads loses to the "
                   "clustered cost of the map (slip cycles near v* cost several times a "
                   "stick-slip point).")
    d = H.get("dask", {})
    if d.get("runs"):
        out.append(f"\n`sweepcore.sweep` and dask against the bare kernel "
                   f"({s(d['kernel_median_s'])}); sweep's output equals the kernel's bit for "
                   f"bit: {d.get('sweep_matches_kernel')}.\n")
        out.append(table(["executor", "chunks (points)", "wall time", "overhead vs kernel",
                          "points/s"],
                         [[r["executor"], r["chunks"], s(r["median_s"]),
                           f"{100 * r['overhead_vs_kernel']:+.0f} %", g(r["points_per_s"])]
                          for r in d["runs"]]))
        out.append("\nOverhead = median over pairs of (executor time / kernel time measured just "
                   "before it) - 1. A negative overhead means the executor split the work "
                   "more evenly between the cores than the bare kernel does on this grid "
                   "(see the thread scaling above): dask's threads take chunks as they "
                   "free up. `dask processes` starts a new process pool on every "
                   "call (dask's multiprocessing scheduler), each process importing "
                   "sweepcore and loading the kernels from numba's cache: that start-up is "
                   "part of its time. The LocalCluster's workers persist (warmed up once, "
                   "`NUMBA_NUM_THREADS=1` via `LocalCluster(env=...)`).")
        cl = [r for r in d["runs"] if "cluster_startup_s" in r]
        if cl:
            out.append(f"\nLocalCluster start-up (not in the times above): "
                       f"{s(cl[0]['cluster_startup_s'])}.")
    c = H.get("compile")
    if c and "cold" in c and "error" not in c["cold"]:
        cold, warm = c["cold"], c.get("warm_cache", {})
        out.append("\nCompilation and memory (fresh processes):\n")
        rows = [["cold (empty NUMBA_CACHE_DIR)", s(cold["t_import_kernels"]),
                 s(cold["t_first_call_parallel"]), s(cold["t_first_call_serial"]),
                 f"{cold['rss_after_first_call_mib']:.0f} MiB"]]
        if "t_first_call_parallel" in warm:
            rows.append(["warm cache", s(warm["t_import_kernels"]),
                         s(warm["t_first_call_parallel"]), s(warm["t_first_call_serial"]),
                         f"{warm['rss_after_first_call_mib']:.0f} MiB"])
        out.append(table(["", "import kernels", "first call, parallel kernel",
                          "then first call, serial kernel", "peak RSS after"], rows))
        if "rss_after_map_mib" in warm:
            out.append(f"\nPeak resident memory (VmHWM) of a fresh warm-cache process: "
                       f"{warm['rss_after_import_mib']:.0f} MiB after imports, "
                       f"{warm['rss_after_first_call_mib']:.0f} MiB after loading the kernels, "
                       f"{warm['rss_after_map_mib']:.0f} MiB after the whole map through the "
                       f"kernel (its arrays: {warm['map_arrays_mib']:.1f} MiB)"
                       + (f", {warm['rss_after_sweep_mib']:.0f} MiB after `sweep()` of the "
                          f"map (xarray Dataset)" if "rss_after_sweep_mib" in warm else "")
                       + f". Map in that process: {s(warm['t_map'])}.\n")
    return "\n".join(out) + "\n"


def _wp(W, Pe, rel):
    out = [f"### 2. Work-precision\n", f"![work-precision]({rel}/work_precision.png)\n"]
    br = W["boundary_reference"]
    ref = W["reference"]
    out.append(f"Points: {W['points']['constant_friction']} constant-friction points; "
               f"{W['points']['alpha2']} alpha2 > 0 points ({W['points']['test_points']} test "
               f"points + stratified map points), reference "
               f"{ref['setting']} (regimes {ref['regimes']}), cross-checked by scipy DOP853 on "
               f"{len(ref['scipy_dop853_check'])} points: max |amp| diff "
               f"{g(ref['scipy_check_max_amp_diff'])} cm, regimes agree "
               f"{ref['scipy_check_regimes_agree']}. Hopf boundary at alpha2 = 0.01, reference: "
               f"cycle up to v = {br['v_cycle_end']:.6f}, equilibrium from "
               f"v = {br['v_eq_start']:.6f} (analytic v* = {br['v_star']:.6f}; between the two, "
               f"points the budget leaves unconverged). Time per point: {W['timing']}.\n")
    rows = []
    for r in W["settings"]:
        c = r["const"]
        a = r.get("alpha2")
        t = r.get("test_points")
        b = r.get("boundary")
        rows.append([r["label"], s(c["s_per_point"]), f"{c['n_converged']}/{c['n']}",
                     g(c["amplitude_abs_max"]),
                     g(c["mean_abs_max"]), g(c["period_abs_max"]),
                     s(a["s_per_point"]) if a else "n/a",
                     g(a["amplitude_abs"]["max"]) if a else "n/a",
                     g(a["mean_abs"]["max"]) if a else "n/a",
                     g(a["period_abs"]["max"]) if a else "n/a",
                     f"{a['n_regime_mismatch']}/{a['n'] - a['n_converged']}" if a else "n/a",
                     g(t["amplitude_abs"]["max"]) if t else "n/a",
                     (f"{b['v_cycle_end']:.5f} / {b['v_eq_start']:.5f} "
                      f"({g(b.get('error_eq_onset'))})" if b and b["v_eq_start"] is not None
                      and math.isfinite(b["v_eq_start"]) else "n/a")])
    out.append(table(["setting", "const: time/pt", "converged", "amp err", "mean err",
                      "period err", "alpha2>0: time/pt", "amp err", "mean err",
                      "period err (cycles)", "regime mismatch / unconverged",
                      "test points amp err",
                      "last cycle / first equilibrium v (eq. onset err)"], rows))
    out.append("\nErrors are maxima of absolute errors [cm, s, cm/s] over the points where "
               "the setting and the reference converged to the same regime.\n")
    return "\n".join(out) + "\n"


def _tp(T, rel):
    out = ["### 3. Throughput against grid size\n", f"![throughput]({rel}/throughput.png)\n"]
    rows = [[f"{r['n_points']:,}", s(r["kernel_median_s"]), g(r["kernel_points_per_s"]),
             s(r.get("sweep_median_s")), g(r.get("sweep_points_per_s")),
             g(r["steps_per_point"]), f"{100 * r['converged_fraction']:.2f} %"]
            for r in T["runs"]]
    out.append(table(["points", "kernel time", "kernel points/s", "sweep() time",
                      "sweep() points/s", "steps/point", "converged"], rows))
    return "\n".join(out) + "\n"


def _peers(Pe, H):
    out = ["### 4. Peers, rerun in the same run\n"]
    pr = Pe["protocol_reference"]
    rows = []
    for name, pts in Pe["work_precision"].items():
        for p in pts:
            rows.append([name, p["setting"], s(p["s_per_point"]), g(p["points_per_s"]),
                         g(p["amp_err_max"]), f"{p['events_right']}/{p['n']}"])
    sc = Pe["sweepcore_same_points"]
    rows.append(["**sweepcore** (attractor, own reference)", sc["setting"],
                 s(sc["s_per_point"]) + f" ({s(sc['s_per_point_without_v_star_point'])} "
                 "without the point at v*)",
                 g(1.0 / sc["s_per_point"]), g(sc["amplitude_abs"]["max"]),
                 f"{sc['n_compared']}/{sc['n']} compared"])
    out.append(f"{len(Pe['points'])} points, one core each; peers' error against "
               f"{pr['solver']} on the same protocol ({s(pr['s_per_point'])}/point).\n")
    out.append(table(["solver", "setting", "time/point (1 core)", "points/s (1 core)",
                      "max abs amp err [cm]", "events right"], rows))
    st = sc.get("status")
    if st:
        out.append(f"\nsweepcore's regimes on these points: {', '.join(st)}.")
    out.append(f"\nThe protocol's own answer differs from the attractor's by up to "
               f"{g(Pe['protocol_vs_attractor_amp_max'])} cm on the converged points "
               "(sampling x every 0.01 s misses the true extremum, and near v* the window "
               "[150, 200] is still transient).\n")
    r = Pe["ratios"]
    pm = Pe["numba_peer_map"]
    rows = [["scipy RK45 loop, per point, 1 core each (same points)", r["scipy_setting"],
             g(r["per_point_1core_ratio"]) + "x"]]
    if "map_ratio_sweepcore_over_scipy" in r:
        rows.append(["map: sweepcore points/s (2 threads) / scipy points/s on 2 cores "
                     "(1-core rate x 2)", r["scipy_setting"],
                     f"**{g(r['map_ratio_sweepcore_over_scipy'])}x** (target >= 1000x)"])
        rows.append([f"map: numba RK4 peer dt = 0.01 on 2 threads ({pm['measured_or_extrapolated']},"
                     f" {s(pm['map_seconds'])}) / sweepcore", "dt = 0.01",
                     g(r["map_ratio_sweepcore_over_numba_peer"]) + "x"])
        out.append(f"Errors at these settings: sweepcore map {g(r['sweepcore_map_amp_err_max'])} "
                   f"cm (max on the subsample, against its attractor reference); scipy loop "
                   f"{g(r['scipy_amp_err_max'])} cm (against its protocol reference).\n")
    # matched error: the cheapest map tolerance whose error is <= the peer's
    if H and "accuracy" in H:
        ref_tol = H["accuracy"]["reference"].split("tol=")[-1]
        n = H["grid"]["n_points"]
        for peer in Pe["work_precision"]["scipy RK45 loop"]:
            cand = [k for k in H["kernel"] if f"{k['tol']:g}" != ref_tol
                    and H["accuracy"]["map"][f"{k['tol']:g}"]["n_regime_mismatch"] == 0
                    and (H["accuracy"]["map"][f"{k['tol']:g}"]["amplitude_abs"]["max"]
                         or 0.0) <= peer["amp_err_max"]]
            if not cand:
                rows.append([f"map at matched error vs scipy RK45 {peer['setting']} "
                             f"(err {g(peer['amp_err_max'])})", peer["setting"],
                             "no map tolerance of the ladder is as accurate"])
                continue
            k = min(cand, key=lambda c: c["median_s"])
            e = H["accuracy"]["map"][f"{k['tol']:g}"]["amplitude_abs"]["max"]
            ratio = (n / k["median_s"]) * peer["s_per_point"] / 2.0
            rows.append([f"**map at matched or better error**: sweepcore tol {k['tol']:g} "
                         f"(err {g(e)} cm, {s(k['median_s'])}) vs scipy RK45 loop "
                         f"(err {g(peer['amp_err_max'])} cm, 1-core rate x 2)",
                         peer["setting"], f"**{g(ratio)}x** (target >= 1000x)"])
    out.append(table(["ratio", "peer setting", "sweepcore faster by"], rows))
    out.append("\nThe two errors are each against their own tight reference: the peers' "
               "against the fixed-horizon protocol solved by DOP853, sweepcore's against "
               "the attractor solved by dopri5 at tol 1e-12 on the map's random subsample "
               "(section 1).\n")
    return "\n".join(out) + "\n"


def _cost(C):
    m = C["map"]
    fc = C["flop_counts"]
    out = ["### 5. Cost model\n"]
    rows = [[k, v["flops"], v["sqrt"], v["skipped_flops"], v["other"],
             ", ".join(v.get("expanded", []))] for k, v in fc.items()]
    out.append(table(["function (one call)", "+ - * / flops", "sqrt", "flops in `if want_q:` "
                      "(accepted steps only)", "abs/max/min (not counted)",
                      "calls expanded"], rows))
    one = ""
    if m.get("ns_per_call_one_thread"):
        one = (f" On one thread (no core idle at the end of an uneven split): "
               f"**{m['ns_per_call_one_thread']:.0f} ns per call** "
               f"(~{m['cycles_per_call_one_thread']:.0f} cycles), "
               f"{g(m['achieved_gflops_one_core_high'])} GFLOP/s of a one-core scalar peak "
               f"of {g(C['peak_gflops_scalar_fma'] / C['cores'])}.")
    out.append(f"""
Map at tol = 1e-8: {m['stepper_calls']:.3g} stepper calls in {s(m['wall_s'])} on
{C['cores']} threads = {m['ns_per_call_per_core']:.0f} ns per call per core
(~{m['cycles_per_call']:.0f} cycles at {C['clock_ghz']:.2f} GHz for
{C['dopri5_flops_per_call']}-{C['dopri5_flops_per_call_with_quadratures']} counted flops).{one}
Achieved on the map {g(m['achieved_gflops_low'])}-{g(m['achieved_gflops_high'])} GFLOP/s against a
peak of {g(C['peak_gflops_scalar_fma'])} GFLOP/s for scalar FMA code (4 flops/cycle/core)
and {g(C['peak_gflops_avx2_fma'])} GFLOP/s for AVX2 FMA (16 flops/cycle/core): **{100 *
m['fraction_of_scalar_peak']:.1f} % of the scalar peak, {100 * m['fraction_of_avx2_peak']:.2f} %
of the vector peak**.""")
    if "numba_peer" in C:
        p = C["numba_peer"]
        out.append(f"""The numba RK4 peer (fixed step, {p['flops_per_step']} flops per step, no
adaptivity) runs at {p['ns_per_step_per_core']:.1f} ns per step per core, {g(p['achieved_gflops'])}
GFLOP/s ({100 * p['fraction_of_scalar_peak']:.1f} % of the scalar peak).""")
    out.append("""
Reading: one point per thread, and inside a point a chain of dependent scalar
operations (each stage needs the previous one), so the ceiling that matters is the
scalar, latency-bound one, not the SIMD peak. The count leaves out the driver's
per-step work (zdot = 0 scan on the step's Hermite cubic, extremum and event
polishing, accumulators, the step-size controller's power): the achieved rate is a
lower bound, and the gap to the scalar peak is partly that uncounted work, partly the
latency of the dependent chain. The fixed-step peer (no controller, a one-line event
test) spends fewer cycles per step for a similar flop rate. (Not profiled here: a
per-function profile would be the next step to split the cycles.)
""")
    return "\n".join(out) + "\n"


# ------------------------------------------------ the top-level README's block
START, END = "<!-- bench:start -->", "<!-- bench:end -->"


def _study_tol(study=common.ROOT / "studies" / "hopf_map.toml") -> float:
    """The tolerance of the main job (studies/hopf_map.toml, [solver] tol)."""
    try:
        import tomllib
    except ImportError:     # Python 3.10
        import tomli as tomllib
    solver = tomllib.loads(Path(study).read_text()).get("solver", {})
    from sweepcore.options import make_options
    import inspect
    default = inspect.signature(make_options).parameters["tol"].default
    return float(solver.get("tol", default))


def readme_block(outdir) -> str:
    """The speed section of the top-level README, from the JSON in ``outdir``.

    Every figure is read from a file named in the block; the block says which run
    (date, machine, commit) produced them.
    """
    outdir = Path(outdir)
    rel = os.path.relpath(outdir, common.ROOT)
    H, Pe = _load(outdir, "hopf_map"), _load(outdir, "peers")
    if H is None:
        return (f"No benchmark results in `{rel}/` yet: run `python benchmarks/run.py`.")
    m, n = H["machine"], H["grid"]["n_points"]
    acc = H["accuracy"]["map"]
    kernel = {f"{k['tol']:g}": k for k in H["kernel"]}

    def map_row(tol, what):
        k, a = kernel.get(f"{tol:g}"), acc.get(f"{tol:g}", {})
        if k is None:
            return []
        err = a.get("amplitude_abs", {}).get("max")
        ref = H["accuracy"]
        row = [[what, f"{s(k['median_s'])}; max amplitude error {g(err)} cm "
                      f"({ref['n_subsample']} random points against {ref['reference']})"]]
        hard = H.get("accuracy_hardest", {})
        h = hard.get("by_tol", {}).get(f"{tol:g}")
        if h:
            statuses = ", ".join(f"{v} {k}" for k, v in sorted(h["status_counts"].items()))
            row.append([f"same run, the {hard['n_points']} slip cycles nearest below v* "
                        f"({hard['per_column']} per alpha2 column)",
                        f"max amplitude error {g(h['max_amp_err'])} cm on the "
                        f"{h['n_compared']} with an independent reference (scipy shooting "
                        f"at rtol 1e-13, or the normal form next to v*); statuses: "
                        f"{statuses}; points above v* not at rest: "
                        f"{h['above_v_star_not_equilibrium']}"])
        return row

    tol = _study_tol()
    rows = map_row(tol, f"{H['grid']['nv']} x {H['grid']['na']} Hopf map at tol {tol:g} "
                        "(the main job's tolerance), bare kernel, warm")
    if f"{tol:g}" != "1e-08":
        rows += map_row(1e-8, "same map at the default tol 1e-8")
    sweep_runs = [r for r in H.get("dask", {}).get("runs", [])
                  if r["executor"].startswith("sweep")]
    if sweep_runs:
        rows.append(["`sweepcore.sweep` of the map at tol 1e-8 (Dataset, boundary)",
                     s(sweep_runs[0]["median_s"])])
    if Pe and "numba_peer_map" in Pe:
        pm = Pe["numba_peer_map"]
        rows.append([f"numba RK4 peer, dt = {pm['dt']:g} s, same map, rerun in the same "
                     f"run ({pm['measured_or_extrapolated']})", s(pm["map_seconds"])])
    if Pe and "ratios" in Pe:
        r = Pe["ratios"]
        rows.append([f"scipy `solve_ivp` RK45 loop ({r['scipy_setting']}), per point on "
                     f"one core, {len(Pe['points'])} points", f"{g(r['per_point_1core_ratio'])}x "
                     "the time of sweepcore on the same points"])
    th = H.get("threads", {})
    if "2" in th.get("grid order", {}):
        rows.append(["thread scaling 1 -> 2 threads", f"{g(th['grid order']['2']['speedup'])}x "
                     "in grid order" + (f", {g(th['shuffled rows']['2']['speedup'])}x on "
                                        "shuffled rows" if "2" in th.get("shuffled rows", {})
                                        else "")])
    c = H.get("compile", {})
    if "t_first_call_parallel" in c.get("cold", {}):
        rows.append(["kernel compilation (first call in a fresh process)",
                     f"{s(c['cold']['t_first_call_parallel'])} with an empty cache, "
                     f"{s(c.get('warm_cache', {}).get('t_first_call_parallel'))} from the cache"])
    head = (f"Measured by `python benchmarks/run.py` (full mode) on {m['date'][:10]}, "
            f"{m['cpu_model']}, {m['cores']} cores, commit `{m['git_commit'][:10]}`; every "
            f"figure below is read from `{rel}/hopf_map.json` and `{rel}/peers.json` "
            "(this block is generated: `python -m benchmarks.report`). Tables, plots and "
            "the method: [benchmarks/README.md](benchmarks/README.md).")
    return head + "\n\n" + table(["", "measured"], rows)


def update_block(readme, block: str) -> bool:
    """Replace the text between the bench markers of ``readme``; False if absent."""
    readme = Path(readme)
    text = readme.read_text()
    if START not in text or END not in text:
        return False
    before, rest = text.split(START, 1)
    after = rest.split(END, 1)[1]
    readme.write_text(f"{before}{START}\n{block}\n{END}{after}")
    return True


def main(argv=None):
    import argparse
    ap = argparse.ArgumentParser(description="Regenerate benchmarks/README.md and the "
                                 "top-level README's speed block from saved results.")
    ap.add_argument("--outdir", type=Path, default=common.RESULTS / "full")
    args = ap.parse_args(argv)
    write_readme(args.outdir, common.BENCH / "README.md", "full", None)
    if not update_block(common.ROOT / "README.md", readme_block(args.outdir)):
        raise SystemExit("README.md has no <!-- bench:start --> ... <!-- bench:end --> block")
    print(f"wrote {common.BENCH / 'README.md'} and the speed block of "
          f"{common.ROOT / 'README.md'} from {args.outdir}")


if __name__ == "__main__":
    main()
