"""Shared pieces of the benchmarks: machine description, timing, the Hopf-map grid.

Importing this module imports sweepcore (the law, the code tables): ``run.py``
points ``NUMBA_CACHE_DIR`` at a private directory before it does.
"""
from __future__ import annotations

import datetime as _dt
import json
import math
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from sweepcore import law

ROOT = Path(__file__).resolve().parent.parent       # the repository
BENCH = ROOT / "benchmarks"
RESULTS = BENCH / "results"

# The paper's slider (Liu): m = 5 kN s^2/cm, k = 50 kN/cm, r_y = 10 kN, alpha1 = 1.
PAPER = dict(m=5.0, k=50.0, r_y=10.0, alpha1=1.0)
# The Hopf map of studies/hopf_map.toml: v in linspace(0.5, 10, 256), alpha2 in geomspace(1e-3, 0.1, 256)
MAP_V = (0.5, 10.0)
MAP_A2 = (1e-3, 0.1)
OMEGA = float(law.derived("omega", PAPER))     # natural frequency [1/s]


# ------------------------------------------------------------------ the grids
def map_axes(nv: int = 256, na: int = 256):
    """The (v, alpha2) axes of the Hopf map at the study's resolution (or another)."""
    return np.linspace(*MAP_V, nv), np.geomspace(*MAP_A2, na)


def rows(v, alpha2, alpha1=PAPER["alpha1"], x0=0.0, xdot0=None, product=True):
    """Kernel rows (n, layout.NP) of the paper's slider; product=True spans
    v x alpha2 (v slow), else pairs them.

    Built by ``sweepcore.Grid`` (product, or ``Grid.points``), which knows every
    column of the row (``sweepcore._kernels.layout``) and the default of each
    parameter not given here. ``xdot0=None`` starts stuck on the belt (xdot0 = v),
    as in the paper's figures.
    """
    from sweepcore.grid import Grid
    v = np.asarray(v, float)
    alpha2 = np.asarray(alpha2, float)
    if product:
        grid = Grid(**PAPER | {"alpha1": alpha1}, v=v, alpha2=alpha2, x0=x0, xdot0=xdot0)
    else:
        V, A = np.broadcast_arrays(v, alpha2)
        grid = Grid.points(**PAPER | {"alpha1": alpha1}, v=V.ravel(), alpha2=A.ravel(),
                           x0=x0, xdot0=xdot0)
    return grid.rows(0, grid.size)


def attractor_map(P, method="auto", tol=1e-8, out=None):
    """Observables rows (n, layout.NOBS) of the kernel rows P on all numba threads.

    The one direct kernel call of the peers' sections (heyoka, pybasin): the
    kernels' entry names live here only.
    """
    from sweepcore._kernels.layout import NOBS
    from sweepcore.options import make_options
    out = np.empty((P.shape[0], NOBS)) if out is None else out
    kernel()(P, make_options(method, tol=tol), out, True)
    return out


def length_scale(P):
    """The kernels' length scale r_y/k + |v|/omega of each row [cm] (error unit)."""
    from sweepcore import law
    return law.length_scale(P)


def kernel():
    """``run(P, o, out, parallel)``: the attractor of every row of the paper's map
    on the kernels of whatever sweepcore is importable (``sweepcore.compiled``; the
    entry kernels ``attractor_rows``/``attractor_rows_parallel`` of versions before
    it), so that a benchmark can probe an older checkout too."""
    try:
        from sweepcore import compiled
        from sweepcore.laws import ANALYTIC
    except ImportError:
        from sweepcore._kernels.attractor import attractor_rows, attractor_rows_parallel

        def run(P, o, out, parallel=True):
            (attractor_rows_parallel if parallel else attractor_rows)(P, o, out)
        return run

    def run(P, o, out, parallel=True):
        compiled.attractors(P, (ANALYTIC,), o, out, parallel)
    return run


# ------------------------------------------------------------------- timing
def timed(fn, repeat=3, warmup=0):
    """Run fn() ``warmup`` + ``repeat`` times; return (median s, all times, last result)."""
    res = None
    for _ in range(warmup):
        res = fn()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        res = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), times, res


def median(xs):
    return statistics.median(xs) if len(xs) else float("nan")


# ------------------------------------------------------------------ machine
def _cpuinfo():
    model, mhz, flags = "unknown", float("nan"), set()
    try:
        text = Path("/proc/cpuinfo").read_text()
    except OSError:
        return model, mhz, flags
    for line in text.splitlines():
        key, _, val = line.partition(":")
        key = key.strip()
        if key == "model name" and model == "unknown":
            model = val.strip()
        elif key == "cpu MHz" and math.isnan(mhz):
            mhz = float(val)
        elif key == "flags" and not flags:
            flags = set(val.split())
    return model, mhz, flags


def git_commit():
    try:
        out = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True,
                             text=True, timeout=10)
        commit = out.stdout.strip() or None
        dirty = subprocess.run(["git", "status", "--porcelain", "--", "sweepcore"],
                               cwd=ROOT, capture_output=True, text=True, timeout=10)
        return commit, bool(dirty.stdout.strip())
    except (OSError, subprocess.SubprocessError):
        return None, None


def machine():
    """Machine, software and repository description stored with every result."""
    import numba
    model, mhz, flags = _cpuinfo()
    commit, dirty = git_commit()
    try:
        import scipy
        scipy_v = scipy.__version__
    except ImportError:
        scipy_v = None
    try:
        import dask
        dask_v = dask.__version__
    except ImportError:
        dask_v = None
    try:
        mem = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30
    except (ValueError, OSError, AttributeError):
        mem = float("nan")
    try:
        affinity = len(os.sched_getaffinity(0))
    except AttributeError:
        affinity = os.cpu_count()
    return {
        "date": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
        "git_commit": commit,
        "sweepcore_dirty": dirty,      # uncommitted changes under sweepcore/ when run
        "cpu_model": model,
        "cpu_mhz": mhz,
        "simd": sorted(f for f in flags if f in ("sse2", "avx", "avx2", "fma",
                                                   "avx512f")),
        "cores": affinity,
        "cpu_count": os.cpu_count(),
        "memory_gib": round(mem, 1),
        "platform": platform.platform(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "numba": numba.__version__,
        "scipy": scipy_v,
        "dask": dask_v,
        "numba_threads": numba.config.NUMBA_NUM_THREADS,
        "numba_threading_layer": threading_layer(),
    }


def threading_layer():
    """numba's threading layer (it is only chosen once a parallel kernel has run)."""
    import numba
    try:
        return numba.threading_layer()
    except ValueError:
        return "none: the kernels run on Python threads (no numba parallel kernel ran)"


def peak_rss_mib():
    """Peak resident set size of this process [MiB]: VmHWM of /proc/self/status.

    Not ``getrusage(RUSAGE_SELF).ru_maxrss``: on Linux that value survives fork and
    exec, so a fresh subprocess reports its parent's peak until it exceeds it.
    VmHWM belongs to the process's own address space, which exec starts afresh.
    """
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return float(line.split()[1]) / 1024.0
    except OSError:
        pass
    import resource
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


# ------------------------------------------------------------------- output
class _Enc(json.JSONEncoder):
    def default(self, o):
        if isinstance(o, np.integer):
            return int(o)
        if isinstance(o, np.floating):
            return float(o)
        if isinstance(o, np.ndarray):
            return o.tolist()
        if isinstance(o, Path):
            return str(o)
        return super().default(o)


def _clean(o):
    """NaN/inf -> None so the JSON is standard."""
    if isinstance(o, dict):
        return {str(k): _clean(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [_clean(v) for v in o]
    if isinstance(o, np.ndarray):
        return _clean(o.tolist())
    if isinstance(o, (float, np.floating)):
        return float(o) if math.isfinite(o) else None
    if isinstance(o, np.integer):
        return int(o)
    return o


def save_json(obj, path):
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(_clean(obj), indent=1, cls=_Enc) + "\n")
    tmp.replace(path)
    return path


def log(*args):
    print(*args, flush=True)
    sys.stdout.flush()


def load():
    """1-minute load average (the machine is shared: contention shows here)."""
    try:
        return os.getloadavg()[0]
    except OSError:
        return float("nan")


# ------------------------------------------------------------------ errors
# Column numbers of the kernels' observables row and the code tables, from the
# package's one definition of each.
from sweepcore._kernels import codes as _codes  # noqa: E402
from sweepcore._kernels.codes import REGIME_NAMES as REGIMES  # noqa: E402
from sweepcore._kernels.codes import STATUS_NAMES as STATUSES  # noqa: E402,F401
from sweepcore._kernels.layout import (OB_AMPLITUDE, OB_MEAN, OB_NSTEPS,  # noqa: E402,F401
                                       OB_PERIOD, OB_REGIME, OB_STATUS)
CYCLES = (_codes.R_SLIP_CYCLE, _codes.R_STICK_SLIP, _codes.R_NEUTRAL)


def regime_counts(out):
    r = out[:, OB_REGIME].astype(int)
    return {REGIMES.get(int(k), str(k)): int((r == k).sum()) for k in np.unique(r)}


def compare(out, ref, L):
    """Errors of the observables ``out`` against ``ref`` (both kernels' rows).

    Amplitude/mean errors are taken where both runs converged to the same regime;
    regime disagreements are counted apart (their amplitude error is the whole
    amplitude, and is reported as ``amp_err_max_incl_mismatch``). ``L`` is the
    points' length scale r_y/k + |v|/omega [cm].
    """
    ok = (out[:, OB_STATUS] == 0) & (ref[:, OB_STATUS] == 0)
    same = ok & (out[:, OB_REGIME] == ref[:, OB_REGIME])
    cyc = same & np.isin(ref[:, OB_REGIME], CYCLES)
    da = np.abs(out[:, OB_AMPLITUDE] - ref[:, OB_AMPLITUDE])
    dm = np.abs(out[:, OB_MEAN] - ref[:, OB_MEAN])
    dT = np.abs(out[:, OB_PERIOD] - ref[:, OB_PERIOD])

    def stats(x):
        x = x[np.isfinite(x)]
        if x.size == 0:
            return {"max": np.nan, "median": np.nan, "p95": np.nan}
        return {"max": float(x.max()), "median": float(np.median(x)),
                "p95": float(np.quantile(x, 0.95))}

    return {
        "n": int(out.shape[0]),
        "n_converged": int((out[:, OB_STATUS] == 0).sum()),
        "n_ref_converged": int((ref[:, OB_STATUS] == 0).sum()),
        "n_compared": int(same.sum()),
        "n_regime_mismatch": int((ok & ~same).sum()),
        "amplitude_abs": stats(da[same]),
        "amplitude_rel_L": stats(da[same] / L[same]),
        "amplitude_rel_cycle": stats(da[cyc] / ref[cyc, OB_AMPLITUDE]),
        "mean_abs": stats(dm[same]),
        "period_abs": stats(dT[cyc]),
        "amp_err_max_incl_mismatch": float(np.nanmax(da[ok])) if ok.any() else np.nan,
    }


def sweep_api():
    """(sweep, Grid) from sweepcore when they exist, else (None, None)."""
    try:
        from sweepcore.grid import Grid
        from sweepcore.sweep import sweep
    except ImportError:
        return None, None
    return sweep, Grid


def map_grid(Grid, v, alpha2):
    return Grid(m=PAPER["m"], k=PAPER["k"], r_y=PAPER["r_y"], alpha1=PAPER["alpha1"],
                v=np.asarray(v), alpha2=np.asarray(alpha2))
