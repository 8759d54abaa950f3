"""Boundaries beyond the grid: the Hopf and stick-onset curves by continuation, timed
against the 256 x 256 Hopf map in the same run, and the regime changes of a located
scan (slide-slide-reversal band).

    python benchmarks/boundaries.py            # ~3-5 min on 2 cores; prints only
    python benchmarks/boundaries.py --write    # also rewrites the tracked results
    python benchmarks/boundaries.py --quick    # one repeat

With ``--write`` (or ``--out FILE``) it writes ``benchmarks/results/boundaries.json``
(the numbers quoted in benchmarks/README.md and docs/physics.md) and, for the tracked
file, its section of benchmarks/README.md; without, it prints the section. The
timing verdict states its noise: "met" or "not met" only when every pairing of the
repeats' times agrees, else "within the noise" with the range of the ratio.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks.common import (PAPER, RESULTS, _clean, _Enc, load, log,  # noqa: E402
                               machine, map_axes, median, save_json)

CURVE_A2 = (2e-3, 0.1, 256)      # the continuation target: 256 alpha2 values
BRACKET = (0.5, 14.0)            # v bracket of the first (scanned) steps [cm/s]
SCAN_A2 = (1e-3, 0.1, 32)        # located scan: every regime change along v
SCAN_BRACKET = (0.5, 20.0)


def _curves(sc, bd, tol, repeats):
    a2 = np.geomspace(*CURVE_A2)
    grid = sc.Grid(**PAPER, alpha2=a2, v=list(BRACKET))
    times, ds = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        ds = bd.continue_boundary(grid, tol=tol)
        times.append(time.perf_counter() - t0)
    hopf = ds.hopf_status.values == bd.LOCATED
    stick = ds.stick_status.values == bd.LOCATED
    ratio = (ds.v_stick_onset / ds.v_star).values
    return ds, {
        "tol": tol, "points": int(a2.size), "times_s": times, "median_s": median(times),
        "load_1min": load(),
        "hopf_located": int(hopf.sum()), "stick_located": int(stick.sum()),
        "continued_steps": int(ds.continued.sum()),
        "attractors": int(ds.evaluations.sum()),
        "attractors_per_continued_step": float(
            ds.evaluations.values[ds.continued.values == 1].mean()),
        "hopf_minus_vstar_max_abs": float(np.nanmax(np.abs(
            (ds.v_hopf - ds.v_star).values[hopf]))),
        "hopf_error_estimate_max": float(np.nanmax(ds.v_hopf_error.values[hopf])),
        "stick_width_max": float(np.nanmax(ds.v_stick_onset_width.values[stick])),
        "stick_ratio_min": float(np.nanmin(ratio[stick])),
        "stick_ratio_max": float(np.nanmax(ratio[stick])),
        "stick_ratio_median": float(np.nanmedian(ratio[stick])),
    }


def _map(sc, tol, repeats):
    v, a2 = map_axes()
    grid = sc.Grid(**PAPER, v=v, alpha2=a2)
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        ds = sc.sweep(grid, tol=tol, progress=False)
        times.append(time.perf_counter() - t0)
    step = float(v[1] - v[0])
    return ds, {"tol": tol, "shape": [v.size, a2.size], "times_s": times,
                "median_s": median(times), "load_1min": load(),
                "v_step": step, "boundary_resolution": step / 2}


def _transitions(sc, bd, tol):
    a2 = np.geomspace(*SCAN_A2)
    grid = sc.Grid(**PAPER, alpha2=a2, v=list(SCAN_BRACKET))
    t0 = time.perf_counter()
    ds = bd.locate_boundaries(grid, bracket=SCAN_BRACKET, scan=40, tol=tol)
    elapsed = time.perf_counter() - t0
    from sweepcore._kernels import codes
    names = codes.REGIME_NAMES
    rows = []
    for i, a in enumerate(a2):
        p = ds.isel(alpha2=i)
        changes = []
        for k in range(p.sizes["transition"]):
            val = float(p.transition_value[k])
            if not math.isfinite(val):
                continue
            changes.append({"v": val, "width": float(p.transition_width[k]),
                            "below": names.get(int(p.regime_below[k])),
                            "above": names.get(int(p.regime_above[k])),
                            "status": bd.SEARCH_NAMES[int(p.transition_status[k])]})
        rows.append({"alpha2": float(a), "v_star": float(p.v_star),
                     "v_hopf": float(p.v_hopf), "v_stick_onset": float(p.v_stick_onset),
                     "changes": changes})
    # the band of slip cycles with slide-slide reversals: a slip_cycle interval
    # below the stick onset, entered from stick-slip
    band = []
    for r in rows:
        ch = r["changes"]
        for c0, c1 in zip(ch, ch[1:]):
            if (c0["below"], c0["above"]) == ("stick_slip", "slip_cycle") and \
                    c1["below"] == "slip_cycle" and c1["above"] == "stick_slip":
                band.append({"alpha2": r["alpha2"], "lower": c0["v"], "upper": c1["v"],
                             "upper_over_vstar": c1["v"] / r["v_star"]})
                break
        else:
            first = ch[0] if ch else None
            if first and (first["below"], first["above"]) == ("stick_slip",
                                                              "slip_cycle") and \
                    first["v"] < 0.8 * r["v_star"]:
                band.append({"alpha2": r["alpha2"], "lower": first["v"], "upper": None,
                             "upper_over_vstar": None})
    return {"tol": tol, "alpha2": list(a2), "bracket": list(SCAN_BRACKET), "scan": 40,
            "seconds": elapsed, "attractors": int(ds.evaluations.sum()),
            "points": rows, "reversal_band": band}


def _damping(sc, bd, tol):
    """v_stick_onset/v* against the dimensionless damping alpha1/sqrt(k m): the
    slip cycle and its grazing depend on nothing else (r_y only shifts x_eq, and
    v ~ v* scales alpha2 out), so two sliders with the same damping must agree."""
    from sweepcore import law
    cases = [dict(m=5.0, k=50.0 * f, r_y=10.0, alpha1=1.0) for f in (25.0, 6.25, 1.0,
                                                                      0.4, 0.1)]
    cases.append(dict(m=2.0, k=125.0, r_y=3.0, alpha1=1.0))  # same damping as paper
    out = []
    for c in cases:
        ds = bd.locate_boundaries(sc.Grid(**c, alpha2=0.03, v=[0.5, 5.0]), scan=24,
                                  tol=tol)
        eps = c["alpha1"] / math.sqrt(c["k"] * c["m"])
        ratio = float(ds.v_stick_onset / ds.v_star)
        src = {**c, "alpha2": 0.03}     # the averaging estimate's ratio, sqrt(4/5)
        averaging = float(law.stick_onset_estimate(src) / law.derived("v_star", src))
        out.append({**c, "alpha2": 0.03, "damping": eps, "ratio": ratio,
                    "ratio_minus_sqrt_4_5": ratio - averaging,
                    "over_damping_squared": (ratio - averaging) / eps ** 2,
                    "hopf_minus_vstar": float(ds.v_hopf - ds.v_star)})
    return out


BEGIN = "<!-- boundaries: written by benchmarks/boundaries.py -->"
END = "<!-- /boundaries -->"


def readme_section(R) -> str:
    """The README section of a result of this script (markdown, between markers)."""
    m, c, mp, r = R["machine"], R["curves"], R["map"], R["time_ratio"]
    rows = []
    for tol, x in c.items():
        rows.append([f"curves, 256 alpha2, tol {tol}", f"{x['median_s']:.2f} s",
                     f"{x['attractors']} ({x['attractors_per_continued_step']:.1f} per "
                     "seeded step)", f"{x['hopf_minus_vstar_max_abs']:.2g}",
                     f"{x['stick_ratio_min']:.10f} - {x['stick_ratio_max']:.10f}"])
    for tol, x in mp.items():
        rows.append([f"map 256 x 256, tol {tol}", f"{x['median_s']:.2f} s", "65536",
                     f"grid: +-{x['boundary_resolution']:.3g}", ""])
    ratios = "; ".join(f"{k.replace('_', ' ')}: **{v:.3f}**" for k, v in r.items())
    verdict = (verdict_at(c["1e-08"], mp["1e-08"]) + " at equal tolerance (tol 1e-8; "
               + verdict_at(c["1e-10"], mp["1e-10"]) + " at tol 1e-10)")
    verdict += ("; the curves at the searches' default (tol 1e-10, needed for "
                "1e-9 cm/s) against the main job's map (the default tol 1e-8): "
                + verdict_at(c["1e-10"], mp["1e-08"]))
    t = R["transitions"]
    d = R["curves_tol_1e-8_vs_1e-10"]
    from benchmarks.report import fill, table
    return fill(
        "boundaries", begin=BEGIN, end=END, command=R["command"], mode=R["mode"],
        date=m["date"], commit=m["git_commit"][:10],
        dirty="with uncommitted changes" if m["sweepcore_dirty"] else "clean",
        load=f"{c[next(iter(c))]['load_1min']:.1f}", cores=m["cores"],
        table=table(["job", "wall time", "attractors", "max abs(v_hopf - v*) [cm/s]",
                     "v_stick_onset / v*"], rows),
        ratios=ratios, verdict=verdict, hopf_diff=f"{d['hopf_max_abs']:.2g}",
        stick_diff=f"{d['stick_max_abs']:.2g}", scan_tol=f"{t['tol']:g}",
        scan_seconds=f"{t['seconds']:.1f}", scan_attractors=t["attractors"])


TARGET = 0.1   # the curves in under a tenth of the map's time


def ratio_range(curves: dict, map_: dict) -> tuple[float, float]:
    """Smallest and largest curves/map time ratio over every pairing of the repeats:
    the spread a shared machine's load puts on the ratio."""
    return (min(curves["times_s"]) / max(map_["times_s"]),
            max(curves["times_s"]) / min(map_["times_s"]))


def verdict_at(curves: dict, map_: dict) -> str:
    """"met" / "not met" for the target ratio when the whole range of the repeats
    agrees, else "within the noise": a loaded machine cannot flip the verdict."""
    lo, hi = ratio_range(curves, map_)
    noise = f"ratio {curves['median_s'] / map_['median_s']:.3f}, {lo:.3f}-{hi:.3f} " \
            f"over the repeats"
    if hi < TARGET:
        return f"met ({noise})"
    if lo >= TARGET:
        return f"not met ({noise})"
    return f"undecided within the noise ({noise})"


def stored_section(path=None) -> str:
    """The section of the stored ``results/boundaries.json``, or "" without one."""
    path = Path(path or RESULTS / "boundaries.json")
    if not path.is_file():
        return ""
    return readme_section(json.loads(path.read_text()))


def update_readme(R, readme=None):
    """Replace (or append) this script's section of benchmarks/README.md."""
    readme = Path(readme or ROOT / "benchmarks" / "README.md")
    text = readme.read_text() if readme.is_file() else ""
    section = readme_section(R)
    if BEGIN in text and END in text:
        head, rest = text.split(BEGIN, 1)
        tail = rest.split(END, 1)[1].lstrip("\n")
        text = head + section + ("\n" + tail if tail else "")
    else:
        text = text.rstrip("\n") + "\n\n" + section
    readme.write_text(text)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--write", action="store_true",
                    help="rewrite results/boundaries.json and benchmarks/README.md")
    ap.add_argument("--out", default=None,
                    help="write the result to this JSON file (not the tracked one)")
    args = ap.parse_args(argv)
    import sweepcore as sc
    from sweepcore import boundaries as bd

    repeats = 1 if args.quick else 2
    log("warm-up (compile or load the kernels)")
    sc.sweep(sc.Grid(**PAPER, v=[1.0, 2.0], alpha2=0.01), progress=False)
    bd.continue_boundary(sc.Grid(**PAPER, alpha2=[0.01, 0.011, 0.012],
                                 v=list(BRACKET)))
    result = {"machine": machine(), "mode": "quick" if args.quick else "full",
              "command": "python benchmarks/boundaries.py"
                         + (" --quick" if args.quick else "")
                         + (" --write" if args.write else "")}
    maps = {}
    for tol in (1e-8, 1e-10):
        log(f"map 256 x 256, tol {tol:g}")
        maps[tol] = _map(sc, tol, repeats)[1]
        log(f"  {maps[tol]['median_s']:.2f} s")
    curves = {}
    for tol in (1e-8, 1e-10):
        log(f"curves by continuation, 256 alpha2, tol {tol:g}")
        ds, curves[tol] = _curves(sc, bd, tol, repeats)
        if tol == 1e-10:
            fine = ds
        else:
            coarse = ds
        log(f"  {curves[tol]['median_s']:.2f} s, |v_hopf - v*| <= "
            f"{curves[tol]['hopf_minus_vstar_max_abs']:.2g}, stick ratio in "
            f"[{curves[tol]['stick_ratio_min']:.12f}, "
            f"{curves[tol]['stick_ratio_max']:.12f}]")
    result["map"] = {f"{t:g}": m for t, m in maps.items()}
    result["curves"] = {f"{t:g}": c for t, c in curves.items()}
    result["curves_tol_1e-8_vs_1e-10"] = {
        "hopf_max_abs": float(np.nanmax(np.abs(coarse.v_hopf - fine.v_hopf))),
        "stick_max_abs": float(np.nanmax(np.abs(coarse.v_stick_onset
                                                - fine.v_stick_onset))),
    }
    result["time_ratio"] = {
        f"curves_tol_{tc:g}_over_map_tol_{tm:g}":
            curves[tc]["median_s"] / maps[tm]["median_s"]
        for tc in curves for tm in maps}
    log("stick onset / v* against the damping alpha1/sqrt(k m)")
    result["damping"] = _damping(sc, bd, 1e-10)
    for c in result["damping"]:
        log(f"  damping {c['damping']:.4f}: ratio {c['ratio']:.10f} "
            f"(- sqrt(4/5))/damping^2 = {c['over_damping_squared']:.4f}")
    log("located scan of 32 alpha2 in v = [0.5, 20]: every regime change")
    result["transitions"] = _transitions(sc, bd, 1e-10)
    log(f"  {result['transitions']['seconds']:.1f} s")
    for name, val in result["time_ratio"].items():
        log(f"{name}: {val:.3f}")
    if not (args.write or args.out):
        print(readme_section(json.loads(json.dumps(_clean(result), cls=_Enc))))
        log("printed only: --write rewrites results/boundaries.json and its README "
            "section")
        return
    path = save_json(result, args.out or RESULTS / "boundaries.json")
    log(f"wrote {path}")
    if args.write and not args.out:
        update_readme(json.loads(path.read_text()))
        log("updated benchmarks/README.md")

if __name__ == "__main__":
    main()
