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
