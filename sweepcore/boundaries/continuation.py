"""Natural continuation of the Hopf point and the stick onset along a second
parameter: :func:`continue_boundary`, each step seeded by the previous ones."""
from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..grid import AXES, COLUMNS, Grid
from ..options import checked_keywords, did_you_mean, make_options
from .dataset import _dataset
from .drive import _drive, _together
from .fold import cycle_boundaries
from .graze import SEED_SPACING, _seeded_graze
from .hopf import _hopf, _seeded_hopf
from .locate import (_check_search, _empty, _locate_point, _other_grid, _scan_values,
                     _start)
from .point import LOCATED, _Point

LOOKAHEAD = 8           # continuation steps predicted from one history, run together


def _predict(xs, ys, x):
    """Linear extrapolation of the last two points, in log-log when all > 0
    (v* ~ alpha2^-1/2 is a straight line there)."""
    (x1, x2), (y1, y2) = xs[-2:], ys[-2:]
    if min(x1, x2, x, y1, y2) > 0.0:
        lx1, lx2, ly1, ly2 = map(math.log, (x1, x2, y1, y2))
        return math.exp(ly2 + (ly2 - ly1) * (math.log(x) - lx2) / (lx2 - lx1))
    return y2 + (y2 - y1) * (x - x2) / (x2 - x1)


def _continued_point(pt, values, xtol, offset, start, hist, over_value):
    """Solver: one step of the natural continuation, seeded by ``hist`` (the
    previous steps); falls back to a scan when the seeds do not bracket."""
    subs, kinds = [], []
    hx = hist["x"]
    if len(hist["hopf"]) >= 2:
        guess = _predict(hx[-2:], hist["hopf"][-2:], over_value)
        reach = hist["reach"][-1] * guess / hist["hopf"][-1]
        shape = hist["shape"][-1]
        subs.append(_seeded_hopf(pt, guess, offset, reach, shape, xtol)
                    if shape is not None else _hopf(pt, guess, -1, offset, reach=reach))
        kinds.append("hopf")
    if len(hist["graze"]) >= 2:
        guess = _predict(hx[-2:], hist["graze"][-2:], over_value)
        # slip cycles beyond the band where they touch the belt within the touch
        # tolerance (~1e-6 relative) and beyond the prediction's error
        delta = max(4.0 * hist["graze_err"], SEED_SPACING * guess)
        scale = guess / hist["graze"][-1]
        seeds = hist["graze_reach"][-1]
        same = abs(delta - hist["graze_delta"] * guess) <= 1e-9 * delta
        if seeds is not None and same:
            seeds = seeds * scale            # the same offsets: scaled cycles
        else:
            seeds = None
        subs.append(_seeded_graze(pt, guess, delta, xtol,
                                  hist["graze_amp"][-1] * scale, seeds,
                                  hist["graze_width"]))
        kinds.append("graze")
    found = yield from _together(subs)      # [] at once when there is none
    res = _empty()
    missing = {"hopf", "graze"} - {k for k, f in zip(kinds, found)
                                   if f["status"] == LOCATED}
    for kind, out in zip(kinds, found):
        if kind == "hopf" and out["status"] == LOCATED:
            res.update(v_hopf=out["value"], v_hopf_error=out["error"],
                       hopf_status=LOCATED, hopf_reach=out["reach"],
                       hopf_shape=out.get("shape"))
        elif kind == "graze" and out["status"] == LOCATED:
            res.update(v_stick_onset=out["value"], v_stick_onset_width=out["width"],
                       stick_status=LOCATED, guess_error=out.get("guess_error", 0.0),
                       graze_amp=out["amp"], graze_reach=out.get("seed_reach"),
                       graze_delta=out.get("delta", math.nan))
    res["fallback"] = bool(missing)
    if missing:
        full = yield from _locate_point(pt, values, xtol, offset, start)
        for key in (("v_hopf", "v_hopf_error", "hopf_status", "hopf_reach",
                     "hopf_shape")
                    if "hopf" in missing else ()) + \
                   (("v_stick_onset", "v_stick_onset_width", "stick_status")
                    if "graze" in missing else ()):
            if key == "stick_status" and "graze_amp" in full:
                res["graze_amp"] = full["graze_amp"]
            res[key] = full[key]
    return res


def _history():
    """What the continuation carries from step to step."""
    return {"x": [], "hopf": [], "reach": [], "shape": [], "graze": [], "graze_amp": [],
            "graze_reach": [], "graze_delta": math.nan, "graze_err": 0.0,
            "graze_width": math.inf}


@checked_keywords(options=True)
def continue_boundary(grid: Grid, over: str = "alpha2", along: str = "v",
                      bracket=None, xtol: float = 1e-9, scan: int = 32,
                      offset: float = 5e-3, tol: float = 1e-10, method: str = "auto",
                      **options) -> xr.Dataset:
    """The Hopf and stick-onset curves along ``over`` by natural continuation.

    Each step is seeded by the previous ones: the two boundaries are predicted by
    linear extrapolation of the last two (in log-log when positive), for
    ``LOOKAHEAD`` steps at once (one batch of attractors); the Hopf point is
    extrapolated from three cycles with the shape of A^2 fitted on an earlier
    step (:func:`_seeded_hopf`, five cycles where that check fails), started on
    the previous step's cycles, scaled by the predicted ratio;
    the grazing is extrapolated from two slip cycles just above its prediction
    (spacing 2e-6 relative, or four times the last prediction error), started on the
    previous step's cycles, with one stick-slip check below it. Where the root
    through the two samples does not agree with the prediction to xtol/4, a
    third cycle is asked (and so for the Hopf point, :func:`_seeded_hopf`). A step
    whose seeds do not bracket falls back to the full scan of
    :func:`locate_boundaries` (so do the first two, and the ``continued`` flag says
    which). About 6 attractors a
    step against 32 for the scan alone. The ends of the unstable slip cycle (the
    subcritical Hopf point and the fold, :mod:`.fold`) are located at every step
    from a scan of cycles (cheap: no attractor is computed). Only ``v`` is
    supported as ``along`` here.

    Parameters
    ----------
    grid : Grid
        ``over`` swept (1-D, in the order to follow), every other axis fixed
        except ``along`` (whose range is the default bracket).
    over : str
        The continuation parameter, default alpha2.
    along, bracket, xtol, scan, offset, tol, method, **options
        As :func:`locate_boundaries`.

    Returns
    -------
    xarray.Dataset
        As :func:`locate_boundaries` over ``over`` (without the ``transition``
        variables), plus ``continued`` (1 where the step was seeded, 0 where it
        fell back to a scan).

        A forced grid (F0 or Y0 given) follows ``<along>_stick_onset`` (and
        reports the stops change) along ``over``: each step is searched within
        5 % of its prediction through the previous two, the whole bracket where
        that finds none (:func:`sweepcore.boundaries.forced.continue_forced`).
    """
    if getattr(grid, "forced", False):
        from .forced import continue_forced
        return continue_forced(grid, over, along, bracket, xtol, tol, method, options)
    _check_search(along, xtol, offset)
    if along != "v":
        raise ValueError(f"continue_boundary follows boundaries along v only, got "
                         f"along={along!r}")
    values = _scan_values(grid, along, bracket, scan, LOOKAHEAD)
    o = make_options(method, tol=tol, **options)
    other = _other_grid(grid, along, float(values[0]))
    if other.swept != (over,):
        raise ValueError(f"over={over!r}: continue_boundary needs {over!r} swept "
                         f"and every other parameter fixed (apart from {along!r}); "
                         f"swept: "
                         f"{other.swept}"
                         f"{'' if over in AXES else did_you_mean(over, AXES[:6])}")
    start = _start(grid)
    xs = np.asarray(other.axis(over))
    base = other.rows(0, other.size)
    hist = _history()
    results = []
    i = 0
    while i < len(base):
        # the next steps, all predicted from the same history, in one batch: the
        # kernel gets ~10 LOOKAHEAD attractors a round instead of ~10
        n = LOOKAHEAD if len(hist["x"]) >= 2 else 1
        rows = base[i:i + n]
        solvers = [_continued_point(_Point(row, along, tol, grid.laws), values, xtol,
                                    offset, start, hist, xs[i + j])
                   for j, row in enumerate(rows)]
        found, evals = _drive(solvers, rows, COLUMNS[along], o, True, grid.laws)
        errs = []
        for j, (res, ne) in enumerate(zip(found, evals)):
            res["evaluations"] = int(ne)
            res.update(cycle_boundaries(_Point(rows[j], along, tol, grid.laws), values,
                                        xtol, offset, o))
            res["continued"] = int(not res.pop("fallback"))
            ok_h = res["hopf_status"] == LOCATED
            ok_g = res["stick_status"] == LOCATED
            if not (ok_h and ok_g):      # restart the histories where a curve is lost
                hist = _history()
            else:
                hist["x"].append(xs[i + j])
                hist["hopf"].append(res["v_hopf"])
                hist["reach"].append(res["hopf_reach"])
                hist["shape"].append(res.get("hopf_shape"))
                hist["graze"].append(res["v_stick_onset"])
                hist["graze_amp"].append(res["graze_amp"])
                hist["graze_reach"].append(res.get("graze_reach"))
                hist["graze_delta"] = res.get("graze_delta", math.nan)
                hist["graze_width"] = res["v_stick_onset_width"]
                errs.append(max(res.pop("guess_error", 0.0), xtol)
                            if res["continued"] else abs(values[1] - values[0]) / 8)
                hist["graze_err"] = max(errs)
            for key in ("hopf_reach", "hopf_shape", "guess_error", "graze_amp",
                        "graze_reach", "graze_delta"):
                res.pop(key, None)
            results.append(res)
        i += len(rows)
    call = (f"sweepcore.continue_boundary({grid!r}, over={over!r}, along={along!r}, "
            f"bracket={(float(values[0]), float(values[-1]))!r}, xtol={xtol!r}, "
            f"scan={scan!r}, offset={offset!r}, tol={tol!r}, method={method!r})")
    ds = _dataset(other, along, results, o, method, call, transitions=False)
    ds["continued"] = xr.Variable(
        other.dims, np.array([r["continued"] for r in results], np.int8),
        {"units": "1", "long_name": "step seeded by the previous ones",
         "flag_values": np.array([0, 1], np.int8),
         "flag_meanings": "scanned continued"})
    return ds
