"""The friction law itself: the paper's Fig. 4."""
from __future__ import annotations

import math

import numpy as np
from matplotlib.figure import Figure

from .. import law
from ..options import checked_keywords


@checked_keywords
def plot_friction(r_y: float, alpha1: float, alpha2: float,
                  zdot_max: float | None = None, r_k: float | None = None,
                  v_s: float | None = None) -> Figure:
    """Fig. 4 of the paper: the friction law r_a(zdot), with its minimum v* marked.

    r_a = r_y sgn(zdot) - alpha1 zdot + alpha2 zdot^3 while sliding (eq. 40), or
    with ``r_k``, ``v_s`` the exponential Stribeck law
    sgn(zdot) (r_k + (r_y - r_k) exp(-|zdot|/v_s)) - alpha1 zdot + alpha2 zdot^3
    (:func:`sweepcore.law.friction`); at zdot = 0 the force is anywhere in
    [-r_y, r_y] (eq. 6), drawn as a vertical segment. The slope is negative for
    |zdot| < v*, where F' = 0 (:mod:`sweepcore.law`; without damping that is the Hopf
    speed), marked when v* is finite and > 0.
    """
    law_of = {"r_y": r_y, "alpha1": alpha1, "alpha2": alpha2, "r_k": r_k, "v_s": v_s}
    stribeck = r_k is not None and r_k != r_y
    v_star = float(law.derived("v_star", law_of))
    if not 0.0 < v_star < math.inf:     # no negative slope: nothing to mark
        v_star = math.nan
    if zdot_max is None:
        zdot_max = 2.2 * v_star if math.isfinite(v_star) else 10.0
    fig = Figure(figsize=(7.5, 5.2), layout="constrained")
    ax = fig.subplots()
    for sgn in (1, -1):
        zd = sgn * np.linspace(1e-9, zdot_max, 400)
        ra = law.friction(zd, law_of, phase=sgn)
        label = (r"$r_a = r_y\,\mathrm{sgn}(\dot z) - \alpha_1\dot z "
                 r"+ \alpha_2\dot z^3$ (eq. 40)") if not stribeck else (
            r"$r_a = \mathrm{sgn}(\dot z)(r_k + (r_y - r_k)e^{-|\dot z|/v_s})"
            r" - \alpha_1\dot z + \alpha_2\dot z^3$")
        ax.plot(zd, ra, color="#0072B2", lw=2, label=label if sgn == 1 else None)
    ax.plot([0, 0], [-r_y, r_y], color="#0072B2", lw=2, ls=":",
            label=r"sticking: $r_a \in [-r_y, r_y]$ (eq. 6)")
    if math.isfinite(v_star):
        r_min = float(law.friction(v_star, law_of))
        for sgn in (1, -1):
            ax.plot(sgn * v_star, sgn * r_min, "o", color="#D55E00", ms=7, zorder=3)
            ax.axvline(sgn * v_star, color="#D55E00", lw=0.8, ls="--")
        name = "$v^*$ ($F' = 0$)" if stribeck else "$v^* = \\sqrt{\\alpha_1/3\\alpha_2}$"
        ax.annotate(f"{name} = {v_star:.3g} cm/s\n"
                    f"min $r_a$ = {r_min:.3g} kN",
                    (v_star, r_min), xytext=(12, -34), textcoords="offset points",
                    fontsize=9, color="#D55E00")
        ax.axvspan(-v_star, v_star, color="#D55E00", alpha=0.07,
                   label=r"negative slope $|\dot z| < v^*$: energy input")
    ax.axhline(0, color="0.6", lw=0.6)
    ax.axvline(0, color="0.6", lw=0.6)
    ax.set(xlabel=r"relative velocity $\dot z$ [cm/s]",
           ylabel="friction force $r_a$ [kN]",
           title=f"Friction-speed law: $r_y$ = {r_y:g} kN, $\\alpha_1$ = {alpha1:g} "
                 f"kN s/cm, $\\alpha_2$ = {alpha2:g} kN s$^3$/cm$^3$"
                 + (f"\n$r_k$ = {r_k:g} kN, $v_s$ = {v_s:g} cm/s" if stribeck else ""))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8.5, loc="upper left")
    return fig
