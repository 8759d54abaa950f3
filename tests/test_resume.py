"""Basin stability and the cycle scan resume through the working store, as sweep does.

What is proven, each against an undisturbed in-memory run of the same call, bit for
bit: an interrupted call computes, when rerun, only the chunks its store lacks, and
the file appears only when complete; a damaged chunk is computed again with a
warning; a rerun with other arguments is refused naming the store; a process killed
by SIGKILL (no cleanup of any kind) resumes; a write killed before its rename leaves
no temporary once the call is rerun; ``sweepcore basins`` resumes the same way.
"""
import importlib
import os
import signal
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import sweepcore as sc
from sweepcore.io import DamagedChunkWarning, WorkingStore, open_result

from conftest import BSTAB_AXES

basins_mod = importlib.import_module("sweepcore.basins")
cycles_mod = importlib.import_module("sweepcore.cycles")
STRIBECK = dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.5, c=0.1)
SPEEDS = [1.1, 1.3, 1.5, 1.7, 1.9, 2.1]
# auto: the exact route where it applies, sampled elsewhere (both in one call)
BASINS = dict(x0=(-2.0, 2.0), xdot0=(0.0, 2.0), samples=24, chunks=1, progress=False)


ORIGINAL = {name: getattr(module, name, None) for module, name in
            ((basins_mod, "basin_chunk"), (cycles_mod, "packed_chunk"))}


class Interrupt(Exception):
    pass


def grid():
    return sc.Grid(**STRIBECK, v=np.array(SPEEDS))


def spy(monkeypatch, module, name, path, interrupt_after=None):
    """Record the first flat index of every chunk ``module.name`` computes; raise
    Interrupt instead of computing chunk ``interrupt_after + 1``. No file may exist
    at ``path`` while chunks still run."""
    starts = []
    real = ORIGINAL[name]

    def task(g, start, stop, *args, **kw):
        assert not path.exists(), "the result file appeared before its last chunk"
        if interrupt_after is not None and len(starts) == interrupt_after:
            raise Interrupt
        starts.append(start)
        return real(g, start, stop, *args, **kw)
    monkeypatch.setattr(module, name, task)
    return starts


def assert_identical(got, want):
    assert set(got.variables) == set(want.variables)
    for name in want.variables:
        if want[name].dtype.kind in "OU":        # names: str in a file, object here
            assert list(got[name].values) == list(want[name].values), name
            continue
        assert got[name].dtype == want[name].dtype, name
        np.testing.assert_array_equal(got[name].values, want[name].values, err_msg=name)


@pytest.fixture(scope="module")
def basins_reference():
    return sc.basin_stability(grid(), **BASINS)


@pytest.fixture(scope="module")
def cycles_reference():
    return sc.slip_cycles(grid(), chunks=1)


CALLS = {
    "basins": (basins_mod, "basin_chunk",
               lambda path: sc.basin_stability(grid(), path=path, **BASINS)),
    "cycles": (cycles_mod, "packed_chunk",
               lambda path: sc.slip_cycles(grid(), path=path, chunks=1)),
}


@pytest.fixture(params=list(CALLS))
def call(request, basins_reference, cycles_reference):
    module, name, run = CALLS[request.param]
    want = basins_reference if request.param == "basins" else cycles_reference
    return module, name, run, want


# ------------------------------------------------------------ interrupted
def test_an_interrupted_call_resumes_computing_only_missing_chunks(call, tmp_path,
                                                                   monkeypatch):
    module, name, run, want = call
    path = tmp_path / "r.nc"
    first = spy(monkeypatch, module, name, path, interrupt_after=2)
    with pytest.raises(Interrupt):
        run(path)
    assert first == [0, 1] and not path.exists()
    assert len(list(WorkingStore.location(path).glob("chunk-*.npy"))) == 2
    resumed = spy(monkeypatch, module, name, path)
    got = run(path)
    assert resumed == [2, 3, 4, 5]
    assert_identical(got, want)
    assert_identical(open_result(path), want)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.nc"]     # store removed


def test_a_damaged_chunk_is_computed_again(call, tmp_path, monkeypatch):
    module, name, run, want = call
    path = tmp_path / "r.nc"
    spy(monkeypatch, module, name, path, interrupt_after=3)
    with pytest.raises(Interrupt):
        run(path)
    victim = sorted(WorkingStore.location(path).glob("chunk-000001.*.npy"))[0]
    data = bytearray(victim.read_bytes())
    data[-3] ^= 0xFF
    victim.write_bytes(bytes(data))
    resumed = spy(monkeypatch, module, name, path)
    with pytest.warns(DamagedChunkWarning, match=victim.name):
        got = run(path)
    assert resumed == [1, 3, 4, 5]
    assert_identical(got, want)


def test_a_rerun_with_other_arguments_is_refused_naming_the_store(tmp_path, monkeypatch):
    path = tmp_path / "r.nc"
    spy(monkeypatch, basins_mod, "basin_chunk", path, interrupt_after=1)
    with pytest.raises(Interrupt):
        sc.basin_stability(grid(), path=path, **BASINS)
    with pytest.raises(ValueError, match="different arguments") as err:
        sc.basin_stability(grid(), path=path, **{**BASINS, "samples": 25})
    assert str(WorkingStore.location(path)) in str(err.value)


# ------------------------------------------------------------ killed
SCRIPT = textwrap.dedent("""\
    import os, signal, sys
    import numpy as np
    import xarray as xr
    import importlib
    import sweepcore as sc

    kind, path, die = sys.argv[1], sys.argv[2], sys.argv[3]
    grid = sc.Grid(**%r, v=np.array(%r))
    module = importlib.import_module("sweepcore." + kind)
    name = {"basins": "basin_chunk", "cycles": "packed_chunk"}[kind]
    real, done = getattr(module, name), []

    def task(*a, **k):
        if die == "run" and len(done) == 2:      # two chunks are stored
            os.kill(os.getpid(), signal.SIGKILL)
        done.append(1)
        return real(*a, **k)
    setattr(module, name, task)
    if die == "write":                           # the temporary written, not renamed
        real_write = xr.Dataset.to_netcdf

        def dying(self, target, *a, **k):
            real_write(self, target, *a, **k)
            os.kill(os.getpid(), signal.SIGKILL)
        xr.Dataset.to_netcdf = dying
    if kind == "basins":
        sc.basin_stability(grid, path=path, **%r)
    else:
        sc.slip_cycles(grid, path=path, chunks=1)
""" % (STRIBECK, SPEEDS, BASINS))


def killed(tmp_path, kind, die):
    script = tmp_path / "run.py"
    script.write_text(SCRIPT)
    env = {**os.environ, "NUMBA_NUM_THREADS": "1"}
    done = subprocess.run([sys.executable, str(script), kind, str(tmp_path / "r.nc"),
                           die], env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == -signal.SIGKILL, done.stderr[-2000:]


@pytest.mark.parametrize("kind", list(CALLS))
def test_a_sigkilled_run_resumes_bit_identically(kind, tmp_path, monkeypatch,
                                                 basins_reference, cycles_reference):
    killed(tmp_path, kind, "run")
    path = tmp_path / "r.nc"
    assert not path.exists()
    assert len(list(WorkingStore.location(path).glob("chunk-*.npy"))) == 2
    module, name, run = CALLS[kind]
    resumed = spy(monkeypatch, module, name, path)
    got = run(path)
    assert resumed == [2, 3, 4, 5]
    want = basins_reference if kind == "basins" else cycles_reference
    assert_identical(open_result(path), want)
    assert_identical(got, want)


@pytest.mark.parametrize("kind", list(CALLS))
def test_a_write_killed_before_its_rename_leaves_no_temporary(kind, tmp_path,
                                                              monkeypatch,
                                                              basins_reference,
                                                              cycles_reference):
    killed(tmp_path, kind, "write")
    path = tmp_path / "r.nc"
    assert not path.exists()
    assert [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]   # left behind
    module, name, run = CALLS[kind]
    resumed = spy(monkeypatch, module, name, path)
    run(path)
    assert resumed == []                     # every chunk was stored: writing only
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.nc", "run.py"]
    want = basins_reference if kind == "basins" else cycles_reference
    assert_identical(open_result(path), want)


# ------------------------------------------------------------ the command
STUDY = BSTAB_AXES + f"v = {SPEEDS}\n[solver]\nchunks = 1\n[basins]\nsamples = 24\n"


def test_sweepcore_basins_resumes_after_ctrl_c(tmp_path, monkeypatch, capsys,
                                               basins_reference):
    from sweepcore.cli import main
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text(STUDY)
    path = tmp_path / "b.nc"

    first = []

    def ctrl_c_after_three(g, start, stop, *a, **k):
        if len(first) == 3:
            raise KeyboardInterrupt
        first.append(start)
        return ORIGINAL["basin_chunk"](g, start, stop, *a, **k)
    monkeypatch.setattr(basins_mod, "basin_chunk", ctrl_c_after_three)
    assert main(["basins", "s.toml", "-o", "b.nc", "-q", "--no-png",
                 "--max-time", "none"]) == 130
    err = capsys.readouterr().err
    assert "sweepcore basins: interrupted (rerun the same command to resume" in err
    resumed = spy(monkeypatch, basins_mod, "basin_chunk", path)
    assert main(["basins", "s.toml", "-o", "b.nc", "-q", "--no-png",
                 "--max-time", "none"]) == 0
    assert resumed == [3, 4, 5]
    got = open_result(path)
    for name in basins_reference.data_vars:
        np.testing.assert_array_equal(got[name].values, basins_reference[name].values)

