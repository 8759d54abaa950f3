"""What the plotting API refuses, before it draws: an argument that is not a result,
a result of another kind than the function draws, names that are not in it, and
arguments of the wrong type; each refusal names the argument and what was expected.
"""
from __future__ import annotations

import numbers

import numpy as np
import xarray as xr

from ..options import did_you_mean

KINDS = {"basins": "a basin-stability result (sweepcore.basin_stability)",
         "bifurcation_diagram": "a bifurcation diagram (sweepcore.bifurcation_diagram)",
         "boundaries": "located boundaries (sweepcore.locate_boundaries or "
                       "continue_boundary)",
         "cycles": "a slip-cycle result (sweepcore.slip_cycles)",
         "simulation": "a simulation (sweepcore.simulate)",
         "sweep": "a sweep (sweepcore.sweep)"}


def kind_of(ds: xr.Dataset) -> str:
    """The kind of result ``ds`` is: a key of :data:`KINDS`."""
    kind = ds.attrs.get("sweepcore_kind")
    if kind in KINDS:
        return kind
    return "simulation" if "time" in ds.dims else "sweep"


def swept(ds: xr.Dataset) -> list[str]:
    """The dimensions of more than one value of a sweep's grid, in its order: those
    of its per-point variables; a measured law's samples (``law_point``) are data
    of the law, never an axis to draw against."""
    dims = next((ds[v].dims for v in ("regime", "status", "amplitude") if v in ds),
                tuple(ds.dims))
    return [d for d in dims if ds.sizes[d] > 1]


def _short(value) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def checked_result(ds, *kinds: str, name: str = "ds") -> xr.Dataset:
    """``ds`` itself, refused unless it is an xarray.Dataset (of one of ``kinds``,
    when given), naming the argument, what it got and what was expected."""
    if not isinstance(ds, xr.Dataset):
        hint = (" (a file name: read it with sweepcore.open_result first)"
                if isinstance(ds, (str, bytes)) or hasattr(ds, "__fspath__") else "")
        raise TypeError(f"{name} must be an xarray.Dataset, a result of sweepcore, "
                        f"got {_short(ds)} of type {type(ds).__name__}{hint}")
    if kinds and kind_of(ds) not in kinds:
        wanted = " or ".join(KINDS[k] for k in kinds)
        raise ValueError(f"{name} must be {wanted}; got {KINDS[kind_of(ds)]} (title: "
                         f"{ds.attrs.get('title', 'none')!r})")
    return ds


def checked_title(title) -> None:
    if title is not None and not isinstance(title, str):
        raise TypeError(f"title must be a str or None, got {_short(title)} of type "
                        f"{type(title).__name__}")


def checked_names(name: str, value, ds: xr.Dataset, default=None) -> list[str]:
    """The variable names of argument ``name``: one str or a sequence of str, each a
    variable of ``ds`` (refused with the closest name and the list). ``value`` None
    gives those of ``default`` that ``ds`` holds."""
    known = list(ds.data_vars)
    if value is None:
        return [v for v in default or () if v in ds]
    if isinstance(value, str):
        value = [value]
    if not isinstance(value, (list, tuple)) or not all(isinstance(v, str)
                                                        for v in value):
        raise TypeError(f"{name} must be a variable name or a sequence of them, got "
                        f"{_short(value)} of type {type(value).__name__}")
    if not value:
        raise ValueError(f"{name} is empty: name at least one variable (has: "
                         f"{', '.join(known)})")
    for v in value:
        if v not in ds.data_vars:
            raise ValueError(f"{name}: {v!r} is not a variable of the result"
                             f"{did_you_mean(v, known)} (has: {', '.join(known)})")
    return list(value)


def checked_dimension(name: str, value, choices) -> None:
    """``value`` None, or one of ``choices`` (the dimensions it may name)."""
    if value is None:
        return
    if not isinstance(value, str):
        raise TypeError(f"{name} must be a dimension name (str), got {_short(value)} "
                        f"of type {type(value).__name__}")
    if value not in choices:
        raise ValueError(f"{name}={value!r} is not a swept numeric dimension of the "
                         f"result{did_you_mean(value, list(choices))} (swept: "
                         f"{', '.join(choices) or 'none'})")


def checked_reference(reference) -> dict:
    """``{label: (x, fraction, error)}``, each three equal-length sequences of
    numbers (a published table), or refused naming ``reference``."""
    if reference is None:
        return {}
    if not isinstance(reference, dict):
        raise TypeError(f"reference must be a dict {{label: (x, fraction, error)}}, "
                        f"got {_short(reference)} of type {type(reference).__name__}")
    out = {}
    for label, value in reference.items():
        try:
            x, f, e = (np.atleast_1d(np.asarray(v)) for v in value)
        except (TypeError, ValueError):
            raise ValueError(f"reference[{label!r}] must be three sequences (x, "
                             f"fraction, error), got {_short(value)}") from None
        arrays = (x, f, e)
        if any(a.ndim != 1 or not all(isinstance(v, numbers.Real) for v in a.tolist())
               for a in arrays):
            raise ValueError(f"reference[{label!r}] must hold numbers in x, fraction "
                             f"and error, got {_short(value)}")
        if len({a.size for a in arrays}) != 1:
            raise ValueError(f"reference[{label!r}]: x, fraction and error must have "
                             f"equal lengths, got {x.size}, {f.size}, {e.size}")
        out[str(label)] = tuple(a.astype(float) for a in arrays)
    return out
