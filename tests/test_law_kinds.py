"""Every law kind, checked against its own force by one shared test.

The kernels learn a law only through its primitives (``sweepcore/_kernels/law.py``):
the force, its first three derivatives, the static limits and a lower bound of the
slope. Nothing else ties them together, so a kind whose F''' has the wrong sign runs
and reads the Hopf point's criticality backwards. Each test below takes every row of
the kernels' law table (``sweepcore._kernels.laws.LAWS``) and of the Python law table
(``sweepcore.laws.LAWS``), on random parameters or data of that kind, and proves:

* F', F'' and F''' (``derivatives``) are the finite differences of ``force``, at
  both slide signs (central differences at steps h and h/2, extrapolated to O(h^4);
  a point where the two steps disagree by more than ``FD_AGREE`` of the order's
  scale -- a breakpoint of a table inside the stencil -- is skipped, and at most
  one point in five may be);
* the static limits hold at least the force at 0+ and 0- (``r_pos >= F(0+)``,
  ``r_neg >= -F(0-)``);
* ``slope_bound`` is a lower bound of the sampled F' on random intervals;
* the Python side's force, static limits and slope scale match the kernels'.

A new kind fails :func:`test_every_kind_has_a_maker` until ``MAKERS`` below makes
random laws of it; then every check runs on it.
"""
import math

import numpy as np
import pytest
from numba import njit

import sweepcore as sc
from sweepcore import laws
from sweepcore._kernels import law as interface
from sweepcore._kernels import laws as kernel_laws
from sweepcore._kernels import layout
from sweepcore.laws import analytic

N_LAWS = 4              # random laws of each Python class
N_SPEEDS = 24           # random relative speeds per law and sign
FD_AGREE = 1e-3         # relative agreement of the step h and h/2 differences
EPS = np.finfo(np.float64).eps
MATCH = 1e-5            # |kernel - finite difference| / scale of that order


# ------------------------------------------------------------- the kernels
@njit(cache=False)
def _force(p, lw, zd, s):
    return interface.force(lw, interface.constants(p, lw, s), zd, s)


@njit(cache=False)
def _derivatives(p, lw, zd):
    return interface.derivatives(p, lw, zd)


@njit(cache=False)
def _static_limits(p, lw):
    return interface.static_limits(p, lw)


@njit(cache=False)
def _slope_bound(p, lw, lo, hi):
    return interface.slope_bound(p, lw, lo, hi)


# ------------------------------------------------ random laws of every class
def _analytic(rng):
    """Rows of the analytic family: half without a Stribeck term (polynomial)."""
    n = 2 * N_LAWS
    r_y = rng.uniform(0.5, 2.0, n)
    r_k = np.where(np.arange(n) % 2 == 0, r_y, r_y * rng.uniform(0.2, 0.9, n))
    grid = sc.Grid(m=1.0, k=1.0, c=0.1, mode="points", r_y=r_y, r_k=r_k,
                   v_s=rng.uniform(0.1, 1.0, n), alpha1=rng.uniform(0.0, 1.0, n),
                   alpha2=rng.uniform(1e-3, 0.1, n), v=rng.uniform(0.5, 3.0, n))
    P = grid.rows(0, n)
    values = {name: P[:, col] for name, col in analytic.COLUMNS.items()}
    return [(analytic.ANALYTIC, P[i:i + 1],
             lambda z, ph=None, i=i: analytic.force(
                 z, values, lambda src, name: src[name][i], ph))
            for i in range(n)]


def _table(rng):
    """Measured tables, decreasing in |s|: odd ones with stiction, asymmetric ones
    with a negative branch of their own."""
    out = []
    for i in range(N_LAWS):
        speed = np.concatenate([[0.0], np.cumsum(rng.uniform(0.1, 1.0, 6))])
        force = np.sort(rng.uniform(0.4, 1.0, 7))[::-1] * rng.uniform(0.5, 2.0)
        static = None
        if i % 2:
            neg_speed = -np.cumsum(rng.uniform(0.1, 1.0, 5))[::-1]
            neg_force = -np.sort(rng.uniform(0.3, 1.2, 6))      # |F| largest at 0-
            speed = np.concatenate([neg_speed, [0.0], speed])
            force = np.concatenate([neg_force, force])
        else:
            static = float(force.max()) * rng.uniform(1.0, 1.5)
        out.append(sc.TableLaw(speed, force, static=static, name=f"t{i}"))
    return [(law, _object_row(law), law.force) for law in out]


def _leine(rng):
    out = [sc.LeineLaw(f_s=rng.uniform(0.3, 3.0), delta=rng.uniform(0.3, 5.0))
           for _ in range(N_LAWS)]
    return [(law, _object_row(law), law.force) for law in out]


def _object_row(law):
    return sc.Grid(m=1.0, k=1.0, c=0.1, v=1.0, law=law).rows(0, 1)


# Python law class -> random laws of it: [(law, one kernel row, numpy force)]
MAKERS = {analytic.AnalyticLaw: _analytic, sc.TableLaw: _table, sc.LeineLaw: _leine}


def _cases():
    """``[(kind name, law, row, law data, numpy force)]`` over every maker."""
    rng = np.random.default_rng(36)
    out = []
    for cls, make in MAKERS.items():
        for law, P, numpy_force in make(rng):
            for kind, rows, lw in law.kernel_groups(P):
                for i in rows:
                    out.append((kernel_laws.LAWS[kind][0], law, np.ascontiguousarray(
                        P[i]), lw, numpy_force))
    return out


CASES = _cases()
KINDS = [row[0] for row in kernel_laws.LAWS]


def _of(kind):
    return [c for c in CASES if c[0] == kind]


def test_every_kind_has_a_maker():
    """Every class of the Python law table has random laws here, and together they
    run every kind of the kernels' law table."""
    assert set(MAKERS) == {cls for cls, _kinds in laws.LAWS}
    assert {c[0] for c in CASES} == set(KINDS)


def _speeds(rng, sign):
    """Relative speeds of one sign, log-uniform over 0.02 ... 8 cm/s."""
    return sign * np.exp(rng.uniform(math.log(0.02), math.log(8.0), N_SPEEDS))


def _differences(f, z, h):
    """Central differences of f at z: (F', F'', F''') to O(h^2)."""
    f2m, fm, f0, fp, f2p = (f(z + j * h) for j in (-2, -1, 0, 1, 2))
    return ((fp - fm) / (2 * h), (fp - 2 * f0 + fm) / (h * h),
            (f2p - 2 * fp + 2 * fm - f2m) / (2 * h ** 3))


@pytest.mark.parametrize("kind", KINDS)
def test_derivatives_are_the_forces_finite_differences(kind):
    """F', F'' and F''' of ``derivatives`` against central differences of ``force``
    on the same slide (sign s = sign of zd), at both signs: agreement to
    ``MATCH`` of the order's scale (its largest |value| over the law's samples)
    wherever the differences at h and h/2 agree to ``FD_AGREE``."""
    rng = np.random.default_rng(3)
    checked = skipped = 0
    for _kind, law, p, lw, _nf in _of(kind):
        for sign in (1.0, -1.0):
            zs = _speeds(rng, sign)
            exact = np.array([_derivatives(p, lw, z) for z in zs])
            scale = np.abs(exact).max(axis=0) + 1e-12
            for z, want in zip(zs, exact):
                h = min(abs(z) / 8.0, 1e-2)
                f = lambda u: _force(p, lw, u, sign)
                coarse = np.array(_differences(f, z, h))
                fine = np.array(_differences(f, z, h / 2.0))
                finer = np.array(_differences(f, z, h / 4.0))
                # Richardson: the O(h^2) terms cancel. Two such estimates that
                # disagree mean a breakpoint inside the stencil (a table's F''' jumps
                # at its samples), where differences say nothing about the law
                r1 = (4.0 * fine - coarse) / 3.0
                r2 = (4.0 * finer - fine) / 3.0
                if np.any(np.abs(coarse - fine) > FD_AGREE * scale) or \
                        np.any(np.abs(r1 - r2) > 0.25 * MATCH * scale):
                    skipped += 1
                    continue
                checked += 1
                err = np.abs(r2 - want) / scale
                assert np.all(err < MATCH), (
                    f"{kind} {law!r} at zd={z!r}: derivatives {tuple(want)} against "
                    f"finite differences {tuple(fine)}")
    assert checked > 4 * skipped and checked > 0


@pytest.mark.parametrize("kind", KINDS)
def test_static_limits_hold_the_force_at_zero(kind):
    """``r_pos >= F(0+)`` and ``r_neg >= -F(0-)``, and the limits are the force's
    one-sided limits at zero or above (stiction); F(0+) is the limit of F(s), s -> 0+."""
    for _kind, law, p, lw, _nf in _of(kind):
        r_pos, r_neg = _static_limits(p, lw)
        f0p, f0n = _force(p, lw, 0.0, 1.0), _force(p, lw, 0.0, -1.0)
        # to rounding: a table's spline gives its end sample back to ~10 ulp
        ulps = 64 * EPS * max(1.0, r_pos, r_neg)
        assert r_pos >= f0p - ulps and r_neg >= -f0n - ulps, (
            kind, law, r_pos, r_neg, f0p, f0n)
        tiny = 1e-9
        assert abs(_force(p, lw, tiny, 1.0) - f0p) < 1e-6 * max(1.0, abs(f0p))
        assert abs(_force(p, lw, -tiny, -1.0) - f0n) < 1e-6 * max(1.0, abs(f0n))
        assert f0p >= 0.0 >= f0n     # friction opposes the relative motion


@pytest.mark.parametrize("kind", KINDS)
def test_slope_bound_is_below_every_sampled_slope(kind):
    """``slope_bound(lo, hi)`` <= F'(s) at 64 samples of random intervals [lo, hi],
    of one sign or spanning zero (F' of ``derivatives``, checked above)."""
    rng = np.random.default_rng(5)
    for _kind, law, p, lw, _nf in _of(kind):
        for _ in range(8):
            lo, hi = np.sort(rng.uniform(-6.0, 6.0, 2))
            bound = _slope_bound(p, lw, lo, hi)
            s = np.linspace(lo, hi, 64)
            s = s[s != 0.0]
            slopes = np.array([_derivatives(p, lw, z)[0] for z in s])
            assert bound <= slopes.min() + 1e-12 * max(1.0, abs(slopes.min())), (
                kind, law, lo, hi, bound, slopes.min())


@pytest.mark.parametrize("kind", KINDS)
def test_python_side_matches_the_kernels(kind):
    """The numpy force (plots, a table's deviation) is the kernels' force to
    rounding, the Python static limits are the kernels', and the slope scale
    (the resolvable-magnitude rule) is at least half of the largest |F'| at
    relative speeds up to the belt's."""
    rng = np.random.default_rng(7)
    for _kind, law, p, lw, numpy_force in _of(kind):
        for sign in (1.0, -1.0):
            zs = _speeds(rng, sign)
            kern = np.array([_force(p, lw, z, sign) for z in zs])
            np.testing.assert_allclose(numpy_force(zs), kern, rtol=1e-12, atol=1e-12)
        if law is not analytic.ANALYTIC:
            assert tuple(law.static_limits()) == tuple(_static_limits(p, lw))
        v = abs(p[layout.V])
        s = np.linspace(-v, v, 201)
        s = s[s != 0.0]
        slopes = np.abs([_derivatives(p, lw, z)[0] for z in s])
        assert 2.0 * law.slope_scale(p[None, :])[0] >= slopes.max(), (kind, law)
