"""Regenerate every study into one directory (default ``out/``, git-ignored).

    python studies/run_all.py [--out out/] [--skip hopf_map ...] [--tables]

TOML studies run through the ``sweepcore run`` command (``boundary`` and
``basins`` for those studies); the scripts (paper figures,
design maps, initial conditions) through their ``main(out)``. ``--tables`` also runs
the table-printing studies (paper claims, method orders; a few minutes) and keeps
their output in ``<out>/<name>.md``. Prints the wall time of each.
"""
import argparse
import contextlib
import importlib
import re
import runpy
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))



def _command(path: Path) -> str:
    """The command that runs a TOML study: boundary, basins (its table) or run."""
    text = path.read_text()
    for table in ("boundary", "basins"):
        if re.search(rf"^\[{table}\]", text, flags=re.M):
            return table
    return "run"


# every TOML study of this folder, by its command: `sweepcore run` first (a boundary
# study draws over a map: boundaries over hopf_map), then boundary, then basins
_BY_COMMAND = {p.stem: _command(p) for p in sorted(HERE.glob("*.toml"))}
TOML = tuple(n for n, c in _BY_COMMAND.items() if c == "run")
BOUNDARY = tuple(n for n, c in _BY_COMMAND.items() if c == "boundary")
BASINS = tuple(n for n, c in _BY_COMMAND.items() if c == "basins")
SCRIPTS = ("paper_fig3", "paper_fig4", "paper_fig5", "design_map", "initial_conditions")
TABLES = ("paper_claims", "method_orders")      # print markdown tables, write no files


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("out"),
                        help="output directory (default out/)")
    parser.add_argument("--skip", nargs="*", default=[], metavar="STUDY",
                        choices=TOML + BOUNDARY + BASINS + SCRIPTS + TABLES,
                        help="studies not to run")
    parser.add_argument("--tables", action="store_true",
                        help="also run " + ", ".join(TABLES) + " into <out>/<name>.md")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    from sweepcore.cli import main as cli

    times = {}
    names = SCRIPTS + TOML + BOUNDARY + BASINS + (TABLES if args.tables else ())
    for name in names:
        if name in args.skip or not (HERE / f"{name}.py").exists() and name in TABLES:
            continue
        t0 = time.perf_counter()
        if name in TOML:
            code = cli(["run", str(HERE / f"{name}.toml"), "-o",
                        str(args.out / f"{name}.nc"), "--png",
                        str(args.out / f"{name}.png")])
            if code:
                return code
        elif name in BOUNDARY + BASINS:
            code = cli(["boundary" if name in BOUNDARY else "basins", str(HERE / f"{name}.toml"), "-o",
                        str(args.out / f"{name}.nc"), "--png",
                        str(args.out / f"{name}.png")])
            if code:
                return code
        elif name in TABLES:
            md = args.out / f"{name}.md"
            with open(md, "w") as f, contextlib.redirect_stdout(f):
                runpy.run_path(str(HERE / f"{name}.py"), run_name="__main__")
            print(f"wrote {md}")
        else:
            importlib.import_module(name).main(args.out)
        times[name] = time.perf_counter() - t0
    print("\nstudy                 wall time")
    for name, t in times.items():
        print(f"{name:20s} {t:8.1f} s")
    print(f"{'total':20s} {sum(times.values()):8.1f} s  -> {args.out}/")
    return 0


if __name__ == "__main__":
    sys.exit(main())
