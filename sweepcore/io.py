"""Result files: CF netCDF4 written atomically, read back, checked; resumable work.

The final product of a sweep is one netCDF4 file written once, to a temporary name in
the target directory, then renamed over the target (``os.replace``), so a reader
never sees a partial file; dask-backed variables are written block by block, so the
result need not fit in memory (:func:`write_netcdf`). :func:`result_path` decides,
before any work, which paths may become a result file. While a sweep runs, finished
chunks go to a working store ``<path>.partial/`` (:class:`WorkingStore`), each with
its SHA-256 and grid range, from which an interrupted sweep resumes after checking
them. Write errors name what was being written, where, and the space it needed.
"""
from __future__ import annotations

import contextlib
import hashlib
import io
import json
import math
import os
import re
import shutil
import stat
import uuid
import warnings
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


def estimated_bytes(ds: xr.Dataset) -> int:
    """Uncompressed bytes of ``ds``'s variables: an upper bound of its file's size."""
    return int(sum(v.size * v.dtype.itemsize for v in ds.variables.values()))


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


def result_path(path, overwrite: bool = False) -> Path:
    """Check a result file name before any work; return it as a Path.

    The rules: ``path`` is a ``str`` or ``os.PathLike`` of ``str``; an existing
    regular file is replaced (atomically, once the new result is complete), unless
    it is read-only (no write permission bit), which needs ``overwrite=True``; an
    existing directory, symbolic link, FIFO, device or socket is refused (a rename
    over it would replace it by a regular file); the directory must exist.

    Raises
    ------
    TypeError, ValueError, FileNotFoundError
        Naming ``path`` and its value.
    """
    raw = os.fspath(path) if isinstance(path, os.PathLike) else path
    if not isinstance(raw, str):
        raise TypeError(f"path must be a str or os.PathLike naming the result file "
                        f"(e.g. 'map.nc'), got {path!r} of type {type(path).__name__}")
    target = Path(raw)
    if raw == "" or raw.endswith(("/", os.sep)) or target.name in ("", ".", ".."):
        raise ValueError(f"path={raw!r} is a directory; give the name of the result "
                         "file (e.g. 'map.nc')")
    try:
        st = os.lstat(target)
    except OSError:       # missing, or its directory is not one: checked below
        st = None
    if st is not None:
        mode = st.st_mode
        if stat.S_ISDIR(mode):
            raise ValueError(f"path={raw!r} is a directory; give the name of the "
                             "result file (e.g. 'map.nc')")
        kind = ("a symbolic link" if stat.S_ISLNK(mode) else "a FIFO" if
                stat.S_ISFIFO(mode) else "a device" if stat.S_ISCHR(mode) or
                stat.S_ISBLK(mode) else "a socket" if stat.S_ISSOCK(mode) else None)
        if kind is not None:
            raise ValueError(f"path={raw!r} is {kind}, not a regular file: the result "
                             "is written to a new file renamed over the path, which "
                             "would replace it; give the name of a regular file")
        if not overwrite and (not mode & 0o222 or not os.access(target, os.W_OK)):
            raise ValueError(f"path={raw!r} is a read-only file (mode "
                             f"{stat.S_IMODE(mode):04o}); pass overwrite=True to "
                             "replace it, or choose another path")
    if not target.parent.is_dir():
        raise FileNotFoundError(f"path={raw!r}: directory {target.parent} does not "
                                "exist")
    if len(os.fsencode(target.name)) > _name_max(target.parent):
        raise ValueError(f"path={raw!r}: file name longer than "
                         f"{_name_max(target.parent)} bytes")
    return target


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
NAME_MAX = 255                   # bytes in one file name (POSIX file systems)
_LONGEST_SUFFIX = len(".partial..tmp") + 1 + 32   # ".<name>.partial.<uuid>.tmp"


class StoreBusy(RuntimeError):
    """Another sweep is running on the same path (its working store is locked)."""


class StoreDamaged(ValueError):
    """The working store cannot be used (its configuration file is unreadable, or
    it is not a directory); the message names it and says what to do."""


class DamagedChunkWarning(UserWarning):
    """A chunk file of a working store failed its check and is computed again."""


def _name_max(directory: Path) -> int:
    try:
        return os.pathconf(directory, "PC_NAME_MAX")
    except (OSError, ValueError, AttributeError):
        return NAME_MAX


def temporary_name(path: Path, suffix: str) -> Path:
    """A fresh hidden name beside ``path`` (``.<name>.<uuid><suffix>``), shortened
    to ``.sweepcore-<uuid><suffix>`` when that would be too long a file name."""
    tag = uuid.uuid4().hex
    name = f".{path.name}.{tag}{suffix}"
    if len(os.fsencode(name)) > _name_max(path.parent):
        name = f".sweepcore-{tag}{suffix}"
    return path.parent / name


def _describe_oserror(err: OSError) -> str:
    return err.strerror or str(err) or type(err).__name__


def free_bytes(directory: Path) -> int | None:
    """Bytes free for this user on the file system of ``directory`` (None: unknown)."""
    try:
        return shutil.disk_usage(directory).free
    except OSError:
        return None


def write_failed(what: str, where: Path, nbytes: int, err: BaseException,
                 after: str) -> OSError:
    """An OSError saying what was being written, where, how much space it needed and
    how much was free; ``after`` says what state things are left in."""
    free = free_bytes(where.parent)
    free_text = "unknown" if free is None else f"{free:,} bytes"
    errno_ = getattr(err, "errno", None)
    reason = _describe_oserror(err) if isinstance(err, OSError) else str(err)
    return OSError(errno_, f"writing {what} to {where} failed ({reason}); it needed "
                           f"about {nbytes:,} bytes, {free_text} free on that file "
                           f"system. {after}")


def _lock(directory: Path):
    """An exclusive lock on ``directory/lock``, held until the returned file closes.

    The kernel drops the lock when its process dies, even by SIGKILL, so a killed
    sweep never blocks its resume. (No locking where ``fcntl`` is missing.)
    """
    try:
        handle = open(directory / "lock", "a")
    except (NotADirectoryError, IsADirectoryError, PermissionError) as err:
        raise StoreDamaged(f"working store {directory} is not usable "
                           f"({_describe_oserror(err)}): it must be a directory made "
                           "by sweepcore; remove it or choose another path") from None
    if fcntl is None:
        return handle
    try:
        fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        handle.close()
        raise StoreBusy(f"another sweep is running on the same path: its working "
                        f"store {directory} is locked; wait for it to finish, or stop "
                        "it and rerun to resume") from None
    return handle


_CHUNK_FILE = re.compile(r"^chunk-(\d{6,})\.(\d+)-(\d+)\.([0-9a-f]{64})\.npy$")


class WorkingStore:
    """Finished chunks of a sweep in progress, in ``<path>.partial/``.

    One file per finished chunk, ``chunk-NNNNNN.START-STOP.SHA256.npy``: an ``.npy``
    array ``(ncols, STOP - START)`` (one contiguous row per observable, so a column
    is read without the others) of the flat grid points ``START <= i < STOP``,
    whose SHA-256 (of the whole file) is part of its name. Each file is written to a
    temporary name and renamed into place, so one that exists was complete when
    written; on resume (:meth:`verified`) every file is read back and its name, range
    and checksum checked, and one that fails (damaged bytes, a value changed, a file
    copied over another, truncated, a directory in its place) is deleted with a
    warning naming it, so that its chunk is computed again. ``config.json`` holds the
    SHA-256 of the resolved configuration (grid values, option row, version, kernel
    sources) and the chunk size; a resume with another configuration is refused.
    The sweep that opened the store holds a lock on it until :meth:`close` (or
    :meth:`remove`): a second sweep on the same path meanwhile raises
    :class:`StoreBusy` at once. Use as a context manager.

    A result name too long to take the ``.partial`` suffix gets a short store name,
    ``sweepcore-<hash of the name>.partial``, beside it (:meth:`location`).
    """

    FORMAT = 2

    def __init__(self, directory: Path, chunk: int, n_points: int, ncols: int, lock):
        self.directory = directory
        self.chunk = chunk
        self.n_points = n_points
        self.ncols = ncols
        self._lock = lock
        self._files = {}

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
        name = f"{path.name}.partial"
        if len(os.fsencode(name)) + _LONGEST_SUFFIX > _name_max(path.parent):
            digest = hashlib.sha256(os.fsencode(path.name)).hexdigest()[:20]
            name = f"sweepcore-{digest}.partial"
        return path.parent / name

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
                "n_points": n_points, "ncols": ncols, "result": str(path),
                "config": config}
        for _attempt in range(3):   # the store may appear or vanish meanwhile
            if not os.path.lexists(directory):
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
        tmp = temporary_name(directory, ".tmp")
        try:
            tmp.mkdir()
            (tmp / "config.json").write_text(json.dumps(meta, indent=1, default=str))
        except OSError as err:
            shutil.rmtree(tmp, ignore_errors=True)
            raise write_failed("the working store's configuration", tmp, 4096, err,
                               "Nothing was computed.") from err
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
            if not isinstance(meta, dict) or meta.get("sweepcore_working_store") \
                    != cls.FORMAT or not isinstance(meta.get("chunk"), int) \
                    or meta["chunk"] < 1:
                raise ValueError("not a sweepcore working store of format "
                                 f"{cls.FORMAT}")
        except (OSError, ValueError, UnicodeDecodeError) as err:
            reason = _describe_oserror(err) if isinstance(err, OSError) else err
            raise StoreDamaged(
                f"{directory} is not a usable sweepcore working store (its "
                f"config.json: {reason}); remove it to start afresh, or choose another "
                "path") from None
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

    # ---------------------------------------------------------------- chunks
    def bounds(self, i: int) -> tuple[int, int]:
        """Flat range ``[start, stop)`` of chunk ``i``."""
        start = i * self.chunk
        return start, min(start + self.chunk, self.n_points)

    @property
    def n_chunks(self) -> int:
        return -(-self.n_points // self.chunk)

    def _discard(self, entry: Path, reason: str) -> None:
        warnings.warn(f"working store: {entry.name} {reason}; it is discarded and its "
                      f"chunk computed again (store {self.directory})",
                      DamagedChunkWarning, stacklevel=3)
        try:
            if entry.is_dir() and not entry.is_symlink():
                shutil.rmtree(entry)
            else:
                entry.unlink()
        except FileNotFoundError:
            pass

    def _check(self, entry: Path, i: int) -> np.ndarray | str:
        """The array stored in ``entry`` for chunk ``i``, or why it cannot be used."""
        m = _CHUNK_FILE.match(entry.name)
        start, stop = self.bounds(i)
        if (int(m.group(2)), int(m.group(3))) != (start, stop):
            return (f"records points [{m.group(2)}, {m.group(3)}), but chunk {i} is "
                    f"[{start}, {stop})")
        try:
            if entry.is_symlink() or not entry.is_file():
                return "is not a regular file"
            data = entry.read_bytes()
        except OSError as err:
            return f"cannot be read ({_describe_oserror(err)})"
        if hashlib.sha256(data).hexdigest() != m.group(4):
            return f"fails its SHA-256 checksum ({len(data)} bytes)"
        try:
            arr = np.load(io.BytesIO(data), allow_pickle=False)
        except Exception as err:  # noqa: BLE001 - any parse failure means unusable
            return f"is not a readable array ({type(err).__name__})"
        if arr.shape != (self.ncols, stop - start) or arr.dtype != np.float64:
            return (f"holds {arr.dtype} {arr.shape}, expected float64 "
                    f"{(self.ncols, stop - start)}")
        return arr.T

    def verified(self) -> list[int]:
        """Indices of the finished chunks, each read back and checked.

        A chunk file that fails (see the class notes) is deleted with a
        :class:`DamagedChunkWarning` naming it, and its chunk is not listed; so is a
        stray entry with a chunk file's name that is not one.
        """
        self._files = {}
        try:
            entries = sorted(os.scandir(self.directory), key=lambda e: e.name)
        except OSError as err:
            raise StoreDamaged(f"working store {self.directory} cannot be listed "
                               f"({_describe_oserror(err)})") from None
        for e in entries:
            if not e.name.startswith("chunk-"):
                continue
            entry = Path(e.path)
            m = _CHUNK_FILE.match(e.name)
            if m is None or int(m.group(1)) >= self.n_chunks:
                self._discard(entry, "is not a chunk file of this store")
                continue
            i = int(m.group(1))
            if i in self._files:
                self._discard(entry, f"is a second file for chunk {i}")
                continue
            got = self._check(entry, i)
            if isinstance(got, str):
                self._discard(entry, got)
                continue
            self._files[i] = entry
        return sorted(self._files)

    def read(self, i: int) -> np.ndarray:
        """The stored ``(stop - start, ncols)`` result of chunk ``i``, checked again.

        Raises
        ------
        StoreDamaged
            The chunk file is missing or fails its check (it is deleted: a rerun of
            the same call computes the chunk again).
        """
        entry = self._files.get(i)
        got = "is missing" if entry is None else self._check(entry, i)
        if isinstance(got, str):
            if entry is not None:
                self._discard(entry, got)
            raise StoreDamaged(f"chunk {i} of the working store {self.directory} "
                               f"{got} (changed during the sweep); it was removed: rerun "
                               "the same call to compute it again")
        return got

    def column(self, i: int, col: int, lo: int, hi: int) -> np.ndarray:
        """Column ``col`` of points ``lo <= j < hi`` of chunk ``i`` (offsets within
        the chunk), read alone from the file (memory-mapped) of a chunk that
        :meth:`verified` or :meth:`write` has listed.

        Raises
        ------
        StoreDamaged
            The chunk is not listed, or its file no longer holds the array.
        """
        entry = self._files.get(i)
        start, stop = self.bounds(i)
        try:
            arr = np.load(entry, mmap_mode="r", allow_pickle=False)
            if arr.shape != (self.ncols, stop - start) or arr.dtype != np.float64:
                raise ValueError(f"holds {arr.dtype} {arr.shape}")
            return np.array(arr[col, lo:hi])
        except Exception as err:  # noqa: BLE001 - anything here means unusable
            raise StoreDamaged(f"chunk {i} of the working store {self.directory} "
                               f"cannot be read ({type(err).__name__}: {err}); rerun "
                               "the same call to check the store and compute what is "
                               "missing") from None

    def write(self, i: int, result: np.ndarray) -> None:
        """Store the result of chunk ``i`` (atomic: temporary file, then rename).

        Raises
        ------
        OSError
            Naming the chunk file, the bytes needed and the space free; the store
            stays resumable.
        """
        start, stop = self.bounds(i)
        buf = io.BytesIO()
        np.save(buf, np.ascontiguousarray(np.asarray(result, dtype=np.float64).T),
                allow_pickle=False)
        data = buf.getvalue()
        final = self.directory / (f"chunk-{i:06d}.{start}-{stop}."
                                  f"{hashlib.sha256(data).hexdigest()}.npy")
        tmp = self.directory / f".chunk-{i:06d}.{uuid.uuid4().hex}.tmp"
        try:
            with open(tmp, "wb") as f:
                f.write(data)
            os.replace(tmp, final)
        except OSError as err:
            raise write_failed(f"chunk {i} (points [{start}, {stop}))", final,
                               len(data), err,
                               "The working store is kept: free space and rerun the "
                               "same call to resume.") from err
        finally:
            tmp.unlink(missing_ok=True)
        self._files[i] = final

    def remove(self) -> None:
        """Delete the store (moved aside first, so no sweep sees it half deleted),
        then release the lock."""
        doomed = temporary_name(self.directory, ".del")
        os.rename(self.directory, doomed)
        shutil.rmtree(doomed)
        self.close()
