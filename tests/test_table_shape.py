"""The shape of a measured table's representation, and what it implies for a sweep.

What is proven:
* monotone samples give a monotone representation (numpy and kernels), on random
  tables of random spacing; a Stribeck curve's samples too, within ``deviation`` of
  the curve; a step does not overshoot, and its ``deviation`` says it is unresolved;
* on random non-monotone tables a piece leaves the range of its two samples only
  next to a turn of the samples, convex there (concave at a maximum) and no deeper
  than a convex curve can go; turns next to each other (noise) are flattened;
* a smooth minimum between samples is kept: a cubic friction curve is reproduced to
  rounding (it was 9.4e-4 kN off at its minimum, 8.6e-3 kN on its last piece) with
  its Hopf speed where F' = 0, and a Stribeck minimum lies within ``deviation``;
* past the table a runout no wider than the last piece moves the force by at most
  the last piece's change, then it is held (F' = 0), never changing sign;
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


def _turns(f):
    """+1 at a minimum of the samples, -1 at a maximum, 0 elsewhere."""
    sg = np.sign(np.diff(f))
    kind = np.zeros(f.size)
    kind[1:-1] = np.where(sg[:-1] * sg[1:] < 0.0, sg[1:], 0.0)
    return kind


@pytest.mark.parametrize("seed", range(6))
def test_a_piece_leaves_its_samples_range_only_at_a_turn_and_convex_there(seed):
    """Random non-monotone tables: every piece stays between its two samples, but
    where the samples turn (a local extremum) and the representation keeps the
    turn's own extremum between them; there the piece is convex at a minimum
    (concave at a maximum: a single extremum, no wiggle), and no deeper than the
    step into the turn allows a convex curve, ``|f_(i-1) - f_i| h_i/h_(i-1)``."""
    rng = np.random.default_rng(100 + seed)
    s, f = random_table(rng, int(rng.integers(6, 30)), monotone=False)
    law = TableLaw(s, f)
    kind = _turns(f)
    t = np.linspace(0.0, 1.0, 257)
    left_turns = 0
    for i in range(s.size - 1):
        F = law.force(s[i] + (s[i + 1] - s[i]) * t, phase=1.0)
        lo, hi = min(f[i], f[i + 1]), max(f[i], f[i + 1])
        out = max(F.max() - hi, lo - F.min())
        if out <= 1e-14:
            continue
        left_turns += 1
        j = i if kind[i] != 0.0 else i + 1             # the turn this piece is next to
        assert kind[j] != 0.0, (i, out)
        assert np.all(kind[j] * np.diff(F, 2) >= -1e-13), i           # convex/concave
        other = j - 1 if j == i + 1 else j + 1                        # the other side
        h_in, h_out = abs(s[j] - s[other]), s[i + 1] - s[i]
        assert out <= abs(f[other] - f[j]) * h_out / h_in + 1e-14, i
    assert left_turns < s.size - 1


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


@pytest.mark.parametrize("f", [[1.0, 0.6, 0.3, 0.2, 0.21, 0.2, 0.3, 0.6, 1.0],
                               [1.0, 0.7, 0.45, 0.3, 0.24, 0.25, 0.24, 0.3, 0.45]])
def test_noise_turns_are_flattened_not_amplified(f):
    """Turns of the samples next to each other (noise of 0.01 kN at the bottom of a
    curve) are no smooth extremum (the data's second differences disagree in sign
    there): flattened onto the samples, no piece leaves its two samples' range
    (keeping them overshot by 1.6e-3 and 9.3e-4 kN)."""
    s, f = np.arange(9.0), np.array(f)
    law = TableLaw(s, f)
    t = np.linspace(0.0, 1.0, 513)
    for i in range(s.size - 1):
        F = law.force(s[i] + t, phase=1.0)
        assert F.min() >= min(f[i], f[i + 1]) - 1e-15, i
        assert F.max() <= max(f[i], f[i + 1]) + 1e-15, i


def test_a_smooth_minimum_between_samples_is_kept():
    """The curve 1 - 0.2 s + 0.03 s^2 - 0.001 s^3 (kN, s in cm/s) at 17 speeds on
    [0, 8]: its minimum lies between samples, at ``10 - 10/sqrt(3) = 4.2265`` cm/s.
    Flattening the turn onto the sample at 4 put the representation 9.4e-4 kN off
    there, and the flat end condition 8.6e-3 kN off on the last piece; the spline
    reproduces a cubic (slopes and curvatures of the seven-point polynomials are
    exact), so the representation is the curve to rounding, the kernels' too, and
    ``deviation`` says so. With c = 0 the Hopf speed is where F' = 0: the minimum."""
    cubic = lambda s: 1.0 - 0.2 * s + 0.03 * s ** 2 - 0.001 * s ** 3   # noqa: E731
    s = np.linspace(0.0, 8.0, 17)
    law = TableLaw(s, cubic(s))
    u = np.linspace(0.0, 8.0, 40001)
    assert np.abs(law.force(u, phase=1.0) - cubic(u)).max() <= 1e-14
    assert np.abs(kernel_force(law, u[1::97]) - cubic(u[1::97])).max() <= 1e-14
    assert law.deviation <= 1e-14
    p = sc.Params(m=1.0, k=1.0, c=0.0, v=1.0, law=law)
    assert p.v_star == pytest.approx(10.0 - 10.0 / np.sqrt(3.0), abs=1e-12)
    assert p.criticality == "subcritical"                   # F''' = -0.006 < 0


def test_a_stribeck_minimum_is_represented_within_its_deviation():
    """Velocity weakening turning to strengthening: ``0.5 + 0.5 exp(-s/0.5) + 0.05 s``
    at 25 speeds on [0, 6], minimum at ``0.5 ln 20 = 1.4979`` cm/s (between samples).
    The representation stays within ``deviation`` of the curve, and its minimum
    (the Hopf speed at c = 0) within 1e-3 cm/s of the curve's; the flattened turn
    put it on the sample at 1.5 and the force 0.0030 kN off."""
    curve = lambda s: 0.5 + 0.5 * np.exp(-s / 0.5) + 0.05 * s    # noqa: E731
    s = np.linspace(0.0, 6.0, 25)
    law = TableLaw(s, curve(s))
    u = np.linspace(0.0, 6.0, 60001)
    err = np.abs(law.force(u, phase=1.0) - curve(u)).max()
    assert err <= law.deviation <= 1e-3
    p = sc.Params(m=1.0, k=1.0, c=0.0, v=1.0, law=law)
    assert p.v_star == pytest.approx(0.5 * np.log(20.0), abs=1e-3)


def test_a_stribeck_table_stays_monotone_and_a_step_says_it_is_unresolved():
    """A monotone Stribeck curve (13 samples of ``0.5 + 0.5 exp(-s/0.5)``): monotone,
    between its end samples, within ``deviation`` of the curve. A step: no
    overshoot, and ``deviation`` at least a tenth of the step (where it lies
    between the samples 2 and 3 they do not say)."""
    curve = lambda s: 0.5 + 0.5 * np.exp(-s / 0.5)      # noqa: E731
    s = np.linspace(0.0, 4.0, 13)
    law = TableLaw(s, curve(s))
    u = np.linspace(0.0, 4.0, 40001)
    F = law.force(u, phase=1.0)
    assert np.all(np.diff(F) <= 1e-15) and F.min() >= curve(4.0) and F.max() <= 1.0
    assert np.abs(F - curve(u)).max() <= law.deviation <= 1e-3
    step = TableLaw([0, 1, 2, 3, 4, 5], [1, 1, 1, 0, 0, 0])
    F = step.force(dense(step.speed, 256), phase=1.0)
    assert F.min() >= 0.0 and F.max() <= 1.0 and np.all(np.diff(F) <= 1e-15)
    assert step.deviation >= 0.1


@pytest.mark.parametrize("odd", [True, False])
def test_past_the_table_a_runout_then_a_held_force(odd):
    """Past the last sample the slope decays to 0 over a runout no wider than the
    last piece, moving the force monotonically by at most the last piece's change,
    then that force is held (F' = 0), numpy and kernels alike; the table's span
    stays the samples'."""
    law = TableLaw(README_SPEED, README_FORCE) if odd else TableLaw(
        np.r_[-README_SPEED[::-1] * 2.0, README_SPEED],
        np.r_[-README_FORCE[::-1] * 0.8, README_FORCE])
    run = np.linspace(4.0, 6.0, 201)                       # the last piece: 2 cm/s
    F = law.force(run)
    held = F[-1]
    assert np.all(np.diff(F) <= 1e-15) and 0.49 - 1e-15 <= held <= 0.5
    far = np.array([6.0, 10.0, 1e3])
    np.testing.assert_allclose(law.force(far), held, rtol=0, atol=1e-15)
    np.testing.assert_allclose(kernel_force(law, np.r_[run, far]),
                               np.r_[F, np.full(far.size, held)], rtol=0, atol=1e-14)
    back = -np.array([12.0, 16.0, 8e3]) if not odd else -far
    want = -0.4 if not odd else -0.5
    G = law.force(back)
    assert np.all(G == G[0]) and want <= G[0] <= want + 0.01 * (0.8 if not odd else 1.0)
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
