"""No excitation: the autonomous belt, on the autonomous attractor kernel exactly as
without an excitation table."""
import numpy as np

from .._kernels import layout

NAME = "none"


def run(P: np.ndarray, laws, loads, o: np.ndarray, out: np.ndarray, parallel: bool) -> None:
    """The attractor of every row into the forced layout's first ``NOBS`` columns
    (``sweepcore.execute.attractors``); the forced-only columns NaN."""
    from .. import execute
    sub = np.empty((P.shape[0], layout.NOBS))
    execute.attractors(P, laws, o, sub, parallel)
    out[:, :layout.NOBS] = sub
    out[:, layout.NOBS:] = np.nan
