"""sweepcore: parameter sweeps of the stick-slip friction oscillator (Liu's model).

Units throughout: force kN, length cm, time s (mass kN s^2/cm).

Public API::

    Params, simulate, attractor, Attractor, Grid, sweep, estimate, SweepTooLarge,
    hopf_boundary,
    locate_boundaries, continue_boundary, bifurcation_diagram, slip_cycles,
    basin_stability, frequency_response, stroboscopic_diagram,
    open_result, write_netcdf, check_cf,
    plot_result, plot_map, plot_lines, plot_trajectory, plot_cases, plot_friction,
    plot_diagram, plot_hysteresis, plot_boundaries, plot_basins, plot_forced_map,
    plot_frequency_response, plot_stroboscopic

The plotting functions are those of :mod:`sweepcore.plot` (each returns a
matplotlib Figure; ``sweepcore.plot.save`` writes one as PNG). They are imported
on first use, so ``import sweepcore`` does not import matplotlib.
"""
from .attractor import Attractor, attractor
from .basins import basin_stability
from .boundaries import continue_boundary, locate_boundaries
from .boundary import hopf_boundary
from .cycles import slip_cycles
from .diagram import bifurcation_diagram
from .grid import Grid
from .io import check_cf, open_result, write_netcdf
from .labels import version as _version
from .laws import OBJECTS as _LAW_CLASSES
from .params import Params
from .simulate import simulate
from .response_curves import frequency_response, stroboscopic_diagram
from .sizing import SweepTooLarge, estimate
from .sweep import sweep

__version__ = _version()
# the friction laws given as objects (law=): every class of the law table
# (sweepcore.laws.LAWS), by its name: sweepcore.TableLaw, sweepcore.LeineLaw, ...
LAWS = tuple(cls.__name__ for cls in _LAW_CLASSES)
globals().update({cls.__name__: cls for cls in _LAW_CLASSES})

PLOTS = ("plot_result", "plot_map", "plot_lines", "plot_trajectory", "plot_cases",
         "plot_friction", "plot_diagram", "plot_hysteresis", "plot_boundaries",
         "plot_basins", "plot_forced_map", "plot_frequency_response", "plot_stroboscopic")

__all__ = ["Params", "simulate", "attractor", "Attractor", "Grid", "sweep", "estimate",
           "SweepTooLarge",
           "hopf_boundary", "locate_boundaries", "continue_boundary",
           "bifurcation_diagram", "slip_cycles", "basin_stability", "frequency_response",
           "stroboscopic_diagram",
           "open_result", "write_netcdf", "check_cf", *PLOTS, *LAWS,
           "__version__"]


def __getattr__(name):
    # PEP 562: the plotting API from sweepcore.plot, imported (with matplotlib) on
    # first use only
    if name in PLOTS:
        from . import plot
        return getattr(plot, name)
    from .options import did_you_mean
    raise AttributeError(f"module 'sweepcore' has no attribute {name!r}"
                         f"{did_you_mean(name, __all__)}")


def __dir__():
    return sorted(set(globals()) | set(PLOTS))
