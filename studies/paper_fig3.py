"""Paper Fig. 3: constant friction, started stuck on the belt (m=5, k=50, r_y=10, v=5).

Time histories of z, zdot, x, xdot and both phase planes, with the circle of eq. (39)
(centre r_y/k, radius v/omega in the (x, xdot/omega) plane) drawn over the orbit: the
slider slips at t = r_y/(k v) (eq. 32) and then touches the belt speed once per
period in an abnormal stop of zero duration (eq. 31), never sticking again.

    python studies/paper_fig3.py [--out out/]   ->  paper_fig3.nc, paper_fig3.png
"""
import math

import numpy as np

import sweepcore as sc
from sweepcore.io import write_netcdf
from sweepcore.plot import save, plot_trajectory

from _common import Timer, output_dir

PAPER = dict(m=5.0, k=50.0, r_y=10.0, v=5.0)    # kN s^2/cm, kN/cm, kN, cm/s
T_END = 12.0                                    # s: about six periods


def main(out):
    p = sc.Params(**PAPER)
    with Timer("paper_fig3"):
        ds = sc.simulate(p, t_end=T_END, x0=0.0, xdot0=None, method="exact",
                         output_dt=0.005)
        ds.attrs["title"] = "Liu, Fig. 3: constant Coulomb friction, started stuck"
        write_netcdf(ds, out / "paper_fig3.nc")
        fig = plot_trajectory(ds, title=(
            "Fig. 3: constant friction, $m$ = 5 kN s$^2$/cm, $k$ = 50 kN/cm, "
            "$r_y$ = 10 kN, $v$ = 5 cm/s, started stuck ($x_0$ = 0, $\\dot x_0 = v$)"))
        _draw_circle(fig.axes[5], p)
        save(fig, out / "paper_fig3.png")
    # the closed form the picture shows, checked on the run
    w = p.omega
    slide = ds.time.values > p.r_y / (p.k * p.v) + 1e-9
    radius = np.hypot(ds.x.values[slide] - p.r_y / p.k, ds.xdot.values[slide] / w)
    print(f"  radius of the orbit after the slip: {radius.min():.12g} .. "
          f"{radius.max():.12g} cm; v/omega = {p.v / w:.12g} cm (eq. 39)")
    return [out / "paper_fig3.nc", out / "paper_fig3.png"]


def _draw_circle(ax, p):
    th = np.linspace(0.0, 2.0 * math.pi, 400)
    R = p.v / p.omega
    ax.plot(p.r_y / p.k + R * np.cos(th), p.omega * R * np.sin(th), color="#E69F00",
            lw=2.5, ls=(0, (4, 4)), zorder=2,
            label=r"eq. (39): centre $r_y/k$, radius $v/\omega$")
    ax.legend(fontsize=7.5, loc="center")


if __name__ == "__main__":
    main(output_dir(__doc__))
