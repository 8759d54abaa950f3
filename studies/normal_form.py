"""How accurate is the Hopf normal form? (it decides the points next to v*)

For sliders (m, k, alpha1) spanning G = c2^2/(c3 omega) = 9 alpha2 v^2/(m omega)
from 0.15 to 9 (r_y = 10, several alpha2), the slip cycle's amplitude from the
shooting solve (tol 1e-11, status ok only) against first-order averaging,
A1^2 = 4 m q / (3 alpha2 omega^2):

* ``coefficient`` = (A - A1) / A / (G q/omega): the second-order term the engine adds
  (7/18, ``sweepcore/_kernels/normal_form.py``);
* ``remainder`` = |A - A_nf| / A / ((1 + G) q/omega)^2 for the corrected A_nf: the
  engine trusts the normal form only where NF_KAPPA times this scale is below the
  tolerance, so NF_KAPPA must exceed every remainder measured here.

Run:  python studies/normal_form.py           (under a minute; prints the table)
      python studies/normal_form.py --write   (also rewrites studies/results/normal_form.json,
                                               its numbers rounded as printed)
"""
import argparse
import json
import math
from pathlib import Path

import sweepcore as sc
from sweepcore import law
from sweepcore._kernels.normal_form import NF_KAPPA

RY = 10.0
SLIDERS = ((5.0, 50.0, 1.0), (1.0, 400.0, 1.0), (20.0, 5.0, 1.0), (1.0, 1.0, 1.0),
           (1.0, 1.0, 3.0))                        # (m, k, alpha1)
OUT = Path(__file__).resolve().parent / "results" / "normal_form.json"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true",
                        help=f"rewrite {OUT.relative_to(OUT.parents[2])}")
    write = parser.parse_args(argv).write
    rows = []
    print("| m | k | alpha1 | alpha2 | v / v* | G | q/omega | A [cm] | coefficient | "
          "remainder |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for m, k, a1 in SLIDERS:
        w = float(law.derived("omega", {"m": m, "k": k}))
        for a2 in (0.001, 0.1):
            vs = float(law.derived("v_star", {"alpha1": a1, "alpha2": a2}))
            for r in (0.98, 0.99, 0.995, 0.998, 0.999):
                p = sc.Params(m, k, RY, r * vs, a1, a2)
                a = sc.attractor(p, tol=1e-11)
                if a.status != "ok" or a.regime != "slip_cycle":
                    continue
                G = 9.0 * a2 * p.v ** 2 / (m * w)
                qw = p.q / w
                A1 = math.sqrt(4 * m * p.q / (3 * a2)) / w
                coef = (a.amplitude - A1) / a.amplitude / (G * qw)
                A_nf = A1 * (1.0 + 7.0 / 18.0 * G * qw)
                rem = abs(a.amplitude - A_nf) / a.amplitude / ((1.0 + G) * qw) ** 2
                # stored as printed, so a rerun rewrites the same file
                rows.append(dict(m=m, k=k, alpha1=a1, alpha2=a2, ratio=r,
                                 G=round(G, 3), q_over_omega=float(f"{qw:.2e}"),
                                 amplitude=round(a.amplitude, 8),
                                 coefficient=round(coef, 4), remainder=round(rem, 3)))
                print(f"| {m} | {k} | {a1} | {a2} | {r} | {G:.3f} | {qw:.2e} | "
                      f"{a.amplitude:.8f} | {coef:.4f} | {rem:.3f} |")
    coefs = [r["coefficient"] for r in rows]
    worst = max(r["remainder"] for r in rows)
    print(f"\ncoefficient {min(coefs):.4f} .. {max(coefs):.4f} (engine: 7/18 = "
          f"{7 / 18:.4f}); largest remainder {worst:.3f}; NF_KAPPA = {NF_KAPPA}")
    if not write:
        print(f"(printed only; --write rewrites {OUT.name})")
        return
    OUT.parent.mkdir(exist_ok=True)
    OUT.write_text(json.dumps({"rows": rows, "coefficient_range": [min(coefs), max(coefs)],
                               "largest_remainder": worst, "nf_kappa": NF_KAPPA},
                              indent=1) + "\n")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
