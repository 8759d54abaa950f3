"""Study files: a sweep described in TOML, validated before anything runs.

A study file names the swept axes, the solver and the outputs (format in
``docs/studies.md``)::

    title = "Hopf map"
    [axes]            # scalar, array, or {start, stop, num, spacing}
    m = 5.0
    k = 50.0
    r_y = 10.0
    alpha1 = 1.0
    v = { start = 0.5, stop = 10.0, num = 256 }
    alpha2 = { start = 1e-3, stop = 0.1, num = 256, spacing = "geometric" }
    [solver]
    method = "auto"
    tol = 1e-8
    [output]
    path = "out/hopf_map.nc"
    png = "out/hopf_map.png"

Every refusal is a :class:`StudyError` that names the file, the line, the key and the
offending value. ``tomllib`` reports line numbers only for syntax errors, so the line
of a semantically bad key is found by scanning the text (:func:`key_line`).
"""
from __future__ import annotations

import math
import numbers
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import excitations
from .options import MAX_PERIODS_SOUGHT, METHODS, did_you_mean
from .params import LONG_NAMES, RULES, UNITS, check_real
from .study_basins import basins_table
from .study_boundary import boundary_table
from .study_excitation import excitation_table, load_table
from .study_law import law_table

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

# axis name -> check_real keywords (the Params / initial-state rules); the
# excitation's keywords are axes of [excitation] (sweepcore.study_excitation)
AXIS_RULES = {n: r for n, r in RULES.items() if n not in excitations.KEYWORDS}
REQUIRED_AXES = ("m", "k", "r_y", "v")      # r_y: unless [law] gives the law
SPACINGS = ("linear", "geometric")
RANGE_KEYS = ("start", "stop", "num", "spacing")
MAX_POINTS = 50_000_000

TOP_KEYS = ("title", "description", "axes", "excitation", "law", "solver", "output",
            "plot", "boundary", "basins")
SOLVER_KEYS = ("method", "tol", "chunks", "dt", "max_steps", "max_periods", "gps_a",
               "graze", "periods")
OUTPUT_KEYS = ("path", "png")
PLOT_KEYS = ("variables", "x", "y")


class StudyError(ValueError):
    """A study file that cannot run, with the place to fix it.

    ``str(err)`` reads ``FILE:LINE: KEY: message`` (the compiler convention), so an
    editor can jump to it.
    """

    def __init__(self, message: str, key: str | None = None, line: int | None = None,
                 path: str | None = None):
        self.message, self.key, self.line, self.path = message, key, line, path
        where = str(path) if path is not None else "<study>"
        if line is not None:
            where += f":{line}"
        super().__init__(f"{where}: {key + ': ' if key else ''}{message}")


@dataclass(frozen=True)
class Axis:
    """One axis of a study: its values and how they were spaced.

    ``spacing`` is "scalar" (a fixed value), "list" (explicit values), "linear" or
    "geometric" (a range); plots use it to choose a log axis.
    """

    name: str
    values: np.ndarray
    spacing: str

    @property
    def swept(self) -> bool:
        return self.values.size > 1 or self.spacing != "scalar"

    def value(self):
        """The Grid argument: a float for a scalar, else the 1-D array."""
        return float(self.values[0]) if self.spacing == "scalar" else self.values


@dataclass(frozen=True)
class Study:
    """A validated study file.

    Attributes
    ----------
    axes : dict of str -> Axis
        In file order, ``[axes]`` then ``[excitation]``; unlisted optional axes
        (alpha1, alpha2, x0) are 0 and an unlisted xdot0 means "start stuck on the
        belt" (xdot0 = v).
    solver : dict
        ``method``, ``tol`` and any further options of ``sweep`` (``dt``,
        ``max_steps``, ``max_periods``, ``gps_a``, ``graze``); ``chunks`` apart.
    """

    path: Path | None
    text: str
    title: str
    description: str
    axes: dict
    method: str = "auto"
    tol: float = 1e-8
    chunks: int | None = None
    options: dict = field(default_factory=dict)
    output_path: str | None = None
    png: str | bool | None = None
    plot: dict = field(default_factory=dict)
    boundary: dict = field(default_factory=dict)
    basins: dict = field(default_factory=dict)
    law: object = None
    load: object = None

    @property
    def stem(self) -> str:
        return self.path.stem if self.path is not None else "study"

    @property
    def shape(self) -> tuple:
        return tuple(a.values.size for a in self.axes.values() if a.spacing != "scalar")

    @property
    def size(self) -> int:
        return int(np.prod(self.shape)) if self.shape else 1

    def grid_kwargs(self) -> dict:
        """Keyword arguments of :class:`sweepcore.grid.Grid`, in file order (and the
        law object of ``[law]``)."""
        kw = {name: ax.value() for name, ax in self.axes.items()}
        if self.law is not None:
            kw["law"] = self.law
        if self.load is not None:
            kw["load"] = self.load
        return kw

    def grid(self):
        """The :class:`sweepcore.grid.Grid` of this study."""
        from .grid import Grid
        return Grid(**self.grid_kwargs())

    def spacing_attrs(self) -> dict:
        """``{axis: spacing}`` for swept axes (stored on the result's coordinates)."""
        return {n: a.spacing for n, a in self.axes.items() if a.spacing != "scalar"}


# --------------------------------------------------------------------------- lines
_HEADER = re.compile(r"^\s*\[\s*([^\[\]]+?)\s*\]\s*(#.*)?$")
_KEYLINE = re.compile(r"""^\s*((?:[A-Za-z0-9_-]+|"[^"]*"|'[^']*')"""
                      r"""(?:\s*\.\s*(?:[A-Za-z0-9_-]+|"[^"]*"|'[^']*'))*)\s*=""")


def _split_key(dotted: str) -> tuple:
    parts = re.findall(r'"[^"]*"|\'[^\']*\'|[A-Za-z0-9_-]+', dotted)
    return tuple(p.strip("\"'") for p in parts)


def key_line(text: str, keypath) -> int | None:
    """1-based line of ``keypath`` (e.g. ``("axes", "v", "num")``) in TOML ``text``.

    Tracks ``[table]`` headers and ``key = value`` lines (dotted and quoted keys
    included). When the full path lives inside an inline table or a multi-line
    value, the line of ``key =`` inside it is searched from the line of its deepest
    found parent on; failing that, the parent's line is returned.
    """
    keypath = tuple(keypath)
    table: tuple = ()
    best, best_len = None, 0
    lines = text.splitlines()
    for i, line in enumerate(lines, start=1):
        h = _HEADER.match(line)
        if h and not line.lstrip().startswith("[["):
            table = _split_key(h.group(1))
            full = table
        else:
            k = _KEYLINE.match(line)
            if not k:
                continue
            full = table + _split_key(k.group(1))
        n = len(full)
        if n > best_len and keypath[:n] == full:
            best, best_len = i, n
            if n == len(keypath):
                return i
    if best is None or best_len == 0:
        return best
    # the rest of the path is inside an inline table / array starting at `best`
    pattern = re.compile(r"(?:^|[{,\s])" + re.escape(keypath[-1]) + r"\s*=")
    for j in range(best - 1, min(len(lines), best + 50)):
        if j > best - 1 and (_HEADER.match(lines[j]) or _KEYLINE.match(lines[j])):
            break
        if pattern.search(lines[j]):
            return j + 1
    return best


# --------------------------------------------------------------------- validation
class _Checker:
    """Raise StudyErrors located in one file."""

    def __init__(self, text: str, path):
        self.text, self.path = text, path

    def fail(self, keypath, message: str):
        keypath = tuple(keypath)
        raise StudyError(message, key=".".join(keypath) or None,
                         line=key_line(self.text, keypath) if keypath else None,
                         path=self.path)

    def known(self, table: dict, allowed, keypath=()):
        for key in table:
            if key not in allowed:
                hint = did_you_mean(key, allowed)     # the API's: tolerance -> tol
                where = f"[{'.'.join(keypath)}]" if keypath else "the top level"
                self.fail(tuple(keypath) + (key,),
                          f"unknown key {key!r} in {where}{hint} "
                          f"(allowed: {', '.join(allowed)})")

    def table(self, doc: dict, key: str) -> dict:
        val = doc.get(key, {})
        if not isinstance(val, dict):
            self.fail((key,), f"must be a table [{key}], got {_describe(val)}")
        return val

    def string(self, keypath, val, choices=None) -> str:
        if not isinstance(val, str):
            self.fail(keypath, f"must be a string, got {_describe(val)}")
        if choices is not None and val not in choices:
            self.fail(keypath, f"must be one of {', '.join(map(repr, choices))}, "
                               f"got {val!r}{did_you_mean(val, list(choices))}")
        return val

    def real(self, keypath, val, name=None, **rule) -> float:
        try:
            return check_real(name or keypath[-1], val, **rule)
        except (TypeError, ValueError) as err:
            self.fail(keypath, str(err))

    def integer(self, keypath, val, minimum=1) -> int:
        if isinstance(val, bool) or not isinstance(val, numbers.Integral):
            self.fail(keypath, f"must be an integer, got {_describe(val)}")
        if val < minimum:
            self.fail(keypath, f"must be an integer >= {minimum}, got {val}")
        return int(val)


def _describe(val) -> str:
    kind = {bool: "boolean", str: "string", int: "integer", float: "float",
            dict: "table", list: "array"}.get(type(val), type(val).__name__)
    return f"{kind} {val!r}" if not isinstance(val, (dict, list)) or len(repr(val)) < 60 \
        else kind


def _axis(ck: _Checker, name: str, val, table: str = "axes") -> Axis:
    kp = (table, name)
    rule = RULES[name]
    if isinstance(val, dict):
        ck.known(val, RANGE_KEYS, kp)
        for req in ("start", "stop", "num"):
            if req not in val:
                ck.fail(kp, f"a range needs start, stop and num; {req!r} is missing")
        spacing = ck.string(kp + ("spacing",), val.get("spacing", "linear"), SPACINGS)
        start = ck.real(kp + ("start",), val["start"], name=name, **rule)
        stop = ck.real(kp + ("stop",), val["stop"], name=name, **rule)
        num = ck.integer(kp + ("num",), val["num"], minimum=1)
        if num > 1 and start == stop:
            ck.fail(kp + ("stop",), f"start and stop are both {start}; a range of "
                                    f"{num} points needs start != stop")
        if spacing == "geometric":
            if not (start > 0 and stop > 0):
                bad = "start" if not start > 0 else "stop"
                ck.fail(kp + (bad,), f"a geometric range needs start > 0 and stop > 0, "
                                     f"got {bad} = {val[bad]!r}")
            values = np.geomspace(start, stop, num)
        else:
            values = np.linspace(start, stop, num)
        return Axis(name, values, spacing)
    if isinstance(val, list):
        if not val:
            ck.fail(kp, "an array of values must not be empty")
        values = np.array([ck.real(kp, x, **rule) for x in val], dtype=np.float64)
        if np.unique(values).size != values.size:
            ck.fail(kp, f"array values must be distinct, got {val!r}")
        return Axis(name, values, "list")
    return Axis(name, np.array([ck.real(kp, val, **rule)]), "scalar")


def _axes(ck: _Checker, doc: dict) -> dict:
    if "axes" not in doc:
        ck.fail((), "missing [axes] table (it needs at least m, k, r_y and v)")
    table = ck.table(doc, "axes")
    for key in table:
        if key in excitations.KEYWORDS:
            ck.fail(("axes", key), f"{key} is a key of the excitation: move it to an "
                                   "[excitation] table")
    ck.known(table, tuple(AXIS_RULES), ("axes",))
    for name in REQUIRED_AXES:
        if name == "r_y" and "law" in doc:
            continue                    # the [law] table gives the friction law
        if name not in table:
            raise StudyError(
                f"missing axis {name!r} ({LONG_NAMES[name]} [{UNITS[name]}]); "
                f"[axes] needs {', '.join(REQUIRED_AXES)}", key=f"axes.{name}",
                line=key_line(ck.text, ("axes",)), path=ck.path)
    # sized from the raw tables first: no axis is built for a grid refused anyway
    given = doc.get("excitation")
    extra = list(given.values()) if isinstance(given, dict) else []
    size = math.prod(_raw_size(val) for val in [*table.values(), *extra])
    if size > MAX_POINTS:
        ck.fail(("axes",), f"the grid has {size} points, more than {MAX_POINTS}; "
                           "split the study")
    return {name: _axis(ck, name, val) for name, val in table.items()}


def _raw_size(val) -> int:
    """Values of an axis as written (1 where ``_axis`` will refuse it anyway)."""
    if isinstance(val, list):
        return len(val)
    num = val.get("num") if isinstance(val, dict) else None
    return num if isinstance(num, int) and not isinstance(num, bool) and num > 0 else 1


def _solver(ck: _Checker, doc: dict) -> dict:
    table = ck.table(doc, "solver")
    ck.known(table, SOLVER_KEYS, ("solver",))
    out = {"method": "auto", "tol": 1e-8, "chunks": None, "options": {}}
    for key, val in table.items():
        kp = ("solver", key)
        if key == "method":
            out["method"] = ck.string(kp, val, METHODS)
        elif key == "chunks":
            out["chunks"] = ck.integer(kp, val, minimum=1)
        elif key == "max_steps":
            out["options"][key] = ck.integer(kp, val, minimum=1)
        elif key == "periods":      # a forced response's largest multiplicity
            out["options"][key] = ck.integer(kp, val, minimum=1)
            if val > MAX_PERIODS_SOUGHT:
                ck.fail(kp, f"must be an integer in [1, {MAX_PERIODS_SOUGHT}], got {val}")
        elif key in ("tol", "graze"):
            x = ck.real(kp, val, positive=True)
            if not x < 1.0:
                ck.fail(kp, f"must be a number in (0, 1), got {val!r}")
            if key == "tol":
                out["tol"] = x
            else:
                out["options"][key] = x
        else:  # dt, max_periods > 0; gps_a any finite length
            rule = {} if key == "gps_a" else {"positive": True}
            out["options"][key] = ck.real(kp, val, **rule)
    return out


def _output(ck: _Checker, doc: dict) -> dict:
    table = ck.table(doc, "output")
    ck.known(table, OUTPUT_KEYS, ("output",))
    out = {"path": None, "png": None}
    if "path" in table:
        out["path"] = ck.string(("output", "path"), table["path"])
        if not out["path"].endswith(".nc"):
            ck.fail(("output", "path"), f"must end in .nc, got {out['path']!r}")
    if "png" in table:
        val = table["png"]
        if val is True or isinstance(val, str) and val:
            out["png"] = val
        elif val is False:
            out["png"] = False
        else:
            ck.fail(("output", "png"), f"must be a file name or true/false, "
                                       f"got {_describe(val)}")
    return out


def sweep_variables() -> list[str]:
    """Names of the data variables a sweep can write (what ``[plot] variables``
    may name)."""
    from . import variables
    from .boundary import BOUNDARY_VARIABLES

    forced = [n for n in variables.FORCED_OBSERVABLES if n not in variables.OBSERVABLES]
    return [*variables.OBSERVABLES, *forced, "regime", "status", "converged",
            *variables.ANALYTIC, *BOUNDARY_VARIABLES]


def _plot(ck: _Checker, doc: dict, axes: dict) -> dict:
    table = ck.table(doc, "plot")
    ck.known(table, PLOT_KEYS, ("plot",))
    swept = [n for n, a in axes.items() if a.values.size > 1]
    out = {}
    if "variables" in table:
        val = table["variables"]
        if not isinstance(val, list) or not val or \
                not all(isinstance(s, str) for s in val):
            ck.fail(("plot", "variables"), f"must be a non-empty array of variable "
                                           f"names, got {_describe(val)}")
        known = sweep_variables()
        unknown = [n for n in val if n not in known]
        if unknown:
            ck.fail(("plot", "variables"), f"{', '.join(map(repr, unknown))} "
                                           f"{'is' if len(unknown) == 1 else 'are'} "
                                           f"not a variable of a sweep; known: "
                                           f"{', '.join(known)}")
        out["variables"] = list(val)
    for key in ("x", "y"):
        if key in table:
            out[key] = ck.string(("plot", key), table[key], swept)
    return out


def parse_study(text: str, path: str | Path | None = None) -> Study:
    """Validate the TOML ``text`` of a study (``path`` only names it in errors).

    Raises
    ------
    StudyError
        On a syntax error, an unknown key, a wrong type, a missing axis or a value
        outside its range; the message names the key, its line and the value.
    """
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        msg = str(err)
        m = re.search(r"\s*\(at line (\d+), column (\d+)\)", msg)
        line = int(m.group(1)) if m else None
        if m:
            msg = msg[:m.start()] + f" (column {m.group(2)})"
        raise StudyError(f"TOML syntax error: {msg}", line=line, path=path) from None
    ck = _Checker(text, path)
    ck.known(doc, TOP_KEYS)
    title = ck.string(("title",), doc.get("title", Path(path).stem if path else "study"))
    description = ck.string(("description",), doc.get("description", ""))
    axes = _axes(ck, doc)
    law = law_table(ck, doc, axes, path)
    axes = {**axes, **excitation_table(ck, doc, _axis, axes)}
    load = load_table(ck, doc, path)
    solver = _solver(ck, doc)
    output = _output(ck, doc)
    plot = _plot(ck, doc, axes)
    boundary = boundary_table(ck, doc, axes)
    basins = basins_table(ck, doc, axes)
    study = Study(path=Path(path) if path is not None else None, text=text, title=title,
                  description=description, axes=axes, method=solver["method"],
                  tol=solver["tol"], chunks=solver["chunks"], options=solver["options"],
                  output_path=output["path"], png=output["png"], plot=plot,
                  boundary=boundary, basins=basins, law=law, load=load)
    if study.method != "auto":
        from .forced import check_method as check_forced
        from .options import check_method
        try:
            grid = study.grid()
            check_forced(study.method) if grid.forced else check_method(study.method, grid)
        except ValueError as err:
            ck.fail(("solver", "method"), f"{err}; use 'auto'")
    return study


def load_study(path: str | Path) -> Study:
    """Read and validate the study file at ``path`` (see :func:`parse_study`)."""
    path = Path(path)
    if path.exists() and not path.is_file():   # a FIFO would block the read forever
        kind = ("a directory" if path.is_dir() else "a FIFO" if path.is_fifo()
                else "a device or socket")
        raise StudyError(f"not a regular file ({kind})", path=path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise StudyError("no such study file", path=path) from None
    except (OSError, UnicodeDecodeError) as err:
        raise StudyError(f"cannot read: {err}", path=path) from None
    return parse_study(text, path)
