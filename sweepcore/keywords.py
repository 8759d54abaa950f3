"""Names a user types: "did you mean" for a misspelt one, and public functions that
refuse an unknown keyword by name (:func:`checked_keywords`).

Apart from :mod:`sweepcore.options` (which re-exports them) because they need no
kernel: a command that only reads a result (``sweepcore info``) imports them
without numba.
"""
from __future__ import annotations

import difflib
import functools
import inspect


def suggestion(name: str, choices) -> str | None:
    """The choice a misspelt ``name`` most likely meant, or None.

    A choice the name starts with, or that starts with the name (``tolerance`` ->
    ``tol``, ``amp`` -> ``amplitude``; the longest such), else difflib's closest
    match (similarity >= 0.6). Leading dashes of options are not compared."""
    strip = {str(c).lstrip("-").lower(): str(c) for c in choices}
    low = str(name).lstrip("-").lower()
    prefixed = [c for c in strip if len(c) >= 2 and len(low) >= 3 and
                (low.startswith(c) or c.startswith(low))]
    if prefixed:
        return strip[max(prefixed, key=len)]
    close = difflib.get_close_matches(low, list(strip), n=1)
    return strip[close[0]] if close else None


def did_you_mean(name: str, choices, quote: str = "'") -> str:
    """``"; did you mean 'tol'?"`` for a misspelt ``name``, or ``""``."""
    best = suggestion(name, choices)
    return f"; did you mean {quote}{best}{quote}?" if best else ""


def _named(fn) -> list[str]:
    return [p.name for p in inspect.signature(fn).parameters.values()
            if p.name != "self" and p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)]


def checked_keywords(fn=None, *, options: bool = False, also=()):
    """Refuse an unknown keyword argument of a public function before it runs, with
    "did you mean" and the allowed names, as ``Params`` and ``Grid`` do.

    ``options=True``: the function passes ``**options`` on to :func:`make_options`,
    whose keywords (dt, max_steps, ...) it accepts too, so a typo is named as the
    caller's (``sweep(tolerance=...)``), not as an internal function's. ``also``:
    functions whose keywords ``fn`` forwards through ``**kwargs``. The signature is
    kept (``functools.wraps``)."""
    if fn is None:
        return functools.partial(checked_keywords, options=options, also=also)
    names = _named(fn)
    if options:
        from .options import make_options
        names += [n for n in _named(make_options) if n not in names]
    for other in also:
        names += [n for n in _named(other) if n not in names]
    known = set(names)
    owner = fn.__qualname__.removesuffix(".__init__")

    @functools.wraps(fn)
    def checked(*args, **kwargs):
        for key in kwargs:
            if key not in known:
                raise TypeError(f"{owner}() got an unexpected keyword argument {key!r}"
                                f"{did_you_mean(key, names)} (allowed: "
                                f"{', '.join(names)})")
        return fn(*args, **kwargs)
    return checked
