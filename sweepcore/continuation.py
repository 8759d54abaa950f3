"""A forced response followed in one parameter, unstable stretches and special
points included: :func:`follow_response`.

The branch is the set of fixed points of the stroboscopic map P^n (n forcing
periods, n the multiplicity of the response it starts from) as the parameter
moves; :mod:`sweepcore.branch` follows it by pseudo-arclength continuation, through
folds, and locates on it the folds, branch points, period doublings and tori
(multipliers through +1, -1 or the unit circle) and the non-smooth events where the
pattern of sticks and stops per period changes. No stick pattern is set by hand:
each point's motion is integrated as it comes (the driver's events), so the branch
goes on through a pattern change. The result is a labelled Dataset along ``point``.
"""
from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import xarray as xr

from . import branch, excitations, labels, law, variables
from ._kernels import codes, layout
from .options import checked_keywords, did_you_mean, make_options
from .params import LONG_NAMES, RULES, UNITS, Params, check_real

# the parameters a branch can follow: the slider's columns and the excitation's
PARAMETERS = tuple(law.COLUMNS) + tuple(excitations.COLUMNS)
ANALYTIC_ONLY = ("r_y", "alpha1", "alpha2", "r_k", "v_s")    # not with a law object
STATUS_NAMES = {**codes.STATUS_NAMES, branch.CORRECTOR_FAILED: "corrector_failed"}
# the observables a point carries, from its image's row
OBSERVED = ("amplitude", "mean", "x_max", "x_min", "xdot_max", "velocity_amplitude",
            "sticks_per_period", "stops_per_period", "stick_fraction", "period")


# ------------------------------------------------------------------ the problem
def check_parameter(name, params: Params | None = None, what: str = "over") -> str:
    """``name`` if a branch can follow it (for ``params``' law), else a ValueError
    naming it (as the argument ``what``)."""
    if not isinstance(name, str) or name not in PARAMETERS:
        raise ValueError(f"{what} must be one of {', '.join(PARAMETERS)}, got {name!r}"
                         f"{did_you_mean(str(name), list(PARAMETERS))}")
    if params is not None and params.law is not None and name in ANALYTIC_ONLY:
        raise ValueError(f"over={name!r} is a parameter of the analytic friction "
                         f"law; this slider's law is {params.law.name!r} (a law "
                         "object holds its own data)")
    return name


def columns(row: np.ndarray, name: str) -> tuple:
    """The kernel columns the parameter ``name`` sets: its own, and r_k with r_y
    where they are equal (Coulomb friction moves as one level)."""
    col = law.COLUMNS.get(name, excitations.COLUMNS.get(name))
    r_k = law.COLUMNS["r_k"]
    if name == "r_y" and row[r_k] == row[col]:
        return (col, r_k)
    return (col,)


def excitation(row: np.ndarray) -> dict:
    """The excitation's keywords of a kernel row, read through the excitation
    table's columns (``sweepcore.excitations.COLUMNS``)."""
    return {name: float(row[col]) for name, col in excitations.COLUMNS.items()}


def scales(row: np.ndarray, law_object, load) -> tuple:
    """(L [cm], Lv [cm/s]) of a forced row: the static bound and the excitation
    over k, plus |v|/omega; Lv = omega L + |v|."""
    k, m, c = row[layout.K], row[layout.M], row[layout.C]
    omega = math.sqrt(k / m)
    ex = excitation(row)
    excite = abs(ex["F0"]) * load.bound() + abs(ex["Y0"]) * math.hypot(
        k, c * ex["Omega"])
    L = float(law.length_scale(row[None, :], (law_object,))[0]) + excite / k
    return L, omega * L + abs(row[layout.V])


def problem(row, law_object, load, over: str, n: int, o, tol: float,
            lam_scale: float) -> branch.Problem:
    """The branch problem of the kernel row ``row`` along ``over``."""
    rule = RULES.get(over, {})
    lower = 0.0 if rule.get("positive") or rule.get("nonnegative") else None
    L, Lv = scales(row, law_object, load)
    return branch.Problem(row, law_object, load, columns(row, over), n, o, tol,
                          (L, Lv, lam_scale), lower)


def first_point(prob: branch.Problem, x: float, xdot: float, lam: float, what: str):
    """The fixed point of P^n near (x, xdot) at ``lam``, or a ValueError saying
    ``what`` was not one."""
    try:
        return prob.at_parameter(prob.scaled(x, xdot, lam), lam)
    except branch.Failed as e:
        raise ValueError(f"{what} is not a periodic point the corrector can solve "
                         f"(P^{prob.n}: {STATUS_NAMES.get(e.status, e.status)})") \
            from None


# ------------------------------------------------------------------ public
def _checked_number(name, value, least=None, below=None) -> float:
    x = check_real(name, value)
    if (least is not None and not x > least) or (below is not None and not x < below):
        raise ValueError(f"{name} must be a number in ({least}, {below}), got {value!r}")
    return x


def _at(params: Params, over: str, value: float, what: str) -> Params:
    """``params`` with ``over = value`` (and r_k with a Coulomb r_y), validated; a
    refusal names ``what``."""
    extra = {"r_k": value} if over == "r_y" and params.law is None and \
        params.r_k == params.r_y else {}
    try:
        p = dataclasses.replace(params, **{over: value, **extra})
    except (TypeError, ValueError) as e:
        raise ValueError(f"{what} = {value!r} for {over!r}: {e}") from None
    if not p.forced:
        raise ValueError(f"{what} = {value!r} for {over!r} leaves no excitation (F0 = "
                         "Y0 = 0): a branch of forced responses needs one")
    return p


@checked_keywords(options=True)
def follow_response(params: Params, over: str = "Omega", to: float | None = None,
                    x0: float | None = None, xdot0: float | None = None,
                    multiplicity: int | None = None, bounds=None, tol: float = 1e-10,
                    method: str = "auto", step: float = 0.01, max_step: float = 0.05,
                    max_points: int = 400, xtol: float = 1e-9,
                    **options) -> xr.Dataset:
    """Follow a forced slider's periodic response in one parameter, through folds.

    Parameters
    ----------
    params : Params
        A forced slider (F0 or Y0 given); the branch starts at its value of ``over``.
    over : str
        The parameter followed: ``Omega``, ``F0``, ``Y0``, ``phi``, ``v``, ``m``,
        ``k``, ``c`` or, for the analytic law, ``r_y``, ``alpha1``, ``alpha2``,
        ``r_k``, ``v_s`` (``r_y`` of a Coulomb law, r_k = r_y, moves r_k with it).
    to : float
        The value to follow it to (required; not the start's).
    x0, xdot0 : float, optional
        The start [cm], [cm/s]: the branch starts at the response
        :func:`sweepcore.attractor` reaches from it (default x0 = 0, stuck on the
        belt). With ``multiplicity`` they are a periodic point instead (xdot0 None:
        stuck), corrected as a fixed point of P^multiplicity: any branch, an
        unstable one too.
    multiplicity : int, optional
        n of a given periodic point (see x0).
    bounds : (lo, hi), optional
        The window the branch is followed in [units of over]; default between the
        start's value and ``to``. A branch that turns back ends where it leaves it.
    tol : float
        The residual of every point, ``|P^n(u) - u|`` relative to the scales
        (L = (static bound + excitation)/k + |v|/omega and omega L + |v|); the
        images are integrated at 1e-2 tol.
    method, **options
        As :func:`sweepcore.attractor` (the start's search and the images).
    step, max_step : float
        First and largest pseudo-arclength step, in the scaled unknowns
        (x/L, xdot/Lv, parameter/max(|start|, |to|)).
    max_points : int
        Steps at most (the branch ends there, with a warning).
    xtol : float
        Special points are located to ``xtol`` times the parameter's value (times
        1e-3 of its scale where it is near 0).

    Returns
    -------
    xarray.Dataset
        Along ``point`` (in the order of the branch): the parameter (named
        ``over``), ``x_section``, ``xdot_section`` (the periodic point: the state at
        t = 0 mod n T, T = 2 pi/Omega), amplitude, mean, x_max, x_min, xdot_max,
        velocity_amplitude, period, multiplicity, sticks_per_period,
        stops_per_period, stick_fraction, ``floquet``, ``multiplier_real`` and
        ``multiplier_imag`` (point, multiplier: largest modulus first), ``stable``,
        ``special`` (start, end, fold, branch_point, period_doubling, torus,
        stick_onset, grazing, stops_change; regular elsewhere), ``special_width``,
        ``arclength`` and ``status`` (ok; where a correction failed, the last point
        says why, with NaN values).

    Raises
    ------
    TypeError, ValueError
        An argument out of range (named, with its value), or a start whose response
        is not periodic (aperiodic, failed) or not a periodic point.
    """
    if not isinstance(params, Params):
        raise TypeError(f"params must be a sweepcore.Params, got {type(params).__name__}")
    if not params.forced:
        raise ValueError("params must be a forced slider: give F0 or Y0 (and Omega)")
    over = check_parameter(over, params)
    if to is None:
        raise TypeError(f"follow_response needs to=, the value of {over} to follow "
                        "the branch to")
    to = check_real("to", to)
    lam0 = float(getattr(params, over))
    if to == lam0:
        raise ValueError(f"to = {to!r} is the start's own {over}: give another value")
    _at(params, over, to, "to")
    window = (min(lam0, to), max(lam0, to))
    if bounds is not None:
        if not (isinstance(bounds, (tuple, list)) and len(bounds) == 2):
            raise ValueError(f"bounds must be a pair (lo, hi), got {bounds!r}")
        lo, hi = (check_real(f"bounds[{i}]", b) for i, b in enumerate(bounds))
        if not lo <= window[0] <= window[1] <= hi:
            raise ValueError(f"bounds = {bounds!r} must hold the start's {over} = "
                             f"{lam0!r} and to = {to!r}")
        _at(params, over, lo, "bounds[0]")
        _at(params, over, hi, "bounds[1]")
        window = (lo, hi)
    step = _checked_number("step", step, 0.0, 1.0)
    max_step = _checked_number("max_step", max_step, 0.0, 1.0)
    xtol = _checked_number("xtol", xtol, 0.0, 1e-3)
    if isinstance(max_points, bool) or not isinstance(max_points, (int, np.integer)) \
            or max_points < 1:
        raise ValueError(f"max_points must be an integer >= 1, got {max_points!r}")
    o = make_options(method, tol=tol, **options)
    from . import forced
    forced.check_method(method)
    x_s, xd_s, n, what = _start(params, x0, xdot0, multiplicity, method, tol, options)
    prob = problem(params.row(0.0, 0.0), params.friction_law, params.loads[0], over, n,
                   o, tol, max(abs(lam0), abs(to), *map(abs, window)) or 1.0)
    first = first_point(prob, x_s, xd_s, lam0, what)
    records, ended = branch.follow(prob, first, to, window, min(step, max_step),
                                   max_step, int(max_points), xtol)
    _warn(records, ended, over, prob, max_points)
    call = (f"sweepcore.follow_response({params!r}, over={over!r}, to={to!r}, "
            f"x0={x0!r}, xdot0={xdot0!r}, multiplicity={multiplicity!r}, "
            f"bounds={bounds!r}, tol={tol!r}, method={method!r})")
    return branch_dataset(records, prob, params, over, call, ended)


def _start(params, x0, xdot0, multiplicity, method, tol, options):
    """(x, xdot, n, description) of the branch's first periodic point guess."""
    if multiplicity is not None:
        if isinstance(multiplicity, bool) or not isinstance(multiplicity, (int, np.integer)) \
                or not 1 <= multiplicity <= 64:
            raise ValueError(f"multiplicity must be an integer in [1, 64], got "
                             f"{multiplicity!r}")
        if x0 is None:
            raise ValueError("multiplicity given: x0 (and xdot0) must be the periodic "
                             "point")
        x = check_real("x0", x0)
        xd = params.v if xdot0 is None else check_real("xdot0", xdot0)
        return x, xd, int(multiplicity), (f"(x0, xdot0) = ({x!r}, {xd!r}) with "
                                          f"multiplicity {multiplicity}")
    from .attractor import attractor
    x = 0.0 if x0 is None else x0
    r = attractor(params, x0=x, xdot0=xdot0, method=method, tol=min(tol * 100, 1e-8),
                  **options)
    if not math.isfinite(r.multiplicity) or r.status not in ("ok", "unresolved"):
        raise ValueError(f"the response from x0={x!r}, xdot0={xdot0!r} is {r.regime} "
                         f"(status {r.status}): no periodic point to follow; give "
                         "another start, or a periodic point with multiplicity=")
    return (r.x_section, r.xdot_section, int(r.multiplicity),
            f"the response from x0={x!r}, xdot0={xdot0!r}")


def _warn(records, ended, over, prob, max_points) -> None:
    last = records[-1]
    where = f"{over} = {prob.lam(last.w):.10g}"
    if ended == branch.FAILED:
        warnings.warn(f"follow_response: the branch ends at {where}, where no correction "
                      f"converged ({STATUS_NAMES.get(last.status, last.status)}; the "
                      "last point has that status and NaN values)", RuntimeWarning,
                      stacklevel=3)
    elif ended == branch.BUDGET:
        warnings.warn(f"follow_response: max_points = {max_points} steps spent, the "
                      f"branch ends at {where}; raise max_points or max_step",
                      RuntimeWarning, stacklevel=3)
    bad = [r for r in records if r.special != branch.REGULAR and r.status != codes.OK
           and r.point is not None]
    if bad:
        warnings.warn(f"follow_response: {len(bad)} special point(s) not located to "
                      f"xtol (status corrector_failed, special_width their bracket)",
                      RuntimeWarning, stacklevel=3)


# ------------------------------------------------------------------ the Dataset
def branch_dataset(records, prob, params, over: str, call: str, ended: str) -> xr.Dataset:
    """The labelled Dataset of a followed branch (see :func:`follow_response`)."""
    npt = len(records)
    w = np.array([r.w for r in records]) * prob.S
    obs = np.full((npt, layout.NFOB), np.nan)
    mu = np.full((npt, 2), np.nan + 0j)
    for i, r in enumerate(records):
        if r.point is not None:
            obs[i] = r.point.obs
            mu[i] = r.point.multipliers()
    ok = np.array([r.point is not None for r in records])
    dim = ("point",)
    data = {over: (dim, w[:, 2], labels.attrs(UNITS[over], LONG_NAMES[over],
                                              "the parameter followed"))}
    for name in ("x_section", "xdot_section"):
        _c, units, long, comment = variables.FORCED_OBSERVABLES[name]
        data[name] = (dim, np.where(ok, w[:, 0 if name == "x_section" else 1], np.nan),
                      labels.attrs(units, long, comment))
    for name in OBSERVED:
        col, units, long, comment = variables.FORCED_OBSERVABLES[name]
        vals = obs[:, col]
        if name in variables.INTEGER:
            vals = np.where(np.isfinite(vals), vals, -1).astype(np.int64)
        data[name] = (dim, vals, labels.attrs(units, long, comment))
    _c, units, long, comment = variables.FORCED_OBSERVABLES["multiplicity"]
    data["multiplicity"] = (dim, np.full(npt, prob.n, np.int64),
                            labels.attrs(units, long, "n of P^n along the branch"))
    floq = np.where(ok, np.abs(mu[:, 0]), np.nan)
    for name, vals, dims in (("floquet", floq, dim),
                             ("multiplier_real", mu.real, ("point", "multiplier")),
                             ("multiplier_imag", mu.imag, ("point", "multiplier"))):
        data[name] = (dims, vals, labels.attrs(*variables.BRANCH[name]))
    data["stable"] = (dim, (ok & (floq < 1.0)).astype(np.int8), {
        **labels.attrs(*variables.BRANCH["stable"]),
        "flag_values": np.array([0, 1], np.int8), "flag_meanings": "unstable stable"})
    data["special"] = (dim, np.array([r.special for r in records], np.int8),
                       labels.flags(branch.SPECIAL_NAMES, "special point of the branch"))
    for name, vals in (("special_value", [math.nan if r.at is None else r.at
                                          for r in records]),
                       ("special_width", [r.width for r in records])):
        _u, long_w, comment_w = variables.BRANCH[name]
        data[name] = (dim, np.array(vals, float), labels.attrs(UNITS[over], long_w,
                                                                comment_w))
    steps = np.linalg.norm(np.diff(w / prob.S, axis=0), axis=1) if npt > 1 else []
    data["arclength"] = (dim, np.concatenate([[0.0], np.cumsum(steps)]),
                         labels.attrs(*variables.BRANCH["arclength"]))
    data["status"] = (dim, np.array([r.status for r in records], np.int8),
                      labels.flags(STATUS_NAMES, "numerical status of the point"))
    from .response_curves import _fixed
    coords = _fixed(params, over)
    coords["point"] = xr.Variable("point", np.arange(npt), {
        "units": "1", "long_name": "index of the point along the branch"})
    coords["multiplier"] = xr.Variable("multiplier", np.array([1, 2]), {
        "units": "1", "long_name": "index of the multiplier, largest modulus first"})
    ds = xr.Dataset(data, coords)
    ds.attrs.update({
        **labels.provenance(
            "Branch of periodic responses of the forced friction oscillator", call,
            "fixed points of the stroboscopic map followed by pseudo-arclength "
            "continuation (sweepcore.branch)",
            "Units kN, cm, s. Unstable responses included (stable = 0); special "
            "points located to xtol on the branch."),
        "sweepcore_kind": "response_branch", "over": over, "ended": ended,
        "multiplicity": int(prob.n), "tol": float(prob.tol),
        "images": int(prob.images)})
    return ds
