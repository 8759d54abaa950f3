"""The excitation table: the kinds of external excitation the kernels know, one
module each.

A row is ``(name, data class, module, sample)``, as the law table's
(``laws/__init__.py``): the data class (a namedtuple) is the type of the excitation
data ``ex`` that the forced kernels carry beside the parameter row, and
``excitation.py``'s interface resolves each excitation function to the row's module
by it. The per-point parameters (F0, Omega, phi, Y0) are columns of the row, read by
the kind modules only.

* ``none``: no excitation. The kernels of the autonomous belt serve it, unchanged
  (``entries.py``'s attractor, cycle and trajectory kernels); its module says so.
* ``harmonic``: a harmonic load on the slider and a harmonic motion of the anchor of
  spring and damper, which enter the slider's equation as one harmonic force.
"""
from . import harmonic, none

EXCITATIONS = (
    ("none", none.Unforced, none, none.Unforced()),
    ("harmonic", harmonic.Harmonic, harmonic, harmonic.Harmonic()),
)
MODULES = {row[1]: row[2] for row in EXCITATIONS}
KIND_CODES = {row[0]: i for i, row in enumerate(EXCITATIONS)}
SAMPLES = {row[0]: row[3] for row in EXCITATIONS}
