"""Result files: CF metadata, netCDF round trip, compression, atomic writes.

A sweep written to netCDF and read back must give the same values (bit for bit), the
same dtypes (flag variables stay int8) and the same attributes; the checker must
accept what sweep writes and reject each kind of broken metadata.
"""
from pathlib import Path

import netCDF4
import numpy as np
import pytest
import xarray as xr

from sweepcore.grid import Grid
from sweepcore.io import (DamagedChunkWarning, StoreBusy, StoreDamaged, WorkingStore,
                          check_cf, chunk_shape, open_result, write_netcdf)
from sweepcore.sweep import sweep


@pytest.fixture(scope="module")
def result(paper_map):
    return sweep(paper_map, progress=False)


def test_sweep_output_passes_the_cf_check(result):
    assert check_cf(result) == []
    assert result.attrs["Conventions"] == "CF-1.11"
    assert "sweepcore" in result.attrs["history"] and "Liu" in result.attrs["references"]
    assert result.v.attrs == {"units": "cm s-1", "long_name": "belt speed",
                              "spacing": "linear"}
    assert result.m.dims == () and result.m.attrs["units"] == "kN s2 cm-1"


def test_netcdf_round_trip_keeps_values_dtypes_and_attributes(result, tmp_path):
    path = write_netcdf(result, tmp_path / "map.nc")
    back = open_result(path)
    assert check_cf(back) == []
    assert set(back.variables) == set(result.variables)
    for name, var in result.variables.items():
        assert back[name].dtype == var.dtype, name
        assert back[name].dims == var.dims, name
        np.testing.assert_array_equal(back[name].values, var.values, err_msg=name)
        assert back[name].attrs.keys() == var.attrs.keys(), name
        for key, val in var.attrs.items():
            np.testing.assert_array_equal(back[name].attrs[key], val,
                                          err_msg=f"{name}.{key}")
    assert back.regime.dtype == np.int8
    assert back.regime.attrs["flag_values"].dtype == np.int8
    assert back.attrs == result.attrs


def test_file_is_compressed_and_coordinates_have_no_fill_value(result, tmp_path):
    path = write_netcdf(result, tmp_path / "map.nc")
    with netCDF4.Dataset(path) as nc:
        assert nc.data_model == "NETCDF4"
        amp = nc.variables["amplitude"]
        assert amp.filters()["zlib"] and amp.filters()["shuffle"]
        assert amp.filters()["complevel"] == 4
        for name in ("v", "alpha2", "m"):
            assert "_FillValue" not in nc.variables[name].ncattrs(), name
        assert "_FillValue" not in nc.variables["regime"].ncattrs()
        assert nc.variables["regime"].dtype == np.int8


def test_chunk_shape_keeps_trailing_dimensions_and_the_byte_budget():
    assert chunk_shape((1000, 200, 50), 8, nbytes=8 * 20_000) == (2, 200, 50)
    assert chunk_shape((1000, 200, 50), 8, nbytes=8 * 100) == (1, 2, 50)
    assert chunk_shape((10, 3), 8) == (10, 3)
    shape = chunk_shape((7, 3000, 4000), 1, nbytes=2**20)
    assert np.prod(shape) <= 2**20 and shape[-1] == 4000


def test_failed_write_leaves_the_target_untouched_and_no_temporary(result, tmp_path,
                                                                  monkeypatch):
    path = tmp_path / "map.nc"
    path.write_text("previous result")

    def disk_full_midway(self, target, *args, **kwargs):
        Path(target).write_text("half a file")
        raise OSError("No space left on device")
    monkeypatch.setattr(xr.Dataset, "to_netcdf", disk_full_midway)
    with pytest.raises(OSError, match="No space left"):
        write_netcdf(result, path)
    assert path.read_text() == "previous result"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["map.nc"]


def test_write_into_a_missing_directory_is_refused(result, tmp_path):
    with pytest.raises(FileNotFoundError, match="does not exist"):
        write_netcdf(result, tmp_path / "nowhere" / "map.nc")


def test_sweep_to_path_writes_the_file_it_returns(paper_map, tmp_path):
    path = tmp_path / "map.nc"
    ds = sweep(paper_map, path=path, chunks=20, progress=False)
    back = open_result(path)
    for name in ds.data_vars:
        np.testing.assert_array_equal(back[name].values, ds[name].values, err_msg=name)
    assert not WorkingStore.location(path).exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["map.nc"]


def test_points_sweep_round_trips(warm_sweep, tmp_path):
    ds = sweep(Grid.points(m=5.0, k=50.0, r_y=10.0, v=[1.0, 2.0, 1.0]), progress=False)
    assert check_cf(ds) == []
    back = open_result(write_netcdf(ds, tmp_path / "points.nc"))
    np.testing.assert_array_equal(back.v.values, [1.0, 2.0, 1.0])
    np.testing.assert_array_equal(back.amplitude.values, ds.amplitude.values)


# ----------------------------------------------------------- working store
def open_store(path, digest="d", chunk=None):
    return WorkingStore.open(path, digest, {}, n_points=10, ncols=3, chunk=chunk,
                             default_chunk=4)


def test_store_round_trips_chunks_and_survives_a_reopen(tmp_path):
    path = tmp_path / "map.nc"
    block = np.arange(12.0).reshape(4, 3)
    with open_store(path) as store:
        assert store.chunk == 4 and store.verified() == []
        store.write(1, block)
    with open_store(path) as store:          # resumed: chunk size adopted
        assert store.chunk == 4 and store.verified() == [1]
        np.testing.assert_array_equal(store.read(1), block)
        store.remove()
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_second_sweep_on_a_locked_store_is_refused_at_once(tmp_path):
    path = tmp_path / "map.nc"
    with open_store(path):
        with pytest.raises(StoreBusy, match="another sweep is running on .*map.nc"):
            open_store(path)
    with open_store(path):                   # released on close: resumable
        pass


def test_store_refuses_other_configuration_and_chunking(tmp_path):
    path = tmp_path / "map.nc"
    open_store(path).close()
    with pytest.raises(ValueError, match="different arguments"):
        open_store(path, digest="other")
    with pytest.raises(ValueError, match="holds chunks of 4 points, got chunks=5"):
        open_store(path, chunk=5)
    open_store(path).close()                 # a refusal leaves the store unlocked


def test_chunk_damaged_during_the_sweep_is_reported_naming_the_store(tmp_path):
    path = tmp_path / "map.nc"
    with open_store(path) as store:
        store.write(0, np.zeros((4, 3)))
        (f,) = store.directory.glob("chunk-*.npy")
        f.write_bytes(f.read_bytes()[:-8])
        with pytest.warns(DamagedChunkWarning, match="fails its SHA-256"):
            with pytest.raises(StoreDamaged, match=r"chunk 0 of the working store "
                               r".*partial .*rerun the same call"):
                store.read(0)
        assert not f.exists()


# ------------------------------------------------------------- the checker
def minimal():
    return xr.Dataset(
        {"amplitude": ("v", [0.0, 1.0], {"units": "cm", "long_name": "amplitude"}),
         "regime": ("v", np.array([0, 2], np.int8),
                    {"units": "1", "long_name": "regime",
                     "flag_values": np.array([0, 1, 2], np.int8),
                     "flag_meanings": "equilibrium slip_cycle stick_slip"})},
        coords={"v": ("v", [1.0, 2.0], {"units": "cm s-1", "long_name": "belt speed"})},
        attrs={"Conventions": "CF-1.11", "title": "t", "history": "h", "source": "s",
               "references": "r"})


def test_checker_accepts_a_minimal_good_dataset():
    assert check_cf(minimal()) == []


def broken(change):
    """Problems found after ``change`` edits a good dataset (or returns a new one)."""
    ds = minimal()
    out = change(ds)
    return check_cf(out if isinstance(out, xr.Dataset) else ds)


@pytest.mark.parametrize("change, problem", [
    (lambda ds: ds.attrs.pop("Conventions"), "Conventions"),
    (lambda ds: ds.attrs.update(Conventions="COARDS"), "Conventions"),
    (lambda ds: ds.attrs.pop("history"), "history is missing"),
    (lambda ds: ds.amplitude.attrs.pop("units"), "amplitude has no units"),
    (lambda ds: ds.v.attrs.pop("long_name"), "v has no long_name"),
    (lambda ds: ds.regime.attrs.pop("flag_meanings"), "needs both"),
    (lambda ds: ds.regime.attrs.update(flag_meanings="equilibrium slip_cycle"),
     "3 flag_values but 2 flag_meanings"),
    (lambda ds: ds.regime.attrs.update(flag_values=np.array([0, 1, 2])),
     "flag_values of type int64, variable of type int8"),
    (lambda ds: ds.regime.attrs.update(flag_values=np.array([0, 0, 2], np.int8)),
     "not distinct"),
    (lambda ds: ds.regime.values.__setitem__(1, 5), r"values [5] are not among"),
    (lambda ds: ds.assign_coords(v=("v", [np.nan, 2.0], ds.v.attrs)),
     "coordinate v contains NaN"),
])
def test_checker_reports_each_broken_rule(change, problem):
    problems = broken(change)
    assert any(problem in p for p in problems), problems
