"""Shared by the study scripts: the output directory and a timed report."""
from __future__ import annotations

import argparse
import time
from pathlib import Path


def output_dir(description: str, argv=None) -> Path:
    """Parse ``--out DIR`` (default ``out/``), create it and return it."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--out", default="out", type=Path,
                        help="output directory (default: out/, git-ignored)")
    out = parser.parse_args(argv).out
    out.mkdir(parents=True, exist_ok=True)
    return out


def no_options(description: str, argv=None) -> None:
    """The command line of a study that takes no option: ``--help`` prints
    ``description`` and exits; anything else is refused (argparse's exit code 2)."""
    argparse.ArgumentParser(description=description,
                            formatter_class=argparse.RawDescriptionHelpFormatter
                            ).parse_args(argv)


class Timer:
    """``with Timer("name"):`` prints the wall time of the block."""

    def __init__(self, name: str):
        self.name = name

    def __enter__(self):
        self.t0 = time.perf_counter()
        return self

    def __exit__(self, *exc):
        self.seconds = time.perf_counter() - self.t0
        print(f"{self.name}: {self.seconds:.1f} s")
