"""Parameters of one slider, validated at the boundary, with derived quantities.

Units (the paper's): force kN, length cm, time s, so mass is kN s^2/cm, stiffness
kN/cm, alpha1 kN s/cm and alpha2 kN s^3/cm^3.
"""
from __future__ import annotations

import cmath
import difflib
import functools
import inspect
import math
import numbers
from dataclasses import dataclass

import numpy as np

UNITS = {
    "m": "kN s2 cm-1", "k": "kN cm-1", "r_y": "kN", "v": "cm s-1",
    "alpha1": "kN s cm-1", "alpha2": "kN s3 cm-3", "x0": "cm", "xdot0": "cm s-1",
}
# units of the run settings, for the messages of check_real
SETTING_UNITS = {"t_end": "s", "output_dt": "s", "dt": "s"}
LONG_NAMES = {
    "m": "slider mass", "k": "spring stiffness", "r_y": "friction bound",
    "v": "belt speed", "alpha1": "linear friction-speed coefficient",
    "alpha2": "cubic friction-speed coefficient", "x0": "initial position",
    "xdot0": "initial velocity",
}


def check_real(name: str, value, *, positive=False, nonnegative=False) -> float:
    """Return ``value`` as a float, or raise naming the parameter and the value.

    Accepts Python and NumPy real numbers; rejects bool, complex, strings, NaN and
    infinities. ``positive`` demands > 0, ``nonnegative`` >= 0.
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {value!r} "
                        f"of type {type(value).__name__}")
    x = float(value)
    if not math.isfinite(x):
        raise ValueError(f"{name} must be finite, got {value!r}")
    units = UNITS.get(name) or SETTING_UNITS.get(name)
    units = f" [{units}]" if units else ""
    if positive and not x > 0.0:
        raise ValueError(f"{name} must be > 0{units}, got {value!r}")
    if nonnegative and not x >= 0.0:
        hint = (" (a negative cubic coefficient makes the friction force unbounded "
                "at high sliding speed)") if name == "alpha2" else ""
        raise ValueError(f"{name} must be >= 0{units}, got {value!r}{hint}")
    return x


DERIVED = {
    "omega": "natural frequency sqrt(k/m) [1/s]",
    "q": "Hopf quantity (alpha1 - 3 alpha2 v^2)/m [1/s] of eq. (46)",
    "x_eq": "equilibrium (r_y - alpha1 |v| + alpha2 |v|^3)/k [cm] of eq. (43)",
    "length": "length scale r_y/k + |v|/omega [cm]",
}


def derived_bounds(m, k, r_y, v, alpha1, alpha2) -> dict[str, float]:
    """Largest magnitudes of the derived quantities over the given ranges.

    Each argument is a (low, high) pair of the parameter's range (or its value
    twice). Sums of absolute values are used, so a finite bound means every
    derived quantity of every combination is finite; ``omega`` is bounded below as
    well (its low value, which must be > 0). Overflow gives inf or NaN.
    """
    with np.errstate(all="ignore"):
        lo = {n: np.float64(min(x)) for n, x in dict(m=m, k=k).items()}
        hi = {n: np.float64(max(np.abs(x))) for n, x in dict(
            m=m, k=k, r_y=r_y, v=v, alpha1=alpha1, alpha2=alpha2).items()}
        w_hi = np.sqrt(hi["k"] / lo["m"])
        w_lo = np.sqrt(lo["k"] / hi["m"])
        va = hi["v"]
        return {
            "omega": float(w_hi if w_lo > 0.0 else np.nan),
            "q": float((hi["alpha1"] + 3.0 * hi["alpha2"] * va ** 2) / lo["m"]),
            "x_eq": float((hi["r_y"] + hi["alpha1"] * va + hi["alpha2"] * va ** 3)
                          / lo["k"]),
            "length": float(hi["r_y"] / lo["k"] + va / w_lo),
        }


def check_derived(where: str, ranges: dict) -> None:
    """Refuse parameter magnitudes whose derived quantities overflow float64 (or
    whose natural frequency underflows to 0), naming them and the values.

    ``ranges``: parameter name -> (low, high).
    """
    bounds = derived_bounds(**ranges)
    bad = [n for n, b in bounds.items() if not math.isfinite(b)]
    if bad:
        shown = ", ".join(f"{n}={lo!r}" if lo == hi else f"{n} in [{lo!r}, {hi!r}]"
                          for n, (lo, hi) in ranges.items())
        what = " and the ".join(DERIVED[n] for n in bad)
        verb = "overflow" if len(bad) > 1 else "overflows"
        zero = " (or omega underflows to 0)" if "omega" in bad else ""
        raise ValueError(f"{where}: the {what} {verb} float64{zero} with {shown}; "
                         "choose units in which the magnitudes are moderate")


@dataclass(frozen=True)
class Params:
    """One slider on the belt (Liu, Fig. 1), friction law eq. (40).

    Parameters
    ----------
    m : float
        Mass [kN s^2/cm], > 0.
    k : float
        Stiffness [kN/cm], > 0.
    r_y : float
        Friction bound [kN], >= 0.
    v : float
        Belt speed [cm/s], any finite value: ``v < 0`` is the mirror image of
        ``-v``, ``v = 0`` a static belt.
    alpha1 : float
        Linear coefficient of eq. (40) [kN s/cm], any finite value.
    alpha2 : float
        Cubic coefficient of eq. (40) [kN s^3/cm^3], >= 0.

    Raises
    ------
    TypeError, ValueError
        A parameter that is not a finite real number in its range, or magnitudes
        whose derived quantities (omega, q, x_eq, the length scale) overflow.
    """

    m: float
    k: float
    r_y: float
    v: float
    alpha1: float = 0.0
    alpha2: float = 0.0

    def __post_init__(self):
        for name, kw in (("m", dict(positive=True)), ("k", dict(positive=True)),
                         ("r_y", dict(nonnegative=True)), ("v", {}), ("alpha1", {}),
                         ("alpha2", dict(nonnegative=True))):
            object.__setattr__(self, name, check_real(name, getattr(self, name), **kw))
        check_derived("Params", {n: (getattr(self, n),) * 2 for n in
                                 ("m", "k", "r_y", "v", "alpha1", "alpha2")})

    @property
    def omega(self) -> float:
        """Natural frequency sqrt(k/m) [1/s]."""
        return math.sqrt(self.k / self.m)

    @property
    def q(self) -> float:
        """Hopf quantity q = (alpha1 - 3 alpha2 v^2)/m [1/s], eq. (46).

        The equilibrium's eigenvalues solve lambda^2 - q lambda + omega^2 = 0
        (eq. 45): stable for q < 0, unstable for q > 0.
        """
        return (self.alpha1 - 3.0 * self.alpha2 * self.v ** 2) / self.m

    @property
    def v_star(self) -> float:
        """Hopf belt speed sqrt(alpha1 / (3 alpha2)) [cm/s], below eq. (51).

        ``inf`` when alpha2 = 0 and alpha1 > 0 (q > 0 at every speed), ``nan``
        when alpha1 <= 0 and alpha2 = 0 or alpha1 < 0 (q <= 0 at every speed:
        there is no crossing), and 0 when alpha1 = 0 < alpha2.
        """
        if self.alpha2 == 0.0:
            return math.inf if self.alpha1 > 0.0 else math.nan
        if self.alpha1 < 0.0:
            return math.nan
        return math.sqrt(self.alpha1 / (3.0 * self.alpha2))

    @property
    def x_eq(self) -> float:
        """Steady-sliding equilibrium (r_y - alpha1 v + alpha2 v^3)/k [cm], eq. (43).

        Written for v > 0 (the slider slower than the belt). For v < 0 the mirror
        image -x_eq(-v) is returned; for v = 0 there is a band of rest positions
        |x| <= r_y/k and the value returned is 0.
        """
        v = self.v
        if v == 0.0:
            return 0.0
        sgn = 1.0 if v > 0 else -1.0
        va = abs(v)
        return sgn * (self.r_y - self.alpha1 * va + self.alpha2 * va ** 3) / self.k

    @property
    def eigenvalues(self) -> tuple[complex, complex]:
        """Roots of eq. (45), lambda^2 - q lambda + omega^2 = 0 [1/s]."""
        q = self.q
        d = cmath.sqrt(q * q - 4.0 * self.omega ** 2)
        return (0.5 * (q + d), 0.5 * (q - d))

    def row(self, x0: float, xdot0: float) -> np.ndarray:
        """The kernel's flat parameter row (layout.py)."""
        return np.array([self.m, self.k, self.r_y, self.v, self.alpha1, self.alpha2,
                         x0, xdot0], dtype=np.float64)


def did_you_mean(fn):
    """Wrap ``fn`` so that a misspelt keyword argument gets "did you mean" (difflib).

    The signature is kept (``functools.wraps`` exposes the original to ``inspect``);
    a known keyword costs one set lookup.
    """
    params = inspect.signature(fn).parameters.values()
    names = [p.name for p in params if p.name != "self" and p.kind in (
        p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)]
    known = set(names)
    owner = fn.__qualname__.removesuffix(".__init__")

    @functools.wraps(fn)
    def checked(*args, **kwargs):
        for key in kwargs:
            if key not in known:
                close = difflib.get_close_matches(key, names, n=1)
                hint = f"; did you mean {close[0]!r}?" if close else ""
                raise TypeError(f"{owner}() got an unexpected keyword argument {key!r}"
                                f"{hint} (allowed: {', '.join(names)})")
        return fn(*args, **kwargs)
    return checked


Params.__init__ = did_you_mean(Params.__init__)