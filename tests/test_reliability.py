"""Reliability: bad input refused before any work, naming the key and the value;
unwritable outputs leave nothing behind; one failing point never disturbs the
others; result files reopen and carry their CF metadata.

Complements test_params.py (Params and simulate arguments) and test_sweep.py (the
Grid table): here the numerical options, the remaining axis rules, study files and
output paths, per-point isolation and the file format.
"""
import math
import os
import re
import stat

import netCDF4
import numpy as np
import pytest
import xarray as xr

import sweepcore as sc
import importlib
sweep_mod = importlib.import_module("sweepcore.sweep")  # the package attribute is the function
from sweepcore.grid import Grid
from sweepcore.io import WorkingStore, check_cf, open_result, write_netcdf
from sweepcore.sweep import sweep
from sweepcore.variables import OBSERVABLES

BASE = dict(m=5.0, k=50.0, r_y=10.0, v=1.0)
GOOD = sc.Params(m=5.0, k=50.0, r_y=10.0, v=5.0, alpha1=1.0, alpha2=0.01)
SMALL = Grid(m=5.0, k=50.0, r_y=10.0, v=[1.0, 2.0], alpha1=1.0, alpha2=0.01)


@pytest.fixture
def no_work(monkeypatch):
    """Any kernel call (direct or dask path) fails the test: refusals come first."""
    def forbidden(*args, **kwargs):
        raise AssertionError("a chunk was computed before the input was refused")
    monkeypatch.setattr(sweep_mod, "run_chunk_parallel", forbidden)
    monkeypatch.setattr(sweep_mod, "run_chunk", forbidden)


def names(err, *words):
    text = str(err.value)
    for w in words:
        assert w in text, f"{w!r} not in {text!r}"


# ------------------------------------------------------------- numerical options
# (option, bad value, exception): each rule of make_options once, through sweep
BAD_OPTIONS = [
    ("tol", 1.0, ValueError), ("tol", -1e-8, ValueError), ("tol", math.nan, ValueError),
    ("tol", math.inf, ValueError), ("tol", "1e-8", ValueError), ("tol", True, ValueError),
    ("graze", 0.0, ValueError), ("graze", 2.0, ValueError),
    ("dt", math.nan, ValueError), ("dt", math.inf, ValueError), ("dt", 0.0, ValueError),
    ("dt", "0.01", ValueError),
    ("max_steps", -5, ValueError), ("max_steps", 2.5, ValueError),
    ("max_steps", True, ValueError), ("max_steps", "100", ValueError),
    ("max_periods", 0.0, ValueError), ("max_periods", math.inf, ValueError),
    ("max_periods", math.nan, ValueError), ("max_periods", "5", ValueError),
    ("gps_a", math.inf, ValueError), ("gps_a", math.nan, ValueError),
    ("gps_a", "1", ValueError),
    ("method", "EXACT", ValueError), ("method", None, ValueError),
]


@pytest.mark.parametrize("name,value,exc", BAD_OPTIONS,
                         ids=[f"{n}={v!r}" for n, v, _e in BAD_OPTIONS])
def test_bad_option_is_refused_before_work_naming_it(name, value, exc, no_work):
    with pytest.raises(exc) as err:
        sweep(SMALL, progress=False, **{name: value})
    names(err, name, repr(value))


ATTRACTOR_OPTIONS = BAD_OPTIONS[:6] + BAD_OPTIONS[12:16]      # tol and max_steps


@pytest.mark.parametrize("name,value,exc", ATTRACTOR_OPTIONS,
                         ids=[f"{n}={v!r}" for n, v, _e in ATTRACTOR_OPTIONS])
def test_bad_option_is_refused_by_attractor_too(name, value, exc):
    with pytest.raises(exc) as err:
        sc.attractor(GOOD, **{name: value})
    names(err, name, repr(value))


def test_misspelt_option_is_named(no_work):
    with pytest.raises(TypeError) as err:
        sweep(SMALL, progress=False, max_step=10)
    names(err, "max_step")
    with pytest.raises(TypeError) as err:
        sc.attractor(GOOD, max_period=10)
    names(err, "max_period")


def test_exact_with_a_cubic_term_is_refused_on_a_grid_and_flagged_per_point(no_work):
    """Decided API: sweep refuses method="exact" when any alpha2 > 0 (before work,
    naming alpha2 and the value); the kernel, given such a row anyway, marks the
    point "method_not_applicable" and writes no numbers."""
    grid = Grid(**BASE, alpha2=[0.0, 0.25])
    with pytest.raises(ValueError) as err:
        sweep(grid, method="exact", progress=False)
    names(err, "alpha2", "0.25", "exact")

    from sweepcore import compiled
    from sweepcore._kernels import codes, layout
    from sweepcore.options import make_options
    out = np.empty((2, layout.NOBS))
    compiled.attractors(grid.rows(0, 2), grid.laws, make_options("exact"), out)
    assert out[0, layout.OB_STATUS] == codes.OK
    assert out[1, layout.OB_STATUS] == codes.BAD_METHOD
    assert out[1, layout.OB_REGIME] == codes.R_FAILED
    assert np.isnan(out[1, layout.OB_AMPLITUDE]) and out[1, layout.OB_NSTEPS] == 0


# ---------------------------------------------------------------------- grid axes
# rules beyond test_sweep.BAD_GRIDS: the start axes, object arrays, names, modes
BAD_AXES = {
    "x0_nan": (dict(x0=[0.0, math.nan]), ValueError, ["x0", "nan", "element 1"]),
    "xdot0_inf": (dict(xdot0=math.inf), ValueError, ["xdot0", "inf"]),
    "xdot0_string": (dict(xdot0="fast"), TypeError, ["xdot0", "'fast'"]),
    "alpha1_inf_in_array": (dict(alpha1=[1.0, math.inf]), ValueError,
                            ["alpha1", "inf", "element 1"]),
    "none_in_array": (dict(v=[1.0, None]), TypeError, ["v", "None"]),
    "empty_numpy": (dict(v=np.array([], float)), ValueError, ["v", "empty"]),
    "k_zero_in_array": (dict(k=[50.0, 0.0]), ValueError, ["k", "0.0", "element 1"]),
    "r_y_minus_inf": (dict(r_y=[-math.inf]), ValueError, ["r_y", "inf"]),
}


@pytest.mark.parametrize("case", sorted(BAD_AXES))
def test_bad_axis_is_refused_naming_axis_and_value(case):
    changes, exc, words = BAD_AXES[case]
    with pytest.raises(exc) as err:
        Grid(**{**BASE, **changes})
    names(err, *words)


def test_unknown_axis_and_mode_are_named():
    with pytest.raises(TypeError) as err:
        Grid(**BASE, mass=5.0)
    names(err, "mass")
    with pytest.raises(ValueError) as err:
        Grid(**BASE, mode="grid")
    names(err, "mode", "'grid'")


def test_empty_points_are_refused():
    with pytest.raises(ValueError) as err:
        Grid.points(m=[], k=1.0, r_y=1.0, v=[])
    names(err, "empty")


def test_object_array_of_floats_is_an_axis():
    """An object-dtype array of Python floats (what pandas hands out) is a valid axis;
    refusing it with "v must hold real numbers, got 1.0 of type float" contradicts
    itself."""
    grid = Grid(**{**BASE, "v": np.array([1.0, 2.0], dtype=object)})
    np.testing.assert_array_equal(grid.v, [1.0, 2.0])


# -------------------------------------------------------------------- study files
STUDY = """\
title = "reliability"
[axes]
m = 5.0
k = 50.0
r_y = 10.0
alpha1 = 1.0
alpha2 = 0.01
v = { start = 1.0, stop = 2.0, num = 2 }
[solver]
method = "auto"
tol = 1e-8
"""

# (replace this, with this, line, words the message must contain); messages read
# FILE:LINE: KEY: message
BAD_STUDIES = {
    "syntax": ("m = 5.0", "m = 5.0 =", 3, ["syntax"]),
    "unknown_key": ("tol = 1e-8", "tolerance = 1e-8", 11,
                    ["solver.tolerance", "'tolerance'"]),
    "missing_axis": ("k = 50.0\n", "", None, ["axes.k"]),
    "negative_mass": ("m = 5.0", "m = -5.0", 3, ["axes.m", "-5.0"]),
    "nan": ("r_y = 10.0", "r_y = nan", 5, ["axes.r_y", "nan"]),
    "inf": ("k = 50.0", "k = inf", 4, ["axes.k", "inf"]),
    "string_value": ("alpha1 = 1.0", 'alpha1 = "one"', 6, ["axes.alpha1", "'one'"]),
    "num_zero": ("num = 2", "num = 0", 8, ["axes.v.num", "0"]),
    "geometric_from_zero": ("start = 1.0, stop = 2.0, num = 2",
                            'start = 0.0, stop = 2.0, num = 2, spacing = "geometric"',
                            8, ["axes.v.start", "0.0"]),
    "empty_list": ("v = { start = 1.0, stop = 2.0, num = 2 }", "v = []", 8,
                   ["axes.v", "empty"]),
    "duplicate_values": ("v = { start = 1.0, stop = 2.0, num = 2 }", "v = [1.0, 1.0]",
                         8, ["axes.v", "distinct"]),
    "tol_too_large": ("tol = 1e-8", "tol = 2.0", 11, ["solver.tol", "2.0"]),
    "max_steps_float": ("tol = 1e-8", "tol = 1e-8\nmax_steps = 1.5", 12,
                        ["solver.max_steps", "1.5"]),
    "exact_with_cubic": ('method = "auto"', 'method = "exact"', 10,
                         ["solver.method", "alpha2"]),
    "bad_method": ('method = "auto"', 'method = "euler"', 10,
                   ["solver.method", "'euler'"]),
    "output_not_nc": ("tol = 1e-8", 'tol = 1e-8\n[output]\npath = "out.txt"', 13,
                      ["output.path", "'out.txt'"]),
}


@pytest.mark.parametrize("case", sorted(BAD_STUDIES))
def test_malformed_study_is_refused_by_the_cli_writing_nothing(case, tmp_path, capsys,
                                                             no_work):
    from sweepcore.cli import main

    old, new, line, words = BAD_STUDIES[case]
    assert old in STUDY
    study = tmp_path / "study.toml"
    study.write_text(STUDY.replace(old, new, 1))
    out = tmp_path / "out" / "result.nc"
    code = main(["run", str(study), "-o", str(out), "--no-png", "-q"])
    err = capsys.readouterr().err
    assert code == 2, err
    for w in words:
        assert w in err, f"{w!r} not in {err!r}"
    assert f"{study}:{line}:" in err if line else str(study) in err
    assert not out.exists() and not WorkingStore.location(out).exists()


def test_good_study_runs_through_the_cli(tmp_path, capsys):
    """The template above is valid: the refusals are due to the one change each."""
    from sweepcore.cli import main

    study = tmp_path / "study.toml"
    study.write_text(STUDY)
    out = tmp_path / "result.nc"
    assert main(["run", str(study), "-o", str(out), "--no-png", "-q"]) == 0
    ds = open_result(out)
    assert ds.sizes == {"v": 2} and (ds.converged == 1).all()


# -------------------------------------------------------------------- output paths
def leftovers(directory):
    return sorted(p.name for p in directory.iterdir())


def test_output_in_a_missing_directory_is_refused_before_work(tmp_path, no_work):
    path = tmp_path / "missing" / "map.nc"
    with pytest.raises(OSError) as err:
        sweep(SMALL, path=path, progress=False)
    names(err, str(path.parent))
    assert leftovers(tmp_path) == []


def test_output_below_a_file_is_refused_before_work(tmp_path, no_work):
    (tmp_path / "afile").write_text("x")
    path = tmp_path / "afile" / "map.nc"
    with pytest.raises(OSError) as err:
        sweep(SMALL, path=path, progress=False)
    names(err, str(path.parent))
    assert leftovers(tmp_path) == ["afile"]


@pytest.mark.parametrize("make", ["directory", "empty"])
def test_output_path_that_cannot_be_a_file_is_refused_before_work(tmp_path, no_work,
                                                                  monkeypatch, make):
    """A path that names an existing directory (or is empty, i.e. ".") cannot become
    the result file: that is known before any chunk runs, and must be said then,
    naming the path, not after the sweep when the final rename fails."""
    monkeypatch.chdir(tmp_path)
    if make == "directory":
        (tmp_path / "adir").mkdir()
        path = "adir"
    else:
        path = ""
    before = leftovers(tmp_path)
    with pytest.raises((ValueError, OSError)) as err:
        sweep(SMALL, path=path, progress=False)
    names(err, "path")
    assert leftovers(tmp_path) == before


def test_read_only_directory_is_refused_before_work(tmp_path, no_work):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(stat.S_IRUSR | stat.S_IXUSR)
    try:
        if os.access(ro, os.W_OK):
            pytest.skip("running as root: a read-only mode does not stop writes")
        with pytest.raises(OSError):
            sweep(SMALL, path=ro / "map.nc", progress=False)
        assert leftovers(ro) == []
    finally:
        ro.chmod(stat.S_IRWXU)


def test_failed_final_write_leaves_the_old_file_and_no_temporary(tmp_path, monkeypatch):
    """The netCDF file is written to a temporary name and renamed: a crash half-way
    through the write leaves whatever was at the path before, byte for byte, no
    temporary file, and the working store (so a rerun computes nothing)."""
    path = tmp_path / "map.nc"
    path.write_bytes(b"previous result")
    real = xr.Dataset.to_netcdf

    def half_written(self, target, *args, **kwargs):
        with open(target, "wb") as f:
            f.write(b"\x89HDF partial")
        raise OSError("disk full")
    monkeypatch.setattr(xr.Dataset, "to_netcdf", half_written)
    with pytest.raises(OSError, match="disk full"):
        sweep(SMALL, path=path, chunks=1, progress=False)
    assert path.read_bytes() == b"previous result"
    assert leftovers(tmp_path) == ["map.nc", "map.nc.partial"]

    monkeypatch.setattr(xr.Dataset, "to_netcdf", real)
    monkeypatch.setattr(sweep_mod, "run_chunk_parallel",
                        lambda *a: pytest.fail("a stored chunk was recomputed"))
    ds = sweep(SMALL, path=path, chunks=1, progress=False)
    assert leftovers(tmp_path) == ["map.nc"]
    assert_same(open_result(path), ds)


# ------------------------------------------------------------- per-point isolation
def assert_same(a, b, index=None):
    for name in list(OBSERVABLES) + ["regime", "status", "converged"]:
        x = a[name].values if index is None else a[name].values[index]
        np.testing.assert_array_equal(x, b[name].values, err_msg=name)


FAILED = {"unconverged", "failed", "unbounded"}


def regime_name(ds, i):
    from sweepcore._kernels import codes
    return codes.REGIME_NAMES[int(ds.regime.values[i])], \
        codes.STATUS_NAMES[int(ds.status.values[i])]


# good neighbours: the paper's slider at a few speeds and starts
NEIGHBOURS = [dict(v=3.0), dict(v=2.0, x0=0.3, xdot0=0.0), dict(v=7.0),
              dict(v=4.0, alpha2=0.03), dict(v=6.0, x0=-0.5, xdot0=2.0)]

# failing points (with the options that make them fail) and the status they must get
BAD_POINTS = {
    "diverged": ({}, dict(alpha1=100.0, alpha2=0.0), ("unbounded", "diverged")),
    "step_budget": (dict(max_steps=3000), dict(x0=1e4, xdot0=0.0),
                    ("unconverged", "step_budget_exceeded")),
    "fixed_step_too_large": (dict(method="gps", dt=0.05), dict(k=1e6),
                             ("failed", "fixed_step_too_large")),
    "gps_denominator": (dict(method="gps", dt=0.05), dict(alpha2=1e3, xdot0=1e6),
                        ("failed", "gps_denominator_guard")),
    "time_budget": (dict(max_periods=20.0), dict(v=5.76, x0=1e4, xdot0=0.0),
                    ("unconverged", "unconverged")),
    # subnormal belt speed without friction bound: L * tol underflows to 0
    "subnormal_speed": ({}, dict(m=1.0, k=1.0, r_y=0.0, v=5e-324, alpha2=0.01), None),
}


def points(rows):
    full = [{**dict(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, alpha2=0.01, x0=0.0,
                    xdot0=None), **r} for r in rows]
    cols = {n: [r[n] for r in full] for n in ("m", "k", "r_y", "v", "alpha1", "alpha2",
                                              "x0")}
    xd = [r["v"] if r["xdot0"] is None else r["xdot0"] for r in full]
    return Grid.points(**cols, xdot0=xd)


@pytest.mark.parametrize("kind", sorted(BAD_POINTS))
@pytest.mark.parametrize("scheduler", [None, "synchronous"])
def test_failing_point_is_flagged_and_leaves_its_neighbours_alone(kind, scheduler):
    options, bad, expect = BAD_POINTS[kind]
    clean = sweep(points(NEIGHBOURS), progress=False, scheduler=scheduler, chunks=3,
                  **options)
    assert (clean.converged == 1).all()
    bad_row = {**dict(v=5.0), **bad}
    mixed_rows = NEIGHBOURS[:2] + [bad_row] + NEIGHBOURS[2:] + [bad_row]
    mixed = sweep(points(mixed_rows), progress=False, scheduler=scheduler, chunks=3,
                  **options)
    good = [0, 1, 3, 4, 5]
    assert_same(mixed, clean, index=good)
    for i in (2, 6):
        regime, status = regime_name(mixed, i)
        assert mixed.converged.values[i] == 0
        assert regime in FAILED and status != "ok"
        if expect is not None:
            assert (regime, status) == expect
        if regime != "unconverged":
            assert np.isnan(mixed.amplitude.values[i])


# ------------------------------------------------------------------- CF and files
UNITS = {"m": "kN s2 cm-1", "k": "kN cm-1", "r_y": "kN", "v": "cm s-1",
         "alpha1": "kN s cm-1", "alpha2": "kN s3 cm-3", "x0": "cm", "xdot0": "cm s-1",
         "amplitude": "cm", "mean": "cm", "velocity_amplitude": "cm s-1",
         "cycle_size": "cm", "period": "s", "stick_fraction": "1", "t_settle": "s",
         "x_max": "cm", "x_min": "cm", "regime": "1", "status": "1", "converged": "1",
         "q": "s-1", "v_star": "cm s-1", "x_eq": "cm", "omega": "s-1"}
CF_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


def own_cf_problems(path):
    """An independent reading of the file with netCDF4 (not xarray, not check_cf)."""
    problems = []
    with netCDF4.Dataset(path) as nc:
        if nc.data_model != "NETCDF4":
            problems.append(f"data model {nc.data_model}")
        conv = getattr(nc, "Conventions", "")
        if not re.fullmatch(r"CF-1\.\d+", conv):
            problems.append(f"Conventions {conv!r}")
        for att in ("title", "history", "source", "references"):
            if not getattr(nc, att, ""):
                problems.append(f"no global {att}")
        for line in getattr(nc, "history", "").splitlines():
            if not re.match(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d", line):
                problems.append(f"history line without a timestamp: {line!r}")
        for name, var in nc.variables.items():
            attrs = var.ncattrs()
            if not CF_NAME.match(name):
                problems.append(f"bad name {name}")
            for att in ("units", "long_name"):
                if att not in attrs or not str(var.getncattr(att)):
                    problems.append(f"{name} has no {att}")
            if name in UNITS and "units" in attrs and var.getncattr("units") != UNITS[name]:
                problems.append(f"{name} units {var.getncattr('units')!r}")
            data = var[...]
            if name in nc.dimensions:                  # coordinate variable
                if "_FillValue" in attrs or np.ma.is_masked(data) or \
                        np.isnan(np.ma.filled(data, 0.0)).any():
                    problems.append(f"coordinate {name} may hold missing values")
            if "flag_values" in attrs:
                fv = np.atleast_1d(var.getncattr("flag_values"))
                meanings = var.getncattr("flag_meanings").split()
                if var.dtype != np.int8 or fv.dtype != np.int8:
                    problems.append(f"flag variable {name} is {var.dtype}, not byte")
                if len(meanings) != fv.size or np.unique(fv).size != fv.size:
                    problems.append(f"{name}: flag_values/meanings do not pair up")
                if not np.isin(np.asarray(data), fv).all():
                    problems.append(f"{name} holds values outside flag_values")
            if var.dtype.kind == "f" and name not in nc.dimensions and var.ndim > 0:
                filters = var.filters() or {}
                if not filters.get("zlib"):
                    problems.append(f"{name} is not compressed")
    return problems


@pytest.fixture(scope="module")
def result_file(tmp_path_factory):
    grid = Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, v=[1.0, 3.0, 6.0],
                alpha2=[0.0, 0.02], x0=[0.0, 1e4], xdot0=0.0)
    path = tmp_path_factory.mktemp("cf") / "map.nc"
    ds = sweep(grid, path=path, progress=False, max_steps=3000)
    return path, ds


def test_result_file_reopens_equal_with_xarray_and_netcdf4(result_file):
    path, ds = result_file
    back = open_result(path)
    assert_same(back, ds)
    for name in ds.variables:
        np.testing.assert_array_equal(back[name].values, ds[name].values, err_msg=name)
        assert back[name].dtype == ds[name].dtype, name
    with netCDF4.Dataset(path) as nc:
        assert set(nc.dimensions) == set(ds.dims)
        np.testing.assert_array_equal(nc["amplitude"][...].filled(np.nan),
                                      ds.amplitude.values)
    # the grid holds failed points (x0 = 1e4 with max_steps 3000): NaN survives
    assert np.isnan(back.amplitude.values).any() and (back.converged == 0).any()


def test_result_file_carries_cf_metadata(result_file):
    path, _ds = result_file
    assert own_cf_problems(path) == []
    assert check_cf(open_result(path)) == []


def test_cf_checkers_catch_a_broken_file(result_file, tmp_path):
    """Both checkers can fail: a file without units, with an unpaired flag and an
    out-of-range flag value is reported by each."""
    path, ds = result_file
    broken = ds.load().copy(deep=True)     # sweep(path=...) returns it lazily
    del broken["amplitude"].attrs["units"]
    broken["regime"].attrs["flag_meanings"] += " extra"
    broken["status"].values[(0,) * broken.status.ndim] = 99
    del broken.attrs["Conventions"]
    out = write_netcdf(broken, tmp_path / "broken.nc")
    own = " | ".join(own_cf_problems(out))
    theirs = " | ".join(check_cf(open_result(out)))
    for text in (own, theirs):
        assert "amplitude" in text and "regime" in text and "status" in text
        assert "Conventions" in text
