"""Closed forms of the harmonically forced friction oscillator (numpy only).

The model, in physical units (kN, cm, s, rad)::

    m x'' + c (x' - y') + k (x - y) + F(x' - v) = F0 cos(Omega t + phi),
    y = Y0 cos(Omega t),

F the friction law of the relative speed ``s = x' - v`` (Coulomb here:
``F(s) = r_k sgn(s)``, static bound ``r_y = r_k``), ``v`` the belt speed (``v = 0``:
the slider on fixed ground). Den Hartog's case (``c = 0``, ``v = 0``, ``Y0 = 0``) is
written scaled: ``tau = omega t`` with ``omega = sqrt(k/m)``, ``x`` in units of
``F0/k``, so that ``x'' + x + r sgn(x') = cos(beta tau)`` with the frequency ratio
``beta = Omega/omega`` and the friction ratio ``r = r_k/F0``. Each closed form is
given scaled (``*_scaled``) and in physical units; the derivations are in
docs/physics.md, section "Forced vibration".

Where a closed form does not apply (no continuous motion, the slider reaches the
belt) the physical functions return NaN, never a number of another motion; bad
input is refused with a ValueError naming the parameter.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["den_hartog_scaled", "den_hartog_phase_scaled",
           "den_hartog_multipliers_scaled", "continuous_motion_boundary",
           "den_hartog_amplitude", "den_hartog_multipliers", "belt_critical_load",
           "belt_linear_response", "base_equivalent_load", "neutral_family"]


def _checked(name, value, low=0.0, strict=True):
    """``value`` as a float array, refused with its name unless finite and > low
    (>= low with ``strict=False``)."""
    a = np.asarray(value, dtype=float)
    bad = ~np.isfinite(a) | ((a <= low) if strict else (a < low))
    if bad.any():
        shown = a[bad].flat[0] if a.ndim else float(a)
        raise ValueError(f"{name} must be finite and {'>' if strict else '>='} {low:g}, "
                         f"got {shown!r}")
    return a


def _v_u(beta):
    """Den Hartog's V = 1/(1 - beta^2) and U = tan(pi/(2 beta))/beta (NaN at
    beta = 1, where the motion grows without bound)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        V = np.where(beta == 1.0, np.nan, 1.0 / (1.0 - beta * beta))
    return V, np.tan(0.5 * np.pi / beta) / beta


def den_hartog_scaled(beta, r):
    """Amplitude x0 of Den Hartog's steady motion without stops of finite length.

    ``x'' + x + r sgn(x') = cos(beta tau)``: the symmetric motion of period
    ``2 pi/beta`` that reverses twice a period (two zero-duration stops) at
    ``x = -x0`` and ``x = +x0``.

    Parameters
    ----------
    beta : float or array
        Frequency ratio Omega/omega (> 0, != 1).
    r : float or array
        Friction ratio r_k/F0 (>= 0).

    Returns
    -------
    x0 : float or array
        ``sqrt(V^2 - (r U)^2)``, ``V = 1/(1 - beta^2)``, ``U = tan(pi/(2 beta))/beta``,
        in units of F0/k; NaN where the radicand is negative (no such motion). The
        motion exists as written only for ``r < continuous_motion_boundary(beta)``.

    References
    ----------
    J. P. Den Hartog, "Forced vibrations with combined viscous and Coulomb damping",
    Phil. Mag. 9(59) (1930) 801-817.
    """
    beta = _checked("beta", beta)
    r = _checked("r", r, strict=False)
    V, U = _v_u(beta)
    rad = V * V - (r * U) ** 2
    with np.errstate(invalid="ignore"):
        return np.where(rad >= 0.0, np.sqrt(np.maximum(rad, 0.0)), np.nan)[()]


def den_hartog_phase_scaled(beta, r):
    """Forcing phase psi [rad] at which Den Hartog's motion passes its minimum.

    At ``beta tau = psi`` (mod 2 pi) the slider stands at ``x = -x0`` with ``x' = 0``
    and slides on with ``x' > 0``; ``cos psi = -x0/V``, ``sin psi = r U/V``
    (docs/physics.md). NaN where ``den_hartog_scaled`` is NaN.
    """
    x0 = den_hartog_scaled(beta, r)
    V, U = _v_u(np.asarray(beta, float))
    return np.arctan2(np.asarray(r, float) * U / V, -x0 / V)[()]


def den_hartog_multipliers_scaled(beta, r):
    """Floquet multipliers of Den Hartog's motion over one forcing period.

    ``mu = lambda^2`` with ``lambda^2 - (1 + rho) cos(pi/beta) lambda + rho = 0`` and
    ``rho = (beta^2 x0 - r)/(beta^2 x0 + r)``: each half period is a rotation by
    ``pi/beta`` of the perturbation (x, x'), each reversal multiplies the velocity
    perturbation by the ratio rho of the accelerations after and before it
    (docs/physics.md derives it). ``|mu| < 1`` while ``0 < rho < 1``; at
    ``beta = 1/(2n)`` one multiplier is 1 (``neutral_family``).

    Returns
    -------
    mu : complex array, shape ``broadcast(beta, r).shape + (2,)``
        The two multipliers, largest modulus first; NaN where x0 is NaN.
    """
    x0 = den_hartog_scaled(beta, r)
    b2 = np.asarray(beta, float) ** 2
    r = np.asarray(r, float)
    rho = (b2 * x0 - r) / (b2 * x0 + r)
    half = 0.5 * (1.0 + rho) * np.cos(np.pi / np.asarray(beta, float))
    root = np.sqrt((half * half - rho).astype(complex))
    lam = np.stack([half + root, half - root], axis=-1)
    mu = lam * lam
    order = np.argsort(-np.abs(mu), axis=-1)
    return np.take_along_axis(mu, order, axis=-1)


def _kappa_sup(beta):
    """sup over 0 < u < pi/beta of kappa(u) = (sin u - t cos u + t cos(beta u))/
    (beta sin(beta u)), t = tan(pi/(2 beta)); kappa(0+) = 1/beta^2.

    Den Hartog's half period (from the minimum, x' > 0) has the velocity
    x'(u) = r (t cos u - sin u - t cos(beta u)) + beta x0 sin(beta u), positive inside
    iff x0/r > kappa(u) for every u: the motion is continuous iff x0/r > sup kappa.
    The sup is found on a grid fine against both periods (2 pi and 2 pi/beta) and
    polished by golden-section search on the best cell."""
    p = math.pi / beta
    t = math.tan(0.5 * p)

    def kappa(u):
        num = np.sin(u) - t * np.cos(u) + t * np.cos(beta * u)
        return num / (beta * np.sin(beta * u))

    n = 400 * (1 + int(p / (2 * math.pi)))
    u = np.linspace(0.0, p, n + 1)[1:-1]
    k = kappa(u)
    i = int(np.argmax(k))
    best = max(float(k[i]), 1.0 / (beta * beta))
    lo, hi = u[max(i - 1, 0)], u[min(i + 1, u.size - 1)]
    g = 0.5 * (math.sqrt(5.0) - 1.0)
    for _ in range(80):             # golden section to the cell's rounding
        a, b = hi - g * (hi - lo), lo + g * (hi - lo)
        if kappa(a) > kappa(b):
            hi = b
        else:
            lo = a
    return max(best, float(kappa(0.5 * (lo + hi))))


def continuous_motion_boundary(beta):
    """The largest friction ratio r_b = r_k/F0 with Den Hartog's continuous motion.

    Below r_b the motion has no stop of finite length (two zero-duration stops a
    period); above it, it sticks. With
    ``kappa(u) = (sin u - t cos u + t cos(beta u))/(beta sin(beta u))``,
    ``t = tan(pi/(2 beta))``, the motion is continuous while ``x0/r > sup_u kappa``
    over the half period ``0 < u < pi/beta``, so (with ``x0^2 = V^2 - (r U)^2``)

        r_b = |V| / sqrt(kappa_sup^2 + U^2).

    For ``beta >= 1/2`` the sup is ``kappa(0+) = 1/beta^2`` (the condition that the
    slider does not stick at the reversal, ``beta^2 x0 > r``):
    ``r_b = beta^2 |V| / sqrt(1 + beta^4 U^2)``, limits pi/4 at beta -> 1 and
    ``1/sqrt(1 + pi^2/4)`` as beta -> infinity. Below 1/2 the velocity first touches
    zero inside the half period and the sup is an interior maximum, found
    numerically (``_kappa_sup``).

    Parameters
    ----------
    beta : float or array
        Frequency ratio Omega/omega (> 0).

    Returns
    -------
    r_b : float or array
        Dimensionless (r_k/F0).

    References
    ----------
    L. Marino, A. Cicirello, Nonlinear Dyn. (2020), eq. 6 (the continuous-motion
    boundary); derived here from Den Hartog (1930) (docs/physics.md).
    """
    beta = _checked("beta", beta)

    def one(b):
        if b == 1.0:
            return math.pi / 4.0            # the limit: V and U both blow up
        V, U = 1.0 / (1.0 - b * b), math.tan(0.5 * math.pi / b) / b
        kap = 1.0 / (b * b) if b >= 0.5 else _kappa_sup(b)
        return abs(V) / math.sqrt(kap * kap + U * U)

    return np.vectorize(one, otypes=[float])(beta)[()]


def _den_hartog_ratios(m, k, F0, Omega, r_k):
    m, k = _checked("m", m), _checked("k", k)
    F0, Omega = _checked("F0", F0), _checked("Omega", Omega)
    r_k = _checked("r_k", r_k, strict=False)
    beta, r = Omega / np.sqrt(k / m), r_k / F0
    if np.any(beta == 1.0):
        raise ValueError("Omega must differ from sqrt(k/m) (resonance: Den Hartog's "
                         f"motion grows without bound), got {Omega!r}")
    return beta, r, np.where(r < continuous_motion_boundary(beta), 1.0, np.nan)


def den_hartog_amplitude(m, k, F0, Omega, r_k):
    """Amplitude [cm] of Den Hartog's continuous steady motion (c = 0, v = 0).

    ``X = (F0/k) x0(beta, r)``, ``beta = Omega/sqrt(k/m)``, ``r = r_k/F0`` (m [kN s^2/cm],
    k [kN/cm], F0 and r_k [kN], Omega [rad/s]); NaN where ``r`` is not below
    ``continuous_motion_boundary(beta)`` (the motion sticks: another motion).
    """
    beta, r, ok = _den_hartog_ratios(m, k, F0, Omega, r_k)
    return (np.asarray(F0, float) / np.asarray(k, float) * den_hartog_scaled(beta, r)
            * ok)[()]


def den_hartog_multipliers(m, k, F0, Omega, r_k):
    """Floquet multipliers (largest modulus first) of Den Hartog's motion over one
    forcing period 2 pi/Omega, in physical units as ``den_hartog_amplitude``;
    dimensionless, NaN where that motion does not exist."""
    beta, r, ok = _den_hartog_ratios(m, k, F0, Omega, r_k)
    return den_hartog_multipliers_scaled(beta, r) * np.asarray(ok)[..., None]


def belt_critical_load(m, k, c, v, Omega):
    """The load amplitude F0_crit [kN] below which a forced slider on a belt never
    reaches the belt speed (Coulomb friction, r_y = r_k).

    While ``x' < v`` (v > 0) the friction is the constant ``-r_k``, so the motion is
    linear and its steady state is ``r_k/k + X cos(Omega t + phi - theta)`` with
    ``X = F0/sqrt((k - m Omega^2)^2 + (c Omega)^2)``; it holds while ``Omega X < |v|``:

        F0_crit = |v| sqrt((k - m Omega^2)^2 + (c Omega)^2) / Omega.

    Parameters: m [kN s^2/cm], k [kN/cm], c [kN s/cm] (>= 0), v [cm/s] (!= 0),
    Omega [rad/s]. A base motion counts with its equivalent load
    (``base_equivalent_load``).
    """
    m, k, Omega = _checked("m", m), _checked("k", k), _checked("Omega", Omega)
    c = _checked("c", c, strict=False)
    v = np.asarray(v, float)
    if not np.all(np.isfinite(v) & (v != 0.0)):
        raise ValueError(f"v must be finite and nonzero (a belt), got {v!r}")
    return (np.abs(v) * np.hypot(k - m * Omega ** 2, c * Omega) / Omega)[()]


def belt_linear_response(m, k, c, v, r_k, F0, Omega, phi=0.0):
    """The steady response below ``belt_critical_load`` (Coulomb friction, belt v).

    Returns
    -------
    amplitude : float or array
        ``F0/sqrt((k - m Omega^2)^2 + (c Omega)^2)`` [cm]; NaN where F0 >= F0_crit
        (the slider reaches the belt: sticks appear).
    mean : float or array
        ``sgn(v) r_k/k`` [cm], the time average of x.
    lag : float or array
        ``theta = atan2(c Omega, k - m Omega^2)`` [rad]: ``x = mean + amplitude
        cos(Omega t + phi - theta)``.

    For c = 0 the free oscillation never decays: this response is one of a neutral
    family (any free oscillation may be added while the slider stays off the belt).
    """
    crit = belt_critical_load(m, k, c, v, Omega)
    F0 = _checked("F0", F0, strict=False)
    r_k = _checked("r_k", r_k, strict=False)
    den = np.hypot(k - m * Omega ** 2, c * Omega)
    amp = np.where(F0 < crit, F0 / den, np.nan)
    return (amp[()], (np.sign(v) * r_k / k)[()],
            np.arctan2(c * Omega, k - m * Omega ** 2)[()])


def base_equivalent_load(k, c, Omega, Y0, F0=0.0, phi=0.0):
    """The single load ``F0_eq cos(Omega t + phi_eq)`` [kN, rad] equivalent to a base
    motion ``y = Y0 cos(Omega t)`` [cm] plus a load ``F0 cos(Omega t + phi)``.

    The friction acts on the slider's own speed, so the base enters only through
    ``k y + c y' = Y0 sqrt(k^2 + (c Omega)^2) cos(Omega t + atan2(c Omega, k))``: the
    motion is the same for any friction law. Returns ``(F0_eq, phi_eq)``.
    """
    k, Omega = _checked("k", k), _checked("Omega", Omega)
    c = _checked("c", c, strict=False)
    Y0, F0 = np.asarray(Y0, float), np.asarray(F0, float)
    z = F0 * np.exp(1j * np.asarray(phi, float)) + Y0 * (k + 1j * c * Omega)
    return np.abs(z)[()], np.angle(z)[()]


def neutral_family(m, k, Omega, c=0.0, v=0.0, rtol=1e-9):
    """True where Den Hartog's motion is one of a neutral family.

    At ``beta = Omega/sqrt(k/m) = 1/(2n)`` (n = 1, 2, ...) with no damping (c = 0) on
    fixed ground (v = 0) and Coulomb friction, ``cos(pi/beta) = 1`` makes one
    multiplier exactly 1 (``den_hartog_multipliers_scaled``): a continuum of
    asymmetric, marginally stable motions exists (Csernak, Stepan & Shaw), so no
    amplitude is attracting. ``rtol`` is the relative distance of ``1/(2 beta)`` from
    an integer still counted as equal.

    References
    ----------
    G. Csernak, G. Stepan, S. W. Shaw, "Sub-harmonic resonant solutions of a
    harmonically excited dry friction oscillator", Nonlinear Dyn. 50 (2007) 93-109.
    """
    m, k, Omega = _checked("m", m), _checked("k", k), _checked("Omega", Omega)
    c = _checked("c", c, strict=False)
    n = 0.5 * np.sqrt(k / m) / Omega              # 1/(2 beta)
    near = (np.rint(n) >= 1) & (np.abs(n - np.rint(n)) <= rtol * n)
    return (near & (c == 0.0) & (np.asarray(v, float) == 0.0))[()]
