"""The package's metadata and what its help points to.

What is proven: pyproject declares the license as an SPDX expression with its file
(PEP 639; the TOML-table form is deprecated by setuptools), no License classifier
beside it (setuptools refuses both), the setuptools that reads it, and classifiers;
every page the command's help names is a file of the package (``sweepcore/docs``)
matched by the package-data globs, so an installed wheel holds it.
"""
import argparse
import fnmatch
import re
import sys
from pathlib import Path

from sweepcore.cli import build_parser

if sys.version_info >= (3, 11):
    import tomllib
else:
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())


def test_license_is_an_spdx_expression_with_its_file():
    project = PYPROJECT["project"]
    assert project["license"] == "MIT"
    assert project["license-files"] == ["LICENSE"] and (ROOT / "LICENSE").is_file()
    assert not [c for c in project["classifiers"] if c.startswith("License ::")]
    (req,) = PYPROJECT["build-system"]["requires"]
    assert re.fullmatch(r"setuptools>=(\d+)", req) and int(req.split(">=")[1]) >= 77


def test_classifiers_name_the_field_and_the_pythons():
    classifiers = PYPROJECT["project"]["classifiers"]
    assert "Topic :: Scientific/Engineering :: Physics" in classifiers
    low = PYPROJECT["project"]["requires-python"].removeprefix(">=")
    assert f"Programming Language :: Python :: {low}" in classifiers


def help_texts():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    return [parser.format_help()] + [p.format_help() for p in sub.choices.values()]


def test_the_help_keeps_a_hyphenated_path_whole():
    """A documentation path in a checkout whose directory has a hyphen is printed on
    one line (argparse's own formatter breaks lines at hyphens)."""
    from sweepcore.cli.parser import HelpFormatter
    path = "/work/wt-some-checkout-with-hyphens/sweepcore/docs/variables.md"
    parser = argparse.ArgumentParser(prog="x", formatter_class=HelpFormatter,
                                     description="Output variables: " + path + ".",
                                     epilog="Pages: " + path + " and more words here.")
    parser.add_argument("--a", help="see " + path)
    lines = parser.format_help().splitlines()
    assert sum(path in line for line in lines) == 3, lines


def test_every_page_the_help_names_ships_with_the_package():
    text = " ".join(" ".join(h.split()) for h in help_texts())
    pages = set(re.findall(r"([^\s(]*docs/\w+\.md)", text))
    assert len(pages) >= 2
    globs = PYPROJECT["tool"]["setuptools"]["package-data"]["sweepcore"]
    for page in pages:
        path = Path(page)
        assert path.is_file(), page                   # the path printed exists
        rel = path.resolve().relative_to((ROOT / "docs").resolve())
        assert (ROOT / "sweepcore" / "docs" / rel).is_file(), page
        assert any(fnmatch.fnmatch(f"docs/{rel}", g) for g in globs), page
