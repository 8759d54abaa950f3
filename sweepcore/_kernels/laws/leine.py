"""Leine's decreasing friction law: ``F(s) = F_s sgn(s) / (1 + delta |s|)``.

The law of Leine & Nijmeijer's stick-slip example (R. I. Leine, D. H. van Campen,
A. de Kraker, L. van den Steen, "Stick-slip vibrations induced by alternate friction
models", Nonlinear Dynamics 16 (1998) 41-54; Leine & Nijmeijer, "Dynamics and
Bifurcations of Non-Smooth Mechanical Systems", Springer 2004): the friction force
falls from the static ``F_s`` as the relative speed grows. Its data are the two
numbers of ``Leine`` (the same type for every value: a new law compiles nothing).
Everything else (x_eq, q, the Hopf speeds, the certificate) is the interface's
generic form from these primitives.
"""
from collections import namedtuple

from ..jit import kernel
from ..layout import C

Leine = namedtuple("Leine", ("f_s", "delta"))


@kernel(inline="always")
def force(lw, cf, zd, s):
    """The sign of the slide s (of zd where s = 0), as the analytic law: the field
    of a slide stays continuous and bounded where its last stages overshoot zd = 0."""
    sg = s if s != 0.0 else (1.0 if zd > 0.0 else -1.0)
    return sg * lw.f_s / (1.0 + lw.delta * abs(zd))


@kernel(inline="always")
def derivatives(p, lw, zd):
    u = 1.0 + lw.delta * abs(zd)
    d = lw.delta
    sg = 1.0 if zd > 0.0 else -1.0
    return (-lw.f_s * d / (u * u), sg * 2.0 * lw.f_s * d * d / (u * u * u),
            -6.0 * lw.f_s * d * d * d / (u * u * u * u))


@kernel(inline="always")
def static_limits(p, lw):
    return lw.f_s, lw.f_s


@kernel(inline="always")
def slope_bound(p, lw, lo, hi):
    # F' = -F_s delta / (1 + delta |s|)^2 is least where |s| is least
    near = 0.0 if lo <= 0.0 <= hi else min(abs(lo), abs(hi))
    u = 1.0 + lw.delta * near
    return -lw.f_s * lw.delta / (u * u)


@kernel(inline="always")
def speed_range(p, lw):
    return 1e-9 / lw.delta, 1e9 / lw.delta


@kernel(inline="always")
def anti_damped(p, lw):
    """F' tends to 0 at high speed: anti-damped only for c < 0 (never: c >= 0)."""
    return p[C] < 0.0
