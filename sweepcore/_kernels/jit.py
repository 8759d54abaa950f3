"""Compile options of every kernel, decided once, here.

* ``cache=True``: compiled once per machine and reused by later processes (tests,
  benchmarks, dask workers), in a directory keyed by a hash of all kernel sources
  (``__init__.py``), so a change anywhere never runs with stale inlined code.
* ``error_model="numpy"``: a division by zero gives inf/nan instead of raising.
  Kernels never raise (failure is a status code), and the Python error model puts a
  zero check on every division of the hot loop.
* no ``fastmath``: results must be bit-identical whatever the chunking, scheduler or
  number of workers.
* no CPython wrapper but for the entry points (``entry=True``): the kernels call
  each other, and the wrapper that unboxes Python arguments is code numba would
  generate and compile for every one of them (~12 % of a cold compilation).
  ``python_callable`` gives a test a callable copy of an internal kernel.
* no array assigned to a slice or a row (``a[:] = b``, ``a[i] = b``): numba checks
  the shapes, and the error it would raise formats them, for which it compiles its
  string machinery (str and repr of integers, concatenation, code points: ~4 s of
  CPU in a cold entry). ``copy_into`` copies without it.
* a kernel called from another is compiled for the types of that call's
  arguments, and a constant argument (``True``, ``1``) is typed as its literal
  value: each distinct constant compiles the whole callee, and all it calls, once
  more. ``runtime(value)`` passes a constant as a plain value where one compiled
  copy is to serve every value (a branch on it stays a branch).

Compile-time choices (the friction law's kind, the stepper) are made by numba's
``overload``: a call of an interface function (``law.py``, ``stepper.step``) is typed
to the one implementation its arguments select, so a run compiles only the law kind
and the method it uses. ``OVERLOAD_OPTIONS`` are the options those implementations
are compiled with.
"""
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic
from numba.np.arrayobj import make_array

OVERLOAD_OPTIONS = {"cache": True, "error_model": "numpy", "no_cpython_wrapper": True}


def kernel(fn=None, entry=False, **options):
    """``numba.njit`` with the project's options; ``entry=True`` for a kernel that
    Python calls; extra options (inline, nogil, parallel) are passed on."""
    opts = {**OVERLOAD_OPTIONS, **options}
    if entry:
        del opts["no_cpython_wrapper"]
    if fn is not None:
        return njit(**opts)(fn)
    return njit(**opts)


def python_callable(fn):
    """A copy of the internal kernel ``fn`` that Python can call (for tests)."""
    return njit(cache=False, error_model="numpy")(fn.py_func)


@intrinsic
def runtime(typingctx, value):
    """``value`` typed as a plain (non-literal) value: a kernel called with it is
    compiled once for every value instead of once per constant (module docstring)."""
    plain = types.unliteral(value)

    def codegen(context, builder, sig, args):
        return context.cast(builder, args[0], sig.args[0], sig.return_type)
    return plain(value), codegen


@intrinsic
def unowned(typingctx, arr):
    """A view of the array ``arr`` that carries no reference count.

    numba counts references to an array through its meminfo with atomic operations:
    every kernel that takes an array increments and decrements that count, and
    where threads share an array they contend for one cache line. An entry kernel
    takes views of this kind of the arrays its caller owns for the whole call (the
    parameter rows, the options, the outputs, a table law's data): no count, no
    contention. The view must not outlive the call (no kernel keeps one)."""
    if not isinstance(arr, types.Array):
        return None

    def codegen(context, builder, sig, args):
        view = make_array(arr)(context, builder, value=args[0])
        view.meminfo = cgutils.get_null_value(view.meminfo.type)
        view.parent = cgutils.get_null_value(view.parent.type)
        return view._getvalue()
    return arr(arr), codegen


@kernel(inline="always")
def copy_into(dst, src):
    """``dst[i] = src[i]`` for every i of the 1-d array ``dst`` (``src`` at least as
    long): ``dst[:] = src`` without numba's shape check (module docstring)."""
    for i in range(dst.shape[0]):
        dst[i] = src[i]
