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

``kind`` names a class of the law table (``sweepcore.laws.LAWS``; default
``"table"``), whose ``STUDY_KEYS`` are the keys it takes. A list of them
(``[[law]]``) is a ``law`` dimension. A table's path is relative to the study file.
"""
from __future__ import annotations

from pathlib import Path

from .laws import OBJECTS, analytic


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
    kinds = {cls.kind: cls for cls in OBJECTS}
    cls = kinds[ck.string(("law", "kind"), table.get("kind", "table"), tuple(kinds))]
    ck.known(table, ("kind", "name") + tuple(cls.STUDY_KEYS), ("law",))
    values = {}
    for key, what in cls.STUDY_KEYS.items():
        kp = ("law", key)
        if key not in table:
            if what.endswith("required"):
                ck.fail(("law",), f"the {cls.kind} law needs {key}")
            continue
        if what.startswith("path"):
            file = Path(ck.string(kp, table[key]))
            values[key] = file if file.is_absolute() or path is None else \
                Path(path).parent / file
        else:
            values[key] = ck.real(kp, table[key], name=key, positive=True)
    if "name" in table:
        values["name"] = ck.string(("law", "name"), table["name"])
    for key, what in cls.STUDY_KEYS.items():       # a file that cannot be read: its key
        if what.startswith("path") and key in values and not values[key].is_file():
            ck.fail(("law", key), f"no file {str(values[key])!r}")
    try:
        return cls.from_study(values)
    except (OSError, ValueError, TypeError) as err:
        ck.fail(("law",), str(err))
