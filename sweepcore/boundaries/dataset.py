"""The labelled result of a boundary search: CF variables over the grid's other
dimensions, the regime changes along ``transition``, and the analytic values along
v to compare with."""
from __future__ import annotations

import numpy as np
import xarray as xr

from .. import labels, law
from .._kernels import codes, layout
from ..grid import Grid
from ..params import LONG_NAMES, UNITS
from .point import ABSENT, SEARCH_NAMES


def _dataset(other: Grid, along: str, results, o, method, call,
             transitions: bool) -> xr.Dataset:
    dims, shape = other.dims, other.shape
    units = UNITS[along]

    def field(key, dtype=np.float64):
        return np.array([r[key] for r in results], dtype).reshape(shape)

    status = labels.flags(SEARCH_NAMES, "outcome of the boundary search")
    data = {
        "v_hopf": (field("v_hopf"), {
            "units": units, "long_name": "measured Hopf point (cycle | equilibrium)",
            "comment": "root of the cycle's amplitude squared, a cubic in v^2 through "
                       "four cycles at relative distances offset, 2 offset, ... "}),
        "v_hopf_error": (field("v_hopf_error"), {
            "units": units, "long_name": "estimated error of the Hopf point",
            "comment": "difference between the roots of the cubics through samples "
                       "1-4 and 2-5; continued steps: between the root and the "
                       "prediction (or a third sample's root), plus the move of "
                       "the root under amplitude errors of 2 tol L"}),
        "hopf_status": (field("hopf_status", np.int8),
                        {**status, "long_name": "outcome of the Hopf point search"}),
        "v_stick_onset": (field("v_stick_onset"), {
            "units": units, "long_name": "measured stick onset (slip cycle grazes the "
                                         "belt)",
            "comment": "root of v - xdot_max on the slip cycles (safeguarded secant) "
                       "inside a bracket of stick_slip | slip_cycle labels"}),
        "v_stick_onset_width": (field("v_stick_onset_width"), {
            "units": units, "long_name": "uncertainty of the stick onset",
            "comment": "last correction of the root estimate, or the distance "
                       "between the roots of the polynomials of two degrees"}),
        "stick_status": (field("stick_status", np.int8),
                         {**status, "long_name": "outcome of the stick-onset search"}),
        "v_hopf_subcritical": (field("v_hopf_subcritical"), {
            "units": units, "long_name": "subcritical Hopf point (unstable slip "
                                         "cycle | unstable equilibrium)",
            "comment": "root of the unstable cycle's amplitude squared, a cubic in "
                       "v^2 through four unstable cycles of the cycle scan"}),
        "v_hopf_subcritical_error": (field("v_hopf_subcritical_error"), {
            "units": units, "long_name": "estimated error of the subcritical Hopf "
                                         "point",
            "comment": "difference between the roots of the cubics through samples "
                       "1-4 and 2-5"}),
        "subcritical_status": (field("subcritical_status", np.int8), {
            **status, "long_name": "outcome of the subcritical Hopf point search",
            "comment": "searched where hopf_criticality is subcritical or "
                       "degenerate, absent elsewhere"}),
        "v_fold": (field("v_fold"), {
            "units": units, "long_name": "fold of cycles at grazing (end of the "
                                         "stick-slip attractor)",
            "comment": "root of v - xdot_max on the unstable slip cycle: it grazes "
                       "the belt and meets the stick-slip cycle; steady sliding and "
                       "stick-slip coexist between v_hopf_subcritical and v_fold"}),
        "v_fold_width": (field("v_fold_width"), {
            "units": units, "long_name": "uncertainty of the fold",
            "comment": "distance between the roots of the polynomials of two "
                       "degrees, plus the root's move under errors of 2 tol L in "
                       "xdot_max"}),
        "fold_status": (field("fold_status", np.int8), {
            **status, "long_name": "outcome of the fold search"}),
        "evaluations": (field("evaluations", np.int64), {
            "units": "1", "long_name": "attractors computed for the point"}),
    }
    ds = xr.Dataset({k: (dims, v, a) for k, v, a in
                     ((k, *val) for k, val in data.items())}, other.coords())
    ds = ds.drop_vars([along] + [n for n in ("x0", "xdot0") if n in ds.coords])
    if transitions:
        n = max([len(r["transitions"]) for r in results] + [1])
        val = np.full(shape + (n,), np.nan)
        wid = np.full(shape + (n,), np.nan)
        below = np.full(shape + (n,), -1, np.int8)
        above = np.full(shape + (n,), -1, np.int8)
        st = np.full(shape + (n,), ABSENT, np.int8)
        for flat, r in enumerate(results):
            idx = np.unravel_index(flat, shape) if shape else ()
            for k, (x, w, rb, ra, s) in enumerate(r["transitions"]):
                val[idx + (k,)], wid[idx + (k,)] = x, w
                below[idx + (k,)], above[idx + (k,)], st[idx + (k,)] = rb, ra, s
        regimes = {-1: "none", **codes.REGIME_NAMES}
        tdims = dims + ("transition",)
        ds["transition"] = xr.Variable("transition", np.arange(n), {
            "units": "1", "long_name": "index of the regime change along " + along})
        ds["transition_value"] = xr.Variable(tdims, val, {
            "units": units, "long_name": f"{LONG_NAMES[along]} of a regime change"})
        ds["transition_width"] = xr.Variable(tdims, wid, {
            "units": units, "long_name": "final bracket width (Hopf: error estimate)"})
        ds["regime_below"] = xr.Variable(tdims, below, labels.flags(
            regimes, "regime below the change"))
        ds["regime_above"] = xr.Variable(tdims, above, labels.flags(
            regimes, "regime above the change"))
        ds["transition_status"] = xr.Variable(tdims, st, {
            **status, "long_name": "outcome of the search of the change"})
    if along == "v":        # the analytic values to compare with
        ds["v_star"] = labels.analytic("v_star", ds, laws=other.laws).variable
        ds["hopf_criticality"] = xr.Variable(
            ds["v_star"].dims, labels.criticality(ds, other.laws).values,
            labels.flags(law.CRITICALITY, "kind of the Hopf point v_star (sign of "
                                          "F''' there: of the first Lyapunov "
                                          "coefficient)"))
        ds["v_stick_onset_estimate"] = labels.stick_onset_estimate(
            ds, other.laws).variable
    ds.attrs.update({
        **labels.provenance(
            "Regime boundaries of the stick-slip friction oscillator", call,
            "root solves on smooth indicators of the attractor (sweepcore.boundaries)",
            "Units kN, cm, s. Status flags say where a boundary was not located and "
            "why."),
        "along": along,
        "method": method,
        "tol": float(o[layout.O_RTOL]),
        "sweepcore_kind": "boundaries",
    })
    return ds
