"""Faults: killed workers, a killed sweep process, two sweeps on one path.

Each sweep here is compared with an undisturbed run of the same grid, variable by
variable and bit for bit (every point is computed independently, so nothing a fault
does to the schedule may change a number).

The sweep process is a real subprocess killed with SIGKILL (no cleanup of any kind
runs); it records each chunk it finishes in a log file, which is how the tests see
what a resumed run recomputes. Workers are real processes of a LocalCluster on
127.0.0.1, killed with SIGKILL while tasks run.
"""
import os
import signal
import subprocess
import sys
import textwrap
import threading
import time

import dask
import numpy as np
import pytest

from sweepcore.grid import Grid
from sweepcore.io import WorkingStore, open_result
from sweepcore.sweep import sweep

N_V = 40                     # grid: 40 speeds x 4 alpha2 = 160 points, 16 chunks
ALPHA2 = [0.01, 0.02, 0.03, 0.04]
# rk4 at a small fixed step: a few ms per point, so chunks take long enough to be
# interrupted and every point is a real computation
KW = dict(method="rk4", dt=3e-4, chunks=10)
N_CHUNKS = N_V * len(ALPHA2) // KW["chunks"]
COMPARED = ("amplitude", "mean", "velocity_amplitude", "cycle_size", "period",
            "stick_fraction", "sticks_per_period", "t_settle", "x_max", "x_min",
            "n_steps", "regime", "status", "converged", "q", "v_star", "x_eq", "omega")


def fault_grid(n_v=N_V):
    return Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, v=np.linspace(3.0, 8.0, n_v),
                alpha2=ALPHA2)


@pytest.fixture(scope="module")
def reference():
    """The undisturbed result (direct path, in this process)."""
    return sweep(fault_grid(), progress=False, **KW)


def assert_identical(got, want):
    assert got.sizes == want.sizes
    for name in COMPARED:
        assert got[name].dtype == want[name].dtype, name
        np.testing.assert_array_equal(got[name].values, want[name].values, err_msg=name)
    for name in want.coords:
        np.testing.assert_array_equal(got[name].values, want[name].values, err_msg=name)


# ------------------------------------------------------------ sweep subprocess
SCRIPT = textwrap.dedent("""\
    import sys, time
    import numpy as np
    import importlib
    sm = importlib.import_module("sweepcore.sweep")
    rs = importlib.import_module("sweepcore.resumable")
    from sweepcore.grid import Grid

    path, log, pause, n_v = sys.argv[1], sys.argv[2], float(sys.argv[3]), int(sys.argv[4])
    final_pause = float(sys.argv[5])
    real = sm.run_chunk
    real_write = rs.write_netcdf

    def slow_write(ds, p):                     # a slow disk: room to be killed
        time.sleep(final_pause)
        return real_write(ds, p)

    def logged(grid, start, stop, o):
        out = real(grid, start, stop, o)
        time.sleep(pause)                      # pace the chunks: room to interrupt
        with open(log, "a") as f:
            f.write(f"{start}\\n")
        return out

    sm.run_chunk = logged
    rs.write_netcdf = slow_write
    grid = Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, v=np.linspace(3.0, 8.0, n_v),
                alpha2=%r)
    sm.sweep(grid, path=path, scheduler="synchronous", progress=False, **%r)
    print("finished")
""" % (ALPHA2, KW))


class SweepProcess:
    """``sweep(..., path=path)`` in a subprocess that logs every chunk it finishes."""

    def __init__(self, tmp_path, path, name, pause=0.1, n_v=N_V, final_pause=0.0):
        script = tmp_path / "run_sweep.py"
        if not script.exists():
            script.write_text(SCRIPT)
        self.log = tmp_path / f"{name}.log"
        self.err = tmp_path / f"{name}.err"
        env = {**os.environ, "NUMBA_NUM_THREADS": "1"}
        with open(self.err, "w") as err:
            self.proc = subprocess.Popen(
                [sys.executable, str(script), str(path), str(self.log), str(pause),
                 str(n_v), str(final_pause)],
                stdout=subprocess.DEVNULL, stderr=err, env=env, cwd=tmp_path)

    def computed(self):
        """Flat start indices of the chunks this process finished."""
        if not self.log.exists():
            return []
        return [int(s) for s in self.log.read_text().split()]

    def wait(self, timeout=120):
        return self.proc.wait(timeout=timeout)

    def stderr(self):
        return self.err.read_text()

    def kill(self):
        self.proc.send_signal(signal.SIGKILL)
        self.proc.wait(timeout=30)


def chunk_files(store):
    return sorted(store.glob("chunk-*.npy")) if store.is_dir() else []


def wait_for_chunks(store, n, proc, timeout=90):
    """Block until the working store holds >= n finished chunks."""
    t0 = time.monotonic()
    while len(chunk_files(store)) < n:
        assert proc.proc.poll() is None, f"sweep ended early:\n{proc.stderr()}"
        assert time.monotonic() - t0 < timeout, "no progress"
        time.sleep(0.005)


def chunk_index(f):
    return int(f.name.split(".")[0].split("-")[1])


def kill_and_resume(tmp_path, kill_after):
    """Run, SIGKILL after each count in ``kill_after``, then let a last run finish.

    Returns the result path and, per run, (chunks stored before it, chunks it
    computed).
    """
    path = tmp_path / "map.nc"
    store = WorkingStore.location(path)
    runs = []
    for i, n in enumerate(kill_after):
        before = {chunk_index(f) for f in chunk_files(store)}
        proc = SweepProcess(tmp_path, path, f"run{i}")
        wait_for_chunks(store, n, proc)
        proc.kill()
        assert not path.exists(), "the sweep finished before it could be killed"
        runs.append((before, proc.computed()))
    before = {chunk_index(f) for f in chunk_files(store)}
    last = SweepProcess(tmp_path, path, "last", pause=0.0)
    assert last.wait() == 0, last.stderr()
    runs.append((before, last.computed()))
    return path, runs


def check_resumed(path, runs, reference):
    size = fault_grid().size
    all_starts = set(range(0, size, KW["chunks"]))
    for before, computed in runs:
        # a resumed run computes exactly what is not stored, each chunk once
        assert not before & {s // KW["chunks"] for s in computed}, (before, computed)
        assert len(computed) == len(set(computed))
    before, computed = runs[-1]
    assert {s // KW["chunks"] for s in computed} == \
        {s // KW["chunks"] for s in all_starts} - before
    assert 0 < len(before) < N_CHUNKS          # the last run really resumed
    assert sorted(p.name for p in path.parent.iterdir() if p.suffix in (".nc", "")
                  or p.name.endswith(".tmp")) == ["map.nc"]
    assert_identical(open_result(path), reference)


def test_sigkilled_sweep_resumes_without_recomputing(tmp_path, reference):
    path, runs = kill_and_resume(tmp_path, kill_after=[4])
    check_resumed(path, runs, reference)


@pytest.mark.slow
def test_sigkilled_sweep_resumes_after_repeated_kills(tmp_path, reference):
    path, runs = kill_and_resume(tmp_path, kill_after=[1, 5, 9, 14])
    check_resumed(path, runs, reference)


def test_sigkill_with_every_chunk_stored_resumes_by_writing_only(tmp_path, reference):
    """Killed after the last chunk was stored but before the file was written: the
    rerun computes nothing and writes the file."""
    path = tmp_path / "map.nc"
    store = WorkingStore.location(path)
    proc = SweepProcess(tmp_path, path, "run0", pause=0.0, final_pause=30.0)
    wait_for_chunks(store, N_CHUNKS, proc)
    proc.kill()
    assert not path.exists()
    last = SweepProcess(tmp_path, path, "last", pause=0.0)
    assert last.wait() == 0, last.stderr()
    assert last.computed() == []
    assert not store.exists()
    assert_identical(open_result(path), reference)


# --------------------------------------------------------- two sweeps, one path
def test_two_sweeps_on_one_path_never_corrupt_and_the_loser_refuses(tmp_path, reference):
    """A second sweep on a path whose sweep is running either waits and wins
    cleanly or refuses at once (computing nothing, naming the path). Whatever the
    interleaving, the file at the path is a complete, correct result."""
    path = tmp_path / "map.nc"
    store = WorkingStore.location(path)
    first = SweepProcess(tmp_path, path, "first")
    wait_for_chunks(store, 2, first)
    second = SweepProcess(tmp_path, path, "second")
    codes = [first.wait(), second.wait()]
    assert 0 in codes, (first.stderr(), second.stderr())
    assert_identical(open_result(path), reference)
    assert sorted(p.name for p in tmp_path.iterdir()
                  if p.name.startswith(("map", ".map"))) == ["map.nc"]
    for proc, code in ((first, codes[0]), (second, codes[1])):
        if code != 0:
            assert proc.computed() == [], \
                f"the losing sweep computed {len(proc.computed())} chunks, then:\n" \
                f"{proc.stderr()}"
            assert str(path) in proc.stderr() or "map.nc" in proc.stderr()


@pytest.mark.slow
def test_two_sweeps_started_together(tmp_path, reference):
    path = tmp_path / "map.nc"
    procs = [SweepProcess(tmp_path, path, f"p{i}") for i in range(2)]
    codes = [p.wait() for p in procs]
    assert 0 in codes
    assert_identical(open_result(path), reference)
    for proc, code in zip(procs, codes):
        if code != 0:
            assert proc.computed() == [], proc.stderr()


# ------------------------------------------------------------- killed workers
@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("distributed")
    # env=, not the pre-spawn-environ config key: that one is also written into this
    # process, whose numba then refuses to compile under its running thread pool
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=None,
                                  env={"NUMBA_NUM_THREADS": "1"}) as c:
        yield c


@pytest.fixture
def client(cluster):
    from distributed import Client

    with Client(cluster) as c:
        c.wait_for_workers(2, timeout=60)
        # compile (or load from cache) the kernel on every worker before timing
        sweep(Grid(m=5.0, k=50.0, r_y=10.0, v=[1.0, 2.0]), client=c, chunks=1,
              progress=False, method=KW["method"], dt=KW["dt"])
        yield c


class Killer(threading.Thread):
    """Kill one worker process (SIGKILL) once ``ready()`` holds."""

    def __init__(self, client, ready, choose):
        super().__init__(daemon=True)
        self.client, self.ready, self.choose = client, ready, choose
        self.pids = client.run(os.getpid)
        self.killed = None
        self.error = None

    def run(self):
        try:
            t0 = time.monotonic()
            while not self.ready():
                if time.monotonic() - t0 > 60:
                    return
                time.sleep(0.002)
            victim = self.choose(self.client, self.pids)
            os.kill(self.pids[victim], signal.SIGKILL)
            self.killed = victim
        except Exception as err:  # reported by the test
            self.error = err


def first_worker(client, pids):
    return sorted(pids)[0]


def run_with_killer(client, tmp_path, ready, choose):
    path = tmp_path / "map.nc"
    store = WorkingStore.location(path)
    killer = Killer(client, lambda: ready(client, store), choose)
    killer.start()
    ds = sweep(fault_grid(), client=client, path=path, progress=False, **KW)
    killer.join(timeout=60)
    assert killer.error is None, killer.error
    assert killer.killed is not None, "no worker was killed during the sweep"
    return path, ds, killer


def test_worker_killed_after_the_first_chunk(client, tmp_path, reference):
    def ready(client, store):
        return len(chunk_files(store)) >= 1
    path, ds, killer = run_with_killer(client, tmp_path, ready, first_worker)
    assert killer.killed not in client.run(os.getpid)     # it really died
    assert_identical(ds, reference)
    assert_identical(open_result(path), reference)


def test_worker_killed_before_any_chunk_finishes(client, tmp_path, reference):
    """A worker dies while every task is still running (the store exists, no chunk is
    stored yet): each task carries its own grid block, so dask reruns the lost tasks
    and nothing is lost."""
    def ready(client, store):
        return store.is_dir() and not chunk_files(store)
    path, ds, killer = run_with_killer(client, tmp_path, ready, first_worker)
    assert_identical(ds, reference)
    assert_identical(open_result(path), reference)


@pytest.mark.slow
def test_workers_killed_again_and_again(client, tmp_path, reference):
    """Kill a worker after 2, 6 and 10 chunks (the nanny restarts it each time, with
    a new pid: the workers are looked up again before each kill)."""
    path = tmp_path / "map.nc"
    store = WorkingStore.location(path)
    killed, errors = [], []

    def serial_killer():
        try:
            for i, n in enumerate((2, 6, 10)):
                while len(chunk_files(store)) < n:
                    if path.exists():
                        return
                    time.sleep(0.002)
                # a worker being restarted answers with an error: skip it
                pids = {w: pid for w, pid in client.run(
                    os.getpid, on_error="return").items() if isinstance(pid, int)}
                victim = sorted(pids)[i % len(pids)]
                os.kill(pids[victim], signal.SIGKILL)
                killed.append(pids[victim])
        except Exception as err:  # noqa: BLE001 - reported by the test
            errors.append(err)
    th = threading.Thread(target=serial_killer, daemon=True)
    th.start()
    ds = sweep(fault_grid(), client=client, path=path, progress=False,
               **{**KW, "chunks": 5})
    th.join(timeout=60)
    assert not th.is_alive() and errors == []
    assert len(set(killed)) == 3, f"killed {killed} before the sweep ended"
    want = sweep(fault_grid(), progress=False, **{**KW, "chunks": 5})
    assert_identical(ds, want)
    assert_identical(open_result(path), want)
