"""docs/architecture.md names the rooms as they are, and the rooms keep their shape.

What is proven:
* every ``sweepcore/...`` path the page names exists, and every dotted name
  ``sweepcore.a.b`` it names imports (module, then attribute);
* every Python module of sweepcore outside ``_kernels/`` is named on the page (a new
  room fails here until the page lists it);
* no such module exceeds the size the page states;
* the Python side's method list is the kernels' method table plus "auto".
"""
import ast
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


# --------------------------------------------------- the friction law, one unit
LAW_COLUMNS = {"RY", "RK", "A1", "A2", "VS"}      # the analytic law's row columns
KERNEL_LAWS = PACKAGE / "_kernels" / "laws"
PYTHON_LAWS = PACKAGE / "laws"
# the law's own modules: the two interfaces, the layout that defines the columns,
# and one module per law kind on each side
LAW_MODULES = ({PACKAGE / "law.py", PACKAGE / "_kernels" / "law.py",
                PACKAGE / "_kernels" / "layout.py"}
               | set(KERNEL_LAWS.glob("*.py")) | set(PYTHON_LAWS.glob("*.py")))
OUTSIDE = [p for p in sorted(PACKAGE.rglob("*.py")) + sorted(
    (ROOT / "benchmarks").glob("*.py")) if p not in LAW_MODULES]


def _layout_aliases(tree):
    """Names bound to the layout module in a module (``from ._kernels import layout
    as L``, ``import sweepcore._kernels.layout as L``)."""
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            for a in node.names:
                if a.name == "layout":
                    names.add(a.asname or a.name)
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.endswith(".layout") and a.asname:
                    names.add(a.asname)
    return names


def test_only_the_law_modules_read_the_laws_columns():
    """A file outside the law modules that reads r_y, alpha1, alpha2, r_k or v_s
    from a kernel row (``layout.RY`` ..., or imports those columns) fails here: the
    law's data reach the other rooms only through its interface."""
    found = []
    for path in OUTSIDE:
        tree = ast.parse(path.read_text())
        aliases = _layout_aliases(tree)
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and (node.module or "").endswith("layout"):
                found += [f"{path.name}:{node.lineno} imports {a.name}"
                          for a in node.names if a.name in LAW_COLUMNS]
            if isinstance(node, ast.Attribute) and node.attr in LAW_COLUMNS and \
                    isinstance(node.value, ast.Name) and node.value.id in aliases:
                found.append(f"{path.name}:{node.lineno} reads {node.value.id}.{node.attr}")
    assert found == []


def test_only_the_law_modules_test_the_laws_kind():
    """Outside the law modules nothing asks which law a row has: no data class of a
    kind, no ``instance_class``, no kind name compared, no ``is ANALYTIC``, no
    isinstance of a law class."""
    from sweepcore._kernels import laws as kernel_laws
    from sweepcore import laws
    classes = {row[1].__name__ for row in kernel_laws.LAWS} | \
        {cls.__name__ for cls, _kinds in laws.LAWS}
    kinds = {row[0] for row in kernel_laws.LAWS}
    public = {cls.__name__ for cls in laws.OBJECTS}     # sweepcore.TableLaw, ...
    found = []
    for path in OUTSIDE:
        if "_kernels" in path.parts and path.name == "prefetch.py":
            continue            # builds a kind's data type by name, from the table
        if path == PACKAGE / "_kernels" / "excitation.py":
            continue            # resolves the excitation's kinds (its own unit)
        if path == PACKAGE / "_kernels" / "jit.py":
            continue            # resolves an interface's kinds (jit.resolved_by)
        for node in ast.walk(ast.parse(path.read_text())):
            where = f"{path.name}:{getattr(node, 'lineno', '?')}"
            if isinstance(node, ast.Attribute) and node.attr == "instance_class":
                found.append(f"{where} instance_class")
            elif isinstance(node, ast.Compare):
                parts = [node.left, *node.comparators]
                if any(isinstance(p, ast.Constant) and p.value in kinds for p in parts):
                    found.append(f"{where} compares a kind name")
                if any(isinstance(op, (ast.Is, ast.IsNot)) for op in node.ops) and any(
                        isinstance(p, ast.Name) and p.id == "ANALYTIC" for p in parts):
                    found.append(f"{where} tests 'is ANALYTIC'")
            elif isinstance(node, ast.Call) and getattr(node.func, "id", "") == "isinstance":
                names = {n.id for n in ast.walk(node.args[1]) if isinstance(n, ast.Name)}
                if names & classes:
                    found.append(f"{where} isinstance of a law class")
            elif isinstance(node, ast.Name) and node.id in classes - public:
                found.append(f"{where} names {node.id}")
    assert found == []


def test_every_law_kind_is_a_module_with_the_primitives():
    """The kernels' law table: each kind's module defines its data class and the
    primitives the interface has no generic form of; the Python side's table runs
    every kind, each with one class."""
    from sweepcore._kernels import law as interface
    from sweepcore._kernels import laws as kernel_laws
    from sweepcore import laws
    required = [name for name in ("force", "derivatives", "static_limits", "slope_bound")
                if name not in interface._DEFAULTS]
    assert required == ["force", "derivatives", "static_limits", "slope_bound"]
    for name, data, module, _sample in kernel_laws.LAWS:
        assert Path(module.__file__).parent == KERNEL_LAWS
        assert getattr(module, data.__name__) is data
        missing = [f for f in required if not hasattr(module, f)]
        assert missing == [], f"law kind {name} lacks {missing}"
    run = [kind for _cls, kinds in laws.LAWS for kind in kinds]
    assert sorted(run) == sorted(row[0] for row in kernel_laws.LAWS)
    for cls, _kinds in laws.LAWS:
        assert Path(importlib.import_module(cls.__module__).__file__).parent == PYTHON_LAWS


def test_python_calls_only_entry_kernels():
    """A kernel without a CPython wrapper (an internal one) called from Python
    crashes the interpreter instead of raising: every kernel a Python room holds is
    an entry (``kernel(entry=True)``)."""
    from numba.core.dispatcher import Dispatcher
    bad = []
    for path in sorted(PACKAGE.rglob("*.py")):
        if "_kernels" in path.parts or path.name == "__main__.py":
            continue
        name = ".".join(path.relative_to(ROOT).with_suffix("").parts).removesuffix(
            ".__init__")
        module = importlib.import_module(name)
        for attr, obj in vars(module).items():
            if isinstance(obj, Dispatcher) and obj.targetoptions.get("no_cpython_wrapper"):
                bad.append(f"{name}.{attr}")
    assert bad == []


def test_the_second_compilers_signature_is_the_kernels():
    """``sweepcore._kernels.prefetch`` compiles the search half of a cold kernel for
    the signature the attractor kernel calls it with; were it another, the cache would
    never be hit (no error: only the time lost). Run the kernel, compare."""
    import numpy as np
    import sweepcore as sc
    from sweepcore._kernels import attractor, prefetch, stepper
    sc.attractor(sc.Params(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, alpha2=0.01, v=5.0))
    want = prefetch.search_signature(stepper.DOP853, "polynomial")
    # the signatures compiled in this process for this method and law kind (other
    # tests may have compiled others: the table law's, another method's)
    mine = [tuple(s) for s in attractor.on_event.signatures
            if s[0] == want[0] and s[4] == want[4]]
    if not mine:                             # the kernel came whole from the cache
        attractor.on_event.compile(want)
        return      # (cache hits are what the kernel's own typing would ask for)
    assert want in mine
    assert np.all(prefetch.derived_signature("table")[1] ==
                  prefetch.law_type("table"))


def test_the_second_compiler_names_every_kinds_law_data():
    """The type the second compiler compiles for is the type of the data a law object
    of that kind hands the kernels (Leine's two floats, a table's array, ...), for
    every kind of the law table (random laws of each: ``test_law_kinds.MAKERS``)."""
    from numba import typeof
    from sweepcore._kernels import laws as kernel_laws, prefetch
    from test_law_kinds import CASES
    given = {kind: lw for kind, _law, _row, lw, _force in CASES}
    assert set(given) == {row[0] for row in kernel_laws.LAWS}
    for kind, data in given.items():
        assert prefetch.law_type(kind) == typeof(data), kind


# ----------------------------------------------- the excitation, one unit too
def test_every_excitation_kind_is_a_module_with_the_primitives():
    """The kernels' excitation table: each kind's module defines its data class and
    the functions the interface has no generic form of; the Python side's table
    holds a load class per forced kind, with what the rooms ask of a load."""
    from sweepcore import excitations
    from sweepcore._kernels import excitation as interface
    from sweepcore._kernels import excitations as kernel_excitations
    required = [name for name in ("work_size", "with_work", "coefficients")
                if name not in interface.interface.defaults]
    assert required == ["work_size", "with_work", "coefficients"]
    for name, data, module, _sample in kernel_excitations.EXCITATIONS:
        assert Path(module.__file__).parent == PACKAGE / "_kernels" / "excitations"
        assert getattr(module, data.__name__) is data
        missing = [f for f in required if not hasattr(module, f)]
        assert missing == [], f"excitation kind {name} lacks {missing}"
    kernel_kinds = [row[0] for row in kernel_excitations.EXCITATIONS]
    assert [row[0] for row in excitations.EXCITATIONS] == kernel_kinds
    for name, module, cls in excitations.EXCITATIONS:
        assert Path(module.__file__).parent == PACKAGE / "excitations"
        if cls is None:
            continue
        assert cls.kind == name
        for attr in ("data", "force", "attrs", "describe", "fingerprint"):
            assert callable(getattr(cls, attr, None)), f"{cls.__name__} lacks {attr}"


def test_no_kernel_is_longer_than_80_lines():
    """A kernel says one thing: none over 80 lines, but for the stages of the
    eighth-order pair (its Butcher tableau, written out stage by stage)."""
    long = []
    for path in sorted((PACKAGE / "_kernels").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef) and \
                    node.end_lineno - node.lineno + 1 > 80 and \
                    (path.name, node.name) != ("dop853.py", "_stages"):
                long.append(f"{path.name}:{node.name} "
                            f"({node.end_lineno - node.lineno + 1} lines)")
    assert long == []
