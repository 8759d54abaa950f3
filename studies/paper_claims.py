"""Check two of the paper's claims against the dynamics (issue: attractor observables).

(a) "the amplitude is independent of the initial conditions";
(b) "a subcritical Hopf bifurcation at v*".

Run:  python studies/paper_claims.py            (about a minute on 2 cores)
Prints markdown tables; docs/physics.md quotes them.
"""
import math

import numpy as np

import sweepcore as sc
from sweepcore import law

M, K, RY, A1, A2 = 5.0, 50.0, 10.0, 1.0, 0.01
TOL = 1e-10


def starts(p):
    """Stuck on the belt, next to the equilibrium, at rest, and a far start."""
    return {"stuck": (0.0, None), "near x_eq": (p.x_eq + 1e-3, p.v),
            "rest": (0.0, 0.0), "far": (p.x_eq + 1.2, p.v - 2.0)}


def claim_a():
    print("### (a) amplitude against the start\n")
    print("| law | start | regime | amplitude [cm] |")
    print("|---|---|---|---|")
    for name, (a1, a2) in {"constant (alpha1 = alpha2 = 0)": (0.0, 0.0),
                           "speed-dependent, q > 0 (alpha2 = 0.01)": (A1, 0.01),
                           "speed-dependent, q < 0 (alpha2 = 0.05)": (A1, 0.05)}.items():
        p = sc.Params(M, K, RY, 5.0, a1, a2)
        for label, (x0, xd0) in {**starts(p), "x0 = 1, at rest": (1.0, 0.0)}.items():
            a = sc.attractor(p, x0=x0, xdot0=xd0, tol=TOL)
            print(f"| {name} | {label} | {a.regime} | {a.amplitude:.6f} |")
    print()


def claim_b():
    vs = float(law.derived("v_star", {"alpha1": A1, "alpha2": A2}))
    w = float(law.derived("omega", {"m": M, "k": K}))
    print(f"### (b) cycle amplitude across v* = {vs:.6f} cm/s "
          f"(m={M}, k={K}, r_y={RY}, alpha1={A1}, alpha2={A2})\n")
    print("Averaging prediction below v* (first Lyapunov coefficient < 0, supercritical): "
          "(A omega)^2 = 4 m q / (3 alpha2); sticking starts where A omega = v, "
          "v = sqrt(4/5) v*.\n")
    print("| v / v* | q [1/s] | averaging A [cm] | " + " | ".join(starts(sc.Params(M, K, RY, 1.0)))
          + " |")
    print("|---|---|---|" + "---|" * 4)
    for r in [0.80, 0.89, 0.894, 0.895, 0.90, 0.95, 0.98, 0.99, 0.995, 1.005, 1.01, 1.05]:
        p = sc.Params(M, K, RY, r * vs, A1, A2)
        pred = math.sqrt(max(4 * M * p.q / (3 * A2), 0.0)) / w
        cells = []
        for x0, xd0 in starts(p).values():
            a = sc.attractor(p, x0=x0, xdot0=xd0, tol=TOL, max_periods=20000)
            cells.append(f"{a.regime} {a.amplitude:.5f}")
        print(f"| {r:.3f} | {p.q:+.4f} | {pred:.5f} | " + " | ".join(cells) + " |")
    print()


if __name__ == "__main__":
    from _common import no_options
    no_options(__doc__)
    np.set_printoptions(precision=6)
    claim_a()
    claim_b()
