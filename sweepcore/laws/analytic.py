"""The analytic friction family on the Python side: keywords, columns, numpy forms.

``F(s) = sgn(s) (r_k + (r_y - r_k) exp(-|s|/v_s)) - alpha1 s + alpha2 s^3`` with the
parameters ``r_y, alpha1, alpha2, r_k, v_s`` (keywords of ``Params``, axes of
``Grid``, columns of the kernel rows); the kernels' half is
``sweepcore/_kernels/laws/analytic.py``. ``r_k = r_y`` is Liu's eq. (40); rows with
it run the kernels' ``polynomial`` kind, the others the ``stribeck`` kind. ``v_s = 0``
is the family's limit v_s -> 0+: Coulomb friction with static above kinetic, a jump
from the static bound r_y to the sliding level r_k at zero speed (``F(0+) = r_k``,
sticking holds up to r_y); its sliding field is the polynomial law's with the level
r_k, and such rows run the ``polynomial`` kind too.
"""
from __future__ import annotations

import numpy as np

from .._kernels import layout
from .._kernels import laws as _kernel_laws
from .base import FrictionLaw

PARAMETERS = ("r_y", "alpha1", "alpha2", "r_k", "v_s")
COLUMNS = {"r_y": layout.RY, "alpha1": layout.A1, "alpha2": layout.A2, "r_k": layout.RK,
           "v_s": layout.VS}
# None means "the default": r_k = r_y (no Stribeck term), and then v_s does not
# enter (NaN in kernel rows: any use would show as NaN)
DEFAULTS = {"alpha1": 0.0, "alpha2": 0.0, "r_k": None, "v_s": None}
UNITS = {"r_y": "kN", "alpha1": "kN s cm-1", "alpha2": "kN s3 cm-3", "r_k": "kN",
         "v_s": "cm s-1"}
LONG_NAMES = {
    "r_y": "static friction bound (the largest force sticking holds)",
    "alpha1": "linear friction-speed coefficient",
    "alpha2": "cubic friction-speed coefficient",
    "r_k": "kinetic friction level (Stribeck law; r_k = r_y: none)",
    "v_s": "Stribeck speed (0: a jump from r_y to r_k at zero speed)",
}
RULES = {"r_y": {"nonnegative": True}, "alpha1": {}, "alpha2": {"nonnegative": True},
         "r_k": {"nonnegative": True}, "v_s": {"nonnegative": True}}
_POLYNOMIAL = _kernel_laws.KIND_CODES["polynomial"]
_STRIBECK = _kernel_laws.KIND_CODES["stribeck"]


class AnalyticLaw(FrictionLaw):
    """The keyword family: its parameters live in the rows, one law object for all."""

    kind = "analytic"
    name = "analytic"

    def kernel_groups(self, P):
        polynomial = _no_stribeck(P)
        out = []
        for code, rows in ((_POLYNOMIAL, np.flatnonzero(polynomial)),
                           (_STRIBECK, np.flatnonzero(~polynomial))):
            if rows.size:
                out.append((code, rows, _kernel_laws.LAWS[code][1]()))
        return out

    def missing_column(self, name, P):
        """r_k left out is r_y (no Stribeck term), v_s left out is not used (NaN)."""
        return P[:, layout.RY] if name == "r_k" else np.nan

    def closed_form(self, P):
        return (P[:, layout.A2] == 0.0) & _no_stribeck(P)

    def closed_form_grid(self, where):
        """No cubic term (alpha2 = 0) and no Stribeck term (r_k = r_y, or v_s = 0: a
        jump) anywhere."""
        alpha2 = np.atleast_1d(where.alpha2)
        if (alpha2 != 0.0).any():
            return f"got alpha2={float(alpha2[alpha2 != 0.0][0])!r} (needs alpha2 = 0)"
        r_y, r_k = where.r_y, where.r_k
        if r_k is None or (where.v_s is not None
                           and not np.any(np.atleast_1d(where.v_s) != 0.0)):
            return ""
        a, b = np.atleast_1d(r_y), np.atleast_1d(r_k)
        if getattr(where, "mode", "product") == "points":
            a, b = np.broadcast_arrays(a, b)
            same = bool(np.all(a == b))
        else:
            same = bool(np.all(a == a[0]) and np.all(b == a[0]))
        return "" if same else (f"got r_k={float(b[0])!r} beside r_y={float(a[0])!r} "
                                "(needs r_k = r_y: no Stribeck term)")

    def fingerprint(self):
        return b"analytic"

    def static_bound(self, P):
        return P[:, layout.RY]

    def slope_scale(self, P):
        v = P[:, layout.V]
        with np.errstate(all="ignore"):
            d = P[:, layout.RY] - P[:, layout.RK]
            return np.maximum.reduce([
                np.abs(P[:, layout.A1]), 3.0 * np.abs(P[:, layout.A2]) * v * v,
                np.where(_no_stribeck(P), 0.0, np.abs(d) / P[:, layout.VS])])

    def conservative(self, P):
        """No cubic or Stribeck term and c = alpha1 (kernel ``conservative``)."""
        return ((P[:, layout.A2] == 0.0) & _no_stribeck(P)
                & (P[:, layout.C] == P[:, layout.A1]))

    def attrs(self):
        return {}

    def describe(self):
        return "analytic law"

    def __reduce__(self):
        return (_analytic, ())


def _analytic():
    return ANALYTIC


def _no_stribeck(P):
    """Rows without a Stribeck term: r_k = r_y, or v_s = 0 (the jump's limit)."""
    return (P[:, layout.RY] == P[:, layout.RK]) | (P[:, layout.VS] == 0.0)


ANALYTIC = AnalyticLaw()


def force(zdot, source, value, phase=None) -> np.ndarray:
    """F(zdot) [kN] of the analytic law with the parameters of ``source``, read with
    ``value(source, name)`` (numpy broadcasting); at zdot = 0 the sliding limit of
    the side ``phase`` (``r_k`` for v_s = 0: below the static bound r_y)."""
    zdot = np.asarray(zdot, np.float64)
    s = np.sign(zdot) if phase is None else np.asarray(phase, np.float64)
    r_y = np.asarray(value(source, "r_y"), np.float64)
    r_k = value(source, "r_k")
    d = 0.0 if r_k is None else r_y - np.asarray(r_k, np.float64)
    lev = r_y
    if np.any(d != 0.0):
        v_s = np.asarray(value(source, "v_s"), np.float64)
        with np.errstate(invalid="ignore", divide="ignore"):
            stribeck = d * np.expm1(-np.abs(zdot) / v_s)
        lev = np.where(d == 0.0, r_y, np.where(v_s == 0.0, np.asarray(r_k, np.float64),
                                               r_y + stribeck))
    return (lev * s - value(source, "alpha1") * zdot
            + value(source, "alpha2") * zdot * zdot * zdot)
