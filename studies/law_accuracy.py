"""Accuracy of every friction law against the independent scipy reference.

Run:  python studies/law_accuracy.py        (about half a minute)

For each law (the paper's cubic law; the bSTAB Stribeck law with damping; a law with
every term; a Stribeck law with a supercritical Hopf point) the attractor from the
stuck start at the default tolerance (1e-8) is compared with tests/reference.py
(scipy DOP853 at rtol 1e-12 .. 1e-13, no sweepcore code): stick-slip cycles from the
breakaway point, slip cycles by shooting (with their Floquet multiplier), equilibria
by the force balance. Belt speeds include the hard cases: slip cycles next to the
Hopf point and stick-slip cycles next to the fold. Prints one markdown table; errors
are in units of the point's length scale L = r_y/k + |v|/omega.
"""
import math
import sys
import time
from pathlib import Path

import numpy as np

import sweepcore as sc

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
from reference import (reference_equilibrium, reference_slip_cycle,  # noqa: E402
                       reference_stick_slip_cycle)

LAWS = {
    "cubic (eq. 40)": (dict(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, alpha2=0.01),
                       [0.5, 2.0, 4.0, 5.0, 5.2, 5.5, 5.7, 5.77, 6.0, 8.0]),
    "Stribeck + damping (bSTAB)": (
        dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.5, c=0.1),
        [0.3, 1.0, 1.175, 1.5, 1.8, 1.83, 1.836, 1.9, 2.5]),
    "all terms": (dict(m=2.0, k=3.0, r_y=1.2, r_k=0.7, v_s=0.3, c=0.05, alpha1=0.1,
                       alpha2=0.02), [0.3, 0.8, 1.3, 1.46, 1.5, 2.0]),
    "Stribeck + cubic, supercritical": (
        dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.5, c=0.02, alpha1=0.6, alpha2=0.1),
        [1.0, 1.3, 1.4, 1.44, 1.45, 1.454, 1.5, 2.0]),
}


def kwargs(p):
    return dict(c=p.c, r_k=p.r_k, v_s=p.v_s if p.v_s is not None else 1.0)


def error(p, a):
    """(largest error of amplitude, mean, x_max, x_min in L; relative period error;
    Floquet error) of the attractor a against the reference."""
    L = p.r_y / p.k + abs(p.v) / p.omega
    if a.regime == "equilibrium":
        ref = reference_equilibrium(p.m, p.k, p.r_y, p.v, p.alpha1, p.alpha2, **kwargs(p))
        return abs(a.mean - ref["x_eq"]) / L, 0.0, 0.0
    if a.regime == "stick_slip":
        ref = reference_stick_slip_cycle(p.m, p.k, p.r_y, p.v, p.alpha1, p.alpha2,
                                         **kwargs(p))
        fl = abs(a.floquet)
    else:
        ref = reference_slip_cycle(p.m, p.k, p.r_y, p.v, p.alpha1, p.alpha2, a.x_max,
                                   **kwargs(p))
        fl = abs(a.floquet - ref["floquet"])
    e = max(abs(getattr(a, n) - ref[n]) for n in ("amplitude", "mean", "x_max", "x_min"))
    return e / L, abs(a.period - ref["period"]) / ref["period"], fl


def main():
    t0 = time.perf_counter()
    print("| law | points | regimes (ok) | max error of amplitude, mean, extrema [L] "
          "| max period error [rel] | max Floquet error |")
    print("|---|---|---|---|---|---|")
    for name, (pars, speeds) in LAWS.items():
        errs, regimes = [], {}
        for v in speeds:
            p = sc.Params(**pars, v=v)
            a = sc.attractor(p)
            regimes[a.regime] = regimes.get(a.regime, 0) + (a.status == "ok")
            if a.status == "ok":
                errs.append(error(p, a))
        e = np.array(errs)
        reg = ", ".join(f"{k} {n}" for k, n in sorted(regimes.items()))
        print(f"| {name} | {len(speeds)} | {reg} | {e[:, 0].max():.1e} | "
              f"{e[:, 1].max():.1e} | {e[:, 2].max():.1e} |")
    print(f"\n({time.perf_counter() - t0:.0f} s; every point status ok is listed in "
          "the regime counts)")


if __name__ == "__main__":
    from _common import no_options
    no_options(__doc__)
    main()
