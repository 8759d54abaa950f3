"""Which Runge-Kutta pair for the slip cycles: right-hand-side evaluations against error.

The map's dearest points are slip cycles (about 60 % of its stepper calls), whose
returns are integrated at the user's tolerance and, for the last two returns, at
``0.45 tol (1 - P')`` (docs/methods.md): 1e-8 to about 1e-10 for the default tol.
Whether a higher-order pair would pay there is a question of evaluations per
period at equal error, measured here with scipy's implementations of both pairs
(``RK45`` = Dormand-Prince 5(4), sweepcore's dopri5; ``DOP853``, Hairer's 8(5,3))
on the smooth sliding equation of the paper's slider (eqs. 40-41) over one period of
a slip cycle found by ``sweepcore.attractor``. Error: the state after one period
against DOP853 at rtol 2.2e-14 (100 eps, scipy's smallest), relative to the length
scale r_y/k + |v|/omega.

    python benchmarks/pair_choice.py          # prints a table, writes results/pair_choice.json

Cost per step is not measured: a DOP853 step takes 12 evaluations (11 with FSAL
reuse) against dopri5's 6, so the evaluation ratio is the step-cost ratio only if the
driver's own work per step (event scan, bookkeeping) is small; the JSON keeps nfev.
"""
from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

PAPER = dict(m=5.0, k=50.0, r_y=10.0, alpha1=1.0)
POINTS = ((4.71, 0.001056), (6.05, 0.001435), (7.54, 0.001056), (5.5, 0.01), (5.7, 0.01))   # (v, alpha2)
RTOLS = (1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11)


def _rhs(m, k, r_y, v, a1, a2):
    """The sliding field (x, zdot) of the peers' independent solver, slip with
    sgn(zdot) = -1 (eqs. 40-41), without its third component (the integral of x)."""
    from benchmarks.peers import _slide_rhs
    f3 = _slide_rhs(m, k, r_y, v, a1, a2, -1.0)
    return lambda t, y: f3(t, (y[0], y[1], 0.0))[:2]


def one_point(v, a2):
    import sweepcore as sc
    p = dict(PAPER, v=v, alpha2=a2)
    att = sc.attractor(sc.Params(**p))
    if att.regime != "slip_cycle":
        return None
    f = _rhs(p["m"], p["k"], p["r_y"], v, p["alpha1"], a2)
    y0 = [att.x_max, -v]                            # the section: xdot = 0 at x_max
    T = att.period
    L = p["r_y"] / p["k"] + v / math.sqrt(p["k"] / p["m"])
    # scipy's smallest rtol (100 eps; below it scipy warns and uses this one)
    tight = 100 * np.finfo(float).eps
    ref = solve_ivp(f, (0, T), y0, method="DOP853", rtol=tight, atol=tight * L).y[:, -1]
    rows = []
    for method in ("RK45", "DOP853"):
        for rtol in RTOLS:
            sol = solve_ivp(f, (0, T), y0, method=method, rtol=rtol, atol=rtol * L)
            err = float(np.max(np.abs(sol.y[:, -1] - ref) / np.array([L, L * math.sqrt(
                p["k"] / p["m"])])))
            rows.append({"method": method, "rtol": rtol, "nfev": int(sol.nfev),
                         "steps": int(sol.t.size - 1), "error_over_L": err})
    return {"v": v, "alpha2": a2, "v_over_v_star": v / math.sqrt(p["alpha1"] / (3 * a2)),
            "floquet": att.floquet, "period_s": T, "rows": rows}


def nfev_at(rows, method, err):
    """Evaluations to reach ``err`` (log-log interpolation along the rtol ladder)."""
    pts = sorted((r["error_over_L"], r["nfev"]) for r in rows if r["method"] == method
                 and r["error_over_L"] > 0)
    e, n = np.log([q[0] for q in pts]), np.log([q[1] for q in pts])
    if not e[0] <= math.log(err) <= e[-1]:
        return None
    return float(np.exp(np.interp(math.log(err), e, n)))


def main():
    res = {"points": [one_point(v, a2) for v, a2 in POINTS]}
    res["points"] = [r for r in res["points"] if r]
    print("| v / v* | error / L | RK45 nfev | DOP853 nfev | DOP853 / RK45 |")
    print("|---|---|---|---|---|")
    res["ratios"] = []
    for r in res["points"]:
        for err in (1e-7, 1e-8, 1e-9, 1e-10):
            a, b = nfev_at(r["rows"], "RK45", err), nfev_at(r["rows"], "DOP853", err)
            if a and b:
                res["ratios"].append({"v_over_v_star": r["v_over_v_star"], "error": err,
                                      "nfev_rk45": a, "nfev_dop853": b, "ratio": b / a})
                print(f"| {r['v_over_v_star']:.3f} | {err:g} | {a:.0f} | {b:.0f} | "
                      f"{b / a:.2f} |")
    out = ROOT / "benchmarks" / "results" / "pair_choice.json"
    out.write_text(json.dumps(res, indent=1))
    print(f"written {out.relative_to(ROOT)}")


if __name__ == "__main__":
    import argparse
    argparse.ArgumentParser(description=__doc__,
                            formatter_class=argparse.RawDescriptionHelpFormatter
                            ).parse_args()
    main()
