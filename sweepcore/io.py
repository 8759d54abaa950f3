"""Result files: CF netCDF4 written atomically, read back, checked; resumable work.

The final product of a sweep is one netCDF4 file written once, to a temporary name in
the target directory, then renamed over the target (``os.replace``), so a reader
never sees a partial file. While a sweep runs, finished chunks go to a working store
``<path>.partial/`` (:class:`WorkingStore`) from which an interrupted sweep resumes.
"""
from __future__ import annotations

import json
import math
import os
import re
import shutil
import uuid
from pathlib import Path

try:
    import fcntl
except ImportError:  # not POSIX: no lock against two sweeps on one path
    fcntl = None

import numpy as np
import xarray as xr

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
    """Explicit netCDF4 encoding: zlib + shuffle, ~MiB chunks, no fill on coordinates.

    Coordinates (CF section 2.5.1: no missing data) and integer flag variables get
    no ``_FillValue``; float data variables keep xarray's NaN fill.
    """
    enc = {}
    for name, var in ds.variables.items():
        e = {}
        if name in ds.coords or var.dtype.kind in "iub":
            e["_FillValue"] = None
        if var.ndim > 0 and name not in ds.coords:
            e.update(zlib=True, shuffle=True, complevel=complevel,
                     chunksizes=chunk_shape(var.shape, var.dtype.itemsize))
        enc[name] = e
    return enc


def write_netcdf(ds: xr.Dataset, path) -> Path:
    """Write ``ds`` to ``path`` (netCDF4, compressed) atomically.

    The file is written to a temporary name in the same directory and renamed over
    ``path`` only once complete; on any error the temporary file is removed and
    ``path`` is left as it was.

    Returns
    -------
    pathlib.Path
        The path written.
    """
    path = Path(path)
    if not path.parent.is_dir():
        raise FileNotFoundError(f"directory of path={str(path)!r} does not exist")
    tmp = path.parent / f".{path.name}.{uuid.uuid4().hex}.tmp"
    try:
        ds.drop_encoding().to_netcdf(tmp, engine="netcdf4", format="NETCDF4",
                                     encoding=netcdf_encoding(ds))
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)
    return path


def open_result(path) -> xr.Dataset:
    """Read a result file into memory (the file is closed on return).

    Nothing is decoded as time: variables in seconds stay float64, flag variables
    keep their integer type.
    """
    with xr.open_dataset(path, engine="netcdf4", decode_times=False,
                         decode_timedelta=False) as ds:
        return ds.load()


# ---------------------------------------------------------------- CF check
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


# ----------------------------------------------------------- working store
class StoreBusy(RuntimeError):
    """Another sweep is running on the same path (its working store is locked)."""


def _lock(directory: Path):
    """An exclusive lock on ``directory/lock``, held until the returned file closes.

    The kernel drops the lock when its process dies, even by SIGKILL, so a killed
    sweep never blocks its resume. (No locking where ``fcntl`` is missing.)
    """
    handle = open(directory / "lock", "a")
    if fcntl is None:
        return handle
    try:
        fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        handle.close()
        target = directory.with_name(directory.stem)
        raise StoreBusy(f"another sweep is running on {target}: its working store "
                        f"{directory} is locked; wait for it to finish, or stop it "
                        "and rerun to resume") from None
    return handle


class WorkingStore:
    """Finished chunks of a sweep in progress, in ``<path>.partial/``.

    One ``chunk-NNNNNN.npy`` file per finished chunk, each written to a temporary
    name and renamed into place, so a chunk file that exists is complete: its
    presence is the chunk's ``done`` flag. ``config.json`` holds the SHA-256 of the
    resolved configuration (grid values, option row, version, kernel sources) and
    the chunk size; a resume with another configuration is refused. The sweep that
    opened the store holds a lock on it until :meth:`close` (or :meth:`remove`): a
    second sweep on the same path meanwhile raises :class:`StoreBusy` at once.
    Use as a context manager.
    """

    FORMAT = 1

    def __init__(self, directory: Path, chunk: int, n_points: int, ncols: int, lock):
        self.directory = directory
        self.chunk = chunk
        self.n_points = n_points
        self.ncols = ncols
        self._lock = lock

    def __enter__(self) -> WorkingStore:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Release the lock (the store stays on disk for a resume)."""
        self._lock.close()

    @staticmethod
    def location(path) -> Path:
        """The working-store directory of a result ``path``."""
        path = Path(path)
        return path.parent / f"{path.name}.partial"

    @classmethod
    def open(cls, path, digest: str, config: dict, n_points: int, ncols: int,
             chunk: int | None, default_chunk: int) -> WorkingStore:
        """Resume the store of ``path`` (locked), or create it (locked).

        ``chunk`` None adopts the stored chunk size on resume (``default_chunk`` on
        creation); an explicit ``chunk`` must match the stored one.
        """
        directory = cls.location(path)
        meta = {"sweepcore_working_store": cls.FORMAT, "sha256": digest,
                "chunk": default_chunk if chunk is None else chunk,
                "n_points": n_points, "ncols": ncols, "config": config}
        for _attempt in range(3):   # the store may appear or vanish meanwhile
            if not directory.exists():
                store = cls._create(directory, meta)
                if store is not None:
                    return store
            try:
                lock = _lock(directory)
            except FileNotFoundError:     # removed by the sweep that just finished
                continue
            try:
                return cls._resume(directory, lock, digest, n_points, ncols, chunk)
            except BaseException:
                lock.close()
                raise
        raise StoreBusy(f"working store {directory} keeps appearing and vanishing: "
                        "another sweep is running on the same path")

    @classmethod
    def _create(cls, directory: Path, meta: dict) -> WorkingStore | None:
        """Build the store under a temporary name, locked, then rename it into place;
        None if another sweep created it first."""
        tmp = directory.parent / f".{directory.name}.{uuid.uuid4().hex}.tmp"
        tmp.mkdir()
        (tmp / "config.json").write_text(json.dumps(meta, indent=1, default=str))
        lock = _lock(tmp)
        try:
            os.rename(tmp, directory)
        except OSError:
            lock.close()
            shutil.rmtree(tmp)
            return None
        return cls(directory, meta["chunk"], meta["n_points"], meta["ncols"], lock)

    @classmethod
    def _resume(cls, directory, lock, digest, n_points, ncols, chunk) -> WorkingStore:
        try:
            meta = json.loads((directory / "config.json").read_text())
        except (OSError, ValueError) as err:
            raise ValueError(f"{directory} is not a sweepcore working store ({err}); "
                             "remove it or choose another path") from None
        if meta.get("sha256") != digest or meta.get("n_points") != n_points \
                or meta.get("ncols") != ncols:
            raise ValueError(
                f"working store {directory} was made by a sweep with different "
                "arguments (grid, method, tolerance, options, or the kernels changed); "
                "resume with the same arguments, or remove the store to start afresh")
        if chunk is not None and chunk != meta["chunk"]:
            raise ValueError(f"working store {directory} holds chunks of "
                             f"{meta['chunk']} points, got chunks={chunk}; pass "
                             f"chunks={meta['chunk']} (or None) to resume")
        return cls(directory, meta["chunk"], n_points, ncols, lock)

    def _file(self, i: int) -> Path:
        return self.directory / f"chunk-{i:06d}.npy"

    def done(self, n_chunks: int) -> list[int]:
        """Indices of the finished chunks."""
        return [i for i in range(n_chunks) if self._file(i).exists()]

    def read(self, i: int, n: int) -> np.ndarray:
        """The stored ``(n, ncols)`` result of chunk ``i``."""
        arr = np.load(self._file(i))
        if arr.shape != (n, self.ncols) or arr.dtype != np.float64:
            raise ValueError(f"{self._file(i)} holds {arr.dtype} {arr.shape}, expected "
                             f"float64 {(n, self.ncols)}: the store is damaged; remove "
                             f"{self.directory} to start afresh")
        return arr

    def write(self, i: int, result: np.ndarray) -> None:
        """Store the result of chunk ``i`` (atomic: temporary file, then rename)."""
        final = self._file(i)
        tmp = self.directory / f".{final.stem}.{uuid.uuid4().hex}.tmp.npy"
        try:
            np.save(tmp, np.ascontiguousarray(result, dtype=np.float64))
            os.replace(tmp, final)
        finally:
            tmp.unlink(missing_ok=True)

    def remove(self) -> None:
        """Delete the store (moved aside first, so no sweep sees it half deleted),
        then release the lock."""
        name = self.directory.name
        doomed = self.directory.with_name(f".{name}.{uuid.uuid4().hex}.del")
        os.rename(self.directory, doomed)
        shutil.rmtree(doomed)
        self.close()
