"""Forced responses against the independent reference at random points, by class.

    python -m benchmarks.forced_accuracy [--points 150] [--seed 2026]

Each point is drawn from one of three classes (in turn), started at random, and
solved by ``sweepcore.attractor`` (default tolerance 1e-8) and by the reference
(``tests/reference_forced.py``: scipy DOP853 at rtol 1e-12 with exact sticks, the
stroboscopic map iterated from the same start until its period shows, the fixed
point by the chord method, multipliers by central differences):

* ``harmonics``: a load of 2-3 harmonics with the anchor's motion, any law of the
  analytic family, on fixed ground or a belt;
* ``coexistence``: where a stable slip response coexists with stick-slip: steep
  Stribeck friction (v_s 0.05-0.3) or static above kinetic (v_s = 0), a belt, a load
  or the anchor's motion, light damping, starts that reach either;
* ``harmonic``: one cosine, any law, fixed ground or belt.

A point is *wrong with status ok* when sweepcore says ok and the reference's response
differs: another multiplicity, stick or stop count, or an amplitude, mean or extreme
more than 1e-6 of the length scale L away, or aperiodic where the reference finds a
period (or the other way round). A period the reference finds whose orbit repels
(largest multiplier modulus above 1 + 1e-3: its chord method can converge on an
unstable orbit inside a chaotic motion) is not where the start settles: the
reference's answer there is aperiodic. Where the reference's search fails (its chord
method does not converge, or scipy stops on a step size) or it finds the slider at
rest, sweepcore's ok answer is checked against the reference's own motion from the
start (``long_check``: followed until it repeats, or, for a rest at the edge of the
band where a slider on fixed ground rests for ever, creeping towards that edge,
whose position is the load's extreme plus the static limit over k); only what
neither settles counts as *reference failed*. Saves ``benchmarks/results/forced_accuracy.json``:
per class the counts (agree, wrong with ok, flagged, reference failed) and the
largest differences of the agreeing points.
"""
from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
CONTRACT = 1e-6


def draw(rng, cls):
    """A random point of class ``cls``: (Params kwargs, reference kwargs, x0, xd0)."""
    m, k = rng.uniform(0.5, 2.0, 2)
    omega = math.sqrt(k / m)
    kw = dict(m=m, k=k, Omega=omega * rng.uniform(0.4, 3.0))
    cos = sin = None
    if cls == "coexistence":
        r_y = rng.uniform(0.5, 1.5)
        kw.update(r_y=r_y, r_k=r_y * rng.uniform(0.3, 0.7),
                  v_s=rng.choice([0.0, rng.uniform(0.05, 0.3)]), c=rng.uniform(0.0, 0.08),
                  v=rng.uniform(0.3, 1.5))
        if rng.uniform() < 0.5:
            kw.update(F0=rng.uniform(0.05, 0.6) * r_y, phi=rng.uniform(0, 2 * math.pi))
        else:
            kw.update(Y0=rng.uniform(0.05, 0.6) * r_y / k)
    else:
        r_y = rng.uniform(0.3, 1.0)
        kw.update(r_y=r_y, alpha1=rng.uniform(0.0, 0.2), alpha2=rng.uniform(0.0, 0.1),
                  r_k=r_y * rng.uniform(0.6, 1.0), v_s=rng.uniform(0.3, 1.0),
                  c=rng.choice([0.0, rng.uniform(0.02, 0.3)]),
                  v=rng.choice([0.0, rng.uniform(0.2, 1.5)]),
                  F0=rng.uniform(0.5, 3.0), phi=rng.uniform(0, 2 * math.pi),
                  Y0=rng.choice([0.0, rng.uniform(0.2, 1.0)]))
        if cls == "harmonics":
            n = int(rng.integers(2, 4))
            cos, sin = rng.uniform(-1, 1, n), rng.uniform(-1, 1, n)
    x0, xd0 = rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.5)
    return kw, cos, sin, x0, xd0


def compare(kw, cos, sin, x0, xd0):
    """One point: the verdict and the differences [L]."""
    import sweepcore as sc
    from reference_forced import Forced, forced_steady
    load = sc.PeriodicLoad(cos=cos, sin=sin) if cos is not None else None
    mod = Forced(**kw, cos=cos, sin=sin)
    t = time.process_time()
    res = sc.attractor(sc.Params(**kw, load=load), x0=x0, xdot0=xd0)
    t_mine = time.process_time() - t
    t = time.process_time()
    out = {"status": res.status, "regime": res.regime, "t_sweepcore_s": t_mine}
    try:
        ref = forced_steady(mod, x0=x0, xd0=xd0)
    except RuntimeError as err:
        ref = {"status": "raised", "why": str(err)[:80]}
    out.update(t_ref_s=time.process_time() - t, reference=ref["status"])
    if ref["status"] == "rest":
        # stuck for ever where it started: sweepcore's rest, the same position
        if res.status != "ok":
            return {**out, "verdict": "flagged"}
        d = abs(res.mean - ref["mean"]) + res.amplitude
        return {**out, "diff_L": d / mod.L,
                "verdict": "agree" if res.regime == "stuck" and d <= CONTRACT * mod.L
                else "wrong_ok"}
    if ref["status"] not in ("ok", "aperiodic"):
        # the reference's search failed: its own motion, followed long, checks an ok
        # periodic answer of sweepcore (or its rest at the band's edge)
        if res.status != "ok":
            return {**out, "verdict": "reference_failed"}
        return {**out, **long_check(mod, res, x0, xd0)}
    if ref["status"] == "ok" and ref["floquet"] > 1.0 + 1e-3:
        # the reference's chord method converged on a periodic orbit that repels
        # (floquet > 1): the start's motion cannot settle on it; what it does is
        # aperiodic (the reference's own Lyapunov exponent says how)
        out["reference_unstable_orbit"] = float(ref["floquet"])
        ref = {**ref, "status": "aperiodic"}
    if res.status != "ok":
        return {**out, "verdict": "flagged"}
    if ref["status"] == "aperiodic" or res.regime == "aperiodic":
        same = ref["status"] == "aperiodic" and res.regime == "aperiodic"
        return {**out, "verdict": "agree" if same else "wrong_ok"}
    counts = (res.multiplicity, res.sticks_per_period, res.stops_per_period) == \
        (ref["multiplicity"], ref["sticks_per_period"], ref["stops_per_period"])
    d = max(abs(getattr(res, n) - ref[n]) for n in ("amplitude", "mean", "x_max", "x_min"))
    out.update(diff_L=d / mod.L, floquet_diff=abs(res.floquet - ref["floquet"]))
    return {**out, "verdict": "agree" if counts and d <= CONTRACT * mod.L else "wrong_ok"}


def long_check(mod, res, x0, xd0, periods=20000, rtol=1e-10):
    """Where the reference's search fails: sweepcore's ok answer against the
    reference's motion from the same start (scipy at ``rtol``, exact sticks).

    A rest on fixed ground (regime stuck): the motion's stroboscopic x must approach
    the position monotonically from outside the band where the slider rests for ever,
    and the position must be that band's edge, the load's extreme (on a grid of
    4e5 phases, refined at the coarse extreme) plus or minus the static limit over k,
    within the contract (a motion that creeps to the edge never reaches it, so the
    run cannot show the position itself). A periodic answer (multiplicity n): the
    motion is followed until its state repeats after n periods within 1e-9 of the
    scales, then the state nearest sweepcore's periodic point and the amplitude of its
    last n periods must agree within the contract, and its sticks and stops."""
    from reference_forced import _map, load_extreme
    scale = np.array([mod.L, mod.Lv])
    z, t = np.array([x0, xd0], float), 0.0
    try:
        if res.regime == "stuck" and mod.v == 0.0:
            xs = []
            for _ in range(60):
                z = _map(mod, z, t, 1, rtol)[0]
                t += mod.T
                xs.append(z[0])
            edges = ((load_extreme(mod, min) + mod.r_neg) / mod.k,
                     (load_extreme(mod, max) - mod.r_pos) / mod.k)
            edge = min(edges, key=lambda x: abs(x - res.mean))
            steps = np.diff(xs[10:])
            side = np.sign(xs[-1] - edge)
            creeps = bool(np.all(side * steps <= 0.0) and side != 0.0)
            d = abs(res.mean - edge)
            return {"check": "band_edge", "diff_L": d / mod.L,
                    "verdict": "agree" if creeps and d <= CONTRACT * mod.L else "wrong_ok"}
        n = int(res.multiplicity)
        if res.regime == "aperiodic" or n < 1:
            return {"verdict": "reference_failed"}
        states, runs = [z], []
        for j in range(periods):
            z, run = _map(mod, z, t, 1, rtol)
            t += mod.T
            states.append(z)
            runs.append(run)
            if j > 2 * n and np.max(np.abs(states[-1] - states[-1 - n]) / scale) < 1e-9:
                break
        else:
            return {"verdict": "reference_failed", "why": "long run did not repeat"}
    except RuntimeError as err:
        return {"verdict": "reference_failed", "why": str(err)[:80]}
    last = np.array(states[-n:])
    d_state = np.min(np.max(np.abs(last - [res.x_section, res.xdot_section]) / scale,
                            axis=1))
    xe = [x for r in runs[-n:] for x in r["x_ext"]]
    amp = 0.5 * (max(xe) - min(xe))
    sticks = sum(1 for r in runs[-n:] for e in r["events"] if e[1] == "stick")
    stops = sum(1 for r in runs[-n:] for e in r["events"] if e[1].endswith("_stop"))
    counts = (sticks, stops) == (res.sticks_per_period, res.stops_per_period)
    d = max(d_state * mod.L, abs(amp - res.amplitude))
    return {"check": "long_run", "diff_L": d / mod.L,
            "verdict": "agree" if counts and d <= CONTRACT * mod.L else "wrong_ok"}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--points", type=int, default=150)
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--json", default=str(ROOT / "benchmarks" / "results" /
                                          "forced_accuracy.json"))
    args = ap.parse_args(argv)
    sys.path.insert(0, str(ROOT))
    sys.path.insert(0, str(ROOT / "tests"))
    from benchmarks import common
    rng = np.random.default_rng(args.seed)
    classes = ("harmonics", "coexistence", "harmonic")
    rows = []
    for i in range(args.points):
        cls = classes[i % 3]
        kw, cos, sin, x0, xd0 = draw(rng, cls)
        r = compare(kw, cos, sin, x0, xd0)
        rows.append({"class": cls, "params": {k: float(v) for k, v in kw.items()},
                     "cos": None if cos is None else [float(x) for x in cos],
                     "sin": None if sin is None else [float(x) for x in sin],
                     "x0": x0, "xdot0": xd0, **r})
        if r["verdict"] == "wrong_ok":
            common.log(f"point {i} ({cls}) wrong with ok: {r}")
    summary = {}
    for cls in classes:
        mine = [r for r in rows if r["class"] == cls]
        diffs = [r["diff_L"] for r in mine if r["verdict"] == "agree" and "diff_L" in r]
        fl = [r["floquet_diff"] for r in mine if r["verdict"] == "agree" and "floquet_diff" in r]
        summary[cls] = {v: sum(r["verdict"] == v for r in mine) for v in
                        ("agree", "wrong_ok", "flagged", "reference_failed")}
        summary[cls].update(points=len(mine), max_diff_L=max(diffs, default=None),
                            long_check=sum(r["verdict"] == "agree" and "check" in r
                                           for r in mine),
                            max_floquet_diff=max(fl, default=None))
        common.log(f"{cls}: {summary[cls]}")
    common.save_json({"machine": common.machine(), "points": args.points,
                      "seed": args.seed, "contract_L": CONTRACT, "summary": summary,
                      "rows": rows}, args.json)
    common.log(f"saved {args.json}")



def stored_section(path=None) -> str:
    """The benchmarks/README.md section of the stored ``results/forced_accuracy.json``."""
    import json
    path = Path(path or ROOT / "benchmarks" / "results" / "forced_accuracy.json")
    if not path.is_file():
        return ""
    R = json.loads(path.read_text())
    m = R["machine"]
    from benchmarks.report import table
    rows = [[cls, r["points"], f"{r['agree']} ({r.get('long_check', 0)})",
             r["wrong_ok"], r["flagged"],
             r["reference_failed"],
             "-" if r["max_diff_L"] is None else f"{r['max_diff_L']:.1e}",
             "-" if r["max_floquet_diff"] is None else f"{r['max_floquet_diff']:.1e}"]
            for cls, r in R["summary"].items()]
    return "\n".join([
        "## Forced responses against the reference", "",
        f"`python -m benchmarks.forced_accuracy --points {R['points']} --seed {R['seed']}` "
        f"({m['date']}, commit `{m['git_commit'][:10]}`) writes "
        "`results/forced_accuracy.json`: random forced points in three classes (loads of "
        "2-3 harmonics with the anchor's motion; coexistence windows: steep Stribeck or "
        "static above kinetic friction on a belt under a load or the anchor's motion, "
        "where stick-slip and a slip response coexist; one cosine), each from a random "
        "start, solved by `sweepcore.attractor` (tol 1e-8) and by the independent "
        "reference from the same start. 'wrong ok': sweepcore says ok and the "
        f"reference's response differs (counts, or a length more than {R['contract_L']:g} L "
        "away, or periodic against aperiodic). In brackets, the points where the "
        "reference's own search failed and sweepcore's "
        "answer was checked against the reference's motion followed from the start "
        "(until it repeats; a motion creeping to the edge of the band where a slider "
        "on fixed ground rests for ever: towards the edge, placed by the load's "
        "extreme).", "",
        table(["class", "points", "agree (long run)", "wrong ok", "flagged", "reference failed",
               "largest difference [L]", "largest multiplier difference"], rows), ""])


if __name__ == "__main__":
    main()
