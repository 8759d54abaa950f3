"""Memory of sweeps streamed to a file, and the time of the size refusal.

``python benchmarks/memory.py [--points 1e6,1e7]`` writes
``benchmarks/results/memory.json``:

* for each point count, ``sweep(grid, path=...)`` in a fresh subprocess (and, for
  comparison, the first count without ``path``, in memory): its peak
  resident set size (VmHWM of /proc/self/status, so the interpreter, numpy, numba
  and dask are included), wall time, the size of the file, and what
  :func:`sweepcore.sweep.estimate` predicted. The grid is cheap on purpose
  (alpha2 = 0: the closed-form "exact" stepper; alpha1 = -1: every point settles
  quickly to steady sliding; 1000 speeds x n/1000 stiffnesses),
  so the measurement is about storage, not integration.
* the time from ``sweep()`` being called to :class:`SweepTooLarge` for grids of 1e9
  and 1e12 points held in memory (no ``path``), and a check that nothing was left
  behind.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
if str(HERE.parent) not in sys.path:
    sys.path.insert(0, str(HERE.parent))

from benchmarks.common import RESULTS, machine, save_json  # noqa: E402

CHILD = textwrap.dedent("""\
    import json, os, sys, time
    import numpy as np
    from sweepcore.grid import Grid
    from sweepcore.sweep import estimate, sweep

    n, path = int(float(sys.argv[1])), sys.argv[2]
    grid = Grid(m=5.0, k=np.linspace(20.0, 80.0, n // 1000), r_y=10.0,
                v=np.linspace(0.5, 10.0, 1000), alpha1=-1.0, alpha2=0.0)
    path = None if path == "-" else path            # "-": in memory, for comparison
    est = estimate(grid, path=path)
    def hwm():
        status = dict(line.split(":", 1) for line in open("/proc/self/status")
                      if ":" in line)
        return int(status["VmHWM"].split()[0]) / 1024

    sweep(Grid(m=5.0, k=50.0, r_y=10.0, v=[1.0, 2.0]), progress=False)   # compile
    warm = hwm()
    t0 = time.perf_counter()
    ds = sweep(grid, path=path, progress=False)
    wall = time.perf_counter() - t0
    ok = int(ds.converged.sum())
    ds.close()
    print(json.dumps({"points": grid.size, "wall_s": wall, "converged": ok,
                      "vm_hwm_mib": hwm(), "vm_hwm_before_mib": warm,
                      "in_memory": path is None,
                      "file_mib": os.path.getsize(path) / 2**20 if path else None,
                      "estimate": est}))
""")


def streamed(n: float, workdir: Path, in_memory: bool = False) -> dict:
    """Peak RSS and wall time of a fresh process sweeping ``n`` points to a file
    (or, ``in_memory``, without ``path``)."""
    path = workdir / f"sweep_{int(n)}.nc"
    out = subprocess.run([sys.executable, "-c", CHILD, str(n),
                          "-" if in_memory else str(path)],
                         capture_output=True, text=True, check=True,
                         env={**os.environ, "PYTHONPATH": str(HERE.parent)})
    path.unlink(missing_ok=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def refusal(n_axis: int, workdir: Path) -> dict:
    """Time to refuse a grid of ``n_axis**3`` points held in memory."""
    import numpy as np

    from sweepcore.grid import Grid
    from sweepcore.sweep import SweepTooLarge, sweep

    axis = np.linspace(1.0, 2.0, n_axis)
    grid = Grid(m=axis, k=axis + 10.0, r_y=1.0, v=axis)
    before = sorted(os.listdir(workdir))
    t0 = time.perf_counter()
    try:
        sweep(grid, progress=False)
        message = None
    except SweepTooLarge as err:
        message = str(err)
    took = time.perf_counter() - t0
    return {"points": grid.size, "refused": message is not None, "seconds": took,
            "message": message, "left_behind": sorted(os.listdir(workdir)) != before}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", default="1e6,1e7",
                        help="comma-separated point counts (multiples of 1000)")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(dir=RESULTS) as tmp:
        work = Path(tmp)
        runs = []
        counts = [float(s) for s in args.points.split(",")]
        for n, in_memory in [(counts[0], True)] + [(n, False) for n in counts]:
            runs.append(streamed(n, work, in_memory))
            r = runs[-1]
            where = ("in memory" if in_memory
                     else f"streamed, file {r['file_mib']:.1f} MiB")
            print(f"{r['points']:.3g} points {where}: peak RSS {r['vm_hwm_mib']:.0f} MiB "
                  f"({r['vm_hwm_before_mib']:.0f} MiB before the sweep; estimate "
                  f"{r['estimate']['memory_bytes'] / 2**20:.0f} MiB), "
                  f"{r['wall_s']:.1f} s", flush=True)
        refusals = [refusal(1000, work), refusal(10_000, work)]
        for r in refusals:
            print(f"{r['points']:.3g} points refused={r['refused']} in "
                  f"{r['seconds'] * 1e3:.1f} ms", flush=True)
    save_json({"machine": machine(), "streamed": runs, "refusals": refusals},
              RESULTS / "memory.json")
    return 0


if __name__ == "__main__":
    sys.exit(main())


def stored_section(path=None) -> str:
    """The benchmarks/README.md section of the stored ``results/memory.json``."""
    path = Path(path or HERE / "results" / "memory.json")
    if not path.is_file():
        return ""
    R = json.loads(path.read_text())
    m = R["machine"]
    rows = []
    for r in R["streamed"]:
        where = "in memory" if r["in_memory"] else f"streamed to a {r['file_mib']:.1f} MiB file"
        rows.append([f"{r['points']:,}", where, f"{r['vm_hwm_mib']:.0f} MiB "
                     f"({r['vm_hwm_before_mib']:.0f} MiB before the sweep)",
                     f"{r['wall_s']:.1f} s"])
    refusals = "; ".join(f"{r['points']:.0e} points refused in {1e3 * r['seconds']:.2f} ms"
                         for r in R["refusals"])
    from benchmarks.report import fill, table
    return fill("memory", date=m["date"], commit=m["git_commit"][:10],
                table=table(["points", "result", "peak memory", "wall time"], rows),
                refusals=refusals)
