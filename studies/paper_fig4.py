"""Paper Fig. 4: the friction-speed law (40) with r_y = 10, alpha1 = 1, alpha2 = 0.01.

r_a = r_y sgn(zdot) - alpha1 zdot + alpha2 zdot^3 while sliding, anything in
[-r_y, r_y] while sticking (eq. 6). The slope dr_a/dzdot = -alpha1 + 3 alpha2 zdot^2
is negative for |zdot| < v* = sqrt(alpha1/(3 alpha2)) = 5.77 cm/s: there friction
feeds energy into the vibration. The curve's minimum there is r_y - (2/3) alpha1 v*.

    python studies/paper_fig4.py [--out out/]   ->  paper_fig4.nc, paper_fig4.png
"""
import datetime

import numpy as np
import xarray as xr

import sweepcore
from sweepcore import law
from sweepcore.io import write_netcdf
from sweepcore.labels import REFERENCE
from sweepcore.params import LONG_NAMES, UNITS
from sweepcore.plot import plot_friction, save

from _common import Timer, output_dir

R_Y, ALPHA1, ALPHA2 = 10.0, 1.0, 0.01      # kN, kN s/cm, kN s^3/cm^3


def main(out):
    with Timer("paper_fig4"):
        law_of = {"r_y": R_Y, "alpha1": ALPHA1, "alpha2": ALPHA2}
        v_star = float(law.derived("v_star", law_of))
        zd = np.linspace(-2.2 * v_star, 2.2 * v_star, 881)
        zd = zd[zd != 0.0]
        ra = law.friction(zd, law_of)
        now = datetime.datetime.now(datetime.timezone.utc)
        ds = xr.Dataset(
            {"r_a": ("zdot", ra, {"units": "kN", "long_name": "friction force",
                                  "comment": "eq. (40), sliding branches"})},
            coords={"zdot": ("zdot", zd, {"units": "cm s-1",
                                          "long_name": "relative velocity"}),
                    **{n: ((), val, {"units": UNITS[n], "long_name": LONG_NAMES[n]})
                       for n, val in (("r_y", R_Y), ("alpha1", ALPHA1),
                                      ("alpha2", ALPHA2))},
                    "v_star": ((), v_star, {"units": "cm s-1",
                                            "long_name": "Hopf belt speed v*"}),
                    "r_a_min": ((), R_Y - 2 * ALPHA1 * v_star / 3,
                                {"units": "kN",
                                 "long_name": "minimum sliding friction, at v*"})},
            attrs={"Conventions": "CF-1.11", "title": "Liu, Fig. 4: friction-speed law",
                   "source": f"sweepcore {sweepcore.__version__}: studies/paper_fig4.py",
                   "references": REFERENCE,
                   "history": f"{now:%Y-%m-%dT%H:%M:%SZ} python studies/paper_fig4.py"})
        write_netcdf(ds, out / "paper_fig4.nc")
        save(plot_friction(R_Y, ALPHA1, ALPHA2), out / "paper_fig4.png")
    print(f"  v* = {v_star:.6g} cm/s, minimum sliding friction "
          f"{R_Y - 2 * ALPHA1 * v_star / 3:.6g} kN")
    return [out / "paper_fig4.nc", out / "paper_fig4.png"]


if __name__ == "__main__":
    main(output_dir(__doc__))
