"""sweepcore: parameter sweeps of the stick-slip friction oscillator (Liu's model).

Units throughout: force kN, length cm, time s (mass kN s^2/cm).

Public API::

    Params, simulate, attractor, Attractor, Grid, sweep, estimate, SweepTooLarge,
    hopf_boundary,
    locate_boundaries, continue_boundary, bifurcation_diagram, slip_cycles,
    basin_stability,
    open_result, write_netcdf, check_cf
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
from .params import Params
from .simulate import simulate
from .sizing import SweepTooLarge, estimate
from .sweep import sweep

__version__ = _version()

__all__ = ["Params", "simulate", "attractor", "Attractor", "Grid", "sweep", "estimate",
           "SweepTooLarge",
           "hopf_boundary", "locate_boundaries", "continue_boundary",
           "bifurcation_diagram", "slip_cycles", "basin_stability", "open_result", "write_netcdf", "check_cf", "__version__"]
