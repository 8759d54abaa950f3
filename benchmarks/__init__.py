"""sweepcore benchmarks: ``python benchmarks/run.py [--quick]`` (see README.md)."""
