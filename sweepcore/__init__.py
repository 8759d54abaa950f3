"""sweepcore: parameter sweeps of the stick-slip friction oscillator (Liu's model).

Units throughout: force kN, length cm, time s (mass kN s^2/cm).

Public API::

    Params, simulate, attractor, Attractor, Grid, sweep, estimate, SweepTooLarge,
    hopf_boundary,
    locate_boundaries, continue_boundary, bifurcation_diagram, slip_cycles,
    basin_stability, frequency_response, stroboscopic_diagram, follow_response,
    open_result, write_netcdf, check_cf, compile,
    plot_result, plot_map, plot_lines, plot_trajectory, plot_cases, plot_friction,
    plot_diagram, plot_hysteresis, plot_boundaries, plot_basins, plot_forced_map,
    plot_frequency_response, plot_stroboscopic, plot_branch, plot_forced_boundaries,
    TableLaw, LeineLaw (every law class of ``sweepcore.laws.LAWS``),
    PeriodicLoad (every load class of ``sweepcore.excitations.LOADS``)

Every name is imported on first use (PEP 562): ``import sweepcore`` imports
neither numba nor matplotlib, so the command line's ``--help`` answers at once.
The plotting functions are those of :mod:`sweepcore.plot` (each returns a
matplotlib Figure; ``sweepcore.plot.save`` writes one as PNG).

Kernels compile on first use of each method and law kind (per install location)
and are cached; each compilation is announced on stderr (a warning of the logger
``"sweepcore.compile"``; ``logging.getLogger("sweepcore.compile").setLevel(
logging.ERROR)`` silences it). :func:`compile` compiles ahead of time.
"""
import importlib
import importlib.util
import sys
import types

# name -> the module that defines it
_WHERE = {
    "Attractor": ".attractor", "attractor": ".attractor",
    "basin_stability": ".basins",
    "continue_boundary": ".boundaries", "locate_boundaries": ".boundaries",
    "hopf_boundary": ".boundary",
    "slip_cycles": ".cycles",
    "bifurcation_diagram": ".diagram",
    "Grid": ".grid",
    "compile": ".compiled",
    "check_cf": ".io", "open_result": ".io", "write_netcdf": ".io",
    "Params": ".params",
    "simulate": ".simulate",
    "SweepTooLarge": ".sizing", "estimate": ".sizing",
    "sweep": ".sweep",
    "frequency_response": ".response_curves", "stroboscopic_diagram": ".response_curves",
    "follow_response": ".continuation",
}
PLOTS = ("plot_result", "plot_map", "plot_lines", "plot_trajectory", "plot_cases",
         "plot_friction", "plot_diagram", "plot_hysteresis", "plot_boundaries",
         "plot_basins", "plot_forced_map", "plot_frequency_response", "plot_stroboscopic",
         "plot_branch", "plot_forced_boundaries")
_NAMES = ["Params", "simulate", "attractor", "Attractor", "Grid", "sweep", "estimate",
          "SweepTooLarge",
          "hopf_boundary", "locate_boundaries", "continue_boundary",
          "bifurcation_diagram", "slip_cycles", "basin_stability", "frequency_response",
          "stroboscopic_diagram", "follow_response",
          "open_result", "write_netcdf", "check_cf", "compile", *PLOTS]


def _law_classes() -> dict:
    """The friction laws given as objects (law=): every class of the law table
    (sweepcore.laws.LAWS), by its name: sweepcore.TableLaw, sweepcore.LeineLaw, ..."""
    from .laws import OBJECTS
    return {cls.__name__: cls for cls in OBJECTS}


def _load_classes() -> dict:
    """The load objects' classes (load=): every class of the excitation table
    (sweepcore.excitations.LOADS), by its name: sweepcore.PeriodicLoad, ..."""
    from .excitations import LOADS
    return {cls.__name__: cls for cls in LOADS}


def __getattr__(name):
    # PEP 562: every public name imported on first use
    if name in _WHERE:
        value = getattr(importlib.import_module(_WHERE[name], __name__), name)
    elif name in PLOTS:
        from . import plot
        value = getattr(plot, name)
    elif name == "LAWS":
        value = tuple(_law_classes())
    elif name == "__all__":
        value = [*_NAMES, *_law_classes(), *_load_classes(), "__version__"]
    elif name == "__version__":
        from .labels import version
        value = version()
    elif name in (laws := _law_classes()):
        value = laws[name]
    elif name in (loads := _load_classes()):
        value = loads[name]
    elif not name.startswith("_") and importlib.util.find_spec(f"{__name__}.{name}"):
        value = importlib.import_module(f".{name}", __name__)   # a subpackage, as scipy's
    else:
        from .options import did_you_mean
        raise AttributeError(f"module 'sweepcore' has no attribute {name!r}"
                             f"{did_you_mean(name, __getattr__('__all__'))}")
    if name not in _SHADOWED:
        globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__getattr__("__all__")))


# A function named as its module (sweepcore.attractor, .simulate, .sweep): once the
# module is imported, Python sets the package's attribute to the module; the
# package's attribute is the function, as the API says.
_SHADOWED = {"attractor", "simulate", "sweep"}


class _Package(types.ModuleType):
    def __getattribute__(self, name):
        value = super().__getattribute__(name)
        if name in _SHADOWED and isinstance(value, types.ModuleType):
            value = getattr(value, name)
        return value


sys.modules[__name__].__class__ = _Package
