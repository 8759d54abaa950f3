"""The excitation table: the kinds of external excitation the kernels know, one
module each.

A row is ``(name, data class, module, sample)``, as the law table's
(``laws/__init__.py``): the data class (a namedtuple) is the type of the excitation
data ``fx`` that the kernels carry beside the law's, and ``excitation.py``'s
interface resolves each excitation function to the row's module by it (or to its
generic form, a periodic load's). The per-point parameters (F0, Omega, phi, Y0) are
columns of the row, read by the kind modules only.

* ``none``: no excitation, the autonomous belt: its closed forms and stop rules.
* ``periodic``: a periodic load (its shape's harmonics as data) on the slider and a
  harmonic motion of the anchor.
"""
from ..jit import kernel
from . import none, periodic

EXCITATIONS = (
    ("none", none.Unforced, none, none.Unforced()),
    ("periodic", periodic.Periodic, periodic, periodic.sample()),
)
MODULES = {row[1]: row[2] for row in EXCITATIONS}
KIND_CODES = {row[0]: i for i, row in enumerate(EXCITATIONS)}
SAMPLES = {row[0]: row[3] for row in EXCITATIONS}
UNFORCED = none.Unforced()


@kernel(inline="always")
def autonomous():
    """The data of the excitation ``none``: the autonomous belt's searches (the
    Poincare section's, the cycle scan) run over the driver with it."""
    return none.Unforced()
