"""A periodic load on the slider and a harmonic motion of the anchor.

    m x'' + c (x' - y') + k (x - y) + F(x' - v) = F0 p(Omega t + phi),
    y = Y0 cos(Omega t),

with the load's shape over one period a trigonometric polynomial of the data
(``Periodic.cos``, ``Periodic.sin``: a_n, b_n per unit load, n = 1 .. N; one cosine,
``a = (1,)``, is the harmonic load of Hong & Liu, J. Sound Vib. 229 (2000)
1171-1192). The anchor's motion enters the slider's equation as the force
``k y + c y'`` at n = 1, so the kernels see the one force of ``trig.py``,

    e(t) = sum_n alpha_n cos(n Omega t) + beta_n sin(n Omega t),
    alpha_n = F0 (a_n cos(n phi) + b_n sin(n phi)) + [n = 1] k Y0,
    beta_n  = F0 (b_n cos(n phi) - a_n sin(n phi)) - [n = 1] c Omega Y0,

and the positions the kernels report are the slider's (absolute) x. The shape is
data (a new shape compiles nothing); the columns F0 [kN], OMEGA [rad/s], PHI [rad],
Y0 [cm] of the parameter row are read here only.
"""
import math
from collections import namedtuple

import numpy as np

from ..jit import kernel, unowned
from ..layout import C, F0, K, OMEGA, PHI, Y0
from ..trig import XC_HEAD, XC_N
from ..trig import work_size as trig_work

Periodic = namedtuple("Periodic", ("cos", "sin", "xc"))


def sample():
    """Data of the kind (for the type a second compiler names)."""
    return Periodic(np.ones(1), np.zeros(1), np.zeros(0))


# (the Python side's PeriodicLoad.data() gives writable copies: one numba type)


@kernel(inline="always")
def work_size(fx):
    return trig_work(fx.cos.shape[0])


@kernel(inline="always")
def with_work(fx, work):
    return Periodic(unowned(fx.cos), unowned(fx.sin), unowned(work))


@kernel(inline="always")
def coefficients(fx, p):
    _coefficients(fx.cos, fx.sin, fx.xc, p)


@kernel
def _coefficients(cos, sin, xc, p):
    """alpha_n, beta_n of the point p (module docstring) into xc."""
    n_h = cos.shape[0]
    xc[XC_N] = n_h
    f0 = p[F0]
    phi = p[PHI]
    for i in range(n_h):
        a = cos[i]
        b = sin[i]
        cn = math.cos((i + 1) * phi)
        sn = math.sin((i + 1) * phi)
        xc[XC_HEAD + i] = f0 * (a * cn + b * sn)
        xc[XC_HEAD + n_h + i] = f0 * (b * cn - a * sn)
    xc[XC_HEAD] += p[K] * p[Y0]
    xc[XC_HEAD + n_h] -= p[C] * p[OMEGA] * p[Y0]
