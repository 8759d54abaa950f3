"""Compile half of a cold entry kernel in a second process (``python -m``).

numba compiles single-threaded, and most of a cold start is compilation: the
attractor kernel of dop853 and the polynomial law is ~36 s of CPU (``python
benchmarks/compile_probe.py --breakdown attractor_rows dop853 polynomial``). Its two
halves are the driver (``attractor.next_event``, compiled first, as the entry is
typed; about two thirds) and the attractor search (``attractor.on_event``, compiled
after it); the derived quantities of the result (``derived.derived_rows``) come after
the sweep. A second process started with the first call compiles the search and the
derived quantities into numba's cache while this one compiles the driver, and this
one then loads them from the cache: on two cores the cold start takes about the
driver's time. Where the second process is late, or the signature below no longer
matches the entry's (a test checks that it does), this process compiles them
itself: never a wrong kernel, at worst no gain.

Usage: ``python -m sweepcore._kernels.prefetch METHOD_CODE KIND_NAME``.
"""
import sys

from numba import types, typeof

from . import attractor, derived, laws

A1 = types.Array(types.float64, 1, "C")
A2 = types.Array(types.float64, 2, "C")


def law_type(kind: str):
    """The numba type of a kind's law data (of the law table's sample)."""
    return typeof(laws.SAMPLES[kind])


def search_signature(meth: int, kind: str) -> tuple:
    """The argument types with which ``attractor_point`` calls ``on_event``."""
    return (types.literal(meth), types.int64, A1, A1, law_type(kind), A1, A1, A2, A1)


def derived_signature(kind: str) -> tuple:
    """The argument types of ``derived.derived_rows`` (rows, law data, which, out)."""
    return (A2, law_type(kind), types.int64, A1)


def cached(dispatcher, sig) -> bool:
    """Whether numba's cache holds ``dispatcher`` compiled for ``sig`` (its index has
    the key; a surprise in numba's private cache API counts as cached: no prefetch)."""
    try:
        cache = dispatcher._cache
        key = cache._index_key(sig, dispatcher.targetctx.codegen())
        return key in cache._cache_file._load_index()
    except Exception:
        return True


def main(meth: int, kind: str) -> None:
    attractor.on_event.compile(search_signature(meth, kind))
    derived.derived_rows.compile(derived_signature(kind))


if __name__ == "__main__":
    main(int(sys.argv[1]), sys.argv[2])
