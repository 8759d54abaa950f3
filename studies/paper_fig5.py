"""Paper Fig. 5: speed-dependent friction, alpha1 = 1, alpha2 = 0.05, 1/75, 0.01.

m = 5, k = 50, r_y = 10, v = 5, started stuck. q = (alpha1 - 3 alpha2 v^2)/m (eq. 46)
is -0.55, 0 and 0.05 1/s: the orbit spirals into the equilibrium x_eq of eq. (43)
(q < 0), creeps towards it only algebraically at q = 0 (the paper's "small periodic
orbit" is this slow decay: the cubic term still damps), or settles on a stick-slip
limit cycle (q > 0). Rows: x(t), xdot(t), phase plane (x, xdot); the attractor
measured by ``sweepcore.attractor`` is printed.

    python studies/paper_fig5.py [--out out/]   ->  paper_fig5.nc, paper_fig5.png
"""
import numpy as np
import xarray as xr

import sweepcore as sc
from sweepcore.io import write_netcdf
from sweepcore.plot import plot_cases, save

from _common import Timer, output_dir

PAPER = dict(m=5.0, k=50.0, r_y=10.0, v=5.0, alpha1=1.0)
CASES = ((0.05, "q < 0"), (1 / 75, "q = 0"), (0.01, "q > 0"))   # alpha2 [kN s^3/cm^3]
T_END = 60.0                                                    # s
KEEP = ("x", "xdot", "z", "zdot", "r_a", "phase")


def main(out):
    runs, labels, eqs, rows = [], [], [], []
    with Timer("paper_fig5"):
        for alpha2, sign in CASES:
            p = sc.Params(**PAPER, alpha2=alpha2)
            ds = sc.simulate(p, t_end=T_END, method="auto", output_dt=0.01)
            a = sc.attractor(p)
            runs.append(ds)
            labels.append(f"$\\alpha_2$ = {alpha2:.4g}, $q$ = {_signed(p.q)} 1/s ({sign}): "
                          f"{_verdict(a, ds)}")
            eqs.append(p.x_eq)
            rows.append((alpha2, p.q, a))
        fig = plot_cases(runs, labels, equilibria=eqs, title=(
            "Fig. 5: friction law (40), $\\alpha_1$ = 1 kN s/cm, $m$ = 5, $k$ = 50, "
            "$r_y$ = 10, $v$ = 5 cm/s, started stuck"))
        save(fig, out / "paper_fig5.png")
        alpha2 = xr.Variable("alpha2", [c[0] for c in CASES],
                             {"units": "kN s3 cm-3",
                              "long_name": "cubic friction-speed coefficient"})
        ds = xr.concat([r[list(KEEP)] for r in runs], dim=xr.IndexVariable(
            "alpha2", alpha2.values, alpha2.attrs), combine_attrs="override")
        ds["q"] = ("alpha2", [r[1] for r in rows], {"units": "s-1",
                                                    "long_name": "Hopf quantity q"})
        ds["n_steps"] = ("alpha2", [r.attrs["n_steps"] for r in runs],
                         {"units": "1", "long_name": "integration steps of the run"})
        ds["x_eq"] = ("alpha2", eqs, {"units": "cm", "long_name": "equilibrium x_eq"})
        # variable attrs (units) and the CF globals from the runs; status per run
        ds.attrs.update(title="Liu, Fig. 5: three alpha2 cases",
                        status=" ".join(r.attrs["status"] for r in runs))
        write_netcdf(ds, out / "paper_fig5.nc")
    for alpha2, q, a in rows:
        print(f"  alpha2 = {alpha2:.5g}: q = {_signed(q)} 1/s -> {a.regime} "
              f"(amplitude {a.amplitude:.5g} cm, mean {a.mean:.4g} cm, stick fraction "
              f"{a.stick_fraction:.2g}, status {a.status})")
    print(f"  q = 0 at t = {T_END:g} s: x still oscillates with half-range "
          f"{_swing(runs[1]):.3g} cm (slow algebraic decay)")
    return [out / "paper_fig5.nc", out / "paper_fig5.png"]


def _swing(ds) -> float:
    """Half the range of x over the last natural period of a run [cm]."""
    period = 2 * np.pi / sc.Params(**PAPER).omega
    last = ds.x.values[ds.time.values > T_END - period]
    return float(np.ptp(last) / 2)


def _verdict(a, ds) -> str:
    """The attractor's regime; for an equilibrium the run has not reached by its end
    (q = 0: algebraic decay), how far x still swings."""
    regime = a.regime.replace("_", "-")
    if a.regime == "equilibrium" and _swing(ds) > 1e-3:
        return (f"{regime}, approached slowly (x still swings $\\pm${_swing(ds):.2g} cm "
                f"at t = {T_END:g} s)")
    return regime


def _signed(q: float) -> str:
    """q with its sign, and a plain 0 for the neutral case (rounding noise)."""
    return "0" if abs(q) < 1e-12 else f"{q:+.2g}"


if __name__ == "__main__":
    main(output_dir(__doc__))
