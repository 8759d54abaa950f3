"""Compile time, measured in fresh processes.

Two uses:

``python benchmarks/compile_probe.py NV NA [map]`` (run by ``hopf_map.py`` in a new
interpreter with ``NUMBA_CACHE_DIR`` pointing at an empty directory, cold: every
kernel is compiled, and again at the same, now filled, directory, warm): import,
first call (compile or cache load), peak memory; prints one JSON line. Peak memory is
the process's peak resident set size (VmHWM of /proc/self/status; it includes the
interpreter, numpy, numba/LLVM), read after the imports, after the first call and
after one whole map.

``python benchmarks/compile_probe.py --kinds`` writes
``benchmarks/results/compile.json``: what the first use of each law kind costs a user
with an empty kernel cache. One fresh process per kind (analytic, table, leine), each
with its own empty ``SWEEPCORE_CACHE_DIR``: ``sweepcore.attractor`` of one slider,
again (warm), then ``sweepcore.sweep`` of 64 sliders, again (warm); the first call
less the second is what compiling cost. Then the main job (``sweepcore run
studies/hopf_map.toml``) from an empty cache and warm, back to back (the same
measurement as the Hopf-map section's). ``python -m benchmarks.report`` and a full
run put the paragraph of ``stored_section`` into benchmarks/README.md.

``python benchmarks/compile_probe.py --breakdown ENTRY METHOD KIND [...]`` (ENTRY a
key of ``sweepcore._kernels.entries.FACTORIES``, METHOD a method name, KIND a law
kind; several triples in turn) compiles those entry kernels, in that order, in one
fresh process with an empty kernel cache and prints one JSON line per entry: the
CPU seconds of its compilation, the part of them spent holding numba's LLVM lock
(LLVM's optimisation and machine code, the union of the ``numba:llvm_lock`` event
intervals; the rest is numba's own typing and lowering), and how many functions
numba compiled on the way, with the names compiled for more than one signature
(``kernels_compiled_more_than_once``: sweepcore's own, with those signatures: each
is a recompilation of the kernel and of all it calls, ``sweepcore/_kernels/jit.py``).
With ``NUMBA_OPT=0`` in the environment LLVM does not optimise: the drop bounds
what optimisation costs (the kernels' speed is then not the shipped one).
``--breakdown suite`` compiles what the default test run compiles, in its order;
``--save`` after the triples stores the lines in ``results/compile.json`` (key
``breakdown``), whose paragraph in benchmarks/README.md quotes them.

``python benchmarks/compile_probe.py --warm OUT.npz SIDE [CHECKOUT]`` times, warm
and on one thread, the maps of ``benchmarks/forced.py`` (two forced maps and the
Hopf map, SIDE x SIDE; CPU seconds, once each after a warm-up run) on the sweepcore
and benchmarks of CHECKOUT (default: this one) and saves their output arrays to
OUT.npz: run it alternately on two checkouts to compare a change's warm cost, and
compare the arrays for bit-identity.
"""
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

KINDS = ("analytic", "table", "leine")

# the child of --kinds: the first use of one law kind, in a process of its own
KIND_CHILD = """
import json, sys, time
t0 = time.perf_counter()
import numpy as np
import sweepcore as sc
t_import = time.perf_counter() - t0
kind = sys.argv[1]
if kind == "analytic":
    law = dict(r_y=1.0, alpha1=0.2, alpha2=0.05)
elif kind == "table":                   # the README's measured table
    speed = np.array([0.0, 0.1, 0.25, 0.5, 1.0, 2.0, 4.0])
    force = np.array([1.0, 0.93, 0.82, 0.68, 0.55, 0.51, 0.50])
    law = dict(law=sc.TableLaw(speed, force, static=1.1, name="measured"))
else:
    law = dict(law=sc.LeineLaw(f_s=1.0, delta=3.0))
base = dict(m=1.0, k=1.0, c=0.1)
res = {"kind": kind, "t_import": t_import}
for label, call in (
        ("attractor", lambda: sc.attractor(sc.Params(**base, v=0.5, **law))),
        ("sweep", lambda: sc.sweep(sc.Grid(**base, v=np.linspace(0.2, 3.0, 64), **law),
                                   progress=False))):
    for rep in ("first", "second"):
        c0, w0 = time.process_time(), time.perf_counter()
        call()
        res[f"{label}_{rep}_wall_s"] = time.perf_counter() - w0
        res[f"{label}_{rep}_cpu_s"] = time.process_time() - c0
print(json.dumps(res))
"""


def probe(nv, na, run_map):
    """The Hopf-map section's probe (see the module's docstring); one JSON line."""
    t0 = time.perf_counter()
    import numpy as np
    import numba  # noqa: F401
    t_numba = time.perf_counter() - t0
    from benchmarks import common
    t1 = time.perf_counter()
    from sweepcore.options import make_options
    from sweepcore._kernels.layout import NOBS
    t_import = time.perf_counter() - t1
    rss_import = common.peak_rss_mib()

    run = common.kernel()
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


# the entry kernels the default test run compiles, in the order it first calls them
# (the conftest's warm-up first); each compiled on an empty cache by --breakdown suite
SUITE = (("attractor_rows", "dop853", "polynomial"), ("trajectory", "dop853", "polynomial"),
         ("forced_rows", "dop853", "polynomial"), ("forced_rows", "dop853", "stribeck"),
         ("forced_rows", "dop853", "table"), ("forced_rows", "dop853", "leine"),
         ("attractor_rows", "dop853", "stribeck"), ("attractor_rows", "dop853", "table"),
         ("attractor_rows", "dop853", "leine"), ("slip_cycles_rows", "dop853", "polynomial"),
         ("slip_cycles_rows", "dop853", "stribeck"), ("slip_cycles_rows", "dop853", "table"),
         ("attractor_rows", "exact", "polynomial"), ("attractor_rows", "dopri5", "polynomial"),
         ("attractor_rows", "rk4", "polynomial"), ("attractor_rows", "gps", "polynomial"))


def _entry_arguments(name, kind):
    """Arrays of the types the Python side calls entry ``name`` with for ``kind``
    (the forced entries with the first forced excitation kind's sample data)."""
    from sweepcore import compiled
    from sweepcore._kernels import excitations
    from sweepcore._kernels import laws as kernel_laws
    lw = kernel_laws.SAMPLES[kind]
    if name in compiled.FORCED_ENTRIES:
        return compiled._arguments(name, lw, excitations.EXCITATIONS[1][3])
    return compiled._arguments(name, lw)


def breakdown(triples):
    """Compile each (entry, method, kind) in turn here (the caller gives this process
    an empty cache); one JSON line each (see the module's docstring)."""
    import collections
    from numba import typeof
    from numba.core import event
    from sweepcore._kernels import codes, entries

    class Record(event.Listener):
        """numba's compile events: the LLVM lock's CPU time, every function compiled,
        and each one's own CPU time (its compilation less the nested ones)."""

        def __init__(self):
            self.lock, self.depth, self.start, self.sigs = 0.0, 0, 0.0, []
            self.stack, self.own = [], collections.Counter()

        def on_start(self, ev):
            if ev.kind == "numba:llvm_lock":
                if self.depth == 0:
                    self.start = time.process_time()
                self.depth += 1
                return
            d = ev.data.get("dispatcher")
            py = getattr(d, "py_func", None)
            fn = getattr(py, "__qualname__", str(d))
            self.sigs.append((fn, str(ev.data.get("args")),
                              getattr(py, "__module__", "").startswith("sweepcore.")))
            self.stack.append([fn, time.process_time(), 0.0])

        def on_end(self, ev):
            if ev.kind == "numba:llvm_lock":
                self.depth -= 1
                if self.depth == 0:
                    self.lock += time.process_time() - self.start
                return
            fn, t0, nested = self.stack.pop()
            took = time.process_time() - t0
            self.own[fn] += took - nested
            if self.stack:
                self.stack[-1][2] += took

    for name, method, kind in triples:
        rec = Record()
        event.register("numba:llvm_lock", rec)
        event.register("numba:compile", rec)
        c0 = time.process_time()
        entries.entry(name, codes.METHOD_CODES[method]).compile(
            tuple(typeof(a) for a in _entry_arguments(name, kind)))
        cpu = time.process_time() - c0
        event.unregister("numba:llvm_lock", rec)
        event.unregister("numba:compile", rec)
        per = collections.Counter(n for n, _, _ in rec.sigs)
        print(json.dumps({"entry": name, "method": method, "kind": kind,
                          "cpu_s": round(cpu, 2), "llvm_lock_cpu_s": round(rec.lock, 2),
                          "numba_opt": os.environ.get("NUMBA_OPT", "default"),
                          "functions_compiled": len(rec.sigs),
                          "compiled_more_than_once": {n: c for n, c in per.items() if c > 1},
                          "kernels_compiled_more_than_once": {
                              n: [a for m, a, _ in rec.sigs if m == n]
                              for n, c in per.items() if c > 1 and
                              any(m == n and ours for m, _, ours in rec.sigs)},
                          "own_cpu_s_top": {n: round(t, 2)
                                            for n, t in rec.own.most_common(12)}}),
              flush=True)


def breakdown_fresh(args, opt=None):
    """``breakdown`` in a fresh process with an empty cache: yields its JSON lines,
    parsed, as they come."""
    with tempfile.TemporaryDirectory(prefix="sweepcore-breakdown-") as tmp:
        env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
        env["SWEEPCORE_CACHE_DIR"] = tmp
        if opt is not None:
            env["NUMBA_OPT"] = str(opt)
        with subprocess.Popen([sys.executable, __file__, "--breakdown-here", *args],
                              env=env, cwd=ROOT, stdout=subprocess.PIPE,
                              stderr=subprocess.DEVNULL, text=True) as child:
            for line in child.stdout:
                if line.startswith("{"):
                    yield json.loads(line)
        if child.returncode != 0:
            raise RuntimeError(f"the breakdown process failed ({child.returncode})")


def save_breakdown(args, save, path=None):
    """Print ``breakdown_fresh(args)``'s lines as they come; with ``save``, store them
    with the machine and the load in ``results/compile.json`` (key ``breakdown``)."""
    from benchmarks import common
    res = {"command": "python benchmarks/compile_probe.py --breakdown " + " ".join(args),
           "machine": common.machine(), "load_before": common.load(), "entries": []}
    for line in breakdown_fresh(args):
        print(json.dumps(line), flush=True)
        res["entries"].append(line)
    res["load_after"] = common.load()
    if save:
        path = Path(path or common.RESULTS / "compile.json")
        stored = json.loads(path.read_text()) if path.is_file() else {}
        stored["breakdown"] = res
        common.save_json(stored, path)
        common.log(f"written {path}")


def warm(path, side=48):
    """The warm maps of ``benchmarks.forced`` (see the module's docstring): prints
    one JSON line of CPU seconds per map and saves the outputs to ``path``."""
    import numba
    import numpy as np
    import sweepcore
    from benchmarks import forced
    from sweepcore.options import make_options
    numba.set_num_threads(1)
    grids, hopf = forced.grids(side)
    grids["hopf"] = hopf
    o = make_options("auto", tol=1e-8)
    cpu, outs = {}, {}
    for name, grid in grids.items():
        forced.run(grid, o)
        cpu[name], outs[name] = forced.run(grid, o)
    np.savez(path, **outs)
    print(json.dumps({"sweepcore": str(Path(sweepcore.__file__).parent), "side": side,
                      "cpu_s": cpu, "load": os.getloadavg()[0]}), flush=True)


def first_use(kind, timeout=3600):
    """The first use of law ``kind`` in a fresh process with an empty kernel cache:
    the child's timings, its CPU seconds with its children (the second compiler),
    and the compile seconds of each kernel it compiled."""
    import resource
    with tempfile.TemporaryDirectory(prefix=f"sweepcore-first-{kind}-") as tmp:
        env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
        env["SWEEPCORE_CACHE_DIR"] = tmp
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        cp = subprocess.run([sys.executable, "-c", KIND_CHILD, kind], env=env, cwd=ROOT,
                            capture_output=True, text=True, timeout=timeout)
        wall = time.perf_counter() - t0
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        if cp.returncode != 0:
            return {"kind": kind, "error": cp.stderr[-2000:]}
        res = json.loads(cp.stdout.strip().splitlines()[-1])
        seconds = {}
        for f in Path(tmp).glob("numba-*/sweepcore_compile_seconds.json"):
            seconds.update(json.loads(f.read_text()))
    res.update(process_wall_s=wall, process_cpu_s=(r1.ru_utime - r0.ru_utime)
               + (r1.ru_stime - r0.ru_stime), compile_seconds=seconds)
    for label in ("attractor", "sweep"):
        res[f"{label}_compile_s"] = res[f"{label}_first_wall_s"] - res[f"{label}_second_wall_s"]
    return res


def kinds(path=None):
    """Every kind's first use, then the main job cold and warm; saved to ``path``."""
    from benchmarks import common, hopf_map
    res = {"machine": common.machine(), "load_before": common.load(), "kinds": {}}
    for kind in KINDS:
        r = res["kinds"][kind] = first_use(kind)
        common.log(f"first use of the {kind} law: " + (
            r["error"] if "error" in r else
            f"attractor {r['attractor_first_wall_s']:.1f} s (then "
            f"{r['attractor_second_wall_s']:.3f} s), sweep {r['sweep_first_wall_s']:.1f} s "
            f"(then {r['sweep_second_wall_s']:.3f} s), process {r['process_cpu_s']:.1f} CPU-s"))
    res["main_job"] = hopf_map.main_job()
    res["load_after"] = common.load()
    path = Path(path or common.RESULTS / "compile.json")
    common.save_json(res, path)
    common.log(f"written {path}")
    return res


def stored_section(path=None) -> str:
    """The benchmarks/README.md paragraph of the stored ``results/compile.json``."""
    path = Path(path or ROOT / "benchmarks" / "results" / "compile.json")
    if not path.is_file():
        return ""
    R = json.loads(path.read_text())
    from benchmarks.report import fill, s
    parts = []
    for kind in KINDS:
        r = R["kinds"].get(kind, {})
        if "error" in r or not r:
            parts.append(f"{kind}: failed")
            continue
        kernels = ", ".join(f"`{k}` {s(v)}" for k, v in sorted(r["compile_seconds"].items()))
        parts.append(f"**{kind}** {s(r['attractor_first_wall_s'])} wall "
                     f"({s(r['attractor_first_cpu_s'])} CPU) for the first `attractor`, "
                     f"{s(r['attractor_second_wall_s'])} the second; the first `sweep` "
                     f"after it {s(r['sweep_first_wall_s'])}, the second "
                     f"{s(r['sweep_second_wall_s'])}; kernels compiled: {kernels}; "
                     f"{s(r['process_cpu_s'])} CPU in all")
    mj = R["main_job"]
    main = (f"{s(mj['cold']['wall_s'])} wall ({s(mj['cold']['cpu_s'])} CPU) cold against "
            f"{s(mj['warm']['wall_s'])} ({s(mj['warm']['cpu_s'])} CPU) warm: "
            f"**{mj['ratio_wall']:.2f}x** wall, "
            f"{mj['cold']['cpu_s'] / mj['warm']['cpu_s']:.2f}x CPU"
            if "ratio_wall" in mj else "failed")
    m = R["machine"]
    return fill("compile_kinds", date=m["date"], commit=m["git_commit"][:10],
                load=f"{R['load_before']:.1f}-{R['load_after']:.1f}", kinds=". ".join(parts),
                main=main, breakdown=_breakdown_text(R.get("breakdown")))


def _breakdown_text(B) -> str:
    """The sentences of a stored ``--breakdown`` (empty where none is stored)."""
    if not B:
        return ""
    from benchmarks.report import s
    each = "; ".join(
        f"`{e['entry']}` ({e['method']}, {e['kind']}) {s(e['cpu_s'])} CPU, "
        f"{s(e['llvm_lock_cpu_s'])} of it in LLVM, {e['functions_compiled']} functions"
        for e in B["entries"])
    twice = sorted({n for e in B["entries"]
                    for n in e.get("kernels_compiled_more_than_once", {})})
    if any("kernels_compiled_more_than_once" in e for e in B["entries"]):
        each += (". Compiled for more than one signature within an entry: "
                 + (", ".join(f"`{n}`" for n in twice) if twice else
                    "none of sweepcore's kernels (numba's own helpers only)"))
    m = B["machine"]
    return (f"\n\nWhere a compilation's time goes: `{B['command']} --save` "
            f"({m['date']}, commit `{m['git_commit'][:10]}`, 1-minute load "
            f"{B['load_before']:.1f}-{B['load_after']:.1f}) compiles those entry kernels "
            "in turn in one fresh process with an empty cache (a kernel another one "
            "already compiled is loaded, not compiled again) and records numba's compile "
            "events: the CPU seconds of each, the part spent under LLVM's lock "
            "(optimisation and machine code; the rest is numba's typing and lowering), "
            f"and how many functions numba compiled on the way: {each}.")


if __name__ == "__main__":
    if sys.argv[1:2] in (["-h"], ["--help"]):
        print("usage: compile_probe.py [-h] [--kinds | --breakdown ENTRY METHOD KIND ... "
              "[--save] | --warm OUT.npz SIDE [CHECKOUT] | NV NA [map]]\n")
        print(__doc__)
    elif sys.argv[1:2] == ["--kinds"]:
        kinds()
    elif sys.argv[1:2] == ["--warm"]:
        if sys.argv[4:5]:
            sys.path.insert(0, str(Path(sys.argv[4]).resolve()))
        warm(sys.argv[2], int(sys.argv[3]))
    elif sys.argv[1:2] in (["--breakdown"], ["--breakdown-here"]):
        args = [a for a in sys.argv[2:] if a != "--save"]
        save = "--save" in sys.argv[2:]
        if args == ["suite"]:
            args = [a for t in SUITE for a in t]
        if len(args) % 3 or not args:
            sys.exit("--breakdown takes ENTRY METHOD KIND triples (or 'suite')")
        if sys.argv[1] == "--breakdown":
            save_breakdown(args, save)
        else:
            breakdown([tuple(args[i:i + 3]) for i in range(0, len(args), 3)])
    else:
        probe(int(sys.argv[1]), int(sys.argv[2]), len(sys.argv) > 3 and sys.argv[3] == "map")
