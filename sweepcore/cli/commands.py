"""What each subcommand of ``sweepcore`` does: run, boundary and basins (study files),
simulate (one slider), plot, info and export (result files)."""
from __future__ import annotations

import math
import os
import shlex
import sys
import time
from pathlib import Path

import numpy as np

from ..labels import run_statuses, timestamp, version
from ..keywords import did_you_mean
from .tables import csv_tables, units_table
from .timings import say_call_time, say_time
from .summaries import (basin_lines, boundary_lines, describe, describe_basins,
                        describe_boundaries, forced_lines, regime_line,
                        simulation_summary, status_line)


class UsageError(ValueError):
    """A refused command line (exit code 2)."""


# ---------------------------------------------------------------- commands
def _resolve_outputs(args, default: str, study_png) -> tuple[Path, Path | None]:
    """The result file and picture of a command that runs a study (run, boundary).

    ``-o`` replaces the study's outputs as a whole: the result is ``-o`` and its
    picture ``--png``, else the result's path with .png (the study's own picture
    path is then not used: it may name a directory of the study's place). Without
    ``-o``: ``default`` (the study's path, or a name after the study) and ``--png``,
    else the study's png file, else the result's path with .png. No picture with
    ``--no-png`` or (without ``-o``) a study's ``png = false``."""
    out = Path(args.output or default)
    if out.suffix != ".nc":
        raise UsageError(f"output must end in .nc, got {str(out)!r}")
    if args.output:
        study_png = None
    if args.no_png or (args.png is None and study_png is False):
        png = None
    elif args.png is not None:
        png = Path(args.png)
    elif isinstance(study_png, str):
        png = Path(study_png)
    else:
        png = out.with_suffix(".png")
    if png is not None and png.suffix.lower() != ".png":
        raise UsageError(f"picture must end in .png, got {str(png)!r}")
    return out, png


def _check_directories(*paths) -> None:
    """Refuse an output whose directory is missing (sweepcore never creates one)."""
    for path in paths:
        if path is not None and not Path(path).parent.is_dir():
            parent = Path(path).parent
            raise UsageError(f"directory {str(parent)!r} of {str(path)!r} does not "
                             f"exist: create it first (mkdir -p {shlex.quote(str(parent))})"
                             " or choose another path")


def cmd_run(args) -> int:
    """``sweepcore run``: validate, sweep, label, write, draw."""
    from ..grid import Grid
    from ..options import make_options
    from ..study import load_study

    study = load_study(args.study)
    grid = Grid(**study.grid_kwargs())
    make_options(study.method, tol=study.tol, **study.options)
    out, png = _resolve_outputs(args, study.output_path or f"{study.stem}.nc",
                                study.png)
    _check_directories(out, png)
    return _run(args, study, grid, out, png)


def _run(args, study, grid, out, png) -> int:
    from ..sweep import sweep

    if not args.quiet:
        # in the result's order (the sweep puts v last), as `sweepcore info` says it
        sizes = sorted(zip(grid.dims, grid.shape), key=lambda dn: dn[0] == "v")
        print(f"sweepcore run {args.study}: {grid.size} points "
              f"({' x '.join(f'{d}: {n}' for d, n in sizes)}), "
              f"method {study.method}, tol {study.tol:g}", flush=True)
    from ..timing import left_to_compute
    say_time(args, f"sweepcore run {args.study}", grid, study,
              left_to_compute(grid, out))
    t0 = time.perf_counter()
    ds = sweep(grid, method=study.method, tol=study.tol,
               chunks=args.chunks or study.chunks, scheduler=args.scheduler, path=out,
               progress=_progress(args), max_seconds=None, **study.options)
    return _finish(ds, study, args, out, png, t0, grid.size,
                   lambda d: [regime_line(d), status_line(d), *forced_lines(d)],
                   study.plot)


def _progress(args):
    """A sweep's progress: a bar on a terminal, a plain line every 10 s or tenth of
    the work where stderr goes to a file (sweepcore.resumable.ProgressLines);
    nothing with --quiet."""
    if args.quiet:
        return False
    return None if sys.stderr.isatty() else True


def _finish(ds, study, args, out, png, t0, n, summary, plot=None, attrs=None) -> int:
    """Label the result of a study with the study, the command and ``attrs``, write
    it and its picture, and say so (``n`` points, the ``summary`` lines)."""
    from ..io import write_netcdf

    elapsed = time.perf_counter() - t0
    ds = label_with_study(ds, study, _command_line(args))
    ds.attrs.update(attrs or {})
    write_netcdf(ds, out)
    if not args.quiet:
        print(f"wrote {out} ({'' if n is None else f'{n} points in '}{elapsed:.1f} s)")
        for line in summary(ds):
            print(line)
    if png is not None:
        from ..plot import plot_result, save
        args.on_interrupt = (f"while drawing; the result {out} is complete, "
                             f"`sweepcore plot {out} -o {png}` draws it")
        save(plot_result(ds, **(plot or {})), png)
        if not args.quiet:
            print(f"wrote {png}")
    return 0


def label_with_study(ds, study, command: str):
    """Record the study (title, file, full text) and the command in ``ds``'s attrs.

    The text of the study file plus the version in ``history`` reproduce the result.
    Geometric axes get ``spacing = "geometric"`` (plots use a log scale for them).
    """
    ds.attrs["study_title"] = study.title
    if study.description:
        ds.attrs["study_description"] = study.description
    ds.attrs["study_file"] = str(study.path) if study.path else ""
    ds.attrs["study"] = study.text
    ds.attrs["history"] = (ds.attrs.get("history", "") + "\n" + command).strip()
    for name, spacing in study.spacing_attrs().items():
        if name in ds.coords:
            ds[name].attrs["spacing"] = spacing
    return ds


def _command_line(args) -> str:
    """``history`` line: time, version and the command as typed."""
    return f"{timestamp()} sweepcore {version()}: " + shlex.join(["sweepcore", *args.argv])


def cmd_plot(args) -> int:
    """``sweepcore plot``: the natural picture of a result file."""
    from ..plot import plot_result, save

    ds = _open(args.result, "plot")
    out = Path(args.output) if args.output else Path(args.result).with_suffix(".png")
    if out.suffix.lower() != ".png":
        raise UsageError(f"picture must end in .png, got {str(out)!r}")
    _check_directories(out)
    failed = [s for s in run_statuses(ds) if s != "ok"] if "time" in ds.dims else []
    if failed and len(failed) == len(run_statuses(ds)):
        what = "a failed simulation" if len(failed) == 1 else "only failed simulations"
        raise UsageError(f"{args.result} holds {what} (status {' '.join(failed)}): "
                         "nothing to draw")
    kwargs = {}
    _check_plot_options(args, ds)
    if "time" not in ds.dims:
        kwargs = {k: getattr(args, k) for k in ("x", "y") if getattr(args, k)}
        swept = [d for d in ds.dims if ds.sizes[d] > 1 and ds[d].dtype.kind in "iuf"]
        for key, dim in kwargs.items():
            if dim not in swept:
                raise UsageError(f"--{key} {dim}: not a swept axis of {args.result}"
                                 f"{did_you_mean(dim, swept)} (swept: "
                                 f"{', '.join(swept) or 'none'})")
        if len(swept) < 2 and kwargs:
            raise UsageError("--x/--y apply to maps; this result has one swept axis")
        if kwargs.get("x") and kwargs.get("x") == kwargs.get("y"):
            raise UsageError(f"--x and --y are both {args.x}: a map needs two different "
                             f"axes (swept: {', '.join(swept)})")
        if args.variables:
            kwargs["variables"] = _variable_names(args, ds, ("regime", *ds.data_vars))
        elif "study" in ds.attrs and ds.attrs.get("sweepcore_kind") is None:
            from ..study import StudyError, parse_study     # a sweep's [plot] table
            try:
                kwargs = {**parse_study(ds.attrs["study"]).plot, **kwargs}
            except StudyError:    # a study of another version: default picture
                pass
    args.on_interrupt = f"while drawing; {out} not written"
    save(plot_result(ds, **kwargs), out)
    print(f"wrote {out}")
    return 0


def _check_plot_options(args, ds) -> None:
    """Refuse --variables, --x and --y where the picture has no use for them (they
    would be ignored): --variables apply to sweeps, --x and --y to sweeps and basin
    maps."""
    from ..plot.checks import KINDS, kind_of

    kind = kind_of(ds)
    given = [f"--{k}" for k in ("variables", "x", "y") if getattr(args, k)]
    takes = {"sweep": ("--variables", "--x", "--y"), "basins": ("--x", "--y")}
    refused = [g for g in given if g not in takes.get(kind, ())]
    if refused:
        taken = ", ".join(takes.get(kind, ())) or "none"
        raise UsageError(f"{' and '.join(refused)}: {args.result} holds {KINDS[kind]}, "
                         f"whose picture takes {taken} of them (--variables: sweeps; "
                         "--x, --y: maps of sweeps and basins)")


def cmd_simulate(args) -> int:
    """``sweepcore simulate``: one slider, Fig. 3 style."""
    from ..io import write_netcdf
    from ..simulate import simulate

    p = _simulated_params(args)
    for path, suffix in ((args.output, ".nc"), (args.png, ".png")):
        if path is not None and Path(path).suffix.lower() != suffix:
            raise UsageError(f"{path!r} must end in {suffix}")
    _check_directories(args.output, args.png)
    if args.output:     # sweep's rules: no symbolic link, FIFO, read-only file, ...
        from ..io import result_path
        result_path(args.output)
    extra = {"dt": args.dt} if args.dt is not None else {}
    ds = simulate(p, t_end=args.t_end, x0=args.x0, xdot0=args.xdot0, method=args.method,
                  output_dt=args.output_dt, tol=args.tol, **extra)
    ds.attrs["history"] = _command_line(args)
    print(simulation_summary(ds, p), flush=True)
    if ds.attrs["status"] != "ok":
        raise SimulationFailed(f"{ds.attrs['status']}: {failure_reason(ds, p, args)}; "
                               "nothing written")
    if args.output:
        write_netcdf(ds, args.output)
        print(f"wrote {args.output}")
    if args.png:
        from ..plot import save, plot_trajectory
        save(plot_trajectory(ds), args.png)
        print(f"wrote {args.png}")
    if not (args.output or args.png):
        print("(nothing written: give -o RUN.nc and/or --png FIG.png)")
    return 0


def _simulated_params(args):
    """The slider of ``sweepcore simulate``: the analytic law's options, or the law
    of ``--law-table`` (then no analytic option may be given)."""
    from ..excitations import KEYWORDS
    from ..params import Params
    forcing = {n: getattr(args, n) for n in KEYWORDS}    # --F0 --Omega --phi --Y0
    if getattr(args, "load", None) is not None:
        forcing["load"] = _load_of(args.load)
    if args.law_table is None:
        if args.static is not None or args.smoothing is not None:
            raise UsageError("--static and --smoothing go with --law-table")
        if args.r_y is None:
            raise UsageError("give --r-y (the analytic law) or --law-table FILE.csv")
        return Params(m=args.m, k=args.k, r_y=args.r_y, v=args.v, alpha1=args.alpha1,
                      alpha2=args.alpha2, c=args.c, r_k=args.r_k, v_s=args.v_s,
                      **forcing)
    given = [f"--{n.replace('_', '-')}" for n in ("r_y", "r_k", "v_s")
             if getattr(args, n) is not None]
    given += [f"--{n}" for n in ("alpha1", "alpha2") if getattr(args, n) != 0.0]
    if given:
        raise UsageError(f"--law-table gives the friction law: drop {', '.join(given)}")
    if not args.law_table.strip():        # Path("") is ".", "a directory"
        raise UsageError(f"--law-table {args.law_table!r}: the path is empty; give the "
                         "friction table's CSV file (--law-table friction.csv)")
    from ..laws import TableLaw
    law = TableLaw.from_csv(args.law_table, static=args.static, smoothing=args.smoothing)
    return Params(m=args.m, k=args.k, v=args.v, c=args.c, law=law, **forcing)


def _load_of(file: str):
    """The load's shape of ``--load FILE.csv``: one period of samples at uniform
    phases (``sweepcore.PeriodicLoad.from_csv``)."""
    from ..excitations import PeriodicLoad
    if not file.strip():
        raise UsageError(f"--load {file!r}: the path is empty; give a CSV file of one "
                         "period of the load's samples (--load force.csv)")
    try:
        return PeriodicLoad.from_csv(file)
    except ValueError as err:
        raise UsageError(f"--load {file}: {err}") from None


class SimulationFailed(RuntimeError):
    """A simulation stopped before t_end (exit code 1, nothing written)."""


def failure_reason(ds, p, args) -> str:
    """The rule a failed simulation broke, in words, with its numbers."""
    status = ds.attrs["status"]
    method = ds.attrs.get("method", args.method)
    if status == "fixed_step_too_large":
        dt = args.dt if args.dt is not None else 2 * np.pi / p.omega / 50
        return (f"the fixed step dt = {dt:g} s is too large for method {method}: gps "
                f"and rk4 need omega dt <= 1, and omega = sqrt(k/m) = {p.omega:.6g} s-1 "
                f"here, so dt <= {1 / p.omega:.6g} s (give a smaller --dt, or --method "
                "dopri5)")
    if status == "gps_denominator_guard":
        return ("the group-preserving step's denominator ||u||^2 - tau^2 ||f||^2 "
                "(eqs. 49-50) was not safely positive: give a smaller --dt")
    if status == "step_budget_exceeded":
        return (f"the run used its budget of integrator steps before t_end = "
                f"{args.t_end:g} s: shorten --t-end, or loosen --tol")
    if status == "step_size_underflow":
        return ("the adaptive step fell below the floating-point resolution of t: "
                "loosen --tol")
    if status == "diverged":
        return "the state left the finite range (|x| or |zdot| > 1e150, or NaN)"
    if status == "event_location_failed":
        return "a stick/slip event could not be located inside a step"
    from .parser import doc
    return f"see {doc('variables.md')} (status codes)"


def cmd_info(args) -> int:
    """``sweepcore info``: what a result file holds."""
    ds = _open(args.result)
    print(f"{args.result}:")
    if ds.attrs.get("sweepcore_kind") in ("boundaries", "bifurcation_diagram"):
        print(describe_boundaries(ds))
    elif ds.attrs.get("sweepcore_kind") == "basins":
        print(describe_basins(ds))
    else:
        print(describe(ds))
    return 0


def cmd_compile(args) -> int:
    """``sweepcore compile``: the kernels of a law kind and method into the cache
    ahead of time (a line per kernel on stderr while it compiles)."""
    import numba
    from ..compiled import compile_kernels
    started = time.perf_counter()
    done = compile_kernels(args.law, args.method)
    fresh = [took for _what, took in done if took is not None]
    print(f"sweepcore compile: {len(fresh)} kernel(s) compiled in "
          f"{time.perf_counter() - started:.1f} s, {len(done) - len(fresh)} already in "
          f"the cache {numba.config.CACHE_DIR}")
    return 0


def cmd_export(args) -> int:
    """``sweepcore export``: a result file as CSV, units in the column headers."""
    ds = _open(args.result, "export")
    out = Path(args.csv)
    if out.suffix.lower() != ".csv":
        raise UsageError(f"--csv must end in .csv, got {str(out)!r}")
    _check_directories(out)
    if args.variables:
        ds = ds[_variable_names(args, ds, list(ds.data_vars))]
    tables = csv_tables(ds)
    tables["_units"] = units_table(ds, [c for frame in tables.values()
                                        for c in frame.columns])
    from ..io import temporary_name
    done = []
    try:        # every table under a temporary name first, then all renamed
        for suffix, frame in tables.items():
            path = out.with_name(out.stem + suffix + out.suffix)
            done.append((temporary_name(path, ".tmp"), path))
            frame.to_csv(done[-1][0], index=False)
        for tmp, path in done:
            os.replace(tmp, path)
    finally:
        for tmp, _path in done:
            tmp.unlink(missing_ok=True)
    print("wrote " + ", ".join(f"{path} ({len(frame)} rows)" for (_t, path), frame
                               in zip(done, tables.values())))
    return 0


def _variable_names(args, ds, known) -> list[str]:
    """The names of ``--variables a,b``, each a variable of the result (``known``):
    an unknown one is refused with the closest name and the list."""
    names = [n.strip() for n in args.variables.split(",") if n.strip()]
    if not names:
        raise UsageError("--variables: give at least one name")
    known = list(dict.fromkeys(known))
    for name in names:
        if name not in known:
            raise UsageError(f"--variables: {name!r} is not a variable of {args.result}"
                             f"{did_you_mean(name, known)} (has {', '.join(known)})")
    return names


def _open(path, command: str = "info"):
    from ..io import open_result
    try:
        return open_result(path)
    except (OSError, ValueError) as err:    # each names the file and what is wrong
        raise UsageError(_study_file(path, command) or str(err)) from None


def _study_file(path, command: str) -> str | None:
    """What to say when the file given for a result is a study file (TOML with an
    [axes] table): run it first, and where its result will be. None otherwise."""
    import tomllib
    try:
        if os.path.getsize(path) > 2**20:       # a study is a page of text
            return None
        with open(path, "rb") as fh:
            study = tomllib.load(fh)
    except (OSError, ValueError):
        return None
    if not isinstance(study.get("axes"), dict):
        return None
    output = study.get("output") if isinstance(study.get("output"), dict) else {}
    result = output.get("path") or f"{Path(path).stem}.nc"
    return (f"{path} is a study file, not a result file: run it with `sweepcore run "
            f"{shlex.quote(str(path))}` (it writes {result}), then `sweepcore {command} "
            f"{shlex.quote(str(result))}{' --csv OUT.csv' if command == 'export' else ''}`")


def cmd_boundary(args) -> int:
    """``sweepcore boundary``: boundaries, their continuation or a diagram."""
    from ..grid import Grid
    from ..study import load_study

    study = load_study(args.study)
    b = study.boundary or {}
    grid = Grid(**study.grid_kwargs())
    if not b:
        from ..study import parse_study
        b = parse_study(study.text + "\n[boundary]\n", study.path).boundary
    out, png = _resolve_outputs(args, b.get("path") or f"{study.stem}_boundaries.nc",
                                b.get("png"))
    if (args.scheduler or args.chunks) and (b["continuation"] or b["diagram"]):
        raise UsageError("--scheduler and --chunks apply to located boundaries, not to "
                         "a continuation or a diagram (sequential by nature)")
    over = args.over or b.get("over")
    if over and not over.endswith(".nc"):
        raise UsageError(f"--over must name a .nc map, got {over!r}")
    _check_directories(out, png)
    from ..io import result_path
    result_path(out)    # sweep's rules: no symbolic link, FIFO, read-only file, ...
    why = _no_curves(grid, b)
    if why and png is not None:
        if args.png is not None:
            raise UsageError(f"--png {args.png}: {why}; nothing written")
        if not args.quiet:
            print(f"(no picture: {why})")
        png = None
    say_time(args, f"sweepcore boundary {args.study}", grid, study,
              *_boundary_runs(grid, b), tol=b["tol"])
    t0 = time.perf_counter()
    ds = _boundary_result(grid, study, b, args)
    return _finish(ds, study, args, out, png, t0, None, boundary_lines,
                   attrs={"over": over} if over else {})


def _boundary_runs(grid, b) -> tuple[float, str]:
    """Attractor runs of the boundary command per grid point (``say_time``'s
    ``runs``, and the words that say so): each search scans ``scan`` values and
    bisects its two boundaries down to xtol (log2(span/xtol) runs each); a
    diagram runs every value of its axis once per direction."""
    along = np.atleast_1d(grid.axis(b["along"]))
    n_along = along.size
    if b["diagram"]:
        sweeps = 2 if (b.get("sweep") or "both") == "both" else 1
        return sweeps, f" ({sweeps} run(s) a point of the diagram)"
    span = float(b["bracket"][1] - b["bracket"][0]) if b.get("bracket") else \
        float(np.ptp(along)) or 1.0
    search = b["scan"] + 2 * max(1, math.ceil(math.log2(max(span / b["xtol"], 2.0))))
    return (search / n_along, f" ({search} runs a search: scan {b['scan']} and two "
                              "bisections to xtol)")


def _no_curves(grid, b) -> str | None:
    """Why located boundaries of ``grid`` cannot be drawn as curves (None: they can;
    decided before any work)."""
    if b["diagram"] or b["continuation"]:
        return None
    if not any(d != "v" and n > 1 for d, n in zip(grid.dims, grid.shape)):
        return ("boundary curves are drawn over a second swept parameter, and this "
                "study sweeps v only (its one point per boundary is in the summary)")
    return None


def _boundary_result(grid, study, b, args):
    from ..boundaries import continue_boundary, locate_boundaries
    from ..diagram import bifurcation_diagram

    common = dict(tol=b["tol"], method=study.method, **study.options)
    if b["diagram"]:
        sweep = getattr(args, "sweep", None) or b.get("sweep", "both")
        return bifurcation_diagram(grid, along=b["along"], sweep=sweep, **common)
    search = dict(along=b["along"], bracket=b["bracket"], xtol=b["xtol"],
                  scan=b["scan"], offset=b["offset"], **common)
    if b["continuation"]:
        return continue_boundary(grid, over=b["continuation"], **search)
    return locate_boundaries(grid, chunks=args.chunks, scheduler=args.scheduler,
                             **search)


def cmd_basins(args) -> int:
    """``sweepcore basins``: basin fractions over the study's grid ([basins])."""
    from ..basins import basin_stability
    from ..grid import Grid
    from ..study import load_study, parse_study

    study = load_study(args.study)
    b = study.basins or parse_study(study.text + "\n[basins]\n", study.path).basins
    grid = Grid(**study.grid_kwargs())
    out, png = _resolve_outputs(args, b["path"] or f"{study.stem}_basins.nc", b["png"])
    _check_directories(out, png)
    if not args.quiet:
        print(f"sweepcore basins {args.study}: {grid.size} points, route {b['route']}, "
              f"{b['samples']} samples a point where sampled", flush=True)
    common = dict(x0=b["x0"], xdot0=b["xdot0"], samples=b["samples"],
                  route=b["route"], sampling=b["sampling"], seed=b["seed"],
                  checks=b["checks"], ftol=b["ftol"], match=b["match"],
                  method=study.method, tol=study.tol, **study.options)
    say_call_time(args, f"sweepcore basins {args.study}", grid,
                   lambda g: basin_stability(g, progress=False, **common))
    t0 = time.perf_counter()
    # with path: run's rules for the file (no symbolic link, FIFO, read-only file,
    # ...) checked before any work, and an interrupted run resumes from the store
    ds = basin_stability(grid, chunks=args.chunks or study.chunks,
                         scheduler=args.scheduler, path=out, progress=_progress(args),
                         **common)
    return _finish(ds, study, args, out, png, t0, grid.size, basin_lines)
