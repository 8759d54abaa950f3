"""The autonomous answers of this checkout against an earlier commit's, array by array.

    python -m benchmarks.autonomous_identity --before 3d01dc9

Three autonomous maps (the paper's Hopf map over (v, alpha2); the bSTAB Stribeck
slider over (v, c); Coulomb friction over (v, k)), each with dop853, dopri5, rk4 and
the paper's group-preserving scheme, are swept by this checkout and by the commit
``--before`` (its own package, checked out with ``git worktree``, its own kernel
cache, in a process of its own). Every numeric output variable, the stepper calls a
point (``n_steps``) included, is compared bit for bit (NaN equal to NaN). Saves
``benchmarks/results/autonomous_identity.json``: the arrays compared, how many are
identical, and for any that are not, the cells that differ and the largest
difference.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
METHODS = ("dop853", "dopri5", "rk4", "gps")


def grids():
    import sweepcore as sc
    return {
        "hopf": sc.Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, v=np.linspace(0.5, 10, 48),
                        alpha2=np.geomspace(1e-3, 0.1, 24)),
        "stribeck": sc.Grid(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.5,
                            c=np.linspace(0.0, 0.2, 16), alpha1=0.0, alpha2=0.0,
                            v=np.linspace(0.2, 2.0, 32)),
        "coulomb": sc.Grid(m=1.0, k=np.linspace(0.5, 4, 16), r_y=1.0, alpha1=0.0,
                           alpha2=0.0, v=np.linspace(0.1, 3, 24)),
    }


def probe(save: str) -> None:
    """Sweep every map with every method in the sweepcore on PYTHONPATH."""
    import sweepcore as sc
    out = {}
    for name, grid in grids().items():
        for method in METHODS:
            ds = sc.sweep(grid, method=method, progress=False)
            for var in ds.data_vars:
                if ds[var].dtype.kind in "fiu":
                    out[f"{name}/{method}/{var}"] = ds[var].values
    np.savez(save, **out)


def _run(src: Path, cache: str, save: str) -> None:
    env = dict(os.environ, PYTHONPATH=str(src), NUMBA_CACHE_DIR=cache,
               SWEEPCORE_CACHE_DIR=cache)
    cp = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--probe", save],
                        env=env, cwd=src, capture_output=True, text=True, timeout=7200)
    if cp.returncode != 0:
        raise RuntimeError(cp.stderr[-3000:])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--before", default="3d01dc9", help="the commit to compare with")
    ap.add_argument("--probe", help=argparse.SUPPRESS)
    ap.add_argument("--json", default=str(ROOT / "benchmarks" / "results" /
                                          "autonomous_identity.json"))
    args = ap.parse_args(argv)
    if args.probe:
        probe(args.probe)
        return
    if str(ROOT) not in sys.path:
        sys.path.insert(0, str(ROOT))
    from benchmarks import common
    sha = subprocess.run(["git", "rev-parse", "--verify", args.before + "^{commit}"],
                         cwd=ROOT, capture_output=True, text=True, check=True).stdout.strip()
    with tempfile.TemporaryDirectory(prefix="sweepcore-identity-") as tmp:
        wt = Path(tmp) / "tree"
        subprocess.run(["git", "worktree", "add", "--detach", str(wt), sha], cwd=ROOT,
                       check=True, capture_output=True)
        try:
            for side, src in (("before", wt), ("after", ROOT)):
                common.log(f"sweeping the maps with {side}'s package")
                _run(src, str(Path(tmp) / f"cache-{side}"), str(Path(tmp) / f"{side}.npz"))
            a = dict(np.load(Path(tmp) / "before.npz"))
            b = dict(np.load(Path(tmp) / "after.npz"))
        finally:
            subprocess.run(["git", "worktree", "remove", "--force", str(wt)], cwd=ROOT,
                           capture_output=True)
    differ = {}
    for key in sorted(set(a) | set(b)):
        if key not in a or key not in b or a[key].shape != b[key].shape:
            differ[key] = "missing or reshaped"
            continue
        x, y = a[key], b[key]
        same = (x == y) | (np.isnan(x) & np.isnan(y)) if x.dtype.kind == "f" else x == y
        if not same.all():
            differ[key] = {"cells": int((~same).sum()),
                           "largest": float(np.nanmax(np.abs(x - y)))}
    result = {"machine": common.machine(), "commit_before": sha,
              "maps": list(grids()), "methods": list(METHODS),
              "arrays": len(set(a) | set(b)),
              "identical": len(set(a) | set(b)) - len(differ), "differ": differ}
    Path(args.json).write_text(json.dumps(result, indent=1) + "\n")
    common.log(f"{result['identical']} of {result['arrays']} arrays identical; "
               f"saved {args.json}")


def stored_section(path=None) -> str:
    """The benchmarks/README.md section of the stored ``results/autonomous_identity.json``."""
    path = Path(path or ROOT / "benchmarks" / "results" / "autonomous_identity.json")
    if not path.is_file():
        return ""
    R = json.loads(path.read_text())
    m = R["machine"]
    differ = "none differ" if not R["differ"] else \
        "differing: " + ", ".join(f"`{k}`" for k in R["differ"])
    return "\n".join([
        "## Autonomous answers against an earlier commit", "",
        f"`python -m benchmarks.autonomous_identity --before {R['commit_before'][:7]}` "
        f"({m['date']}, commit `{m['git_commit'][:10]}`): the maps "
        f"{', '.join(R['maps'])} swept with {', '.join(R['methods'])} by this checkout "
        "and by that commit's package, every numeric output (stepper calls a point "
        f"included) compared bit for bit: {R['identical']} of {R['arrays']} arrays "
        f"identical, {differ}.", ""])


if __name__ == "__main__":
    main()
