"""The ``[boundary]`` table of a study file (``sweepcore boundary``; docs/studies.md):
what to locate, continue or scan along one parameter, validated with the key and
line of every error (the checker of :mod:`sweepcore.study`)."""
from __future__ import annotations

import math

from . import law
from .params import UNITS


BOUNDARY_KEYS = ("along", "bracket", "xtol", "scan", "offset", "tol", "continuation",
                 "diagram", "sweep", "over", "path", "png")
BOUNDARY_ALONG = law.PARAMETERS


def boundary_table(ck, doc: dict, axes: dict) -> dict:
    """The ``[boundary]`` table of ``sweepcore boundary`` (docs/studies.md); ``{}``
    when the study has none (``sweepcore boundary`` then validates the defaults)."""
    from .study import _describe          # the checker's own wording of a value
    if "boundary" not in doc:
        return {}
    table = ck.table(doc, "boundary")
    ck.known(table, BOUNDARY_KEYS, ("boundary",))
    kp = lambda key: ("boundary", key)   # noqa: E731
    out = {"along": "v", "xtol": 1e-9, "scan": 32, "offset": 5e-3, "tol": 1e-10,
           "continuation": None, "diagram": False, "over": None, "path": None,
           "png": None, "bracket": None, "sweep": "both"}
    if "along" in table:
        out["along"] = ck.string(kp("along"), table["along"], BOUNDARY_ALONG)
    along = out["along"]
    if "bracket" in table:
        val = table["bracket"]
        if not isinstance(val, list) or len(val) != 2:
            ck.fail(kp("bracket"), f"must be an array [lo, hi] of two numbers "
                                   f"[{UNITS[along]}], got {_describe(val)}")
        lo, hi = (ck.real(kp("bracket"), x, name=along) for x in val)
        if not lo < hi:
            ck.fail(kp("bracket"), f"needs lo < hi, got {val!r}")
        if along == "v" and not lo > 0.0:
            ck.fail(kp("bracket"), f"along v the bracket must lie in v > 0, got "
                                   f"lo = {lo!r}")
        out["bracket"] = (lo, hi)
    elif along not in axes or axes[along].values.size < 2:
        ck.fail(("boundary",), f"give bracket = [lo, hi] or sweep {along!r} in [axes] "
                               "(its range is the default bracket)")
    for key in ("xtol", "offset", "tol"):
        if key in table:
            x = ck.real(kp(key), table[key], positive=True)
            limit = {"xtol": math.inf, "offset": 0.1, "tol": 1.0}[key]
            if not x < limit:
                ck.fail(kp(key), f"must be a number in (0, {limit:g}), got "
                                 f"{table[key]!r}")
            out[key] = x
    if "scan" in table:
        out["scan"] = ck.integer(kp("scan"), table["scan"], minimum=3)
    swept = [n for n, a in axes.items() if a.values.size > 1 and n != along]
    if "continuation" in table:
        name = ck.string(kp("continuation"), table["continuation"], swept or ["(none)"])
        others = [n for n in swept if n != name]
        if others:
            ck.fail(kp("continuation"), f"continuation along {name!r} needs every other "
                                        f"parameter fixed; also swept: "
                                        f"{', '.join(others)}")
        if along != "v":
            ck.fail(kp("continuation"), f"continuation follows boundaries along v "
                                        f"only, got along = {along!r}")
        out["continuation"] = name
    if "diagram" in table:
        val = table["diagram"]
        if not isinstance(val, bool):
            ck.fail(kp("diagram"), f"must be true or false, got {_describe(val)}")
        if val and swept:
            ck.fail(kp("diagram"), f"a diagram along {along!r} needs every other "
                                   f"parameter fixed; swept: {', '.join(swept)}")
        if val and out["continuation"]:
            ck.fail(kp("diagram"), "choose a diagram or a continuation, not both")
        out["diagram"] = val
    if "sweep" in table:
        out["sweep"] = ck.string(kp("sweep"), table["sweep"], ("up", "down", "both"))
        if not out["diagram"]:
            ck.fail(kp("sweep"), "the scan direction applies to a diagram "
                                 "(diagram = true)")
    for key, suffix in (("over", ".nc"), ("path", ".nc"), ("png", ".png")):
        if key in table:
            name = ck.string(kp(key), table[key])
            if not name.endswith(suffix):
                ck.fail(kp(key), f"must end in {suffix}, got {name!r}")
            out[key] = name
    return out
