"""The cost of forced response maps against the Hopf map, per point, in one run, now
and at an earlier commit, beside the independent scipy reference on a sample.

    python -m benchmarks.forced [--side 64] [--repeats 3] [--sample 6] [--before REV]

Four forced maps (m = k = 1, r_y = 1, c = 0.05; Omega/omega in [0.3, 3], started at
rest at x = 0): on fixed ground (v = 0, Den Hartog's case) and on a belt (v = 0.5
cm/s), each with F0/r_y in [0.2, 4] and in [1.2, 4] (the larger loads: more of the
map moves every period). The Hopf map is the paper's (m = 5, k = 50, r_y = 10,
alpha1 = 1, v in [0.5, 10], alpha2 in [1e-3, 0.1], started stuck on the belt) on the
same side. Each runs through the kernels a sweep runs (``sweepcore.forced.responses``
and ``sweepcore.execute.attractors``: no xarray), on one thread, warm; CPU seconds per
point, medians over the repeats; the ratio is forced / Hopf within one probe. With
``--before REV`` the same maps run in probes of that commit's package (a temporary
``git worktree``, its own kernel cache), interleaved with this checkout's, so that
drifting load on a shared machine hits both alike; stepper calls a point are
deterministic. The reference (``tests/reference_forced.py``: scipy DOP853 with exact
sticks, a Python loop over points) runs on ``--sample`` points of each forced map, and
its answers are compared with sweepcore's (amplitude, mean, counts). Saves
``benchmarks/results/forced.json``.
"""
from __future__ import annotations

import argparse
import inspect
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent

# the forced maps: name -> (v, F0 range)
FORCED = {"ground": (0.0, (0.2, 4.0)), "belt": (0.5, (0.2, 4.0)),
          "ground_F0_1.2-4": (0.0, (1.2, 4.0)), "belt_F0_1.2-4": (0.5, (1.2, 4.0))}


def grids(side):
    """The maps as ``{name: Grid}`` (whatever sweepcore is importable builds them)."""
    import sweepcore as sc
    om = np.linspace(0.3, 3.0, side)
    out = {name: sc.Grid(m=1.0, k=1.0, r_y=1.0, v=v, c=0.05, Omega=om,
                         F0=np.linspace(*f0, side), x0=0.0, xdot0=0.0)
           for name, (v, f0) in FORCED.items()}
    out["hopf"] = sc.Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0,
                          v=np.linspace(0.5, 10.0, side), alpha2=np.geomspace(1e-3, 0.1, side))
    return out


def run(grid, o):
    """The kernels of a sweep on every row of ``grid``: (CPU seconds, rows out).
    Works with this checkout and with the versions before the ``load`` keyword."""
    from sweepcore import execute, forced
    from sweepcore._kernels import layout
    P = grid.rows(0, grid.size)
    t = time.process_time()
    if grid.forced:
        out = np.empty((grid.size, layout.NFOB))
        if "loads" in inspect.signature(forced.responses).parameters:
            forced.responses(P, grid.laws, grid.loads, o, out, False)
        else:
            forced.responses(P, grid.laws, o, out, False)
    else:
        out = np.empty((grid.size, layout.NOBS))
        execute.attractors(P, grid.laws, o, out, False)
    return time.process_time() - t, out


def probe(side: int, repeats: int, save: str | None = None) -> dict:
    """Every map ``repeats`` times after a warm-up (compiling or loading the kernels)
    in this process, one thread: per map the CPU microseconds a point of each repeat,
    stepper calls a point, regime and status counts."""
    import numba
    from sweepcore._kernels import codes, layout
    from sweepcore.options import make_options
    numba.set_num_threads(1)
    maps = grids(side)
    o = make_options("auto", tol=1e-8)
    for grid in maps.values():
        run(grid, o)
    cpu = {name: [] for name in maps}
    outs = {}
    for _ in range(repeats):
        for name, grid in maps.items():
            seconds, outs[name] = run(grid, o)
            cpu[name].append(seconds / grid.size * 1e6)
    res = {}
    for name, out in outs.items():
        entry = {"cpu_us_per_point": cpu[name],
                 "stepper_calls_mean": float(out[:, layout.OB_NSTEPS].mean()),
                 "stepper_calls_median": float(np.median(out[:, layout.OB_NSTEPS])),
                 "regimes": {codes.REGIME_NAMES[int(k)]: int(c) for k, c in
                             zip(*np.unique(out[:, layout.OB_REGIME], return_counts=True))},
                 "statuses": {codes.STATUS_NAMES[int(k)]: int(c) for k, c in
                              zip(*np.unique(out[:, layout.OB_STATUS], return_counts=True))}}
        if name != "hopf":
            stops = out[:, layout.OB_STOPS_PER_PERIOD]
            entry["stops_per_period"] = {int(k): int(c) for k, c in
                                         zip(*np.unique(stops[np.isfinite(stops)],
                                                        return_counts=True))}
        res[name] = entry
    if save:
        np.savez(save, **outs)
    commit = subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True,
                            cwd=Path(sys.modules["sweepcore"].__file__).parent).stdout.strip()
    return {"commit": commit, "maps": res}


def _run_probe(src: Path, side: int, repeats: int, cache: str, save: str) -> dict:
    env = dict(os.environ, PYTHONPATH=str(src), NUMBA_CACHE_DIR=cache,
               SWEEPCORE_CACHE_DIR=cache)
    cp = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--probe",
                         "--side", str(side), "--repeats", str(repeats), "--save", save],
                        env=env, cwd=src, capture_output=True, text=True, timeout=7200)
    if cp.returncode != 0:
        raise RuntimeError(cp.stderr[-3000:])
    return json.loads(cp.stdout.strip().splitlines()[-1])


def reference_sample(grid, out, count, seed=1):
    """The scipy reference at ``count`` random points of a forced grid: its seconds
    a point and the largest differences from sweepcore's answers."""
    sys.path.insert(0, str(ROOT / "tests"))
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


def _summary(probes: list) -> dict:
    """Medians over rounds: CPU microseconds a point, the ratio to the Hopf map within
    each probe, stepper calls a point."""
    names = probes[0]["maps"]
    out = {}
    for name in names:
        per = [float(np.median(p["maps"][name]["cpu_us_per_point"])) for p in probes]
        ratio = [float(np.median(p["maps"][name]["cpu_us_per_point"])) /
                 float(np.median(p["maps"]["hopf"]["cpu_us_per_point"])) for p in probes]
        m = probes[0]["maps"][name]
        out[name] = {"cpu_us_per_point": float(np.median(per)),
                     "ratio_to_hopf": float(np.median(ratio)), "round_ratios": ratio,
                     **{k: m[k] for k in m if k != "cpu_us_per_point"}}
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--side", type=int, default=64, help="points per axis (default 64)")
    ap.add_argument("--repeats", type=int, default=3, help="timed runs a probe")
    ap.add_argument("--rounds", type=int, default=2,
                    help="interleaved rounds of probes (default 2)")
    ap.add_argument("--sample", type=int, default=6,
                    help="reference points per forced map (default 6)")
    ap.add_argument("--before", default=None,
                    help="an earlier commit to probe beside this checkout")
    ap.add_argument("--probe", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--save", default=None, help=argparse.SUPPRESS)
    ap.add_argument("--json", default=str(ROOT / "benchmarks" / "results" / "forced.json"))
    args = ap.parse_args(argv)
    if args.probe:      # in the sweepcore of PYTHONPATH (this checkout or another)
        print(json.dumps(probe(args.side, args.repeats, args.save)))
        return
    if str(ROOT) not in sys.path:
        sys.path.insert(0, str(ROOT))
    from benchmarks import common
    sides = {"after": ROOT}
    with tempfile.TemporaryDirectory(prefix="sweepcore-forced-") as tmp:
        sha = None
        if args.before:
            sha = subprocess.run(["git", "rev-parse", "--verify", args.before + "^{commit}"],
                                 cwd=ROOT, capture_output=True, text=True,
                                 check=True).stdout.strip()
            wt = Path(tmp) / "tree"
            subprocess.run(["git", "worktree", "add", "--detach", str(wt), sha], cwd=ROOT,
                           check=True, capture_output=True)
            sides = {"before": wt, "after": ROOT}
        try:
            probes = {side: [] for side in sides}
            for _ in range(args.rounds):
                for side, src in sides.items():
                    probes[side].append(_run_probe(src, args.side, args.repeats,
                                                   str(Path(tmp) / side),
                                                   str(Path(tmp) / f"{side}.npz")))
                    common.log(f"{side}: " + ", ".join(
                        f"{n} {np.median(m['cpu_us_per_point']):.1f} us"
                        for n, m in probes[side][-1]["maps"].items()))
            outs = dict(np.load(Path(tmp) / "after.npz"))
        finally:
            if sha:
                subprocess.run(["git", "worktree", "remove", "--force", str(Path(tmp) / "tree")],
                               cwd=ROOT, capture_output=True)
    result = {"machine": common.machine(), "side": args.side, "repeats": args.repeats,
              "rounds": args.rounds, "tol": 1e-8, "threads": 1,
              "commit_before": sha, **{side: _summary(p) for side, p in probes.items()}}
    maps = grids(args.side)
    for name in FORCED:
        ref_s, worst = reference_sample(maps[name], outs[name], args.sample)
        per = result["after"][name]["cpu_us_per_point"] * 1e-6
        result["after"][name]["reference"] = {"cpu_s_per_point": ref_s,
                                              "sweepcore_speedup": ref_s / per, **worst}
    for name in maps:
        a = result["after"][name]
        b = result.get("before", {}).get(name)
        common.log(f"{name}: {a['cpu_us_per_point']:.1f} us/point CPU, x{a['ratio_to_hopf']:.2f} "
                   f"the Hopf map, {a['stepper_calls_mean']:.0f} stepper calls a point"
                   + (f" (before: x{b['ratio_to_hopf']:.2f}, {b['stepper_calls_mean']:.0f} "
                      "calls)" if b else ""))
    common.save_json(result, args.json)
    common.log(f"saved {args.json}")



NAMES = {"ground": "fixed ground, F0/r_y 0.2-4", "belt": "belt v = 0.5, F0/r_y 0.2-4",
         "ground_F0_1.2-4": "fixed ground, F0/r_y 1.2-4",
         "belt_F0_1.2-4": "belt v = 0.5, F0/r_y 1.2-4", "hopf": "the Hopf map"}


def stored_section(path=None) -> str:
    """The benchmarks/README.md section of the stored ``results/forced.json``."""
    path = Path(path or ROOT / "benchmarks" / "results" / "forced.json")
    if not path.is_file():
        return ""
    R = json.loads(path.read_text())
    if "after" not in R:
        return ""
    m = R["machine"]
    before = R.get("before", {})
    rows = []
    for name, a in R["after"].items():
        b = before.get(name)
        ref = a.get("reference", {})
        rows.append([NAMES.get(name, name), f"{a['cpu_us_per_point']:.1f}",
                     f"{b['cpu_us_per_point']:.1f}" if b else "-",
                     f"{a['ratio_to_hopf']:.2f}",
                     f"{b['ratio_to_hopf']:.2f}" if b else "-",
                     f"{a['stepper_calls_mean']:.0f}",
                     f"{b['stepper_calls_mean']:.0f}" if b else "-",
                     ", ".join(f"{k} {v}" for k, v in a["statuses"].items()),
                     f"{ref['amplitude_L']:.1e}" if ref else "-"])
    from benchmarks.report import table
    head = ["map (64 x 64 unless said)", "CPU us a point", "before", "x Hopf map",
            "x Hopf map before", "stepper calls a point", "before", "statuses",
            "reference: largest amplitude difference [L]"]
    return "\n".join([
        "## Forced maps", "",
        f"`python -m benchmarks.forced --before {R.get('commit_before', '')[:7]}` "
        f"({m['date']}, commit `{m['git_commit'][:10]}`; {R['side']} x {R['side']} maps, "
        f"one thread, warm, {R['rounds']} interleaved rounds of {R['repeats']} runs, "
        "medians; 'before' is the commit's own package in a probe of its own, run "
        "beside this checkout's) writes `results/forced.json`: the forced response "
        "maps of m = k = 1, r_y = 1, c = 0.05, Omega in [0.3, 3] rad/s, started at rest "
        "at x = 0, CPU per point against the Hopf map's in the same probe (m = 5, k = 50, "
        "r_y = 10, alpha1 = 1, v in [0.5, 10], alpha2 in [1e-3, 0.1], started stuck), "
        "and the stepper calls a point (deterministic). The reference (scipy DOP853 "
        "with exact sticks, `tests/reference_forced.py`) reruns a few points of each "
        "forced map:", "",
        table(head, rows), ""])


if __name__ == "__main__":
    main()
