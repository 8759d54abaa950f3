"""Accuracy of every friction law against the independent scipy reference.

Run:  python studies/law_accuracy.py        (about half a minute)

For each law (the paper's cubic law; the bSTAB Stribeck law with damping; a law with
every term; a Stribeck law with a supercritical Hopf point) the attractor from the
stuck start at the default tolerance (1e-8) is compared with tests/reference.py
(scipy DOP853 at rtol 1e-12 .. 1e-13, no sweepcore code): stick-slip cycles from the
breakaway point, slip cycles by shooting (with their Floquet multiplier), equilibria
by the force balance. Belt speeds include the hard cases: slip cycles next to the
Hopf point and stick-slip cycles next to the fold. Laws given as objects
(sweepcore.TableLaw, sweepcore.LeineLaw) against tests/reference_law.py, the same
machinery with F from numpy: a table against the same interpolant evaluated there
(the representation is the law it solves), the bSTAB law sampled as a table against
the analytic reference (its error includes the representation's), Leine's law
against its formula. Prints one markdown table; errors are in units of the point's
length scale L = r_y/k + |v|/omega (the static bound for r_y).
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
import reference_law as RL  # noqa: E402

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


# laws given as objects: (slider, law, speeds, reference branch of F or None: the
# analytic law's reference, with these parameters)
SPEEDS_OBJECTS = [0.2, 0.5, 1.0, 1.175, 1.5, 2.5]
STICTION_S = np.array([0.0, 0.05, 0.1, 0.2, 0.35, 0.5, 0.8, 1.2, 1.8, 2.5, 3.5, 5.0, 7.0])


def object_laws():
    """(name, slider, law, speeds, branch of F for the reference, analytic parameters)"""
    stiction = sc.TableLaw(STICTION_S, 0.6 + 0.35 * np.exp(-STICTION_S / 0.4)
                           + 0.02 * STICTION_S, static=1.1, name="stiction")
    bstab = sc.TableLaw.from_function(
        lambda s: np.sign(s) * (0.5 + 0.5 * np.exp(-np.abs(s) / 0.5)), speed_max=8.0,
        tol=1e-11, name="bstab")
    leine = sc.LeineLaw(1.0, 3.0)

    def leine_branch(s, sgn):
        u = 1.0 + 3.0 * sgn * s
        return sgn / u, -3.0 / (u * u)
    return [
        ("table with stiction (13 points), same interpolant", dict(m=1.0, k=1.0, c=0.05),
         stiction, SPEEDS_OBJECTS, RL.pp_branch(*stiction._pos[:2]), None),
        (f"bSTAB law as a table ({bstab.speed.size} points), analytic reference",
         dict(m=1.0, k=1.0, c=0.1), bstab, SPEEDS_OBJECTS, None,
         dict(r_y=1.0, r_k=0.5, v_s=0.5)),
        ("Leine (f_s = 1, delta = 3), its formula", dict(m=1.0, k=1.0, c=0.1), leine,
         SPEEDS_OBJECTS, leine_branch, None),
    ]


def object_error(slider, law, v, branch, analytic, a):
    """As ``error``, for a law object: against reference_law with ``branch``, or
    against the analytic reference with the parameters ``analytic``."""
    if analytic is not None:
        return error(sc.Params(**slider, **analytic, v=v), a)
    static = max(law.static_limits())
    L = static / slider["k"] + abs(v) / math.sqrt(slider["k"] / slider["m"])
    mod = RL.LawModel(slider["m"], slider["k"], v, slider["c"], branch, static)
    if a.regime == "equilibrium":
        return abs(a.mean - RL.equilibrium(mod)["x_eq"]) / L, 0.0, 0.0
    if a.regime == "stick_slip":
        ref, fl = RL.stick_slip_cycle(mod), abs(a.floquet)
        e = max(abs(getattr(a, n) - ref[n]) for n in ("amplitude", "mean", "x_max",
                                                       "x_min"))
    else:
        ref = RL.slip_cycle(mod, a.x_max)
        e, fl = abs(a.x_max - ref["x_max"]), abs(a.floquet - ref["floquet"])
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
    for name, slider, law, speeds, branch, analytic in object_laws():
        errs, regimes = [], {}
        for v in speeds:
            a = sc.attractor(sc.Params(**slider, v=v, law=law))
            regimes[a.regime] = regimes.get(a.regime, 0) + (a.status == "ok")
            if a.status == "ok":
                errs.append(object_error(slider, law, v, branch, analytic, a))
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
