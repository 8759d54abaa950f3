"""What every friction law of the Python side answers (the laws' common base).

A law is either the analytic family, whose parameters are keywords of ``Params`` and
axes of ``Grid`` (columns of the kernel rows, :mod:`sweepcore.laws.analytic`), or an
object given as ``law=`` (a :class:`~sweepcore.laws.table.TableLaw`, a
:class:`~sweepcore.laws.leine.LeineLaw`), whose data travel to the kernels as the
law data ``lw`` (``sweepcore/_kernels/law.py``).
"""
from __future__ import annotations

import numpy as np

from .._kernels import laws as _kernel_laws


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

    def describe(self) -> str:
        """One line for summaries (the command line's "slider:" line)."""
        return f"law {self.name!r} ({self.kind})"

    def __repr__(self) -> str:
        return f"{type(self).__name__}(name={self.name!r})"
