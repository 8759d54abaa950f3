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


def _together(gens):
    """Run sub-solvers in lockstep inside one solver; returns their results."""
    results = [None] * len(gens)
    asks = {}
    for i, g in enumerate(gens):
        try:
            asks[i] = next(g)
        except StopIteration as stop:
            results[i] = stop.value
    while asks:
        rows = yield [r for i in asks for r in asks[i]]
        pos, nxt = 0, {}
        for i, req in asks.items():
            part = rows[pos:pos + len(req)]
            pos += len(req)
            try:
                nxt[i] = gens[i].send(part)
            except StopIteration as stop:
                results[i] = stop.value
        asks = nxt
    return results


def _drive(solvers, base: np.ndarray, col: int, o: np.ndarray, parallel: bool):
    """Run one solver per row of ``base`` to the end; returns (results, evaluations).

    A solver yields a list of requests ``(value, x0, xdot0)`` (``value`` goes in
    column ``col``; ``xdot0 = NaN`` starts stuck on the belt) and receives the
    observables rows (layout.OB_*) of their attractors.
    """
    n = len(solvers)
    results, evals, asks = [None] * n, np.zeros(n, np.int64), {}
    for i, g in enumerate(solvers):
        try:
            asks[i] = next(g)
        except StopIteration as stop:
            results[i] = stop.value
    while asks:
        owners = [i for i in asks for _ in asks[i]]
        P = base[owners].copy()
        req = np.array([r for i in asks for r in asks[i]], dtype=np.float64)
        P[:, col] = req[:, 0]
        P[:, layout.X0] = req[:, 1]
        P[:, layout.XD0] = np.where(np.isnan(req[:, 2]), P[:, layout.V], req[:, 2])
        out = np.empty((len(owners), layout.NOBS))
        execute.attractors(P, o, out, parallel)
        # A start inside a cycle that the search does not bring to an attractor
        # (a motion growing slowly onto a stick-slip cycle at low damping ends with
        # the budget spent) is retried once from rest on the belt at x = 0.
        again = np.flatnonzero(np.isin(out[:, layout.OB_STATUS], RETRY)
                               & ~np.isnan(req[:, 2]))
        if again.size:
            Q = P[again].copy()
            Q[:, layout.X0] = 0.0
            Q[:, layout.XD0] = Q[:, layout.V]
            redo = np.empty((again.size, layout.NOBS))
            execute.attractors(Q, o, redo, parallel)
            out[again] = redo
            for j in again:
                evals[owners[j]] += 1
        pos, nxt = 0, {}
        for i, r in asks.items():
            evals[i] += len(r)
            part = out[pos:pos + len(r)]
            pos += len(r)
            try:
                nxt[i] = solvers[i].send(part)
            except StopIteration as stop:
                results[i] = stop.value
        asks = nxt
    return results, evals
