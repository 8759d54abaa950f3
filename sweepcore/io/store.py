"""The working store of a sweep in progress: finished chunks, each checked by its
SHA-256 and grid range, under a lock, from which an interrupted sweep resumes."""
from __future__ import annotations

import hashlib
import io
import json
import os
import re
import shutil
import uuid
import warnings
from pathlib import Path

try:
    import fcntl
except ImportError:  # not POSIX: no lock against two sweeps on one path
    fcntl = None

import numpy as np

from .files import name_max, describe_oserror, temporary_name, write_failed

_LONGEST_SUFFIX = len(".partial..tmp") + 1 + 32   # ".<name>.partial.<uuid>.tmp"


class StoreBusy(RuntimeError):
    """Another sweep is running on the same path (its working store is locked)."""


class StoreDamaged(ValueError):
    """The working store cannot be used (its configuration file is unreadable, or
    it is not a directory); the message names it and says what to do."""


class DamagedChunkWarning(UserWarning):
    """A chunk file of a working store failed its check and is computed again."""


def _lock(directory: Path):
    """An exclusive lock on ``directory/lock``, held until the returned file closes.

    The kernel drops the lock when its process dies, even by SIGKILL, so a killed
    sweep never blocks its resume. (No locking where ``fcntl`` is missing.)
    """
    if os.path.islink(directory):
        # its removal at the end would rename the link and fail on its target
        raise StoreDamaged(f"working store {directory} is a symbolic link (to "
                           f"{os.readlink(directory)}), not a directory made by "
                           "sweepcore; remove the link or choose another path")
    if os.path.isdir(directory / "lock") or os.path.islink(directory / "lock"):
        raise StoreDamaged(f"the lock file {directory / 'lock'} of the working store "
                           "is not a regular file; remove it (the store's chunks are "
                           "kept) or choose another path")
    try:
        handle = open(directory / "lock", "a")
    except (NotADirectoryError, IsADirectoryError, PermissionError) as err:
        raise StoreDamaged(f"working store {directory} is not usable "
                           f"({describe_oserror(err)}): it must be a directory made "
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
    is read without the others; a store of ``ncols`` None takes chunks of any width,
    for answers whose size varies, such as the attractors of a basin point) of the
    flat grid points ``START <= i < STOP``,
    whose SHA-256 (of the store's configuration digest followed by the whole file)
    is part of its name: a chunk copied from a store of other settings fails it. Each file is written to a
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

    FORMAT = 3          # 3: chunk hashes include the configuration digest

    def __init__(self, directory: Path, chunk: int, n_points: int, ncols: int | None,
                 lock, digest: str):
        self.directory = directory
        self._salt = digest.encode("ascii")
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
        if len(os.fsencode(name)) + _LONGEST_SUFFIX > name_max(path.parent):
            digest = hashlib.sha256(os.fsencode(path.name)).hexdigest()[:20]
            name = f"sweepcore-{digest}.partial"
        return path.parent / name

    @classmethod
    def open(cls, path, digest: str, config: dict, n_points: int, ncols: int | None,
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
        return cls(directory, meta["chunk"], meta["n_points"], meta["ncols"], lock,
                   meta["sha256"])

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
            reason = describe_oserror(err) if isinstance(err, OSError) else err
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
        return cls(directory, meta["chunk"], n_points, ncols, lock, digest)

    # ---------------------------------------------------------------- chunks
    def bounds(self, i: int) -> tuple[int, int]:
        """Flat range ``[start, stop)`` of chunk ``i``."""
        start = i * self.chunk
        return start, min(start + self.chunk, self.n_points)

    @property
    def n_chunks(self) -> int:
        return -(-self.n_points // self.chunk)

    def _hash(self, data: bytes) -> str:
        """A chunk file's checksum: SHA-256 of the configuration digest and the bytes."""
        return hashlib.sha256(self._salt + data).hexdigest()

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
            return f"cannot be read ({describe_oserror(err)})"
        if self._hash(data) != m.group(4):
            return (f"fails its SHA-256 checksum ({len(data)} bytes; damaged, or "
                    "copied from a sweep of other settings)")
        try:
            arr = np.load(io.BytesIO(data), allow_pickle=False)
        except Exception as err:  # noqa: BLE001 - any parse failure means unusable
            return f"is not a readable array ({type(err).__name__})"
        if not self._fits(arr, stop - start):
            return (f"holds {arr.dtype} {arr.shape}, expected float64 "
                    f"{(self.ncols or 'any', stop - start)}")
        return arr.T

    def _fits(self, arr, n: int) -> bool:
        """A chunk's array: float64 (ncols, n); ``ncols`` None: any width >= 1."""
        width = arr.shape[0] if arr.ndim == 2 and arr.shape[0] >= 1 else -1
        return arr.dtype == np.float64 and arr.ndim == 2 and \
            arr.shape == (self.ncols or width, n)

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
                               f"({describe_oserror(err)})") from None
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
            if not self._fits(arr, stop - start):
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
                                  f"{self._hash(data)}.npy")
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
        if doomed.is_symlink():     # replaced during the sweep: the link only goes
            warnings.warn(f"working store {self.directory} was replaced by a symbolic "
                          f"link during the sweep; the link is removed, its target "
                          f"{os.readlink(doomed)} is left as it is", RuntimeWarning,
                          stacklevel=2)
            doomed.unlink()
        else:
            shutil.rmtree(doomed)
        self.close()
