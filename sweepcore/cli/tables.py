"""What ``sweepcore export`` writes: a result as tables (one per group of
dimensions), each column headed by its variable's name and units
(``amplitude [cm]``, the form ``TableLaw.from_csv`` reads), and the table of
their units and long names."""
from __future__ import annotations

import numpy as np


def csv_tables(ds) -> dict:
    """``{file suffix: pandas.DataFrame}``: one table per group of dimensions.

    A sweep is one table over its grid (variables on fewer dimensions, such as the
    measured boundary, are repeated along the others); a simulation one over
    ``time`` ("") and one over ``event`` ("_events"). Scalar coordinates (fixed
    parameters) are repeated as columns. Flag variables become their names; headers
    are :func:`header` (``pandas.read_csv`` gives them as they are in the file; the
    plain names: ``frame.rename(columns=lambda c: c.split(" [")[0])``); units and
    long names are also in :func:`units_table`.
    """
    if "event" not in ds.dims:
        return {"": _frame(ds)}
    on_event = [n for n, v in ds.data_vars.items() if "event" in v.dims]
    rest = [n for n in ds.data_vars if n not in on_event]
    tables = {"": _frame(ds[rest])} if rest else {}
    if on_event:
        tables["_events"] = _frame(ds[on_event].drop_vars("time", errors="ignore"))
    return tables


def _frame(ds):
    if not ds.dims:             # a one-point sweep: one row (pandas needs an index)
        ds = ds.expand_dims("row")
        frame = ds.to_dataframe().reset_index(drop=True)
    else:
        frame = ds.to_dataframe().reset_index()
    for name in frame.columns:
        attrs = ds[name].attrs if name in ds.variables else {}
        if "flag_values" in attrs and "flag_meanings" in attrs:
            codes = dict(zip(np.atleast_1d(attrs["flag_values"]).tolist(),
                             str(attrs["flag_meanings"]).split()))
            frame[name] = frame[name].map(lambda c: codes.get(int(c), f"code {c}"))
    return frame.rename(columns=lambda name: header(ds, name))


def _units(ds, name) -> str:
    """The units of column ``name`` as a CSV states them: a CF time unit
    (``seconds since ...``) as ``s``; "" for none and for dimensionless ("1")."""
    units = str(ds[name].attrs.get("units", "")) if name in ds.variables else ""
    units = "s" if " since " in units else units
    return "" if units == "1" else units


def header(ds, name) -> str:
    """The CSV header of variable ``name``: ``amplitude [cm]``, ``time [s]``; the
    bare name where it has no units (counts, flags written as names)."""
    units = _units(ds, name)
    return f"{name} [{units}]" if units else str(name)


def units_table(ds, columns):
    """The ``column, name, units, long_name`` of every CSV column (``columns``, the
    headers as written; units "" where dimensionless), the table ``sweepcore
    export`` writes beside the data as ``<OUT stem>_units.csv``."""
    import pandas as pd

    names = {header(ds, n): n for n in ds.variables}
    rows = []
    for column in dict.fromkeys(columns):
        name = names.get(column, column)
        attrs = ds[name].attrs if name in ds.variables else {}
        rows.append({"column": column, "name": name, "units": _units(ds, name),
                     "long_name": attrs.get("long_name", "")})
    return pd.DataFrame(rows, columns=["column", "name", "units", "long_name"])
