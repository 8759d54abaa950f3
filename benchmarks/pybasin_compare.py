"""Section 7: basin stability against pybasin, its published friction case, same run.

pybasin (https://github.com/adrianwix/pybasin; the Python port of bSTAB) estimates a
basin fraction by integrating thousands of starts (JAX/diffrax) and classifying them
after a fixed time. Its friction case is the published basin-stability case of
``studies/bstab_basins.toml``. It needs Python >= 3.12, so it lives in its own
environment, outside the repository:

    python3.12 -m venv ../pybasin-venv          # beside the checkout, or anywhere:
    ../pybasin-venv/bin/pip install "pybasin[jax]==0.2.0"
    export PYBASIN_PYTHON=/path/to/pybasin-venv/bin/python

This section runs ``benchmarks/pybasin_case.py`` in that interpreter (``$PYBASIN_PYTHON``,
else ``../pybasin-venv/bin/python`` beside the repository) as a subprocess, then times
sweepcore on the same speeds in this process: the exact route (one speed, and the
256-speed curve of the study) and the sampled route (5,000 starts, the published
count), wall and CPU seconds, medians of repeats. When that interpreter is absent (or
fails), pybasin's side comes from the saved results ``benchmarks/results/pybasin_peer.json``
(written by the last full run that ran it, with its date, command, machine and
versions) and the section says so.

The starts pybasin drew are classified exactly too (inside the unstable slip cycle or
not, the independent scipy reference of tests/reference.py): the starts inside that
pybasin labels stick-slip have not settled by its classification time.
"""
from __future__ import annotations

import json
import os
import shlex
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from . import common
from .common import log

SAVED = common.RESULTS / "pybasin_peer.json"
CASE = common.BENCH / "pybasin_case.py"
STUDY = common.ROOT / "studies" / "bstab_basins.toml"


def interpreter():
    """pybasin's Python: $PYBASIN_PYTHON, else ../pybasin-venv/bin/python beside the
    repository; None when it does not exist."""
    path = Path(os.environ.get("PYBASIN_PYTHON")
                or common.ROOT.parent / "pybasin-venv" / "bin" / "python")
    return path if path.exists() else None


def run_pybasin(python, speeds, samples, timeout=3600):
    """pybasin's results for ``speeds`` from a subprocess, with the starts' exact check."""
    from . import basin_peer
    with tempfile.TemporaryDirectory(prefix="sweepcore-pybasin-") as tmp:
        out, starts = Path(tmp) / "pybasin.json", Path(tmp) / "starts.npz"
        cmd = [str(python), str(CASE), "--speeds", ",".join(f"{v:g}" for v in speeds),
               "--samples", str(samples), "--out", str(out), "--starts", str(starts)]
        t0 = time.perf_counter()
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout,
                              cwd=tmp)
        if done.returncode != 0:
            raise RuntimeError(done.stderr[-3000:])
        res = json.loads(out.read_text())
        arrays = np.load(starts)
        for row in res["speeds"]:
            key = f"{row['v']:g}"
            row["exact_check"] = basin_peer.exact_check(arrays[f"starts_{key}"],
                                                        arrays[f"steady_{key}"], row["v"])
    res["process_wall_s"] = time.perf_counter() - t0
    res["command"] = " ".join(["$PYBASIN_PYTHON benchmarks/pybasin_case.py"]
                              + [shlex.quote(c) for c in cmd[2:-4]])
    return res


def _timed(fn, repeats):
    walls, cpus, out = [], [], None
    for _ in range(repeats):
        c0, t0 = time.process_time(), time.perf_counter()
        out = fn()
        walls.append(time.perf_counter() - t0)
        cpus.append(time.process_time() - c0)
    return dict(wall_s=common.median(walls), cpu_s=common.median(cpus), walls_s=walls,
                cpus_s=cpus), out


def sweepcore_side(speeds, samples, repeats, curve=True):
    """sweepcore on the same case: exact and sampled routes per speed, the curve."""
    import sweepcore as sc
    from sweepcore.study import load_study
    study = load_study(STUDY)
    b = study.basins
    box = dict(x0=b["x0"], xdot0=b["xdot0"])
    params = {k: v for k, v in study.grid_kwargs().items() if k != "v"}

    def one(v, route, **kw):
        return sc.basin_stability(sc.Grid(**params, v=np.array([v])), **box, route=route,
                                  progress=False, **kw)

    one(speeds[0], "exact")                              # compile / load the kernels
    one(speeds[0], "sampled", samples=16)
    rows = []
    for v in speeds:
        ex_t, ex = _timed(lambda: one(v, "exact", ftol=b["ftol"]), repeats)
        mc_t, mc = _timed(lambda: one(v, "sampled", samples=samples, seed=b["seed"]), repeats)

        def frac(ds, what="basin_fraction"):
            return float(ds[what].sel(attractor="equilibrium")[0])
        rows.append(dict(v=v, exact=dict(ex_t, fraction=frac(ex),
                                         error=frac(ex, "basin_fraction_error")),
                         sampled=dict(mc_t, samples=samples, fraction=frac(mc),
                                      error=frac(mc, "basin_fraction_error"))))
        log(f"    sweepcore v = {v:g}: exact {ex_t['wall_s']:.3f} s ({ex_t['cpu_s']:.3f} "
            f"CPU-s) {rows[-1]['exact']['fraction']:.5f}; sampled {mc_t['wall_s']:.3f} s "
            f"({mc_t['cpu_s']:.3f} CPU-s) {rows[-1]['sampled']['fraction']:.4f}")
    res = {"speeds": rows}
    if curve:
        grid = study.grid()
        c_t, ds = _timed(lambda: sc.basin_stability(grid, **box, route="exact",
                                                    ftol=b["ftol"], progress=False),
                         repeats)
        res["curve"] = dict(c_t, points=grid.size,
                            routes_exact=int((ds.basin_route.values == 0).sum()))
        log(f"    sweepcore curve of {grid.size} speeds (exact route): "
            f"{c_t['wall_s']:.2f} s ({c_t['cpu_s']:.2f} CPU-s)")
    return res


def ratios(peer, sc_side):
    """pybasin over sweepcore, per speed (wall and CPU) and for the curve."""
    by_v = {round(r["v"], 9): r for r in sc_side["speeds"]}
    rows = []
    for p in peer["speeds"]:
        s = by_v.get(round(p["v"], 9))
        if s is None:
            continue
        rows.append(dict(v=p["v"], **{f"{what}_{route}": p[f"{what}_s"] / s[route][f"{what}_s"]
                                      for what in ("wall", "cpu")
                                      for route in ("exact", "sampled")}))
    out = {"per_speed": rows}
    if "curve" in sc_side and peer["speeds"]:
        n = sc_side["curve"]["points"]
        per = {w: common.median([p[f"{w}_s"] for p in peer["speeds"]]) for w in ("wall", "cpu")}
        out["curve"] = {f"pybasin_{w}_s_extrapolated": per[w] * n for w in per}
        out["curve"].update({f"{w}": per[w] * n / sc_side["curve"][f"{w}_s"] for w in per})
    return out


def run(profile, outdir, official=False):
    """The section: pybasin live (or its saved results) and sweepcore in this run."""
    log("[7] pybasin (basin stability, published friction case)")
    speeds, samples = profile["pybasin_speeds"], profile["pybasin_samples"]
    res = {"load_before": common.load(), "speeds": speeds, "samples": samples}
    python = interpreter()
    peer = None
    if python is not None:
        try:
            peer = run_pybasin(python, speeds, samples)
            peer["source"] = "live"
            res["interpreter"] = str(python)
            for r in peer["speeds"]:
                log(f"    pybasin v = {r['v']:g}: {r['wall_s']:.2f} s ({r['cpu_s']:.2f} "
                    f"CPU-s), steady sliding {r['fraction']:.4f} +- {r['error']:.4f}; "
                    f"inside the cycle labelled stick-slip: "
                    f"{r['exact_check']['inside_labelled_stick_slip']}")
            if official:
                common.save_json(peer, SAVED)
        except (RuntimeError, subprocess.SubprocessError, OSError, ValueError) as err:
            res["live_error"] = str(err)[-2000:]
            log(f"    pybasin failed ({python}): {str(err)[-300:]}")
    if peer is None:
        res["interpreter"] = None
        if SAVED.exists():
            peer = json.loads(SAVED.read_text())
            peer["source"] = f"saved results ({SAVED.relative_to(common.ROOT)})"
            log(f"    pybasin's environment absent: its saved results of "
                f"{peer['machine']['date']} ({peer['command']})")
        else:
            log("    pybasin's environment absent and no saved results: sweepcore only")
    res["pybasin"] = peer
    peer_speeds = [r["v"] for r in peer["speeds"]] if peer else speeds
    res["sweepcore"] = sweepcore_side(peer_speeds, samples if peer is None else
                                      peer["settings"]["samples"],
                                      profile["pybasin_repeats"],
                                      curve=profile.get("pybasin_curve", True))
    if peer:
        res["ratios"] = ratios(peer, res["sweepcore"])
        for r in res["ratios"]["per_speed"]:
            log(f"    v = {r['v']:g}: pybasin / sweepcore exact {r['wall_exact']:.0f}x wall, "
                f"{r['cpu_exact']:.0f}x CPU; / sampled {r['wall_sampled']:.1f}x wall, "
                f"{r['cpu_sampled']:.1f}x CPU")
    res["load_after"] = common.load()
    return res

