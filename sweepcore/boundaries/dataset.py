"""The labelled result of a boundary search: CF variables over the grid's other
dimensions, the regime changes along ``transition``, and the analytic values along
v to compare with."""
from __future__ import annotations

import datetime
import math

import numpy as np
import xarray as xr

from .. import variables
from .._kernels import codes, layout
from ..grid import Grid
from ..law import v_star as _v_star
from ..params import LONG_NAMES, UNITS
from .point import ABSENT, SEARCH_NAMES


def _flag(meanings: dict, long_name: str) -> dict:
    keys = sorted(meanings)
    return {"units": "1", "long_name": long_name,
            "flag_values": np.array(keys, np.int8),
            "flag_meanings": " ".join(meanings[k] for k in keys)}


def _analytic(ds: xr.Dataset) -> xr.Dataset:
    """``v_star`` and the averaging estimate of the stick onset beside the located
    boundaries (along v)."""
    vs_units, vs_long, vs_comment = variables.ANALYTIC["v_star"]
    vs = xr.apply_ufunc(_v_star, ds["alpha1"], ds["alpha2"])
    ds["v_star"] = xr.Variable(vs.dims, np.asarray(vs.values, np.float64),
                               {"units": vs_units, "long_name": vs_long,
                                "comment": vs_comment})
    ds["v_stick_onset_estimate"] = xr.Variable(
        vs.dims, 2.0 / math.sqrt(5.0) * np.asarray(vs.values, np.float64),
        {"units": "cm s-1", "long_name": "averaging estimate 2 v*/sqrt(5) of the "
                                         "stick onset",
         "comment": "the averaged cycle's velocity amplitude 2 sqrt(v*^2 - v^2) "
                    "reaches v"})
    return ds


def _dataset(other: Grid, along: str, results, o, method, call,
             transitions: bool) -> xr.Dataset:
    from ..sweep import REFERENCE, _version
    dims, shape = other.dims, other.shape
    units = UNITS[along]

    def field(key, dtype=np.float64):
        return np.array([r[key] for r in results], dtype).reshape(shape)

    status = _flag(SEARCH_NAMES, "outcome of the boundary search")
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
        ds["regime_below"] = xr.Variable(tdims, below, _flag(regimes,
                                                             "regime below the change"))
        ds["regime_above"] = xr.Variable(tdims, above, _flag(regimes,
                                                             "regime above the change"))
        ds["transition_status"] = xr.Variable(tdims, st, {
            **status, "long_name": "outcome of the search of the change"})
    if along == "v":        # the analytic values to compare with
        ds = _analytic(ds)
    now = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    ds.attrs.update({
        "Conventions": "CF-1.11",
        "title": "Regime boundaries of the stick-slip friction oscillator",
        "history": f"{now} sweepcore {_version()}: {call}",
        "source": f"sweepcore {_version()}: root solves on smooth indicators of the "
                  "attractor (sweepcore.boundaries)",
        "references": REFERENCE,
        "comment": "Units kN, cm, s. Status flags say where a boundary was not "
                   "located and why.",
        "along": along,
        "method": method,
        "tol": float(o[layout.O_RTOL]),
        "sweepcore_kind": "boundaries",
    })
    return ds
