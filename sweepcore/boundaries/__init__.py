"""Regime boundaries to full precision, located and continued beyond the grid.

Along the belt speed ``v`` (or another parameter) the attractor of Liu's model
changes regime at two bifurcations of the slip cycle:

* the **Hopf point** (cycle <-> equilibrium), the root of the cycle's amplitude
  squared, extrapolated from a few cycles near it (:mod:`.hopf`);
* the **stick onset** (slip cycle <-> stick-slip), where the slip cycle grazes the
  belt, the root of ``v - xdot_max`` on the slip side (:mod:`.graze`).

Any other regime change in the bracket (e.g. the edges of the band of slip cycles
with slide-slide reversals at small alpha2, for which no smooth indicator is known)
is located by bisection on the regime labels, to ``xtol`` (:mod:`.locate`).
:func:`continue_boundary` follows the two curves along a second parameter, each
step seeded by the previous ones (:mod:`.continuation`).

The solvers are Python generators that ask for attractors and receive the kernel's
observables rows; the driver of :mod:`.drive` runs the solvers of many grid points
in lockstep, each round one batched call of the attractor kernel (numba threads, or
the serial kernel inside a dask task), so Python costs a few microseconds per
attractor. A start that does not reach an attractor within the kernel's budget is
retried once from rest on the belt; an ``unresolved`` cycle next to the Hopf point
keeps its label in the scan. :mod:`.dataset` labels the result.

Rooms: ``point`` (outcome codes, what a solver knows of its search), ``roots`` (the
bracketed root solver), ``drive``, ``hopf``, ``graze``, ``locate``,
``continuation``, ``dataset``.
"""
from .continuation import continue_boundary
from .locate import locate_boundaries, locate_chunk
from .point import ABSENT, FAILED, INCONSISTENT, LOCATED, SEARCH_NAMES
from .roots import bracketed_root

__all__ = ["locate_boundaries", "continue_boundary", "locate_chunk", "bracketed_root",
           "LOCATED", "ABSENT", "FAILED", "INCONSISTENT", "SEARCH_NAMES"]
