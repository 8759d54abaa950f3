"""Compile options of every kernel, decided once, here.

* ``cache=True``: compiled once per machine and reused by later processes (tests,
  benchmarks, dask workers), in a directory keyed by a hash of all kernel sources
  (``__init__.py``), so a change anywhere never runs with stale inlined code.
* ``error_model="numpy"``: a division by zero gives inf/nan instead of raising.
  Kernels never raise (failure is a status code), and the Python error model puts a
  zero check on every division of the hot loop.
* no ``fastmath``: results must be bit-identical whatever the chunking, scheduler or
  number of workers.

Compile-time choices (the friction law's kind, the stepper) are made by numba's
``overload``: a call of an interface function (``law.py``, ``stepper.step``) is typed
to the one implementation its arguments select, so a run compiles only the law kind
and the method it uses. ``OVERLOAD_OPTIONS`` are the options those implementations
are compiled with.
"""
from numba import njit

OVERLOAD_OPTIONS = {"cache": True, "error_model": "numpy"}


def kernel(fn=None, **options):
    """``numba.njit`` with the project's options; extra options (inline, nogil,
    parallel) are passed on."""
    opts = {**OVERLOAD_OPTIONS, **options}
    if fn is not None:
        return njit(**opts)(fn)
    return njit(**opts)
