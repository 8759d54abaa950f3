"""Measured Hopf boundary of a sweep, beside the analytic v* (eq. 46 and below (51)).

Along the belt speed, a map switches from a cycle (slip_cycle or stick_slip) below the
boundary to steady sliding (equilibrium) above it. The measured boundary is known
only to the grid's resolution: it lies between the largest speed with a cycle and
the next larger speed with an equilibrium, and is reported as their midpoint with
half their distance as its resolution.

Two kinds of slip cycle are told apart by whether they reach the belt speed
(``xdot_max`` against ``v``): the small cycles of the Hopf point stay below it (their
growth to ``xdot_max = v`` is the stick onset), the large cycles of the
slide-slide-reversal band at small alpha2 reach or overshoot it (``zdot >= 0`` for a
moment, no
stick). Each transition has its own variables.
"""
from __future__ import annotations

import numpy as np
import xarray as xr

from . import labels
from ._kernels import codes
from .options import checked_keywords, did_you_mean

CYCLES = (codes.R_SLIP_CYCLE, codes.R_STICK_SLIP)
BOUNDARY_VARIABLES = ("v_hopf_measured", "v_hopf_resolution", "v_stick_onset",
                      "v_stick_onset_resolution", "v_reversal_lower",
                      "v_reversal_lower_resolution", "v_reversal_upper",
                      "v_reversal_upper_resolution")


def _switch(before, after, x):
    """Midpoint and half-gap between the last ``before`` along the last axis and the
    first ``after`` beyond it; NaN where there is no such pair.

    ``before``, ``after``: boolean arrays (..., n); ``x``: increasing (n,) values.
    """
    n = x.size
    idx = np.arange(n)
    last = np.where(before, idx, -1).max(axis=-1)
    beyond = after & (idx > last[..., None])
    first = np.where(beyond, idx, n).min(axis=-1)
    found = (last >= 0) & (first < n)
    lo = x[np.clip(last, 0, n - 1)]
    hi = x[np.clip(first, 0, n - 1)]
    mid = np.where(found, 0.5 * (lo + hi), np.nan)
    half = np.where(found, 0.5 * (hi - lo), np.nan)
    return mid, half


def _edges(inside, x):
    """Lower and upper edge of the run of ``inside`` points along the last axis, each
    as the midpoint (and half-gap) between its first/last point and the grid speed
    outside it; NaN where there is no such point or the run reaches the grid's end."""
    n = x.size
    idx = np.arange(n)
    first = np.where(inside, idx, n).min(axis=-1)
    last = np.where(inside, idx, -1).max(axis=-1)
    lo_ok = (first < n) & (first > 0)
    hi_ok = (last >= 0) & (last < n - 1)
    f, b = np.clip(first, 1, n - 1), np.clip(last, 0, n - 2)
    lower = np.where(lo_ok, 0.5 * (x[f] + x[f - 1]), np.nan)
    lower_half = np.where(lo_ok, 0.5 * (x[f] - x[f - 1]), np.nan)
    upper = np.where(hi_ok, 0.5 * (x[b] + x[b + 1]), np.nan)
    upper_half = np.where(hi_ok, 0.5 * (x[b + 1] - x[b]), np.nan)
    return lower, lower_half, upper, upper_half


def reversal_cycles(ds: xr.Dataset, axis: str = "v") -> xr.DataArray:
    """Slip cycles that reach the belt speed (``xdot_max >= v``): the
    slide-slide-reversal band (the Hopf point's cycles stay below it). All False without ``xdot_max`` in ``ds``; a boolean
    ``reversal`` variable of ``ds`` (a lazy sweep's, computed once) is taken as is."""
    if "reversal" in ds:
        return ds["reversal"]
    slip = ds["regime"] == codes.R_SLIP_CYCLE
    if "xdot_max" not in ds:
        return slip & False
    return slip & (ds["xdot_max"] >= ds[axis])


def _labelled(da: xr.DataArray, **attrs) -> xr.DataArray:
    """``da`` with exactly these attributes (inputs' flag attributes dropped)."""
    da = da.copy(deep=False)
    da.attrs = attrs
    return da


@checked_keywords
def hopf_boundary(ds: xr.Dataset, axis: str = "v") -> xr.Dataset:
    """Measured Hopf and stick boundaries along the belt speed, with the analytic v*.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep result with a ``regime`` variable and ``axis`` swept with >= 2
        values (any order).
    axis : str
        The belt-speed dimension.

    Returns
    -------
    xarray.Dataset
        Over the other dimensions of ``regime`` [cm/s]:

        ``v_hopf_measured``
            midpoint between the largest speed with a cycle (slip_cycle or
            stick_slip) and the smallest larger speed with equilibrium; NaN where
            the map never switches from a cycle to equilibrium.
        ``v_hopf_resolution``
            half the distance between those two speeds: the measured boundary is
            ``v_hopf_measured +- v_hopf_resolution``.
        ``v_stick_onset``, ``v_stick_onset_resolution``
            the stick onset: where stick_slip ends, the next larger speed being a
            slip cycle that stays below the belt speed (``xdot_max < v``: the
            Hopf point's cycle) or equilibrium; NaN where the map does not reach it
            (at small alpha2 it lies above the speeds of the map).
        ``v_reversal_lower``, ``v_reversal_upper`` (and ``_resolution``)
            the edges of the band of slip cycles that reach the belt speed
            (``xdot_max >= v``, slide-slide reversals); NaN without such cycles or
            where the band reaches the end of the grid.
        ``v_star``
            the analytic Hopf speed sqrt(alpha1/(3 alpha2)).
    """
    if axis not in ds.dims:
        raise ValueError(f"axis={axis!r} is not a dimension of the Dataset"
                         f"{did_you_mean(axis, list(ds.dims))} "
                         f"(dimensions: {tuple(ds.dims)})")
    if ds.sizes[axis] < 2:
        raise ValueError(f"axis={axis!r} needs >= 2 values to locate a boundary, got "
                         f"{ds.sizes[axis]}")
    regime = ds["regime"]
    if not (np.diff(regime[axis].values) > 0).all():
        regime = regime.sortby(axis)
    x = regime[axis].values
    units = ds[axis].attrs.get("units", "")

    def measured(before, after):
        return xr.apply_ufunc(_switch, before, after, kwargs={"x": x},
                              input_core_dims=[[axis], [axis]],
                              output_core_dims=[[], []])

    hopf, hopf_res = measured(regime.isin(CYCLES), regime == codes.R_EQUILIBRIUM)
    reversal = reversal_cycles(ds, axis).sortby(axis).transpose(*regime.dims)
    stick, stick_res = measured(
        regime == codes.R_STICK_SLIP,
        ((regime == codes.R_SLIP_CYCLE) & ~reversal) | (regime == codes.R_EQUILIBRIUM))
    band = xr.apply_ufunc(_edges, reversal, kwargs={"x": x},
                          input_core_dims=[[axis]], output_core_dims=[[]] * 4)
    rule = ("midpoint between the largest {a} with {b} and the next larger {a} with "
            "{c}; NaN where there is no such switch")
    half = "half the distance between the two speeds across the switch"
    out = xr.Dataset({
        "v_hopf_measured": _labelled(
            hopf, units=units, long_name="measured Hopf belt speed",
            comment=rule.format(a=axis, b="a cycle (slip_cycle or stick_slip)",
                                c="equilibrium")),
        "v_hopf_resolution": _labelled(
            hopf_res, units=units, comment=half,
            long_name="resolution of the measured Hopf belt speed"),
        "v_stick_onset": _labelled(
            stick, units=units, long_name="measured stick onset (end of stick-slip)",
            comment=rule.format(a=axis, b="stick_slip", c="a slip cycle below the "
                                "belt speed (xdot_max < v) or equilibrium")),
        "v_stick_onset_resolution": _labelled(
            stick_res, units=units, comment=half,
            long_name="resolution of the measured stick onset"),
    })
    edge = ("midpoint between the {w} {a} with a slip cycle reaching the belt "
            "speed (xdot_max >= v) and the {a} {o} it; NaN without one or at the "
            "grid's end")
    for name, da, text in (("lower", band[0], edge.format(w="smallest", a=axis,
                                                          o="below")),
                           ("upper", band[2], edge.format(w="largest", a=axis,
                                                          o="above"))):
        out[f"v_reversal_{name}"] = _labelled(
            da, units=units, comment=text,
            long_name=f"{name} edge of the slide-slide-reversal band")
        out[f"v_reversal_{name}_resolution"] = _labelled(
            band[1 if name == "lower" else 3], units=units, comment=half,
            long_name=f"resolution of the reversal band's {name} edge")
    # the analytic value: the result's own (a law object's is in the file), or from
    # the analytic law's parameters
    out["v_star"] = ds["v_star"] if "v_star" in ds else labels.analytic("v_star", ds)
    return out
