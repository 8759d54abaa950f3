"""Results at scale: a verified working store, output-path rules, write errors, the
size estimate and refusal, and a result streamed to its file.

Every damaged store is compared with an undisturbed in-memory sweep of the same grid,
bit for bit: a damaged chunk must be computed again (with a warning naming its
file), never used.
"""
import errno
import importlib
import os
import re
import stat
import tracemalloc

import numpy as np
import pytest
import xarray as xr

from sweepcore._kernels import layout
from sweepcore.grid import Grid
from sweepcore.io import (DamagedChunkWarning, StoreDamaged, WorkingStore, open_result,
                          result_path)
from sweepcore.sweep import SweepTooLarge, estimate, sweep
from sweepcore.variables import OBSERVABLES

sweep_mod = importlib.import_module("sweepcore.sweep")
sizing_mod = importlib.import_module("sweepcore.sizing")
store_mod = importlib.import_module("sweepcore.io.store")
RUN_CHUNK = sweep_mod.run_chunk_parallel
CHUNKS = 10                   # the paper map's 72 points: 8 chunks
COMPARED = list(OBSERVABLES) + ["regime", "status", "converged", "q", "v_star", "x_eq",
                                "omega"]


class Interrupt(Exception):
    pass


def spy(monkeypatch, interrupt_after=None):
    """Record the first flat index of every chunk computed (direct path); raise
    Interrupt instead of computing chunk ``interrupt_after + 1``."""
    starts = []

    def run(grid, start, stop, o):
        if interrupt_after is not None and len(starts) == interrupt_after:
            raise Interrupt
        starts.append(start)
        return RUN_CHUNK(grid, start, stop, o)
    monkeypatch.setattr(sweep_mod, "run_chunk_parallel", run)
    return starts


@pytest.fixture(scope="module")
def reference(paper_map):
    return sweep(paper_map, progress=False)


def assert_same(got, want):
    for name in COMPARED:
        assert got[name].dtype == want[name].dtype, name
        np.testing.assert_array_equal(got[name].values, want[name].values, err_msg=name)


def interrupted(paper_map, path, monkeypatch, n=5):
    """A store holding the first ``n`` chunks of the paper map (the sweep stopped)."""
    spy(monkeypatch, interrupt_after=n)
    with pytest.raises(Interrupt):
        sweep(paper_map, chunks=CHUNKS, path=path, progress=False)
    store = WorkingStore.location(path)
    files = sorted(store.glob("chunk-*.npy"))
    assert len(files) == n
    return store, files


def chunk_start(f):
    return int(f.name.split(".")[1].split("-")[0])


# ------------------------------------------------------ damaged working store
def garble(files):
    data = bytearray(files[2].read_bytes())
    rng = np.random.default_rng(1)
    data[200:1000] = rng.integers(0, 256, 800, dtype=np.uint8).tobytes()
    files[2].write_bytes(bytes(data))
    return files[2]


def garble_header(files):
    """The .npy header (where a parser would raise EOFError or TokenError)."""
    data = bytearray(files[2].read_bytes())
    data[8:60] = b"{'descr': '<f8', 'fortran_order': ((((((((((((((((((((("
    files[2].write_bytes(bytes(data))
    return files[2]


def copy_over(files):
    files[3].write_bytes(files[1].read_bytes())
    return files[3]


def copy_with_name(files):
    """Chunk 1's file (its own, valid name and checksum) put in place of chunk 3:
    its recorded grid range does not match the index."""
    name = files[1].name.replace("chunk-000001", "chunk-000003")
    files[3].unlink()
    (files[3].parent / name).write_bytes(files[1].read_bytes())
    return files[3].parent / name


def rewrite_values(change):
    def damage(files):
        arr = np.load(files[2])
        change(arr)
        with open(files[2], "wb") as f:       # in place, same name
            np.save(f, arr)
        return files[2]
    return damage


def scale(arr):
    assert arr[layout.OB_NSTEPS, 3] > 0
    arr[layout.OB_NSTEPS, 3] *= 1.01


def insert_nan(arr):
    assert np.isfinite(arr[layout.OB_X_MAX, 4])
    arr[layout.OB_X_MAX, 4] = np.nan


def truncate(files):
    data = files[4].read_bytes()
    files[4].write_bytes(data[:len(data) // 2])
    return files[4]


def directory(files):
    files[0].unlink()
    files[0].mkdir()
    (files[0] / "inside").write_text("x")
    return files[0]


def empty(files):
    files[1].write_bytes(b"")
    return files[1]


@pytest.mark.parametrize("damage, reason", [
    (garble, "fails its SHA-256"),
    (garble_header, "fails its SHA-256"),
    (copy_over, "fails its SHA-256"),
    (copy_with_name, r"records points \[10, 20\), but chunk 3 is \[30, 40\)"),
    (rewrite_values(scale), "fails its SHA-256"),
    (rewrite_values(insert_nan), "fails its SHA-256"),
    (truncate, "fails its SHA-256"),
    (directory, "is not a regular file"),
    (empty, "fails its SHA-256"),
])
def test_damaged_chunk_is_recomputed_with_a_warning(paper_map, reference, tmp_path,
                                                    monkeypatch, damage, reason):
    path = tmp_path / "map.nc"
    _store, files = interrupted(paper_map, path, monkeypatch)
    bad = damage(files)
    resumed = spy(monkeypatch)
    with pytest.warns(DamagedChunkWarning) as record:
        ds = sweep(paper_map, chunks=CHUNKS, path=path, progress=False)
    messages = [str(w.message) for w in record]
    assert any(bad.name in m and re.search(reason, m) for m in messages), messages
    # exactly the damaged chunk and the never-computed ones ran again
    damaged = int(bad.name.split(".")[0].split("-")[1]) * CHUNKS
    assert sorted(resumed) == sorted({damaged} | set(range(50, 72, CHUNKS)))
    assert_same(ds, reference)
    assert_same(open_result(path), reference)


def test_stray_file_named_like_a_chunk_is_discarded(paper_map, reference, tmp_path,
                                                    monkeypatch):
    path = tmp_path / "map.nc"
    store, _files = interrupted(paper_map, path, monkeypatch)
    (store / "chunk-000099.0-10.nonsense.npy").write_text("x")
    spy(monkeypatch)
    with pytest.warns(DamagedChunkWarning, match="not a chunk file of this store"):
        ds = sweep(paper_map, chunks=CHUNKS, path=path, progress=False)
    assert_same(ds, reference)


@pytest.mark.parametrize("damage", ["garbled", "directory", "missing", "other_format"])
def test_damaged_store_configuration_is_a_clear_error(paper_map, tmp_path, monkeypatch,
                                                      damage):
    path = tmp_path / "map.nc"
    store, _files = interrupted(paper_map, path, monkeypatch)
    config = store / "config.json"
    if damage == "garbled":
        config.write_bytes(config.read_bytes()[:40] + b"\x00\xff{{")
    elif damage == "directory":
        config.unlink()
        config.mkdir()
    elif damage == "missing":
        config.unlink()
    else:
        config.write_text('{"sweepcore_working_store": 1, "chunk": 10}')
    spy(monkeypatch, interrupt_after=0)        # nothing may run
    with pytest.raises(StoreDamaged, match=r"map\.nc\.partial is not a usable "
                       r"sweepcore working store .*remove it"):
        sweep(paper_map, chunks=CHUNKS, path=path, progress=False)


def test_store_path_taken_by_a_file_is_a_clear_error(paper_map, tmp_path, monkeypatch):
    path = tmp_path / "map.nc"
    WorkingStore.location(path).write_text("not a directory")
    spy(monkeypatch, interrupt_after=0)
    with pytest.raises(StoreDamaged, match=r"map\.nc\.partial is not usable .*must be "
                       "a directory"):
        sweep(paper_map, path=path, progress=False)


def test_chunk_damaged_while_the_sweep_runs_is_recomputed(paper_map, reference,
                                                          tmp_path, monkeypatch):
    """Chunks are checked again before the file is filled: one damaged after it was
    stored (here by the sweep's own last chunk) is computed again."""
    path = tmp_path / "map.nc"
    store = WorkingStore.location(path)
    starts = []

    def run(grid, start, stop, o):
        starts.append(start)
        if start == 70:
            (first,) = store.glob("chunk-000000.*.npy")
            first.write_bytes(first.read_bytes()[:-1] + b"\x01")
        return RUN_CHUNK(grid, start, stop, o)
    monkeypatch.setattr(sweep_mod, "run_chunk_parallel", run)
    with pytest.warns(DamagedChunkWarning, match="chunk-000000"):
        ds = sweep(paper_map, chunks=CHUNKS, path=path, progress=False)
    assert starts == list(range(0, 72, CHUNKS)) + [0]
    assert_same(ds, reference)


# --------------------------------------------------------------- path rules
NO_WORK = dict(progress=False)


@pytest.fixture
def no_work(monkeypatch):
    spy(monkeypatch, interrupt_after=0)


def leftovers(d):
    return sorted(p.name for p in d.iterdir())


@pytest.mark.parametrize("make, match", [
    ("directory", "is a directory"),
    ("fifo", "is a FIFO, not a regular file"),
    ("symlink", "is a symbolic link, not a regular file"),
    ("dangling", "is a symbolic link, not a regular file"),
])
def test_output_that_is_not_a_regular_file_is_refused(paper_map, tmp_path, no_work,
                                                      make, match):
    path = tmp_path / "out.nc"
    if make == "directory":
        path.mkdir()
    elif make == "fifo":
        os.mkfifo(path)
    elif make == "symlink":
        (tmp_path / "real.nc").write_text("kept")
        path.symlink_to(tmp_path / "real.nc")
    else:
        path.symlink_to(tmp_path / "nowhere.nc")
    before = leftovers(tmp_path)
    with pytest.raises(ValueError, match=f"path='.*out.nc' {match}"):
        sweep(paper_map, path=path, **NO_WORK)
    assert leftovers(tmp_path) == before
    if make == "symlink":
        assert path.is_symlink() and (tmp_path / "real.nc").read_text() == "kept"


def test_device_is_refused(paper_map, no_work):
    with pytest.raises(ValueError, match=r"path='/dev/null' is a device"):
        sweep(paper_map, path=os.devnull, **NO_WORK)
    assert stat.S_ISCHR(os.stat(os.devnull).st_mode)


def test_read_only_result_needs_overwrite(paper_map, reference, tmp_path, monkeypatch):
    path = tmp_path / "map.nc"
    path.write_text("an earlier result")
    path.chmod(0o444)
    spy(monkeypatch, interrupt_after=0)
    with pytest.raises(ValueError, match=r"read-only file \(mode 0444\); pass "
                       "overwrite=True"):
        sweep(paper_map, path=path, progress=False)
    assert path.read_text() == "an earlier result"
    assert leftovers(tmp_path) == ["map.nc"]
    spy(monkeypatch)
    ds = sweep(paper_map, path=path, progress=False, overwrite=True)
    assert_same(open_result(path), reference)
    assert_same(ds, reference)


@pytest.mark.parametrize("bad", [123, b"map.nc", 1.5, ["map.nc"]])
def test_path_of_the_wrong_type_is_named(paper_map, bad, no_work):
    with pytest.raises(TypeError, match=r"path must be a str or os.PathLike .*got "
                       f"{type(bad).__name__}|path must be a str .*of type "
                       f"{type(bad).__name__}"):
        sweep(paper_map, path=bad, **NO_WORK)


def test_long_file_name_gets_a_short_store_name(paper_map, reference, tmp_path,
                                                monkeypatch):
    name = "m" * 250 + ".nc"                       # 253 characters: legal
    path = tmp_path / name
    store = WorkingStore.location(path)
    assert store.parent == tmp_path and len(store.name) < 64
    assert store != WorkingStore.location(tmp_path / ("n" * 250 + ".nc"))
    interrupted(paper_map, path, monkeypatch, n=2)
    assert store.is_dir()
    spy(monkeypatch)
    ds = sweep(paper_map, chunks=CHUNKS, path=path, progress=False)
    assert_same(ds, reference)
    assert leftovers(tmp_path) == [name]


def test_result_path_accepts_a_new_regular_or_existing_file(tmp_path):
    assert result_path(str(tmp_path / "a.nc")) == tmp_path / "a.nc"
    (tmp_path / "b.nc").write_text("old")
    assert result_path(tmp_path / "b.nc") == tmp_path / "b.nc"


# ------------------------------------------------------------- write errors
def full_disk(*args, **kwargs):
    raise OSError(errno.ENOSPC, "No space left on device")


def test_disk_full_while_storing_a_chunk_names_it_and_stays_resumable(
        paper_map, reference, tmp_path, monkeypatch):
    path = tmp_path / "map.nc"

    class FullDisk:
        def __init__(self, file):
            self.file = file

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            self.file.close()

        def write(self, data):
            self.file.write(data[:len(data) // 3])
            full_disk()

    def chunk_open(file, mode="r", *args, **kwargs):
        f = open(file, mode, *args, **kwargs)
        return FullDisk(f) if ".chunk-000003." in str(file) else f
    monkeypatch.setattr(store_mod, "open", chunk_open, raising=False)
    spy(monkeypatch)
    with pytest.raises(OSError, match=r"writing chunk 3 \(points \[30, 40\)\) to "
                       r".*map\.nc\.partial/chunk-000003.* failed \(No space left on "
                       r"device\); it needed about [\d,]+ bytes, [\d,]+ bytes free .*"
                       "rerun the same call to resume") as err:
        sweep(paper_map, chunks=CHUNKS, path=path, progress=False)
    assert err.value.errno == errno.ENOSPC
    assert not list(WorkingStore.location(path).glob(".chunk-*"))   # no temporary
    monkeypatch.delattr(store_mod, "open")
    resumed = spy(monkeypatch)
    ds = sweep(paper_map, chunks=CHUNKS, path=path, progress=False)
    assert sorted(resumed) == list(range(30, 72, CHUNKS))
    assert_same(ds, reference)


def test_disk_full_while_writing_the_file_names_it_and_keeps_the_store(
        paper_map, reference, tmp_path, monkeypatch):
    path = tmp_path / "map.nc"

    def hdf_error(*args, **kwargs):
        raise RuntimeError("NetCDF: HDF error")
    monkeypatch.setattr(xr.Dataset, "to_netcdf", hdf_error)
    spy(monkeypatch)
    with pytest.raises(OSError, match=r"writing the result file to .*map\.nc failed "
                       r"\(NetCDF: HDF error\); it needed about [\d,]+ bytes, .* free "
                       r".*working store .*map\.nc\.partial is kept"):
        sweep(paper_map, chunks=CHUNKS, path=path, progress=False)
    assert leftovers(tmp_path) == ["map.nc.partial"]
    monkeypatch.undo()
    resumed = spy(monkeypatch)
    ds = sweep(paper_map, chunks=CHUNKS, path=path, progress=False)
    assert resumed == []
    assert_same(ds, reference)


# ------------------------------------------------------- estimate and refusal
def test_estimate_counts_the_bytes_of_the_result(paper_map, reference):
    est = estimate(paper_map)
    assert est["points"] == paper_map.size == 72
    assert est["output_bytes"] == sum(v.nbytes for v in reference.data_vars.values())
    assert est["memory_bytes"] > est["output_bytes"]


@pytest.mark.parametrize("n_axis", [1000, 10_000])
def test_grid_too_large_for_memory_is_refused_before_work(tmp_path, monkeypatch,
                                                          no_work, n_axis):
    monkeypatch.chdir(tmp_path)
    axis = np.linspace(1.0, 2.0, n_axis)
    grid = Grid(m=axis, k=axis + 10.0, r_y=1.0, v=axis)     # 1e9 or 1e12 points
    with pytest.raises(SweepTooLarge, match=rf"{n_axis ** 3:,} points .*needs about "
                       r".*of memory, but .* is available; pass path='map.nc'"):
        sweep(grid, progress=False)
    assert leftovers(tmp_path) == []


def test_streamed_sweep_too_large_for_the_disk_is_refused_before_work(tmp_path,
                                                                      no_work):
    axis = np.linspace(1.0, 2.0, 10_000)
    grid = Grid(m=axis, k=axis + 10.0, r_y=axis, v=1.0)      # 1e12 points, v fixed
    with pytest.raises(SweepTooLarge, match=r"of disk for its working store .* is "
                       rf"free in {tmp_path} \(the directory of the path"):
        sweep(grid, path=tmp_path / "map.nc", progress=False)
    assert leftovers(tmp_path) == []


def test_refusal_compares_with_the_memory_available(paper_map, tmp_path, monkeypatch,
                                                    no_work):
    need = estimate(paper_map)["memory_bytes"]
    monkeypatch.setattr(sizing_mod, "available_memory", lambda: need - 1)
    with pytest.raises(SweepTooLarge, match="72 points"):
        sweep(paper_map, progress=False)
    monkeypatch.setattr(sizing_mod, "available_memory", lambda: need)
    with pytest.raises(Interrupt):           # accepted: the first chunk starts
        sweep(paper_map, progress=False)


# ---------------------------------------------------------------- streaming
def test_streamed_result_is_lazy_and_memory_follows_the_chunk(warm_sweep, tmp_path):
    """With path=, nothing grid-sized of the 13 columns is held: the traced peak
    stays well under the bytes of the observables, which the in-memory sweep
    must exceed."""
    grid = Grid(m=np.linspace(1.0, 2.0, 24), k=np.linspace(20.0, 40.0, 20), r_y=5.0,
                v=np.linspace(0.1, 5.0, 100), alpha1=-1.0)   # 48 000 points
    columns = layout.NOBS * 8 * grid.size
    sweep(Grid(m=5.0, k=50.0, r_y=10.0, v=[1.0, 2.0]), path=tmp_path / "warm.nc",
          progress=False)                      # imports of the file path, untraced

    def peak(**kw):
        tracemalloc.start()
        ds = sweep(grid, chunks=2000, progress=False, **kw)
        top = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        return ds, top

    ds, streamed = peak(path=tmp_path / "map.nc")
    mem, in_memory = peak()
    assert ds.amplitude.chunks is not None            # dask-backed, read on demand
    assert_same(ds, mem)
    assert streamed < 0.5 * columns < columns <= in_memory


@pytest.mark.parametrize("grid", [
    Grid(m=5.0, k=50.0, r_y=10.0, v=3.0, alpha1=1.0),                       # 0-d
    Grid.points(m=5.0, k=50.0, r_y=10.0, v=[1.0, 2.0, 1.0], alpha1=[0.5, 1.0, 2.0]),
    Grid(m=[4.0, 5.0], k=50.0, r_y=10.0, v=[0.5, 3.0, 6.0], alpha1=1.0,
         alpha2=[0.0, 0.02], x0=[0.0, 0.3]),                                # 4-d
], ids=["scalar", "points", "product"])
def test_streamed_file_equals_the_in_memory_result(warm_sweep, tmp_path, grid):
    want = sweep(grid, progress=False)
    got = sweep(grid, path=tmp_path / "r.nc", chunks=5, progress=False)
    assert set(got.variables) == set(want.variables)
    for name in want.variables:
        assert got[name].dtype == want[name].dtype, name
        assert got[name].dims == want[name].dims, name
        np.testing.assert_array_equal(got[name].values, want[name].values, err_msg=name)
        assert got[name].attrs.keys() == want[name].attrs.keys(), name


def test_available_memory_follows_an_address_space_limit(tmp_path):
    """In a process limited (RLIMIT_AS) to its current size + 300 MiB, the memory
    available is at most those 300 MiB."""
    import subprocess
    import sys
    script = tmp_path / "limited.py"
    script.write_text(
        "import resource\n"
        "from sweepcore.sizing import available_memory\n"
        "vm = next(int(line.split()[1]) * 1024 for line in open('/proc/self/status')"
        " if line.startswith('VmSize:'))\n"
        "limit = vm + 300 * 2**20\n"
        "resource.setrlimit(resource.RLIMIT_AS, (limit, resource.RLIM_INFINITY))\n"
        "print(available_memory())\n")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                         env=env, check=True)
    assert 0 < int(out.stdout) <= 300 * 2**20
