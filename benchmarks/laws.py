"""The cost of a friction law given as a table (``sweepcore.TableLaw``) against the
analytic law it samples, and what a second table costs to compile.

The case is bSTAB's friction oscillator (m = k = 1, c = 0.1 and the exponential
Stribeck law r_y = 1, r_k = 0.5, v_s = 0.5; Stender et al., bSTAB, 2022): the analytic
law, and the same law sampled at 400 speeds on [0, 8] cm/s (a table as a user with a
measured curve would bring it). A grid of belt speeds (across the Hopf speed ln(10)/2)
and initial positions runs through the kernels of ``sweep`` for each, the same rows,
same threads; the per-point cost ratio is the median over paired runs of table /
analytic. The table's answers are compared with the analytic ones (their difference is
the representation's error, ``law_deviation``). A second, different table then runs
in the same process while numba's compile events are counted: none is expected.
"""
from __future__ import annotations

import time

import numpy as np

from . import common

BSTAB = dict(m=1.0, k=1.0, c=0.1)
STRIBECK = dict(r_y=1.0, r_k=0.5, v_s=0.5)
SAMPLES = 400
SPEED_MAX = 8.0


def bstab_force(s):
    """bSTAB's sliding force at speeds s >= 0 [kN] (F(0+) = r_y = 1 at s = 0)."""
    return 0.5 + 0.5 * np.exp(-np.asarray(s) / 0.5)


def _kernel_run(grid, tol=1e-8):
    """A function running the attractor kernels of ``sweep`` on every row of the grid
    (no xarray, no progress): the per-point cost of the law, nothing else."""
    from sweepcore import execute
    from sweepcore._kernels.layout import NOBS
    from sweepcore.options import make_options
    P = grid.rows(0, grid.size)
    o = make_options("auto", tol)
    out = np.empty((P.shape[0], NOBS))

    def run():
        execute.attractors(P, grid.laws, o, out, True)
        return out
    return run


def _compiles(fn):
    """(result, names of the functions numba compiled while fn() ran)."""
    from numba.core import event
    names = []

    class Count(event.Listener):
        def on_start(self, ev):
            names.append(ev.data["dispatcher"].py_func.__qualname__)

        def on_end(self, ev):
            pass
    with event.install_listener("numba:compile", Count()):
        res = fn()
    return res, names


def run(profile, outdir) -> dict:
    import sweepcore as sc
    from sweepcore._kernels import layout as K
    common.log("[laws] a table of bSTAB's law (400 points) against the analytic law")
    nv, nx = profile["laws_shape"]
    v = np.linspace(0.2, 3.0, nv)
    x0 = np.linspace(-2.0, 2.0, nx)
    table = sc.TableLaw(np.linspace(0.0, SPEED_MAX, SAMPLES),
                        bstab_force(np.linspace(0.0, SPEED_MAX, SAMPLES)), name="bstab-400")
    analytic = sc.Grid(**BSTAB, **STRIBECK, v=v, x0=x0, xdot0=0.0)
    tabled = sc.Grid(**BSTAB, v=v, x0=x0, xdot0=0.0, law=table)
    runs = {"analytic": _kernel_run(analytic), "table": _kernel_run(tabled)}
    first = {}
    for name, fn in runs.items():             # first call: compiles (fresh cache) or loads
        t0 = time.perf_counter()
        fn()
        first[name] = time.perf_counter() - t0
    times = {"analytic": [], "table": []}
    for _ in range(profile["laws_repeats"]):
        for name, fn in runs.items():
            t0 = time.perf_counter()
            fn()
            times[name].append(time.perf_counter() - t0)
    ratio = common.median([t / a for t, a in zip(times["table"], times["analytic"])])
    a, t = runs["analytic"](), runs["table"]()
    from sweepcore.law import length_scale
    L = length_scale(analytic.rows(0, analytic.size))   # r_y / k + |v| / omega [cm]
    amp = np.abs(t[:, K.OB_AMPLITUDE] - a[:, K.OB_AMPLITUDE]) / L
    status_a, status_t = a[:, K.OB_STATUS], t[:, K.OB_STATUS]
    regime_a, regime_t = a[:, K.OB_REGIME], t[:, K.OB_REGIME]
    n = int(analytic.size)
    res = {
        "case": "bSTAB: m = k = 1, c = 0.1, r_y = 1, r_k = 0.5, v_s = 0.5",
        "table": f"{SAMPLES} speeds on [0, {SPEED_MAX:g}] cm/s, quintic spline",
        "law_deviation": table.deviation,
        "grid": {"nv": nv, "nx": nx, "n_points": n, "v": [float(v[0]), float(v[-1])],
                 "x0": [float(x0[0]), float(x0[-1])]},
        "first_call_s": first,
        "times_s": times,
        "median_s": {k: common.median(x) for k, x in times.items()},
        "per_point_us": {k: 1e6 * common.median(x) / n for k, x in times.items()},
        "ratio_table_over_analytic": ratio,
        "max_amp_diff_over_L": float(np.nanmax(amp)),
        "status_mismatches": int(np.sum(status_a != status_t)),
        "regime_mismatches": int(np.sum(regime_a != regime_t)),
    }
    common.log(f"    analytic {res['per_point_us']['analytic']:.1f} us/point, table "
               f"{res['per_point_us']['table']:.1f} us/point: {ratio:.2f}x (target: at "
               f"most 3x); max |amp diff| / L {res['max_amp_diff_over_L']:.2e}, "
               f"{res['regime_mismatches']} regime mismatches")
    # a second, different table in the same process
    other = sc.TableLaw(np.linspace(0.0, SPEED_MAX, 97),
                        0.6 + 0.4 / (1.0 + 3.0 * np.linspace(0.0, SPEED_MAX, 97)),
                        static=1.1, name="second")
    second = _kernel_run(sc.Grid(**BSTAB, v=v, x0=x0, xdot0=0.0, law=other))
    t0 = time.perf_counter()
    _, names = _compiles(second)
    res["second_table"] = {"seconds": time.perf_counter() - t0, "compiled": names,
                           "n_compiled": len(names)}
    common.log(f"    a second table: {res['second_table']['seconds']:.3f} s, "
               f"{len(names)} functions compiled")
    return res
