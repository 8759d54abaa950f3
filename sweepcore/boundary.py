"""Measured Hopf boundary of a sweep, beside the analytic v* (eq. 46 and below (51)).

Along the belt speed, a map switches from a cycle (slip_cycle or stick_slip) below the
boundary to steady sliding (equilibrium) above it. The measured boundary is known
only to the grid's resolution: it lies between the largest speed with a cycle and
the next larger speed with an equilibrium, and is reported as their midpoint with
half their distance as its resolution.
"""
from __future__ import annotations

import numpy as np
import xarray as xr

from . import labels
from ._kernels import codes
from .options import checked_keywords

CYCLES = (codes.R_SLIP_CYCLE, codes.R_STICK_SLIP)
BOUNDARY_VARIABLES = ("v_hopf_measured", "v_hopf_resolution", "v_stick_onset",
                      "v_stick_onset_resolution")


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
            the same where stick_slip ends (the next larger speed being slip_cycle
            or equilibrium).
        ``v_star``
            the analytic Hopf speed sqrt(alpha1/(3 alpha2)).
    """
    if axis not in ds.dims:
        raise ValueError(f"axis={axis!r} is not a dimension of the Dataset "
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
    stick, stick_res = measured(
        regime == codes.R_STICK_SLIP,
        regime.isin((codes.R_SLIP_CYCLE, codes.R_EQUILIBRIUM)))
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
            stick, units=units, long_name="measured end of stick-slip",
            comment=rule.format(a=axis, b="stick_slip", c="slip_cycle or equilibrium")),
        "v_stick_onset_resolution": _labelled(
            stick_res, units=units, comment=half,
            long_name="resolution of the measured end of stick-slip"),
    })
    out["v_star"] = labels.analytic("v_star", ds)
    return out
