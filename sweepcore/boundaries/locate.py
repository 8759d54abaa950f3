"""Every regime change along one parameter, located to ``xtol``: the public
:func:`locate_boundaries` and the solver of one point (:func:`_locate_point`).

A coarse scan brackets the changes; a change without a smooth indicator (e.g. the
edges of the band of slip cycles with slide-slide reversals at small alpha2) is
bisected on the regime labels; the Hopf point (:mod:`.hopf`) and the grazings
(:mod:`.graze`) are solved on their indicators.
"""
from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import xarray as xr

from .. import execute
from .._kernels import codes, layout
from ..grid import AXES, COLUMNS, Grid, checked_grid
from ..laws import ANALYTIC
from ..options import checked_keywords, did_you_mean, make_options
from ..params import UNITS, check_real
from ..sizing import boundary_need, refuse_unaffordable
from .dataset import _dataset
from .drive import _drive, _together
from .fold import cycle_boundaries
from .graze import _graze
from .hopf import N_SAMPLES, _hopf, _hopf_offset
from .point import (ABSENT, FAILED, INCONSISTENT, LOCATED, PROPER, STUCK, _ok, _Point,
                    _regime)

MAX_TRANSITIONS = 8     # regime changes kept per point (the first ones along the axis)
# what the scan can read: ok, and unresolved cycles next to the Hopf point (_changes)
SEEN = (codes.OK, codes.UNRESOLVED)
GEOMETRIC_SCAN = 100.0  # a positive bracket wider than this ratio is scanned geometrically


# ---------------------------------------------------------------- label changes
def _bisect(pt: _Point, a: float, b: float, ra: int, rb: int, xtol: float, start):
    """Solver: bisection on the regime labels between ``a`` (regime ``ra``) and
    ``b`` (regime ``rb``). Returns ``dict(value, width, status)``."""
    while abs(b - a) > xtol:
        c = 0.5 * (a + b)
        (row,) = yield [(c, *start)]
        if not _ok(row):
            return {"value": 0.5 * (a + b), "width": abs(b - a), "status": FAILED}
        if _regime(row) == ra:
            a = c
        elif _regime(row) == rb:
            b = c
        else:       # a third regime inside: two changes, not one
            return {"value": 0.5 * (a + b), "width": abs(b - a),
                    "status": INCONSISTENT}
    return {"value": 0.5 * (a + b), "width": abs(b - a), "status": LOCATED}


# ------------------------------------------------------------------ one point
def _empty():
    return {"v_hopf": math.nan, "v_hopf_error": math.nan, "hopf_status": ABSENT,
            "v_stick_onset": math.nan, "v_stick_onset_width": math.nan,
            "stick_status": ABSENT, "transitions": [], "hopf_reach": None,
            "hopf_shape": None}


def _hopf_guess(pt, values, rows, j, side, offset):
    """Secant of A^2 (in the fit variable) on the two scan cycles nearest the
    change between values[j] and values[j+1]; the midpoint when they are missing."""
    ic = j if side < 0 else j + 1
    ie = j + 1 if side < 0 else j
    mid = 0.5 * (values[j] + values[j + 1])
    i2 = ic + side
    if not (0 <= i2 < len(values)) or not _ok(rows[i2]) or \
            not _regime(rows[i2]) == _regime(rows[ic]) == codes.R_SLIP_CYCLE:
        return mid, None
    w = pt.fit_variable(np.array([values[ic], values[i2]]))
    a2 = np.array([rows[ic][layout.OB_AMPLITUDE], rows[i2][layout.OB_AMPLITUDE]]) ** 2
    if a2[0] == a2[1]:
        return mid, None
    w0 = w[0] - a2[0] * (w[1] - w[0]) / (a2[1] - a2[0])
    r = (math.sqrt(w0) if w0 > 0 else math.nan) if pt.along == "v" else w0
    lo, hi = sorted((values[ic], values[ie]))
    if not lo < r < hi:
        return mid, None
    # seeds: A^2 linear in the fit variable, through the scan's nearest cycle
    offset = _hopf_offset(pt, r, side, offset)
    us = r * (1.0 + side * offset * np.arange(1, N_SAMPLES + 1))
    amp = np.sqrt(a2[0] * np.abs(pt.fit_variable(us) - w0) / abs(w[0] - w0))
    return r, amp


def _changes(us, rows):
    """Indices j with a change of proper regimes between scan points j and j+1.

    A cycle returned ``unresolved`` (next to the Hopf point, its numbers only
    estimates) keeps its label: the scan needs no more."""
    reg = [_regime(r) if _ok(r) or int(r[layout.OB_STATUS]) == codes.UNRESOLVED
           else -1 for r in rows]
    return reg, [j for j in range(len(us) - 1) if reg[j] != reg[j + 1]
                 and reg[j] in PROPER and reg[j + 1] in PROPER]


def _smooth_kind(pt, us, rows, reg, j):
    """"hopf", "graze" or None: the smooth indicator that serves the change at j."""
    pair = {reg[j], reg[j + 1]}
    if pair == {codes.R_SLIP_CYCLE, codes.R_EQUILIBRIUM}:
        return "hopf"
    if pair == {codes.R_SLIP_CYCLE, codes.R_STICK_SLIP}:
        js = j if reg[j] == codes.R_SLIP_CYCLE else j + 1
        if pt.speed(us[js]) - rows[js][layout.OB_XDOT_MAX] > 0.0:
            return "graze"      # a slip cycle below belt speed grazes it
    return None


def _locate_point(pt: _Point, values: np.ndarray, xtol: float, offset: float, start,
                  max_rounds: int = 80):
    """Solver: coarse scan over ``values``, label changes without a smooth indicator
    bisected to ``xtol`` (splitting where a third regime appears), then the Hopf
    point and the grazings solved on their indicators."""
    rows = yield [(u, *start) for u in values]
    us, rows = list(values), list(rows)
    res = _empty()
    res["scan_failures"] = [(float(u), int(r[layout.OB_STATUS])) for u, r in
                            zip(values, rows) if int(r[layout.OB_STATUS]) not in SEEN]
    for _round in range(max_rounds):
        reg, changes = _changes(us, rows)
        # label changes to xtol; Hopf brackets down to the sample spacing
        todo = [j for j in changes[:MAX_TRANSITIONS]
                if (_smooth_kind(pt, us, rows, reg, j) is None
                    and abs(us[j + 1] - us[j]) > xtol)
                or (_smooth_kind(pt, us, rows, reg, j) == "hopf"
                    and abs(us[j + 1] - us[j]) > 2.0 * offset * abs(us[j + 1]))]
        if not todo:
            break
        mids = [0.5 * (us[j] + us[j + 1]) for j in todo]
        got = yield [(u, *start) for u in mids]
        for u, row in sorted(zip(mids, got), key=lambda q: -q[0]):
            k = int(np.searchsorted(us, u))
            us.insert(k, u)
            rows.insert(k, row)
    reg, changes = _changes(us, rows)
    if any(r == -1 for r in reg):
        res["hopf_status"] = res["stick_status"] = FAILED
    changes = changes[:MAX_TRANSITIONS]
    kinds = [_smooth_kind(pt, us, rows, reg, j) for j in changes]
    subs = []
    for j, kind in zip(changes, kinds):
        if kind == "hopf":
            side = -1 if reg[j] == codes.R_SLIP_CYCLE else 1
            guess, amp = _hopf_guess(pt, us, rows, j, side, offset)
            subs.append(_hopf(pt, guess, side, offset, reach=amp))
        elif kind == "graze":
            js = j if reg[j] == codes.R_SLIP_CYCLE else j + 1
            jt = j + 1 if js == j else j
            subs.append(_graze(pt, us[jt], us[js], xtol, [(us[js], rows[js])]))
    found = iter((yield from _together(subs)))
    hopfs, grazes = [], []
    for j, kind in zip(changes, kinds):
        if kind is None:
            out = {"value": 0.5 * (us[j] + us[j + 1]), "width": abs(us[j + 1] - us[j]),
                   "status": LOCATED if abs(us[j + 1] - us[j]) <= xtol
                   else INCONSISTENT}
        else:
            out = next(found)
            (hopfs if kind == "hopf" else grazes).append(out)
        width = out["error"] if kind == "hopf" else out["width"]
        res["transitions"].append((out["value"], width, reg[j], reg[j + 1],
                                   out["status"]))
    if hopfs:
        # the Hopf point of the cycle branch: the highest (first from above)
        best = max(hopfs, key=lambda o: o["value"] if np.isfinite(o["value"])
                   else -math.inf)
        res.update(v_hopf=best["value"], v_hopf_error=best["error"],
                   hopf_status=best["status"], hopf_reach=best["reach"],
                   hopf_shape=best.get("shape"))
    elif res["hopf_status"] != FAILED:
        res["hopf_status"] = ABSENT
    if grazes:
        # the stick onset of the Hopf branch: the grazing nearest the Hopf point
        ref = res["v_hopf"] if np.isfinite(res["v_hopf"]) else values[-1]
        best = min(grazes, key=lambda o: abs(o["value"] - ref)
                   if np.isfinite(o["value"]) else math.inf)
        res.update(v_stick_onset=best["value"], v_stick_onset_width=best["width"],
                   stick_status=best["status"], graze_amp=best["amp"])
    elif res["stick_status"] != FAILED:
        res["stick_status"] = ABSENT
    return res


# ------------------------------------------------------------------ arguments
def checked_bracket(grid: Grid, along: str, bracket) -> tuple[float, float]:
    """(lo, hi) of a search along ``along``, checked: a pair of finite reals with
    lo < hi; the grid's ``along`` range where ``bracket`` is None."""
    ax = grid.axis(along)
    if bracket is None:
        if not isinstance(ax, np.ndarray):
            raise ValueError(f"bracket is needed when {along!r} is not swept in the "
                             f"grid (got {along}={ax!r})")
        bracket = (float(ax.min()), float(ax.max()))
    if not (isinstance(bracket, (tuple, list, np.ndarray)) and len(bracket) == 2):
        raise ValueError(f"bracket must be a pair (lo, hi) [{UNITS[along]}], got "
                         f"{bracket!r}")
    lo, hi = (check_real(f"bracket[{i}] (along {along})", x) for i, x in
              enumerate(bracket))
    if not lo < hi:
        raise ValueError(f"bracket must be finite with lo < hi, got {bracket!r}")
    return lo, hi


def _scan_values(grid: Grid, along: str, bracket, scan: int,
                 chunks: int | None = None) -> np.ndarray:
    """The coarse scan along ``along``, after the size rule of the searches
    (:func:`sweepcore.sizing.boundary_need`; a task of ``chunks`` searches, default
    all of them)."""
    checked_grid(grid)
    ax = grid.axis(along)
    lo, hi = checked_bracket(grid, along, bracket)
    if along == "v" and lo <= 0.0:
        raise ValueError(f"bracket along v must lie in v > 0 (the motion is mirror "
                         f"symmetric in v), got lo = {lo!r}")
    if isinstance(scan, bool) or not isinstance(scan, (int, np.integer)) or scan < 3:
        raise ValueError(f"scan must be an integer >= 3 (coarse scan points), got "
                         f"{scan!r}")
    points = grid.size // (ax.size if isinstance(ax, np.ndarray) else 1)
    refuse_unaffordable(boundary_need(points, int(scan), chunks or points))
    if lo > 0.0 and hi / lo > GEOMETRIC_SCAN:
        # linear points over decades would all sit in the top one (a bracket
        # (1e-3, 1e6) has none between 1e-3 and 3e4, where v* = 5.77 is)
        return np.geomspace(lo, hi, int(scan))
    return np.linspace(lo, hi, int(scan))


def _check_search(along, xtol, offset):
    if along not in AXES[:6]:
        raise ValueError(f"along must be one of {AXES[:6]}, got {along!r}"
                         f"{did_you_mean(along, AXES[:6])}")
    for name, val in (("xtol", xtol), ("offset", offset)):
        if isinstance(val, bool) or not isinstance(val, (int, float)) or \
                not (math.isfinite(val) and val > 0):
            raise ValueError(f"{name} must be a finite number > 0, got {val!r}")
    if not offset < 0.1:
        raise ValueError(f"offset must be < 0.1 (relative distance of the Hopf "
                         f"samples), got {offset!r}")


def _other_grid(grid: Grid, along: str, placeholder: float) -> Grid:
    """``grid`` with ``along`` fixed (its rows carry a placeholder there)."""
    checked_grid(grid)
    if grid.mode != "product":
        raise ValueError("locate_boundaries needs a product Grid (Grid(...)), not "
                         "Grid.points")
    return dataclasses.replace(grid, **{along: placeholder})


def _start(grid: Grid):
    x0, xd0 = grid.axis("x0"), grid.axis("xdot0")
    if isinstance(x0, np.ndarray) or isinstance(xd0, np.ndarray):
        raise ValueError("x0 and xdot0 must be scalars (one start for every search)")
    return (x0, STUCK if xd0 is None else xd0)


def _warn_scan_failures(results, along: str, values) -> None:
    """One warning saying where the coarse scan's attractors failed and why (the
    searches there end ``attractor_failed``); removes the record from ``results``."""
    failed = [f for r in results for f in r.pop("scan_failures", ())]
    if not failed:
        return
    where = [u for u, _ in failed]
    names = sorted({codes.STATUS_NAMES[s] for _, s in failed})
    warnings.warn(
        f"locate_boundaries: {len(failed)} of {len(values) * len(results)} attractors "
        f"of the coarse scan failed ({', '.join(names)}) at {along} in "
        f"[{min(where):.6g}, {max(where):.6g}] {UNITS[along]}: no regime change is "
        "seen there, and a search that needs one of them ends attractor_failed. "
        "step_budget_exceeded far from the boundaries is usually a stiff equilibrium "
        "(|q| >> omega): narrow the bracket, or raise max_steps",
        RuntimeWarning, stacklevel=3)


# ------------------------------------------------------------------- executors
def locate_chunk(base: np.ndarray, along: str, values: np.ndarray, xtol: float,
                 offset: float, start, o: np.ndarray, laws=(ANALYTIC,),
                 parallel: bool = False):
    """Boundaries of the points ``base`` (kernel rows; their laws ``laws``): the task
    of one chunk."""
    pts = [_Point(row, along, float(o[layout.O_RTOL]), laws) for row in base]
    solvers = [_locate_point(p, values, xtol, offset, start) for p in pts]
    results, evals = _drive(solvers, base, COLUMNS[along], o, parallel, laws)
    for r, n, p in zip(results, evals, pts):
        r["evaluations"] = int(n)
        r.update(cycle_boundaries(p, values, xtol, offset, o))
        for key in ("hopf_reach", "hopf_shape", "graze_amp", "graze_reach"):
            r.pop(key, None)
    return results


@checked_keywords(options=True)
def locate_boundaries(grid: Grid, along: str = "v", bracket=None, xtol: float = 1e-9,
                      scan: int = 32, offset: float = 5e-3, tol: float = 1e-10,
                      method: str = "auto", chunks: int | None = None, client=None,
                      scheduler=None, **options) -> xr.Dataset:
    """Hopf point, stick onset and every regime change along ``along``, to ``xtol``.

    Parameters
    ----------
    grid : Grid
        Parameter sets (kN, cm, s). Every point of the grid *without* the
        ``along`` axis gets its boundaries; ``along``, if swept, gives the bracket.
    along : str
        The parameter searched, default the belt speed ``v``.
    bracket : (lo, hi), optional
        Search interval [units of ``along``]; default the range of ``along`` in
        ``grid``. Along v it must lie in v > 0.
    xtol : float
        Width of the final bracket of the stick onset and of label changes
        [units of ``along``].
    scan : int
        Points of the coarse scan that brackets the changes (an interval narrower
        than the scan step with two changes in it is missed).
    offset : float
        Relative distance between the Hopf samples (see the module notes).
    tol : float
        Tolerance of every attractor search (:func:`sweepcore.attractor`); it
        limits the accuracy of the indicators (benchmarks/README.md).
    method, **options
        As :func:`sweepcore.sweep`.
    chunks, client, scheduler
        As :func:`sweepcore.sweep`: one task per chunk of points, run by numba
        threads in this process (default), a dask local scheduler or a
        distributed cluster. Results do not depend on them.

    Returns
    -------
    xarray.Dataset
        Over the grid's other swept dimensions (CF-1.11, units on every
        variable): ``v_hopf`` and ``v_hopf_error`` (the Hopf point and the
        estimated error of its extrapolation), ``v_hopf_subcritical`` (with
        ``_error``) and ``v_fold`` (with ``_width``), the two ends of the
        unstable slip cycle where steady sliding and stick-slip coexist
        (:mod:`sweepcore.boundaries.fold`; ``subcritical_status``,
        ``fold_status``), ``hopf_criticality`` (analytic, from the first
        Lyapunov coefficient), ``v_stick_onset`` and
        ``v_stick_onset_width`` (its uncertainty), their ``*_status`` flags
        (located, absent, attractor_failed, inconsistent), the analytic ``v_star``
        and the averaging estimate ``v_stick_onset_estimate = 2 v*/sqrt(5)``,
        ``evaluations`` (attractors computed) and, along ``transition``, every
        change found in the scan: ``transition_value``, ``transition_width``,
        ``regime_below``, ``regime_above``, ``transition_status``. (With
        ``along`` other than v the names keep the ``v_`` prefix; units follow
        ``along``.)

        A forced grid (F0 or Y0 given; ``along`` any parameter of
        :func:`sweepcore.follow_response`, e.g. ``"F0"``): over the other axes,
        ``<along>_stick_onset`` (where the response's finite sticks appear or
        vanish) and ``<along>_stops_change`` (where its stops per period change),
        each with ``_width`` (half its final bracket, below ``xtol`` times the
        value: ``xtol`` is relative here), ``stick_status``, ``stops_status``, the
        counts either side, and ``<along>_den_hartog`` where Den Hartog's
        boundary applies (:mod:`sweepcore.boundaries.forced`; ``scan`` and
        ``offset`` are not used).
    """
    if getattr(grid, "forced", False):
        from .forced import locate_forced
        return locate_forced(grid, along, bracket, xtol, tol, method, chunks, client,
                             scheduler, options)
    _check_search(along, xtol, offset)
    execute.check_chunks(chunks)
    values = _scan_values(grid, along, bracket, scan, chunks)
    o = make_options(method, tol=tol, **options)
    kind, target = execute.resolve(client, scheduler)
    other = _other_grid(grid, along, float(values[0]))
    start = _start(grid)
    size = other.size
    chunk = size if chunks is None else min(int(chunks), size)
    bounds = execute.chunk_bounds(size, chunk)
    parts = [None] * len(bounds)

    def task(i):
        rows = other.rows(*bounds[i])
        return locate_chunk, (rows, along, values, xtol, offset, start, o, grid.laws)
    execute.run(kind, target, range(len(bounds)), task, parts.__setitem__)
    results = [r for part in parts for r in part]
    _warn_scan_failures(results, along, values)
    call = (f"sweepcore.locate_boundaries({grid!r}, along={along!r}, "
            f"bracket={(float(values[0]), float(values[-1]))!r}, xtol={xtol!r}, "
            f"scan={scan!r}, offset={offset!r}, tol={tol!r}, method={method!r})")
    return _dataset(other, along, results, o, method, call, transitions=True)
