"""The command line of ``sweepcore``: its subcommands and options, declared once."""
from __future__ import annotations

import argparse
import os
import textwrap
from pathlib import Path


UNITS_HELP = ("units: force kN, length cm, time s; mass kN s^2/cm, stiffness kN/cm, "
              "alpha1 kN s/cm, alpha2 kN s^3/cm^3")
THREAD_VARIABLES = ("NUMBA_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS",
                    "OPENBLAS_NUM_THREADS")


# ------------------------------------------------------------------ threads
def set_threads(n: int) -> None:
    """Limit numba (and BLAS/OpenMP) to ``n`` threads, in this process and children.

    The environment variables are set for worker processes; numba, already imported
    by ``sweepcore``, is reconfigured before its thread pool starts. Once the pool
    runs (``main`` called again in one process), NUMBA_NUM_THREADS is left alone:
    numba re-reads it at every compilation and refuses a value other than the
    pool's; ``numba.set_num_threads`` limits the threads used instead.
    """
    import numba
    from numba.np.ufunc import parallel
    launched = bool(getattr(parallel, "_is_initialized", False))
    for name in THREAD_VARIABLES:
        if not (launched and name == "NUMBA_NUM_THREADS"):
            os.environ[name] = str(n)
    if not launched:
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


# --max-time: seconds, or a number with a unit
DURATION_UNITS = {"s": 1.0, "min": 60.0, "h": 3600.0, "d": 86400.0}


def max_time(text: str) -> float | None:
    """--max-time: ``3600``, ``90s``, ``30min``, ``2h``, ``1d`` [s], or ``none``
    (no limit)."""
    if text.strip().lower() == "none":
        return None
    number, unit = text.strip(), "s"
    for name in sorted(DURATION_UNITS, key=len, reverse=True):
        if number.endswith(name):
            number, unit = number[:-len(name)].strip(), name
            break
    try:
        seconds = float(number) * DURATION_UNITS[unit]
    except ValueError:
        seconds = float("nan")
    if not (seconds > 0 and seconds < float("inf")):
        raise argparse.ArgumentTypeError(
            f"must be a duration > 0 (seconds, or with a unit: 90s, 30min, 2h, 1d) or "
            f"'none', got {text!r}")
    return seconds


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


def doc(name: str) -> str:
    """The page ``docs/<name>`` where it is on this machine: the copy installed with
    the package (``sweepcore/docs``, in the wheel), else its source-tree name."""
    page = Path(__file__).resolve().parents[1] / "docs" / name
    return str(page) if page.is_file() else f"docs/{name}"


# ------------------------------------------------------------------- parser
class HelpFormatter(argparse.HelpFormatter):
    """argparse's formatter, but a line never breaks at a hyphen or inside a word:
    the help prints the documentation pages' paths, which must survive a copy (a
    checkout under ``/work/wt-x/`` was cut at its hyphen)."""

    def _split_lines(self, text, width):
        return textwrap.wrap(" ".join(text.split()), width, break_on_hyphens=False,
                             break_long_words=False)

    def _fill_text(self, text, width, indent):
        return textwrap.fill(" ".join(text.split()), width, initial_indent=indent,
                             subsequent_indent=indent, break_on_hyphens=False,
                             break_long_words=False)


def _forced_help() -> str:
    return ("Forced vibration: a periodic load F0 p(Omega t + phi) [kN] on the slider "
            "(p one cosine, or any shape: its harmonics or one period of samples) "
            "and a motion Y0 cos(Omega t) [cm] of its anchor, Omega in rad/s, phi in "
            "rad (m x'' + c (x' - y') + k (x - y) + r_a = F0 p(Omega t + phi)). A "
            "study's [excitation] table sweeps F0, Omega, phi, Y0 and names the load "
            "(run: stops and sticks per period, multiplicity, amplitude; "
            "studies/forced_map.toml); simulate --F0 F0 --Omega OMEGA [--phi PHI] "
            "[--Y0 Y0] [--load FILE.csv] runs one forced slider; from Python, sweepcore.frequency_response (up and down sweeps "
            "in Omega) and sweepcore.stroboscopic_diagram. Documented in "
            f"{doc('studies.md')} (The [excitation] table), {doc('variables.md')} "
            f"(Forced response) and {doc('physics.md')} (Forced vibration).")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``sweepcore`` (the subcommands of :data:`SUBCOMMANDS`)."""
    parser = argparse.ArgumentParser(
        prog="sweepcore", formatter_class=HelpFormatter,
        description="Parameter sweeps of the stick-slip friction oscillator (Liu): a "
                    "slider of mass m on a belt of speed v, spring k, friction "
                    "r_a = sgn(zdot) (r_k + (r_y - r_k) exp(-|zdot|/v_s)) - alpha1 zdot "
                    "+ alpha2 zdot^3, damping c (r_k = r_y: eq. 40). " + _forced_help()
                    + " " + UNITS_HELP + ".",
        epilog="Examples: sweepcore run studies/hopf_map.toml; sweepcore info "
               "out/hopf_map.nc; sweepcore export out/hopf_map.nc --csv map.csv; "
               "sweepcore simulate --m 5 --k 50 --r-y 10 --v 5 --png fig3.png; "
               "sweepcore run studies/forced_map.toml; sweepcore simulate --m 1 --k 1 "
               "--r-y 0.3 --v 0 --F0 1 --Omega 0.8 --png forced.png. "
               f"Output variables and codes: {doc('variables.md')}. "
               "Exit codes: 0 ok, 1 failure, 2 refused input.")
    _add_global_options(parser, argparse.SUPPRESS)
    parser.set_defaults(threads=None, traceback=False)
    parser.add_argument("--version", action=_Version, nargs=0,
                        help="show the version and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, (summary, description, add_options) in SUBCOMMANDS.items():
        p = sub.add_parser(name, help=summary, description=description,
                           formatter_class=HelpFormatter)
        add_options(p)
        # before or after the subcommand alike: `sweepcore run --threads 1 S.toml`
        _add_global_options(p.add_argument_group("global options"), argparse.SUPPRESS)
    return parser


class _Version(argparse.Action):
    """--version, reading the version only when asked (``labels`` imports xarray)."""

    def __call__(self, parser, namespace, values, option_string=None):
        from ..labels import version
        parser.exit(message=f"sweepcore {version()}\n")


class _Lazy:
    """Choices of an option read from the package only when argparse looks at them
    (the method and law tables import numba): ``sweepcore --help`` stays quick. The
    option needs a metavar (argparse formats the choices of one without it when the
    option is added)."""

    def __init__(self, read):
        self.read = read

    def __iter__(self):
        return iter(self.read())

    def __contains__(self, value):
        return value in self.read()

    def __len__(self):
        return len(self.read())

    def __getitem__(self, i):
        return self.read()[i]


def _methods():
    from ..options import METHODS
    return METHODS


def _add_global_options(p, default) -> None:
    """--threads and --traceback, accepted before and after the subcommand.

    Their ``default`` is ``argparse.SUPPRESS`` on both parsers, so an option given
    on one is not overwritten by the other's default (the top-level parser's
    ``set_defaults`` supplies the values when neither gives one)."""
    p.add_argument("--threads", type=_thread_count, metavar="N", default=default,
                   help="numba threads (sets NUMBA_NUM_THREADS and friends); "
                        "default: numba's (all cores)")
    p.add_argument("--traceback", action="store_true", default=default,
                   help="show the full traceback of an error")


def _add_study_options(p, output: str, png: str, scheduler: str, chunks: str,
                       quiet: str) -> None:
    """The options of the commands that run a study file (run, boundary, basins), declared
    once: the study, the result and its picture, the executor, the quiet switch;
    each command gives its own help texts (its defaults differ)."""
    p.add_argument("study", metavar="STUDY.toml", help="study file")
    p.add_argument("-o", "--output", metavar="OUT.nc", help=output)
    group = p.add_mutually_exclusive_group()
    group.add_argument("--png", metavar="FIG.png", help=png)
    group.add_argument("--no-png", action="store_true", help="draw no picture")
    p.add_argument("--scheduler", metavar="ADDRESS|threads|processes|synchronous",
                   help=scheduler)
    p.add_argument("--chunks", type=_positive_int, metavar="N", help=chunks)
    p.add_argument("--max-time", dest="max_time", type=max_time, default=3600.0,
                   metavar="DURATION",
                   help="refuse, before any work, a run whose time measured on a "
                        "sample of its points exceeds this (seconds, or 90s, 30min, "
                        "2h, 1d; 'none': no limit); default 1h")
    p.add_argument("-q", "--quiet", action="store_true", help=quiet)


def _run_options(p):
    _add_study_options(
        p, output="netCDF result; default [output] path of the study, else <study "
                  "stem>.nc in the current directory",
        png="picture; default [output] png of the study, else the result's path with "
            ".png",
        scheduler="dask scheduler (one task per chunk) or a distributed scheduler "
                  "address tcp://host:port; default: numba threads in this process",
        chunks="points per chunk (task and resume unit); default [solver] chunks, else "
               "sweepcore's choice",
        quiet="no progress bar and no summary")


def _plot_options(p):
    p.add_argument("result", metavar="RESULT.nc", help="netCDF result of run/simulate")
    p.add_argument("-o", "--output", metavar="FIG.png",
                   help="picture; default the result's path with .png")
    p.add_argument("--x", metavar="DIM", help="dimension across (maps); default v")
    p.add_argument("--y", metavar="DIM", help="dimension up (maps)")
    p.add_argument("--variables", metavar="NAME[,NAME...]",
                   help="panels, e.g. regime,amplitude,mean (sweeps)")


def _simulate_options(p):
    req = p.add_argument_group("slider (required)")
    req.add_argument("--m", type=float, required=True, help="mass [kN s^2/cm], > 0")
    req.add_argument("--k", type=float, required=True, help="stiffness [kN/cm], > 0")
    p.add_argument("--r-y", dest="r_y", type=float, default=None,
                   help="friction bound r_y [kN], >= 0 (required unless --law-table)")
    req.add_argument("--v", type=float, required=True, help="belt speed [cm/s]")
    p.add_argument("--alpha1", type=float, default=0.0,
                   help="linear friction-speed coefficient [kN s/cm] (default 0)")
    p.add_argument("--alpha2", type=float, default=0.0,
                   help="cubic friction-speed coefficient [kN s^3/cm^3], >= 0 "
                        "(default 0)")
    p.add_argument("--c", type=float, default=0.0,
                   help="viscous damping on the slider [kN s/cm], >= 0 (default 0)")
    p.add_argument("--r-k", dest="r_k", type=float, default=None,
                   help="kinetic friction level of the Stribeck law [kN], >= 0 "
                        "(default r_y: no Stribeck term)")
    p.add_argument("--v-s", dest="v_s", type=float, default=None,
                   help="Stribeck speed [cm/s], >= 0 (needed with --r-k; 0: "
                        "a jump from r_y to r_k at zero speed)")
    law = p.add_argument_group("a measured friction law (instead of --r-y ... --v-s)")
    law.add_argument("--law-table", dest="law_table", metavar="FILE.csv", default=None,
                     help="force against relative speed, header 'speed [cm/s],force "
                          "[kN]' (m/s, mm/s; N too): sweepcore.TableLaw.from_csv")
    law.add_argument("--static", type=float, default=None,
                     help="largest force sticking holds [kN] (default F(0+))")
    law.add_argument("--smoothing", type=float, default=None,
                     help="noise of the forces [kN]: a smoothing fit (default: "
                          "interpolate)")
    forced = p.add_argument_group(
        "an excitation (m x'' + c (x' - y') + k (x - y) + r_a = "
        "F0 p(Omega t + phi), y = Y0 cos(Omega t); p = cos unless --load)")
    forced.add_argument("--F0", type=float, default=0.0,
                        help="load amplitude [kN] (default 0: none)")
    forced.add_argument("--Omega", type=float, default=None,
                        help="excitation frequency [rad/s], > 0 (needed with --F0 or "
                             "--Y0)")
    forced.add_argument("--phi", type=float, default=0.0,
                        help="phase of the load in radians, |phi| <= 2 pi (90 "
                             "degrees: 1.5708; default 0)")
    forced.add_argument("--Y0", type=float, default=0.0,
                        help="amplitude of the anchor's motion [cm] (default 0: none)")
    forced.add_argument("--load", metavar="FILE.csv", default=None,
                        help="the load's shape p over one period, as samples at uniform "
                             "phases (one value per row, a header allowed): the load is "
                             "F0 p(Omega t + phi) (default p = cos)")
    p.add_argument("--x0", type=float, default=0.0, help="initial position [cm] "
                                                         "(default 0)")
    p.add_argument("--xdot0", type=float, default=None,
                   help="initial velocity [cm/s] (default v: start stuck on the belt)")
    p.add_argument("--t-end", dest="t_end", type=float, default=60.0,
                   help="end time [s] (default 60)")
    p.add_argument("--output-dt", dest="output_dt", type=float, default=None,
                   help="sampling interval [s] (default a hundredth of 2 pi/omega)")
    p.add_argument("--method", default="auto", choices=_Lazy(_methods), metavar="METHOD",
                   help="stepper: %(choices)s (default auto: exact for a "
                        "piecewise-linear law, "
                        "else dop853 below tol 1e-7, dopri5 above)")
    p.add_argument("--tol", type=float, default=1e-10,
                   help="tolerance of the adaptive steppers (default 1e-10, tighter "
                        "than run's 1e-8: a time history carries the error of every "
                        "step to t_end, where an attractor's observables converge "
                        "onto the attractor; sweepcore.simulate's default too)"),
    p.add_argument("--dt", type=float, default=None,
                   help="fixed step of gps and rk4 [s] (default 2 pi/omega/50)")
    p.add_argument("-o", "--output", metavar="RUN.nc", help="write the run as netCDF")
    p.add_argument("--png", metavar="FIG.png", help="write the picture")


def _kinds():
    from .._kernels.laws import LAWS
    return (*(row[0] for row in LAWS), "all")


def _compile_options(p):
    p.add_argument("--law", default="all", metavar="KIND", choices=_Lazy(_kinds),
                   help="law kind of the kernels' law table: %(choices)s (default "
                        "all; polynomial is eq. 40, stribeck with the Stribeck term)")
    p.add_argument("--method", default="dop853",
                   choices=_Lazy(lambda: (*_methods()[1:], "all")), metavar="METHOD",
                   help="stepper: %(choices)s; default dop853 (what auto runs at the "
                        "default tolerance)")


def _info_options(p):
    p.add_argument("result", metavar="RESULT.nc")


def _export_options(p):
    p.add_argument("result", metavar="RESULT.nc", help="netCDF result of run/simulate")
    p.add_argument("--csv", required=True, metavar="OUT.csv", help="CSV file to write")
    p.add_argument("--variables", metavar="NAME[,NAME...]",
                   help="only these variables (default all)")


def _boundary_options(p):
    _add_study_options(
        p, output="netCDF result; default [boundary] path, else <study "
                  "stem>_boundaries.nc",
        png="picture; default [boundary] png, else the result's path with .png",
        scheduler="as for run (not for continuation or diagrams)",
        chunks="points per task (not for continuation or diagrams)",
        quiet="no summary")
    p.add_argument("--over", metavar="MAP.nc",
                   help="map to draw the curves over; default [boundary] over")
    p.add_argument("--sweep", choices=("up", "down", "both"),
                   help="direction of a diagram's scan (default [boundary] sweep, "
                        "else both: up, then down)")


def _basins_options(p):
    _add_study_options(
        p, output="netCDF result; default [basins] path, else <study stem>_basins.nc",
        png="picture; default [basins] png, else the result's path with .png",
        scheduler="as for run", chunks="grid points per task", quiet="no summary")


# name -> (one-line help, description, the function adding its options); the
# command's function is commands.cmd_<name> (imported when the command runs)
SUBCOMMANDS = {
    "run": (
        "run the sweep of a TOML study file, write netCDF and its picture",
        f"Run the sweep described by a TOML study file (format: {doc('studies.md')}), "
        "write the result as netCDF and draw it. The study file is validated first: "
        "on any error nothing is written. An interrupted run resumes when rerun with "
        "the same output. A study with an [excitation] table (F0, Omega, phi, Y0) "
        "sweeps the forced slider: the steady response each point settles on, its "
        "stops and sticks per period and multiplicity. " + UNITS_HELP + ".",
        _run_options),
    "plot": (
        "draw the natural picture of a result file",
        "Draw a result: a 2-D sweep as regime and amplitude maps with the analytic v* "
        "and the measured boundaries, a 1-D sweep as amplitude and mean against its "
        "axis, a simulation as time histories and phase planes (the paper's Fig. 3).",
        _plot_options),
    "simulate": (
        "simulate one slider: time histories and phase planes",
        "Simulate one slider from (x0, xdot0) and draw z, zdot, x, xdot against time "
        "and the phase planes (z, zdot) and (x, xdot), as the paper's Fig. 3; with "
        "--F0 or --Y0 and --Omega, under a periodic load or anchor motion (on fixed "
        "ground, v = 0, the top row draws the forces instead of repeating x). "
        + UNITS_HELP + ".",
        _simulate_options),
    "info": (
        "summarise a result file",
        "Print the dimensions, axes with units, regime and status counts, converged "
        "fraction and the provenance attributes of a result file.",
        _info_options),
    "compile": (
        "compile the kernels ahead of time into the cache",
        "Compile the kernels of a law kind and a method into numba's cache (what the "
        "first use of that kind and method compiles otherwise: tens of seconds each). "
        "The cache is per install location, in $SWEEPCORE_CACHE_DIR or "
        "~/.cache/sweepcore.",
        _compile_options),
    "export": (
        "write a result file as CSV (one row per point or sample)",
        "Write a result as CSV: a sweep as one row per grid point (the swept "
        "parameters, then every variable), a simulation as one row per time sample "
        "(its event log goes to <OUT stem>_events.csv). Column headers are the "
        "variables' names with their units, 'amplitude [cm]' (pandas reads the "
        "numbers as numbers; dimensionless columns bare); each column's name, units "
        "and long name also go to <OUT stem>_units.csv; regime, status and other "
        "flag variables are "
        f"written as names. Meanings: {doc('variables.md')}.",
        _export_options),
    "boundary": (
        "locate the Hopf point and the stick onset to full precision, or draw a "
        "bifurcation diagram",
        "Locate the regime boundaries of a study along v (the Hopf point from the "
        "cycle's amplitude, the stick onset from the grazing of the cycle with the "
        "belt, every other change from the labels) to xtol, for every point of the "
        "other axes, or follow them along one parameter by continuation, or scan a "
        "bifurcation diagram up and down; settings in the study's [boundary] table "
        f"({doc('studies.md')}). " + UNITS_HELP + ".",
        _boundary_options),
    "basins": (
        "basin stability: the share of a box of starts ending on each attractor",
        "For every point of a study's grid, the fraction of a box of start states "
        "(x0, xdot0) that ends on each attractor, with its error: exact where one "
        "unstable slip cycle bounds the stable equilibrium's basin (the area of its "
        "interior in the box), else sampled on the attractor kernel; settings in the "
        "study's [basins] table (docs/studies.md). " + UNITS_HELP + ".",
        _basins_options),
}
