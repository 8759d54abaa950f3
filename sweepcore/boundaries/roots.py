"""The scalar root solver of the boundary searches."""
from __future__ import annotations

import math


def bracketed_root(f, a: float, b: float, xtol: float, maxiter: int = 200) -> float:
    """Root of ``f`` in the bracket ``[a, b]`` (``f(a) f(b) <= 0``) to ``xtol``.

    Illinois (modified regula falsi): the end that stays twice in a row has its
    value halved, so both ends move and convergence is superlinear; a step that
    does not halve the bracket within three iterations is replaced by bisection.

    Raises
    ------
    ValueError
        If ``f(a)`` and ``f(b)`` have the same sign (no bracket).
    """
    fa, fb = float(f(a)), float(f(b))
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if math.copysign(1.0, fa) == math.copysign(1.0, fb):
        raise ValueError(f"no bracket: f({a!r}) = {fa!r} and f({b!r}) = {fb!r} have "
                         "the same sign")
    kept = 0           # +1: b kept last time, -1: a kept
    widths = [abs(b - a)]
    for _ in range(maxiter):
        if abs(b - a) <= xtol:
            break
        if len(widths) >= 4 and widths[-1] > 0.5 * widths[-4]:
            c = 0.5 * (a + b)
        else:
            c = (a * fb - b * fa) / (fb - fa)
            if not min(a, b) < c < max(a, b):
                c = 0.5 * (a + b)
        fc = float(f(c))
        if fc == 0.0:
            return c
        if math.copysign(1.0, fc) == math.copysign(1.0, fb):
            b, fb = c, fc
            if kept == -1:
                fa *= 0.5
            kept = -1
        else:
            a, fa = c, fc
            if kept == 1:
                fb *= 0.5
            kept = 1
        widths.append(abs(b - a))
    return (a * fb - b * fa) / (fb - fa) if fb != fa else 0.5 * (a + b)
