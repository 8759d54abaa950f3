"""Pictures of results: the plotting API of sweepcore.

Every function builds a :class:`matplotlib.figure.Figure` directly (no pyplot, no
global state, no display needed) and returns it; :func:`save` writes a PNG
atomically. :func:`plot_result` picks the natural picture of any result:

* a simulation (has a ``time`` dimension): :func:`plot_trajectory`, the paper's
  Fig. 3 layout, time histories of z, zdot, x, xdot and the phase planes (z, zdot)
  and (x, xdot); simulations stacked along a parameter: :func:`plot_cases`, one row
  of x(t), xdot(t), (x, xdot) each (the paper's Fig. 5 layout);
* a 1-D sweep: :func:`plot_lines`, amplitude and mean against the swept parameter
  (a second axis of at most four values, or a categorical one, gives one series per
  value);
* a 2-D sweep: :func:`plot_map`, the regime as a categorical map with a legend, the
  amplitude map, the analytic Hopf speed v* drawn over both, and the measured
  boundaries of :mod:`sweepcore.boundary` when they can be computed; a third swept
  axis of at most six values gives one row of maps per value;
* basin fractions (:func:`sweepcore.basin_stability`): :func:`plot_basins`;
* a forced response map (F0 or Y0 given): :func:`plot_forced_map`, stops and
  sticks per period as categorical maps and the amplitude; a frequency-response
  curve: :func:`plot_frequency_response`; a stroboscopic diagram:
  :func:`plot_stroboscopic`; a branch of responses (``sweepcore.follow_response``):
  :func:`plot_branch`, unstable stretches dashed, special points marked; a forced
  boundary file: :func:`plot_forced_boundaries` (also over a map:
  ``plot_forced_map(..., boundaries=)``);
* a bifurcation diagram: :func:`plot_diagram`, or :func:`plot_hysteresis` (stable
  branches solid, unstable slip cycles dashed) where it has unstable cycles;
  located boundaries: :func:`plot_boundaries`; any other 1-D file: its variables
  against its axis.

:func:`plot_friction` draws the friction law (the paper's Fig. 4), :func:`map_panel`
one map into a given axes. Axis labels carry the units of the data (kN, cm, s);
geometric axes are drawn on a log scale.

Rooms: ``style`` (colours, labels, save), ``maps``, ``lines``, ``trajectories``,
``friction``, ``forced``, ``basins``, ``boundaries`` (diagrams and boundary curves),
``branches`` (hysteresis), ``result`` (the choice of picture).
"""
from .basins import plot_basins
from .boundaries import plot_boundaries, plot_diagram
from .forced import (plot_branch, plot_forced_boundaries, plot_forced_map,
                     plot_frequency_response, plot_stroboscopic)
from .branches import plot_hysteresis
from .friction import plot_friction
from .lines import plot_lines
from .maps import map_panel, plot_map
from .result import plot_result
from .style import (REGIME_COLOURS, fixed_parameters, flag_axis, is_geometric, label,
                    pretty_units, save)
from .trajectories import plot_cases, plot_trajectory

__all__ = ["plot_result", "plot_map", "plot_lines", "plot_trajectory", "plot_cases",
           "plot_friction", "plot_basins", "plot_diagram", "plot_hysteresis",
           "plot_boundaries", "plot_forced_map", "plot_frequency_response",
           "plot_stroboscopic", "plot_branch", "plot_forced_boundaries", "map_panel", "save", "REGIME_COLOURS", "fixed_parameters",
           "flag_axis", "is_geometric", "label", "pretty_units"]
