"""The ``[excitation]`` table of a study file: the load and the anchor's motion
(``sweepcore.excitations``), each key a scalar or an axis written as in ``[axes]``
(docs/studies.md), and the load's shape::

    [excitation]
    F0 = { start = 0.2, stop = 5.0, num = 256 }     # kN: F0 p(Omega t + phi)
    Omega = { start = 0.1, stop = 3.0, num = 256 }  # rad/s, > 0
    phi = 0.0                                       # rad, |phi| <= 2 pi (default 0)
    Y0 = 0.0                                        # cm: y = Y0 cos(Omega t) (default 0)
    load = { cos = [1.0, 0.0, 0.3], sin = [0.0, 0.2] }  # p (default: cos)
    # or  load = { samples = "force.csv" }: one period at uniform phases
    # or  load = [{ name = "a", cos = [1.0] }, { name = "b", sin = [1.0] }]: a dimension

Omega is required with F0 or Y0; phi is in radians (90 degrees is 1.5708: a phase
beyond 2 pi is refused as degrees written by mistake). The keys live here and not in ``[axes]``, so that a
reader of the file sees at once that the slider is forced; the errors name the key
and its line as those of ``[axes]`` do (the checker of :mod:`sweepcore.study`).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from . import excitations
from .params import check_forcing


def excitation_table(ck, doc: dict, axis, axes: dict) -> dict:
    """The axes of ``[excitation]`` (name -> ``sweepcore.study.Axis``, in file
    order); empty without the table. ``axis(ck, name, val, table)`` builds one axis
    with ``[axes]``'s rules and messages; ``axes`` are those of ``[axes]`` (the
    slider the excitation must suit: ``sweepcore.params.check_forcing``)."""
    if "excitation" not in doc:
        return {}
    table = ck.table(doc, "excitation")
    ck.known(table, excitations.KEYWORDS + ("load",), ("excitation",))
    out = {name: axis(ck, name, val, "excitation") for name, val in table.items()
           if name != "load"}
    forcing = [n for n in ("F0", "Y0") if n in out and np.any(out[n].values != 0.0)]
    if forcing and "Omega" not in out:
        ck.fail(("excitation",), f"Omega (the excitation frequency "
                                 f"[{excitations.UNITS['Omega']}], > 0) is required "
                                 f"with {' and '.join(forcing)}")
    unused = {"Omega": (not forcing, "nothing excites the slider (F0 = Y0 = 0)",
                        "F0 or Y0"),
              "phi": ("F0" not in forcing, "phi is the phase of the load F0 cos(Omega "
                      "t + phi), and F0 = 0", "F0")}
    for name, (idle, why, give) in unused.items():
        if idle and name in out and out[name].swept:
            ck.fail(("excitation", name), f"{name} is swept but {why}: every value "
                                          f"would give the same result; give {give}, "
                                          f"or leave {name} out")
    given = {**axes, **out}
    if forcing and "m" in given and "k" in given:
        try:
            check_forcing("", *(given[n].values if n in given else 0.0
                                            for n in ("m", "k", "c", "F0", "Omega", "Y0")))
        except ValueError as err:
            ck.fail(("excitation",), str(err))
    for other in ("boundary", "basins"):    # searches of the autonomous attractor
        if forcing and other in doc:
            ck.fail((other,), f"[{other}] applies to the unforced slider; this study "
                              f"is forced ({' and '.join(forcing)} in [excitation])")
    return out


def load_table(ck, doc: dict, path):
    """The load's shape of ``[excitation]``'s ``load`` key: a
    :class:`~sweepcore.PeriodicLoad` from its coefficients (``cos``, ``sin``) or
    from a CSV file of samples of one period (``samples``, relative to the study
    file), a tuple of them for an array (a ``load`` dimension), or None (one
    cosine)."""
    given = doc.get("excitation", {}).get("load") if isinstance(doc.get("excitation"),
                                                                dict) else None
    if given is None:
        return None
    many = isinstance(given, list)
    tables = given if many else [given]
    if not tables or not all(isinstance(t, dict) for t in tables):
        ck.fail(("excitation", "load"), "must be a table { cos = [...], sin = [...] }, "
                                        "{ samples = \"file.csv\" } or an array of them")
    loads = []
    for t in tables:
        ck.known(t, ("cos", "sin", "samples", "name"), ("excitation", "load"))
        name = ck.string(("excitation", "load", "name"), t["name"]) if "name" in t else None
        if "samples" in t and ("cos" in t or "sin" in t):
            ck.fail(("excitation", "load"), "give samples or coefficients (cos, sin), "
                                            "not both")
        try:
            if "samples" in t:
                file = Path(ck.string(("excitation", "load", "samples"), t["samples"]))
                if not file.is_absolute() and path is not None:
                    file = Path(path).parent / file
                loads.append(excitations.PeriodicLoad.from_csv(file, name=name))
            else:
                loads.append(excitations.PeriodicLoad(t.get("cos", ()), t.get("sin", ()),
                                                      name=name))
        except (TypeError, ValueError) as err:
            ck.fail(("excitation", "load"), str(err))
    try:
        return excitations.check_loads("[excitation]", tuple(loads) if many else loads[0])
    except (TypeError, ValueError) as err:
        ck.fail(("excitation", "load"), str(err))
