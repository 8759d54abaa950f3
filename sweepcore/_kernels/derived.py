"""The derived quantities of a parameter row for Python (``sweepcore.law.derived``:
Params, Grid, the results' analytic variables): omega, q, x_eq, the breakaway point,
the Hopf speeds, their criticality and the first Lyapunov coefficient, each from
the law's interface (``law.py``), one column ``D_*`` at a time."""
import math

import numpy as np

from .jit import kernel
from .law import breakaway, criticality, first_lyapunov, hopf_speeds, q, x_eq
from .layout import K, M

# columns of the derived-quantity rows (derived_rows)
D_OMEGA, D_Q, D_XEQ, D_VSTAR, D_VSTAR2, D_NHOPF, D_LYAP, D_XS, D_CRIT = range(9)


@kernel
def derived_value(p, lw, which):
    """Analytic quantity ``which`` (a column D_*) of one parameter row."""
    if which == D_OMEGA:
        return math.sqrt(p[K] / p[M])
    if which == D_Q:
        return q(p, lw)
    if which == D_XEQ:
        return x_eq(p, lw)
    if which == D_XS:
        return breakaway(p, lw)
    n, u1, u2 = hopf_speeds(p, lw)
    if which == D_VSTAR:
        return u1
    if which == D_VSTAR2:
        return u2
    if which == D_NHOPF:
        return float(n)
    if which == D_CRIT:
        return float(criticality(p, lw, n, u1))
    return first_lyapunov(p, lw, u1) if n > 0 else np.nan


@kernel(entry=True)
def derived_rows(P, lw, which, out):
    """``derived_value(P[i], lw, which)`` for every row of P into ``out[i]``."""
    for i in range(P.shape[0]):
        out[i] = derived_value(P[i], lw, which)
