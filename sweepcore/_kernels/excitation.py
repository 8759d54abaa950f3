"""The excitation's interface: what the forced kernels know of the excitation.

Which excitation is a *kind* of the excitation table (``excitations/__init__.py``),
and its data is the value ``ex`` that the forced kernels carry beside the parameter
row: a namedtuple whose class names the kind, as the friction law's ``lw``
(``law.py``). Each function below resolves, when it is compiled, to the kind module's
function of that name, by the class of ``ex``; nothing outside the excitation
modules tests the kind or reads an excitation column (a test checks it).

A kind module defines

* ``coefficients(ex, p)``: ``(a, b, Omega)``: the excitation is the force
  ``a cos(Omega t) + b sin(Omega t)`` [kN] on the slider, Omega [rad/s];
* ``forcing_period(ex, p)``: its period [s].
"""
import inspect

from numba import types
from numba.core.errors import TypingError
from numba.extending import overload

from .jit import OVERLOAD_OPTIONS


def _implementation(stub, ex):
    from .excitations import MODULES
    if not isinstance(ex, types.BaseNamedTuple) or ex.instance_class not in MODULES:
        raise TypingError(f"{stub.__name__}: excitation data must be an excitation "
                          f"table's data class (excitations.EXCITATIONS), got {ex}")
    fn = getattr(MODULES[ex.instance_class], stub.__name__)
    return getattr(fn, "py_func", fn)


def interface(stub):
    """Declare ``stub`` an excitation function resolved by the class of ``ex``."""
    at = list(inspect.signature(stub).parameters).index("ex")

    def typer(*args):
        return _implementation(stub, args[at])
    typer.__signature__ = inspect.signature(stub)
    overload(stub, inline="always", jit_options=OVERLOAD_OPTIONS)(typer)
    return stub


@interface
def coefficients(ex, p):
    """``(a, b, Omega)`` of the load ``a cos(Omega t) + b sin(Omega t)`` [kN]."""


@interface
def forcing_period(ex, p):
    """The forcing period [s]."""
