"""File rules shared by the result file and the working store: which paths may
become a result (:func:`result_path`), fresh temporary names beside a target, and
write errors that name what was written, where, and the space it needed."""
from __future__ import annotations

import os
import re
import shutil
import stat
import uuid
from pathlib import Path

NAME_MAX = 255                   # bytes in one file name (POSIX file systems)


def name_max(directory: Path) -> int:
    try:
        return os.pathconf(directory, "PC_NAME_MAX")
    except (OSError, ValueError, AttributeError):
        return NAME_MAX


def temporary_name(path: Path, suffix: str) -> Path:
    """A fresh hidden name beside ``path`` (``.<name>.<uuid><suffix>``), shortened
    to ``.sweepcore-<uuid><suffix>`` when that would be too long a file name."""
    tag = uuid.uuid4().hex
    name = f".{path.name}.{tag}{suffix}"
    if len(os.fsencode(name)) > name_max(path.parent):
        name = f".sweepcore-{tag}{suffix}"
    return path.parent / name


def stale_temporaries(path: Path, suffix: str = ".tmp") -> list[Path]:
    """The temporaries :func:`temporary_name` made beside ``path`` (a write killed
    before its rename leaves one behind); not the shortened ``.sweepcore-<uuid>``
    names, which do not say whose they are. Only the caller knows none is in use."""
    pattern = re.compile(rf"^\.{re.escape(path.name)}\.[0-9a-f]{{32}}{re.escape(suffix)}$")
    try:
        return [path.parent / n for n in os.listdir(path.parent) if pattern.match(n)]
    except OSError:
        return []


def describe_oserror(err: OSError) -> str:
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
    reason = describe_oserror(err) if isinstance(err, OSError) else str(err)
    return OSError(errno_, f"writing {what} to {where} failed ({reason}); it needed "
                           f"about {nbytes:,} bytes, {free_text} free on that file "
                           f"system. {after}")


def check_flag(name: str, value, none: bool = False) -> None:
    """Refuse anything but True or False (and None if ``none``): a string such as
    "no" would count as true."""
    if (value is None and none) or isinstance(value, bool) or \
            type(value).__name__ == "bool_":        # numpy's bool
        return
    raise TypeError(f"{name} must be True or False{' (or None)' if none else ''}, "
                    f"got {value!r} of type {type(value).__name__}")


def path_text(path, what: str = "path") -> str:
    """``path`` as a str that can name a netCDF file, or raise naming ``what``.

    A str or ``os.PathLike`` of str, not empty, without NUL bytes, and encodable as
    UTF-8 (netCDF opens files by UTF-8 names: a name holding bytes undecodable in
    this locale would be refused by netCDF only after the work).
    """
    raw = os.fspath(path) if isinstance(path, os.PathLike) else path
    if not isinstance(raw, str):
        raise TypeError(f"{what} must be a str or os.PathLike naming the result file "
                        f"(e.g. 'map.nc'), got {path!r} of type {type(path).__name__}")
    if raw == "":
        raise ValueError(f"{what} is empty; give the name of a result file (e.g. "
                         "'map.nc')")
    if "\x00" in raw:
        raise ValueError(f"{what}={raw!r} holds a NUL byte, which no file name can")
    try:
        raw.encode("utf-8")
    except UnicodeEncodeError as err:
        raise ValueError(f"{what}={raw!r} holds bytes that are not UTF-8 (position "
                         f"{err.start}); netCDF opens files by UTF-8 names only: "
                         "rename it") from None
    return raw


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
    check_flag("overwrite", overwrite)
    raw = path_text(path)
    target = Path(raw)
    if raw.endswith(("/", os.sep)) or target.name in ("", ".", ".."):
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
    if len(os.fsencode(target.name)) > name_max(target.parent):
        raise ValueError(f"path={raw!r}: file name longer than "
                         f"{name_max(target.parent)} bytes")
    return target
