"""What every friction law of the Python side answers (the laws' common base).

A law is either the analytic family, whose parameters are keywords of ``Params`` and
axes of ``Grid`` (columns of the kernel rows, :mod:`sweepcore.laws.analytic`), or an
object given as ``law=`` (a :class:`~sweepcore.laws.table.TableLaw`, a
:class:`~sweepcore.laws.leine.LeineLaw`), whose data travel to the kernels as the
law data ``lw`` (``sweepcore/_kernels/law.py``).
"""
from __future__ import annotations

import math
import numbers

import numpy as np

from .._kernels import laws as _kernel_laws

# The magnitudes a law's numbers may have (nonzero ones) [kN, cm/s, s/cm]: the window
# in which a change of units of the paper's slider leaves its answers unchanged
# (sweepcore.law, "resolvable magnitudes"); beyond it the law's slopes and their
# products (F'^2/F'', the certificate's sums) overflow or lose every digit.
WINDOW = (1e-100, 1e100)


def _shown(value) -> str:
    """``repr`` of a value, or the size of a huge integer (its repr says nothing)."""
    if isinstance(value, numbers.Integral) and abs(int(value)).bit_length() > 64:
        return f"an integer of about 1e{int(abs(int(value)).bit_length() * 0.30103)}"
    return repr(value)


def real(name: str, value, unit: str, positive: bool = False, window: bool = False,
         shown=None, rule: str | None = None) -> float:
    """``value`` as a float, refused by ``name`` unless it is a real number (not a
    bool), finite in float64, > 0 if ``positive`` and, with ``window``, of a
    magnitude inside ``WINDOW``."""
    units = f" [{unit}]" if unit else ""
    rule = rule or f"a finite number{' > 0' if positive else ''}{units}"
    bad = ValueError(f"{name} must be {rule}, got {_shown(value if shown is None else shown)}")
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise bad
    try:
        x = float(value)
    except (OverflowError, ValueError):
        raise bad from None
    if not math.isfinite(x) or (positive and not x > 0.0):
        raise bad
    if window:
        magnitude_window(name, np.array([x]), unit)
    return x


def magnitude_window(name: str, a: np.ndarray, unit: str) -> None:
    """Refuse an array whose nonzero magnitudes leave ``WINDOW``, by name."""
    mag = np.abs(a[a != 0.0])
    out = mag[(mag < WINDOW[0]) | (mag > WINDOW[1])]
    if out.size:
        raise ValueError(f"{name} holds {float(out[0])!r}{' ' + unit if unit else ''}: "
                         f"magnitudes from {WINDOW[0]:g} to {WINDOW[1]:g} (or 0) are "
                         "resolved; choose units in which they are moderate")


def check_name(name) -> str:
    """A law's label: a non-empty str without NUL (netCDF strings end at one)."""
    if not isinstance(name, str) or not name.strip() or "\x00" in name:
        raise ValueError(f"name must be a non-empty string without NUL characters, "
                         f"got {name!r}")
    return name


class FrictionLaw:
    """Base of the friction laws given as objects (``law=``).

    Subclasses set ``kind`` (a name of the kernels' law table,
    ``sweepcore._kernels.laws.LAWS``) and define :meth:`data`, :meth:`force`,
    :meth:`static_limits` and :meth:`slope_scale`. A law object is immutable and
    picklable (dask ships it to workers with the grid).
    """

    kind: str = ""
    name: str = ""
    # the keys of a study file's [law] table besides kind and name: "number" (> 0)
    # or "path" (relative to the study file), "... required" where it must be given
    STUDY_KEYS: dict = {}

    @classmethod
    def from_study(cls, values: dict):
        """The law of a study's validated ``[law]`` table (``sweepcore.study_law``)."""
        return cls(**values)

    # ---- the kernels' view
    def data(self):
        """The law data for the kernels (an instance of the kind's data class)."""
        raise NotImplementedError

    def kernel_groups(self, P: np.ndarray):
        """``[(kind code, row indices, law data)]`` of the rows P: one group."""
        return [(_kernel_laws.KIND_CODES[self.kind], np.arange(P.shape[0]), self.data())]

    def missing_column(self, name: str, P: np.ndarray):
        """The kernel row's column of analytic parameter ``name``, not given:
        unused by a law object (NaN: any use would show)."""
        return np.nan

    def closed_form(self, P: np.ndarray) -> np.ndarray:
        """Rows whose sliding field is linear (method "exact"): none."""
        return np.zeros(P.shape[0], bool)

    def closed_form_grid(self, where) -> str:
        """Why not every point of ``where`` (a Params or Grid) has a closed form ("":
        every one has)."""
        return f"the law {self.name!r} ({self.kind}) has none"

    def fingerprint(self) -> bytes:
        """Bytes that identify the law exactly (a resumed sweep's grid match)."""
        raise NotImplementedError

    # ---- the Python side's view
    def force(self, zdot, phase=None) -> np.ndarray:
        """Friction force F(zdot) [kN] while sliding; ``phase`` the sign of zdot (at
        zdot = 0: the side's limit)."""
        raise NotImplementedError

    def static_limits(self) -> tuple[float, float]:
        """``(r_pos, r_neg)`` [kN]: a stuck slider holds while ``-r_pos <= k x + c v
        <= r_neg``."""
        raise NotImplementedError

    def static_bound(self, P: np.ndarray) -> np.ndarray:
        """The larger static limit [kN] of every row (the length scale's offset)."""
        return np.full(P.shape[0], max(self.static_limits()))

    def slope_scale(self, P: np.ndarray) -> np.ndarray:
        """An upper bound of |F'| [kN s/cm] at every row's speeds (the resolvable-
        magnitude rule of :func:`sweepcore.law.unresolvable`)."""
        raise NotImplementedError

    def conservative(self, P: np.ndarray) -> np.ndarray:
        """Rows whose sliding field is conservative (the kernels' ``conservative``:
        neutral circles, exact touches); none for a law that damps or drives."""
        return np.zeros(np.atleast_2d(P).shape[0], bool)

    def attrs(self) -> dict:
        """Attributes that describe the law in a result file."""
        return {"law": self.name, "law_kind": self.kind}

    def table(self):
        """``(speed, force)`` arrays the law was given as, or None."""
        return None

    def speed_span(self) -> tuple[float, float]:
        """``(lo, hi)`` [cm/s]: the relative speeds where the law is known (a table's
        range; beyond it a table holds its end forces); every speed for a formula."""
        return -np.inf, np.inf

    def describe(self) -> str:
        """One line for summaries (the command line's "slider:" line)."""
        return f"law {self.name!r} ({self.kind})"

    def __repr__(self) -> str:
        return f"{type(self).__name__}(name={self.name!r})"
