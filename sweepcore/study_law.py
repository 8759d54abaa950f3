"""The ``[law]`` table of a study file: a friction law given as an object instead of
the analytic parameters of ``[axes]`` (docs/studies.md), validated with the key and
line of every error (the checker of :mod:`sweepcore.study`).

::

    [law]
    table = "friction.csv"   # header 'speed [cm/s],force [kN]' (m/s, mm/s; N too)
    static = 1.2             # kN, optional: the largest force sticking holds
    smoothing = 0.005        # kN, optional: the forces' noise (a smoothing fit)
    name = "measured"        # optional; default the file's stem

    [law]
    kind = "leine"           # Leine's law F = f_s sgn(s) / (1 + delta |s|)
    f_s = 1.0                # kN
    delta = 3.0              # s/cm

A list of them (``[[law]]``) is a ``law`` dimension. The table's path is relative to
the study file.
"""
from __future__ import annotations

from pathlib import Path

from .laws import analytic

KINDS = {"table": ("table", "static", "smoothing", "name"),
         "leine": ("f_s", "delta", "name")}


def law_table(ck, doc: dict, axes: dict, path):
    """The validated law of ``[law]`` (a law object, a tuple of them for ``[[law]]``),
    or None without one (the analytic law of ``[axes]``)."""
    if "law" not in doc:
        return None
    given = doc["law"]
    many = isinstance(given, list)
    tables = given if many else [given]
    if not tables or not all(isinstance(t, dict) for t in tables):
        ck.fail(("law",), "must be a table [law] or an array of tables [[law]]")
    for name in analytic.PARAMETERS:
        if name in axes:
            ck.fail(("axes", name), f"{name} is a parameter of the analytic law; the "
                                    "[law] table replaces it (remove one of them)")
    laws = tuple(_one(ck, t, path) for t in tables)
    names = [law.name for law in laws]
    if len(set(names)) < len(names):
        ck.fail(("law", "name"), f"the laws of [[law]] need distinct names, got {names}")
    return laws if many else laws[0]


def _one(ck, table: dict, path):
    from .laws import LeineLaw, TableLaw
    kind = ck.string(("law", "kind"), table.get("kind", "table"), tuple(KINDS))
    ck.known(table, ("kind",) + KINDS[kind], ("law",))
    opts = {}
    if "name" in table:
        opts["name"] = ck.string(("law", "name"), table["name"])
    try:
        if kind == "leine":
            for key in ("f_s", "delta"):
                if key not in table:
                    ck.fail(("law",), f"Leine's law needs {key}")
            return LeineLaw(ck.real(("law", "f_s"), table["f_s"], name="f_s"),
                            ck.real(("law", "delta"), table["delta"], name="delta"),
                            **opts)
        if "table" not in table:
            ck.fail(("law",), "needs table = \"FILE.csv\" (columns 'speed [cm/s],force "
                              "[kN]')")
        csv = Path(ck.string(("law", "table"), table["table"]))
        if not csv.is_absolute() and path is not None:
            csv = Path(path).parent / csv
        for key in ("static", "smoothing"):
            if key in table:
                opts[key] = ck.real(("law", key), table[key], name=key, positive=True)
        return TableLaw.from_csv(csv, **opts)
    except (OSError, ValueError, TypeError) as err:
        ck.fail(("law",), str(err))
