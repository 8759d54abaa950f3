"""The shape of a measured table's representation, and what it implies for a sweep.

What is proven:
* monotone samples give a monotone representation (numpy and kernels), on random
  tables of random spacing;
* no piece leaves the range of its two samples (no new extremum; the bound
  ``deviation`` records is rounding), on random non-monotone tables;
* past the table the last sample's force is held (F' = 0), never changing sign;
* the README's measured table gives no unbounded, diverged or failed point at any
  belt speed 0.2 .. 3.9 cm/s, and a point whose motion leaves the table says so;
* an asymmetric table that is the mirror image of an odd one gives the odd one's
  labels and answers for the same motion.

The table's step bound at its knots (where F''' jumps) is proven against scipy in
test_table_law.py (the unstable slip cycle: 1.1e-6 off at tol 1e-8 without it).
"""
import numpy as np
import pytest

import sweepcore as sc
from sweepcore.law import evaluate
from sweepcore.laws import TableLaw

README_SPEED = np.array([0.0, 0.1, 0.25, 0.5, 1.0, 2.0, 4.0])
README_FORCE = np.array([1.0, 0.93, 0.82, 0.68, 0.55, 0.51, 0.50])


def random_table(rng, n, monotone):
    s = np.concatenate([[0.0], np.cumsum(rng.uniform(0.01, 1.0, n - 1))])
    if monotone:                    # decreasing, with flat stretches
        f = 0.3 + np.sort(rng.uniform(0.0, 1.0, n))[::-1]
        for i in np.flatnonzero(rng.uniform(size=n) < 0.2):
            f[i] = f[i - 1] if i else f[i]
    else:
        f = rng.uniform(0.05, 1.0, n)
    return s, f


def dense(s, per=64):
    """``per`` points in every piece, its ends included."""
    t = np.linspace(0.0, 1.0, per + 1)
    return np.unique((s[:-1, None] + np.diff(s)[:, None] * t).ravel())


def kernel_force(law, u):
    """F(u) at relative speeds u > 0 by the kernels: steady sliding at belt speed
    -u rests at ``x_eq = -F(u)/k`` (k = 1)."""
    u = np.asarray(u, np.float64)
    return -evaluate("x_eq", 1.0, -u[u > 0.0], law=law)


@pytest.mark.parametrize("seed", range(6))
def test_monotone_samples_give_a_monotone_representation(seed):
    rng = np.random.default_rng(seed)
    s, f = random_table(rng, int(rng.integers(6, 30)), monotone=True)
    assert np.all(np.diff(f) <= 0.0)
    law = TableLaw(s, f)
    u = dense(s)
    F = law.force(u, phase=1.0)
    scale = 1e-13 * f.max()
    assert np.all(np.diff(F) <= scale), np.diff(F).max()
    K = kernel_force(law, u[1::7])
    assert np.all(np.diff(K) <= scale)
    np.testing.assert_allclose(K, F[1::7], rtol=0, atol=1e-14)


@pytest.mark.parametrize("seed", range(6))
def test_no_piece_leaves_the_range_of_its_samples(seed):
    rng = np.random.default_rng(100 + seed)
    s, f = random_table(rng, int(rng.integers(6, 30)), monotone=False)
    law = TableLaw(s, f)
    assert law.deviation <= 1e-14
    t = np.linspace(0.0, 1.0, 257)
    for i in range(s.size - 1):
        F = law.force(s[i] + (s[i + 1] - s[i]) * t, phase=1.0)
        lo, hi = min(f[i], f[i + 1]), max(f[i], f[i + 1])
        assert F.min() >= lo - 1e-14 and F.max() <= hi + 1e-14, i


def test_tables_that_swung_negative_stay_between_their_samples():
    """The quintic interpolant gave -352.8 kN at 3.647 cm/s for the first, a step
    from 1 to 0 kN swung negative."""
    law = TableLaw([0, .01, .02, 1, 2, 3, 4], [1, .5, .45, .4, .4, .4, .4])
    assert law.force(3.647) == pytest.approx(0.4, abs=1e-15)
    u = dense(law.speed, 256)
    F = law.force(u, phase=1.0)
    assert F.min() >= 0.4 - 1e-15 and F.max() <= 1.0 + 1e-15
    step = TableLaw([0, 1, 2, 3, 4, 5], [1, 1, 1, 0, 0, 0])
    F = step.force(dense(step.speed, 256), phase=1.0)
    assert F.min() >= 0.0 and F.max() <= 1.0 and np.all(np.diff(F) <= 1e-15)


@pytest.mark.parametrize("odd", [True, False])
def test_past_the_table_the_last_force_is_held(odd):
    law = TableLaw(README_SPEED, README_FORCE) if odd else TableLaw(
        np.r_[-README_SPEED[::-1] * 2.0, README_SPEED],
        np.r_[-README_FORCE[::-1] * 0.8, README_FORCE])
    far = np.array([4.0, 4.5, 5.0, 10.0, 1e3])
    np.testing.assert_allclose(law.force(far), 0.5, rtol=0, atol=1e-15)
    np.testing.assert_allclose(kernel_force(law, far), 0.5, rtol=0, atol=1e-15)
    back = -8.0 if not odd else -4.0
    want = -0.4 if not odd else -0.5
    np.testing.assert_allclose(law.force(np.array([back, 2 * back, 1e3 * back])), want,
                               rtol=0, atol=1e-15)
    p = sc.Params(m=1.0, k=1.0, c=0.0, v=-10.0, law=law)     # sliding at s = +10
    assert p.q == 0.0                                          # F' = 0 there
    lo, hi = law.speed_span()
    assert (lo, hi) == ((-4.0, 4.0) if odd else (-8.0, 4.0))


def test_the_readme_table_has_no_failed_point_at_any_belt_speed():
    """The README table swept over v = 0.2 .. 3.9 cm/s (m = k = 1, c = 0.1). The data's slope
    beyond 2 cm/s (-0.005) is damped by c: no speed is unbounded (the quintic's
    linear continuation to negative friction made 3.0 .. 3.9 unbounded)."""
    law = TableLaw(README_SPEED, README_FORCE, static=1.1, name="measured")
    v = np.round(np.arange(0.2, 3.95, 0.1), 10)
    ds = sc.sweep(sc.Grid(m=1.0, k=1.0, c=0.1, v=v, law=law), progress=False)
    regimes = dict(zip(ds.regime.attrs["flag_meanings"].split(),
                       ds.regime.attrs["flag_values"]))
    assert (ds.status.values == 0).all()                     # ok everywhere
    assert not np.isin(ds.regime.values, [regimes["unbounded"]]).any()
    rest = ds.regime.values == regimes["equilibrium"]
    assert rest[v > 2.0].all()                               # steady sliding, damped
    # the flag: xdot - v leaves [-4, 4] exactly where xdot_max/amplitude say so
    top = ds.xdot_max.values - v
    bottom = top - 2.0 * ds.velocity_amplitude.values
    np.testing.assert_array_equal(ds.beyond_table.values,
                                  ((top > 4.0) | (bottom < -4.0)).astype(np.int8))
    assert ds.beyond_table.attrs["flag_meanings"] == "within_table beyond_table"


def test_a_point_that_leaves_the_table_says_so():
    """A table that ends at 0.3 cm/s, damped (c + F' = 0.17 > 0): steady sliding at
    v = 0.2 slides at relative speed -0.2 (inside), at v = 1 at -1 (past it)."""
    law = TableLaw(np.linspace(0.0, 0.3, 7), np.linspace(1.0, 0.9, 7))
    ds = sc.sweep(sc.Grid(m=1.0, k=1.0, c=0.5, v=[0.2, 1.0], law=law), progress=False)
    assert list(ds.regime.values) == [0, 0]                   # equilibrium
    assert list(ds.beyond_table.values) == [0, 1]


def mirrored(law_speed, law_force):
    return TableLaw(np.r_[-law_speed[::-1], law_speed], np.r_[-law_force[::-1], law_force])


@pytest.mark.parametrize("seed", range(3))
def test_an_asymmetric_mirror_table_gets_the_odd_tables_labels(seed):
    """The same law given odd and as two branches: the same regime, status and
    numbers at every belt speed, both signs (the kernels' two code paths)."""
    rng = np.random.default_rng(200 + seed)
    s = np.concatenate([[0.0], np.cumsum(rng.uniform(0.1, 0.8, 7))])
    f = 0.5 + 0.5 * np.exp(-s / rng.uniform(0.2, 1.0)) + rng.uniform(-0.05, 0.05) * s
    f = np.maximum(f, 0.05)
    odd = TableLaw(s, f, name="odd")
    two = mirrored(s, f)
    v = np.array([-2.5, -0.6, 0.3, 0.6, 1.2, 2.5, 4.5])
    grid = dict(m=1.0, k=1.0, c=rng.uniform(0.0, 0.2))
    a = sc.sweep(sc.Grid(**grid, v=v, law=odd), progress=False)
    b = sc.sweep(sc.Grid(**grid, v=v, law=two), progress=False)
    np.testing.assert_array_equal(a.regime.values, b.regime.values)
    np.testing.assert_array_equal(a.status.values, b.status.values)
    L = 1.0 + np.abs(v)
    assert np.nanmax(np.abs(a.amplitude.values - b.amplitude.values) / L) <= 1e-7


def test_a_smoothed_tables_deviation_is_its_largest_residual():
    """With smoothing the representation passes near the points: ``deviation`` is
    the largest |F(s_i) - F_i| (FITPACK's criterion bounds it by sqrt(n) sigma),
    and the smoothed curve keeps the force's sign."""
    rng = np.random.default_rng(7)
    s = np.linspace(0.0, 5.0, 41)
    f = 0.6 + 0.4 * np.exp(-s) + rng.normal(0.0, 0.01, s.size)
    law = TableLaw(s, f, smoothing=0.01)
    residual = np.abs(law.force(s, phase=1.0) - f).max()
    assert law.deviation == pytest.approx(residual, rel=1e-9, abs=1e-15)
    assert 0.0 < law.deviation <= np.sqrt(s.size) * 0.01
    assert law.force(dense(s), phase=1.0).min() > 0.0
