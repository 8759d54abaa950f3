"""Friction laws: the analytic family (keywords) and laws given as objects (``law=``).

The Python side's law table: each row is a law class and the kernels' kinds it runs
on (``sweepcore._kernels.laws.LAWS``, one kernel module per kind). The analytic
family's parameters are keywords of ``Params`` and axes of ``Grid``; a law object
(:class:`TableLaw`, :class:`LeineLaw`) is given as ``Params(..., law=...)`` or
``Grid(..., law=[...])`` (a ``law`` dimension labelled by the laws' names).
"""
from .analytic import ANALYTIC, AnalyticLaw
from .base import FrictionLaw
from .leine import LeineLaw
from .table import TableLaw

# law class, the kernel kinds it runs on
LAWS = (
    (AnalyticLaw, ("polynomial", "stribeck")),
    (TableLaw, ("table",)),
    (LeineLaw, ("leine",)),
)
OBJECTS = tuple(cls for cls, _kinds in LAWS if cls is not AnalyticLaw)
LAW_DIM = "law"         # the dimension of a sweep over several law objects

__all__ = ["ANALYTIC", "AnalyticLaw", "FrictionLaw", "LAWS", "LAW_DIM", "OBJECTS",
           *(cls.__name__ for cls in OBJECTS)]
