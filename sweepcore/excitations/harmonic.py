"""A harmonic load on the slider and a harmonic motion of the anchor: both enter the
slider's equation as one harmonic force (``sweepcore/_kernels/excitations/harmonic.py``),
solved by the forced kernels (``sweepcore/_kernels/forced_attractor.py``)."""
import numpy as np

from .._kernels.excitations import harmonic as _kernel

NAME = "harmonic"
DATA = _kernel.Harmonic()


def load(params, t: np.ndarray) -> np.ndarray:
    """``F0 cos(Omega t + phi) + k Y0 cos(Omega t) - c Omega Y0 sin(Omega t)`` [kN]."""
    w = params.Omega * np.asarray(t, np.float64)
    return (params.F0 * np.cos(w + params.phi) + params.k * params.Y0 * np.cos(w)
            - params.c * params.Omega * params.Y0 * np.sin(w))
