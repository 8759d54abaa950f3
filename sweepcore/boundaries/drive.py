"""Lockstep drivers: the boundary solvers are Python generators that ask for
attractors and receive the kernel's observables rows; the drivers run the solvers
of many grid points together, each round one batched call of the attractor kernel
(numba threads, or the serial kernel inside a dask task), so Python costs a few
microseconds per attractor."""
from __future__ import annotations

import numpy as np

from .. import execute
from .._kernels import codes, layout

RETRY = (codes.UNCONVERGED, codes.STEP_BUDGET)  # retried from rest on the belt


def lockstep(solvers):
    """Generator: the solvers run together, as one.

    Each round yields the requests of every solver still running, as
    ``(owner, request)`` pairs (``owner`` the solver's index), and is sent their
    rows, in the same order; each solver gets its own rows back. Returns
    ``(results, evaluations)``: each solver's return value and how many requests
    it made.
    """
    n = len(solvers)
    results, evals, asks = [None] * n, np.zeros(n, np.int64), {}
    for i, g in enumerate(solvers):
        try:
            asks[i] = next(g)
        except StopIteration as stop:
            results[i] = stop.value
    while asks:
        rows = yield [(i, r) for i in asks for r in asks[i]]
        pos, nxt = 0, {}
        for i, req in asks.items():
            evals[i] += len(req)
            part = rows[pos:pos + len(req)]
            pos += len(req)
            try:
                nxt[i] = solvers[i].send(part)
            except StopIteration as stop:
                results[i] = stop.value
        asks = nxt
    return results, evals


def _together(gens):
    """Run sub-solvers in lockstep inside one solver; returns their results."""
    run = lockstep(gens)
    try:
        asks = next(run)
        while True:
            asks = run.send((yield [req for _owner, req in asks]))
    except StopIteration as stop:
        return stop.value[0]


def _drive(solvers, base: np.ndarray, col: int, o: np.ndarray, parallel: bool, laws):
    """Run one solver per row of ``base`` to the end; returns (results, evaluations).

    A solver yields a list of requests ``(value, x0, xdot0)`` (``value`` goes in
    column ``col``; ``xdot0 = NaN`` starts stuck on the belt) and receives the
    observables rows (layout.OB_*) of their attractors. ``laws`` are the rows'
    laws (``layout.LAW`` indexes them).
    """
    run = lockstep(solvers)
    retried = np.zeros(len(solvers), np.int64)
    try:
        asks = next(run)
        while True:
            owners = [i for i, _req in asks]
            P = base[owners].copy()
            req = np.array([r for _owner, r in asks], dtype=np.float64)
            P[:, col] = req[:, 0]
            P[:, layout.X0] = req[:, 1]
            P[:, layout.XD0] = np.where(np.isnan(req[:, 2]), P[:, layout.V], req[:, 2])
            out = np.empty((len(owners), layout.NOBS))
            execute.attractors(P, laws, o, out, parallel)
            # A start inside a cycle that the search does not bring to an attractor
            # (a motion growing slowly onto a stick-slip cycle at low damping ends
            # with the budget spent) is retried once from rest on the belt at x = 0.
            again = np.flatnonzero(np.isin(out[:, layout.OB_STATUS], RETRY)
                                   & ~np.isnan(req[:, 2]))
            if again.size:
                Q = P[again].copy()
                Q[:, layout.X0] = 0.0
                Q[:, layout.XD0] = Q[:, layout.V]
                redo = np.empty((again.size, layout.NOBS))
                execute.attractors(Q, laws, o, redo, parallel)
                out[again] = redo
                for j in again:
                    retried[owners[j]] += 1
            asks = run.send(out)
    except StopIteration as stop:
        results, evals = stop.value
    return results, evals + retried
