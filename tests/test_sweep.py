"""The sweep engine: grids, chunked execution, invariance, resume, Hopf boundary.

Every grid point is computed independently with fastmath off, so results must agree
bit for bit (``assert_array_equal``) across chunk sizes, schedulers, worker counts and
interrupted-then-resumed runs, and with per-point calls of the serial kernel. Closed
forms are checked at 1e-12 relative (exact method: rounding only).
"""
import itertools
import math
import os
import tracemalloc

import dask
import numpy as np
import pytest

import sweepcore as sc
import importlib
sweep_mod = importlib.import_module("sweepcore.sweep")  # the package attribute is the function
from sweepcore._kernels import codes, layout
from sweepcore import compiled
from sweepcore.laws import ANALYTIC
from sweepcore.boundary import hopf_boundary
from sweepcore.grid import Grid
from sweepcore import law, resumable
from sweepcore.io import WorkingStore, open_result
from sweepcore.options import make_options
from sweepcore.sweep import sweep
from sweepcore.variables import OBSERVABLES

# independent of sweepcore.grid: the kernel row's column order (layout.py)
AXES = ("m", "k", "r_y", "v", "alpha1", "alpha2", "c", "r_k", "v_s", "x0", "xdot0")
COLUMN = {"m": layout.M, "k": layout.K, "r_y": layout.RY, "v": layout.V,
          "alpha1": layout.A1, "alpha2": layout.A2, "c": layout.C, "r_k": layout.RK,
          "v_s": layout.VS, "x0": layout.X0, "xdot0": layout.XD0}
BASE = dict(m=5.0, k=50.0, r_y=10.0, v=1.0)
# closed-form (alpha2 = 0) and integrated (alpha2 > 0) points, two starts
MIXED = dict(m=[4.0, 5.0], k=50.0, r_y=10.0, v=[0.5, 3.0, 6.0], alpha1=1.0,
             alpha2=[0.0, 0.02], x0=[0.0, 0.3])


def product_rows(**axes):
    """Kernel rows of the outer product in C order, built without sweepcore.grid."""
    full = {**dict(alpha1=0.0, alpha2=0.0, x0=0.0, xdot0=None, c=0.0, r_k=None,
                   v_s=None), **axes}
    lists = [np.atleast_1d(np.asarray(full[n], dtype=object)) for n in AXES]
    rows = []
    for combo in itertools.product(*lists):
        row = dict(zip(AXES, combo))
        if row["xdot0"] is None:
            row["xdot0"] = row["v"]
        if row["r_k"] is None:
            row["r_k"] = row["r_y"]
        if row["v_s"] is None:
            row["v_s"] = np.nan
        r = np.zeros(layout.NP)                  # the law's index (layout.LAW) 0
        r[layout.OMEGA] = np.nan                 # no excitation: F0 = Y0 = 0, no Omega
        for n in AXES:
            r[COLUMN[n]] = float(row[n])
        rows.append(r)
    return np.array(rows)


def per_point(rows, o):
    """The serial kernel called on one row at a time."""
    out = np.empty((len(rows), layout.NOBS))
    for i, row in enumerate(rows):
        compiled.attractors(np.ascontiguousarray(row[None, :]), (ANALYTIC,), o,
                            out[i:i + 1])
    return out


def assert_same_results(a, b):
    for name in list(OBSERVABLES) + ["regime", "status", "converged", "q", "v_star",
                                     "x_eq", "omega"]:
        assert a[name].dtype == b[name].dtype, name
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)


# ------------------------------------------------------------------ Grid
def test_grid_rows_are_the_outer_product_in_c_order():
    axes = dict(m=[1.0, 2.0], k=3.0, r_y=[0.0, 1.0, 2.0], v=[5.0, -1.0], x0=[0.25, 0.5],
                xdot0=None)
    grid = Grid(**axes)
    assert grid.dims == ("m", "r_y", "v", "x0")
    assert grid.shape == (2, 3, 2, 2) and grid.size == len(grid) == 24
    np.testing.assert_array_equal(grid.rows(0, 24), product_rows(**axes))
    np.testing.assert_array_equal(grid.rows(5, 13), product_rows(**axes)[5:13])


def test_grid_xdot0_none_starts_stuck_and_an_array_is_an_axis():
    stuck = Grid(**{**BASE, "v": [1.0, 2.0]})
    np.testing.assert_array_equal(stuck.rows(0, 2)[:, layout.XD0], [1.0, 2.0])
    moving = Grid(**{**BASE, "xdot0": [0.0, -1.0]})
    assert moving.dims == ("xdot0",)
    np.testing.assert_array_equal(moving.rows(0, 2)[:, layout.XD0], [0.0, -1.0])


def test_huge_grid_is_accepted_and_rows_come_from_the_axes():
    axis = np.linspace(1.0, 2.0, 1000)
    grid = Grid(m=axis, k=axis, r_y=axis, v=axis)          # 1e12 points, never built
    assert grid.size == 10**12
    last = grid.rows(10**12 - 2, 10**12)
    np.testing.assert_array_equal(last[:, :4], [[2.0, 2.0, 2.0, axis[-2]], [2.0] * 4])


def test_points_mode_reads_axes_together_and_allows_repeats():
    grid = Grid.points(m=[5.0, 5.0, 2.0], k=50.0, r_y=[10.0, 10.0, 1.0],
                       v=[1.0, 1.0, 3.0])
    assert grid.dims == ("point",) and grid.shape == (3,)
    rows = grid.rows(0, 3)
    np.testing.assert_array_equal(rows[:, layout.M], [5.0, 5.0, 2.0])
    np.testing.assert_array_equal(rows[:, layout.V], [1.0, 1.0, 3.0])
    np.testing.assert_array_equal(rows[:, layout.K], [50.0] * 3)


def test_block_of_a_points_grid_holds_only_its_points():
    grid = Grid.points(m=[1.0, 2.0, 3.0, 4.0], k=50.0, r_y=10.0, v=[5.0, 6.0, 7.0, 8.0])
    block, lo, hi = grid.block(1, 3)
    assert block.size == 2
    np.testing.assert_array_equal(block.rows(lo, hi), grid.rows(1, 3))
    product = Grid(m=[1.0, 2.0], k=50.0, r_y=10.0, v=[5.0, 6.0])
    assert product.block(1, 3) == (product, 1, 3)


BAD_GRIDS = {
    "nan": (dict(v=[1.0, np.nan]), ValueError, r"v must be finite, got nan .*element 1"),
    "inf": (dict(k=np.inf), ValueError, r"k must be finite, got inf"),
    "m_zero": (dict(m=0.0), ValueError, r"m must be > 0 .*got 0\.0"),
    "m_negative": (dict(m=[1.0, -2.0]), ValueError, r"m must be > 0 .*-2\.0.*element 1"),
    "k_nonpositive": (dict(k=[-1.0]), ValueError, r"k must be > 0 .*got -1\.0"),
    "r_y_negative": (dict(r_y=-0.5), ValueError, r"r_y must be >= 0 .*got -0\.5"),
    "alpha2_negative": (dict(alpha2=[0.0, -0.01]), ValueError,
                        r"alpha2 must be >= 0 .*got -0\.01"),
    "empty": (dict(v=[]), ValueError, r"v axis is empty"),
    "two_d": (dict(v=[[1.0, 2.0], [3.0, 4.0]]), ValueError,
              r"v must be a scalar or a 1-D array, got an array of shape \(2, 2\)"),
    "ragged_nested": (dict(v=[[1.0], [2.0, 3.0]]), ValueError,
                      r"v must be a scalar or a 1-D array"),
    "duplicate": (dict(v=[1.0, 2.0, 1.0]), ValueError,
                  r"v axis has the duplicated value 1\.0"),
    "bool_scalar": (dict(m=True), TypeError, r"m must be a real number, got True"),
    "bool_in_list": (dict(v=[1.0, True]), TypeError,
                     r"v must hold real numbers, got True"),
    "bool_array": (dict(alpha1=np.array([True, False])), TypeError,
                   r"alpha1 must hold real numbers, got .*True"),
    "string": (dict(k="50"), TypeError, r"k must be a real number, got '50'"),
    "object_string": (dict(v=np.array([1.0, "2"], dtype=object)), TypeError,
                      r"v must hold real numbers, got '2'"),
    "complex": (dict(v=[1.0 + 2.0j]), TypeError,
                r"v must hold real numbers, got \(1\+2j\)"),
    "none": (dict(r_y=None), TypeError, r"r_y must be a real number, got None"),
}


@pytest.mark.parametrize("case", sorted(BAD_GRIDS))
def test_bad_grid_is_refused_naming_axis_and_value(case):
    changes, exc, match = BAD_GRIDS[case]
    with pytest.raises(exc, match=match):
        Grid(**{**BASE, **changes})


def test_ragged_points_are_refused_naming_the_lengths():
    with pytest.raises(ValueError, match=r"equal lengths, got m: 2, v: 3"):
        Grid.points(m=[1.0, 2.0], k=1.0, r_y=1.0, v=[1.0, 2.0, 3.0])


@pytest.mark.parametrize("kwargs, exc, match", [
    (dict(chunks=0), ValueError, r"chunks must be an integer >= 1 .*got 0"),
    (dict(chunks=True), ValueError, r"chunks must be .*got True"),
    (dict(method="exact", ), ValueError, r"method='exact' needs a piecewise-linear law.*alpha2=0\.01"),
    (dict(method="euler"), ValueError, r"method must be one of"),
    (dict(scheduler="thread"), ValueError, r"scheduler must be one of .*'thread'"),
    (dict(scheduler="threads", client="tcp://127.0.0.1:1"), ValueError, "not both"),
    (dict(client=42), TypeError, r"client must be a distributed.Client .*42"),
    (dict(dt=-1.0), ValueError, r"dt must be a finite number > 0"),
    (dict(path="."), ValueError, r"path='\.' is a directory"),
    (dict(path="no/such/dir/map.nc"), FileNotFoundError,
     r"path='no/such/dir/map.nc': directory no/such/dir does not exist"),
])
def test_bad_sweep_arguments_are_refused_before_work(kwargs, exc, match, monkeypatch):
    def no_work(*args):
        raise AssertionError("a chunk ran")
    monkeypatch.setattr(sweep_mod, "run_chunk_parallel", no_work)
    with pytest.raises(exc, match=match):
        sweep(Grid(**{**BASE, "alpha2": [0.0, 0.01]}), progress=False, **kwargs)


def test_sweep_needs_a_grid():
    with pytest.raises(TypeError, match="grid must be a sweepcore.Grid, got dict"):
        sweep(dict(BASE))


# ------------------------------------------------------- values of a sweep
def flat(da):
    """A sweep variable in the grid's flat order (the grid's axis order; the file
    puts v last for xarray's default plot)."""
    return da.transpose(*[a for a in Grid(**MIXED).dims if a in da.dims]).values.ravel()


def test_sweep_equals_serial_kernel_point_by_point(warm_sweep):
    o = make_options("auto", tol=1e-8)
    ds = sweep(Grid(**MIXED), progress=False)
    ref = per_point(product_rows(**MIXED), o)
    for name, (col, *_meta) in OBSERVABLES.items():
        np.testing.assert_array_equal(flat(ds[name]), ref[:, col], err_msg=name)
    np.testing.assert_array_equal(flat(ds.regime), ref[:, layout.OB_REGIME])
    np.testing.assert_array_equal(flat(ds.status), ref[:, layout.OB_STATUS])
    np.testing.assert_array_equal(flat(ds.converged),
                                  ref[:, layout.OB_STATUS] == codes.OK)


def test_sweep_equals_the_attractor_api(warm_sweep):
    axes = dict(m=5.0, k=50.0, r_y=10.0, v=[0.5, 3.0], alpha1=1.0, alpha2=[0.0, 0.02],
                x0=0.3, xdot0=[0.0, 2.0])
    ds = sweep(Grid(**axes), progress=False)
    for v, a2, xd0 in itertools.product(axes["v"], axes["alpha2"], axes["xdot0"]):
        p = sc.Params(m=5.0, k=50.0, r_y=10.0, v=v, alpha1=1.0, alpha2=a2)
        ob = sc.attractor(p, x0=0.3, xdot0=xd0)
        at = ds.sel(v=v, alpha2=a2, xdot0=xd0)
        for name in OBSERVABLES:
            np.testing.assert_equal(float(at[name]), float(getattr(ob, name)),
                                    err_msg=name)
        assert codes.REGIME_NAMES[int(at.regime)] == ob.regime
        assert codes.STATUS_NAMES[int(at.status)] == ob.status
        assert bool(at.converged) == ob.converged
        for name in ("q", "v_star", "x_eq"):
            np.testing.assert_equal(float(at[name]), getattr(ob, name), err_msg=name)


def test_constant_friction_closed_form(warm_sweep):
    """alpha1 = alpha2 = 0, start stuck: the circle of radius v/omega about r_y/k."""
    ds = sweep(Grid(m=[2.0, 5.0], k=[20.0, 50.0], r_y=[0.0, 10.0], v=[0.5, 3.0]),
               progress=False)
    def expect(expr):
        return expr.broadcast_like(ds.amplitude).transpose(*ds.amplitude.dims).values

    w = np.sqrt(ds.k / ds.m)
    assert (ds.converged == 1).all()
    np.testing.assert_allclose(ds.amplitude, expect(ds.v / w), rtol=1e-12)
    np.testing.assert_allclose(ds.period, expect(2 * np.pi / w), rtol=1e-12)
    scale = float((ds.r_y / ds.k + ds.v / w).max())     # r_y = 0: the mean is 0
    np.testing.assert_allclose(ds["mean"], expect(ds.r_y / ds.k), rtol=0,
                               atol=1e-12 * scale)


def test_scalar_grid_gives_zero_dimensional_variables(warm_sweep):
    ds = sweep(Grid(**BASE), progress=False)
    assert ds.amplitude.dims == () and float(ds.v) == 1.0
    assert float(ds.amplitude) == pytest.approx(1.0 / math.sqrt(10.0), rel=1e-12)


def test_points_sweep_equals_serial_kernel(warm_sweep):
    pts = dict(m=[5.0, 4.0, 5.0], k=50.0, r_y=10.0, v=[3.0, 6.0, 3.0], alpha1=1.0,
               alpha2=[0.02, 0.0, 0.02])
    ds = sweep(Grid.points(**pts), progress=False)
    rows = np.array([sc.Params(m=m, k=50.0, r_y=10.0, v=v, alpha1=1.0, alpha2=a2).row(0.0, v)
                     for m, v, a2 in zip(pts["m"], pts["v"], pts["alpha2"])])
    ref = per_point(rows, make_options())
    np.testing.assert_array_equal(ds.amplitude.values, ref[:, layout.OB_AMPLITUDE])
    np.testing.assert_array_equal(ds.v.values, pts["v"])
    assert ds.v.dims == ("point",) and ds.k.dims == ()


def test_analytic_arrays_equal_params_bit_for_bit():
    """The vectorised path (a grid's analytic variables) and the scalar path (Params)
    read the same kernel definition: equal bit for bit."""
    vals = dict(m=[2.0, 5.0], k=[50.0], r_y=[0.0, 10.0], v=[-2.0, 0.0, 3.0, 7.5],
                alpha1=[-1.0, 0.0, 1.0], alpha2=[0.0, 0.02], c=[0.0, 0.3])
    combos = [dict(zip(vals, combo)) for combo in itertools.product(*vals.values())]
    for name in ("omega", "q", "v_star", "x_eq", "first_lyapunov"):
        args = law.DERIVED[name][1]
        arrays = [np.array([d.get(a) if a in d else law.DEFAULTS.get(a) or 0.0
                            for d in combos]) if a not in ("r_k", "v_s") else None
                  for a in args]
        got = law.evaluate(name, *arrays)
        want = [getattr(sc.Params(**d), name) for d in combos]
        np.testing.assert_array_equal(got, want, err_msg=name)


def test_analytic_variables_span_only_their_dimensions(paper_map):
    ds = sweep(paper_map, progress=False)
    assert ds.omega.dims == () and ds.v_star.dims == ("alpha2",)
    assert ds.q.dims == ds.x_eq.dims == ("alpha2", "v")     # v last: plotted on x
    p = sc.Params(m=5.0, k=50.0, r_y=10.0, v=float(ds.v[7]), alpha1=1.0, alpha2=0.02)
    at = ds.isel(v=7).sel(alpha2=0.02)
    assert (float(at.q), float(at.x_eq), float(at.v_star)) == (p.q, p.x_eq, p.v_star)


# ------------------------------------------------------------- invariance
@pytest.fixture(scope="module")
def map_reference(paper_map):
    """The paper map in one chunk on the direct path."""
    return sweep(paper_map, chunks=paper_map.size, progress=False)


@pytest.mark.parametrize("chunks", [1, 3, 7, None])
def test_chunking_does_not_change_results(paper_map, map_reference, chunks):
    assert_same_results(sweep(paper_map, chunks=chunks, progress=False), map_reference)


def test_numba_thread_count_does_not_change_results(paper_map, map_reference):
    import numba
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        assert_same_results(sweep(paper_map, chunks=9, progress=False), map_reference)
    finally:
        numba.set_num_threads(before)


@pytest.mark.parametrize("scheduler", [
    "synchronous", "threads", pytest.param("processes", marks=pytest.mark.slow)])
def test_dask_schedulers_do_not_change_results(paper_map, map_reference, scheduler):
    ds = sweep(paper_map, scheduler=scheduler, chunks=5, progress=False)
    assert_same_results(ds, map_reference)


@pytest.fixture(scope="module")
def local_cluster():
    """Two single-threaded worker processes on 127.0.0.1, numba limited to 1 thread."""
    distributed = pytest.importorskip("distributed")
    # env=, not the pre-spawn-environ config key: that one is also written into this
    # process, whose numba then refuses to compile under its running thread pool
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       host="127.0.0.1", dashboard_address=None,
                                       env={"NUMBA_NUM_THREADS": "1"})
    with cluster:
        yield cluster


def test_local_cluster_gives_identical_results(paper_map, map_reference, local_cluster):
    from distributed import Client

    with Client(local_cluster) as client:
        numba_threads = client.run(lambda: os.environ.get("NUMBA_NUM_THREADS"))
        assert set(numba_threads.values()) == {"1"}
        assert_same_results(sweep(paper_map, client=client, chunks=10, progress=False),
                            map_reference)
    by_address = sweep(paper_map, scheduler=local_cluster.scheduler_address, chunks=17,
                       progress=False)
    assert_same_results(by_address, map_reference)


# ------------------------------------------------------- memory, progress
def test_computation_memory_follows_the_chunk_not_the_grid(warm_sweep, monkeypatch):
    grid = Grid(m=np.linspace(1.0, 2.0, 24), k=np.linspace(20.0, 40.0, 20), r_y=5.0,
                v=np.linspace(0.1, 5.0, 100))                         # 48 000 points
    seen = []
    real = sweep_mod.execute.attractors

    def spy(P, laws, o, out, parallel):
        seen.append(len(P))
        real(P, laws, o, out, parallel)
    monkeypatch.setattr(sweep_mod.execute, "attractors", spy)

    def peak(chunks):
        tracemalloc.start()
        sweep(grid, chunks=chunks, progress=False, max_seconds=None)  # no timed sample
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        return peak

    output = layout.NOBS * 8 * grid.size
    chunked = peak(2000)
    assert seen and max(seen) == 2000 and sum(seen) == grid.size
    # one chunk holds the rows (8 float64) and the results (13) of every point at once
    whole = peak(grid.size)
    assert chunked < 1.5 * output < whole


def test_progress_bar_only_when_asked_or_on_a_terminal(warm_sweep, capsys):
    grid = Grid(**{**BASE, "v": [1.0, 2.0]})
    sweep(grid)                       # stderr is captured here: not a terminal
    assert capsys.readouterr().err == ""
    sweep(grid, progress=True)
    err = capsys.readouterr().err
    assert "sweep" in err and "100%" in err


# ----------------------------------------------------------------- resume
RUN_CHUNK = sweep_mod.run_chunk_parallel


class Interrupt(Exception):
    pass


def spy_chunks(monkeypatch, path, interrupt_after=None):
    """Record the first flat index of every chunk computed on the direct path;
    raise Interrupt instead of computing chunk ``interrupt_after + 1``. Every call
    also checks that no file exists at ``path`` while chunks are still running."""
    starts = []

    def spy(grid, start, stop, o):
        assert not path.exists(), "final file present while chunks still run"
        if interrupt_after is not None and len(starts) == interrupt_after:
            raise Interrupt
        starts.append(start)
        return RUN_CHUNK(grid, start, stop, o)
    monkeypatch.setattr(sweep_mod, "run_chunk_parallel", spy)
    return starts


def test_interrupted_sweep_resumes_computing_only_missing_chunks(paper_map, tmp_path,
                                                                 monkeypatch, capsys):
    path = tmp_path / "map.nc"
    store = WorkingStore.location(path)
    first = spy_chunks(monkeypatch, path, interrupt_after=3)
    with pytest.raises(Interrupt):
        sweep(paper_map, chunks=10, path=path, progress=False)
    assert len(first) == 3 and not path.exists() and store.is_dir()

    resumed = spy_chunks(monkeypatch, path)
    capsys.readouterr()
    sweep(paper_map, chunks=10, path=path)      # says so (no bar off a terminal)
    assert "sweep: resuming 3 of 8 chunks" in capsys.readouterr().err
    assert sorted(resumed) == sorted(set(range(0, paper_map.size, 10)) - set(first))
    assert path.exists() and not store.exists()

    monkeypatch.undo()
    sweep(paper_map, path=tmp_path / "whole.nc", progress=False)
    got, want = open_result(path), open_result(tmp_path / "whole.nc")
    assert_same_results(got, want)
    assert {k: v for k, v in got.attrs.items() if k != "history"} == \
        {k: v for k, v in want.attrs.items() if k != "history"}


def test_finished_store_is_written_without_computing(paper_map, tmp_path, monkeypatch):
    path = tmp_path / "map.nc"

    def crash(ds, p):
        raise Interrupt
    with monkeypatch.context() as patch:
        patch.setattr(resumable, "write_netcdf", crash)
        with pytest.raises(Interrupt):
            sweep(paper_map, chunks=30, path=path, progress=False)
    assert not path.exists()
    recomputed = spy_chunks(monkeypatch, path)
    ds = sweep(paper_map, chunks=30, path=path, progress=False)
    assert recomputed == []
    assert_same_results(open_result(path), ds)


@pytest.mark.parametrize("change, match", [
    (dict(tol=1e-6), "different arguments"),
    (dict(max_periods=50.0), "different arguments"),
    (dict(grid=Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, v=np.linspace(3.0, 8.0, 24),
                    alpha2=[0.01, 0.02, 0.04])), "different arguments"),
    (dict(chunks=20), "holds chunks of 10 points, got chunks=20"),
])
def test_resume_with_other_arguments_is_refused_naming_the_store(
        paper_map, tmp_path, monkeypatch, change, match):
    path = tmp_path / "map.nc"
    spy_chunks(monkeypatch, path, interrupt_after=1)
    with pytest.raises(Interrupt):
        sweep(paper_map, chunks=10, path=path, progress=False)
    args = {"grid": paper_map, "chunks": 10, **change}
    with pytest.raises(ValueError, match=match) as err:
        sweep(path=path, progress=False, **args)
    assert str(WorkingStore.location(path)) in str(err.value)


def test_resume_after_a_kernel_change_is_refused(paper_map, tmp_path, monkeypatch):
    path = tmp_path / "map.nc"
    spy_chunks(monkeypatch, path, interrupt_after=1)
    with pytest.raises(Interrupt):
        sweep(paper_map, chunks=10, path=path, progress=False)
    monkeypatch.setattr(resumable, "kernel_digest", lambda: "edited kernels")
    with pytest.raises(ValueError, match="kernels changed"):
        sweep(paper_map, chunks=10, path=path, progress=False)


# --------------------------------------------------------------- boundary
def test_measured_hopf_boundary_brackets_the_analytic_v_star(paper_map):
    """Starting stuck, the map switches from a cycle to equilibrium at v*: the
    measured boundary is within half a grid spacing of sqrt(alpha1/(3 alpha2))."""
    ds = sweep(paper_map, progress=False)
    half = (5.0 / 23) / 2
    exact = np.sqrt(1.0 / (3.0 * np.array([0.01, 0.02, 0.03])))
    np.testing.assert_allclose(ds.v_star, exact, rtol=1e-15)
    np.testing.assert_allclose(ds.v_hopf_resolution, half, rtol=1e-12)
    assert (abs(ds.v_hopf_measured - ds.v_star) <= ds.v_hopf_resolution).all()


def synthetic_map(regimes, v):
    import xarray as xr
    return xr.Dataset(
        {"regime": (("alpha2", "v"), np.array(regimes, dtype=np.int8))},
        coords={"v": ("v", np.asarray(v, float), {"units": "cm s-1"}),
                "alpha2": [0.01, 0.02, 0.03, 0.04], "alpha1": 1.0})


def test_boundary_rules_on_a_synthetic_map():
    S, C = codes.R_STICK_SLIP, codes.R_SLIP_CYCLE
    E, U = codes.R_EQUILIBRIUM, codes.R_UNCONVERGED
    v = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
    regimes = [[S, S, C, C, E, E],      # hopf between 4 and 5, stick ends between 2 and 3
               [S, S, S, U, E, E],      # an unconverged point widens the bracket
               [C, C, C, C, C, C],      # no switch: NaN
               [E, E, C, C, E, E]]      # equilibrium below the cycles does not count
    order = [3, 0, 5, 1, 4, 2]          # any order of v
    ds = synthetic_map(np.array(regimes)[:, order], np.array(v)[order])
    bd = hopf_boundary(ds)
    np.testing.assert_array_equal(bd.v_hopf_measured, [4.5, 4.0, np.nan, 4.5])
    np.testing.assert_array_equal(bd.v_hopf_resolution, [0.5, 1.0, np.nan, 0.5])
    np.testing.assert_array_equal(bd.v_stick_onset, [2.5, 4.0, np.nan, np.nan])
    np.testing.assert_array_equal(bd.v_stick_onset_resolution, [0.5, 1.0, np.nan, np.nan])
    np.testing.assert_array_equal(bd.v_star, np.sqrt(1.0 / (3.0 * ds.alpha2.values)))
    assert bd.v_hopf_measured.attrs["units"] == "cm s-1"
    assert "flag_values" not in bd.v_hopf_measured.attrs


def test_boundary_needs_a_swept_speed():
    ds = synthetic_map(np.zeros((4, 1)), [1.0])
    with pytest.raises(ValueError, match="needs >= 2 values"):
        hopf_boundary(ds)
    with pytest.raises(ValueError, match="axis='speed' is not a dimension"):
        hopf_boundary(ds, axis="speed")


def test_stick_onset_and_reversal_band_are_separate_variables():
    """Synthetic rows: a reversal band (slip cycles overshooting the belt,
    xdot_max > v) between stick-slip runs is not the stick onset, which is where
    stick-slip gives way to a slip cycle below the belt speed or equilibrium."""
    S, C, E = codes.R_STICK_SLIP, codes.R_SLIP_CYCLE, codes.R_EQUILIBRIUM
    v = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    regimes = [[S, C, C, S, C, E],       # band 1.5-3.5, onset 4.5
               [S, S, C, C, C, C],       # band from 2.5 to the grid's end: no onset
               [S, S, S, C, C, E],       # no band: onset 3.5
               [C, C, S, S, S, S]]       # band from the grid's start, no onset
    over = np.array([[0, 1, 1, 0, 0, 0], [0, 0, 1, 1, 1, 1], [0, 0, 0, 0, 0, 0],
                     [1, 1, 0, 0, 0, 0]], bool)
    ds = synthetic_map(regimes, v)
    ds["xdot_max"] = (("alpha2", "v"), np.where(over, 1.01, 0.99) * v)
    bd = hopf_boundary(ds)
    np.testing.assert_array_equal(bd.v_stick_onset, [4.5, np.nan, 3.5, np.nan])
    np.testing.assert_array_equal(bd.v_reversal_lower, [1.5, 2.5, np.nan, np.nan])
    np.testing.assert_array_equal(bd.v_reversal_upper, [3.5, np.nan, np.nan, 2.5])
    np.testing.assert_array_equal(bd.v_reversal_upper_resolution,
                                  [0.5, np.nan, np.nan, 0.5])


def test_map_stick_onset_is_the_grazing_of_the_hopf_cycle():
    """On the paper's slider the measured stick onset is 0.8945 v* (the located
    curve, benchmarks/boundaries.py; averaging: sqrt(4/5)) to the grid resolution
    on every row where it lies inside the map, NaN where it lies above the map's
    speeds, never the reversal band's edge at small alpha2 (3.7-4.7 cm/s)."""
    a2 = np.geomspace(1e-3, 1e-2, 8)
    ds = sweep(Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, v=np.linspace(0.5, 10, 40),
                    alpha2=a2), progress=False)
    onset = 0.8945 * ds.v_star
    inside = onset < 10.0
    assert inside.sum() >= 4 and (~inside).sum() >= 2
    err = abs(ds.v_stick_onset - onset).where(inside)
    assert (err <= ds.v_stick_onset_resolution + 1e-3 * ds.v_star).where(inside,
                                                                         True).all()
    assert ds.v_stick_onset.where(~inside).isnull().all()
    # the band is where slip cycles overshoot the belt, at small alpha2 only
    band = ds.v_reversal_lower.isel(alpha2=0)
    assert 3.0 < band < 5.0
    assert ds.v_reversal_lower.isel(alpha2=-1).isnull()
