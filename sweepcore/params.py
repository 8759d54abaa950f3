"""Parameters of one slider, validated at the boundary, with derived quantities.

Units (the paper's): force kN, length cm, time s, so mass is kN s^2/cm, stiffness
kN/cm, alpha1 kN s/cm and alpha2 kN s^3/cm^3.
"""
from __future__ import annotations

import cmath
import math
import numbers
from dataclasses import dataclass

import numpy as np

from . import excitations, law
from ._kernels import layout
from .laws import ANALYTIC, OBJECTS
from .laws import analytic as _analytic
from .options import checked_keywords

UNITS = {
    "m": "kN s2 cm-1", "k": "kN cm-1", "r_y": "kN", "v": "cm s-1",
    "alpha1": "kN s cm-1", "alpha2": "kN s3 cm-3", "c": "kN s cm-1", "r_k": "kN",
    "v_s": "cm s-1", "x0": "cm", "xdot0": "cm s-1", **excitations.UNITS,
}
# units of the run settings, for the messages of check_real
SETTING_UNITS = {"t_end": "s", "output_dt": "s", "dt": "s"}
LONG_NAMES = {
    "m": "slider mass", "k": "spring stiffness",
    "r_y": "static friction bound (the largest force sticking holds)",
    "v": "belt speed", "alpha1": "linear friction-speed coefficient",
    "alpha2": "cubic friction-speed coefficient", "c": "viscous damping coefficient",
    "r_k": "kinetic friction level (Stribeck law; r_k = r_y: none)",
    "v_s": "Stribeck speed (0: a jump from r_y to r_k)", "x0": "initial position",
    "xdot0": "initial velocity",
    **excitations.LONG_NAMES,
}
# validation rules of every parameter (check_real keywords)
RULES = {"m": {"positive": True}, "k": {"positive": True}, "r_y": {"nonnegative": True},
         "v": {}, "alpha1": {}, "alpha2": {"nonnegative": True},
         "c": {"nonnegative": True}, "r_k": {"nonnegative": True},
         "v_s": {"nonnegative": True}, "x0": {}, "xdot0": {}, **excitations.RULES}
# a phase is in radians: |phi| <= 2 pi (a phase of 90 is 90 degrees, by mistake)
RULES["phi"] = {**RULES["phi"], "phase": True}
PHASE_MAX = 2.0 * math.pi


def check_real(name: str, value, *, positive=False, nonnegative=False,
               phase=False) -> float:
    """Return ``value`` as a float, or raise naming the parameter and the value.

    Accepts Python and NumPy real numbers; rejects bool, complex, strings, NaN and
    infinities. ``positive`` demands > 0, ``nonnegative`` >= 0, ``phase`` an angle
    in radians, ``|value| <= 2 pi`` (:func:`phase_error`).
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {value!r} "
                        f"of type {type(value).__name__}")
    try:
        x = float(value)
    except OverflowError:       # an integer beyond float64 (10**400)
        raise ValueError(f"{name} must be finite, got {_short(value)}, beyond the "
                         "largest float64 (1.8e308)") from None
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
    if phase and not abs(x) <= PHASE_MAX:
        raise ValueError(phase_error(name, x))
    return x


def phase_error(name: str, x: float) -> str:
    """The refusal of a phase beyond 2 pi: most likely degrees."""
    return (f"{name} is a phase in radians, |{name}| <= 2 pi = {PHASE_MAX:.6g} [rad], "
            f"got {x!r}; if that is {x:g} degrees, give {name} = "
            f"{math.radians(x):.6g} (math.radians({x:g}))")


def _short(value) -> str:
    """``repr`` of a number, or the size of a huge integer (a 400-digit repr says
    nothing, and beyond 4300 digits Python refuses to print one)."""
    if isinstance(value, numbers.Integral) and abs(int(value)).bit_length() > 64:
        exponent = int(abs(int(value)).bit_length() * math.log10(2))
        return f"an integer of about {'-' if value < 0 else ''}1e{exponent}"
    return repr(value)


DERIVED = {
    "omega": "natural frequency sqrt(k/m) [1/s]",
    "q": "Hopf quantity -(c + F'(-v))/m [1/s] (eq. 46)",
    "x_eq": "equilibrium -F(-v)/k [cm] (eq. 43)",
    "length": "length scale r_y/k + |v|/omega [cm]",
}


def derived_bounds(m, k, r_y, v, alpha1, alpha2, c=(0.0,), r_k=(0.0,),
                   v_s=(1.0,)) -> dict[str, float]:
    """Largest magnitudes of the derived quantities over the given ranges.

    Each argument is a (low, high) pair of the parameter's range (or its value
    twice); for v_s the smallest positive value (a v_s of 0, the jump, adds no
    slope: give ``(inf, inf)`` where every v_s is 0). Sums of absolute values are
    used, so a finite bound means every derived quantity of every combination is
    finite; ``omega`` is bounded below as well (its low value, which must be > 0).
    Overflow gives inf or NaN.
    """
    v_s = tuple(x for x in v_s if x > 0.0) or (np.inf,)
    with np.errstate(all="ignore"):
        lo = {n: np.float64(min(x)) for n, x in dict(m=m, k=k, v_s=v_s).items()}
        hi = {n: np.float64(max(np.abs(x))) for n, x in dict(
            m=m, k=k, r_y=r_y, v=v, alpha1=alpha1, alpha2=alpha2, c=c, r_k=r_k).items()}
        w_hi = np.sqrt(hi["k"] / lo["m"])
        w_lo = np.sqrt(lo["k"] / hi["m"])
        va = hi["v"]
        drop = hi["r_y"] + hi["r_k"]          # bounds |r_y - r_k|
        return {
            "omega": float(w_hi if w_lo > 0.0 else np.nan),
            "q": float((hi["alpha1"] + 3.0 * hi["alpha2"] * va ** 2 + hi["c"]
                        + drop / lo["v_s"]) / lo["m"]),
            "x_eq": float((drop + hi["alpha1"] * va + hi["alpha2"] * va ** 3)
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


# ------------------------------------------------- the excitation the kernels resolve
# The forcing frequency against the natural one, r = Omega/omega (as law.unresolvable's
# magnitudes, measured on the paper's slider m = 5, k = 50, r_y = 10, v = 2 with c = 1
# and F0 = 1 against the closed form F0/sqrt((k - m Omega^2)^2 + (c Omega)^2) of its
# stick-free response): right to 2e-14 down to r = 1e-7, where a forcing period of
# 1/r natural periods took 8.5e8 steps (85/r; 386 s for the one point); below 1e-8
# the rounding of t over those steps (85/r x 1.1e-16) passes the 1e-6 of an answer.
# Above, the search's 2000 natural periods are 2000 r forcing periods of >= 1 step,
# more than the largest step budget (2**53) from r = 4.5e12 on (measured: a status,
# unresolved, from r = 1e5 on, where the response F0/(m Omega^2) falls below 1e-12 L).
FORCING_RATIO = (1e-8, 1e12)
# The forcing period [s] the drivers step through: their step floor is EPS max(|t|,
# 1 s), so a period of 2e-14 s ended in step_size_underflow (m = 5, r = 1e14; m =
# 5e-20 from r = 1e12 on), 4e-14 s was right.
FORCING_PERIOD_MIN = 1e-13
# The state the drivers keep finite (codes.DIVERGED: |x|, |zdot| > 1e150 diverged):
# the excitation's own length (|F0| + k |Y0| + c Omega |Y0|)/k [cm] and its speed
# Omega times that [cm/s] (measured: F0 = 1e150 with k = 50 right, 1e160 diverged).
STATE_MAX = 1e150


def check_forcing(where: str, m, k, c, F0, Omega, Y0, paired: bool = False) -> None:
    """Refuse an excitation the forced kernels cannot resolve, naming the input, its
    value and the limit: ``Omega/omega`` outside :data:`FORCING_RATIO`, a forcing
    period ``2 pi/Omega`` below :data:`FORCING_PERIOD_MIN` or not finite, or the
    excitation's length or speed beyond :data:`STATE_MAX`.

    Each argument is a number or a 1-D array; ``paired`` arrays are read index by
    index (``Grid.points``), else their extremes are combined (an outer product
    holds every combination, so the extremes are attained). ``where`` (the caller,
    or "") begins the message."""
    arrays = {n: np.atleast_1d(np.asarray(a, np.float64)) for n, a in
              dict(m=m, k=k, c=c, F0=F0, Omega=Omega, Y0=Y0).items()}
    if not paired:
        arrays = {n: np.array([a.min(), a.max()]) for n, a in arrays.items()}
        low_m, high_m = arrays["m"]
        low_k, high_k = arrays["k"]
        omega = np.array([math.sqrt(low_k / high_m), math.sqrt(high_k / low_m)])
        W = arrays["Omega"]
        ratio = W / omega[::-1]             # the smallest and the largest
        big = {n: np.abs(arrays[n]).max() for n in ("F0", "Y0", "c", "Omega")}
        length = np.array([big["F0"] / low_k + big["Y0"]
                           + big["c"] * big["Omega"] * big["Y0"] / low_k])
        speed = big["Omega"] * length
        at = {"Omega": W, "omega": omega[::-1]}
    else:
        a = dict(zip(arrays, np.broadcast_arrays(*arrays.values())))
        with np.errstate(all="ignore"):
            omega = np.sqrt(a["k"] / a["m"])
            ratio = a["Omega"] / omega
            length = (np.abs(a["F0"]) / a["k"] + np.abs(a["Y0"])
                      + a["c"] * a["Omega"] * np.abs(a["Y0"]) / a["k"])
            speed = a["Omega"] * length
        at = {"Omega": a["Omega"], "omega": omega}
    with np.errstate(all="ignore"):
        period = 2.0 * math.pi / at["Omega"]
    pre = f"{where}: " if where else ""
    lo, hi = FORCING_RATIO
    bad = np.flatnonzero(~((ratio >= lo) & (ratio <= hi)))
    if bad.size:
        i = bad[0]
        W, w = float(at["Omega"][i]), float(at["omega"][i])
        raise ValueError(
            f"{pre}Omega={W!r} [rad s-1] is {W / w:.3g} times the natural frequency "
            f"omega = sqrt(k/m) = {w:.6g} s-1 there; the forced kernels resolve Omega/"
            f"omega in [{lo:g}, {hi:g}] (a forcing period 2 pi/Omega = {2 * math.pi / W:.3g}"
            f" s of {w / W:.3g} natural periods), so give Omega in [{lo * w:.3g}, "
            f"{min(hi * w, 2 * math.pi / FORCING_PERIOD_MIN):.3g}] rad s-1 here")
    short = np.flatnonzero(~(period >= FORCING_PERIOD_MIN))
    if short.size:
        W = float(at["Omega"][short[0]])
        raise ValueError(
            f"{pre}Omega={W!r} [rad s-1] gives the forcing period 2 pi/Omega = "
            f"{2 * math.pi / W:.3g} s, shorter than the {FORCING_PERIOD_MIN:g} s the "
            "drivers step through (their step floor is 2.2e-16 s); choose a unit of "
            "time in which the period is longer (Omega at most "
            f"{2 * math.pi / FORCING_PERIOD_MIN:.3g} rad s-1)")
    for what, values, unit in (("length (|F0| + k |Y0| + c Omega |Y0|)/k", length, "cm"),
                               ("speed Omega (|F0| + k |Y0| + c Omega |Y0|)/k", speed,
                                "cm s-1")):
        over = np.flatnonzero(~(values <= STATE_MAX))
        if over.size:
            shown = ", ".join(f"{n}={_extreme(arrays[n])}" for n in
                              ("F0", "Y0", "Omega", "k", "c") if np.any(arrays[n]))
            raise ValueError(
                f"{pre}the excitation's {what} is {float(values[over[0]]):.3g} "
                f"{unit} with {shown}, beyond the {STATE_MAX:g} the drivers keep "
                "finite (a state beyond it is diverged); choose units in which the "
                "magnitudes are moderate")


def checked_excitation(values: dict) -> dict:
    """The excitation's keywords (name -> value) checked by their rules: None only
    where the default is None (Omega: no excitation), never for F0, phi, Y0 (whose
    default is 0: leave them out)."""
    out = {}
    for name, value in values.items():
        if value is None and excitations.DEFAULTS.get(name, 0.0) is None:
            out[name] = None
        elif value is None:
            raise TypeError(f"{name} must be a real number [{UNITS[name]}], got None: "
                            f"leave it out for its default {excitations.DEFAULTS[name]!r}")
        else:
            out[name] = check_real(name, value, **RULES[name])
    return out


def _extreme(a: np.ndarray) -> str:
    """The value, or the range, of an argument of :func:`check_forcing`."""
    lo, hi = float(a.min()), float(a.max())
    return f"{lo!r}" if lo == hi else f"[{lo!r}, {hi!r}]"


def check_law(where: str, law_object, analytic: dict) -> None:
    """Refuse a law that is not a law object, or analytic parameters beside it."""
    if isinstance(law_object, OBJECTS):
        given = [f"{n}={v!r}" for n, v in analytic.items() if v is not None]
        if given:
            raise ValueError(f"{where}: law= replaces the analytic law's parameters "
                             f"(r_y, alpha1, alpha2, r_k, v_s); got {', '.join(given)} "
                             f"beside law={law_object!r}")
        return
    names = ", ".join(cls.__name__ for cls in OBJECTS)
    raise TypeError(f"law must be a friction law object ({names}; sweepcore.laws), "
                    f"got {law_object!r} of type {type(law_object).__name__}")


def law_ranges(law_object, ranges: dict) -> dict:
    """``check_derived``'s ranges for a law object: its static bound stands for r_y
    and its slope bound for alpha1 (magnitudes only)."""
    one = np.zeros((1, layout.NP))
    return {**ranges, "r_y": (float(law_object.static_bound(one)[0]),) * 2,
            "alpha1": (float(law_object.slope_scale(one)[0]),) * 2, "alpha2": (0.0, 0.0)}


@dataclass(frozen=True)
class Params:
    """One slider on the belt (Liu, Fig. 1) and its friction law.

    ``m x'' + c x' + k x + r_a = 0``; while sliding with relative speed
    ``s = x' - v``, ``r_a = F(s) = sgn(s) (r_k + (r_y - r_k) exp(-|s|/v_s))
    - alpha1 s + alpha2 s^3``; while stuck ``|k x + c v| <= r_y``. The defaults
    (``c = 0``, ``r_k = r_y``) give the paper's law, eq. (40); ``v_s = 0`` is the
    limit v_s -> 0+, Coulomb friction with static above kinetic (``r_k < r_y``: a
    jump at zero speed, Shaw 1986).

    Parameters
    ----------
    m : float
        Mass [kN s^2/cm], > 0.
    k : float
        Stiffness [kN/cm], > 0.
    r_y : float
        Static friction bound [kN], >= 0: the largest force sticking holds (= F(0+),
        but for v_s = 0, where F(0+) = r_k).
        Required unless ``law`` is given.
    v : float
        Belt speed [cm/s], any finite value: ``v < 0`` is the mirror image of
        ``-v``, ``v = 0`` a static belt.
    alpha1 : float
        Linear coefficient of eq. (40) [kN s/cm], any finite value.
    alpha2 : float
        Cubic coefficient of eq. (40) [kN s^3/cm^3], >= 0.
    c : float
        Viscous damping on the slider [kN s/cm], >= 0.
    r_k : float, optional
        Kinetic friction level [kN], >= 0: the Coulomb part of F at high speed
        (exponential Stribeck law). Default ``r_y``: no Stribeck term.
    v_s : float, optional
        Stribeck speed [cm/s], >= 0; required when ``r_k != r_y``. ``v_s = 0`` is the
        exact jump: ``F(s) = sgn(s) r_k - alpha1 s + alpha2 s^3`` while sliding
        (``F(0+) = r_k``), sticking up to r_y (static above kinetic friction).
    law : TableLaw or LeineLaw, optional
        A friction law given as an object (:mod:`sweepcore.laws`) instead of the
        analytic family: then r_y, alpha1, alpha2, r_k and v_s are not given (the law
        holds its own data), and the damping c stays the slider's.
    F0, Omega, phi, Y0 : float, optional
        The external excitation (``sweepcore.excitations``): a load
        ``F0 p(Omega t + phi)`` [kN] on the slider and a motion ``Y0 cos(Omega t)``
        [cm] of the anchor of spring and damper (then the slider's equation is
        ``m x'' + c (x' - y') + k (x - y) + r_a = F0 p(Omega t + phi)``); Omega
        [rad/s] > 0 is required with either, and Omega/omega must lie in
        ``FORCING_RATIO`` (:func:`check_forcing`). The phase ``phi`` is in
        **radians**, ``|phi| <= 2 pi`` (90 degrees is ``phi = math.radians(90)``;
        ``phi = 90`` is refused). Default: none (F0 = Y0 = 0, phi = 0).
    load : PeriodicLoad, optional
        The load's shape p over one period (:class:`sweepcore.PeriodicLoad`: its
        harmonics); default one cosine, p = cos.

    Raises
    ------
    TypeError, ValueError
        A parameter that is not a finite real number in its range, a missing v_s,
        analytic parameters beside ``law``, magnitudes whose derived quantities
        (omega, q, x_eq, the length scale) overflow, or an excitation the forced
        kernels cannot resolve (:func:`check_forcing`).
    """

    m: float
    k: float
    r_y: float | None = None
    v: float | None = None
    alpha1: float | None = None
    alpha2: float | None = None
    c: float = 0.0
    r_k: float | None = None
    v_s: float | None = None
    law: object = None
    F0: float = 0.0
    Omega: float | None = None
    phi: float = 0.0
    Y0: float = 0.0
    load: object = None

    def __post_init__(self):
        if isinstance(self.load, (list, tuple)):
            raise TypeError("Params: load must be one sweepcore.PeriodicLoad (a sweep "
                            "over several is Grid(..., load=[...]))")
        excitations.check_loads("Params", self.load)
        for name, value in checked_excitation(self.excitation_values()).items():
            object.__setattr__(self, name, value)
        excitations.check("Params", self.excitation_values())
        if self.load is not None and not self.F0:
            raise ValueError(f"Params: load={self.load.name!r} given but F0 = "
                             f"{self.F0!r}: the load's amplitude F0 [kN] is needed")
        if self.v is None:
            raise TypeError("Params() missing the belt speed v [cm s-1]")
        for name in ("m", "k", "v", "c"):
            object.__setattr__(self, name, check_real(name, getattr(self, name),
                                                      **RULES[name]))
        if self.forced:
            check_forcing("Params", self.m, self.k, self.c, self.F0, self.Omega, self.Y0)
        if self.law is not None:
            check_law("Params", self.law, {n: getattr(self, n)
                                           for n in _analytic.PARAMETERS})
            check_derived("Params", law_ranges(self.law, {
                n: (getattr(self, n),) * 2 for n in ("m", "k", "v", "c")}))
            return
        if self.r_y is None:
            raise TypeError("r_y must be a real number, got None: the friction bound "
                            "[kN] is required (or a law object: law=)")
        for name in ("alpha1", "alpha2"):
            if getattr(self, name) is None:
                object.__setattr__(self, name, 0.0)
        for name in ("r_y", "alpha1", "alpha2"):
            object.__setattr__(self, name, check_real(name, getattr(self, name),
                                                      **RULES[name]))
        for name in ("r_k", "v_s"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, check_real(name, getattr(self, name),
                                                          **RULES[name]))
        if self.r_k is None:
            object.__setattr__(self, "r_k", self.r_y)
        if self.v_s is None and self.r_k != self.r_y:
            raise ValueError(f"v_s (Stribeck speed [cm s-1]) is required when r_k "
                             f"differs from r_y; got r_k={self.r_k!r}, r_y={self.r_y!r}")
        check_derived("Params", {n: (v, v) for n, v in self.values().items()
                                 if v is not None and n != "law"})

    def excitation_values(self) -> dict:
        """The excitation's keywords by name."""
        return {n: getattr(self, n) for n in excitations.KEYWORDS}

    @property
    def forced(self) -> bool:
        """Whether the slider is excited (F0 or Y0 not 0)."""
        return excitations.given(self.excitation_values())

    @property
    def loads(self) -> tuple:
        """The load shapes of the kernel row (``layout.LOAD`` indexes them): the one
        given, or one cosine."""
        return (self.load if self.load is not None else excitations.HARMONIC,)

    @property
    def friction_law(self):
        """The law object: ``law``, or the analytic family (``sweepcore.laws``)."""
        return ANALYTIC if self.law is None else self.law

    def values(self) -> dict:
        """The parameters by name (v_s None when not given; the law's parameters None
        and ``law`` the object for a law object)."""
        return {n: getattr(self, n) for n in law.PARAMETERS + ("law",)}

    def __getitem__(self, name: str):
        """``params["m"]``: a Params is a source of the friction law (``sweepcore.law``)."""
        if name not in law.PARAMETERS and name != "law":
            raise KeyError(name)
        return getattr(self, name)

    @property
    def omega(self) -> float:
        """Natural frequency sqrt(k/m) [1/s]."""
        return math.sqrt(self.k / self.m)

    @property
    def q(self) -> float:
        """Hopf quantity ``q = -(c + F'(-v))/m`` [1/s]; eq. (46),
        ``(alpha1 - 3 alpha2 v^2)/m``, for the paper's law.

        The equilibrium's eigenvalues solve lambda^2 - q lambda + omega^2 = 0
        (eq. 45): stable for q < 0, unstable for q > 0.
        """
        return law.derived("q", self)

    @property
    def v_star(self) -> float:
        """Lowest analytic Hopf speed [cm/s]: where ``c + F'(-v)`` vanishes;
        ``sqrt(alpha1 / (3 alpha2))`` below eq. (51) for the paper's law.

        ``inf`` when steady sliding is unstable at every speed (alpha2 = 0 <
        alpha1 for the paper's law), ``nan`` when it is stable at every speed, 0
        when alpha1 = 0 < alpha2. A second root, where the law has one, is
        ``hopf_speeds[1]``.
        """
        return law.derived("v_star", self)

    @property
    def hopf_speeds(self) -> tuple:
        """Every analytic Hopf speed [cm/s] (0, 1 or 2 of them), increasing."""
        roots = (law.derived("v_star", self), law.derived("v_star_2", self))
        return tuple(r for r in roots if math.isfinite(r))

    @property
    def first_lyapunov(self) -> float:
        """First Lyapunov coefficient at v* [1/(s cm^2)]: averaging gives
        ``dA/dt = q A/2 + l1 A^3``; < 0 supercritical, > 0 subcritical."""
        return law.derived("first_lyapunov", self)

    @property
    def criticality(self) -> str:
        """"supercritical", "subcritical", "degenerate", or "none" (no Hopf speed)."""
        return law.CRITICALITY[int(law.criticality_code(self))]

    @property
    def x_eq(self) -> float:
        """Steady-sliding equilibrium ``-F(-v)/k`` [cm]; eq. (43),
        ``(r_y - alpha1 v + alpha2 v^3)/k``, for the paper's law.

        Written for v > 0 (the slider slower than the belt). For v < 0 the mirror
        image -x_eq(-v) is returned; for v = 0 there is a band of rest positions
        and the value returned is 0.
        """
        return law.derived("x_eq", self)

    @property
    def eigenvalues(self) -> tuple[complex, complex]:
        """Roots of eq. (45), lambda^2 - q lambda + omega^2 = 0 [1/s]."""
        q = self.q
        d = cmath.sqrt(q * q - 4.0 * self.omega ** 2)
        return (0.5 * (q + d), 0.5 * (q - d))

    def row(self, x0: float, xdot0: float) -> np.ndarray:
        """The kernel's flat parameter row (layout.py); v_s NaN when not given (and
        the analytic columns NaN for a law object); its law is the call's first."""
        r = np.zeros(layout.NP)
        for name, col in law.COLUMNS.items():
            val = getattr(self, name)
            r[col] = np.nan if val is None else val
        r[layout.X0] = x0
        r[layout.XD0] = xdot0
        r[layout.LAW] = 0.0
        for name, col in excitations.COLUMNS.items():
            val = getattr(self, name)
            r[col] = np.nan if val is None else val
        return r


Params.__init__ = checked_keywords(Params.__init__)