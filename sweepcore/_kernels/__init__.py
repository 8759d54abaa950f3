"""numba kernels of sweepcore: pure functions on float64 scalars and arrays.

Nothing here validates input or raises: the Python layer (``sweepcore.params``,
``sweepcore.sweep``) validates at the boundary, and every kernel reports failure
through the status codes of :mod:`sweepcore._kernels.codes`.

Compiled kernels are cached (``jit.py``) in a directory named after a hash of all the
kernel sources. numba keys each cache entry on its own file only, while the attractor
kernel inlines code from the driver and the steppers: without the hash a change to one
file could run with another file's stale machine code. The directory is
``$SWEEPCORE_CACHE_DIR`` or ``~/.cache/sweepcore``; an explicit ``NUMBA_CACHE_DIR``
is respected as given.
"""
import hashlib
import os
import pathlib

from numba.core import config as _config

_sources = sorted(pathlib.Path(__file__).parent.rglob("*.py"))
SOURCE_HASH = hashlib.sha256(b"".join(p.read_bytes() for p in _sources)).hexdigest()[:16]
if not os.environ.get("NUMBA_CACHE_DIR"):
    _base = os.environ.get("SWEEPCORE_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "sweepcore")
    _config.CACHE_DIR = os.path.join(_base, "numba-" + SOURCE_HASH)


# ----------------------------------------------------- the cache, never fatal
# numba's cache is a directory of pickles (an index ``.nbi`` per function, a data
# file ``.nbc`` per signature). Two ways it used to break a run for good: a damaged
# file (a killed write, a full disk) raised UnpicklingError at every later load, and
# a cache directory that cannot be written made numba fall back to the next place it
# knows, the installed package's own ``__pycache__``. Below, sweepcore's kernels are
# cached in the cache directory only (read-only: read, never written), and a file
# that does not load is recompiled and rewritten, with a line that says so.
import logging as _logging
import pickle as _pickle

from numba.core import caching as _caching

_PACKAGE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_log = _logging.getLogger("sweepcore.compile")
_told = set()


def _say_once(key: str, line: str) -> None:
    if key not in _told:
        _told.add(key)
        _log.warning(line)


class _Locator(_caching.UserProvidedCacheLocator):
    """numba's locator of a user-given cache directory, for sweepcore's kernels
    whether or not the directory can be written (others: numba's own locators)."""

    @classmethod
    def from_function(cls, py_func, py_file):
        if not _config.CACHE_DIR or not os.path.abspath(py_file).startswith(
                _PACKAGE + os.sep):
            return None
        return cls(py_func, py_file)

    def ensure_cache_path(self):
        try:
            super().ensure_cache_path()
        except OSError as err:      # read-only: loads still work, saves are skipped
            _say_once("unwritten", f"sweepcore: the kernel cache {_config.CACHE_DIR} "
                      f"cannot be written ({err.strerror}): kernels compiled now "
                      "are kept for this process only (set SWEEPCORE_CACHE_DIR to a "
                      "writable directory to keep them)")


def _ours(cache_file) -> bool:
    return str(cache_file._cache_path).startswith(str(_config.CACHE_DIR))


_DAMAGE = (_pickle.UnpicklingError, EOFError, ValueError, TypeError, AttributeError,
           ImportError, IndexError, KeyError, OSError)
_load_index, _load_data, _save = (_caching.IndexDataCacheFile._load_index,
                                  _caching.IndexDataCacheFile._load_data,
                                  _caching.IndexDataCacheFile.save)


def _damaged(path, err) -> None:
    _say_once(path, f"sweepcore: the kernel cache file {path} is damaged "
              f"({type(err).__name__}: {err}): recompiling it")


def _safe_load_index(self):
    try:
        return _load_index(self)
    except _DAMAGE as err:
        if not _ours(self):
            raise
        _damaged(self._index_path, err)
        return {}           # as an empty index: compiled again, then rewritten


def _safe_load_data(self, name):
    try:
        return _load_data(self, name)
    except FileNotFoundError:
        raise               # numba's own answer: not cached
    except _DAMAGE as err:
        if not _ours(self):
            raise
        _damaged(self._data_path(name), err)
        raise FileNotFoundError(name) from err     # numba: not cached, compile


def _safe_save(self, key, data):
    try:
        _save(self, key, data)
    except OSError as err:
        if not _ours(self):
            raise
        _say_once("unwritten", f"sweepcore: a compiled kernel could not be written to "
                  f"the cache {_config.CACHE_DIR} ({err.strerror}): it is kept for "
                  "this process only")


_caching.IndexDataCacheFile._load_index = _safe_load_index
_caching.IndexDataCacheFile._load_data = _safe_load_data
_caching.IndexDataCacheFile.save = _safe_save
_impl = getattr(_caching, "CacheImpl", None) or _caching._CacheImpl  # numba < 0.60
if _Locator not in _impl._locator_classes:
    _impl._locator_classes.insert(0, _Locator)


# Every compilation is announced (``sweepcore.compiled``: what, how long it took
# before, how long it took), whichever room of the Python side calls a kernel first:
# numba's compile events go there from here, the one module every kernel imports.
from numba.core import event as _event


class _Compiles(_event.Listener):
    def on_start(self, ev):
        from ..compiled import ANNOUNCER
        ANNOUNCER.on_start(ev)

    def on_end(self, ev):
        from ..compiled import ANNOUNCER
        ANNOUNCER.on_end(ev)


_event.register("numba:compile", _Compiles())
