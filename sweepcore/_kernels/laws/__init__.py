"""The law table: the kinds of friction law the kernels know, one module each.

A row is ``(name, data class, module, sample)``. The data class (a namedtuple) is the
type of the law data ``lw`` that the kernels carry beside the parameter row (the
sample: data of that type, whose numba type a second compiler can name); numba
compiles the kernels once per data class, and ``law.py``'s interface resolves each
law function to the row's module by it. A kind's per-point parameters are columns
of the row (the analytic family's); data shared by every point of a call (a measured
table) are fields of ``lw``: a new table is new data of the same type, so it
compiles nothing.

Adding a kind: its module (the primitives listed in ``law.py``), one row here, the
Python side's module under ``sweepcore/laws/`` and its row there, and tests.
"""
import numpy as np

from . import analytic, leine, table

LAWS = (
    ("polynomial", analytic.Polynomial, analytic, analytic.Polynomial()),  # eq. (40)
    ("stribeck", analytic.Stribeck, analytic, analytic.Stribeck()),  # + Stribeck term
    ("table", table.Table, table, table.Table(np.zeros(1))),  # a measured table
    ("leine", leine.Leine, leine, leine.Leine(1.0, 1.0)),     # Leine's decreasing law
)
MODULES = {row[1]: row[2] for row in LAWS}
KIND_CODES = {row[0]: i for i, row in enumerate(LAWS)}
SAMPLES = {row[0]: row[3] for row in LAWS}
