"""No excitation: the autonomous belt (its rows run on the autonomous kernels)."""
from .._kernels.excitations import none as _kernel

NAME = "none"
DATA = _kernel.Unforced()
