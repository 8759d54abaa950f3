"""Harmonic excitation: a load on the slider and a motion of the anchor.

    m x'' + c (x' - y') + k (x - y) + F(x' - v) = F0 cos(Omega t + phi),
    y = Y0 cos(Omega t)

(Hong & Liu, J. Sound Vib. 229 (2000) 1171-1192: harmonic loads and base
excitations of the Coulomb friction oscillator; the paper's eq. (4) carries the load
p(t)). The anchor's motion enters the slider's equation as the force
``k y + c y'``, so both excitations are one harmonic force on the slider,

    e(t) = F0 cos(Omega t + phi) + k Y0 cos(Omega t) - c Omega Y0 sin(Omega t)
         = a cos(Omega t) + b sin(Omega t),
    a = F0 cos(phi) + k Y0,   b = -F0 sin(phi) - c Omega Y0,

and the positions the kernels report are the slider's (absolute) x. The columns
F0 [kN], OMEGA [rad/s], PHI [rad], Y0 [cm] of the parameter row are read here only.
"""
import math
from collections import namedtuple

from ..jit import kernel
from ..layout import C, F0, K, OMEGA, PHI, Y0

Harmonic = namedtuple("Harmonic", ())


@kernel(inline="always")
def coefficients(ex, p):
    """``(a, b, Omega)``: the load on the slider is ``a cos(Omega t) + b sin(Omega t)``
    [kN], Omega [rad/s]."""
    om = p[OMEGA]
    a = p[F0] * math.cos(p[PHI]) + p[K] * p[Y0]
    b = -p[F0] * math.sin(p[PHI]) - p[C] * om * p[Y0]
    return a, b, om


@kernel(inline="always")
def forcing_period(ex, p):
    """The forcing period ``T = 2 pi / Omega`` [s]."""
    return 2.0 * math.pi / p[OMEGA]
