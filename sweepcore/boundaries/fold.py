"""The ends of the unstable slip cycle: a subcritical Hopf point and a fold at
grazing (coexistence of steady sliding and stick-slip).

Where the Hopf point is subcritical (first Lyapunov coefficient > 0, e.g. the
exponential Stribeck law with damping) no stable slip cycle is born there: an
*unstable* slip cycle (Floquet multiplier > 1) surrounds the stable equilibrium
and bounds its basin. The attractor search cannot see it; the cycle scan of
``_kernels/cycles.py`` (fixed points of the return map, stable or not) can. Along
the searched parameter the unstable cycle exists on a band with two ends:

* the **subcritical Hopf point**, where it shrinks into the equilibrium (the
  equilibrium is unstable, q > 0 of eq. (46), on the side without the cycle). Its
  amplitude squared is smooth in ``v^2`` and vanishes there: the cubic through
  four unstable cycles at relative offsets ``offset, 2 offset, ...`` gives the root
  (as :mod:`.hopf` does with stable cycles), the cubic through samples 2..5 the
  error estimate;
* the **fold at grazing**, where its top reaches the belt (``xdot_max = v``):
  there it meets the stick-slip cycle, which exists only on the cycle's side (the
  stick-slip attractor disappears; the equilibrium is stable on both sides). The
  indicator ``g = v - xdot_max`` of the unstable cycle is smooth and vanishes
  linearly at the fold; it is extrapolated from the side where the cycle exists
  (:func:`sweepcore.boundaries.graze._slip_root`, polynomial through the nearest
  values), samples approaching the predicted root, until the roots of the
  polynomials of two degrees agree to ``xtol``. Existence alone brackets it: a
  cycle within ~1e-8 (relative) of grazing is no longer resolved by the scan,
  which is why the indicator, not existence, decides.

Each point costs one coarse scan (``scan`` cycle scans, ~2,000 steps each) and
~20 more near the two ends, ten times the attractor searches of a supercritical
point: the search runs only where the Hopf point v* is subcritical or degenerate
(first Lyapunov coefficient >= 0, :func:`may_coexist`); elsewhere both ends are
reported absent without a search (the paper's cubic law: always supercritical).
"""
from __future__ import annotations

import math

import numpy as np

from .. import execute, law
from .._kernels import codes, layout
from .._kernels.cycles import MAX_CYCLES
from .graze import _slip_root
from .hopf import N_SAMPLES, _fit_root
from .point import ABSENT, FAILED, INCONSISTENT, LOCATED, _Point

MAX_ROUNDS = 60
RESOLVED = (codes.OK, codes.UNRESOLVED)   # a cycle found (unresolved: next to the Hopf
                                         # point, its numbers only estimates)
MAX_OFFSET = 0.05       # widest relative spacing of the Hopf samples


def _empty() -> dict:
    return {"v_hopf_subcritical": math.nan, "v_hopf_subcritical_error": math.nan,
            "subcritical_status": ABSENT, "v_fold": math.nan, "v_fold_width": math.nan,
            "fold_status": ABSENT}


def unstable_cycles(pt: _Point, values, o: np.ndarray) -> np.ndarray:
    """Observables (len(values), NOBS) of the largest unstable slip cycle
    (Floquet multiplier > 1) at each value of ``along``; NaN rows where none (its
    status ``unresolved`` where the scan could not verify it to ``tol``)."""
    values = np.atleast_1d(np.asarray(values, np.float64))
    P = np.array([pt.at(u) for u in values])
    out = np.empty((len(values), MAX_CYCLES, layout.NOBS))
    found = np.zeros(len(values), np.int64)
    execute.cycles(P, pt.laws, o, out, found, parallel=False)
    rows = np.full((len(values), layout.NOBS), np.nan)
    for i in range(len(values)):
        cyc = out[i, :found[i]]
        ok = np.isin(cyc[:, layout.OB_STATUS], RESOLVED) & \
            (cyc[:, layout.OB_FLOQUET] > 1.0)
        if ok.any():
            rows[i] = cyc[ok][-1]         # increasing amplitude: the largest
    return rows


def _exists(rows) -> np.ndarray:
    return np.isfinite(rows[:, layout.OB_AMPLITUDE])


def _noise(pt, pts, root, o) -> float:
    """The move of the root under errors of 2 tol L in xdot_max (the cycles'
    accuracy, L = r_y/k + |v|/omega): 2 tol L / |dg/du|, the slope from the two
    values nearest the root."""
    (u1, g1), (u2, g2) = sorted(pts, key=lambda q: abs(q[0] - root))[:2]
    slope = abs((g1 - g2) / (u1 - u2))
    return 2.0 * float(o[layout.O_RTOL]) * float(pt.length_scale(root)) / slope \
        if slope > 0.0 else math.inf


def _fold(pt, ue, un, xtol, o, known):
    """The fold between ``ue`` (unstable cycle exists) and ``un`` (absent):
    ``dict(value, width, status)``. ``known``: (value, row) already computed."""
    s = math.copysign(1.0, un - ue)
    pts = [(u, pt.speed(u) - r[layout.OB_XDOT_MAX]) for u, r in known]
    if not all(g > 0.0 for _u, g in pts):
        return {"value": math.nan, "width": abs(un - ue), "status": INCONSISTENT}
    root, unc = None, math.inf
    for _round in range(MAX_ROUNDS):
        root, unc = _slip_root(pts, un)
        inside = root is not None and (root - ue) * s > 0.0 and (un - root) * s > 0.0
        if inside and unc <= xtol:
            return {"value": root, "width": unc + _noise(pt, pts, root, o),
                    "status": LOCATED}
        if abs(un - ue) <= xtol:
            break
        if inside:      # approach the predicted root from the cycle's side
            u = ue + 0.7 * (root - ue)
            if abs(root - u) < 1e-7 * abs(root):
                u = 0.5 * (ue + un)
        else:
            u = 0.5 * (ue + un)
        row = unstable_cycles(pt, u, o)[0]
        if np.isfinite(row[layout.OB_AMPLITUDE]):
            ue = u
            pts.append((u, pt.speed(u) - row[layout.OB_XDOT_MAX]))
        else:
            un = u
    if root is not None and abs(un - ue) <= xtol:
        return {"value": 0.5 * (ue + un), "width": abs(un - ue), "status": LOCATED}
    return {"value": math.nan, "width": abs(un - ue), "status": FAILED}


def _subcritical_hopf(pt, ue, un, offset, o):
    """The subcritical Hopf point between ``ue`` (unstable cycle exists) and ``un``
    (absent, equilibrium unstable): ``dict(value, error, status)``."""
    side = math.copysign(1.0, ue - un)
    # existence down to the samples' spacing
    for _ in range(MAX_ROUNDS):
        if abs(ue - un) <= offset * abs(un):
            break
        u = 0.5 * (ue + un)
        if np.isfinite(unstable_cycles(pt, u, o)[0, layout.OB_AMPLITUDE]):
            ue = u
        else:
            un = u
    r = 0.5 * (ue + un)
    for _round in range(8):
        us = r * (1.0 + side * offset * np.arange(1, N_SAMPLES + 1))
        check = r * (1.0 - side * offset)
        rows = unstable_cycles(pt, np.r_[us, check], o)
        have = _exists(rows)
        if not have[:N_SAMPLES].all() or have[N_SAMPLES]:
            r = us[0] if not have[0] else check       # move towards the change
            continue
        if np.any(rows[:N_SAMPLES, layout.OB_STATUS] != codes.OK) and \
                offset < MAX_OFFSET:
            offset = min(MAX_OFFSET, 2.0 * offset)    # too close to be resolved
            continue
        a2 = rows[:N_SAMPLES, layout.OB_AMPLITUDE] ** 2
        w = pt.fit_variable(us)
        wc = float(pt.fit_variable(check))
        near = _fit_root(w[:4], a2[:4], float(w[0]), wc)
        far = _fit_root(w[1:], a2[1:], float(w[0]), wc)
        if not np.isfinite(near):
            break
        root = math.sqrt(near) if pt.along == "v" else near
        err = abs(root - (math.sqrt(far) if pt.along == "v" else far)) \
            if np.isfinite(far) else math.inf
        if abs(root - r) <= 0.3 * offset * abs(r):
            return {"value": root, "error": err, "status": LOCATED}
        r = root
    return {"value": math.nan, "error": math.nan, "status": INCONSISTENT}


def may_coexist(pt: _Point) -> bool:
    """Whether the Hopf point v* of the point's law is subcritical or degenerate
    (first Lyapunov coefficient >= 0): where an unstable slip cycle is searched."""
    l1 = float(law.derived("first_lyapunov", pt.source(pt.row[pt.col])))
    return l1 >= 0.0


def cycle_boundaries(pt: _Point, values: np.ndarray, xtol: float, offset: float,
                     o: np.ndarray) -> dict:
    """Both ends of the unstable slip cycle inside ``values`` (a coarse scan): keys
    of :func:`_empty`. An end where the equilibrium is unstable on the cycle-free
    side is a subcritical Hopf point; an end where it stays stable, a fold at
    grazing. The first of each along ``values`` is kept."""
    res = _empty()
    if not may_coexist(pt):
        return res
    rows = unstable_cycles(pt, values, o)
    have = _exists(rows)
    for j in range(len(values) - 1):
        if have[j] == have[j + 1]:
            continue
        je, jn = (j, j + 1) if have[j] else (j + 1, j)
        ue, un = float(values[je]), float(values[jn])
        q = float(law.derived("q", pt.source(un)))
        if q > 0.0 and res["subcritical_status"] == ABSENT:
            h = _subcritical_hopf(pt, ue, un, offset, o)
            res.update(v_hopf_subcritical=h["value"],
                       v_hopf_subcritical_error=h["error"],
                       subcritical_status=h["status"])
        elif q <= 0.0 and res["fold_status"] == ABSENT:
            known = [(float(values[i]), rows[i]) for i in (je, je - (jn - je))
                     if 0 <= i < len(values) and have[i]]
            f = _fold(pt, ue, un, xtol, o, known)
            res.update(v_fold=f["value"], v_fold_width=f["width"],
                       fold_status=f["status"])
    return res
