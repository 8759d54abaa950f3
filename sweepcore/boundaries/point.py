"""What every boundary solver knows of its search: the outcome codes, the regime
groups, and :class:`_Point` (the fixed parameters of one search, the parameter
``along`` which it moves, and what the solvers derive from them)."""
from __future__ import annotations

import math

import numpy as np

from .. import law
from .._kernels import codes, layout
from ..grid import COLUMNS
from ..laws import ANALYTIC

# Outcome of one boundary search (codes in _kernels/codes.py, the one table)
LOCATED = codes.B_LOCATED
ABSENT = codes.B_ABSENT
FAILED = codes.B_FAILED
INCONSISTENT = codes.B_INCONSISTENT
SEARCH_NAMES = codes.SEARCH_NAMES

CYCLES = (codes.R_SLIP_CYCLE, codes.R_STICK_SLIP)
PROPER = (codes.R_EQUILIBRIUM, codes.R_SLIP_CYCLE, codes.R_STICK_SLIP,
          codes.R_NEUTRAL, codes.R_STUCK)
STUCK = math.nan        # xdot0 of a request: start stuck on the belt (xdot0 = v)


class _Point:
    """The fixed parameters of one search and what the solvers need from them."""

    def __init__(self, row: np.ndarray, along: str, tol: float | None = None,
                 laws=(ANALYTIC,)):
        self.row, self.along, self.tol, self.laws = row, along, tol, laws
        self.col = COLUMNS[along]
        self.law = laws[int(row[layout.LAW])]

    def at(self, value: float) -> np.ndarray:
        r = self.row.copy()
        r[self.col] = value
        return r

    def source(self, value: float) -> dict:
        """The parameters at ``along = value``, as a source of :mod:`sweepcore.law`."""
        return law.from_row(self.at(value), self.law)

    def x_eq(self, value: float) -> float:
        """Steady-sliding position at ``along = value`` [cm], eq. (43)."""
        return float(law.derived("x_eq", self.source(value)))

    def speed(self, value: float) -> float:
        return self.at(value)[layout.V]

    def length_scale(self, value: float) -> float:
        """The kernel's length scale L = r_y/k + |v|/omega at ``along = value`` [cm]:
        the unit of its tolerances."""
        src = self.source(value)
        omega = float(law.derived("omega", src))
        static = float(self.law.static_bound(self.at(value)[None, :])[0])
        return static / src["k"] + abs(src["v"]) / omega

    def contraction(self, value: float) -> float:
        """``|q| T`` at ``along = value`` (q of eq. 46, T = 2 pi/omega): ``1 - mu``
        of a small slip cycle there (mu its Floquet multiplier) is about this."""
        src = self.source(value)
        q = float(law.derived("q", src))
        return abs(q) * 2.0 * math.pi / float(law.derived("omega", src))

    def fit_variable(self, value):
        """The variable in which A^2 is fitted: v^2 along v (q is linear in it)."""
        return np.asarray(value) ** 2 if self.along == "v" else np.asarray(value)


def _ok(row) -> bool:
    return int(row[layout.OB_STATUS]) == codes.OK


def _regime(row) -> int:
    return int(row[layout.OB_REGIME])
