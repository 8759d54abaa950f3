"""The time a command's work takes, said before the work and held to ``--max-time``:
the kernels of a study's grid timed on a sample of its points
(``sweepcore.timing``)."""
from __future__ import annotations


def say_time(args, what: str, grid, study, runs: float = 1.0, doing: str = "",
              tol: float | None = None) -> dict:
    """Print (unless --quiet) how long the kernels of the study's grid take here,
    measured on a sample of its points (``sweepcore.timing.time_estimate``; ``runs``
    kernel runs a point), and refuse, naming --max-time, what exceeds it (the
    command then passes no limit on: one sample, one check)."""
    from ..sizing import options_row
    from ..timing import refuse_if_too_long, time_estimate, time_text
    if _untimed(args):
        return {}
    timing = time_estimate(grid, options_row(grid, study.method, tol or study.tol,
                                             study.options), runs)
    if not args.quiet:
        print(f"{what}: {time_text(timing)}{doing}", flush=True)
    refuse_if_too_long(what, timing, args.max_time, command_line=True)
    return timing


def _untimed(args) -> bool:
    """No sample to time: on a cluster (not this machine), or with nothing to say
    (--quiet) and no limit (--max-time none)."""
    return bool(args.scheduler and ":" in args.scheduler) or (
        args.quiet and args.max_time is None)


def say_call_time(args, what: str, grid, call) -> None:
    """As :func:`say_time` for a command whose points do more than a sweep's:
    ``call`` itself timed on a few points (``sweepcore.timing.time_call``)."""
    from ..timing import refuse_if_too_long, time_call, time_text
    if _untimed(args):
        return
    timing = time_call(grid, call)
    if timing is None:
        return
    if not args.quiet:
        print(f"{what}: {time_text(timing)}", flush=True)
    refuse_if_too_long(what, timing, args.max_time, command_line=True)
