"""Result files: CF netCDF4 written atomically, read back, checked.

The final product of a sweep is one netCDF4 file written once, to a temporary name in
the target directory, then renamed over the target (``os.replace``), so a reader
never sees a partial file; dask-backed variables are written block by block, so the
result need not fit in memory (:func:`write_netcdf`).
"""
from __future__ import annotations

import contextlib
import math
import os
import re
import stat
from pathlib import Path

import numpy as np
import xarray as xr

from ..keywords import checked_keywords
from .files import describe_oserror, path_text, temporary_name, write_failed

COMPLEVEL = 4
CHUNK_BYTES = 4 * 2**20          # HDF5 chunks of about 4 MiB compress well
_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
_FLAG_WORD = re.compile(r"^[A-Za-z0-9_.+\-@]+$")


# ------------------------------------------------------------------ netCDF
def chunk_shape(shape: tuple[int, ...], itemsize: int,
                nbytes: int = CHUNK_BYTES) -> tuple[int, ...]:
    """HDF5 chunk shape of about ``nbytes``: trailing dimensions whole, leading cut."""
    budget = max(1, nbytes // itemsize)
    out = []
    for d, n in enumerate(shape):
        rest = math.prod(shape[d + 1:])
        if rest > budget:
            out.append(1)
            continue
        out.append(max(1, min(n, budget // rest)))
        out.extend(shape[d + 1:])
        break
    return tuple(out)


def netcdf_encoding(ds: xr.Dataset, complevel: int = COMPLEVEL) -> dict:
    """Explicit netCDF4 encoding: zlib + shuffle, ~MiB chunks, no fill on coordinates,
    a Fletcher-32 checksum on every array.

    Coordinates (CF section 2.5.1: no missing data) and integer flag variables get
    no ``_FillValue``; float data variables keep xarray's NaN fill. Every variable
    with a dimension, coordinates included, carries HDF5's Fletcher-32 checksum of
    each chunk, checked by HDF5 whenever the chunk is read (:func:`open_result`
    reads them all): a flipped bit is an error, never a value.
    """
    enc = {}
    for name, var in ds.variables.items():
        e = {"fletcher32": True} if var.ndim > 0 else {}
        if name in ds.coords or var.dtype.kind in "iub":
            e["_FillValue"] = None
        if var.ndim > 0 and name not in ds.coords:
            e.update(zlib=True, shuffle=True, complevel=complevel,
                     chunksizes=chunk_shape(var.shape, var.dtype.itemsize))
        enc[name] = e
    return enc


def estimated_bytes(ds: xr.Dataset) -> int:
    """Uncompressed bytes of ``ds``'s variables: an upper bound of its file's size."""
    return int(sum(v.size * v.dtype.itemsize for v in ds.variables.values()))


@checked_keywords
def write_netcdf(ds: xr.Dataset, path) -> Path:
    """Write ``ds`` to ``path`` (netCDF4, compressed) atomically.

    The file is written to a temporary name in the same directory and renamed over
    ``path`` only once complete; on any error the temporary file is removed and
    ``path`` is left as it was. Dask-backed variables are computed and written one
    block at a time (synchronous scheduler) into the file xarray laid out, so the
    Dataset need not fit in memory.

    Parameters
    ----------
    ds : xarray.Dataset
    path : str or path-like

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    OSError
        The write failed (disk full, ...): the message names the file, the bytes it
        needed (uncompressed, an upper bound) and the space free.
    """
    import dask

    path = Path(path)
    if not path.parent.is_dir():
        raise FileNotFoundError(f"directory of path={str(path)!r} does not exist")
    tmp = temporary_name(path, ".tmp")
    lazy = {name: var for name, var in ds.variables.items() if _is_dask(var.data)}
    try:
        with dask.config.set(scheduler="synchronous"), _small_chunk_cache():
            _skeleton(ds).drop_encoding().to_netcdf(
                tmp, engine="netcdf4", format="NETCDF4", encoding=netcdf_encoding(ds))
            if lazy:
                _fill_blocks(tmp, lazy)
        os.replace(tmp, path)
    except (OSError, RuntimeError) as err:
        # netCDF4 reports a full disk as RuntimeError("NetCDF: HDF error")
        if isinstance(err, RuntimeError) and not str(err).startswith("NetCDF"):
            raise
        raise write_failed("the result file", path, estimated_bytes(ds), err,
                           f"{path} is left as it was.") from err
    finally:
        tmp.unlink(missing_ok=True)
    return path


@contextlib.contextmanager
def _small_chunk_cache():
    """HDF5 chunk caches of one chunk per variable while a file is written (netCDF's
    default, 64 MiB per variable, would hold ~20 x 64 MiB of a large result)."""
    import netCDF4

    saved = netCDF4.get_chunk_cache()
    netCDF4.set_chunk_cache(CHUNK_BYTES + 2**20, 31, saved[2])
    try:
        yield
    finally:
        netCDF4.set_chunk_cache(*saved)


def _is_dask(data) -> bool:
    return type(data).__module__.startswith("dask")


def _fill_blocks(target: Path, lazy: dict) -> None:
    """Compute the dask-backed variables one block at a time and write each block
    into the file at its place (so no variable is ever whole in memory)."""
    import netCDF4

    with netCDF4.Dataset(target, "a") as nc:
        nc.set_auto_maskandscale(False)
        for name, var in lazy.items():
            data = var.data
            out = nc.variables[name]
            if data.ndim == 0:
                out.assignValue(np.asarray(data.compute(scheduler="synchronous"),
                                           dtype=var.dtype))
                continue
            starts = [np.cumsum((0,) + c[:-1]) for c in data.chunks]
            for index in np.ndindex(*data.numblocks):
                where = tuple(slice(s[i], s[i] + c[i])
                              for s, c, i in zip(starts, data.chunks, index))
                block = data.blocks[index].compute(scheduler="synchronous")
                out[where] = np.asarray(block, dtype=var.dtype)


def _skeleton(ds: xr.Dataset) -> xr.Dataset:
    """``ds`` with every dask-backed variable replaced by zeros that take no memory
    (a broadcast scalar per block): xarray writes the file's structure, metadata
    and the in-memory variables, and :func:`_fill_blocks` the data."""
    import dask.array as dsa

    out = ds.copy()
    for name, var in ds.variables.items():
        if _is_dask(var.data) and name not in ds.indexes:
            zero = dsa.broadcast_to(np.zeros((), var.dtype), var.shape,
                                    chunks=var.data.chunks)
            out[name] = xr.Variable(var.dims, zero, var.attrs)
    return out


@checked_keywords
def open_result(path) -> xr.Dataset:
    """Read a result file into memory (the file is closed on return).

    Nothing is decoded as time: variables in seconds stay float64, flag variables
    keep their integer type. Every value is read, so every Fletcher-32 checksum of
    the file is verified (:func:`write_netcdf` puts one on every array).

    Raises
    ------
    TypeError, ValueError
        ``path`` is not a usable file name (empty, NUL byte, ...).
    FileNotFoundError
        No such file.
    ValueError
        ``path`` is a directory, a FIFO (it would block) or another non-file; or
        the file is not netCDF, is truncated, or fails a checksum (damaged): the
        message names the file.
    """
    raw = path_text(path)
    try:
        mode = os.stat(raw).st_mode
    except FileNotFoundError:
        raise FileNotFoundError(f"no such result file: {raw}") from None
    except OSError as err:
        raise ValueError(f"cannot read {raw}: {describe_oserror(err)}") from None
    if not stat.S_ISREG(mode):
        kind = ("a directory" if stat.S_ISDIR(mode) else "a FIFO" if
                stat.S_ISFIFO(mode) else "not a regular file")
        raise ValueError(f"{raw} is {kind}, not a result file")
    try:
        with xr.open_dataset(raw, engine="netcdf4", decode_times=False,
                             decode_timedelta=False) as ds:
            return ds.load()
    except PermissionError:
        raise PermissionError(f"cannot read {raw}: permission denied") from None
    except (OSError, RuntimeError) as err:
        # netCDF4 says "NetCDF: HDF error" for a failed checksum or a cut file
        size = os.stat(raw).st_size
        raise ValueError(
            f"{raw} ({size:,} bytes) cannot be read as a netCDF result: "
            f"{describe_oserror(err) if isinstance(err, OSError) else err} (the file "
            "is truncated, damaged - a chunk failed its Fletcher-32 checksum - or not "
            "netCDF); write it again") from None


# ---------------------------------------------------------------- CF check
@checked_keywords
def check_cf(ds: xr.Dataset) -> list[str]:
    """Problems with the CF metadata of a sweep Dataset (empty list: none found).

    Checks the global attributes of CF section 2.6 (Conventions, title, history,
    source, references), variable names (2.3), ``units`` and ``long_name`` on every
    data and coordinate variable (3.1, 3.2), coordinates free of NaN (2.5.1), and
    flag variables (3.5): ``flag_values`` and ``flag_meanings`` both present, as many
    values as meanings, distinct values of the variable's type, and no data outside
    the flag values.
    """
    problems = []
    conv = ds.attrs.get("Conventions")
    if not (isinstance(conv, str) and conv.startswith("CF-")):
        problems.append(f"global attribute Conventions is {conv!r}, expected 'CF-x.y'")
    for att in ("title", "history", "source", "references"):
        if not ds.attrs.get(att):
            problems.append(f"global attribute {att} is missing")
    for name, var in ds.variables.items():
        if not _NAME.match(str(name)):
            problems.append(f"variable name {name!r} is not letters, digits and "
                            "underscores starting with a letter")
        for att in ("units", "long_name"):
            if not isinstance(var.attrs.get(att), str) or not var.attrs[att]:
                problems.append(f"variable {name} has no {att}")
        if name in ds.coords and var.dtype.kind == "f" and np.isnan(var.values).any():
            problems.append(f"coordinate {name} contains NaN")
        problems.extend(_check_flags(name, var))
    return problems


def _check_flags(name, var) -> list[str]:
    values = var.attrs.get("flag_values")
    meanings = var.attrs.get("flag_meanings")
    if values is None and meanings is None:
        return []
    if values is None or meanings is None:
        return [f"flag variable {name} needs both flag_values and flag_meanings"]
    values = np.atleast_1d(values)
    words = str(meanings).split()
    problems = []
    if len(words) != values.size:
        problems.append(f"flag variable {name}: {values.size} flag_values but "
                        f"{len(words)} flag_meanings")
    if np.unique(values).size != values.size:
        problems.append(f"flag variable {name}: flag_values are not distinct")
    if values.dtype != var.dtype:
        problems.append(f"flag variable {name}: flag_values of type {values.dtype}, "
                        f"variable of type {var.dtype}")
    bad_words = [w for w in words if not _FLAG_WORD.match(w)]
    if bad_words:
        problems.append(f"flag variable {name}: flag_meanings {bad_words} are not "
                        "single words")
    outside = np.setdiff1d(np.unique(var.values), values)
    if outside.size:
        problems.append(f"flag variable {name}: values {outside.tolist()} are not "
                        "among its flag_values")
    return problems
