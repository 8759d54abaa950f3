"""Leine's decreasing friction law on the Python side (``sweepcore._kernels.laws.leine``).

``F(s) = F_s sgn(s) / (1 + delta |s|)``, sticking up to ``F_s``: the example of
Leine & Nijmeijer, "Dynamics and Bifurcations of Non-Smooth Mechanical Systems"
(Springer 2004), with k = m = F_s = 1, delta = 3 and belt speed 0.2.
"""
from __future__ import annotations

import numpy as np

from .._kernels.laws.leine import Leine
from .base import FrictionLaw, check_name, real


class LeineLaw(FrictionLaw):
    """Leine's law: ``F(s) = f_s sgn(s) / (1 + delta |s|)``.

    Parameters
    ----------
    f_s : float
        Static friction force [kN], > 0 (also the largest force sticking holds).
    delta : float
        Decay rate of the force with the relative speed [s/cm], > 0.
    name : str, optional
        The law's label; default ``"leine"``.
    """

    kind = "leine"
    STUDY_KEYS = {"f_s": "number, required", "delta": "number, required"}

    def __init__(self, f_s, delta, name=None):
        self.f_s = real("f_s", f_s, "kN", positive=True, window=True)
        self.delta = real("delta", delta, "s cm-1", positive=True, window=True)
        self.name = check_name("leine" if name is None else name)
        if not np.isfinite(6.0 * self.f_s * self.delta ** 3):
            raise ValueError(f"f_s = {self.f_s!r} kN with delta = {self.delta!r} s/cm: "
                             "the third derivative at zero speed (6 f_s delta^3) "
                             "overflows float64; choose units in which the "
                             "magnitudes are moderate")

    def data(self):
        return Leine(self.f_s, self.delta)

    def force(self, zdot, phase=None):
        zdot = np.asarray(zdot, np.float64)
        s = np.sign(zdot) if phase is None else np.asarray(phase, np.float64)
        return s * self.f_s / (1.0 + self.delta * np.abs(zdot))

    def static_limits(self):
        return self.f_s, self.f_s

    def slope_scale(self, P):
        return np.full(P.shape[0], self.f_s * self.delta)

    def attrs(self):
        return {"law": self.name, "law_kind": self.kind, "law_f_s": self.f_s,
                "law_delta": self.delta}

    def describe(self):
        return f"Leine's law {self.name!r}: f_s = {self.f_s:g} kN, delta = {self.delta:g} s/cm"

    def fingerprint(self):
        return self.name.encode() + np.array([self.f_s, self.delta]).tobytes()

    def __eq__(self, other):
        return isinstance(other, LeineLaw) and (self.f_s, self.delta, self.name) == \
            (other.f_s, other.delta, other.name)

    __hash__ = None
