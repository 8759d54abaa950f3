"""Fresh-process probe: import, first call (compile or cache load), peak memory.

Run by ``hopf_map.py`` in a new interpreter with ``NUMBA_CACHE_DIR`` pointing at an
empty directory (cold: every kernel is compiled) and again at the same, now filled,
directory (warm: the kernels are loaded from numba's cache). Prints one JSON line.

Peak memory is the process's peak resident set size (VmHWM of /proc/self/status; it
includes the interpreter, numpy, numba/LLVM), read after the imports, after the first
call and after one whole map.
"""
import json
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

t0 = time.perf_counter()
import numpy as np  # noqa: E402
import numba  # noqa: E402,F401
t_numba = time.perf_counter() - t0
from benchmarks import common  # noqa: E402
t1 = time.perf_counter()
from sweepcore.options import make_options  # noqa: E402
from sweepcore._kernels.layout import NOBS  # noqa: E402
t_import = time.perf_counter() - t1
rss_import = common.peak_rss_mib()

run = common.kernel()
nv, na = (int(a) for a in sys.argv[1:3])
run_map = len(sys.argv) > 3 and sys.argv[3] == "map"
o = make_options("auto", tol=1e-8)
P_small = common.rows(*common.map_axes(8, 8))
out_small = np.empty((P_small.shape[0], NOBS))
t2 = time.perf_counter()
run(P_small, o, out_small, True)
t_first_parallel = time.perf_counter() - t2
t3 = time.perf_counter()
run(P_small, o, out_small, False)
t_first_serial = time.perf_counter() - t3
t4 = time.perf_counter()
run(P_small, o, out_small, True)
t_second = time.perf_counter() - t4
rss_compiled = common.peak_rss_mib()
res = {"t_import_numba": t_numba, "t_import_kernels": t_import,
       "t_first_call_parallel": t_first_parallel, "t_first_call_serial": t_first_serial,
       "t_second_call_64pts": t_second, "rss_after_import_mib": rss_import,
       "rss_after_first_call_mib": rss_compiled}
if run_map:
    P = common.rows(*common.map_axes(nv, na))
    out = np.empty((P.shape[0], NOBS))
    t5 = time.perf_counter()
    run(P, o, out, True)
    res["t_map"] = time.perf_counter() - t5
    res["rss_after_map_mib"] = common.peak_rss_mib()
    res["map_arrays_mib"] = (P.nbytes + out.nbytes) / 2**20
    res["n_points"] = P.shape[0]
    sweep, Grid = common.sweep_api()
    if sweep is not None:
        grid = common.map_grid(Grid, *common.map_axes(nv, na))
        t6 = time.perf_counter()
        sweep(grid, progress=False)
        res["t_first_sweep"] = time.perf_counter() - t6
        res["rss_after_sweep_mib"] = common.peak_rss_mib()
print(json.dumps(res))
