"""The ``sweepcore`` command: run study files, simulate one slider, plot, inspect,
export.

Units everywhere (the paper's): force kN, length cm, time s; mass kN s^2/cm,
stiffness kN/cm, alpha1 kN s/cm, alpha2 kN s^3/cm^3.

Exit codes: 0 success; 2 a refused input (bad study file, bad parameter, unknown
option, missing output directory; nothing is written); 1 a failure while running
(a simulation that fails writes nothing); 130 interrupted (a sweep with an output
path resumes where it stopped when the same command is run again). Output
directories are never created: a missing one is refused, as by the Python API.
"""
from __future__ import annotations

import argparse
import difflib
import os
import shlex
import sys
import time
import traceback
from collections import Counter
from pathlib import Path

import numpy as np

UNITS_HELP = ("units: force kN, length cm, time s; mass kN s^2/cm, stiffness kN/cm, "
              "alpha1 kN s/cm, alpha2 kN s^3/cm^3")
THREAD_VARIABLES = ("NUMBA_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS",
                    "OPENBLAS_NUM_THREADS")


class UsageError(ValueError):
    """A refused command line (exit code 2)."""


# ------------------------------------------------------------------ threads
def set_threads(n: int) -> None:
    """Limit numba (and BLAS/OpenMP) to ``n`` threads, in this process and children.

    The environment variables are set for worker processes; numba, already imported
    by ``sweepcore``, is reconfigured before its thread pool starts.
    """
    for name in THREAD_VARIABLES:
        os.environ[name] = str(n)
    if "numba" in sys.modules:
        import numba
        numba.config.reload_config()
        numba.set_num_threads(min(n, numba.config.NUMBA_NUM_THREADS))


def _positive_int(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an integer >= 1, got {text!r}") \
            from None
    if n < 1:
        raise argparse.ArgumentTypeError(f"must be an integer >= 1, got {text!r}")
    return n


def _thread_count(text: str) -> int:
    """--threads: an integer from 1 to the threads numba allows (its
    NUMBA_NUM_THREADS, by default the number of cores)."""
    n = _positive_int(text)
    import numba
    top = numba.config.NUMBA_NUM_THREADS
    if n > top:
        raise argparse.ArgumentTypeError(
            f"must be at most {top} (the threads numba allows here: "
            f"NUMBA_NUM_THREADS, by default the number of cores), got {text!r}")
    return n


# ------------------------------------------------------------------- parser
def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``sweepcore`` (subcommands run, plot, simulate, info)."""
    parser = argparse.ArgumentParser(
        prog="sweepcore",
        description="Parameter sweeps of the stick-slip friction oscillator (Liu): a "
                    "slider of mass m on a belt of speed v, spring k, friction "
                    "r_a = r_y sgn(zdot) - alpha1 zdot + alpha2 zdot^3. " + UNITS_HELP
                    + ".",
        epilog="Examples: sweepcore run studies/hopf_map.toml; sweepcore info "
               "out/hopf_map.nc; sweepcore export out/hopf_map.nc --csv map.csv; "
               "sweepcore simulate --m 5 --k 50 --r-y 10 --v 5 --png fig3.png. "
               "Output variables and codes: docs/variables.md. "
               "Exit codes: 0 ok, 1 failure, 2 refused input.")
    parser.add_argument("--threads", type=_thread_count, metavar="N",
                        help="numba threads (sets NUMBA_NUM_THREADS and friends); "
                             "default: numba's (all cores)")
    parser.add_argument("--traceback", action="store_true",
                        help="show the full traceback of an error")
    from . import __version__
    parser.add_argument("--version", action="version", version=f"sweepcore {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    _add_run(sub)
    _add_plot(sub)
    _add_simulate(sub)
    _add_info(sub)
    _add_export(sub)
    _add_boundary(sub)
    return parser


def _add_run(sub):
    p = sub.add_parser(
        "run", help="run the sweep of a TOML study file, write netCDF and its picture",
        description="Run the sweep described by a TOML study file (format: "
                    "docs/studies.md), write the result as netCDF and draw it. The "
                    "study file is validated first: on any error nothing is written. "
                    "An interrupted run resumes when rerun with the same output. "
                    + UNITS_HELP + ".")
    p.add_argument("study", metavar="STUDY.toml", help="study file")
    p.add_argument("-o", "--output", metavar="OUT.nc",
                   help="netCDF result; default [output] path of the study, else "
                        "<study stem>.nc in the current directory")
    png = p.add_mutually_exclusive_group()
    png.add_argument("--png", metavar="FIG.png",
                     help="picture; default [output] png of the study, else the "
                          "result's path with .png")
    png.add_argument("--no-png", action="store_true", help="draw no picture")
    p.add_argument("--scheduler", metavar="ADDRESS|threads|processes|synchronous",
                   help="dask scheduler (one task per chunk) or a distributed "
                        "scheduler address tcp://host:port; default: numba threads "
                        "in this process")
    p.add_argument("--chunks", type=_positive_int, metavar="N",
                   help="points per chunk (task and resume unit); default [solver] "
                        "chunks, else sweepcore's choice")
    p.add_argument("-q", "--quiet", action="store_true",
                   help="no progress bar and no summary")
    p.set_defaults(func=cmd_run)


def _add_plot(sub):
    p = sub.add_parser(
        "plot", help="draw the natural picture of a result file",
        description="Draw a result: a 2-D sweep as regime and amplitude maps with "
                    "the analytic v* and the measured boundaries, a 1-D sweep as "
                    "amplitude and mean against its axis, a simulation as time "
                    "histories and phase planes (the paper's Fig. 3).")
    p.add_argument("result", metavar="RESULT.nc", help="netCDF result of run/simulate")
    p.add_argument("-o", "--output", metavar="FIG.png",
                   help="picture; default the result's path with .png")
    p.add_argument("--x", metavar="DIM", help="dimension across (maps); default v")
    p.add_argument("--y", metavar="DIM", help="dimension up (maps)")
    p.add_argument("--variables", metavar="NAME[,NAME...]",
                   help="panels, e.g. regime,amplitude,mean (sweeps)")
    p.set_defaults(func=cmd_plot)


def _add_simulate(sub):
    p = sub.add_parser(
        "simulate", help="simulate one slider: time histories and phase planes",
        description="Simulate one slider from (x0, xdot0) and draw z, zdot, x, xdot "
                    "against time and the phase planes (z, zdot) and (x, xdot), as "
                    "the paper's Fig. 3. " + UNITS_HELP + ".")
    req = p.add_argument_group("slider (required)")
    req.add_argument("--m", type=float, required=True, help="mass [kN s^2/cm], > 0")
    req.add_argument("--k", type=float, required=True, help="stiffness [kN/cm], > 0")
    req.add_argument("--r-y", dest="r_y", type=float, required=True,
                     help="friction bound r_y [kN], >= 0")
    req.add_argument("--v", type=float, required=True, help="belt speed [cm/s]")
    p.add_argument("--alpha1", type=float, default=0.0,
                   help="linear friction-speed coefficient [kN s/cm] (default 0)")
    p.add_argument("--alpha2", type=float, default=0.0,
                   help="cubic friction-speed coefficient [kN s^3/cm^3], >= 0 "
                        "(default 0)")
    p.add_argument("--x0", type=float, default=0.0, help="initial position [cm] "
                                                         "(default 0)")
    p.add_argument("--xdot0", type=float, default=None,
                   help="initial velocity [cm/s] (default v: start stuck on the belt)")
    p.add_argument("--t-end", dest="t_end", type=float, default=60.0,
                   help="end time [s] (default 60)")
    p.add_argument("--output-dt", dest="output_dt", type=float, default=None,
                   help="sampling interval [s] (default a hundredth of 2 pi/omega)")
    p.add_argument("--method", default="auto",
                   choices=("auto", "exact", "gps", "rk4", "dopri5"),
                   help="stepper (default auto: exact for alpha2 = 0, else dopri5)")
    p.add_argument("--tol", type=float, default=1e-10,
                   help="tolerance of dopri5 (default 1e-10)")
    p.add_argument("--dt", type=float, default=None,
                   help="fixed step of gps and rk4 [s] (default 2 pi/omega/50)")
    p.add_argument("-o", "--output", metavar="RUN.nc", help="write the run as netCDF")
    p.add_argument("--png", metavar="FIG.png", help="write the picture")
    p.set_defaults(func=cmd_simulate)


def _add_info(sub):
    p = sub.add_parser("info", help="summarise a result file",
                       description="Print the dimensions, axes with units, regime "
                                   "and status counts, converged fraction and the "
                                   "provenance attributes of a result file.")
    p.add_argument("result", metavar="RESULT.nc")
    p.set_defaults(func=cmd_info)


def _add_export(sub):
    p = sub.add_parser(
        "export", help="write a result file as CSV (one row per point or sample)",
        description="Write a result as CSV: a sweep as one row per grid point (the "
                    "swept parameters, then every variable), a simulation as one row "
                    "per time sample (its event log goes to <OUT stem>_events.csv). "
                    "Column headers carry the units, e.g. 'amplitude [cm]'; regime, "
                    "status and other flag variables are written as names. Meanings: "
                    "docs/variables.md.")
    p.add_argument("result", metavar="RESULT.nc", help="netCDF result of run/simulate")
    p.add_argument("--csv", required=True, metavar="OUT.csv", help="CSV file to write")
    p.add_argument("--variables", metavar="NAME[,NAME...]",
                   help="only these variables (default all)")
    p.set_defaults(func=cmd_export)


# ----------------------------------------------------------- compilation
COMPILE_MESSAGE = "sweepcore: compiling kernels, first run only, ~25 s"
# schedulers that run the kernels on this machine, from this machine's numba cache
LOCAL_SCHEDULERS = (None, "threads", "processes", "synchronous", "sync",
                    "single-threaded")


def kernels_cold(command: str, dask: bool = False) -> bool:
    """True when the numba cache holds no fresh machine code for the kernels that
    ``command`` ("run" or "simulate") calls first, so they compile on this call.

    Reads numba's cache index (the same test numba makes before compiling: index
    present, numba version and source stamp unchanged). Any surprise in numba's
    private cache API counts as warm: then no message, never a wrong one.
    """
    from ._kernels import attractor, trajectory
    try:
        if command == "simulate":
            kernels = (trajectory.run_trajectory, attractor.resolve_options)
        else:
            kernels = (attractor.attractor_rows if dask
                       else attractor.attractor_rows_parallel,)
        return any(not k._cache._cache_file._load_index() for k in kernels)
    except Exception:   # kernels renamed, or numba's cache internals changed: say nothing
        return False


def announce_compile(command: str, dask: bool, quiet: bool) -> None:
    """One line on stderr before a cold-cache compilation (silent otherwise)."""
    if not quiet and kernels_cold(command, dask):
        print(COMPILE_MESSAGE, file=sys.stderr, flush=True)


# ---------------------------------------------------------------- commands
def _resolve_outputs(study, args) -> tuple[Path, Path | None]:
    out = Path(args.output or study.output_path or f"{study.stem}.nc")
    if out.suffix != ".nc":
        raise UsageError(f"output must end in .nc, got {str(out)!r}")
    if args.no_png or (args.png is None and study.png is False):
        png = None
    elif args.png is not None:
        png = Path(args.png)
    elif isinstance(study.png, str):
        png = Path(study.png)
    else:
        png = out.with_suffix(".png")
    if png is not None and png.suffix.lower() != ".png":
        raise UsageError(f"picture must end in .png, got {str(png)!r}")
    _check_directories(out, png)
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
    from .grid import Grid
    from .options import make_options
    from .study import load_study

    study = load_study(args.study)
    grid = Grid(**study.grid_kwargs())
    make_options(study.method, tol=study.tol, **study.options)
    out, png = _resolve_outputs(study, args)
    return _run(args, study, grid, out, png)


def _run(args, study, grid, out, png) -> int:
    from .io import write_netcdf
    from .sweep import sweep

    if not args.quiet:
        print(f"sweepcore run {args.study}: {grid.size} points "
              f"({' x '.join(f'{d}: {n}' for d, n in zip(grid.dims, grid.shape))}), "
              f"method {study.method}, tol {study.tol:g}", flush=True)
    if args.scheduler in LOCAL_SCHEDULERS:   # else the cache is a worker's, or refused
        announce_compile("run", args.scheduler is not None, args.quiet)
    t0 = time.perf_counter()
    ds = sweep(grid, method=study.method, tol=study.tol,
               chunks=args.chunks or study.chunks, scheduler=args.scheduler, path=out,
               progress=False if args.quiet else None, **study.options)
    elapsed = time.perf_counter() - t0
    ds = label_with_study(ds, study, _command_line(args))
    write_netcdf(ds, out)
    if not args.quiet:
        print(f"wrote {out} ({grid.size} points in {elapsed:.1f} s)")
        print(regime_line(ds))
    if png is not None:
        from .plot import plot_result, save
        save(plot_result(ds, **study.plot), png)
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
    from . import __version__
    now = time.strftime("%Y-%m-%dT%H:%M:%S%z")
    return f"{now} sweepcore {__version__}: " + shlex.join(["sweepcore", *args.argv])


def cmd_plot(args) -> int:
    """``sweepcore plot``: the natural picture of a result file."""
    from .plot import plot_result, save

    ds = _open(args.result)
    out = Path(args.output) if args.output else Path(args.result).with_suffix(".png")
    if out.suffix.lower() != ".png":
        raise UsageError(f"picture must end in .png, got {str(out)!r}")
    _check_directories(out)
    if "time" in ds.dims and ds.attrs.get("status", "ok") != "ok":
        raise UsageError(f"{args.result} holds a failed simulation (status "
                         f"{ds.attrs['status']}): nothing to draw")
    kwargs = {}
    if "time" not in ds.dims:
        kwargs = {k: getattr(args, k) for k in ("x", "y") if getattr(args, k)}
        swept = [d for d in ds.dims if ds.sizes[d] > 1 and ds[d].dtype.kind in "iuf"]
        for key, dim in kwargs.items():
            if dim not in swept:
                raise UsageError(f"--{key} {dim}: not a swept axis of {args.result} "
                                 f"(swept: {', '.join(swept)})")
        if len(swept) < 2 and kwargs:
            raise UsageError("--x/--y apply to maps; this result has one swept axis")
        if args.variables:
            names = [s.strip() for s in args.variables.split(",") if s.strip()]
            missing = [n for n in names if n not in ds]
            if missing:
                raise UsageError(f"--variables: {', '.join(missing)} not in "
                                 f"{args.result} (has {', '.join(ds.data_vars)})")
            kwargs["variables"] = names
        elif "study" in ds.attrs:
            from .study import StudyError, parse_study
            try:
                kwargs = {**parse_study(ds.attrs["study"]).plot, **kwargs}
            except StudyError:    # a study of another version: default picture
                pass
    save(plot_result(ds, **kwargs), out)
    print(f"wrote {out}")
    return 0


def cmd_simulate(args) -> int:
    """``sweepcore simulate``: one slider, Fig. 3 style."""
    from .io import write_netcdf
    from .params import Params
    from .simulate import simulate

    p = Params(m=args.m, k=args.k, r_y=args.r_y, v=args.v, alpha1=args.alpha1,
               alpha2=args.alpha2)
    for path, suffix in ((args.output, ".nc"), (args.png, ".png")):
        if path is not None and Path(path).suffix.lower() != suffix:
            raise UsageError(f"{path!r} must end in {suffix}")
    _check_directories(args.output, args.png)
    extra = {"dt": args.dt} if args.dt is not None else {}
    announce_compile("simulate", False, False)
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
        from .plot import save, plot_trajectory
        save(plot_trajectory(ds), args.png)
        print(f"wrote {args.png}")
    if not (args.output or args.png):
        print("(nothing written: give -o RUN.nc and/or --png FIG.png)")
    return 0


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
    return "see docs/variables.md (status codes)"


def cmd_info(args) -> int:
    """``sweepcore info``: what a result file holds."""
    ds = _open(args.result)
    print(f"{args.result}:")
    if ds.attrs.get("sweepcore_kind") in ("boundaries", "bifurcation_diagram"):
        print(describe_boundaries(ds))
    else:
        print(describe(ds))
    return 0


def cmd_export(args) -> int:
    """``sweepcore export``: a result file as CSV, units in the column headers."""
    ds = _open(args.result)
    out = Path(args.csv)
    if out.suffix.lower() != ".csv":
        raise UsageError(f"--csv must end in .csv, got {str(out)!r}")
    _check_directories(out)
    if args.variables:
        names = [n.strip() for n in args.variables.split(",") if n.strip()]
        missing = [n for n in names if n not in ds.data_vars]
        if missing:
            raise UsageError(f"--variables: {', '.join(missing)} not in {args.result} "
                             f"(has {', '.join(ds.data_vars)})")
        ds = ds[names]
    tables = csv_tables(ds)
    written = []
    for suffix, frame in tables.items():
        path = out.with_name(out.stem + suffix + out.suffix)
        frame.to_csv(path, index=False)
        written.append(f"{path} ({len(frame)} rows)")
    print("wrote " + ", ".join(written))
    return 0


def csv_tables(ds) -> dict:
    """``{file suffix: pandas.DataFrame}``: one table per group of dimensions.

    A sweep is one table over its grid (variables on fewer dimensions, such as the
    measured boundary, are repeated along the others); a simulation one over
    ``time`` ("") and one over ``event`` ("_events"). Scalar coordinates (fixed
    parameters) are repeated as columns. Flag variables become their names; headers are
    ``name [units]``.
    """
    if "event" not in ds.dims:
        return {"": _frame(ds)}
    on_event = [n for n, v in ds.data_vars.items() if "event" in v.dims]
    rest = [n for n in ds.data_vars if n not in on_event]
    tables = {"": _frame(ds[rest])} if rest else {}
    if on_event:
        tables["_events"] = _frame(ds[on_event].drop_vars("time", errors="ignore"))
    return tables


def _frame(ds):
    frame = ds.to_dataframe().reset_index()
    columns = {}
    for name in frame.columns:
        attrs = ds[name].attrs if name in ds.variables else {}
        if "flag_values" in attrs and "flag_meanings" in attrs:
            codes = dict(zip(np.atleast_1d(attrs["flag_values"]).tolist(),
                             str(attrs["flag_meanings"]).split()))
            frame[name] = frame[name].map(lambda c: codes.get(int(c), f"code {c}"))
        units = str(attrs.get("units", ""))
        units = "s" if " since " in units else units
        columns[name] = f"{name} [{units}]" if units not in ("", "1") else name
    return frame.rename(columns=columns)


def _open(path):
    from .io import open_result
    if not Path(path).is_file():
        raise UsageError(f"no such result file: {path}")
    try:
        return open_result(path)
    except (OSError, ValueError) as err:
        raise UsageError(f"cannot read {path} as netCDF: {err}") from None


# ---------------------------------------------------------------- summaries
def _units(var) -> str:
    u = var.attrs.get("units", "")
    return "" if u in ("", "1") else f" {u}"


def _flag_counts(da) -> list[tuple[str, int]]:
    values = np.atleast_1d(da.attrs.get("flag_values", []))
    names = str(da.attrs.get("flag_meanings", "")).split()
    counts = Counter(np.asarray(da.values).ravel().tolist())
    out = [(name, counts.pop(int(val), 0)) for val, name in zip(values, names)]
    out += [(f"code {code}", n) for code, n in sorted(counts.items())]
    return out


def regime_line(ds) -> str:
    """One line of regime counts, e.g. ``regime: equilibrium 120, stick_slip 80``."""
    if "regime" not in ds:
        return ""
    return "regime: " + ", ".join(f"{n} {c}" for n, c in _flag_counts(ds["regime"])
                                  if c)


def describe(ds) -> str:
    """Multi-line summary of a sweep or simulation Dataset (``sweepcore info``)."""
    if "time" in ds.dims:
        return _describe_simulation(ds)
    lines = []
    size = int(np.prod([ds.sizes[d] for d in ds.dims])) if ds.dims else 1
    shape = " x ".join(f"{d}: {n}" for d, n in ds.sizes.items())
    lines.append(f"  sweep of {size} points ({shape})")
    for key in ("study_title", "study_file"):
        if ds.attrs.get(key):
            lines.append(f"  {key.replace('_', ' ')}: {ds.attrs[key]}")
    lines.append("  axes:")
    for d in ds.dims:
        c = ds[d]
        vals = c.values
        spacing = c.attrs.get("spacing", "")
        name = f"{c.attrs.get('long_name', '')} [{c.attrs.get('units', '')}]"
        lines.append(f"    {d:8s} {name}: {vals.size} values in [{vals.min():.6g}, {vals.max():.6g}]"
                     + (f" ({spacing})" if spacing else ""))
    fixed = [n for n in ds.coords if ds[n].ndim == 0]
    if fixed:
        lines.append("  fixed: " + ", ".join(f"{n} = {float(ds[n]):.6g}{_units(ds[n])}"
                                             for n in fixed))
    if "initial_velocity" in ds.attrs:
        lines.append(f"  start: {ds.attrs['initial_velocity']}")
    for var in ("regime", "status"):
        if var in ds:
            lines.append(f"  {var} counts:")
            for name, count in _flag_counts(ds[var]):
                if count:
                    lines.append(f"    {name:22s} {count:9d}  ({100 * count / size:.3g} %)")
    if "converged" in ds:
        n = int(np.asarray(ds["converged"].values).sum())
        lines.append(f"  converged: {n} of {size} ({100 * n / size:.6g} %)")
    for var in ("amplitude", "mean", "period"):
        if var in ds:
            vals = ds[var].values
            if np.isfinite(vals).any():
                lines.append(f"  {var}: [{np.nanmin(vals):.6g}, {np.nanmax(vals):.6g}]"
                             f"{_units(ds[var])}")
    lines.extend(_boundary_lines(ds))
    lines.append("  attributes:")
    for key in ("method", "tol", "max_steps", "max_periods", "dt", "graze",
                "Conventions", "source", "history"):
        if key in ds.attrs:
            text = str(ds.attrs[key]).replace("\n", "\n" + " " * 16)
            lines.append(f"    {key:12s}{text}")
    return "\n".join(lines)


def _boundary_lines(ds) -> list[str]:
    if "v_hopf_measured" not in ds or "v_star" not in ds:
        return []
    measured = ds["v_hopf_measured"]
    ok = np.isfinite(measured.values)
    if not ok.any():
        return ["  measured Hopf boundary: no switch from a cycle to equilibrium"]
    vs = ds["v_star"]
    vs = vs.isel(v=0) if "v" in vs.dims else vs
    diff = (measured - vs).values
    sel = ok & np.isfinite(diff)
    res = ds["v_hopf_resolution"].values[sel] if "v_hopf_resolution" in ds else None
    text = (f"  measured Hopf boundary: {int(ok.sum())} of {ok.size} rows switch; "
            f"|v_measured - v*| <= {np.max(np.abs(diff[sel])):.3g} cm s-1"
            if sel.any() else "")
    if res is not None and res.size:
        text += f" (grid resolution +-{np.max(res):.3g})"
    return [text] if text else []


def _scalar(ds, name) -> float:
    """A simulation's parameter: scalar coordinate (older files: global attribute)."""
    if name in ds.coords and ds[name].ndim == 0:
        return float(ds[name])
    return float(ds.attrs.get(name, np.nan))


def _describe_simulation(ds) -> str:
    a = ds.attrs
    t = ds.time.values
    lines = [f"  simulation: {t.size} samples over t in [{t[0]:.6g}, {t[-1]:.6g}] s",
             "  slider: " + ", ".join(f"{n} = {_scalar(ds, n):.6g}{_units(ds[n])}"
                                      if n in ds.coords else f"{n} = {_scalar(ds, n):.6g}"
                                      for n in ("m", "k", "r_y", "v", "alpha1", "alpha2")
                                      if np.isfinite(_scalar(ds, n))),
             f"  start: x0 = {_scalar(ds, 'x0'):.6g} cm, "
             f"xdot0 = {_scalar(ds, 'xdot0'):.6g} cm s-1",
             f"  method: {a.get('method', '?')}, status: {a.get('status', '?')}, "
             f"steps: {a.get('n_steps', '?')}"]
    if "event_kind" in ds:
        counts = [(n, c) for n, c in _flag_counts(ds["event_kind"]) if c]
        lines.append("  events: " + (", ".join(f"{n} {c}" for n, c in counts)
                                     if counts else "none"))
    x = ds.x.values
    tail = (t >= t[-1] - 0.2 * (t[-1] - t[0])) & np.isfinite(x)
    if tail.any():
        lines.append(f"  x over the last 20 % of the run: [{x[tail].min():.6g}, "
                     f"{x[tail].max():.6g}] cm")
    else:
        lines.append("  x over the last 20 % of the run: no valid sample (the run "
                     "stopped early)")
    if "history" in a:
        lines.append(f"  history: {a['history']}")
    return "\n".join(lines)


def simulation_summary(ds, p) -> str:
    """Summary of a fresh simulation with the slider's analytic quantities."""
    return (_describe_simulation(ds) + "\n"
            f"  analytic: omega = {p.omega:.6g} s-1, q = {p.q:.6g} s-1 (eq. 46), "
            f"v* = {p.v_star:.6g} cm s-1, x_eq = {p.x_eq:.6g} cm (eq. 43)")


# ----------------------------------------------------------------- boundary
def _add_boundary(sub):
    p = sub.add_parser(
        "boundary", help="locate the Hopf point and the stick onset to full precision, "
                         "or draw a bifurcation diagram",
        description="Locate the regime boundaries of a study along v (the Hopf point "
                    "from the cycle's amplitude, the stick onset from the grazing of "
                    "the cycle with the belt, every other change from the labels) to "
                    "xtol, for every point of the other axes, or follow them along one "
                    "parameter by continuation, or scan a bifurcation diagram up and "
                    "down; settings in the study's [boundary] table (docs/studies.md). "
                    + UNITS_HELP + ".")
    p.add_argument("study", metavar="STUDY.toml", help="study file")
    p.add_argument("-o", "--output", metavar="OUT.nc",
                   help="netCDF result; default [boundary] path, else "
                        "<study stem>_boundaries.nc")
    png = p.add_mutually_exclusive_group()
    png.add_argument("--png", metavar="FIG.png",
                     help="picture; default [boundary] png, else the result's path "
                          "with .png")
    png.add_argument("--no-png", action="store_true", help="draw no picture")
    p.add_argument("--scheduler", metavar="ADDRESS|threads|processes|synchronous",
                   help="as for run (not for continuation or diagrams)")
    p.add_argument("--chunks", type=_positive_int, metavar="N",
                   help="points per task (not for continuation or diagrams)")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary")
    p.set_defaults(func=cmd_boundary)


def cmd_boundary(args) -> int:
    """``sweepcore boundary``: boundaries, their continuation or a diagram."""
    from .grid import Grid
    from .io import write_netcdf
    from .study import load_study

    study = load_study(args.study)
    b = study.boundary or {}
    grid = Grid(**study.grid_kwargs())
    if not b:
        from .study import parse_study
        b = parse_study(study.text + "\n[boundary]\n", study.path).boundary
    out = Path(args.output or b.get("path") or f"{study.stem}_boundaries.nc")
    if out.suffix != ".nc":
        raise UsageError(f"output must end in .nc, got {str(out)!r}")
    png = None if args.no_png else Path(args.png or b.get("png") or out.with_suffix(".png"))
    if png is not None and png.suffix.lower() != ".png":
        raise UsageError(f"picture must end in .png, got {str(png)!r}")
    if (args.scheduler or args.chunks) and (b["continuation"] or b["diagram"]):
        raise UsageError("--scheduler and --chunks apply to located boundaries, not to "
                         "a continuation or a diagram (sequential by nature)")
    _check_directories(out, png)
    t0 = time.perf_counter()
    ds = _boundary_result(grid, study, b, args)
    elapsed = time.perf_counter() - t0
    ds = label_with_study(ds, study, _command_line(args))
    if b.get("over"):
        ds.attrs["over"] = b["over"]
    write_netcdf(ds, out)
    if not args.quiet:
        print(f"wrote {out} ({elapsed:.1f} s)")
        for line in boundary_lines(ds):
            print(line)
    if png is not None and ds.attrs.get("sweepcore_kind") == "boundaries" and \
            "v_star" not in ds:
        print(f"(no picture: boundary curves are drawn for searches along v, this "
              f"one is along {b['along']})")
        png = None
    if png is not None:
        from .plot import plot_result, save
        save(plot_result(ds), png)
        if not args.quiet:
            print(f"wrote {png}")
    return 0


def _boundary_result(grid, study, b, args):
    from .boundaries import continue_boundary, locate_boundaries
    from .diagram import bifurcation_diagram

    common = dict(tol=b["tol"], method=study.method, **study.options)
    if b["diagram"]:
        return bifurcation_diagram(grid, along=b["along"], **common)
    search = dict(along=b["along"], bracket=b["bracket"], xtol=b["xtol"],
                  scan=b["scan"], offset=b["offset"], **common)
    if b["continuation"]:
        return continue_boundary(grid, over=b["continuation"], **search)
    return locate_boundaries(grid, chunks=args.chunks, scheduler=args.scheduler,
                             **search)


def describe_boundaries(ds) -> str:
    """``sweepcore info`` of a boundaries or bifurcation-diagram result."""
    kind = ds.attrs["sweepcore_kind"].replace("_", " ")
    shape = ", ".join(f"{d}: {n}" for d, n in ds.sizes.items())
    lines = [f"  {kind} ({shape})"]
    for d in ds.dims:
        if ds[d].dtype.kind == "f":
            v = ds[d].values
            lines.append(f"    {d:8s} {ds[d].attrs.get('long_name', '')} "
                         f"[{ds[d].attrs.get('units', '')}]: {v.size} values in "
                         f"[{v.min():.6g}, {v.max():.6g}]")
    fixed = [n for n in ds.coords if ds[n].ndim == 0]
    if fixed:
        lines.append("  fixed: " + ", ".join(f"{n} = {float(ds[n]):.6g}{_units(ds[n])}"
                                             for n in fixed))
    lines.extend(boundary_lines(ds))
    for key in ("tol", "history"):
        if key in ds.attrs:
            text = str(ds.attrs[key]).replace("\n", "\n" + " " * 12)
            lines.append(f"  {key:9s} {text}")
    return "\n".join(lines)


def boundary_lines(ds) -> list[str]:
    """Summary of a boundaries or diagram result: what was located, against v*."""
    from .boundaries import LOCATED
    if ds.attrs.get("sweepcore_kind") == "bifurcation_diagram":
        lines = ["  " + regime_line(ds)]
        for name in ("v_hopf", "v_stick_onset", "v_star"):
            if name in ds:
                lines.append(f"  {name} = {float(ds[name]):.10g} cm s-1")
        return lines
    lines = []
    for name, status, width in (("v_hopf", "hopf_status", "v_hopf_error"),
                                ("v_stick_onset", "stick_status",
                                 "v_stick_onset_width")):
        ok = ds[status].values == LOCATED
        line = f"  {name}: located at {int(ok.sum())} of {ok.size} points"
        if ok.any():
            line += f", {width} <= {np.nanmax(ds[width].values[ok]):.2g}"
        lines.append(line)
    if "v_star" not in ds:      # searched along another parameter than v
        lines.append(f"  attractors computed: {int(ds['evaluations'].sum())}")
        return lines
    hopf = ds["hopf_status"].values == LOCATED
    if hopf.any():
        dv = np.abs(ds["v_hopf"] - ds["v_star"]).values[hopf]
        lines.append(f"  |v_hopf - v*| <= {dv.max():.3g} cm s-1")
    stick = ds["stick_status"].values == LOCATED
    if stick.any():
        r = (ds["v_stick_onset"] / ds["v_star"]).values[stick]
        lines.append(f"  v_stick_onset / v* in [{r.min():.10f}, {r.max():.10f}] "
                     f"(averaging sqrt(4/5) = {np.sqrt(0.8):.10f})")
    lines.append(f"  attractors computed: {int(ds['evaluations'].sum())}")
    return lines


# --------------------------------------------------------------------- main
def main(argv=None) -> int:
    """Entry point of the ``sweepcore`` command; returns the exit code.

    A closed output pipe (``sweepcore info map.nc | head -3``) ends the command
    quietly: the rest of the output is discarded.
    """
    try:
        code = _main(argv)
        sys.stdout.flush()
        return code
    except BrokenPipeError:
        # stdout's reader is gone: point stdout at /dev/null so that the flush at
        # interpreter exit does not raise again
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0


def _main(argv) -> int:
    parser = build_parser()
    argv = sys.argv[1:] if argv is None else list(map(str, argv))
    unknown = unknown_option(parser, argv)
    if unknown:
        command, message = unknown
        print(f"sweepcore{' ' + command if command else ''}: error: {message}",
              file=sys.stderr)
        return 2
    args = parser.parse_args(argv)
    args.argv = argv
    if args.threads:
        set_threads(args.threads)
    from .study import StudyError
    try:
        return args.func(args)
    except KeyboardInterrupt:
        print("sweepcore: interrupted (rerun the same command to resume a sweep)",
              file=sys.stderr)
        return 130
    except BrokenPipeError:
        raise
    except SimulationFailed as err:
        print(f"sweepcore {args.command}: failed: {err}", file=sys.stderr)
        return 1
    except (StudyError, UsageError, ValueError, TypeError) as err:
        # refused input (Params, Grid, options, study file): one clean line. plot and
        # info validate their input themselves (UsageError); a ValueError deeper in
        # them is a failure, not a refusal.
        if args.command in ("plot", "info", "export") and not isinstance(err, UsageError):
            return _failed(args, err)
        if args.traceback:
            traceback.print_exc()
        print(f"sweepcore {args.command}: error: {err}", file=sys.stderr)
        return 2
    except Exception as err:  # a failure while running
        return _failed(args, err)


def _options(parser) -> list[str]:
    return [o for a in parser._actions for o in a.option_strings]


def unknown_option(parser, argv) -> tuple[str, str] | None:
    """``(command, message)`` for the first unknown option in ``argv``, else None.

    argparse checks required options before it reports unknown ones, so ``--ry 10``
    would read as a missing ``--r-y``; this names the typo and the closest option
    instead. Unambiguous prefixes (``--t-e``) are accepted, as argparse does.
    """
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    command, known = "", _options(parser)
    takes_value = {o for a in parser._actions if a.nargs != 0
                   for o in a.option_strings}
    skip = False
    for token in argv:
        if skip:
            skip = False
            continue
        if token == "--":
            return None
        if not command and token in sub.choices:
            command = token
            known = _options(sub.choices[token])
            takes_value = {o for a in sub.choices[token]._actions if a.nargs != 0
                           for o in a.option_strings}
            continue
        if token in known:       # short options too (-o, -q): does a value follow?
            skip = token in takes_value
            continue
        if not token.startswith("--"):   # values, numbers, grouped short flags: argparse's
            continue
        name = token.split("=", 1)[0]
        matches = [o for o in known if o.startswith(name)]
        if matches:      # a value follows an option that takes one
            skip = "=" not in token and (name if name in known else matches[0]) \
                in takes_value
            continue
        close = difflib.get_close_matches(name, known, n=1, cutoff=0.6)
        hint = f"; did you mean {close[0]}?" if close else ""
        where = f"sweepcore {command}" if command else "sweepcore"
        return command, (f"unknown option {name}{hint} (see {where} --help)")
    return None


def _failed(args, err) -> int:
    if args.traceback:
        traceback.print_exc()
    print(f"sweepcore {args.command}: failed: {type(err).__name__}: {err} "
          "(--traceback shows where)", file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
