"""What ``sweepcore export`` writes: a result as tables (one per group of
dimensions) under the variables' names, and the table of their units."""
from __future__ import annotations

import numpy as np


def csv_tables(ds) -> dict:
    """``{file suffix: pandas.DataFrame}``: one table per group of dimensions.

    A sweep is one table over its grid (variables on fewer dimensions, such as the
    measured boundary, are repeated along the others); a simulation one over
    ``time`` ("") and one over ``event`` ("_events"). Scalar coordinates (fixed
    parameters) are repeated as columns. Flag variables become their names; headers
    are the variables' names (``pandas.read_csv`` gives them as they are in the
    file), their units are in :func:`units_table`.
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
    return frame


def units_table(ds, columns):
    """The ``column, units, long_name`` of every CSV column (``1``: dimensionless;
    a simulation's time in s), the table ``sweepcore export`` writes beside the
    data as ``<OUT stem>_units.csv``."""
    import pandas as pd

    rows = []
    for name in dict.fromkeys(columns):
        attrs = ds[name].attrs if name in ds.variables else {}
        units = str(attrs.get("units", ""))
        rows.append({"column": name, "units": "s" if " since " in units else units,
                     "long_name": attrs.get("long_name", "")})
    return pd.DataFrame(rows, columns=["column", "units", "long_name"])
