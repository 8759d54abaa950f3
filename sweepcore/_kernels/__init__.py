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
