"""Slip cycles as fixed points of the return map, unstable ones included
(sweepcore/_kernels/cycles.py), against the independent scipy shooting solve of
tests/reference.py. Tolerances follow from tol = 1e-8 of the length scale L."""
import numpy as np
import pytest

import sweepcore as sc
from sweepcore._kernels import codes, layout as L
from sweepcore import compiled
from sweepcore._kernels.cycles import MAX_CYCLES
from sweepcore.options import make_options

from reference import reference_slip_cycle

BSTAB = dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.5, c=0.1, alpha1=0.0, alpha2=0.0)
FAMILY = dict(m=2.0, k=3.0, r_y=1.2, r_k=0.7, v_s=0.3, c=0.05, alpha1=0.1, alpha2=0.02)
SUPER = dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.5, c=0.02, alpha1=0.6, alpha2=0.1)


def cycles(p):
    """The cycle scan of one point, on the kernel alone (serial)."""
    out = np.empty((1, MAX_CYCLES, L.NOBS))
    found = np.zeros(1, np.int64)
    compiled.cycles(p.row(0.0, p.v)[None, :], (p.friction_law,), make_options(), out,
                    found)
    return out[0, :found[0]]


@pytest.mark.parametrize("pars, v", [(BSTAB, 1.175), (BSTAB, 1.5), (BSTAB, 1.83),
                                     (FAMILY, 1.3)])
def test_unstable_cycle_against_shooting(pars, v):
    """In the bistable band of a subcritical Hopf point the return map has one
    fixed point, unstable (multiplier > 1): the boundary between the basins."""
    p = sc.Params(**pars, v=v)
    (row,) = cycles(p)
    assert row[L.OB_STATUS] == codes.OK and row[L.OB_FLOQUET] > 1.0
    ref = reference_slip_cycle(p.m, p.k, p.r_y, v, p.alpha1, p.alpha2, row[L.OB_X_MAX],
                               c=p.c, r_k=p.r_k, v_s=p.v_s)
    scale = p.r_y / p.k + v / p.omega
    for col, name in ((L.OB_AMPLITUDE, "amplitude"), (L.OB_X_MAX, "x_max"),
                      (L.OB_X_MIN, "x_min"), (L.OB_MEAN, "mean")):
        assert abs(row[col] - ref[name]) <= 1e-7 * scale, name
    assert row[L.OB_PERIOD] == pytest.approx(ref["period"], rel=1e-7)
    assert row[L.OB_FLOQUET] == pytest.approx(ref["floquet"], rel=1e-6)


@pytest.mark.parametrize("v", [1.0, 2.0])
def test_no_slip_cycle_outside_the_bistable_band(v):
    """Below the Hopf point (1.15129) steady sliding is unstable and the motion
    sticks; above the fold (1.8366) only steady sliding is left: no slip cycle."""
    assert len(cycles(sc.Params(**BSTAB, v=v))) == 0


def test_a_stable_cycle_is_found_by_the_scan_as_well():
    """Newton does not care about stability: a supercritical law's stable slip
    cycle is the scan's fixed point too, with the attractor's observables."""
    p = sc.Params(**SUPER, v=0.99 * sc.Params(**SUPER, v=1.0).v_star)
    (row,) = cycles(p)
    a = sc.attractor(p)
    scale = p.r_y / p.k + p.v / p.omega
    assert 0.0 < row[L.OB_FLOQUET] < 1.0
    assert abs(row[L.OB_AMPLITUDE] - a.amplitude) <= 1e-7 * scale
    assert row[L.OB_FLOQUET] == pytest.approx(a.floquet, abs=1e-7)


def test_rows_kernel_equals_the_point_kernel():
    ps = [sc.Params(**BSTAB, v=v) for v in (1.0, 1.3, 1.6, 2.0)]
    P = np.array([p.row(0.0, p.v) for p in ps])
    out = np.empty((len(ps), MAX_CYCLES, L.NOBS))
    found = np.empty(len(ps), np.int64)
    compiled.cycles(P, (ps[0].friction_law,), make_options(), out, found, parallel=True)
    for i, p in enumerate(ps):
        want = cycles(p)
        assert found[i] == len(want)
        np.testing.assert_array_equal(out[i, :found[i]], want)


# ------------------------------------------------------------------ the Python API
def test_slip_cycles_dataset_is_the_kernel_labelled(tmp_path):
    """sweepcore.slip_cycles: the kernel's rows over the grid and ``cycle``, with
    units and flags (CF), written and read back unchanged."""
    vs = np.array([1.0, 1.175, 1.5, 2.0])
    g = sc.Grid(**BSTAB, v=vs)
    ds = sc.slip_cycles(g, chunks=3, path=tmp_path / "c.nc")
    assert ds.sizes == {"v": 4, "cycle": 1}
    assert list(ds.n_cycles.values) == [0, 1, 1, 0]
    for i, v in enumerate(vs):
        want = cycles(sc.Params(**BSTAB, v=v))
        for j, row in enumerate(want):
            assert ds.cycle_amplitude.values[i, j] == row[L.OB_AMPLITUDE]
            assert ds.cycle_floquet.values[i, j] == row[L.OB_FLOQUET]
            assert ds.cycle_period.values[i, j] == row[L.OB_PERIOD]
    # both cycles of the band are unstable; the unused slots say none
    assert list(ds.cycle_stability.values[:, 0]) == [-1, 1, 1, -1]
    assert ds.cycle_stability.attrs["flag_meanings"].split() == [
        "none", "stable", "unstable", "undetermined"]
    assert ds.cycle_amplitude.attrs["units"] == "cm"
    assert ds.cycle_period.attrs["units"] == "s"
    assert sc.check_cf(ds) == []
    back = sc.open_result(tmp_path / "c.nc")
    np.testing.assert_array_equal(back.cycle_floquet.values, ds.cycle_floquet.values)
    np.testing.assert_array_equal(back.cycle_stability.values,
                                  ds.cycle_stability.values)


def test_slip_cycles_refusals():
    with pytest.raises(ValueError, match="x0"):
        sc.slip_cycles(sc.Grid(**BSTAB, v=1.5, x0=np.array([0.0, 1.0])))
    with pytest.raises(ValueError, match="gps"):
        sc.slip_cycles(sc.Grid(**BSTAB, v=1.5), method="gps")
    with pytest.raises(TypeError, match="Grid"):
        sc.slip_cycles(sc.Params(**BSTAB, v=1.5))


def test_cycle_polygon_closes_on_the_cycle():
    """The polygon of the unstable cycle closes after one period (to the cycle's
    tolerance, amplified by the multiplier) and spans [x_min, x_max] of the scan;
    its maximal velocity is the scan's xdot_max."""
    from sweepcore.cycles import cycle_polygon
    p = sc.Params(**BSTAB, v=1.5)
    (row,) = cycles(p)
    x, xd, gap, ok = cycle_polygon(p.row(0.0, p.v), row, make_options(), 4000)
    assert ok and gap < 1e-6
    assert x.max() == pytest.approx(row[L.OB_X_MAX], abs=1e-12)
    assert x.min() == pytest.approx(row[L.OB_X_MIN], abs=1e-5)
    assert xd.max() == pytest.approx(row[L.OB_XDOT_MAX], abs=1e-5)
