"""The external excitation of the slider: its keywords and its kinds.

    m x'' + c (x' - y') + k (x - y) + F(x' - v) = F0 p(Omega t + phi),
    y = Y0 cos(Omega t)

A periodic load of amplitude ``F0`` [kN], frequency ``Omega`` [rad/s] and phase
``phi`` [rad] on the slider, its shape p over one period a
:class:`~sweepcore.excitations.periodic.PeriodicLoad` (``load=``; default one cosine,
Hong & Liu, J. Sound Vib. 229 (2000) 1171-1192; the paper's eq. (4) carries the
load), and a harmonic motion of amplitude ``Y0`` [cm] of the anchor of spring and
damper. F0, Omega, phi and Y0 are keywords of ``Params`` and axes of ``Grid`` like
the slider's parameters, and columns of the kernel rows read only by the excitation
modules (here and ``sweepcore/_kernels/excitations/``); the load's shape is data,
as a law object is (a ``load`` dimension of a Grid over several shapes).

The kinds are rows of ``EXCITATIONS`` (name, module, the class of its load
objects): ``none`` (F0 = Y0 = 0: the autonomous belt, on the autonomous kernels, bit
for bit as without this table) and ``periodic`` (a :class:`PeriodicLoad`, one cosine
by default, and the anchor's motion). The rows of every forced kind run on the
stroboscopic search (``sweepcore.compiled.responses``), compiled for the class of
the load's kernel data. ``sweepcore.excitations.theory`` holds the closed forms of
the forced oscillator.
"""
from __future__ import annotations

import numpy as np

from .._kernels import layout
from . import none, periodic
from .periodic import HARMONIC, PeriodicLoad

EXCITATIONS = (
    ("none", none, None),
    ("periodic", periodic, PeriodicLoad),
)
LOADS = tuple(row[2] for row in EXCITATIONS if row[2] is not None)   # load classes
LOAD_DIM = "load"       # the dimension of a sweep over several load shapes
KEYWORDS = ("F0", "Omega", "phi", "Y0")
UNITS = {"F0": "kN", "Omega": "rad s-1", "phi": "rad", "Y0": "cm"}
LONG_NAMES = {
    "F0": "amplitude of the load F0 p(Omega t + phi) on the slider",
    "Omega": "excitation frequency",
    "phi": "phase of the load",
    "Y0": "amplitude of the anchor's motion Y0 cos(Omega t)",
}
RULES = {"F0": {}, "Omega": {"positive": True}, "phi": {}, "Y0": {}}
DEFAULTS = {"F0": 0.0, "Omega": None, "phi": 0.0, "Y0": 0.0}
COLUMNS = {"F0": layout.F0, "Omega": layout.OMEGA, "phi": layout.PHI, "Y0": layout.Y0}


def kinds(P: np.ndarray) -> np.ndarray:
    """The excitation kind of every kernel row (an index of ``EXCITATIONS``)."""
    forced = (P[:, layout.F0] != 0.0) | (P[:, layout.Y0] != 0.0)
    return forced.astype(np.intp)


def kernel_data(row: np.ndarray, load):
    """The kernels' excitation data of one row: its load's (``load``, or one cosine)
    where it is forced, None where its excitation is none."""
    if kinds(row[None, :])[0] == 0:
        return None
    return (load if load is not None else HARMONIC).data()


def groups(P: np.ndarray):
    """``[(module, rows)]``: the rows of P (indices) of each excitation kind, with
    the kind's module (whose ``run`` solves them)."""
    which = kinds(P)
    return [(module, np.flatnonzero(which == i)) for i, (_n, module, _c) in
            enumerate(EXCITATIONS[:2]) if (which == i).any()]


def given(values: dict) -> bool:
    """Whether keyword values (scalars or arrays, by name) excite the slider."""
    return any(np.any(np.asarray(values.get(n) if values.get(n) is not None else 0.0)
                      != 0.0) for n in ("F0", "Y0"))


def check(where: str, values: dict) -> None:
    """Refuse an excitation without its frequency, naming the keywords."""
    if given(values) and values.get("Omega") is None:
        shown = ", ".join(f"{n}={values[n]!r}" for n in ("F0", "Y0")
                          if values.get(n) is not None and np.any(np.asarray(values[n])))
        raise ValueError(f"{where}: the excitation frequency Omega [rad s-1] is "
                         f"required with {shown}")



def load(params, t: np.ndarray) -> np.ndarray:
    """The excitation of ``params`` as one force on the slider [kN] at the times t
    [s] (``F0 p(Omega t + phi) + k y + c y'``); 0 without one."""
    if not params.forced:
        return np.zeros_like(t)
    return params.loads[0].force(params, np.asarray(t, np.float64))


def check_loads(where: str, load):
    """The load given: None (one cosine), one load object (a class of ``LOADS``), or
    a tuple of them with distinct names (a dimension), refused by name otherwise."""
    many = isinstance(load, (list, tuple))
    loads = tuple(load) if many else (load,)
    if many and not loads:
        raise ValueError(f"{where}: load is an empty list: give at least one load")
    for one in loads:
        if (one is None and not many) or isinstance(one, LOADS):
            continue
        kinds = " or ".join(f"sweepcore.{cls.__name__}" for cls in LOADS)
        raise TypeError(f"{where}: load must be a {kinds} (or a list of them), got "
                        f"{one!r} of type {type(one).__name__}")
    names = [one.name for one in loads if one is not None]
    if len(set(names)) < len(names):
        dup = next(n for n in names if names.count(n) > 1)
        raise ValueError(f"{where}: the loads must have distinct names (they label the "
                         f"load dimension), got {dup!r} twice")
    return loads if many else loads[0]
