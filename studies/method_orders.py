"""Measured order of every method, and how GPS's first-order error moves the Hopf boundary.

Run:  python studies/method_orders.py      (about a minute)
Prints markdown tables; docs/methods.md quotes them.
"""
import math

import numpy as np

import sweepcore as sc
from sweepcore import law

T = 1.5  # inside the first sliding arc after the slip (smooth order)
P0 = sc.Params(5.0, 50.0, 10.0, 5.0, 1.0, 0.0)
P1 = sc.Params(5.0, 50.0, 10.0, 5.0, 1.0, 0.01)


def x_end(p, method, **kw):
    return sc.simulate(p, T, method=method, output_dt=T, **kw).x.values[-1]


def orders():
    ref = {0: x_end(P0, "exact"), 1: x_end(P1, "dopri5", tol=1e-13)}
    per = sc.attractor(P1, method="dopri5", tol=1e-12).period
    print("| method | ladder | slope, alpha2 = 0 vs exact | slope, alpha2 = 0.01 vs tight "
          "| slope of the stick-slip period (across events) |")
    print("|---|---|---|---|---|")
    for meth, dts in (("gps", [2e-3, 1e-3, 5e-4, 2.5e-4]), ("rk4", [0.04, 0.02, 0.01, 0.005])):
        s = []
        for i, p in enumerate((P0, P1)):
            e = [abs(x_end(p, meth, dt=d) - ref[i]) for d in dts]
            s.append(np.polyfit(np.log(dts), np.log(e), 1)[0])
        e = [abs(sc.attractor(P1, method=meth, dt=d).period - per) for d in dts[1:]]
        sp = np.polyfit(np.log(dts[1:]), np.log(e), 1)[0]
        print(f"| {meth} | dt = {dts} s | {s[0]:.2f} | {s[1]:.2f} | {sp:.2f} |")
    tols = [1e-6, 1e-8, 1e-10]
    lx = P0.r_y / P0.k + P0.v / P0.omega
    for meth in ("dopri5", "dop853"):
        e0 = [abs(x_end(P0, meth, tol=t) - ref[0]) / lx for t in tols]
        e1 = [abs(x_end(P1, meth, tol=t) - ref[1]) / lx for t in tols]
        print(f"| {meth} | tol = {tols} | error/(tol L) = "
              f"{', '.join(f'{e / t:.2g}' for e, t in zip(e0, tols))} | "
              f"{', '.join(f'{e / t:.2g}' for e, t in zip(e1, tols))} | |")
    print()


def hopf_shift():
    """Bisection on v for the cycle -> equilibrium switch, per method."""
    a1, a2 = 1.0, 0.01
    vs = float(law.derived("v_star", {"alpha1": a1, "alpha2": a2}))
    print(f"| method | step | measured v* [cm/s] | prediction sqrt((alpha1 + k dt)/(3 alpha2)) "
          f"| error vs v* = {vs:.4f} |")
    print("|---|---|---|---|---|")

    def cyc(v, **kw):
        a = sc.attractor(sc.Params(5.0, 50.0, 10.0, v, a1, a2), max_periods=4000, **kw)
        return a.regime in ("slip_cycle", "stick_slip")
    for meth, kw in (("gps", dict(dt=1e-2)), ("gps", dict(dt=1e-3)), ("gps", dict(dt=1e-4)),
                     ("rk4", dict(dt=1e-2)), ("dopri5", dict(tol=1e-8)),
                     ("dop853", dict(tol=1e-8))):
        lo, hi = 0.8 * vs, 1.5 * vs
        for _ in range(14):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if cyc(mid, method=meth, **kw) else (lo, mid)
        v_m = 0.5 * (lo + hi)
        pred = math.sqrt((a1 + 50.0 * kw["dt"]) / (3 * a2)) if meth == "gps" else vs
        step = f"dt = {kw['dt']}" if "dt" in kw else f"tol = {kw['tol']}"
        print(f"| {meth} | {step} | {v_m:.4f} | {pred:.4f} | {(v_m - vs) / vs:+.2%} |")
    print()


if __name__ == "__main__":
    from _common import no_options
    no_options(__doc__)
    orders()
    hopf_shift()
