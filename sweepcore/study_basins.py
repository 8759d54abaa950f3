"""The ``[basins]`` table of a study file (``sweepcore basins``; docs/studies.md):
the box of start states and the route of :func:`sweepcore.basin_stability`,
validated with the key and line of every error (the checker of
:mod:`sweepcore.study`)."""
from __future__ import annotations

BASINS_KEYS = ("x0", "xdot0", "samples", "route", "sampling", "seed", "checks", "ftol",
               "match", "path", "png")
DEFAULTS = {"x0": (-2.0, 2.0), "xdot0": (0.0, 2.0), "samples": 1000, "route": "auto",
            "sampling": "uniform", "seed": 0, "checks": 16, "ftol": 1e-6, "match": 1e-5,
            "path": None, "png": None}
UNITS = {"x0": "cm", "xdot0": "cm/s"}


def basins_table(ck, doc: dict, axes: dict) -> dict:
    """The validated ``[basins]`` table (defaults filled in); ``{}`` without one."""
    from .basins import ROUTES, SAMPLINGS

    if "basins" not in doc:
        return {}
    table = ck.table(doc, "basins")
    ck.known(table, BASINS_KEYS, ("basins",))
    out = dict(DEFAULTS)
    for name in ("x0", "xdot0"):
        if name in axes and axes[name].values.size > 1:
            ck.fail(("axes", name), f"the [basins] box gives the starts: {name} must "
                                    "not be swept")
        if name in table:
            val = table[name]
            if not isinstance(val, list) or len(val) != 2:
                ck.fail(("basins", name), f"must be an array [lo, hi] of two numbers "
                                          f"[{UNITS[name]}], got {val!r}")
            lo, hi = (ck.real(("basins", name), x, name=name) for x in val)
            if not lo < hi:
                ck.fail(("basins", name), f"needs lo < hi, got {val!r}")
            out[name] = (lo, hi)
    for key, least in (("samples", 1), ("checks", 1), ("seed", 0)):
        if key in table:
            out[key] = ck.integer(("basins", key), table[key], minimum=least)
    for key, choices in (("route", ROUTES), ("sampling", SAMPLINGS)):
        if key in table:
            out[key] = ck.string(("basins", key), table[key], choices)
    for key in ("ftol", "match"):
        if key in table:
            x = ck.real(("basins", key), table[key], positive=True)
            if not x < 1.0:
                ck.fail(("basins", key), f"must be a number in (0, 1), got {x!r}")
            out[key] = x
    for key, suffix in (("path", ".nc"), ("png", ".png")):
        if key in table:
            name = ck.string(("basins", key), table[key])
            if not name.endswith(suffix):
                ck.fail(("basins", key), f"must end in {suffix}, got {name!r}")
            out[key] = name
    _check_size(ck, doc, axes, table, out)
    return out


def _check_size(ck, doc: dict, axes: dict, table: dict, out: dict) -> None:
    """The size rule of :func:`sweepcore.basin_stability` (the estimate in the
    message), before anything runs; blamed on the key that makes the call too large
    (samples, checks, or the axes)."""
    import math

    from .sizing import basin_need, too_large

    points = math.prod(a.values.size for a in axes.values())
    chunks = doc.get("solver", {}).get("chunks") if isinstance(doc.get("solver"),
                                                                dict) else None
    chunks = chunks if isinstance(chunks, int) and chunks >= 1 else None
    why = too_large(basin_need(points, out["samples"], out["checks"], out["route"],
                               chunks))
    if why is None:
        return
    alone = {key: too_large(basin_need(points, out["samples"] if key == "samples"
                                       else 1, out["checks"] if key == "checks" else 1,
                                       out["route"], chunks))
             for key in ("samples", "checks")}
    blamed = [k for k in ("samples", "checks") if alone[k] and k in table]
    ck.fail(("basins", blamed[0]) if blamed else ("axes",), why)
