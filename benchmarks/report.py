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
import re
from pathlib import Path
from string import Template

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
    if x >= 600:
        return f"{x / 60:.3g} min"
    return f"{x:.3g} s"


def table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


TEMPLATES = Path(__file__).with_name("report_templates.md")
_MARKER = re.compile(r"^<!-- (?:block (\w+)|end) -->\n", re.M)


def templates(path=TEMPLATES) -> dict[str, Template]:
    """The blocks of ``report_templates.md``: ``{name: string.Template}``. A block
    runs from its marker to the line before the next one (that line's newline is
    the marker's, so a blank line before it ends the block with a newline)."""
    parts = _MARKER.split(Path(path).read_text())
    return {parts[i]: Template(parts[i + 1].removesuffix("\n"))
            for i in range(1, len(parts) - 1, 2) if parts[i]}


def fill(name: str, **values) -> str:
    """Template block ``name`` with ``values`` substituted (all must be given)."""
    return templates()[name].substitute(values)


def write_readme(outdir, readme, mode, total):
    outdir = Path(outdir)
    readme = Path(readme)
    rel = os.path.relpath(outdir, readme.parent)
    H = _load(outdir, "hopf_map")
    W = _load(outdir, "work_precision")
    T = _load(outdir, "throughput")
    Pe = _load(outdir, "peers")
    C = _load(outdir, "cost_model")
    Hy = _load(outdir, "heyoka")
    Pb = _load(outdir, "pybasin")
    La = _load(outdir, "laws")
    anyres = next((r for r in (H, W, T, Pe, C, Hy, Pb, La) if r), None)
    parts = [fill("head")]
    if anyres is None:
        readme.write_text("\n".join(parts))
        return
    m = anyres["machine"]
    sections = {n: r for n, r in zip(("hopf_map", "work_precision", "throughput", "peers",
                                      "cost_model", "heyoka", "pybasin", "laws"),
                                     (H, W, T, Pe, C, Hy, Pb, La)) if r}
    stamps = {(r["machine"]["git_commit"], r["machine"]["sweepcore_dirty"])
              for r in sections.values()}
    mixed = ""
    if len(stamps) > 1:
        mixed = fill("mixed", states="; ".join(
            f"{n}: `{r['machine']['git_commit'][:10]}`"
            f"{' + uncommitted changes' if r['machine']['sweepcore_dirty'] else ''}"
            f" ({r['machine']['date']})" for n, r in sections.items()))
    minutes = sum(r.get("section_seconds", 0) for r in sections.values()) / 60
    parts.append(fill(
        "results", mode=mode, date=m["date"], minutes=f"{minutes:.1f}",
        cpu_model=m["cpu_model"], mhz=f"{m['cpu_mhz']:.0f}", cores=m["cores"],
        simd=", ".join(m["simd"]), memory_gib=m["memory_gib"], python=m["python"],
        numpy=m["numpy"], numba=m["numba"], threading_layer=m["numba_threading_layer"],
        scipy=m["scipy"], dask=m["dask"], commit=m["git_commit"],
        dirty=("with uncommitted changes under sweepcore/" if m["sweepcore_dirty"]
               else "(clean sweepcore/)"), rel=rel, mixed=mixed))
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
    if Hy and "skipped" not in Hy:
        parts.append(_heyoka(Hy))
    if Pb:
        parts.append(_pybasin(Pb))
    if La:
        parts.append(_laws(La))
    from benchmarks import (autonomous_identity, boundaries,  # their own scripts' results
                            compile_probe, forced, forced_accuracy, memory)
    parts.append(boundaries.stored_section())
    parts.append(autonomous_identity.stored_section())
    parts.append(forced.stored_section())
    parts.append(forced_accuracy.stored_section())
    parts.append(memory.stored_section())
    parts.append(compile_probe.stored_section())
    readme.write_text("\n".join(parts))


def _hopf(H, Pe, rel):
    hd = H["headline"]
    n = H["grid"]["n_points"]
    acc = H["accuracy"]
    rows = []
    for k in H["kernel"]:
        a = acc["map"].get(f"{k['tol']:g}", {})
        same = f"{k['tol']:g}" == acc["reference"].split("tol=")[-1]
        rows.append([f"{k['method']} tol={k['tol']:g}" + (" (= the reference: error 0 by "
                                                          "construction)" if same else ""),
                     s(k["median_s"]), g(k["points_per_s"]),
                     f"{100 * k['converged_fraction']:.3f} %",
                     g(a.get("amplitude_abs", {}).get("max")),
                     g(a.get("amplitude_rel_cycle", {}).get("max")),
                     g(a.get("mean_abs", {}).get("max")),
                     a.get("n_regime_mismatch", "-"), g(k["steps_per_point_mean"])])
    out = [fill("hopf_head", nv=H["grid"]["nv"], na=H["grid"]["na"], n=n, rel=rel,
                n_subsample=acc["n_subsample"], reference=acc["reference"])]
    out.append(table(["setting", "wall time", "points/s", "converged", "max abs amp err [cm]",
                      "max rel amp err (cycles)", "max abs mean err [cm]",
                      "regime mismatches", "steps/point"], rows))
    ok = [k for k in H["kernel"] if f"{k['tol']:g}" != acc["reference"].split("tol=")[-1]
          and (acc["map"].get(f"{k['tol']:g}", {}).get("amplitude_abs", {}).get("max")
               or 1.0) <= 1e-6 and acc["map"][f"{k['tol']:g}"]["n_regime_mismatch"] == 0]
    best = None
    if ok:
        best = min(ok, key=lambda k: k["median_s"])
        out.append(fill("hopf_best", tol=f"{best['tol']:g}", time=s(best["median_s"]),
                        default_time=s(hd["median_s"]), default_error=g(
                            acc["map"].get("1e-08", {}).get("amplitude_abs", {}).get("max"))))
    hard = H.get("accuracy_hardest")
    if hard:
        out.append(fill("hopf_hardest", per_column=hard["per_column"],
                        n_points=hard["n_points"], unresolved=hard["reference_unresolved"],
                        sources=", ".join(f"{v} {k}" for k, v in
                                          sorted(hard["reference_sources"].items()))))
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
    out += _regimes(H.get("regimes"))
    rk = acc["rk4_dt1e-3_vs_reference"]
    out.append(fill(
        "hopf_checks", regimes=", ".join(f"{k} {v} ({100 * v / n:.1f} %)"
                                         for k, v in hd["regimes"].items()),
        rk4_diff=g(rk["amplitude_abs"]["max"]), rk4_mismatches=rk["n_regime_mismatch"],
        n_scipy=len(acc["scipy_dop853_check"]), scipy_amp=g(acc["scipy_check_max_amp_diff"]),
        scipy_mean=g(acc.get("scipy_check_max_mean_diff")),
        scipy_agree=acc["scipy_check_regimes_agree"]))
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
    out.append(table(["", "map wall time", "points/s"], trows))
    th = H["threads"]
    out.append(fill("hopf_threads"))
    out.append(table(["row order", "threads", "wall time", "speedup", "efficiency"],
                     [[order, k, s(v["median_s"]), g(v["speedup"]), g(v["efficiency"])]
                      for order in ("grid order", "shuffled rows") if order in th
                      for k, v in th[order].items()]))
    if "shuffled rows" in th and "2" in th["shuffled rows"] and "2" in th.get("grid order", {}):
        out.append(fill("hopf_shuffled", shuffled=g(th["shuffled rows"]["2"]["speedup"]),
                        grid_order=g(th["grid order"]["2"]["speedup"])))
    d = H.get("dask", {})
    if d.get("runs"):
        out.append(fill("hopf_dask", kernel_time=s(d["kernel_median_s"]),
                        matches=d.get("sweep_matches_kernel")))
        out.append(table(["executor", "chunks (points)", "wall time", "overhead vs kernel",
                          "points/s"],
                         [[r["executor"], r["chunks"], s(r["median_s"]),
                           f"{100 * r['overhead_vs_kernel']:+.0f} %", g(r["points_per_s"])]
                          for r in d["runs"]]))
        out.append(fill("hopf_dask_note"))
        cl = [r for r in d["runs"] if "cluster_startup_s" in r]
        if cl:
            out.append(fill("hopf_cluster", startup=s(cl[0]["cluster_startup_s"])))
    c = H.get("compile")
    if c and "cold" in c and "error" not in c["cold"]:
        cold, warm = c["cold"], c.get("warm_cache", {})
        out.append(fill("hopf_compile"))
        rows = [["cold (empty NUMBA_CACHE_DIR)", s(cold["t_import_kernels"]),
                 s(cold["t_first_call_parallel"]), s(cold["t_first_call_serial"]),
                 f"{cold['rss_after_first_call_mib']:.0f} MiB"]]
        if "t_first_call_parallel" in warm:
            rows.append(["warm cache", s(warm["t_import_kernels"]),
                         s(warm["t_first_call_parallel"]), s(warm["t_first_call_serial"]),
                         f"{warm['rss_after_first_call_mib']:.0f} MiB"])
        out.append(table(["", "import kernels", "first call, parallel kernel",
                          "then first call, serial kernel", "peak RSS after"], rows))
    mj = H.get("main_job")
    if mj and "ratio_wall" in mj:
        out.append(fill("hopf_main_job", ratio=g(mj["ratio_wall"])))
        out.append(table(["`sweepcore run studies/hopf_map.toml`", "wall", "CPU (with the "
                          "second compiler)"],
                         [[label, s(mj[label]["wall_s"]), s(mj[label]["cpu_s"])]
                          for label in ("cold", "warm")]))
        if mj.get("compile_seconds"):
            out.append(fill("hopf_compile_seconds", kernels="; ".join(
                f"{k.replace('/', ', ')} {s(v)}"
                for k, v in sorted(mj["compile_seconds"].items()))))
        if "rss_after_map_mib" in warm:
            after_sweep = fill("hopf_memory_sweep",
                               after_sweep=f"{warm['rss_after_sweep_mib']:.0f}") \
                if "rss_after_sweep_mib" in warm else ""
            out.append(fill("hopf_memory",
                            after_import=f"{warm['rss_after_import_mib']:.0f}",
                            after_kernels=f"{warm['rss_after_first_call_mib']:.0f}",
                            after_map=f"{warm['rss_after_map_mib']:.0f}",
                            map_arrays=f"{warm['map_arrays_mib']:.1f}",
                            after_sweep=after_sweep, map_time=s(warm["t_map"])))
    return "\n".join(out) + "\n"


def _regimes(R):
    """The per-regime step table; before and after when the run probed both."""
    if not R:
        return []
    ba = R.get("before_after", {})
    if "speedup" not in ba:
        cols = {"this run": R["this_run"]}
    else:
        cols = {f"before ({ba['commit_before'][:7]})": ba["before"],
                f"after ({ba['commit_after'][:7]})": ba["after"]}
    header = ["regime"]
    for name in cols:
        header += [f"points, {name}", f"steps a point, {name}", f"share, {name}"]
    rows = []
    for i, r in enumerate(next(iter(cols.values()))["rows"]):
        row = [r["regime"]]
        for t in cols.values():
            c = t["rows"][i]
            row += [c["points"], g(c["steps_mean"]), f"{100 * (c['share'] or 0):.0f} %"]
        rows.append(row)
    rows.append(["all"] + sum(([t["points"], g(t["steps_total"] / t["points"]), "100 %"]
                               for t in cols.values()), []))
    out = [fill("hopf_regimes"), table(header, rows)]
    if "speedup" in ba:
        out.append(fill("hopf_regimes_ba", before=ba["commit_before"][:7],
                        after=ba["commit_after"][:7], rounds=len(ba["round_medians_s"]["before"]),
                        t_before=s(ba["median_s_before"]), t_after=s(ba["median_s_after"]),
                        speedup=g(ba["speedup"]), steps_before=g(ba["before"]["steps_total"]),
                        steps_after=g(ba["after"]["steps_total"]),
                        s_before=s(ba.get("stribeck_map", {}).get("median_s_before")),
                        s_after=s(ba.get("stribeck_map", {}).get("median_s_after")),
                        s_speedup=g(ba.get("stribeck_map", {}).get("speedup")),
                        outputs="; ".join(
                            f"{name} map {o['rows_differing']} of {o['rows']} points "
                            f"differ (largest relative difference "
                            f"{g(o['max_rel_difference'])})"
                            for name, o in ba.get("outputs", {}).items()) or "-"))
    return out


def _wp(W, Pe, rel):
    br = W["boundary_reference"]
    ref = W["reference"]
    out = [fill("wp_head", rel=rel, n_const=W["points"]["constant_friction"],
                n_alpha2=W["points"]["alpha2"], n_test=W["points"]["test_points"],
                reference=ref["setting"], regimes=ref["regimes"],
                n_scipy=len(ref["scipy_dop853_check"]),
                scipy_amp=g(ref["scipy_check_max_amp_diff"]),
                scipy_agree=ref["scipy_check_regimes_agree"],
                v_cycle_end=f"{br['v_cycle_end']:.6f}", v_eq_start=f"{br['v_eq_start']:.6f}",
                v_star=f"{br['v_star']:.6f}", timing=W["timing"])]
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
    out.append(fill("wp_tail"))
    return "\n".join(out) + "\n"


def _tp(T, rel):
    rows = [[f"{r['n_points']:,}", s(r["kernel_median_s"]), g(r["kernel_points_per_s"]),
             s(r.get("sweep_median_s")), g(r.get("sweep_points_per_s")),
             g(r["steps_per_point"]), f"{100 * r['converged_fraction']:.2f} %"]
            for r in T["runs"]]
    return "\n".join([fill("tp_head", rel=rel), table(
        ["points", "kernel time", "kernel points/s", "sweep() time", "sweep() points/s",
         "steps/point", "converged"], rows)]) + "\n"


def _peers(Pe, H):
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
    out = [fill("peers_head", n_points=len(Pe["points"]), solver=pr["solver"],
                time=s(pr["s_per_point"]))]
    out.append(table(["solver", "setting", "time/point (1 core)", "points/s (1 core)",
                      "max abs amp err [cm]", "events right"], rows))
    st = sc.get("status")
    if st:
        out.append(fill("peers_regimes", regimes=", ".join(st)))
    out.append(fill("peers_protocol", diff=g(Pe["protocol_vs_attractor_amp_max"])))
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
        out.append(fill("peers_errors", map_error=g(r["sweepcore_map_amp_err_max"]),
                        scipy_error=g(r["scipy_amp_err_max"])))
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
    out.append(fill("peers_tail"))
    return "\n".join(out) + "\n"


def _cost(C):
    m = C["map"]
    fc = C["flop_counts"]
    rows = [[k, v["flops"], v["sqrt"], v["skipped_flops"], v["other"],
             ", ".join(v.get("expanded", []))] for k, v in fc.items()]
    out = [fill("cost_head"), table(
        ["function (one call)", "+ - * / flops", "sqrt", "flops in `if want_q:` "
         "(accepted steps only)", "abs/max/min (not counted)", "calls expanded"], rows)]
    one = ""
    if m.get("ns_per_call_one_thread"):
        one = fill("cost_one_thread", ns=f"{m['ns_per_call_one_thread']:.0f}",
                   cycles=f"{m['cycles_per_call_one_thread']:.0f}",
                   gflops=g(m["achieved_gflops_one_core_high"]),
                   peak=g(C["peak_gflops_scalar_fma"] / C["cores"]))
    out.append(fill(
        "cost_map", calls=f"{m['stepper_calls']:.3g}", wall=s(m["wall_s"]),
        cores=C["cores"], ns_per_core=f"{m['ns_per_call_per_core']:.0f}",
        cycles=f"{m['cycles_per_call']:.0f}", clock=f"{C['clock_ghz']:.2f}",
        method=C.get("map_stepper", "dopri5"),
        flops=C.get("stepper_flops_per_call", C.get("dopri5_flops_per_call")),
        flops_q=C.get("stepper_flops_per_call_with_quadratures",
                      C.get("dopri5_flops_per_call_with_quadratures")),
        one_thread=one, gflops_low=g(m["achieved_gflops_low"]),
        gflops_high=g(m["achieved_gflops_high"]), peak_scalar=g(C["peak_gflops_scalar_fma"]),
        peak_avx2=g(C["peak_gflops_avx2_fma"]),
        pct_scalar=f"{100 * m['fraction_of_scalar_peak']:.1f}",
        pct_avx2=f"{100 * m['fraction_of_avx2_peak']:.2f}"))
    if "numba_peer" in C:
        p = C["numba_peer"]
        out.append(fill("cost_peer", flops=p["flops_per_step"],
                        ns=f"{p['ns_per_step_per_core']:.1f}", gflops=g(p["achieved_gflops"]),
                        pct=f"{100 * p['fraction_of_scalar_peak']:.1f}"))
    out.append(fill("cost_reading"))
    return "\n".join(out) + "\n"


def _cpu_wall(r):
    return f"{s(r['wall'])} wall, {s(r['cpu'])} CPU"


def _heyoka(Hy):
    hard = Hy["references"]
    last = Hy["ladder"][-1]["errors"]
    out = [fill("heyoka_head", nv=Hy["grid"]["nv"], na=Hy["grid"]["na"],
                version=Hy["heyoka"], processes=Hy["processes"],
                map_converged=hard["map_converged"], hard_resolved=hard["hardest_resolved"],
                no_ref=last["n_without_reference"], date=Hy["machine"]["date"][:16],
                cpu_model=Hy["machine"]["cpu_model"], load=_load_range(Hy))]
    rows = []
    for r in Hy["ladder"]:
        e = r["errors"]
        rows.append([f"tol={r['tol']:g}", s(r["wall_s"]), s(r["cpu_s"]), g(e["amp_err_max_all"]),
                     g(e["amp_err_max"]), f"{e['n_regime_mismatch']} "
                     f"(max amp err {g(e['amp_err_max_regime_mismatch'])})",
                     g(e["hardest"]["max_amp_err"]), e["n_unconverged"], g(r["steps"])])
    mode = Hy["ladder"][0].get("mode", "scalar")
    mode = f"batch ({Hy['batch_size']} lanes)" if mode == "batch" else mode
    out.append(table([f"heyoka, {mode}", "wall time", "CPU time", "max amp err, every point "
                      "[cm]", "same regime", "regime mismatches", "hardest points",
                      "unconverged", "Taylor steps"], rows))
    chosen = next(r for r in Hy["ladder"] if r["tol"] == Hy["chosen_tol"])
    sc = Hy["sweepcore_errors"]
    out.append(fill("heyoka_chosen", tol=f"{Hy['chosen_tol']:g}",
                    note="" if Hy["chosen_meets_target"] else
                    " (none of the ladder meets it: the tightest is shown)",
                    sc_err=g(sc["amp_err_max_all"]), sc_mismatch=sc["n_regime_mismatch"],
                    sc_steps=g(Hy["sweepcore_steps"]), hy_steps=g(chosen["steps"]),
                    top1000=f"{100 * chosen['steps_share_top1000']:.0f} %"))
    med, rat, runs = Hy["median"], Hy["ratios"], Hy["runs"]
    per_point = _events(Hy)
    out.append(fill("heyoka_ratios", tol=f"{Hy['chosen_tol']:g}", n_sc=len(runs["sweepcore"]),
                    n_scalar=len(runs["scalar"]), n_batch=len(runs.get("batch", [])),
                    events=per_point.get("scalar", "?"), events_batch=per_point.get("batch", "?"),
                    faster=min(("scalar", "batch"), key=lambda m: med.get(m, {}).get(
                        "cpu", math.inf)),
                    compile=f"{max(r['compile_s'] for v in runs.values() for r in v if 'compile_s' in r):.2f}"))
    rows = [["sweepcore (kernel, 2 threads, tol 1e-8)", s(med["sweepcore"]["wall"]),
             s(med["sweepcore"]["cpu"]), "1", "1"]]
    for mode, label in (("batch", f"heyoka batch mode ({Hy['batch_size']} lanes)"),
                        ("scalar", "heyoka scalar mode")):
        if mode in med:
            rows.append([f"{label}, {Hy['processes']} processes", s(med[mode]["wall"]),
                         s(med[mode]["cpu"]), f"**{g(rat[mode + '_wall'])}x**",
                         f"**{g(rat[mode + '_cpu'])}x**"])
    out.append(table(["map", "wall time", "CPU time", "wall / sweepcore's",
                      "CPU / sweepcore's"], rows))
    return "\n".join(out) + "\n"


def _pybasin(Pb):
    peer = Pb.get("pybasin")
    scs = Pb["sweepcore"]
    if not peer:
        return ("### 7. Basin stability against pybasin\n\npybasin's environment was "
                "absent and no saved results exist: sweepcore's side only, in "
                "`pybasin.json`.\n")
    v = peer["versions"]
    m = peer["machine"]
    source = ("pybasin ran live in this run" if peer["source"] == "live" else
              f"**pybasin from its saved results** (`benchmarks/results/pybasin_peer.json`, "
              f"{m['date']}): its environment was absent from this run")
    out = [fill("pybasin_head", source=source, version=v["pybasin"], python=v["python"],
                jax=v["jax"], diffrax=v["diffrax"], p_cpu=m["cpu_model"], p_cores=m["cores"],
                p_date=m["date"][:10], samples=peer["settings"]["samples"],
                command=peer["command"],
                curve=(f" and the {scs['curve']['points']} speeds of "
                       "`studies/bstab_basins.toml`" if "curve" in scs else ""),
                repeats=len(scs["speeds"][0]["exact"]["walls_s"]))]
    by_v = {round(r["v"], 9): r for r in scs["speeds"]}
    rows = []
    for p in peer["speeds"]:
        sc = by_v[round(p["v"], 9)]
        ec = p.get("exact_check", {})
        rows.append([f"{p['v']:g}", f"{p['fraction']:.4f} +- {p['error']:.4f}",
                     f"{sc['exact']['fraction']:.5f}",
                     f"{sc['sampled']['fraction']:.4f} +- {sc['sampled']['error']:.4f}",
                     ec.get("inside_labelled_stick_slip", "-"),
                     f"{s(p['wall_s'])} / {s(p['cpu_s'])}",
                     f"{s(sc['exact']['wall_s'])} / {s(sc['exact']['cpu_s'])}",
                     f"{s(sc['sampled']['wall_s'])} / {s(sc['sampled']['cpu_s'])}"])
    out.append(table(["v", "pybasin fraction", "sweepcore exact", "sweepcore sampled",
                      "inside, labelled stick-slip", "pybasin wall / CPU",
                      "sweepcore exact wall / CPU", "sweepcore sampled wall / CPU"], rows))
    rat = Pb["ratios"]
    rows = [[f"{r['v']:g}", f"**{g(r['wall_exact'])}x** / {g(r['cpu_exact'])}x",
             f"**{g(r['wall_sampled'])}x** / {g(r['cpu_sampled'])}x"]
            for r in rat["per_speed"]]
    out.append("")
    out.append(table(["v", "pybasin / sweepcore exact (wall / CPU)",
                      "pybasin / sweepcore sampled (wall / CPU)"], rows))
    if "curve" in rat:
        c, sc = rat["curve"], scs["curve"]
        out.append(f"\nThe {sc['points']}-speed curve: pybasin {s(c['pybasin_wall_s_extrapolated'])} "
                   f"wall, {s(c['pybasin_cpu_s_extrapolated'])} CPU (its median per speed x "
                   f"{sc['points']}), sweepcore's exact route {s(sc['wall_s'])} wall, "
                   f"{s(sc['cpu_s'])} CPU: **{g(c['wall'])}x** wall, {g(c['cpu'])}x CPU.")
    out.append(fill("pybasin_tail"))
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
    m = H["machine"]
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
    rows += _heyoka_rows(_load(outdir, "heyoka")) + _pybasin_rows(_load(outdir, "pybasin"))
    th = H.get("threads", {})
    if "2" in th.get("grid order", {}):
        rows.append(["thread scaling 1 -> 2 threads", f"{g(th['grid order']['2']['speedup'])}x "
                     "in grid order" + (f", {g(th['shuffled rows']['2']['speedup'])}x on "
                                        "shuffled rows" if "2" in th.get("shuffled rows", {})
                                        else "")])
    rows += _laws_rows(_load(outdir, "laws")) + _main_job_rows(H)
    c = H.get("compile", {})
    if "t_first_call_parallel" in c.get("cold", {}):
        rows.append(["kernel compilation (first call in a fresh process)",
                     f"{s(c['cold']['t_first_call_parallel'])} with an empty cache, "
                     f"{s(c.get('warm_cache', {}).get('t_first_call_parallel'))} from the cache"])
    head = fill("readme_block_head", date=m["date"][:10], cpu_model=m["cpu_model"],
                cores=m["cores"], commit=m["git_commit"][:10], rel=rel)
    return head + "\n\n" + table(["", "measured"], rows)


def _laws(La):
    """The table-law section: cost per point against the analytic law, agreement,
    and what a second table compiled."""
    med, pp = La["median_s"], La["per_point_us"]
    rows = [[name, s(med[name]), f"{g(pp[name])} us"] for name in ("analytic", "table")]
    return "\n".join([
        fill("laws_head", case=La["case"], table=La["table"], n=La["grid"]["n_points"],
             nv=La["grid"]["nv"], nx=La["grid"]["nx"], v0=g(La["grid"]["v"][0]),
             v1=g(La["grid"]["v"][1]), x0=g(La["grid"]["x0"][0]),
             x1=g(La["grid"]["x0"][1]), repeats=len(La["times_s"]["table"])),
        table(["law", "median wall time (all points)", "per point"], rows),
        fill("laws_result", ratio=g(La["ratio_table_over_analytic"]),
             amp=g(La["max_amp_diff_over_L"]), deviation=g(La["law_deviation"]),
             regimes=La["regime_mismatches"], statuses=La["status_mismatches"],
             second=s(La["second_table"]["seconds"]),
             compiled=La["second_table"]["n_compiled"])]) + "\n"


def _laws_rows(La):
    """The README's row of the table-law section."""
    if not La:
        return []
    return [[f"a friction table ({La['table']}) against the analytic law it samples, "
             f"{La['grid']['n_points']:,} points of bSTAB's oscillator",
             f"{g(La['ratio_table_over_analytic'])}x the analytic law's time per point; "
             f"answers within {g(La['max_amp_diff_over_L'])} L of it; a second table in "
             f"the same process: {s(La['second_table']['seconds'])}, "
             f"{La['second_table']['n_compiled']} kernels compiled"]]


def _main_job_rows(H):
    """The README's rows of the main job from an empty cache and warm, and of the
    maps against the kernels before (``benchmarks/regimes.py``)."""
    rows = []
    ba = H.get("regimes", {}).get("before_after", {})
    if "speedup" in ba and "stribeck_map" in ba:
        diff = ", ".join(f"{o['rows_differing']} of {o['rows']:,} points of the {name} map"
                         for name, o in ba.get("outputs", {}).items())
        rows.append([f"the Hopf map and the Stribeck map against the kernels before the "
                     f"law interface (commit {ba['commit_before'][:7]}), same run, "
                     f"interleaved", f"speedup x{g(ba['speedup'])} (Hopf map), "
                     f"x{g(ba['stribeck_map']['speedup'])} (Stribeck map); outputs differ "
                     f"on {diff}"])
    mj = H.get("main_job")
    if not mj or "ratio_wall" not in mj:
        return rows
    return rows + [["the main job (`sweepcore run studies/hopf_map.toml`) from an empty kernel "
             "cache, then warm, back to back",
             f"{s(mj['cold']['wall_s'])} cold, {s(mj['warm']['wall_s'])} warm: "
             f"**{g(mj['ratio_wall'])}x** (wall)"]]


def compile_estimates(outdir, path=None) -> bool:
    """Write the compile seconds the main job's cold run measured into
    ``sweepcore/compile_estimates.json`` (the estimates the command line prints
    while a kernel compiles on a machine that has not compiled it before)."""
    H = _load(outdir, "hopf_map")
    seconds = (H or {}).get("main_job", {}).get("compile_seconds")
    if not seconds:
        return False
    path = Path(path or common.ROOT / "sweepcore" / "compile_estimates.json")
    path.write_text(json.dumps({k: round(v, 1) for k, v in sorted(seconds.items())},
                               indent=1) + "\n")
    return True


def _load_range(R):
    """The 1-minute load before and after a section's run, as "a-b"."""
    return f"{R['load_before']:.1f}-{R['load_after']:.1f}"


def _events(Hy):
    """Events handled in Python a point, by mode, as text (runs without the count,
    saved before the peer counted them, give none)."""
    n = Hy["grid"]["nv"] * Hy["grid"]["na"]
    return {mode: f"{common.median([r['events'] for r in v]) / n:.1f}"
            for mode, v in Hy["runs"].items() if mode != "sweepcore" and v
            and all("events" in r for r in v)}


def _heyoka_rows(Hy):
    """The README's rows of the heyoka section (none when it did not run)."""
    if not Hy or "skipped" in Hy:
        return []
    tol = Hy["chosen_tol"]
    e = next(r for r in Hy["ladder"] if r["tol"] == tol)["errors"]
    med, rat = Hy["median"], Hy["ratios"]
    tols = ", ".join(f"{r['tol']:g}" for r in Hy["ladder"])
    modes = "; ".join(
        f"{label} {_cpu_wall(med[mode])}: **{g(rat[mode + '_cpu'])}x** CPU, "
        f"{g(rat[mode + '_wall'])}x wall" for mode, label in
        (("batch", f"batch mode ({Hy['batch_size']} lanes)"), ("scalar", "scalar mode"))
        if mode in med)
    return [[f"heyoka.py {Hy['heyoka']} (Taylor method compiled by LLVM, events by root "
             f"finding), same map, written for the job (`benchmarks/heyoka_peer.py`), "
             f"{Hy['processes']} processes, tol {tol:g}: the cheapest of {tols} with "
             f"amplitude error <= 1e-6 cm on every point" +
             ("" if Hy["chosen_meets_target"] else " (none met it: the tightest)"),
             f"{modes}; sweepcore in the same run {_cpu_wall(med['sweepcore'])}; heyoka's "
             f"max amplitude error {g(e['amp_err_max_all'])} cm on every point with a "
             f"reference (run of {Hy['machine']['date'][:10]}, {Hy['machine']['cpu_model']}, "
             f"load {_load_range(Hy)} on 2 cores). The peer finds each slip cycle by "
             "Newton's method on the return map (its slope from heyoka's variational "
             "state), as sweepcore does; Python handles "
             f"{_events(Hy).get('scalar', '?')} events a point (scalar mode), each a "
             "flight to heyoka's next terminal event"]]


def _pybasin_rows(Pb):
    """The README's rows of the pybasin section (none without pybasin's results)."""
    if not Pb or not Pb.get("pybasin"):
        return []
    peer, sc, rat = Pb["pybasin"], Pb["sweepcore"], Pb["ratios"]
    v = peer["versions"]
    src = ("rerun in the same run" if peer["source"] == "live" else
           f"from its saved results of {peer['machine']['date'][:10]}, "
           "`benchmarks/results/pybasin_peer.json`")
    per = {w: common.median([p[f"{w}_s"] for p in peer["speeds"]]) for w in ("wall", "cpu")}

    def med(route, w):
        return common.median([r[route][f"{w}_s"] for r in sc["speeds"]])

    def ratio(route, w):
        return common.median([r[f"{w}_{route}"] for r in rat["per_speed"]])
    speeds = ", ".join(f"{p['v']:g}" for p in peer["speeds"])
    text = (f"{s(per['wall'])} wall, {s(per['cpu'])} CPU a speed (v = {speeds}); "
            f"sweepcore's exact route {s(med('exact', 'wall'))} wall, "
            f"{s(med('exact', 'cpu'))} CPU: **{g(ratio('exact', 'wall'))}x** wall, "
            f"{g(ratio('exact', 'cpu'))}x CPU; sampled route, same starts a speed, "
            f"{s(med('sampled', 'wall'))} wall: **{g(ratio('sampled', 'wall'))}x** wall, "
            f"{g(ratio('sampled', 'cpu'))}x CPU")
    if "curve" in rat:
        text += (f"; the {sc['curve']['points']}-speed curve "
                 f"{s(rat['curve']['pybasin_wall_s_extrapolated'])} (per speed x "
                 f"{sc['curve']['points']}) against {s(sc['curve']['wall_s'])}")
    rows = [[f"pybasin {v['pybasin']} (JAX/diffrax), its published friction case as "
             f"shipped, {peer['settings']['samples']:,} starts a belt speed, {src}", text]]
    near = min(peer["speeds"], key=lambda p: p["v"])
    exact = next(r for r in sc["speeds"] if abs(r["v"] - near["v"]) < 1e-9)["exact"]
    if "exact_check" in near:
        rows.append([f"pybasin at v = {near['v']:g}" + (" (next to the Hopf point)"
                                                       if near["v"] < 1.2 else ""),
                     f"steady sliding {near['fraction']:.4f} +- {near['error']:.4f}, exact "
                     f"{exact['fraction']:.5f}: {near['exact_check']['inside_labelled_stick_slip']}"
                     f" of its {near['samples']:,} starts lie inside the unstable cycle and "
                     "are labelled stick-slip (not settled by t = 400)"])
    return rows


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
    compile_estimates(args.outdir)
    print(f"wrote {common.BENCH / 'README.md'} and the speed block of "
          f"{common.ROOT / 'README.md'} from {args.outdir}")


if __name__ == "__main__":
    main()
