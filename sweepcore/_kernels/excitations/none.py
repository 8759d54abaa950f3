"""No excitation: the autonomous belt.

Its rows run on the autonomous kernels (``attractor.py``, ``cycles.py``,
``trajectory.py``), compiled exactly as without an excitation table: the forced
kernels are never compiled for it. The functions below make it a complete kind of
the interface (``excitation.py``): a load that is zero at every time.
"""
from collections import namedtuple

import numpy as np

from ..jit import kernel

Unforced = namedtuple("Unforced", ())


@kernel(inline="always")
def coefficients(ex, p):
    """``(a, b, Omega)`` of the load ``a cos(Omega t) + b sin(Omega t)``: none."""
    return 0.0, 0.0, 0.0


@kernel(inline="always")
def forcing_period(ex, p):
    """No period [s]."""
    return np.inf
