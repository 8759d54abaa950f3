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
import inspect

from numba import njit, types
from numba.core import cgutils
from numba.core.errors import TypingError
from numba.extending import intrinsic, overload
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


def resolved_by(arg, modules, what):
    """A decorator ``interface(required=False, inline=False)`` for the functions of
    an interface resolved by the class of their argument ``arg`` (the law's data,
    the excitation's): each resolves, when it compiles, to the function of that name
    in ``modules()[class]`` (the kind's module), else to the stub's own body, its
    generic form (``required``: every kind defines it). Compiled as functions of
    their own, or with ``inline`` into the caller (a body without a branch or a
    loop: numba's own inlining of one trips its scope check). ``what`` names the
    interface in the errors."""
    defaults = {}

    def implementation(stub, data):
        table = modules()
        if not isinstance(data, types.BaseNamedTuple) or data.instance_class not in table:
            raise TypingError(f"{stub.__name__}: {what} data must be a {what} table's "
                              f"data class, got {data}")
        module = table[data.instance_class]
        fn = getattr(module, stub.__name__, None) or defaults.get(stub.__name__)
        if fn is None:
            raise TypingError(f"{what} kind {module.__name__} defines no "
                              f"{stub.__name__}, which has no generic form")
        return getattr(fn, "py_func", fn)

    def interface(required=False, inline=False):
        def declare(stub):
            at = list(inspect.signature(stub).parameters).index(arg)
            if not required:
                defaults[stub.__name__] = stub

            def typer(*args):
                return implementation(stub, args[at])
            typer.__signature__ = inspect.signature(stub)
            overload(stub, inline="always" if inline else "never",
                     jit_options=OVERLOAD_OPTIONS)(typer)
            return stub
        return declare
    interface.defaults = defaults       # the generic forms, by name
    return interface
