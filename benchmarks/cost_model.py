"""Section 5: achieved floating-point rate of the hot loop against the machine's peak.

Flops per stepper call are counted from the source (``ast``), not guessed:
every ``+ - * /`` between values is one flop (a negation is not counted, a division
and a square root count as one flop each although they cost 4-20 cycles);
``abs``/``max``/``min`` and comparisons are not flops. Calls to other kernels
(``zdd`` -> ``friction``, ``scales``, ...) are expanded, found through the caller's
globals, so the count follows the source as it changes. The ``if want_q:`` block
(quadratures of x, xdot^2 and the friction power, needed on accepted steps only) is
counted apart: event polishing calls the stepper without it. The driver's own work
per step (event scan on the Hermite cubic, bookkeeping) is not counted, so the
achieved rate is a lower bound of the arithmetic actually done.

Achieved rate = (stepper calls, column OB_NSTEPS of the kernel's output, summed
over the map) x (flops per call) / (wall time of the map). Peak = cores x clock x
flops/cycle, with the clock read from /proc/cpuinfo and two assumptions stated:
16 flops/cycle/core for AVX2 code (two 256-bit FMA pipes x 4 doubles x 2) and
4 flops/cycle/core for scalar code (two FMA pipes x 1 double x 2) - the kernel is
scalar, sequential code (one point per thread, a chain of dependent stages).
"""
from __future__ import annotations

import ast
import inspect
import textwrap

from . import common
from .common import log

FLOP_OPS = (ast.Add, ast.Sub, ast.Mult, ast.Div)


def _fn_ast(fn):
    fn = getattr(fn, "py_func", fn)
    return ast.parse(textwrap.dedent(inspect.getsource(fn))).body[0]


def _expandable(obj):
    """The Python function behind a call target that belongs to the counted code
    (a numba kernel or a plain function of sweepcore's kernels or of peers.py). A
    function of the law interface (``sweepcore/_kernels/law.py``) counts as the map's
    law kind's (the polynomial law of ``laws/analytic.py``) where that kind defines
    it: the interface resolves it so when it compiles."""
    f = getattr(obj, "py_func", obj)
    mod = getattr(f, "__module__", "") or ""
    if mod == "sweepcore._kernels.law":
        from sweepcore._kernels.laws import analytic
        f = getattr(getattr(analytic, f.__name__, None), "py_func", f)
        mod = f.__module__
    if inspect.isfunction(f) and (mod.startswith("sweepcore") or mod.endswith("peers")):
        return f
    return None


def count_flops(fn, skip_if=("want_q",)):
    """{'flops', 'sqrt', 'other', 'skipped_flops', 'expanded'} of one call of ``fn``.

    Calls to other kernels (resolved through the caller's globals) are expanded and
    counted per call; ``skip_if``: names whose ``if NAME:`` bodies are counted in
    'skipped_flops' instead.
    """
    cache = {}
    expanded = set()

    def fcount(f):
        if f.__name__ not in cache:
            expanded.add(f.__name__)
            cache[f.__name__] = walk(_fn_ast(f).body, f.__globals__)
        return cache[f.__name__]

    def walk(nodes, glb):
        c = {"flops": 0, "sqrt": 0, "other": 0, "skipped_flops": 0}

        def add(d, into="flops"):
            for k, v in d.items():
                if into == "skipped_flops" and k == "flops":
                    c["skipped_flops"] += v
                else:
                    c[k] += v

        for node in nodes:
            if isinstance(node, ast.If) and isinstance(node.test, ast.Name) \
                    and node.test.id in skip_if:
                add(walk(node.body, glb), into="skipped_flops")
                add(walk(node.orelse, glb))
                continue
            for sub in ast.walk(node):
                if isinstance(sub, ast.BinOp) and isinstance(sub.op, FLOP_OPS + (ast.Pow,)):
                    c["flops"] += 1
                elif isinstance(sub, ast.Call):
                    name = sub.func.attr if isinstance(sub.func, ast.Attribute) else \
                        getattr(sub.func, "id", "")
                    target = _expandable(glb.get(name)) if name in glb else None
                    if target is not None:
                        add(fcount(target))
                    elif name == "sqrt":
                        c["sqrt"] += 1
                    elif name in ("abs", "max", "min"):
                        c["other"] += 1
        return c

    f = getattr(fn, "py_func", fn)
    res = walk(_fn_ast(f).body, f.__globals__)
    res["expanded"] = sorted(expanded)
    return res


def map_method(tol=1e-8):
    """The stepper "auto" runs the map with (the rule of ``sweepcore.compiled``)."""
    from sweepcore import compiled
    from sweepcore._kernels import stepper
    from sweepcore.laws import ANALYTIC
    from sweepcore.options import make_options
    P = common.rows([5.0], [0.01])
    return stepper.METHOD_NAMES[int(compiled.methods_of(P, (ANALYTIC,),
                                                        make_options("auto", tol=tol))[0])]


def stepper_flops():
    from sweepcore._kernels import dop853, dopri5, law, rk4
    from . import peers
    return {"zdd (RHS, friction law eq. 40 + eq. 41)": count_flops(law.zdd),
            "sweepcore dopri5_step": count_flops(dopri5.dopri5_step),
            "sweepcore dop853_step": count_flops(dop853.dop853_step),
            "sweepcore rk4_step": count_flops(rk4.rk4_step),
            "numba RK4 peer step": count_flops(peers._rk4)}


def run(profile, outdir, hopf_res, peer_res=None):
    log("[5] cost model")
    model, mhz, flags = common._cpuinfo()
    import numba
    cores = numba.config.NUMBA_NUM_THREADS
    ghz = mhz / 1000.0
    counts = stepper_flops()
    method = map_method()
    d5 = counts[f"sweepcore {method}_step"]
    per_call = d5["flops"] + d5["sqrt"]
    per_call_q = per_call + d5["skipped_flops"]
    peak_simd = cores * ghz * 16.0
    peak_scalar = cores * ghz * 4.0
    default = next(r for r in hopf_res["kernel"] if r["tol"] == 1e-8)
    steps = default["steps_total"]
    t = default["median_s"]
    # per-core cost from the 1-thread run (no idle core at the end of an uneven split)
    t1 = hopf_res.get("threads", {}).get("grid order", {}).get("1", {}).get("median_s")
    lo = steps * per_call / t / 1e9
    hi = steps * per_call_q / t / 1e9
    res = {"cpu_model": model, "clock_ghz": ghz, "cores": cores,
           "simd_flags": sorted(f for f in flags if f in ("avx", "avx2", "fma", "avx512f")),
           "flop_counts": counts,
           "map_stepper": method, "stepper_flops_per_call": per_call,
           "stepper_flops_per_call_with_quadratures": per_call_q,
           "peak_gflops_avx2_fma": peak_simd, "peak_gflops_scalar_fma": peak_scalar,
           "map": {"tol": 1e-8, "stepper_calls": steps, "wall_s": t,
                   "ns_per_call_per_core": t * cores / steps * 1e9,
                   "achieved_gflops_low": lo, "achieved_gflops_high": hi,
                   "fraction_of_avx2_peak": hi / peak_simd,
                   "fraction_of_scalar_peak": hi / peak_scalar,
                   "cycles_per_call": t * cores * ghz * 1e9 / steps,
                   "one_thread_wall_s": t1,
                   "ns_per_call_one_thread": t1 / steps * 1e9 if t1 else None,
                   "cycles_per_call_one_thread": t1 * ghz * 1e9 / steps if t1 else None,
                   "achieved_gflops_one_core_high": steps * per_call_q / t1 / 1e9
                   if t1 else None}}
    log(f"    {method} step: {per_call} flops ({per_call_q} with quadratures); map: "
        f"{steps:.3g} calls in {t:.2f} s = {res['map']['ns_per_call_per_core']:.0f} ns/call/core,"
        f" {lo:.2f}-{hi:.2f} GFLOP/s vs peak {peak_scalar:.1f} (scalar) / {peak_simd:.1f} (AVX2)")
    if peer_res and "numba_peer_map" in peer_res:
        pm = peer_res["numba_peer_map"]
        pf = counts["numba RK4 peer step"]["flops"]
        g = pm["steps_total_run"] * pf / pm["seconds_run"] / 1e9
        res["numba_peer"] = {"flops_per_step": pf, "steps": pm["steps_total_run"],
                             "wall_s": pm["seconds_run"], "achieved_gflops": g,
                             "ns_per_step_per_core": pm["seconds_run"] * cores
                             / pm["steps_total_run"] * 1e9,
                             "fraction_of_scalar_peak": g / peak_scalar}
        log(f"    numba RK4 peer: {pf} flops/step, {g:.2f} GFLOP/s, "
            f"{res['numba_peer']['ns_per_step_per_core']:.1f} ns/step/core")
    return res
