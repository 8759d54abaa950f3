"""Bifurcation diagrams: attractors followed along one parameter, up and down.

Each point starts from the previous point's attractor, at its largest ``x`` and at
rest (``x0 = x_max``, ``xdot0 = 0``), so a branch is followed as long as it exists;
the down scan starts from the last attractor of the up scan. Coexisting attractors
show up as branches that differ between the two directions (hysteresis); with the
supercritical Hopf point of Liu's model (docs/physics.md) they coincide.
"""
from __future__ import annotations

import math

import numpy as np
import xarray as xr

from . import execute, labels, variables
from ._kernels import codes, layout
from .boundaries import locate_boundaries
from .grid import AXES, COLUMNS, Grid
from .options import checked_keywords, did_you_mean, make_options
from .params import LONG_NAMES, UNITS

BRANCHES = ("up", "down")
DIAGRAM_VARIABLES = ("x_max", "x_min", "mean", "amplitude", "floquet", "xdot_max",
                     "period", "stick_fraction")


def _follow(base: np.ndarray, col: int, values, start, o) -> np.ndarray:
    """Observables (len(values), NOBS) along ``values``, each point started from the
    previous attractor (x_max, at rest); ``start`` (x0, xdot0 or NaN) for the first
    and after a point without an attractor."""
    out = np.empty((len(values), layout.NOBS))
    x0, xd0 = start
    row = base.copy()[None, :]
    for i, u in enumerate(values):
        row[0, col] = u
        row[0, layout.X0] = x0
        row[0, layout.XD0] = row[0, layout.V] if np.isnan(xd0) else xd0
        execute.attractors(row, o, out[i:i + 1], parallel=False)
        if int(out[i, layout.OB_STATUS]) == codes.OK and \
                np.isfinite(out[i, layout.OB_X_MAX]):
            x0, xd0 = out[i, layout.OB_X_MAX], 0.0
        else:
            x0, xd0 = start
    return out


@checked_keywords(options=True)
def bifurcation_diagram(grid: Grid, along: str = "v", boundaries: bool = True,
                        tol: float = 1e-10, method: str = "auto",
                        **options) -> xr.Dataset:
    """Attractors along ``along``, followed up and down (hysteresis scan).

    Parameters
    ----------
    grid : Grid
        ``along`` swept (its values, in any order, are sorted), every other
        parameter fixed; x0 and xdot0 give the start of the first point of the up
        scan (default: stuck on the belt).
    along : str
        The parameter of the diagram, default the belt speed v.
    boundaries : bool
        Also locate the Hopf point and the stick onset inside the range
        (:func:`sweepcore.locate_boundaries`) and store them, to mark them.
    tol, method, **options
        As :func:`sweepcore.attractor`.

    Returns
    -------
    xarray.Dataset
        Dimensions ``branch`` ("up", "down") and ``along``: x_max, x_min, mean,
        amplitude, floquet, xdot_max, period, stick_fraction (units from
        :data:`sweepcore.variables.OBSERVABLES`), regime and status flags; the
        analytic ``v_star``; with ``boundaries``, ``v_hopf`` and ``v_stick_onset``.
    """
    if along not in AXES[:6]:
        raise ValueError(f"along must be one of {AXES[:6]}, got {along!r}"
                         f"{did_you_mean(along, AXES[:6])}")
    if not isinstance(grid, Grid):
        raise TypeError(f"grid must be a sweepcore.Grid, got {type(grid).__name__}")
    swept = [n for n in grid.swept if n != along]
    values = grid.axis(along)
    if not isinstance(values, np.ndarray) or values.size < 2 or swept:
        raise ValueError(f"a diagram needs {along!r} swept with >= 2 values and every "
                         f"other parameter fixed; swept: {grid.swept}")
    values = np.sort(values)
    o = make_options(method, tol=tol, **options)
    kw = {n: grid.axis(n) for n in AXES}
    kw[along] = float(values[0])
    base = Grid(**kw).rows(0, 1)[0]
    x0, xd0 = grid.axis("x0"), grid.axis("xdot0")
    start = (x0, math.nan if xd0 is None else xd0)
    col = COLUMNS[along]
    up = _follow(base, col, values, start, o)
    last = (up[-1, layout.OB_X_MAX], 0.0) if int(up[-1, layout.OB_STATUS]) == codes.OK \
        else start
    down = _follow(base, col, values[::-1], last, o)[::-1]
    cols = np.stack([up, down])                 # (branch, along, NOBS)

    dims = ("branch", along)
    data = {}
    for name in DIAGRAM_VARIABLES:
        c, *meta = variables.OBSERVABLES[name]
        data[name] = (dims, cols[:, :, c], labels.attrs(*meta))
    for name, meta in (("regime", variables.REGIME), ("status", variables.STATUS)):
        c = layout.OB_REGIME if name == "regime" else layout.OB_STATUS
        data[name] = (dims, cols[:, :, c].astype(np.int8), labels.flag_attrs(meta))
    coords = {n: v for n, v in Grid(**kw).coords().items()
              if n not in (along, "x0", "xdot0")}
    coords[along] = xr.Variable(along, values, {"units": UNITS[along],
                                                "long_name": LONG_NAMES[along]})
    coords["branch"] = xr.Variable("branch", np.array(BRANCHES), {
        "units": "1", "long_name": "direction of the scan (each point started "
                                   "from the previous attractor)"})
    ds = xr.Dataset(data, coords)
    ds["v_star"] = labels.analytic("v_star", ds).variable
    if boundaries:
        found = locate_boundaries(Grid(**{**kw, along: values}), along=along,
                                  tol=min(tol, 1e-10), method=method, **options)
        for name in ("v_hopf", "v_stick_onset"):
            ds[name] = xr.Variable((), float(found[name].values), found[name].attrs)
    ds.attrs.update({
        **labels.provenance(
            f"Bifurcation diagram of the stick-slip friction oscillator along {along}",
            f"sweepcore.bifurcation_diagram({grid!r}, along={along!r}, tol={tol!r}, "
            f"method={method!r})",
            "attractors followed up and down, each started from the previous one "
            "(x0 = x_max, xdot0 = 0)", "Units kN, cm, s."),
        "sweepcore_kind": "bifurcation_diagram",
        "along": along,
        "tol": float(tol),
    })
    return ds
