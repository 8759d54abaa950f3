"""A hostile-input and fault battery of the newer public functions: basin_stability,
slip_cycles, bifurcation_diagram, locate_boundaries, continue_boundary, the plotting
API, the ``sweepcore basins`` command and the friction laws' interfaces (probes named
"law ...": ``--only law``).

Every probe runs in its own process (forked from this one, which has imported
sweepcore but run no kernel), under an address-space limit (``--memory-gib``) and a
time limit (``--timeout``), and is classified:

* refused: a ValueError/TypeError/FileNotFoundError (a refusal) whose message names
  what the probe expects (the parameter), or a command that exits 2 naming it;
* valid: a probe of valid input that returned, and whose result passes the probe's
  check (invariants: fractions sum to one, labels agree with codes, the figure
  draws what was asked, a file left as it was, ...);
* silent-bad: input that should have been refused was taken, or a result failed
  its check;
* crash: any other exception (a refusal of valid input included), exit code 1, or
  a process killed by a signal;
* hang: the time limit passed.

    python benchmarks/battery.py [--timeout 60] [--memory-gib 6] [--only WORD]
                                 [--json FILE] [--list] [-v]

Run it against another checkout with ``PYTHONPATH=/path/to/checkout``: the probes
only use the public API, so the same battery measures before and after a change.
"""
from __future__ import annotations

import argparse
import io
import json
import math
import multiprocessing as mp
import os
import resource
import signal
import sys
import tempfile
import time
import traceback
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import numpy as np

REFUSALS = (ValueError, TypeError, FileNotFoundError)
STRIBECK = dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.5, c=0.1)
PAPER = dict(m=5.0, k=50.0, r_y=10.0, alpha1=1.0)
SUPER = dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.5, c=0.02, alpha1=0.6, alpha2=0.1)
BOX = dict(x0=(-2.0, 2.0), xdot0=(0.0, 2.0))
HUGE = 10 ** 5             # axis length of the 1e10-point grid (two axes)


# ------------------------------------------------------------------ grids
def sc():
    import sweepcore
    return sweepcore


def g1(*vs, **kw):
    """A Stribeck grid over v (bistable between 1.151 and 1.837 cm/s)."""
    return sc().Grid(**{**STRIBECK, **kw}, v=np.array(vs or (1.3, 1.6)))


def huge():
    """1e10 points from two 1e5-value axes (1.6 MB of axes)."""
    ax = np.linspace(1.0, 2.0, HUGE)
    return sc().Grid(**{**STRIBECK, "c": np.linspace(0.05, 0.2, HUGE)}, v=ax)


def diagram_grid(n=6):
    return sc().Grid(**STRIBECK, v=np.linspace(1.0, 2.0, n))


def boundary_grid():
    return sc().Grid(**PAPER, v=np.linspace(3.0, 8.0, 6), alpha2=[0.01, 0.02])


# ------------------------------------------------------------------ checks
def basins_ok(ds) -> str | None:
    from sweepcore._kernels import codes
    names = [str(n) for n in ds.attractor.values]
    regimes = [int(r) for r in np.atleast_1d(ds.attractor_regime.values)]
    for n, r in zip(names, regimes):
        if not n.startswith(codes.REGIME_NAMES.get(r, "?")):
            return f"attractor {n!r} labelled with regime {codes.REGIME_NAMES.get(r)}"
    total = ds.basin_fraction.sum("attractor").values
    answered = np.isfinite(ds.basin_fraction.values).all(axis=-1)
    if answered.any() and not np.allclose(total[answered], 1.0, atol=1e-9):
        return "fractions of an answered point do not sum to 1"
    return None


def cycles_ok(ds) -> str | None:
    mu, st = ds.cycle_floquet.values, ds.cycle_stability.values
    if np.any((st == 0) & ~(mu < 1)) or np.any((st == 1) & ~(mu > 1)):
        return "cycle_stability disagrees with cycle_floquet"
    return None


def figure_ok(fig, wants=()) -> str | None:
    from matplotlib.figure import Figure
    if not isinstance(fig, Figure) or not fig.axes:
        return f"not a drawn Figure: {type(fig).__name__}"
    text = " ".join(a.get_title() + " " + a.get_ylabel() + " " + a.get_xlabel()
                    for a in fig.axes)
    missing = [w for w in wants if w not in text]
    return f"panels without {missing}" if missing else None


def unchanged(path, text) -> str | None:
    p = Path(path)
    if p.is_symlink() or not p.is_file():
        return f"{p.name} was replaced"
    return None if p.read_bytes() == text.encode() else f"{p.name} was overwritten"


# ------------------------------------------------------------------ fixtures
def make_fixtures(work: Path) -> None:
    """Result files of every kind, for the plotting probes (run in a child)."""
    s = sc()
    files = {
        "sweep2d": lambda: s.sweep(s.Grid(**PAPER, v=np.linspace(3, 8, 6),
                                          alpha2=[0.01, 0.02, 0.03]), progress=False),
        "stribeck": lambda: s.sweep(s.Grid(**{**STRIBECK, "c": [0.05, 0.1, 0.2]},
                                           v=np.linspace(0.5, 2.5, 6)), progress=False),
        "sweep1d": lambda: s.sweep(s.Grid(**PAPER, alpha2=0.01, v=np.linspace(3, 8, 6)),
                                   progress=False),
        "simulation": lambda: s.simulate(s.Params(**PAPER, v=5.0, alpha2=0.01), 2.0),
        "diagram": lambda: s.bifurcation_diagram(diagram_grid(), boundaries=False),
        "cycles": lambda: s.slip_cycles(g1(1.3, 1.6)),
        "basins": lambda: s.basin_stability(g1(1.3, 1.6, 1.9), **BOX, progress=False),
        "basins2d": lambda: s.basin_stability(
            s.Grid(**{**STRIBECK, "c": np.array([0.1, 0.12])}, v=np.array([1.3, 1.6])),
            **BOX, progress=False),
        "boundaries": lambda: s.locate_boundaries(boundary_grid()),
    }
    for name, make in files.items():
        s.write_netcdf(make(), work / f"{name}.nc")


def fx(name):
    return sc().open_result(Path(os.environ["BATTERY_WORK"]) / f"{name}.nc")


# ------------------------------------------------------------------ probes
PROBES = []


def probe(name, call, expect="refuse", names=(), check=None):
    """``call()`` runs in the child; ``expect`` "refuse" (a message naming one of
    ``names``) or "valid" (``check(result)`` None)."""
    PROBES.append(dict(name=name, call=call, expect=expect, names=tuple(names),
                       check=check))


def bs(**kw):
    return lambda: sc().basin_stability(kw.pop("grid", None) or g1(), progress=False,
                                        **{**BOX, **kw})


HOSTILE_INT = [None, "10", True, 2.5, float("nan"), -1, 0, 10 ** 400, 2 ** 63, 10 ** 20,
               10 ** 12, 10 ** 9]
HOSTILE_REAL = [None, "1e-6", True, float("nan"), float("inf"), -1.0, 0.0, 1.0, 10 ** 400,
                [1e-6]]
HOSTILE_BOX = [(10 ** 400, 1), (1.0, 1.0), (2.0, -2.0), (float("nan"), 1.0),
               (0.0, float("inf")), "ab", (1.0, 2.0, 3.0), None, 5.0, ((1, 2), (3, 4)),
               (-10 ** 400, 0)]


def basin_probes():
    for k in ("samples", "checks"):
        for v in HOSTILE_INT:
            kw = {k: v}
            if k == "samples":
                kw["route"] = "sampled"
            probe(f"basin_stability {k}={v!r:.30}", bs(**kw), names=(k,))
    for v in (-1, 2.5, None, "0", 10 ** 400, 2 ** 64):
        probe(f"basin_stability seed={v!r:.30}", bs(seed=v), names=("seed",))
    for k in ("x0", "xdot0"):
        for v in HOSTILE_BOX:
            probe(f"basin_stability {k}={v!r:.30}", bs(**{k: v}), names=(k,))
    for k in ("ftol", "match", "tol"):
        for v in HOSTILE_REAL:
            probe(f"basin_stability {k}={v!r:.30}", bs(**{k: v}), names=(k,))
    for k, vals in (("route", ("fast", None, 5, "EXACT")),
                    ("sampling", ("sobol", None, 3)),
                    ("method", ("rk45", None, 4)),
                    ("chunks", (0, -1, 1.5, True, "2")),
                    ("scheduler", ("foo", 5)), ("client", ("foo", 5)),
                    ("progress", ("yes",)), ("overwrite", ("no",))):
        for v in vals:
            probe(f"basin_stability {k}={v!r}", bs(**{k: v}), names=(k,))
    probe("basin_stability tolerance=1e-8", bs(tolerance=1e-8), names=("tolerance",))
    probe("basin_stability method=gps route=exact", bs(method="gps", route="exact"),
          names=("gps",))
    for g, label in ((None, "None"), ({"m": 1}, "dict")):
        probe(f"basin_stability grid={label}",
              lambda g=g: sc().basin_stability(g), names=("grid",))
    probe("basin_stability swept x0", bs(grid=g1(x0=np.array([0.0, 1.0]))),
          names=("x0",))
    probe("basin_stability of 1e10 points", bs(grid=huge()), names=("points", "memory"))
    probe("basin_stability of 1e10 points, sampled",
          bs(grid=huge(), route="sampled", samples=10), names=("points", "memory"))
    probe("basin_stability max_steps=0", bs(max_steps=0), names=("max_steps",))
    # valid input
    probe("basin_stability exact", bs(route="exact"), "valid", check=basins_ok)
    probe("basin_stability sampled", bs(route="sampled", samples=30), "valid",
          check=basins_ok)
    probe("basin_stability halton", bs(route="sampled", samples=30, sampling="halton"),
          "valid", check=basins_ok)
    probe("basin_stability grid sampling", bs(route="sampled", samples=30,
                                              sampling="grid"), "valid", check=basins_ok)
    probe("basin_stability exact where it does not apply",
          bs(grid=sc().Grid(**SUPER, v=np.array([0.9 * 1.408])), route="exact"),
          "valid", check=basins_ok)
    probe("basin_stability samples=1", bs(route="sampled", samples=1), "valid",
          check=basins_ok)
    probe("basin_stability chunks=1 synchronous",
          bs(route="sampled", samples=20, chunks=1, scheduler="synchronous"), "valid",
          check=basins_ok)


def cy(**kw):
    return lambda: sc().slip_cycles(kw.pop("grid", None) or g1(), **kw)


def cycle_probes():
    for v in HOSTILE_REAL:
        probe(f"slip_cycles tol={v!r:.30}", cy(tol=v), names=("tol",))
    for v in ("gps", "rk45", None):
        probe(f"slip_cycles method={v!r}", cy(method=v), names=("method",))
    probe("slip_cycles method=exact (Stribeck)", cy(method="exact"), names=("exact",))
    for v in (0, -1, 1.5, True):
        probe(f"slip_cycles chunks={v!r}", cy(chunks=v), names=("chunks",))
    for v in HOSTILE_INT[:9]:
        probe(f"slip_cycles max_steps={v!r:.30}", cy(max_steps=v), names=("max_steps",))
    probe("slip_cycles of 1e10 points", cy(grid=huge()), names=("points", "memory"))
    probe("slip_cycles grid=None", lambda: sc().slip_cycles(None), names=("grid",))
    probe("slip_cycles swept x0", cy(grid=g1(x0=np.array([0.0, 1.0]))), names=("x0",))
    probe("slip_cycles tolerance=1e-8", cy(tolerance=1e-8), names=("tolerance",))
    probe("slip_cycles scheduler='foo'", cy(scheduler="foo"), names=("scheduler",))
    probe("slip_cycles", cy(), "valid", check=cycles_ok)
    probe("slip_cycles synchronous chunks=1", cy(scheduler="synchronous", chunks=1),
          "valid", check=cycles_ok)


def dg(**kw):
    return lambda: sc().bifurcation_diagram(kw.pop("grid", None) or diagram_grid(),
                                            boundaries=kw.pop("boundaries", False),
                                            **kw)


def diagram_probes():
    for v in ("x", "x0", None, 5, "V"):
        probe(f"bifurcation_diagram along={v!r}", dg(along=v), names=("along",))
    for v in ("sideways", None, 1):
        probe(f"bifurcation_diagram sweep={v!r}", dg(sweep=v), names=("sweep",))
    for k in ("boundaries", "unstable"):
        probe(f"bifurcation_diagram {k}='no'", dg(**{k: "no"}), names=(k,))
    for v in HOSTILE_REAL:
        probe(f"bifurcation_diagram tol={v!r:.30}", dg(tol=v), names=("tol",))
    probe("bifurcation_diagram two swept axes",
          dg(grid=sc().Grid(**{**STRIBECK, "c": [0.1, 0.2]}, v=[1.0, 2.0])),
          names=("swept",))
    probe("bifurcation_diagram v not swept", dg(grid=sc().Grid(**STRIBECK, v=1.5)),
          names=("swept", "'v'"))
    probe("bifurcation_diagram grid=None", lambda: sc().bifurcation_diagram(None),
          names=("grid",))
    probe("bifurcation_diagram method=gps", dg(method="gps"), names=("gps",))
    probe("bifurcation_diagram", dg(), "valid")
    probe("bifurcation_diagram up", dg(sweep="up", unstable=False), "valid")


def lb(**kw):
    return lambda: sc().locate_boundaries(kw.pop("grid", None) or boundary_grid(), **kw)


def boundary_probes():
    for v in ("x", None, 5):
        probe(f"locate_boundaries along={v!r}", lb(along=v), names=("along",))
    for v in ((None, 5), ("a", "b"), (1.0, float("nan")), (5.0, 1.0), (-1.0, 5.0), 5,
              (1, 2, 3), (10 ** 400, 1)):
        probe(f"locate_boundaries bracket={v!r:.30}", lb(bracket=v), names=("bracket",))
    for v in (2, 2.5, True, 10 ** 9, 10 ** 20, None):
        probe(f"locate_boundaries scan={v!r}", lb(scan=v), names=("scan",))
    for k in ("xtol", "offset", "tol"):
        for v in (0.0, float("nan"), -1.0, "1e-9", 0.5 if k == "offset" else None):
            probe(f"locate_boundaries {k}={v!r}", lb(**{k: v}), names=(k,))
    probe("locate_boundaries of 1e10 points",
          lb(grid=sc().Grid(**{**PAPER, "alpha2": np.geomspace(1e-3, 0.1, HUGE),
                               "alpha1": np.linspace(0.5, 1.5, HUGE)}, v=[3.0, 8.0])),
          names=("points", "memory"))
    probe("locate_boundaries points grid",
          lb(grid=sc().Grid.points(**PAPER, v=[3.0, 8.0], alpha2=[0.01, 0.02])),
          names=("product",))
    probe("locate_boundaries chunks=0", lb(chunks=0), names=("chunks",))
    probe("locate_boundaries", lb(), "valid")
    cb = sc().continue_boundary
    for v in ("x", "v", None, "alpha1"):
        probe(f"continue_boundary over={v!r}",
              lambda v=v: cb(boundary_grid(), over=v), names=("over=",))
    probe("continue_boundary scan=10**20",
          lambda: cb(boundary_grid(), over="alpha2", scan=10 ** 20), names=("scan",))


# ------------------------------------------------------------------ plotting
def pl(fn, *args, **kw):
    return lambda: getattr(sc(), fn)(*(a() if callable(a) else a for a in args), **kw)


def plot_probes():
    kinds = ("sweep2d", "stribeck", "sweep1d", "simulation", "diagram", "cycles",
             "basins", "basins2d", "boundaries")
    for fn in ("plot_map", "plot_result", "plot_basins", "plot_hysteresis",
               "plot_diagram", "plot_boundaries", "plot_lines", "plot_trajectory"):
        for bad in (None, "out.nc", {}, 5):
            probe(f"{fn}({bad!r})", pl(fn, bad, *(("v",) if fn == "plot_lines" else ())),
                  names=("ds",))
    for fn, good in (("plot_basins", ("basins", "basins2d")),
                     ("plot_hysteresis", ("diagram",)),
                     ("plot_diagram", ("diagram",)),
                     ("plot_boundaries", ("boundaries",)),
                     ("plot_trajectory", ("simulation",)),
                     ("plot_map", ("sweep2d", "stribeck", "basins2d"))):
        for k in kinds:
            ok = k in good
            probe(f"{fn} of a {k} file", pl(fn, lambda k=k: fx(k)),
                  "valid" if ok else "refuse", names=("ds",),
                  check=figure_ok if ok else None)
    for k in kinds:
        probe(f"plot_result of a {k} file", pl("plot_result", lambda k=k: fx(k)),
              "valid", check=figure_ok)
    m = lambda: fx("sweep2d")  # noqa: E731
    probe("plot_map variables='amplitude'", pl("plot_map", m, variables="amplitude"),
          "valid", check=lambda f: figure_ok(f, ("amplitude",)))
    probe("plot_map variables=[]", pl("plot_map", m, variables=[]), names=("variables",))
    probe("plot_map variables=['nope']", pl("plot_map", m, variables=["nope"]),
          names=("nope",))
    probe("plot_map variables=5", pl("plot_map", m, variables=5), names=("variables",))
    probe("plot_map x='v', y='v'", pl("plot_map", m, x="v", y="v"), names=("x", "y"))
    probe("plot_map x='nope'", pl("plot_map", m, x="nope"), names=("nope",))
    probe("plot_map x=5", pl("plot_map", m, x=5), names=("x",))
    probe("plot_map boundary='no'", pl("plot_map", m, boundary="no"),
          names=("boundary",))
    probe("plot_map title=5", pl("plot_map", m, title=5), names=("title",))
    s = lambda: fx("stribeck")  # noqa: E731
    for var in ("x_eq", "v_star", "q", "omega"):
        probe(f"plot_map of a (v, c) Stribeck map, {var}",
              pl("plot_map", s, variables=["regime", var]), "valid",
              check=lambda f: figure_ok(f))
    probe("plot_map of a (v, c) Stribeck map draws its Hopf curve",
          pl("plot_map", s), "valid",
          check=lambda f: None if any("v^*" in ln.get_label() or "Hopf" in
                                      ln.get_label() for a in f.axes
                                      for ln in a.get_lines()) or any(
              "v^*" in t.get_text() for leg in f.legends for t in leg.get_texts())
          else "no Hopf curve")
    b = lambda: fx("basins")  # noqa: E731
    for ref in ("x", {"a": ([1.5], [0.3], [0.01, 0.02])}, {"a": ([1.5], [0.3])}, 5,
                {"a": "xyz"}):
        probe(f"plot_basins reference={ref!r:.40}", pl("plot_basins", b, reference=ref),
              names=("reference",))
    probe("plot_basins reference (valid)",
          pl("plot_basins", b, reference={"a": ([1.5], [0.3], [0.01])}), "valid",
          check=figure_ok)
    probe("plot_basins x='nope'", pl("plot_basins", lambda: fx("basins2d"), x="nope"),
          names=("nope",))
    d = lambda: fx("diagram")  # noqa: E731
    probe("plot_hysteresis variable='nope'", pl("plot_hysteresis", d, variable="nope"),
          names=("nope", "variable"))
    probe("plot_hysteresis variable='period'", pl("plot_hysteresis", d,
                                                   variable="period"), "valid",
          check=figure_ok)
    probe("plot_lines dim='nope'", pl("plot_lines", lambda: fx("sweep1d"), "nope"),
          names=("nope",))
    probe("plot_lines variables='amplitude'",
          pl("plot_lines", lambda: fx("sweep1d"), "v", variables="amplitude"), "valid",
          check=figure_ok)
    probe("plot_boundaries over=5", pl("plot_boundaries", lambda: fx("boundaries"),
                                       over=5), names=("over",))


# ------------------------------------------------------------------ the command
STUDY = """\
title = "battery"
[axes]
m = 1.0
k = 1.0
r_y = 1.0
r_k = 0.5
v_s = 0.5
c = 0.1
v = [1.3, 1.6]
[basins]
route = "exact"
"""


def cli(argv, study=STUDY, prepare=None, check=None):
    def run():
        work = Path(tempfile.mkdtemp(dir=os.environ["BATTERY_WORK"]))
        os.chdir(work)
        (work / "s.toml").write_text(study)
        state = prepare(work) if prepare else None
        err = io.StringIO()
        from sweepcore.cli import main
        with redirect_stderr(err), redirect_stdout(io.StringIO()):
            code = main(argv)
        return {"code": code, "stderr": err.getvalue(), "state": state, "work": work,
                "check": check}
    return run


def _readonly(work):
    (work / "F.nc").write_text("keep")
    (work / "F.nc").chmod(0o444)
    return ("F.nc", "keep")


def _symlink(work):
    (work / "target.txt").write_text("keep")
    (work / "F.nc").symlink_to("target.txt")
    return ("target.txt", "keep")


def _fifo(work):
    os.mkfifo(work / "F.nc")
    return None


def command_probes():
    probe("basins -o read-only file", cli(["basins", "s.toml", "-o", "F.nc", "-q"],
                                          prepare=_readonly), names=("read-only",))
    probe("basins -o symbolic link", cli(["basins", "s.toml", "-o", "F.nc", "-q"],
                                         prepare=_symlink), names=("symbolic link",))
    probe("basins -o FIFO", cli(["basins", "s.toml", "-o", "F.nc", "-q"],
                                prepare=_fifo), names=("FIFO",))
    probe("basins -o directory", cli(["basins", "s.toml", "-o", "D.nc", "-q"],
                                     prepare=lambda w: (w / "D.nc").mkdir()),
          names=("directory",))
    probe("basins -o missing directory", cli(["basins", "s.toml", "-o", "no/F.nc"]),
          names=("no",))
    probe("basins -o F.csv", cli(["basins", "s.toml", "-o", "F.csv"]), names=(".nc",))
    for key, value in (("samples", "9223372036854775807"), ("samples", "1_000_000_000"),
                       ("checks", "1_000_000_000_000"), ("samples", "0"),
                       ("x0", "[1e400, 1.0]"), ("x0", "[2.0, 1.0]"),
                       ("ftol", "2.0"), ("seed", "-1"), ("route", '"fast"'),
                       ("tolerance", "1e-8")):
        text = STUDY.replace('route = "exact"', f"route = \"sampled\"\n{key} = {value}"
                             if key == "samples" else f"{key} = {value}")
        probe(f"basins [basins] {key} = {value}", cli(["basins", "s.toml", "-q"], text),
              names=(key,))
    probe("basins [solver] tolerance", cli(
        ["basins", "s.toml", "-q"], STUDY + "[solver]\ntolerance = 1e-8\n"),
        names=("'tol'",))
    probe("basins of 1e10 points", cli(["basins", "s.toml", "-q"], STUDY.replace(
        "v = [1.3, 1.6]", "v = { start = 1.0, stop = 2.0, num = 100000 }\n"
        "alpha1 = { start = 0.0, stop = 0.1, num = 100000 }")),
        names=("points",))
    probe("basins (valid)", cli(["basins", "s.toml", "-q", "-o", "b.nc"]), "valid",
          check=lambda r: None if (r["work"] / "b.nc").is_file() else "no file")


# ------------------------------------------------------------------ law inputs
S7 = [0.0, 0.1, 0.25, 0.5, 1.0, 2.0, 4.0]            # the README's measured table
F7 = [1.0, 0.93, 0.82, 0.68, 0.55, 0.51, 0.50]


def tl(speed=S7, force=F7, **kw):
    return lambda: sc().TableLaw(speed() if callable(speed) else speed,
                                 force() if callable(force) else force, **kw)


def ff(f, speed_max=8.0, **kw):
    return lambda: sc().TableLaw.from_function(f, speed_max, **kw)


def law_between(speeds, lo, hi, force_at):
    """A check: the law's force at ``speeds`` within [lo, hi] (1e-12 slack)."""
    def check(law):
        F = law.force(np.asarray(speeds, float), phase=1.0)
        if not (np.all(F >= lo - 1e-12) and np.all(F <= hi + 1e-12)):
            return f"force {F.min():.4g} .. {F.max():.4g} outside [{lo}, {hi}]"
        return force_at(law) if force_at else None
    return check


def _csv_file(text, mode="w"):
    def make():
        work = Path(tempfile.mkdtemp(dir=os.environ["BATTERY_WORK"]))
        path = work / "curve.csv"
        with open(path, mode) as fh:
            fh.write(text)
        return path
    return make


def from_csv(make):
    return lambda: sc().TableLaw.from_csv(make())


def _fifo_csv():
    work = Path(tempfile.mkdtemp(dir=os.environ["BATTERY_WORK"]))
    os.mkfifo(work / "curve.csv")
    return work / "curve.csv"


def _modifies(s):
    s *= 2.0                                  # changes the speeds it is asked about
    return 0.5 + 0.5 * np.exp(-s / 2.0)


def _many_laws_sweep():
    s = sc()
    speed = np.linspace(0.0, 4.0, 7)
    laws = [s.TableLaw(speed, 1.0 - 0.1 * speed + 1e-4 * i, name=f"t{i}")
            for i in range(1000)]
    return s.sweep(s.Grid(m=1.0, k=1.0, c=0.1, v=[0.5, 1.0], law=laws), progress=False)


def _huge_law_grid():
    s = sc()
    speed = np.linspace(0.0, 4.0, 7)
    laws = [s.TableLaw(speed, 1.0 - 0.1 * speed + 1e-4 * i, name=f"t{i}")
            for i in range(1000)]
    return s.sweep(s.Grid(m=1.0, k=1.0, c=np.linspace(0.05, 0.2, 256),
                          v=np.linspace(0.2, 3.0, 256), law=laws), progress=False)


def _readme_sweep(ds):
    from sweepcore._kernels import codes
    bad = ds.status.values != codes.OK
    unbounded = ds.regime.values == list(ds.regime.attrs["flag_meanings"].split()).index(
        "unbounded")
    return f"{int(bad.sum())} failed, {int(unbounded.sum())} unbounded" \
        if bad.any() or unbounded.any() else None


def law_probes():
    """The friction law's interfaces (TableLaw, its from_function and from_csv,
    LeineLaw): magnitudes, sizes, names, files, and tables whose representation
    must keep the data's shape."""
    line = np.linspace(0.0, 4.0, 7)
    probe("law TableLaw forces of 1e307", tl(line, 1e307 * (1.0 - 0.1 * line)),
          names=("force",))
    probe("law TableLaw forces of 1e300", tl(line, 1e300 * (1.0 - 0.1 * line)),
          names=("force",))
    probe("law TableLaw speeds of 1e-300", tl(1e-300 * line, 1.0 - 0.1 * line),
          names=("speed",))
    probe("law TableLaw speeds closer than float64 resolves",
          tl([0.0, 1e-14, 1.0, 2.0, 3.0, 4.0], F7[:6]), names=("speed",))
    probe("law TableLaw 0-d speed array", tl(np.array(1.0), np.array(1.0)),
          names=("speed",))
    probe("law TableLaw name=b'x'", tl(name=b"x"), names=("name",))
    probe("law TableLaw name with NUL", tl(name="a\x00b"), names=("name",))
    for label, value in (("1e300", 1e300), ("1e6", 1e6), ("10**400", 10 ** 400),
                         ("nan", float("nan")), ("-0.1", -0.1), ("True", True)):
        probe(f"law TableLaw smoothing={label}", tl(smoothing=value),
              names=("smoothing",))
    step_s, step_f = np.arange(10.0), np.r_[np.ones(4), np.zeros(6)]
    probe("law TableLaw smoothing=0.01 of a step (fit goes negative)",
          tl(step_s, step_f, smoothing=0.01), names=("smoothing",))
    probe("law TableLaw step from 1 to 0 kN", tl([0, 1, 2, 3, 4, 5], [1, 1, 1, 0, 0, 0]),
          "valid", check=law_between(np.linspace(0, 8, 4001), 0.0, 1.0, None))
    probe("law TableLaw 1 -> 0.4 kN table at 3.647 cm/s",
          tl([0, .01, .02, 1, 2, 3, 4], [1, .5, .45, .4, .4, .4, .4]), "valid",
          check=law_between(np.linspace(0, 10, 4001), 0.4, 1.0,
                            lambda law: None if abs(float(law.force(3.647)) - 0.4) < 1e-12
                            else f"F(3.647) = {float(law.force(3.647))!r}"))
    probe("law TableLaw README table past its end",
          tl(), "valid", check=law_between(np.linspace(0, 1e3, 4001), 0.5, 1.0, None))
    probe("law TableLaw of 1e5 samples", tl(lambda: np.linspace(0.0, 10.0, 100_000),
                                            lambda: 1.0 + np.exp(-np.linspace(0.0, 10.0,
                                                                              100_000))),
          "valid", check=law_between(np.linspace(0, 12, 4001), 1.0, 2.0, None))
    probe("law TableLaw of 1e6 + 1 samples", tl(lambda: np.linspace(0.0, 1.0, 1_000_001),
                                                lambda: np.ones(1_000_001)),
          names=("points",))
    probe("law LeineLaw(10**400, 3)", lambda: sc().LeineLaw(10 ** 400, 3),
          names=("f_s",))
    probe("law LeineLaw(1e100, 1e100)", lambda: sc().LeineLaw(1e100, 1e100),
          names=("f_s",))
    probe("law LeineLaw(1, 1e-300)", lambda: sc().LeineLaw(1, 1e-300), names=("delta",))
    probe("law LeineLaw name with NUL", lambda: sc().LeineLaw(1, 3, name="a\x00b"),
          names=("name",))
    probe("law LeineLaw name=b'x'", lambda: sc().LeineLaw(1, 3, name=b"x"),
          names=("name",))
    smooth = lambda s: 0.5 + 0.5 * np.exp(-np.abs(s) / 0.5)   # noqa: E731
    for label, value in (("1e300", 1e300), ("1e-300", 1e-300), ("10**400", 10 ** 400),
                         ("inf", float("inf"))):
        probe(f"law from_function speed_max={label}", ff(smooth, value),
              names=("speed_max",))
    probe("law from_function speed_min=-1e300", ff(smooth, speed_min=-1e300),
          names=("speed_min",))
    probe("law from_function 1/s + 0.5", ff(lambda s: 1.0 / s + 0.5), names=("f",))
    probe("law from_function that modifies its input", ff(_modifies), "valid",
          check=lambda law: None if abs(float(law.force(1.0)) - (0.5 + 0.5 * np.exp(
              -1.0))) < 1e-8 else f"F(1) = {float(law.force(1.0))!r}")
    probe("law from_csv FIFO", from_csv(_fifo_csv), names=("FIFO",))
    probe("law from_csv device", lambda: sc().TableLaw.from_csv("/dev/zero"),
          names=("device",))
    probe("law from_csv directory", lambda: sc().TableLaw.from_csv(
        os.environ["BATTERY_WORK"]), names=("directory",))
    rows = "".join(f"{s},{f}\n" for s, f in zip(S7, F7))
    probe("law from_csv UTF-8 BOM (Excel)", from_csv(_csv_file(
        "\ufeffspeed [cm/s],force [kN]\n" + rows, "w")), "valid",
        check=lambda law: None if np.array_equal(law.speed, S7) else "speeds differ")
    probe("law from_csv of 1.1e6 rows", from_csv(_csv_file(
        "speed [cm/s],force [kN]\n" + "".join(f"{i},1\n" for i in range(1_100_000)))),
        names=("rows",))
    probe("law simulate --law-table FIFO", cli(
        ["simulate", "--m", "1", "--k", "1", "--v", "0.5", "--law-table", "F.csv", "-o",
         "s.nc"], prepare=lambda w: os.mkfifo(w / "F.csv")), names=("FIFO",))
    probe("law README table swept v = 0.2 .. 3.9", lambda: sc().sweep(sc().Grid(
        m=1.0, k=1.0, c=0.1, v=np.round(np.arange(0.2, 3.95, 0.1), 10),
        law=tl(static=1.1)()), progress=False), "valid", check=_readme_sweep)
    probe("law Grid of 1,000 tables x 2 speeds", _many_laws_sweep, "valid",
          check=lambda ds: None if ds.sizes["law"] == 1000 else "laws lost")
    probe("law 1,000 tables x 256 x 256", _huge_law_grid, names=("memory",))


def fault_probes():
    """Killed writes and resumes of the file-writing functions (each a probe)."""
    probe("slip_cycles killed mid-write leaves no temporary", killed_write("cycles"),
          "valid", check=lambda r: r)
    probe("basin_stability killed mid-write leaves no temporary",
          killed_write("basins"), "valid", check=lambda r: r)
    probe("basin_stability killed mid-run resumes", killed_run(), "valid",
          check=lambda r: r)


def _writer(kind, path):
    s = sc()
    if kind == "cycles":
        return s.slip_cycles(g1(1.3, 1.6), path=path, chunks=1)
    return s.basin_stability(g1(1.3, 1.6), **BOX, route="exact", path=path, chunks=1,
                             progress=False)


def killed_write(kind):
    def run():
        import xarray as xr
        work = Path(tempfile.mkdtemp(dir=os.environ["BATTERY_WORK"]))
        path = work / "r.nc"
        pid = os.fork()
        if pid == 0:                     # the writer, killed inside to_netcdf
            real = xr.Dataset.to_netcdf

            def dying(self, target, *a, **k):
                real(self, target, *a, **k)
                os.kill(os.getpid(), signal.SIGKILL)
            xr.Dataset.to_netcdf = dying
            try:
                _writer(kind, path)
            finally:
                os._exit(3)
        os.waitpid(pid, 0)
        _writer(kind, path)
        left = [p.name for p in work.iterdir() if p.name != "r.nc"]
        return f"left behind: {left}" if left else None
    return run


def killed_run():
    """A 4-chunk basin map killed after its second chunk: the rerun computes only
    the other two and gives the same fractions."""
    def run():
        import sweepcore.basins as sb
        work = Path(tempfile.mkdtemp(dir=os.environ["BATTERY_WORK"]))
        grid = g1(1.2, 1.4, 1.6, 1.8)
        kw = dict(**BOX, route="sampled", samples=20, chunks=1, progress=False,
                  path=work / "r.nc")
        count = work / "count"
        count.write_text("")
        real = sb.basin_chunk

        def counted(*a, **k):
            if os.environ.get("BATTERY_DIE") and count.stat().st_size >= 2:
                os.kill(os.getpid(), signal.SIGKILL)     # two chunks are done
            out = real(*a, **k)
            with open(count, "a") as f:
                f.write("x")
            return out
        pid = os.fork()
        if pid == 0:
            os.environ["BATTERY_DIE"] = "1"
            sb.basin_chunk = counted
            try:
                sc().basin_stability(grid, **kw)
            finally:
                os._exit(3)
        os.waitpid(pid, 0)
        count.write_text("")
        sb.basin_chunk = counted
        ds = sc().basin_stability(grid, **kw)
        n = count.stat().st_size
        want = sc().basin_stability(grid, **{**kw, "path": None})
        if not np.array_equal(ds.basin_fraction.values, want.basin_fraction.values):
            return "resumed fractions differ"
        return None if n == 2 else f"the rerun computed {n} of 4 chunks"
    return run


# ------------------------------------------------------------------ running
def _child(index, conn, memory, work):
    os.environ["BATTERY_WORK"] = str(work)
    os.environ["NUMBA_NUM_THREADS"] = "1"
    limit = int(memory * 2 ** 30)
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    p = PROBES[index]
    try:
        with redirect_stderr(io.StringIO()):
            import warnings
            warnings.simplefilter("ignore")
            got = p["call"]()
        conn.send(("returned", _verdict_of_return(p, got)))
    except BaseException as err:  # noqa: BLE001 - classified by the parent
        text = f"{type(err).__name__}: {err}"
        refused = p["expect"] == "refuse" and isinstance(err, REFUSALS) and (
            not p["names"] or any(n in str(err) for n in p["names"]))
        conn.send(("refused" if refused else "crash", text[:300]
                   + ("" if refused else "\n" + traceback.format_exc()[-600:])))


def _verdict_of_return(p, got):
    if isinstance(got, dict) and "code" in got:       # a command
        code, err = got["code"], got["stderr"]
        if code == 2:
            named = not p["names"] or any(n in err for n in p["names"])
            ok = named and p["expect"] == "refuse"
            return ("refused" if ok else "crash", err.strip()[:300])
        if code != 0:
            return ("crash", err.strip()[:300])
        if p["expect"] == "refuse":
            bad = unchanged(got["work"] / got["state"][0], got["state"][1]) \
                if got["state"] else "exit 0"
            return ("silent-bad", f"taken: {bad or 'exit 0'}")
        bad = got["check"](got) if got["check"] else None
        return ("silent-bad", bad) if bad else ("valid", "")
    if p["expect"] == "refuse":
        return ("silent-bad", f"taken, returned {type(got).__name__}")
    bad = p["check"](got) if p["check"] else None
    return ("silent-bad", str(bad)) if bad else ("valid", "")


def run_probe(index, timeout, memory, work):
    ctx = mp.get_context("fork")
    parent, child = ctx.Pipe(duplex=False)
    proc = ctx.Process(target=_child, args=(index, child, memory, work))
    t0 = time.monotonic()
    proc.start()
    child.close()
    got = None
    if parent.poll(timeout):
        try:
            got = parent.recv()
        except EOFError:
            got = None
    proc.join(5 if got else 0.1)
    if proc.is_alive():
        os.kill(proc.pid, signal.SIGKILL)
        proc.join()
        if got is None:
            return "hang", f"no answer in {timeout:g} s", time.monotonic() - t0
    if got is None:
        return "crash", f"process died (exit code {proc.exitcode})", \
            time.monotonic() - t0
    kind, detail = got
    if kind == "returned":
        kind, detail = detail
    return kind, detail, time.monotonic() - t0


def build():
    for add in (basin_probes, cycle_probes, diagram_probes, boundary_probes,
                plot_probes, command_probes, fault_probes, law_probes):
        add()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--timeout", type=float, default=60.0, help="seconds per probe")
    ap.add_argument("--memory-gib", type=float, default=6.0,
                    help="address-space limit of each probe [GiB]")
    ap.add_argument("--only", help="run the probes whose name contains this")
    ap.add_argument("--json", help="write every probe's verdict to this file")
    ap.add_argument("--list", action="store_true", help="list the probes, run none")
    ap.add_argument("-v", "--verbose", action="store_true",
                    help="print every probe, not only the failures")
    args = ap.parse_args(argv)
    build()
    chosen = [i for i, p in enumerate(PROBES) if not args.only or args.only in p["name"]]
    if args.list:
        print("\n".join(PROBES[i]["name"] for i in chosen))
        return 0
    import sweepcore
    import sweepcore.plot  # noqa: F401  (matplotlib imported before the forks)
    print(f"battery: {len(chosen)} probes of sweepcore at {Path(sweepcore.__file__).parent}",
          file=sys.stderr)
    with tempfile.TemporaryDirectory(prefix="battery-") as tmp:
        work = Path(tmp)
        ctx = mp.get_context("fork")
        maker = ctx.Process(target=make_fixtures, args=(work,))
        if any("plot" in PROBES[i]["name"] for i in chosen):   # the files they draw
            maker.start()
            maker.join()
        if maker.exitcode not in (0, None):
            print("battery: the fixture files could not be made", file=sys.stderr)
            return 1
        verdicts, counts = [], {}
        for i in chosen:
            kind, detail, secs = run_probe(i, args.timeout, args.memory_gib, work)
            counts[kind] = counts.get(kind, 0) + 1
            verdicts.append(dict(name=PROBES[i]["name"], verdict=kind, detail=detail,
                                 seconds=round(secs, 2)))
            if args.verbose or kind in ("crash", "hang", "silent-bad"):
                first = str(detail).splitlines()[0][:160] if detail else ""
                print(f"{kind:10s} {secs:6.1f} s  {PROBES[i]['name']}: {first}",
                      flush=True)
    order = ("refused", "valid", "crash", "hang", "silent-bad")
    print("battery: " + ", ".join(f"{k} {counts.get(k, 0)}" for k in order)
          + f" of {len(chosen)} probes")
    if args.json:
        Path(args.json).write_text(json.dumps({"counts": counts, "probes": verdicts},
                                              indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
