"""The friction law's derived quantities, for the Python side (one home).

Every Python room (Params, Grid, sweep, simulate, boundaries, plot, benchmarks)
reads q, x_eq, the Hopf speed and the friction force from here, never from a copy
of the formula. A *source* is anything that holds the parameters by name: a
:class:`sweepcore.Params`, a mapping (dict of numbers or arrays), an
``xarray.Dataset`` (its coordinates broadcast by dimension name) or a kernel row
(``from_row``).

Law, eq. (40) of Liu's paper: ``r_a = r_y sgn(zdot) - alpha1 zdot + alpha2 zdot^3``.
"""
from __future__ import annotations

import numpy as np

from ._kernels import layout

# parameters of the slider and its law, in the order of the kernel row
PARAMETERS = ("m", "k", "r_y", "v", "alpha1", "alpha2")
DEFAULTS = {"alpha1": 0.0, "alpha2": 0.0}
_COLUMNS = {"m": layout.M, "k": layout.K, "r_y": layout.RY, "v": layout.V,
            "alpha1": layout.A1, "alpha2": layout.A2}


def value(source, name: str):
    """Parameter ``name`` of ``source`` (mapping, Dataset or attributes), else its
    default."""
    try:
        return source[name]
    except (KeyError, TypeError, IndexError):
        pass
    got = getattr(source, name, None)
    if got is not None:
        return got
    if name in DEFAULTS:
        return DEFAULTS[name]
    raise KeyError(f"the friction law needs parameter {name!r}, which {type(source).__name__} "
                   "does not hold")


def from_row(row) -> dict:
    """A source made of a kernel parameter row (layout ``sweepcore._kernels.layout``)."""
    return {name: float(row[col]) for name, col in _COLUMNS.items()}


# --------------------------------------------------- vectorised formulas
def omega(m, k):
    """Natural frequency sqrt(k/m) [1/s]."""
    return np.sqrt(np.asarray(k, np.float64) / m)


def hopf_q(m, v, alpha1, alpha2):
    """Hopf quantity q = (alpha1 - 3 alpha2 v^2)/m [1/s], eq. (46)."""
    return (np.asarray(alpha1, np.float64) - 3.0 * alpha2 * np.asarray(v) ** 2) / m


def v_star(alpha1, alpha2):
    """Hopf belt speed sqrt(alpha1/(3 alpha2)) [cm/s], below eq. (51).

    inf when alpha2 = 0 < alpha1, NaN when alpha2 = 0 >= alpha1 or alpha1 < 0
    (no crossing of q = 0), as :attr:`sweepcore.Params.v_star`.
    """
    a1, a2 = np.broadcast_arrays(np.asarray(alpha1, np.float64),
                                 np.asarray(alpha2, np.float64))
    with np.errstate(divide="ignore", invalid="ignore"):
        root = np.sqrt(a1 / (3.0 * a2))
    none = np.where(a1 > 0.0, np.inf, np.nan)
    return np.where(a2 == 0.0, none, np.where(a1 < 0.0, np.nan, root))


def x_eq(k, r_y, v, alpha1, alpha2):
    """Steady-sliding position sgn(v)(r_y - alpha1|v| + alpha2|v|^3)/k [cm], eq. (43).

    0 for v = 0 (the middle of the band of rest positions), as
    :attr:`sweepcore.Params.x_eq`.
    """
    v = np.asarray(v, np.float64)
    va = np.abs(v)
    x = np.sign(v) * (r_y - alpha1 * va + alpha2 * va ** 3) / k
    return np.where(v == 0.0, 0.0, x)


# name -> (function, the parameters it takes, in order)
DERIVED = {
    "q": (hopf_q, ("m", "v", "alpha1", "alpha2")),
    "v_star": (v_star, ("alpha1", "alpha2")),
    "x_eq": (x_eq, ("k", "r_y", "v", "alpha1", "alpha2")),
    "omega": (omega, ("m", "k")),
}


def derived(name: str, source):
    """Derived quantity ``name`` (a key of ``DERIVED``) of ``source``."""
    fn, args = DERIVED[name]
    return fn(*(value(source, a) for a in args))


def friction(zdot, source, phase=None):
    """Friction force r_a on the slider while sliding [kN], eq. (40).

    ``phase`` is the sign of zdot (+1, -1); by default ``sign(zdot)``.
    """
    zdot = np.asarray(zdot, np.float64)
    s = np.sign(zdot) if phase is None else phase
    return (value(source, "r_y") * s - value(source, "alpha1") * zdot
            + value(source, "alpha2") * zdot ** 3)


def stick_onset_estimate(source):
    """First-order averaging estimate 2 v*/sqrt(5) of the belt speed [cm/s] below
    which a slip cycle reaches belt speed (sticks): the averaged cycle's velocity
    amplitude 2 sqrt(v*^2 - v^2) reaches v."""
    return 2.0 / np.sqrt(5.0) * derived("v_star", source)
