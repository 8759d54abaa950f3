"""The ``sweepcore`` command: run study files, simulate one slider, plot, inspect,
export.

Units everywhere (the paper's): force kN, length cm, time s; mass kN s^2/cm,
stiffness kN/cm, alpha1 kN s/cm, alpha2 kN s^3/cm^3.

Exit codes: 0 success; 2 a refused input (bad study file, bad parameter, unknown
option, missing output directory; nothing is written); 1 a failure while running
(a simulation that fails writes nothing); 130 interrupted (a sweep with an output
path resumes where it stopped when the same command is run again). Output
directories are never created: a missing one is refused, as by the Python API.

Rooms: :mod:`.parser` (the subcommands and their options, one table),
:mod:`.commands` (what each subcommand does), :mod:`.summaries` (what ``info`` and
the commands print about a result), :mod:`.tables` (what ``export`` writes); here,
:func:`main` and its error handling.
"""
from __future__ import annotations

import argparse
import os
import sys
import traceback

from .parser import build_parser, set_threads

__all__ = ["main", "build_parser", "unknown_option", "UsageError"]


def __getattr__(name):
    # the commands (and numba, xarray with them) are imported once a command runs:
    # `sweepcore --help` answers without them
    if name in ("UsageError", "SimulationFailed"):
        from . import commands
        return getattr(commands, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


# the commands that only read a result file: they compile no kernel, and import
# neither numba nor the kernels (`sweepcore info` answers in the time xarray takes)
READERS = ("info", "export")

# what an interruption leaves, per command (a command says more where it knows:
# args.on_interrupt)
INTERRUPTED = {
    "run": "rerun the same command to resume: the finished chunks are kept",
    "basins": "rerun the same command to resume: the finished chunks are kept",
    "boundary": "nothing written", "simulate": "nothing written",
    "plot": "nothing written", "info": "nothing written", "export": "nothing written",
    "compile": "the kernels compiled so far are kept in the cache"}


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


def _notice(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def _silent(line: str) -> None:
    """--quiet: no compile lines (a damaged or read-only cache still says so)."""


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
    from . import commands
    from .commands import SimulationFailed, UsageError
    args.func = getattr(commands, f"cmd_{args.command}")
    if args.command not in READERS:
        from .. import compiled       # while a kernel compiles, say so on stderr
        compiled.notice = _silent if getattr(args, "quiet", False) else _notice
    if args.threads:
        set_threads(args.threads)
    try:
        return args.func(args)
    except KeyboardInterrupt:
        what = getattr(args, "on_interrupt", None) or INTERRUPTED[args.command]
        print(f"sweepcore {args.command}: interrupted ({what})", file=sys.stderr)
        return 130
    except BrokenPipeError:
        raise
    except SimulationFailed as err:
        print(f"sweepcore {args.command}: failed: {err}", file=sys.stderr)
        return 1
    except (UsageError, ValueError, TypeError) as err:
        # refused input (Params, Grid, options, study file: a StudyError is a
        # ValueError): one clean line. plot and
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
        from ..options import did_you_mean
        hint = did_you_mean(name, [o for o in known if o.startswith("--")], quote="")
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
