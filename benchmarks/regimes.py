"""Where the Hopf map's stepper calls go, by regime, now and at an earlier commit.

The table: for each regime band of the map (v against v* = sqrt(alpha1/(3 alpha2))),
the number of points, the mean stepper calls a point (``OB_NSTEPS``) and the share of
all calls. Step counts are deterministic (the same on every machine and run), so the
table of an earlier commit is as reproducible as today's; its wall time is measured
here, in the same run, by a probe that imports that commit's package from a
temporary ``git worktree`` (before and after probes interleaved, so drifting load on a
shared machine hits both alike).

    python -m benchmarks.regimes --probe 3       # this checkout: JSON on stdout
    python -m benchmarks.regimes 6b6a0bf --out benchmarks/results/events.json --hardest 1
        # before/after against commit 6b6a0bf, saved with the machine and the date,
        # and this checkout's map on its hardest points against the independent
        # references (benchmarks/hopf_map.py)
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

ROOT = Path(__file__).resolve().parent.parent
# the kernels before the friction law became an interface (compiled per method and
# law kind): the map must be the same and no slower (``benchmarks/run.py`` full mode)
BEFORE = "23b2570"

# regime codes of the kernels' table (sweepcore/_kernels/codes.py): equilibrium 0,
# slip cycle 1, stick-slip 2. Bands as nu = v / v*.
BANDS = (("stick-slip", 2, 0.0, np.inf),
         ("slip cycle, v < 0.9 v*", 1, 0.0, 0.9),
         ("slip cycle, 0.9-0.99 v*", 1, 0.9, 0.99),
         ("slip cycle, 0.99-1 v* (hardest)", 1, 0.99, np.inf),
         ("equilibrium, 1-1.1 v*", 0, 0.0, 1.1),
         ("equilibrium, v > 1.1 v*", 0, 1.1, np.inf))


def table(v, alpha1, alpha2, regime, steps) -> dict:
    """The per-regime table of one map run (arrays over its points)."""
    nu = v / np.sqrt(alpha1 / (3.0 * alpha2))
    total = float(steps.sum())
    rows = []
    for name, code, lo, hi in BANDS:
        sel = (regime == code) & (nu >= lo) & (nu < hi)
        n = int(sel.sum())
        rows.append({"regime": name, "points": n,
                     "steps_mean": float(steps[sel].mean()) if n else None,
                     "steps_max": float(steps[sel].max()) if n else None,
                     "share": float(steps[sel].sum()) / total if total else None})
    other = int(len(v) - sum(r["points"] for r in rows))
    return {"rows": rows, "steps_total": total, "points": int(len(v)),
            "points_other": other}


# ------------------------------------------------------------------ the probe
def _maps():
    """The maps a probe times: the paper's 256 x 256 Hopf map (``studies/
    hopf_map.toml``) and the 128 x 64 Stribeck map (``studies/stribeck_map.toml``),
    as (name, Grid keywords)."""
    return (("cubic", dict(m=5.0, k=50.0, r_y=10.0, alpha1=1.0,
                           v=np.linspace(0.5, 10.0, 256), alpha2=np.geomspace(1e-3, 0.1, 256))),
            ("stribeck", dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.5,
                              v=np.linspace(0.2, 3.0, 128),
                              c=np.geomspace(0.02, 0.6, 64))))


def _probe(repeats: int, save: str | None = None) -> dict:
    """Run the maps in whatever sweepcore is importable: its own Grid builds the rows
    and its kernels run them (``sweepcore.compiled``, or the entry kernel
    ``attractor_rows_parallel`` of the versions before it; this script runs with an
    older checkout's package, so it imports nothing else of this one). ``save``: an
    .npz file for the observables of every map (compared between the sides)."""
    from sweepcore._kernels import layout as L
    from sweepcore.grid import Grid
    from sweepcore.options import make_options
    try:
        from sweepcore import compiled
        from sweepcore.laws import ANALYTIC

        def run(P, o, out):
            compiled.attractors(P, (ANALYTIC,), o, out, parallel=True)
    except ImportError:
        from sweepcore._kernels.attractor import attractor_rows_parallel as run
    o = make_options("auto", tol=1e-8)
    res, arrays = {}, {}
    for name, kw in _maps():
        grid = Grid(**kw)
        P = grid.rows(0, grid.size)
        out = np.empty((grid.size, L.NOBS))
        run(P[:4], o, out[:4])
        times = []
        for _ in range(repeats):
            t0 = time.perf_counter()
            run(P, o, out)
            times.append(time.perf_counter() - t0)
        res[name] = {"times_s": times}
        arrays[name] = out.copy()
        if name == "cubic":
            V = P[:, L.V]
            A = np.repeat(kw["alpha2"][None, :], kw["v"].size, axis=0).ravel()
            res["table"] = table(V, 1.0, A, out[:, L.OB_REGIME], out[:, L.OB_NSTEPS])
    if save:
        np.savez(save, **arrays)
    commit = subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True,
                            cwd=Path(sys.modules["sweepcore"].__file__).parent).stdout.strip()
    return {"commit": commit, "times_s": res["cubic"]["times_s"],
            "stribeck_times_s": res["stribeck"]["times_s"], "table": res["table"]}


def compare_outputs(before: str, after: str) -> dict:
    """Rows of each map whose observables differ between two probes' .npz files
    (NaN equal to NaN), and the largest relative difference of those observables."""
    a, b = np.load(before), np.load(after)
    out = {}
    for name in a.files:
        x, y = a[name], b[name]
        same = (x == y) | (np.isnan(x) & np.isnan(y))
        rel = np.abs(x - y) / np.maximum(np.abs(x), np.abs(y))
        rel = rel[~same & np.isfinite(rel)]
        out[name] = {"rows": int(x.shape[0]), "rows_differing": int((~same).any(axis=1).sum()),
                     "max_rel_difference": float(rel.max()) if rel.size else 0.0}
    return out


def _run_probe(src: Path, repeats: int, cache: str, save: str) -> dict:
    env = dict(os.environ, PYTHONPATH=str(src), NUMBA_CACHE_DIR=cache,
               SWEEPCORE_CACHE_DIR=cache)
    cp = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--probe",
                         str(repeats), "--save", save], env=env, cwd=src,
                        capture_output=True, text=True, timeout=1800)
    if cp.returncode != 0:
        raise RuntimeError(cp.stderr[-2000:])
    return json.loads(cp.stdout.strip().splitlines()[-1])


def before_after(ref: str, rounds: int = 3, repeats: int = 3) -> dict:
    """Probes of commit ``ref`` and of this checkout, interleaved ``rounds`` times
    (each ``repeats`` timed map runs after a warm-up); each side compiles once into
    its own private cache. The ratio is the median over rounds of before/after."""
    try:
        sha = subprocess.run(["git", "rev-parse", "--verify", ref + "^{commit}"], cwd=ROOT,
                             capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return {"skipped": f"commit {ref} not in this clone"}
    with tempfile.TemporaryDirectory(prefix="sweepcore-before-") as tmp:
        wt = Path(tmp) / "tree"
        subprocess.run(["git", "worktree", "add", "--detach", str(wt), sha], cwd=ROOT,
                       check=True, capture_output=True)
        try:
            runs = {"before": [], "after": []}
            for _ in range(rounds):
                for side, src in (("before", wt), ("after", ROOT)):
                    runs[side].append(_run_probe(src, repeats, str(Path(tmp) / side),
                                                 str(Path(tmp) / f"{side}.npz")))
            outputs = compare_outputs(str(Path(tmp) / "before.npz"),
                                      str(Path(tmp) / "after.npz"))
        finally:
            subprocess.run(["git", "worktree", "remove", "--force", str(wt)], cwd=ROOT,
                           capture_output=True)
    med = {s: [float(np.median(r["times_s"])) for r in runs[s]] for s in runs}
    strib = {s: [float(np.median(r["stribeck_times_s"])) for r in runs[s]] for s in runs}
    return {"ref": ref, "commit_before": sha, "commit_after": runs["after"][0]["commit"],
            "outputs": outputs,
            "stribeck_map": {"median_s_before": float(np.median(strib["before"])),
                         "median_s_after": float(np.median(strib["after"])),
                         "speedup": float(np.median([b / a for b, a in
                                                     zip(strib["before"], strib["after"])])),
                         "round_medians_s": strib},
            "before": runs["before"][0]["table"], "after": runs["after"][0]["table"],
            "steps_identical_across_rounds": all(
                r["table"] == runs[s][0]["table"] for s in runs for r in runs[s]),
            "median_s_before": float(np.median(med["before"])),
            "median_s_after": float(np.median(med["after"])),
            "speedup": float(np.median([b / a for b, a in zip(med["before"], med["after"])])),
            "round_medians_s": med}


def hardest(per_column: int) -> dict:
    """This checkout's Hopf map at the default tolerance on its hardest points (the
    slip cycles next to v* in each alpha2 column) against the independent references
    of ``benchmarks/hopf_map.py`` (scipy shooting or the normal form)."""
    from sweepcore import compiled
    from sweepcore._kernels import layout as L
    from sweepcore.grid import Grid
    from sweepcore.laws import ANALYTIC
    from sweepcore.options import make_options

    from . import hopf_map
    grid = Grid(**dict(_maps())["cubic"])
    P = grid.rows(0, grid.size)
    out = np.empty((grid.size, L.NOBS))
    compiled.attractors(P, (ANALYTIC,), make_options("auto", tol=1e-8), out, parallel=True)
    return hopf_map.hardest_points(P, {1e-8: out}, per_column)


if __name__ == "__main__":
    import argparse
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("commit", nargs="?", default=BEFORE,
                    help=f"the earlier commit to compare with (default {BEFORE})")
    ap.add_argument("--probe", type=int, metavar="N",
                    help="time N runs of this checkout's maps, print JSON (the probe)")
    ap.add_argument("--save", default=None, help="with --probe: .npz of the observables")
    ap.add_argument("--rounds", type=int, default=3, help="interleaved rounds (default 3)")
    ap.add_argument("--out", default=None, help="save the comparison as JSON here")
    ap.add_argument("--hardest", type=int, default=0, metavar="N",
                    help="also check N hardest points per alpha2 column of the map")
    args = ap.parse_args()
    if args.probe is not None:
        print(json.dumps(_probe(args.probe, args.save)))
    else:
        res = before_after(args.commit, args.rounds)
        if args.hardest:
            res["hardest_points_after"] = hardest(args.hardest)
        if args.out:
            from .common import machine
            res["machine"] = machine()
            res["date"] = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
            Path(args.out).write_text(json.dumps(res, indent=1) + "\n")
        print(json.dumps(res, indent=1))
