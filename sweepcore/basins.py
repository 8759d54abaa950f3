"""Basin stability: which attractor a region of start states ends on, per grid point.

For every point of a grid and a box of starts ``x0 in [lo, hi]``, ``xdot0 in [lo,
hi]``, :func:`basin_stability` gives the fraction of the box that ends on each
attractor, with an error, by one of two routes:

* **exact** (a geometric fact of the plane, no sampling error): the motion cannot
  cross a stop-free slip cycle, so where one unstable slip cycle surrounds a stable
  equilibrium, the equilibrium's basin is the cycle's interior and its fraction is
  the area of that interior inside the box over the box's area. The cycle comes
  from the return-map scan (:mod:`sweepcore.cycles`), its polygon is sampled
  finely enough that the area's error is below ``ftol``, and the polygon is clipped
  to the box (:func:`sweepcore.cycles.clipped_area`). Where the scan finds no slip
  cycle, the box is one basin. Either way a few starts (``checks``) are run on the
  attractor kernel to verify the premise: those inside the cycle end on the
  equilibrium, those outside (in the box) on one other attractor.
* **sampled** (Monte-Carlo): ``samples`` starts per point on the attractor kernel,
  the attractors told apart by their invariants (regime, then amplitude and mean to
  ``match`` of the length scale), the fraction of each with its binomial standard
  error ``sqrt(f (1 - f) / N)``.

``route="auto"`` takes the exact route where it applies and samples elsewhere.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from . import execute, law, resumable
from ._kernels import codes, layout
from ._kernels.cycles import LOWEST, MAX_CYCLES
from .basin_labels import (EXACT, NOT_APPLICABLE, NOT_RESOLVED, OK, ROUTE_NAMES,
                           SAMPLED, STATUS_NAMES, UNCLASSIFIED, UNSETTLED,
                           basin_dataset, names_of, pack, unpack)
from .cycles import (UNSTABLE, _check_no_start, clipped_area, cycle_polygon, inside,
                     stability)
from .grid import Grid, checked_grid
from .io import check_flag, result_path
from .options import checked_keywords, make_options
from .params import check_real
from .sizing import basin_need, refuse_unaffordable

__all__ = ["basin_stability", "clusters", "ROUTE_NAMES", "STATUS_NAMES"]

ROUTES = ("auto", "exact", "sampled")
SAMPLINGS = ("uniform", "halton", "grid")
# regimes whose attractors are told apart by amplitude and mean; the others (a
# neutral family, the failures) count as one attractor each
SPLIT = (codes.R_EQUILIBRIUM, codes.R_SLIP_CYCLE, codes.R_STICK_SLIP)
SEED_MAX = 2**63 - 1        # the seed is an attribute of the file (a netCDF int64)
FIRST_POINTS, MAX_POINTS = 1024, 2 ** 18    # polygon samples: first try, largest


@dataclass(frozen=True)
class Spec:
    """What a basin task needs besides the grid and the option row."""
    box: tuple
    samples: int
    route: str
    sampling: str
    seed: int
    checks: int
    ftol: float
    match: float

    @property
    def area(self) -> float:
        (xl, xh), (yl, yh) = self.box
        return (xh - xl) * (yh - yl)


# ------------------------------------------------------------------ starts
def _uniform(spec, flat: int, n: int, stream: int):
    """``n`` uniform starts in the box, seeded by (seed, flat index, stream): the
    same whatever the chunks."""
    (xl, xh), (yl, yh) = spec.box
    u = np.random.default_rng([spec.seed, flat, stream]).random((n, 2))
    return xl + (xh - xl) * u[:, 0], yl + (yh - yl) * u[:, 1]


def _radical_inverse(i: np.ndarray, base: int) -> np.ndarray:
    """Van der Corput: the digits of i in ``base`` mirrored behind the point."""
    out = np.zeros(i.shape)
    scale = 1.0 / base
    while np.any(i > 0):
        i, digit = np.divmod(i, base)
        out += digit * scale
        scale /= base
    return out


def _starts(spec, flat: int):
    """The sampled route's starts of one point: uniform (seeded); ``halton``: the
    2-D Halton sequence (bases 2 and 3, a low-discrepancy set) shifted modulo 1 by a
    seeded uniform vector (Cranley-Patterson), so that points differ; or the
    midpoints of a grid of about ``samples`` cells, as square as the box allows."""
    (xl, xh), (yl, yh) = spec.box
    if spec.sampling == "uniform":
        return _uniform(spec, flat, spec.samples, 0)
    if spec.sampling == "halton":
        i = np.arange(1, spec.samples + 1)
        shift = np.random.default_rng([spec.seed, flat, 2]).random(2)
        u = (_radical_inverse(i, 2) + shift[0]) % 1.0
        w = (_radical_inverse(i, 3) + shift[1]) % 1.0
        return xl + (xh - xl) * u, yl + (yh - yl) * w
    nx = max(1, round(math.sqrt(spec.samples * (xh - xl) / (yh - yl))))
    ny = max(1, round(spec.samples / nx))
    gx = xl + (np.arange(nx) + 0.5) * (xh - xl) / nx
    gy = yl + (np.arange(ny) + 0.5) * (yh - yl) / ny
    X, Y = np.meshgrid(gx, gy)
    return X.ravel(), Y.ravel()


def _length_scale(row, laws) -> float:
    return float(law.length_scale(row, laws)[0])


def _run(rows, starts, o, parallel, laws):
    """Attractor rows of every start: ``rows[i]`` with the starts ``starts[i]``."""
    counts = [len(s[0]) for s in starts]
    P = np.repeat(np.asarray(rows), counts, axis=0)
    if P.shape[0]:
        P[:, layout.X0] = np.concatenate([s[0] for s in starts])
        P[:, layout.XD0] = np.concatenate([s[1] for s in starts])
    out = np.empty((P.shape[0], layout.NOBS))
    if P.shape[0]:
        execute.attractors(P, laws, o, out, parallel)
    return np.split(out, np.cumsum(counts)[:-1])


# ------------------------------------------------------------------ attractors
def _split(idx, values, gap):
    order = idx[np.argsort(values[idx], kind="stable")]
    return np.split(order, np.flatnonzero(np.diff(values[order]) > gap) + 1)


def clusters(out, lx: float, match: float):
    """The attractors the runs ``out`` (observables rows) ended on: a list of
    ``(regime, indices)``, by regime, then by amplitude and mean (a gap wider than
    ``match * lx`` between sorted values separates two attractors)."""
    regime = out[:, layout.OB_REGIME].astype(np.int64)
    found = []
    for r in np.unique(regime):
        idx = np.flatnonzero(regime == r)
        if r not in SPLIT:
            found.append((int(r), idx))
            continue
        for part in _split(idx, out[:, layout.OB_AMPLITUDE], match * lx):
            found += [(int(r), sub) for sub in _split(part, out[:, layout.OB_MEAN],
                                                        match * lx)]
    return found


def _tally(out, lx, spec):
    """The sampled route's answer for one point."""
    n = out.shape[0]
    found = clusters(out, lx, spec.match)
    entries = []
    for name, (r, idx) in zip(names_of([r for r, _ in found]), found):
        f = idx.size / n
        entries.append((name, r, f, math.sqrt(f * (1.0 - f) / n), out[idx[0]]))
    status = UNCLASSIFIED if any(r in UNSETTLED for r, _ in found) else OK
    return {"route": SAMPLED, "status": status, "samples": n, "attractors": entries}


# ------------------------------------------------------------------ exact route
def _polygon(row, cycle, o, spec, laws):
    """``(fraction, error, x, y)`` of the cycle's interior in the box, or None when
    the polygon cannot be drawn. ``error``: the change of the clipped area from n/2
    to n samples (shoelace areas of a smooth curve converge as h^2, so that change
    is three times the error of n samples), plus the cycle's own error (tol L and
    the closing gap, over the perimeter); the samples are quadrupled until it is
    below ``ftol`` (or ``MAX_POINTS`` is reached)."""
    n = FIRST_POINTS
    while True:
        x, y, gap, ok = cycle_polygon(row, cycle, o, n, law.row_law(row, laws))
        if not ok:
            return None
        fine, perimeter = clipped_area(x, y, spec.box)
        coarse, _ = clipped_area(x[::2], y[::2], spec.box)
        shift = o[layout.O_RTOL] * _length_scale(row, laws) + gap
        error = (abs(fine - coarse) + perimeter * shift) / spec.area
        if error <= spec.ftol or n >= MAX_POINTS:
            return fine / spec.area, error, x, y
        n *= 4


def _plan(row, cycles, n_found, o, spec, flat, laws):
    """What the exact route needs for one point: ``None`` (it does not apply), or
    ``(fraction, error, starts_inside, starts_outside, resolved)``."""
    if n_found > 1 or np.nanmax(cycles[:, layout.OB_NSTEPS]) >= o[layout.O_MAX_STEPS]:
        return None
    omega = math.sqrt(row[layout.K] / row[layout.M])
    if n_found == 0:
        # one basin; a cycle below the scan's lowest rung encloses at most this
        lost = math.pi * omega * (LOWEST * _length_scale(row, laws)) ** 2 / spec.area
        return 0.0, lost, ([], []), _uniform(spec, flat, spec.checks, 1), True
    if stability(cycles[0]) != UNSTABLE:
        return None
    drawn = _polygon(row, cycles[0], o, spec, laws)
    if drawn is None:
        return None
    fraction, error, x, y = drawn
    xe = law.derived("x_eq", law.from_row(row, law.row_law(row, laws)))
    a = cycles[0, layout.OB_X_MAX if row[layout.V] > 0 else layout.OB_X_MIN]
    within = (xe + np.array([0.25, 0.5, 0.75]) * (a - xe), np.zeros(3))
    if not inside(x, y, np.array([xe]), np.array([0.0]))[0]:
        return None
    px, py = _uniform(spec, flat, 50 * spec.checks, 1)     # starts outside the cycle
    outside = ([], [])
    for lo in range(0, px.size, 4 * spec.checks):      # in rounds: the test costs
        cut = slice(lo, lo + 4 * spec.checks)           # (starts x vertices)
        out = ~inside(x, y, px[cut], py[cut])
        outside = tuple(np.concatenate([got, new[cut][out]])[:spec.checks]
                        for got, new in zip(outside, (px, py)))
        if outside[0].size == spec.checks:
            break
    if fraction < 1.0 - 1e-12 and outside[0].size == 0:
        return None                      # an outside too thin to check: sample
    return fraction, error, within, outside, error <= spec.ftol


def _verdict(plan, out_in, out_out, lx, spec):
    """The exact route's answer for one point from its plan and the check runs, or
    None where the checks contradict the premise."""
    fraction, error, _i, _o, resolved = plan
    status = OK if resolved else NOT_RESOLVED
    entries = []
    if out_in.shape[0]:
        inner = clusters(out_in, lx, spec.match)
        if len(inner) != 1 or inner[0][0] != codes.R_EQUILIBRIUM:
            return None
        if fraction > 0.0:
            entries.append(("equilibrium", codes.R_EQUILIBRIUM, fraction, error,
                            out_in[0]))
    if out_out.shape[0]:
        outer = clusters(out_out, lx, spec.match)
        if len(outer) != 1 or outer[0][0] in UNSETTLED or (
                out_in.shape[0] and outer[0][0] == codes.R_EQUILIBRIUM):
            return None
        r = outer[0][0]
        entries.append((codes.REGIME_NAMES[r], r, 1.0 - fraction, error, out_out[0]))
    return {"route": EXACT, "status": status,
            "samples": out_in.shape[0] + out_out.shape[0], "attractors": entries}


# ------------------------------------------------------------------ one chunk
def basin_chunk(grid: Grid, start: int, stop: int, o: np.ndarray, spec: Spec,
                first: int, parallel: bool = False) -> np.ndarray:
    """The task of one chunk: the answer of each point in [start, stop) of ``grid``
    (a block of the whole grid whose flat index ``first`` is ``start``, which seeds
    the starts), route, status, samples, the attractors (regime, fraction, error,
    observables row) and the scan's cycles, packed in one float64 row a point
    (:func:`sweepcore.basin_labels.pack`)."""
    rows = grid.rows(start, stop)
    n = stop - start
    flats = range(first, first + n)
    results = [None] * n
    if spec.route != "sampled":
        cyc = np.empty((n, MAX_CYCLES, layout.NOBS))
        found = np.zeros(n, np.int64)
        execute.cycles(rows, grid.laws, o, cyc, found, parallel)
        plans = [_plan(rows[i], cyc[i], found[i], o, spec, f, grid.laws)
                 for i, f in enumerate(flats)]
        todo = [i for i in range(n) if plans[i] is not None]
        runs = _run(np.repeat(rows[todo], 2, axis=0),
                    [plans[i][k] for i in todo for k in (2, 3)], o, parallel, grid.laws)
        cycles = [{"cycles": cyc[i], "n_cycles": int(found[i])} for i in range(n)]
        for j, i in enumerate(todo):
            results[i] = _verdict(plans[i], runs[2 * j], runs[2 * j + 1],
                                  _length_scale(rows[i], grid.laws), spec)
            if spec.route == "auto" and results[i] and \
                    results[i]["status"] == NOT_RESOLVED:
                results[i] = None                     # sampled instead
    if spec.route == "exact":
        results = [r if r is not None else {"route": EXACT, "status": NOT_APPLICABLE,
                                            "samples": 0, "attractors": []}
                   for r in results]
    todo = [i for i in range(n) if results[i] is None]
    if todo:
        runs = _run(rows[todo], [_starts(spec, flats[i]) for i in todo], o, parallel,
                    grid.laws)
        for i, out in zip(todo, runs):
            results[i] = _tally(out, _length_scale(rows[i], grid.laws), spec)
    if spec.route != "sampled":        # the scan's cycles, beside the fractions
        for r, c in zip(results, cycles):
            r.update(c)
    return pack(results, spec.route != "sampled")


# ------------------------------------------------------------------ the API
def _box(name: str, value) -> tuple:
    try:
        lo, hi = value
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a pair (lo, hi) of numbers, got {value!r}") \
            from None
    try:
        lo, hi = (check_real(f"{name}[{i}]", v) for i, v in enumerate((lo, hi)))
    except (TypeError, ValueError) as err:
        raise type(err)(f"{name} must be a pair (lo, hi) of finite numbers: {err}") \
            from None
    if not lo < hi:
        raise ValueError(f"{name} must be a finite range with lo < hi, got {value!r}")
    return lo, hi


def _count(name: str, value, least: int, most: int | None = None) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) \
            or value < least:
        raise ValueError(f"{name} must be an integer >= {least}, got {value!r}")
    if most is not None and value > most:
        raise ValueError(f"{name} must be an integer in [{least}, {most}] (it is "
                         f"stored as a 64-bit integer), got {value!r}")
    return int(value)


def _fraction_tol(name: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{name} must be a number in (0, 1), got {value!r}")
    x = check_real(name, value)
    if not 0.0 < x < 1.0:
        raise ValueError(f"{name} must be a number in (0, 1), got {value!r}")
    return x


def _spec(x0, xdot0, samples, route, sampling, seed, checks, ftol, match) -> Spec:
    if route not in ROUTES:
        raise ValueError(f"route must be one of {ROUTES}, got {route!r}")
    if sampling not in SAMPLINGS:
        raise ValueError(f"sampling must be one of {SAMPLINGS}, got {sampling!r}")
    return Spec((_box("x0", x0), _box("xdot0", xdot0)), _count("samples", samples, 1),
                route, sampling, _count("seed", seed, 0, SEED_MAX),
                _count("checks", checks, 1), _fraction_tol("ftol", ftol),
                _fraction_tol("match", match))


@checked_keywords(options=True)
def basin_stability(grid: Grid, x0=(-2.0, 2.0), xdot0=(0.0, 2.0), samples: int = 1000,
                    method: str = "auto", tol: float = 1e-8, route: str = "auto",
                    sampling: str = "uniform", seed: int = 0, checks: int = 16,
                    ftol: float = 1e-6, match: float = 1e-5,
                    chunks: int | None = None, client=None, scheduler=None, path=None,
                    progress: bool | None = None, overwrite: bool = False,
                    **options) -> xr.Dataset:
    """The share of a box of start states that ends on each attractor, per grid point.

    Parameters
    ----------
    grid : Grid
        Parameter sets (kN, cm, s); x0 and xdot0 are given by the box, not the grid.
    x0, xdot0 : (lo, hi)
        The box of start states [cm], [cm s-1], lo < hi.
    samples : int
        Starts per point on the sampled route (``sampling="grid"``: the nearest
        count of a grid of square-ish cells, see the variable ``samples``).
    method, tol, **options
        As :func:`sweepcore.sweep` (max_steps, max_periods, dt, graze). The exact
        route needs the ODE's return map: with ``method="gps"`` it does not apply.
    route : {"auto", "exact", "sampled"}
        "exact": the area of the interior of the unstable slip cycle (module
        docstring). It applies where the return-map scan finds either no slip
        cycle (the box is one basin; fraction 1, error the area a cycle below the
        scan's lowest rung could enclose) or exactly one, unstable, around a stable
        equilibrium, and where ``checks`` starts confirm the premise: a few inside
        the cycle end on the equilibrium and ``checks`` uniform starts in the box
        outside it all end on one other attractor. Elsewhere the point's status is
        ``exact_route_not_applicable`` (NaN fractions). "sampled": ``samples``
        starts on the attractor kernel. "auto": exact where it applies, else
        sampled.
    sampling : {"uniform", "halton", "grid"}
        Starts of the sampled route: uniform, seeded by ``(seed, flat index of the
        point)`` (the same whatever the chunks); a randomly shifted Halton sequence
        (low discrepancy: the binomial error then overstates the error); or the
        midpoints of a grid.
    seed : int
        Seed of the uniform starts and of the exact route's checks.
    checks : int
        Starts run to verify the exact route's premise outside the cycle.
    ftol : float
        Target error of an exact fraction (the polygon is refined until the area
        changes by less, up to 2**18 samples; status ``polygon_not_resolved`` and
        NaN beyond).
    match : float
        Two runs end on the same attractor when regime, amplitude and mean agree to
        ``match`` of the length scale L = r_y/k + |v|/omega.
    chunks, client, scheduler, progress
        As :func:`sweepcore.sweep`: one task per chunk of grid points (default
        about 20,000 starts a task).
    path, overwrite
        Also write the result to this netCDF file, with the rules of
        :func:`sweepcore.sweep`'s ``path``: finished chunks are kept in a working
        store ``<path>.partial/``, so that rerunning the same call after an
        interruption computes only the chunks missing (results bit-identical); the
        file appears, atomically, only when complete.

    Returns
    -------
    xarray.Dataset
        Over the grid's dimensions and ``attractor`` (its coordinate the regime
        names; ``_2``, ``_3`` mark further attractors of the same regime at a point,
        in order of amplitude): ``basin_fraction`` and ``basin_fraction_error``
        (dimensionless; 0 where an attractor is not found at a point; the fractions
        of a point sum to 1, NaN where no route answered), the attractor's
        observables (``amplitude``, ``mean``, ``period``, ``floquet``, ``x_max``,
        ``x_min``, ``xdot_max``, ``stick_fraction``, from one start that ends on
        it), ``attractor_regime``; per point ``n_attractors``, ``samples`` (starts
        run), ``basin_route`` and ``basin_status`` (flags), and the analytic q,
        x_eq, v_star. Unless ``route="sampled"``, also the slip cycles of the
        return-map scan over ``cycle`` (the variables of :func:`sweepcore.
        slip_cycles`: ``n_cycles``, ``cycle_amplitude``, ``cycle_floquet`` > 1 for
        the unstable cycle that bounds the basins, ...).
    """
    checked_grid(grid)
    check_flag("overwrite", overwrite)
    check_flag("progress", progress, none=True)
    spec = _spec(x0, xdot0, samples, route, sampling, seed, checks, ftol, match)
    if method == "gps" and route == "exact":
        raise ValueError("route='exact' needs the ODE's return map; method='gps' "
                         "follows its own discrete map: use route='sampled'")
    if method == "gps":
        spec = Spec(**{**spec.__dict__, "route": "sampled"})
    o = make_options(method, tol=tol, **options)
    _check_no_start(grid, "basin stability (the box gives the starts)")
    execute.check_chunks(chunks, " (points per chunk)")
    target_path = None if path is None else result_path(path, overwrite=overwrite)
    kind, target = execute.resolve(client, scheduler)
    need = basin_need(grid.size, spec.samples, spec.checks, spec.route, chunks)
    refuse_unaffordable(need)
    chunk = need["chunk"]
    call = (f"sweepcore.basin_stability({grid!r}, x0={spec.box[0]!r}, "
            f"xdot0={spec.box[1]!r}, samples={spec.samples}, method={method!r}, "
            f"tol={tol!r}, route={route!r}, sampling={sampling!r}, seed={seed!r})")

    def task(bounds):
        return lambda i: (basin_chunk, (*grid.block(*bounds[i]), o, spec,
                                        bounds[i][0]))

    def labelled(parts):
        head, cycles, entries = unpack(parts, spec.route != "sampled")
        return basin_dataset(grid, head, cycles, entries, spec, o, method, tol, call)

    with execute.connected(kind, target) as (kind, target):
        if target_path is None:
            return labelled(resumable.compute_in_memory(grid.size, chunk, kind, target,
                                                        task, progress, "basins"))
        fixed = {"kind": "basins", "grid": grid.fingerprint(), "options": o.tolist(),
                 "spec": [list(spec.box[0]), list(spec.box[1]), spec.samples,
                          spec.route, spec.sampling, spec.seed, spec.checks,
                          spec.ftol, spec.match]}
        with resumable.open_store(target_path, fixed, {"call": call}, grid.size, None,
                                  None if chunks is None else chunk, chunk) as store:
            bounds = [store.bounds(i) for i in range(store.n_chunks)]
            resumable.compute_missing(store, kind, target, task(bounds), progress,
                                      "basin_stability")
            ds = labelled(resumable.stored_chunks(store))
            resumable.write_result(store, ds, target_path)
    return ds
