"""What a result file says about itself: the CF labels of every result.

The global attributes of provenance (:func:`provenance`), variable and flag
attributes (:func:`attrs`, :func:`flag_attrs`, :func:`flags`), and the analytic
variables read from :mod:`sweepcore.law` over a result's coordinates
(:func:`analytic`, :func:`stick_onset_estimate`). Used by sweep, simulate, the
boundary searches and the diagrams; the metadata of each variable is declared once,
in :mod:`sweepcore.variables`.

What reads a result (``sweepcore info``, ``export``) imports this module without
the law modules (and numba with them): they are imported where the analytic
variables are computed.
"""
from __future__ import annotations

import datetime
import math
from importlib.metadata import PackageNotFoundError, version as _installed

import numpy as np
import xarray as xr

REFERENCE = ('C.-S. Liu, "Coulomb friction applied to analyze the cutting vibration '
             'of tool on workpiece"')


def version() -> str:
    """sweepcore's version (installed metadata; "0.1.0" in a source tree)."""
    try:
        return _installed("sweepcore")
    except PackageNotFoundError:   # source tree without install
        return "0.1.0"


def timestamp() -> str:
    """Now, in UTC, ISO 8601 to the second (``2026-01-31T12:00:00+00:00``): the one
    format of every ``history`` line."""
    return datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")


def run_statuses(ds: xr.Dataset) -> list[str]:
    """The status of each run of a simulation file: one for a single run, one per
    run for runs stacked along a parameter (a ``status`` variable, or the global
    attribute with one word per run)."""
    if "status" in ds.data_vars:
        return [str(s) for s in np.ravel(ds["status"].values)]
    return str(ds.attrs.get("status", "ok")).split() or ["ok"]


def run_dims(ds: xr.Dataset) -> list[str]:
    """The dimensions a simulation file stacks runs along (not time or event)."""
    return [d for d in ds.dims if d not in ("time", "event") and ds.sizes[d] > 1]


def is_geometric(values) -> bool:
    """True when ``values`` (> 0, 3 or more) are evenly spaced in log, not linearly."""
    a = np.asarray(values, dtype=float)
    if a.ndim != 1 or a.size < 3 or not np.all(a > 0):
        return False
    dl, d = np.diff(np.log(a)), np.diff(a)
    log_even = np.allclose(dl, dl[0], rtol=1e-6, atol=0)
    lin_even = np.allclose(d, d[0], rtol=1e-6, atol=0)
    return bool(log_even and not lin_even)


def mark_spacing(ds: xr.Dataset) -> xr.Dataset:
    """``spacing = "geometric"`` on each numeric dimension evenly spaced in log (so
    plots, sweepcore's and the reader's, know to use a log axis), ``"linear"`` on
    each evenly spaced one; an attribute already set is kept."""
    for d in ds.dims:
        c = ds[d]
        if c.dtype.kind != "f" or c.size < 3 or "spacing" in c.attrs:
            continue
        d_ = np.diff(c.values)
        if is_geometric(c.values):
            c.attrs["spacing"] = "geometric"
        elif np.allclose(d_, d_[0], rtol=1e-6, atol=0):
            c.attrs["spacing"] = "linear"
    return ds


def provenance(title: str, call: str, source: str, comment: str) -> dict:
    """CF global attributes (section 2.6): Conventions, title, history (the time, the
    version and ``call``), source (the version and ``source``), references, comment."""
    now = timestamp()
    return {
        "Conventions": "CF-1.11",
        "title": title,
        "history": f"{now} sweepcore {version()}: {call}",
        "source": f"sweepcore {version()}: {source}",
        "references": REFERENCE,
        "comment": comment,
    }


def attrs(units: str, long_name: str, comment: str = "") -> dict:
    """``units``, ``long_name`` and, if any, ``comment`` of a variable."""
    out = {"units": units, "long_name": long_name}
    return {**out, "comment": comment} if comment else out


def flag_attrs(meta: dict) -> dict:
    """A flag variable's attributes (``variables.REGIME``, ...) with int8 values."""
    return {**meta, "flag_values": np.array(meta["flag_values"], dtype=np.int8)}


def flags(meanings: dict, long_name: str) -> dict:
    """Flag attributes of the codes ``meanings`` (``{code: name}``)."""
    keys = sorted(meanings)
    return {"units": "1", "long_name": long_name,
            "flag_values": np.array(keys, np.int8),
            "flag_meanings": " ".join(meanings[k] for k in keys)}


def parameter(ds: xr.Dataset, name: str) -> float:
    """A simulation's parameter: its scalar coordinate (files of older versions: the
    global attribute), NaN when absent."""
    if name in ds.coords and ds[name].ndim == 0:
        return float(ds[name])
    return float(ds.attrs.get(name, np.nan))


def slider_parameters(ds: xr.Dataset) -> list[tuple[str, float]]:
    """``(name, value)`` of a simulation's slider, every term of its law: m, k, r_y,
    v, alpha1, alpha2, then the damping c unless it is 0 and the Stribeck terms
    r_k, v_s unless r_k = r_y (eq. 40's law: no such term)."""
    out = [(n, parameter(ds, n)) for n in ("m", "k", "r_y", "v", "alpha1", "alpha2")]
    c, r_k, r_y = parameter(ds, "c"), parameter(ds, "r_k"), parameter(ds, "r_y")
    if math.isfinite(c) and c != 0.0:
        out.append(("c", c))
    if math.isfinite(r_k) and r_k != r_y:
        out += [("r_k", r_k), ("v_s", parameter(ds, "v_s"))]
    return [(n, v) for n, v in out if math.isfinite(v)]


# ------------------------------------------------------------ analytic variables
def _laws(laws) -> tuple:
    """The laws of a result: ``laws``, or (None) the analytic law alone."""
    if laws is None:
        from .laws import ANALYTIC
        return (ANALYTIC,)
    return tuple(laws)


def _over(coords, name: str, formula, laws=None) -> xr.DataArray:
    """``formula(source)`` over the coordinates that ``law.derived(name)`` takes,
    broadcast by dimension name (dask arrays stay lazy); with several ``laws`` (the
    ``law`` dimension of ``coords``) one law at a time, stacked along ``law``."""
    from . import law
    from .laws import LAW_DIM
    laws = _laws(laws)
    if len(laws) > 1:
        first = _over(coords, name, formula, laws[:1])
        if not hasattr(first.data, "dask"):
            # in numpy, one law at a time on the first one's broadcast inputs: an
            # xarray call and concat per law took 40 ms, a minute for 1,000 laws
            given = [n for n in law.names_of(name, {"law": laws[0]}) if n in coords]
            inputs = {n: np.asarray(xr.Variable(coords[n].dims, np.asarray(
                coords[n].data)).set_dims(first.dims).data) for n in given}
            stack = np.stack([np.broadcast_to(formula({**inputs, "law": one}),
                                              first.shape) for one in laws])
            out = xr.Variable((LAW_DIM,) + first.dims, stack)
            return out if isinstance(first, xr.Variable) else xr.DataArray(out)
        return _over_laws(coords, name, formula, laws)
    one = {"law": laws[0]}
    names = law.names_of(name, one)
    given = [n for n in names if n in coords]      # absent: the law's default
    return xr.apply_ufunc(lambda *vals: formula({**dict(zip(given, vals)), **one}),
                          *(coords[n] for n in given), keep_attrs=False,
                          dask="parallelized", output_dtypes=[np.float64])


def _over_laws(coords, name: str, formula, laws):
    """``_over`` of several laws, lazily: one call over the law dimension whose
    blocks evaluate their laws in turn (a graph layer per law, concatenated, made
    every block written of a 1,000-law sweep optimise the whole graph: 631 s for
    2,000 points)."""
    import dask.array as dsa

    from . import law
    from .laws import LAW_DIM
    given = [n for n in law.names_of(name, {"law": laws[0]}) if n in coords]
    chunks = getattr(coords[LAW_DIM].data, "chunks", ((len(laws),),))
    index = xr.Variable(LAW_DIM, dsa.from_array(np.arange(len(laws)), chunks=chunks))
    if not isinstance(coords[LAW_DIM], xr.Variable):
        index = xr.DataArray(index)

    def each_law(which, *vals):
        which, *vals = np.broadcast_arrays(which, *vals)
        out = np.empty(which.shape)
        for i in np.unique(which):
            rows = which == i
            out[rows] = formula({**{n: v[rows] for n, v in zip(given, vals)},
                                 "law": laws[int(i)]})
        return out
    return xr.apply_ufunc(each_law, index, *(coords[n] for n in given),
                          keep_attrs=False, dask="parallelized",
                          output_dtypes=[np.float64])


def analytic(name: str, coords, dims=None, laws=None) -> xr.DataArray:
    """Analytic variable ``name`` (a key of ``variables.ANALYTIC``) of
    :mod:`sweepcore.law` over ``coords`` (a Dataset, or a mapping of DataArrays or
    Variables: then a Variable), labelled from ``variables.ANALYTIC``; its
    dimensions in the order of ``dims``; ``laws`` the grid's laws (a ``law``
    dimension where there are several; None: the analytic law)."""
    from . import law, variables
    da = _over(coords, name, lambda src: law.derived(name, src), laws)
    if dims is not None:
        da = da.transpose(*(d for d in dims if d in da.dims))
    da.attrs = attrs(*variables.ANALYTIC[name])
    return da


def criticality(coords, laws=None) -> xr.DataArray:
    """Codes of ``law.CRITICALITY`` (int8) over ``coords``, on the dimensions of
    ``v_star`` (:func:`sweepcore.law.criticality_code`)."""
    from . import law
    return _over(coords, "criticality", law.criticality_code, laws).astype(np.int8)


def stick_onset_estimate(coords, laws=None) -> xr.DataArray:
    """The averaging estimate of the stick onset (:func:`sweepcore.law.
    stick_onset_estimate`) over ``coords``, on the dimensions of ``v_star``."""
    from . import law, variables
    da = _over(coords, "v_star", law.stick_onset_estimate, laws)
    da.attrs = attrs(*variables.STICK_ONSET_ESTIMATE)
    return da


# ------------------------------------------------------------ the law of a result
def load_labels(loads, many: bool):
    """``(attrs, variables)`` of a forced result's load shapes: one load's attributes
    (``load``, ``load_kind`` and its own: a periodic load's coefficients); for a
    ``load`` dimension each attribute as a variable over ``load``."""
    if not many:
        return dict(loads[0].attrs()), {}
    keys = [k for one in loads for k in one.attrs() if k != "load"]
    variables = {}
    for key in dict.fromkeys(keys):
        vals = [one.attrs().get(key) for one in loads]
        if all(isinstance(v, (int, float)) or v is None for v in vals):
            data = np.array([np.nan if v is None else v for v in vals], np.float64)
        else:
            data = np.array(["" if v is None else str(v) for v in vals])
        variables[key] = xr.Variable("load", data, {"long_name": key.replace("_", " ")})
    return {}, variables


def law_labels(laws) -> tuple[dict, dict]:
    """``(attrs, variables)`` that say which friction law a result used: for one law
    object its attributes (``FrictionLaw.attrs``) and its table (``law_speed``,
    ``law_force`` on ``law_point``, where it has one); for a ``law`` dimension each
    attribute as a variable over ``law`` and the tables side by side (NaN-padded)."""
    from .laws import LAW_DIM
    laws = tuple(one for one in laws if one.attrs())     # the analytic law has none
    if not laws:
        return {}, {}
    tables = [one.table() for one in laws]
    if len(laws) == 1:
        variables = {}
        if tables[0] is not None:
            speed, force = tables[0]
            variables = {"law_speed": xr.Variable("law_point", speed, TABLE_SPEED),
                         "law_force": xr.Variable("law_point", force, TABLE_FORCE)}
        return dict(laws[0].attrs()), variables
    keys = [k for one in laws for k in one.attrs() if k != "law"]
    variables = {}
    for key in dict.fromkeys(keys):
        vals = [one.attrs().get(key) for one in laws]
        if all(isinstance(v, (int, float)) or v is None for v in vals):
            data = np.array([np.nan if v is None else v for v in vals], np.float64)
        else:
            data = np.array(["" if v is None else str(v) for v in vals])
        variables[key] = xr.Variable(LAW_DIM, data, {"long_name": key.replace("_", " ")})
    n = max((t[0].size for t in tables if t is not None), default=0)
    if n:
        pad = np.full((len(laws), 2, n), np.nan)
        for i, t in enumerate(tables):
            if t is not None:
                pad[i, :, :t[0].size] = t
        variables["law_speed"] = xr.Variable((LAW_DIM, "law_point"), pad[:, 0], TABLE_SPEED)
        variables["law_force"] = xr.Variable((LAW_DIM, "law_point"), pad[:, 1], TABLE_FORCE)
    return {}, variables


BEYOND_TABLE = {
    "units": "1", "long_name": "motion beyond the friction table",
    "flag_values": np.array([0, 1], dtype=np.int8),
    "flag_meanings": "within_table beyond_table",
    "comment": "1 where the attractor's relative speed xdot - v (from xdot_max and "
               "xdot_max - 2 velocity_amplitude) leaves the speeds the friction table "
               "covers (law_speed_span), where the table's end force is held; 0 also "
               "where no attractor was measured"}


def beyond_table(ds: xr.Dataset, laws):
    """``beyond_table`` over a sweep's points (int8), or None where no law of the
    sweep is a table (``FrictionLaw.speed_span`` finite)."""
    from .laws import LAW_DIM
    spans = np.array([one.speed_span() for one in laws], np.float64)
    if np.isinf(spans).all() or "xdot_max" not in ds:
        return None
    lo, hi = spans[:, 0], spans[:, 1]
    if LAW_DIM in ds.dims:
        lo, hi = xr.DataArray(lo, dims=LAW_DIM), xr.DataArray(hi, dims=LAW_DIM)
    else:
        lo, hi = lo[0], hi[0]
    top = ds.xdot_max - ds.v
    bottom = top - 2.0 * ds.velocity_amplitude
    flag = ((top > hi) | (bottom < lo)).astype(np.int8)
    return xr.Variable(flag.dims, flag.data, BEYOND_TABLE)


TABLE_SPEED = {"units": "cm s-1", "long_name": "relative speed of the friction table",
               "comment": "the points the law was given (TableLaw); NaN: padding"}
TABLE_FORCE = {"units": "kN", "long_name": "friction force of the friction table",
               "comment": "F at law_speed, as given (the representation: see "
                          "law_deviation)"}
