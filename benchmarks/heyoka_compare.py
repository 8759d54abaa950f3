"""Section 6: the Hopf map by heyoka.py (``heyoka_peer.py``) against sweepcore, same run.

The peer computes every point's attractor (``heyoka_peer`` says how) on 2 worker
processes, batch mode (the ladder and the headline) and scalar mode. Its accuracy is
checked against the references sweepcore's map is checked against (section 1): every
point against the map computed by sweepcore's dopri5 at tol 1e-12 (where that
reference converged), and the slip cycles nearest below v* against the independent
scipy shooting or the normal form (``hopf_map.hardest_references``). Its tolerance is
the cheapest of a ladder whose amplitude error is <= 1e-6 cm on every compared point,
a point whose regime differs from the reference's included, with no point
unconverged.

Timed at that tolerance, interleaved with sweepcore's map at the main job's
tolerance (1e-8) on its 2 numba threads: wall seconds and CPU seconds (the machine
is shared: CPU seconds see through the load), medians of the repeats, and ratios.
"""
from __future__ import annotations

import time

import numpy as np

from . import common
from .common import OB_AMPLITUDE, OB_NSTEPS, OB_REGIME, OB_STATUS, log

TARGET = 1e-6          # cm: amplitude error the peer must meet on every point


def available():
    try:
        import heyoka
        return heyoka.__version__
    except ImportError:
        return None


def _points(P):
    """(m, k, r_y, v, alpha1, alpha2) of the kernel rows P (the peer's rows)."""
    from sweepcore import law
    rows = [law.from_row(p) for p in P]            # each row's parameters by name
    return np.array([[r[n] for n in ("m", "k", "r_y", "v", "alpha1", "alpha2")]
                     for r in rows])


def references(P, profile, outdir, same_grid):
    """The dopri5 tol 1e-12 map and the hardest points' independent references
    (those of this run's Hopf-map section when it ran on the same grid)."""
    from . import hopf_map
    ref = common.attractor_map(P, "dopri5", 1e-12)
    hard = hopf_map.load_references(outdir) if same_grid else None
    if hard is None:
        hard = hopf_map.hardest_references(P, ref, profile["hard_per_column"])
    return ref, hard


def errors(P, amplitude, regime, ref, hard):
    """Amplitude errors [cm] of a map (amplitude, regime codes) against the
    references: every point, and the hardest points."""
    from . import hopf_map
    conv = (regime != 6) & np.isfinite(amplitude)          # 6: unconverged
    ok = ref[:, OB_STATUS] == 0
    same = ok & conv & (regime == ref[:, OB_REGIME])
    da = np.abs(amplitude - ref[:, OB_AMPLITUDE])
    picks, refs = hard
    h = hopf_map.hardest_errors(P, amplitude, conv, picks, refs)
    covered = ok.copy()
    covered[[i for i in picks if refs[i]["resolved"]]] = True
    all_max = max(float(da[ok & conv].max()) if (ok & conv).any() else 0.0,
                  h["max_amp_err"] or 0.0)
    return dict(n=int(P.shape[0]), n_unconverged=int((~conv).sum()),
                n_compared=int(same.sum()), amp_err_max=float(da[same].max()),
                n_regime_mismatch=int((ok & conv & ~same).sum()),
                amp_err_max_regime_mismatch=float(da[ok & conv & ~same].max())
                if (ok & conv & ~same).any() else None,
                hardest=h, n_without_reference=int((~covered).sum()),
                amp_err_max_all=all_max)


def meets(e):
    """Whether errors ``e`` (of ``errors``) meet the target: amplitude within TARGET
    on every referenced point, a regime mismatch included, none unconverged."""
    return (e["amp_err_max_all"] <= TARGET and e["n_unconverged"] == 0
            and (e["amp_err_max_regime_mismatch"] or 0.0) <= TARGET)


def _sweepcore(P, out):
    """sweepcore's map at the main job's tolerance: (wall, CPU) seconds."""
    c0, t0 = time.process_time(), time.perf_counter()
    common.attractor_map(P, "auto", 1e-8, out)
    return time.perf_counter() - t0, time.process_time() - c0


def run(profile, outdir, hopf_res=None):
    from . import heyoka_peer as hp
    version = available()
    if version is None:
        log("[6] heyoka skipped: heyoka is not installed (pip install -e '.[bench]')")
        return {"skipped": "heyoka is not installed (pip install -e '.[bench]')"}
    nv, na = profile["heyoka_map_shape"]
    log(f"[6] heyoka.py {version} on the {nv} x {na} Hopf map")
    P = common.rows(*common.map_axes(nv, na))
    pts = _points(P)
    same_grid = hopf_res is not None and (hopf_res["grid"]["nv"], hopf_res["grid"]["na"]) \
        == (nv, na)
    res = {"heyoka": version, "load_before": common.load(), "grid": {"nv": nv, "na": na},
           "processes": profile["heyoka_processes"], "batch_size": profile["heyoka_batch"],
           "target_amp_err": TARGET}
    ref, hard = references(P, profile, outdir, same_grid)
    res["references"] = {"map": "sweepcore dopri5 tol=1e-12, every point",
                         "map_converged": int((ref[:, OB_STATUS] == 0).sum()),
                         "hardest_points": len(hard[0]),
                         "hardest_resolved": int(sum(r["resolved"] for r in hard[1].values()))}
    sc_out = np.empty_like(ref)
    _sweepcore(P[:4], sc_out[:4])
    _sweepcore(P, sc_out)
    res["sweepcore_errors"] = errors(P, sc_out[:, OB_AMPLITUDE], sc_out[:, OB_REGIME], ref, hard)
    res["sweepcore_steps"] = float(sc_out[:, OB_NSTEPS].sum())
    log(f"    sweepcore tol 1e-8: max amp err {res['sweepcore_errors']['amp_err_max_all']:.2e} "
        f"cm over every referenced point")

    ladder = []
    with hp.pool(profile["heyoka_processes"]) as ex:
        for tol in profile["heyoka_tols"]:                 # compile outside the timing
            for bs in (None, profile["heyoka_batch"]):
                hp.run_map(ex, pts[:16], tol, bs, chunk=8)
        for tol in profile["heyoka_tols"]:
            r = hp.run_map(ex, pts, tol, profile["heyoka_batch"])
            out = r.pop("out")
            e = errors(P, out[:, 0], out[:, 3], ref, hard)
            steps = np.sort(out[:, 4])
            ladder.append(dict(tol=tol, mode="batch", **r, errors=e,
                               steps=float(steps.sum()),
                               steps_share_top1000=float(steps[-1000:].sum() / steps.sum()),
                               returns=float(out[:, 6].sum()),
                               events=float(out[:, 7].sum())))
            log(f"    heyoka tol {tol:g} batch: {r['wall_s']:.1f} s wall, {r['cpu_s']:.1f} "
                f"CPU-s; max amp err {e['amp_err_max_all']:.2e} cm (every referenced "
                f"point), {e['n_regime_mismatch']} regime mismatches, {e['n_unconverged']} "
                f"unconverged; {steps.sum():.3g} Taylor steps, {out[:, 7].mean():.1f} "
                f"events a point handled in Python")
        ok = [r for r in ladder if meets(r["errors"])]
        chosen = min(ok, key=lambda r: r["cpu_s"]) if ok else ladder[-1]
        tol = chosen["tol"]
        res["chosen_tol"] = tol
        res["chosen_meets_target"] = bool(ok)
        log(f"    chosen tol {tol:g} ({'meets' if ok else 'no tolerance meets'} the target)")
        # timing at the chosen tolerance, interleaved with sweepcore's map
        runs = {"sweepcore": [], "scalar": [], "batch": [chosen]}
        for rep in range(profile["heyoka_repeats"]):
            for mode in ("scalar", "batch"):
                if mode == "batch" and rep == 0:
                    continue                               # the ladder's run
                w, c = _sweepcore(P, sc_out)
                runs["sweepcore"].append(dict(wall_s=w, cpu_s=c))
                r = hp.run_map(ex, pts, tol, profile["heyoka_batch"] if mode == "batch"
                               else None)
                out = r.pop("out")
                runs[mode].append(dict(r, steps=float(out[:, 4].sum()),
                                       events=float(out[:, 7].sum()),
                                       amp_err_max_all=errors(P, out[:, 0], out[:, 3], ref,
                                                              hard)["amp_err_max_all"]))
                log(f"    heyoka tol {tol:g} {mode}: {r['wall_s']:.1f} s wall, "
                    f"{r['cpu_s']:.1f} CPU-s; sweepcore {w:.3f} s wall, {c:.3f} CPU-s")
    res["ladder"] = ladder
    res["runs"] = {k: [{kk: vv for kk, vv in r.items() if kk != "errors"} for r in v]
                   for k, v in runs.items()}
    med = {k: {w: common.median([r[f"{w}_s"] for r in v]) for w in ("wall", "cpu")}
           for k, v in runs.items() if v}
    res["median"] = med
    res["ratios"] = {f"{mode}_{w}": med[mode][w] / med["sweepcore"][w]
                     for mode in ("scalar", "batch") if mode in med for w in ("wall", "cpu")}
    res["load_after"] = common.load()
    log("    ratios heyoka / sweepcore: " + ", ".join(f"{k} {v:.1f}x"
                                                   for k, v in res["ratios"].items()))
    return res
