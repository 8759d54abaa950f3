"""docs/architecture.md names the rooms as they are, and the rooms keep their shape.

What is proven:
* every ``sweepcore/...`` path the page names exists, and every dotted name
  ``sweepcore.a.b`` it names imports (module, then attribute);
* every Python module of sweepcore outside ``_kernels/`` is named on the page (a new
  room fails here until the page lists it);
* no such module exceeds the size the page states;
* the Python side's method list is the kernels' method table plus "auto".
"""
import importlib
import re
from pathlib import Path

import pytest

from sweepcore import options
from sweepcore._kernels import codes

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "architecture.md"
PACKAGE = ROOT / "sweepcore"
MAX_LINES = 550          # stated on the page


@pytest.fixture(scope="module")
def page():
    return PAGE.read_text()


def _resolve(dotted: str):
    """The object ``dotted`` names: the longest importable module, then attributes."""
    parts = dotted.split(".")
    for n in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:n]))
        except ImportError:
            continue
        for name in parts[n:]:
            obj = getattr(obj, name)
        return obj
    raise ImportError(dotted)


def test_every_path_on_the_page_exists(page):
    paths = set(re.findall(r"`(sweepcore/[\w/.<>]*)`", page))
    assert paths
    missing = [p for p in paths if "<" not in p and not (ROOT / p).exists()]
    assert missing == []


def test_every_dotted_name_on_the_page_imports(page):
    names = set(re.findall(r"`(sweepcore(?:\.\w+)+)`", page))
    assert len(names) > 20
    broken = []
    for name in sorted(names):
        try:
            _resolve(name)
        except (ImportError, AttributeError) as err:
            broken.append(f"{name}: {err}")
    assert broken == []


def test_every_python_room_is_on_the_page(page):
    named = set(re.findall(r"`(sweepcore/[\w/]+(?:\.py)?)`", page))
    listed = {p.rstrip("/") for p in named}
    rooms = []
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(ROOT).as_posix()
        if "/_kernels/" in rel or path.name in ("__init__.py", "__main__.py"):
            continue
        package = path.parent.relative_to(ROOT).as_posix()
        if rel not in listed and not (package != "sweepcore" and package in listed
                                      and path.stem in page):
            rooms.append(rel)
    assert rooms == [], "modules missing from docs/architecture.md"


def test_no_python_room_is_larger_than_the_page_says():
    big = {p.relative_to(ROOT).as_posix(): n for p in PACKAGE.rglob("*.py")
           if "_kernels" not in p.parts
           and (n := len(p.read_text().splitlines())) > MAX_LINES}
    assert big == {}


def test_the_method_list_is_the_kernels_table():
    assert options.METHODS == ("auto", *codes.METHOD_CODES)
    assert set(codes.METHOD_CODES) == set(codes.METHOD_NAMES.values())
