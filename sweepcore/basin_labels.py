"""The answers of basin stability, packed per chunk and labelled.

A chunk's answers (one per grid point: route, status, starts run, the attractors
found with their fraction, error and observables, and the scan's slip cycles) are
packed into one float64 array (:func:`pack`), which is what a task returns and the
working store keeps (``sweepcore.resumable``); :func:`unpack` joins the chunks and
:func:`basin_dataset` labels them, vectorised (no Python object per point).

Columns of a packed row: ``HEAD`` (route, status, samples, number of attractors,
number of slip cycles or -1 without the scan), the scan's ``MAX_CYCLES`` cycle rows
(unless the route is "sampled"), then one entry per attractor: regime, fraction,
error and the observables row of one start that ended on it. Entries keep their
order, so the attractors' names (``stick_slip_2`` after ``stick_slip``) are the
same after a round trip.
"""
from __future__ import annotations

import numpy as np
import xarray as xr

from . import labels, variables
from ._kernels import codes, layout
from ._kernels.cycles import MAX_CYCLES
from .cycles import cycle_variables

EXACT, SAMPLED = 0, 1
ROUTE_NAMES = {EXACT: "exact", SAMPLED: "sampled"}
OK, UNCLASSIFIED, NOT_APPLICABLE, NOT_RESOLVED = 0, 1, 2, 3
STATUS_NAMES = {OK: "ok", UNCLASSIFIED: "unclassified_starts",
                NOT_APPLICABLE: "exact_route_not_applicable",
                NOT_RESOLVED: "polygon_not_resolved"}
UNANSWERED = (NOT_APPLICABLE, NOT_RESOLVED)     # NaN fractions

ROUTE, STATUS, SAMPLES, N_ENTRIES, N_CYCLES = range(5)
HEAD = 5
CYCLE_COLUMNS = MAX_CYCLES * layout.NOBS
ENTRY = 3 + layout.NOBS                 # regime, fraction, error, observables
NONE = -1                               # attractor_regime of the placeholder "none"
UNSETTLED = (codes.R_UNCONVERGED, codes.R_FAILED)
# observables reported per attractor (from one start that ends on it)
PER_ATTRACTOR = ("amplitude", "mean", "period", "floquet", "x_max", "x_min",
                 "xdot_max", "stick_fraction")


def pack(answers: list, with_cycles: bool) -> np.ndarray:
    """``(n, width)`` float64 rows of a chunk's answers (dicts of route, status,
    samples, attractors ``(name, regime, fraction, error, row)`` and, with the
    scan, cycles and n_cycles)."""
    k = max((len(a["attractors"]) for a in answers), default=0)
    width = HEAD + (CYCLE_COLUMNS if with_cycles else 0) + k * ENTRY
    out = np.full((len(answers), width), np.nan)
    for i, a in enumerate(answers):
        out[i, :HEAD] = (a["route"], a["status"], a["samples"], len(a["attractors"]),
                         a.get("n_cycles", -1))
        at = HEAD
        if with_cycles:
            out[i, at:at + CYCLE_COLUMNS] = np.asarray(a["cycles"]).ravel()
            at += CYCLE_COLUMNS
        for _name, r, f, e, row in a["attractors"]:
            out[i, at:at + ENTRY] = (r, f, e, *row)
            at += ENTRY
    return out


def unpack(chunks: list, with_cycles: bool):
    """``(head (N, HEAD), cycles (N, MAX_CYCLES, NOBS) or None, entries (N, K,
    ENTRY))`` of the packed chunks in order (entries padded with NaN)."""
    first = HEAD + (CYCLE_COLUMNS if with_cycles else 0)
    k = max(((c.shape[1] - first) // ENTRY for c in chunks), default=0)
    n = sum(c.shape[0] for c in chunks)
    entries = np.full((n, max(k, 1), ENTRY), np.nan)
    head = np.empty((n, HEAD))
    cycles = np.empty((n, MAX_CYCLES, layout.NOBS)) if with_cycles else None
    at = 0
    for c in chunks:
        m = c.shape[0]
        head[at:at + m] = c[:, :HEAD]
        if with_cycles:
            cycles[at:at + m] = c[:, HEAD:first].reshape(m, MAX_CYCLES, layout.NOBS)
        kc = (c.shape[1] - first) // ENTRY
        entries[at:at + m, :kc] = c[:, first:].reshape(m, kc, ENTRY)
        at += m
    return head, cycles, entries


def names_of(regimes) -> list[str]:
    """Labels of attractors in order: the regime's name, then ``_2``, ``_3`` for
    further attractors of the same regime (in order of amplitude)."""
    seen = {}
    names = []
    for r in regimes:
        seen[r] = seen.get(r, 0) + 1
        base = codes.REGIME_NAMES[r]
        names.append(base if seen[r] == 1 else f"{base}_{seen[r]}")
    return names


def _ranks(reg: np.ndarray) -> np.ndarray:
    """Per entry, 1 + the earlier entries of its point with the same regime."""
    rank = np.ones(reg.shape, np.int64)
    for k in range(1, reg.shape[1]):
        rank[:, k] += (reg[:, :k] == reg[:, k:k + 1]).sum(axis=1)
    return rank


def _attractor_table(head, entries):
    """``(labels, fraction, error, observables, count)``: the attractors over every
    point, sorted by regime then name, and each point's values on them."""
    n = head.shape[0]
    reg = entries[..., 0]
    found = np.isfinite(reg)
    regi = np.where(found, reg, -1).astype(np.int64)
    rank = _ranks(np.where(found, reg, np.nan))
    pairs = {(int(r), int(k)) for r, k in zip(regi[found], rank[found])}
    table = sorted((r, codes.REGIME_NAMES[r] if k == 1 else
                    f"{codes.REGIME_NAMES[r]}_{k}", k) for r, k in pairs)
    m = max(1, len(table))
    frac, err = np.zeros((n, m)), np.zeros((n, m))
    obs = np.full((n, m, layout.NOBS), np.nan)
    for j, (r, _name, k) in enumerate(table):
        hit = found & (regi == r) & (rank == k)
        row = np.flatnonzero(hit.any(axis=1))
        col = hit[row].argmax(axis=1)
        frac[row, j] = entries[row, col, 1]
        err[row, j] = entries[row, col, 2]
        obs[row, j] = entries[row, col, 3:]
    unanswered = np.isin(head[:, STATUS], UNANSWERED)
    frac[unanswered], err[unanswered] = np.nan, np.nan
    count = (found & ~np.isin(regi, UNSETTLED)).sum(axis=1)
    return table, frac, err, obs, count


def basin_dataset(grid, head, cycles, entries, spec, o, method, tol,
                  call) -> xr.Dataset:
    """The labelled result of :func:`sweepcore.basin_stability` (its Returns)."""
    dims, shape = grid.dims, grid.shape
    table, frac, err, obs, count = _attractor_table(head, entries)
    n = frac.shape[1]
    adims, ashape = dims + ("attractor",), shape + (n,)
    data = {
        "basin_fraction": xr.Variable(adims, frac.reshape(ashape),
                                      labels.attrs(*variables.BASIN_FRACTION)),
        "basin_fraction_error": xr.Variable(
            adims, err.reshape(ashape), labels.attrs(*variables.BASIN_FRACTION_ERROR)),
    }
    for name in PER_ATTRACTOR:
        col, units, long_name, _comment = variables.OBSERVABLES[name]
        data[name] = xr.Variable(adims, obs[..., col].reshape(ashape), labels.attrs(
            units, f"{long_name} (per attractor)",
            "from one start that ends on the attractor; NaN where it is not found"))
    regimes = [r for r, _name, _k in table] or [NONE]
    data["attractor_regime"] = xr.Variable(
        "attractor", np.array(regimes, np.int8),
        labels.flags({NONE: "none", **codes.REGIME_NAMES}, "regime of the attractor"))
    data["n_attractors"] = xr.Variable(dims, count.reshape(shape),
                                       labels.attrs(*variables.N_ATTRACTORS))
    data["samples"] = xr.Variable(dims,
                                  head[:, SAMPLES].astype(np.int64).reshape(shape),
                                  labels.attrs(*variables.SAMPLES))
    data["basin_route"] = xr.Variable(
        dims, head[:, ROUTE].astype(np.int8).reshape(shape),
        labels.flags(ROUTE_NAMES, "route of the basin fractions"))
    data["basin_status"] = xr.Variable(
        dims, head[:, STATUS].astype(np.int8).reshape(shape),
        labels.flags(STATUS_NAMES, "status of the basin fractions of the point"))
    coords = {k: v for k, v in grid.coords().items() if k not in ("x0", "xdot0")}
    if cycles is not None:
        found = head[:, N_CYCLES].astype(np.int64)
        cyc = cycle_variables(cycles, found, dims, shape, o)
        coords["cycle"] = cyc.pop("cycle")
        data.update(cyc)
    names = [name for _r, name, _k in table] or ["none"]
    coords["attractor"] = xr.Variable("attractor", np.array(names, object), {
        "units": "1", "long_name": "attractor (regime name; _2, _3: further "
                                   "attractors of that regime at a point; none: no "
                                   "attractor was found at any point)"})
    ds = xr.Dataset(data, coords)
    for name in ("q", "x_eq", "v_star"):
        da = labels.analytic(name, {k: ds[k] for k in coords if k not in
                                    ("attractor", "cycle")}, dims, grid.laws)
        ds[name] = xr.Variable(da.dims, da.data, da.attrs)
    (xl, xh), (yl, yh) = spec.box
    ds.attrs.update({
        **labels.provenance(
            "Basin stability of the stick-slip friction oscillator", call,
            "exact route: area of the unstable slip cycle's interior in the box "
            "(return-map scan, polygon clipped to the box); sampled route: starts on "
            "the attractor kernel, attractors told apart by regime, amplitude and mean",
            "Units kN, cm, s. basin_fraction: share of the box of start states "
            "(x0, xdot0) that ends on the attractor."),
        "sweepcore_kind": "basins", "method": method, "tol": float(tol),
        "x0_range": np.array([xl, xh]), "xdot0_range": np.array([yl, yh]),
        "samples_requested": spec.samples, "route": spec.route,
        "sampling": spec.sampling, "seed": spec.seed, "checks": spec.checks,
        "ftol": spec.ftol, "match": spec.match})
    return ds
