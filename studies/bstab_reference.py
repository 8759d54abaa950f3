"""Independent reference values for the exponential Stribeck law with damping (scipy only).

The published basin-stability case (bSTAB / pybasin friction case; Stender, Hoffmann &
Papangelo, "The Basin Stability of Bi-Stable Friction-Excited Oscillators", Lubricants
8(12):105, 2020): x'' + 2 xi x' + x = -sgn(x' - v_d) mu(|x' - v_d|), xi = 0.05,
mu(s) = mu_d + mu_d (mu_sd - 1) exp(-s/v0), mu_d = 0.5, mu_sd = 2, v0 = 0.5; in
sweepcore's parameters m = k = 1, c = 0.1, r_y = 1, r_k = 0.5, v_s = 0.5,
alpha1 = alpha2 = 0, v = v_d. Start states uniform in x in [-2, 2], x' in [0, 2].

Computed here with ``tests/reference.py`` (no sweepcore import):

* the Hopf point (linearised damping 0.1 - exp(-2 v) = 0: ln(10)/2) and the fold (the
  largest v with a stick-slip cycle, bisection to 1e-12 at two integration tolerances);
* per belt speed: steady sliding, the unstable slip cycle (shooting on the return map of
  the x maxima, Floquet multiplier by a central difference and by Liouville's formula),
  the stick-slip cycle from the breakaway point, and the exact basin fraction of steady
  sliding (the area of the unstable cycle's interior inside the box over the box area;
  polygon of 20001 points, checked against 40001 points at rtol 1e-12);
* next to the Hopf point, where the focus decays slowly, what the published classifier
  (max |x'| over t in [400, 500] <= 0.2 means steady sliding) makes of the interior: the
  starts of a regular grid of the box inside the unstable cycle integrated to t = 500
  (DOP853, rtol 1e-10, sampled at 100 Hz as bSTAB does), and the share classified as
  steady sliding; "classifier_expected" = exact fraction x that share, i.e. what an
  exact integrator with that classifier would report;
* further points of the law family away from the published case (Stribeck, damping and
  cubic terms together; m = 2, k = 3, c = 0.05, r_y = 1.2, r_k = 0.7, v_s = 0.3,
  alpha1 = 0.1, alpha2 = 0.02): Hopf point and fold, and at v = 0.3, 0.8 (stick-slip,
  unstable equilibrium), 1.3 (bistable) and 1.5 (steady sliding only): equilibrium,
  stick-slip cycle, slip cycles, basin fraction where bistable.

Run:  python studies/bstab_reference.py [--write]     (about a minute; prints a table;
--write saves studies/results/bstab_reference.json)
"""
import argparse
import datetime
import json
import math
import platform
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import scipy
from matplotlib.path import Path as MplPath
from scipy.integrate import solve_ivp

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
from tests.reference import (reference_basin_fraction, reference_equilibrium,  # noqa: E402
                             reference_cycle_polygon, reference_find_slip_cycles,
                             reference_fold, reference_hopf, reference_stick_slip_cycle)

OUT = ROOT / "studies" / "results" / "bstab_reference.json"
BSTAB = dict(m=1.0, k=1.0, r_y=1.0, alpha1=0.0, alpha2=0.0, c=0.1, r_k=0.5, v_s=0.5)
BOX = ((-2.0, 2.0), (0.0, 2.0))
SPEEDS = (1.175, 1.20, 1.25, 1.30, 1.40, 1.50, 1.55, 1.60, 1.70, 1.775, 1.80, 1.83)
# published Monte-Carlo basin fractions of steady sliding, 5,000 samples each
PUBLISHED = {1.175: 0.0132, 1.25: 0.080, 1.40: 0.213, 1.50: 0.304, 1.55: 0.354,
             1.70: 0.492, 1.775: 0.568}
N_SAMPLES = 5000
PUBLISHED_ERROR = {1.50: 0.0065}          # stated; elsewhere the binomial error
CLASSIFIER_SPEEDS = (1.175, 1.20, 1.25)   # where decay by t = 400 is slow
GRID_H = 0.0125                            # grid of starts for the classifier check
FAMILY = dict(m=2.0, k=3.0, r_y=1.2, r_k=0.7, v_s=0.3, alpha1=0.1, alpha2=0.02, c=0.05)
FAMILY_SPEEDS = (0.3, 0.8, 1.3, 1.5)

CYCLE_KEYS = ("x_max", "x_min", "amplitude", "mean", "period", "floquet",
              "floquet_liouville", "xdot_max")
STICK_KEYS = ("amplitude", "x_max", "x_min", "mean", "period", "stick_time", "xdot_max",
              "xdot_min")


def _pick(d, keys):
    return {k: float(d[k]) for k in keys}


def unstable_cycle(v, p=BSTAB):
    """The outermost slip cycle (for the published case: the unstable one)."""
    cycles = reference_find_slip_cycles(v=v, **p, n_scan=24)
    if not cycles:
        return None, 0
    return cycles[-1], len(cycles)


def classifier_share(v, cycle, h=GRID_H, chunk=250):
    """Share of the grid starts inside the unstable cycle (and the box) that the
    published rule (max |x'| over [400, 500] sampled at 100 Hz <= 0.2) calls steady
    sliding. Inside the cycle the motion never reaches belt speed, so the smooth
    sliding field (branch zdot < 0) is exact there; all starts of a chunk are
    integrated as one vector system."""
    (xl, xh), (yl, yh) = BOX
    gx = np.arange(xl + h / 2, xh, h)
    gy = np.arange(yl + h / 2, yh, h)
    X, Y = np.meshgrid(gx, gy)
    pts = np.column_stack([X.ravel(), Y.ravel()])
    _t, cx, cxd = reference_cycle_polygon(v=v, a=cycle["x_max"], n=20001, **BSTAB)
    inside = MplPath(np.column_stack([cx, cxd])).contains_points(pts)
    starts = pts[inside]
    m, k, c, r_k, dr, v_s = 1.0, 1.0, 0.1, 0.5, 0.5, 0.5

    def rhs(_t, y):
        n = y.size // 2
        x, xd = y[:n], y[n:]
        F = -(r_k + dr * np.exp((xd - v) / v_s))          # F(zdot), zdot < 0
        return np.concatenate([xd, (-k * x - c * xd - F) / m])

    t_eval = np.linspace(400.0, 500.0, 10001)
    fp = 0
    for i in range(0, len(starts), chunk):
        s = starts[i:i + chunk]
        y0 = np.concatenate([s[:, 0], s[:, 1]])
        sol = solve_ivp(rhs, (0.0, 500.0), y0, method="DOP853", rtol=1e-10, atol=1e-12,
                        t_eval=t_eval)
        xd = sol.y[len(s):]
        assert xd.max() < v
        fp += int(np.sum(np.abs(xd).max(axis=1) <= 0.2))
    return fp / len(starts), len(starts)


def bstab_rows():
    rows = []
    for v in SPEEDS:
        t0 = time.perf_counter()
        eq = reference_equilibrium(v=v, **BSTAB)
        cy, n_cycles = unstable_cycle(v)
        ss = reference_stick_slip_cycle(v=v, **BSTAB)
        bf = reference_basin_fraction(v=v, a=cy["x_max"], box=BOX, **BSTAB)
        bf2 = reference_basin_fraction(v=v, a=cy["x_max"], box=BOX, n=40001, rtol=1e-12,
                                       **BSTAB)
        row = dict(v=v, x_eq=eq["x_eq"], damping=eq["damping"], n_slip_cycles=n_cycles,
                   unstable_cycle=_pick(cy, CYCLE_KEYS), stick_slip=_pick(ss, STICK_KEYS),
                   basin_fraction=bf["fraction"],
                   basin_fraction_check=abs(bf2["fraction"] - bf["fraction"]))
        if v in PUBLISHED:
            p = PUBLISHED[v]
            sig = PUBLISHED_ERROR.get(v, math.sqrt(p * (1 - p) / N_SAMPLES))
            row.update(published=p, published_error=sig,
                       difference_in_errors=(bf["fraction"] - p) / sig)
        if v in CLASSIFIER_SPEEDS:
            share, n_in = classifier_share(v, cy)
            row.update(classifier_share_inside=share, classifier_grid_points=n_in,
                       classifier_expected=bf["fraction"] * share)
        row["seconds"] = time.perf_counter() - t0
        rows.append(row)
        print(f"| {v:.3f} | {cy['x_max']:.8f} | {cy['x_min']:.8f} | "
              f"{cy['amplitude']:.8f} | {cy['period']:.8f} | {cy['floquet']:.7f} | "
              f"{ss['amplitude']:.8f} | {ss['period']:.8f} | {ss['x_max']:.8f} | "
              f"{ss['x_min']:.8f} | {ss['mean']:.8f} | {bf['fraction']:.5f} | "
              + (f"{row['published']} +- {row['published_error']:.4f} | "
                 f"{row['difference_in_errors']:+.2f} | " if "published" in row
                 else "- | - | ")
              + (f"{row['classifier_expected']:.4f} |" if "classifier_expected" in row
                 else "- |") + f" {row['seconds']:.1f} s", flush=True)
    return rows


def family_rows():
    """Equilibrium, Hopf point, fold, stick-slip cycle and slip cycles (and, where an
    unstable cycle surrounds the stable equilibrium, the basin fraction in BOX) at a
    point with Stribeck, damping and cubic terms together."""
    args = (FAMILY["m"], FAMILY["k"], FAMILY["r_y"], FAMILY["alpha1"], FAMILY["alpha2"])
    kw = dict(c=FAMILY["c"], r_k=FAMILY["r_k"], v_s=FAMILY["v_s"])
    h = reference_hopf(*args, 0.8, 1.5, **kw)
    f = reference_fold(*args, 1.2, 1.6, **kw, xtol=1e-12)
    print(f"\nfamily point {FAMILY}:\nHopf at v = {h['v_hopf']:.10f} ({h['criticality']}), "
          f"fold (last stick-slip cycle) at v = {f['v_fold']:.10f}")
    rows = []
    for v in FAMILY_SPEEDS:
        t0 = time.perf_counter()
        eq = reference_equilibrium(v=v, **FAMILY)
        try:
            ss = _pick(reference_stick_slip_cycle(v=v, **FAMILY), STICK_KEYS)
        except ValueError:          # above the fold: the slide from breakaway spirals in
            ss = None
        cycles = reference_find_slip_cycles(v=v, **FAMILY, n_scan=24)
        row = dict(v=v, x_eq=eq["x_eq"], damping=eq["damping"], stable=bool(eq["stable"]),
                   stick_slip=ss, slip_cycles=[_pick(c, CYCLE_KEYS) for c in cycles])
        if eq["stable"] and cycles and cycles[-1]["floquet"] > 1 and ss is not None:
            row["basin_fraction"] = reference_basin_fraction(
                v=v, a=cycles[-1]["x_max"], box=BOX, **FAMILY)["fraction"]
        row["seconds"] = time.perf_counter() - t0
        rows.append(row)
        print(f"v = {v}: x_eq {eq['x_eq']:.12f}, damping {eq['damping']:+.10f}; "
              + ("no stick-slip cycle" if ss is None else
                 f"stick-slip amplitude {ss['amplitude']:.10f}, period {ss['period']:.10f}, "
                 f"x_max {ss['x_max']:.10f}, x_min {ss['x_min']:.10f}, mean "
                 f"{ss['mean']:.10f}, stick {ss['stick_time']:.10f}")
              + "; slip cycles "
              + (", ".join(f"(x_max {c['x_max']:.8f}, amplitude {c['amplitude']:.8f}, "
                           f"period {c['period']:.8f}, floquet {c['floquet']:.6f})"
                           for c in cycles) or "none")
              + (f"; basin fraction of steady sliding in the box {row['basin_fraction']:.6f}"
                 if "basin_fraction" in row else "")
              + f"  [{row['seconds']:.1f} s]")
    return dict(params=FAMILY, hopf=h, fold=f, rows=rows)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help=f"write {OUT.relative_to(ROOT)}")
    args = ap.parse_args(argv)
    t_all = time.perf_counter()

    t0 = time.perf_counter()
    hopf = reference_hopf(1.0, 1.0, 1.0, 0.0, 0.0, 1.0, 1.3, c=0.1, r_k=0.5, v_s=0.5)
    hopf.update(closed_form=math.log(10) / 2,
                error=hopf["v_hopf"] - math.log(10) / 2, seconds=time.perf_counter() - t0)
    print(f"Hopf: v = {hopf['v_hopf']:.12f} (ln(10)/2 = {math.log(10) / 2:.12f}, "
          f"{hopf['criticality']}) [{hopf['seconds']:.2f} s]")
    folds = {}
    for rtol in (1e-12, 1e-13):
        t0 = time.perf_counter()
        f = reference_fold(1.0, 1.0, 1.0, 0.0, 0.0, 1.7, 1.9, c=0.1, r_k=0.5, v_s=0.5,
                           xtol=1e-12, rtol=rtol)
        f["seconds"] = time.perf_counter() - t0
        folds[f"rtol={rtol:g}"] = f
        print(f"fold (last stick-slip cycle), rtol {rtol:g}: v = {f['v_fold']:.12f} "
              f"[{f['seconds']:.2f} s]")
    fold_values = [f["v_fold"] for f in folds.values()]

    print("\n| v | unstable x_max | x_min | amplitude | period | floquet | stick-slip "
          "amplitude | period | x_max | x_min | mean | exact fraction | published | "
          "(exact - pub)/err | classifier expected | time |")
    print("|" + "---|" * 16)
    rows = bstab_rows()
    family = family_rows()
    total = time.perf_counter() - t_all
    print(f"\ntotal {total:.1f} s")
    if args.write:
        try:
            commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, text=True,
                                    capture_output=True).stdout.strip()
        except OSError:
            commit = ""
        res = dict(
            generated_by="studies/bstab_reference.py", commit=commit,
            date=datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
            machine=dict(platform=platform.platform(), processor=platform.processor(),
                         python=platform.python_version(), numpy=np.__version__,
                         scipy=scipy.__version__),
            settings=dict(method="DOP853", rtol_cycles=1e-13, rtol_runs=1e-12,
                          polygon_points=20001, box=BOX, classifier_grid_h=GRID_H,
                          classifier_rule="max |x'| over t in [400, 500] <= 0.2 "
                                          "(sampled at 100 Hz) is steady sliding"),
            bstab=dict(params=BSTAB, hopf=hopf, fold=folds,
                       fold_spread=max(fold_values) - min(fold_values), rows=rows),
            family=family, seconds=total)
        OUT.parent.mkdir(exist_ok=True)
        OUT.write_text(json.dumps(res, indent=1) + "\n")
        print(f"wrote {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
