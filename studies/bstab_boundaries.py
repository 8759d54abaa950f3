"""Coexistence boundaries and hysteresis of the bSTAB friction case, against the
independent scipy values of studies/results/bstab_reference.json.

The case (Stender, Hoffmann & Papangelo, Lubricants 8(12):105, 2020): m = k = 1,
c = 0.1, r_y = 1, r_k = 0.5, v_s = 0.5, alpha1 = alpha2 = 0. Measured here:

* ``sweepcore.locate_boundaries`` over v in [1, 2] at tol 1e-10 and 1e-12: the
  subcritical Hopf point (from the unstable slip cycles) and the fold at grazing
  (where the unstable slip cycle reaches belt speed), with their error estimates;
* ``sweepcore.bifurcation_diagram`` over 201 belt speeds in [1, 2], up and down
  (as studies/bstab_hysteresis.toml; next to the Hopf point the motion leaves the
  weakly unstable focus slowly, and the diagram raises the budget of such a point
  by itself): the speeds between which each scan jumps, and where the unstable slip
  cycles were found.

Run:  python studies/bstab_boundaries.py [--write]   (a few seconds; --write saves
studies/results/bstab_boundaries.json, quoted in docs/physics.md)
"""
import argparse
import datetime
import json
import math
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
import sweepcore as sc  # noqa: E402
from sweepcore._kernels import codes  # noqa: E402

OUT = ROOT / "studies" / "results" / "bstab_boundaries.json"
REFERENCE = ROOT / "studies" / "results" / "bstab_reference.json"
BSTAB = dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.5, c=0.1, alpha1=0.0, alpha2=0.0)


def located(tol: float) -> dict:
    t0 = time.perf_counter()
    ds = sc.locate_boundaries(sc.Grid(**BSTAB, v=np.linspace(1.0, 2.0, 5)), xtol=1e-9,
                              tol=tol)
    out = {name: float(ds[name]) for name in
           ("v_hopf_subcritical", "v_hopf_subcritical_error", "v_fold", "v_fold_width",
            "v_star")}
    out["criticality"] = sc.law.CRITICALITY[int(ds.hopf_criticality)]
    out["seconds"] = time.perf_counter() - t0
    return out


def jumps(num: int = 201) -> dict:
    """Per scan: the last speed on the starting regime and the first beyond it."""
    t0 = time.perf_counter()
    v = np.linspace(1.0, 2.0, num)
    ds = sc.bifurcation_diagram(sc.Grid(**BSTAB, v=v), boundaries=False)  # as the study
    out = {}
    for branch in ("up", "down"):
        reg = ds.regime.sel(branch=branch).values
        order = np.arange(num) if branch == "up" else np.arange(num)[::-1]
        i = next(k for k in range(num - 1) if reg[order[k + 1]] != reg[order[k]])
        a, b = order[i], order[i + 1]
        out[branch] = dict(last=float(v[a]), first=float(v[b]),
                           regime_before=codes.REGIME_NAMES[int(reg[a])],
                           regime_after=codes.REGIME_NAMES[int(reg[b])])
    inside = np.isfinite(ds.unstable_amplitude.values)
    out["unstable_cycles"] = dict(points=int(inside.sum()),
                                  lowest=float(v[inside].min()),
                                  highest=float(v[inside].max()))
    # growth rate of the focus where the down scan leaves it (eq. 46)
    out["q_at_down_jump"] = float(sc.law.derived("q", dict(BSTAB,
                                                           v=out["down"]["first"])))
    out["points"], out["seconds"] = num, time.perf_counter() - t0
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true",
                    help=f"write {OUT.relative_to(ROOT)}")
    args = ap.parse_args(argv)
    ref = json.loads(REFERENCE.read_text())["bstab"]
    ref_hopf = math.log(10.0) / 2.0
    ref_fold = ref["fold"]["rtol=1e-13"]["v_fold"]
    res = {f"tol={tol:g}": located(tol) for tol in (1e-10, 1e-12)}
    print("| tol | v_hopf_subcritical | error est. | - ln(10)/2 | v_fold | width | "
          "- scipy fold |")
    print("|---|---|---|---|---|---|---|")
    for key, r in res.items():
        print(f"| {key[4:]} | {r['v_hopf_subcritical']:.10f} | "
              f"{r['v_hopf_subcritical_error']:.1e} | "
              f"{r['v_hopf_subcritical'] - ref_hopf:.1e} | {r['v_fold']:.10f} | "
              f"{r['v_fold_width']:.1e} | {r['v_fold'] - ref_fold:.1e} |")
    scans = jumps()
    for branch in ("up", "down"):
        j = scans[branch]
        print(f"{branch} scan: {j['regime_before']} at v = {j['last']:.3f}, "
              f"{j['regime_after']} at v = {j['first']:.3f}")
    if args.write:
        commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, text=True,
                                capture_output=True).stdout.strip()
        OUT.write_text(json.dumps(dict(
            generated_by="studies/bstab_boundaries.py", commit=commit,
            date=datetime.datetime.now(datetime.timezone.utc).isoformat(
                timespec="seconds"),
            params=BSTAB, reference=dict(hopf=ref_hopf, fold=ref_fold,
                                         source="studies/bstab_reference.py"),
            located=res, scans=scans), indent=1) + "\n")
        print(f"wrote {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
