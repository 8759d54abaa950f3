"""What every picture shares: regime colours, symbols, axis labels with units,
log axes for geometric sweeps, titles, and the atomic PNG writer :func:`save`."""
from __future__ import annotations

import os
import uuid
from pathlib import Path

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

from .._kernels import codes
from ..labels import is_geometric  # noqa: F401  (re-exported by sweepcore.plot)

# colour-blind-safe (Okabe-Ito) colours, one per regime code
REGIME_COLOURS = {
    codes.R_EQUILIBRIUM: "#56B4E9",    # sky blue: steady sliding
    codes.R_SLIP_CYCLE: "#E69F00",     # orange: cycle that never sticks
    codes.R_STICK_SLIP: "#D55E00",     # vermillion: stick-slip cycle
    codes.R_NEUTRAL: "#009E73",        # green: neutral circle (constant friction)
    codes.R_STUCK: "#999999",          # grey
    codes.R_UNBOUNDED: "#CC79A7",      # purple
    codes.R_UNCONVERGED: "#F0E442",    # yellow
    codes.R_FAILED: "#000000",         # black
}

SYMBOLS = {
    "m": "m", "k": "k", "r_y": "r_y", "v": "v", "alpha1": r"\alpha_1",
    "alpha2": r"\alpha_2", "x0": "x_0", "xdot0": r"\dot{x}_0", "x": "x",
    "xdot": r"\dot{x}", "z": "z", "zdot": r"\dot{z}", "time": "t", "r_a": "r_a",
    "amplitude": "A", "mean": r"\bar{x}", "velocity_amplitude": r"A_{\dot{x}}",
    "cycle_size": "R", "period": "T", "q": "q", "v_star": "v^*", "x_eq": "x_{eq}",
    "omega": r"\omega", "c": "c", "r_k": "r_k", "v_s": "v_s",
    "F0": "F_0", "Omega": r"\Omega", "phi": r"\varphi", "Y0": "Y_0",
}
# the excitation's terms in a title carry their units: rad/s and rad are the ones a
# reader could take for Hz or degrees
EXCITATION_UNITS = {"F0": "kN", "Omega": "rad/s", "phi": "rad", "Y0": "cm"}

DPI = 150


# ------------------------------------------------------------------- labels
def pretty_units(units: str | None) -> str:
    """UDUNITS string to a label: ``"kN s3 cm-3"`` -> ``kN s$^3$/cm$^3$``.

    ``"1"`` and empty units give ``""`` (dimensionless); a CF time unit
    ``"seconds since <epoch>"`` gives ``s`` (a simulation's elapsed time).
    """
    if not units or units.strip() == "1":
        return ""
    if " since " in units:
        return "s" if units.split()[0] in ("s", "sec", "second", "seconds") else \
            units.split()[0]
    num, den = [], []
    for tok in units.split():
        base = tok.rstrip("-0123456789")
        power = tok[len(base):]
        p = int(power) if power not in ("", "-") else 1
        (num if p > 0 else den).append(base + (f"$^{abs(p)}$" if abs(p) != 1 else ""))
    text = " ".join(num) if num else "1"
    if den:
        text += "/" + (den[0] if len(den) == 1 else "(" + " ".join(den) + ")")
    return text


def label(var, name: str | None = None) -> str:
    """Axis label ``long name $symbol$ [units]`` of a DataArray or Variable."""
    name = name if name is not None else getattr(var, "name", None)
    attrs = getattr(var, "attrs", {})
    text = attrs.get("long_name", str(name))
    if name in SYMBOLS:
        text += f" ${SYMBOLS[name]}$"
    units = pretty_units(attrs.get("units"))
    return f"{text} [{units}]" if units else text


def flag_axis(ax, var, axis: str = "y") -> bool:
    """Label a categorical (flag) variable's axis with its names, not its codes.

    Every code of the variable's ``flag_values`` gets a tick named by its
    ``flag_meanings`` word (underscores as spaces), so that regime and status axes
    read "stick slip", "equilibrium", ... Returns False (axis untouched) for a
    variable that is not a flag variable.
    """
    attrs = getattr(var, "attrs", {})
    if "flag_values" not in attrs or "flag_meanings" not in attrs:
        return False
    values = [int(v) for v in np.atleast_1d(attrs["flag_values"])]
    names = [w.replace("_", " ") for w in str(attrs["flag_meanings"]).split()]
    set_ticks = ax.set_yticks if axis == "y" else ax.set_xticks
    set_lim = ax.set_ylim if axis == "y" else ax.set_xlim
    set_ticks(values, names[:len(values)])
    set_lim(min(values) - 0.5, max(values) + 0.5)
    return True


def axis_scale(ds: xr.Dataset, dim: str) -> str:
    spacing = ds[dim].attrs.get("spacing")
    if spacing is not None:
        return "log" if spacing == "geometric" else "linear"
    return "log" if is_geometric(ds[dim].values) else "linear"


def fixed_parameters(ds: xr.Dataset) -> str:
    """``m = 5, k = 50, ...`` for the 0-d coordinates (the fixed parameters)."""
    parts = []
    for name in ("m", "k", "r_y", "v", "alpha1", "alpha2", "c", "r_k", "v_s", "x0",
                 "xdot0"):
        if name in ds.coords and ds[name].ndim == 0:
            if name == "c" and float(ds[name]) == 0.0:
                continue                      # no damping: the paper's slider
            if name == "r_k" and "r_y" in ds.coords and ds["r_y"].ndim == 0 \
                    and float(ds["r_k"]) == float(ds["r_y"]):
                continue                      # no Stribeck term: eq. (40)
            parts.append(f"${SYMBOLS[name]}$ = {float(ds[name]):.4g}")
    fixed = {n: float(ds[n]) for n in EXCITATION_UNITS
             if n in ds.coords and ds[n].ndim == 0}
    swept = [n for n in ("F0", "Y0") if n in ds.coords and ds[n].ndim > 0]
    excitation = excitation_text(fixed, forced=bool(swept))
    if excitation:
        parts.append(excitation)
    if "xdot0" not in ds.coords and "x0" in ds.coords:
        parts.append("start stuck")
    return ", ".join(parts)


def excitation_text(values: dict, forced: bool = False) -> str:
    r"""``$F_0$ = 1 kN, $\Omega$ = 0.8 rad/s`` of an excitation's fixed terms
    (``{name: value}``), or "" without one: a term that is 0 is left out, and
    Omega is named only where a load or an anchor motion (``forced``: swept) acts."""
    acting = [values.get(n, 0.0) for n in ("F0", "Y0")]
    if not (forced or any(np.isfinite(v) and v != 0.0 for v in acting)):
        return ""
    return ", ".join(f"${SYMBOLS[n]}$ = {v:.4g} {EXCITATION_UNITS[n]}"
                     for n, v in values.items()
                     if np.isfinite(v) and (n == "Omega" or v != 0.0))


def fmt(value) -> str:
    """A coordinate value for a title: numbers with 4 digits, strings as they are."""
    v = np.asarray(value).item()
    return f"{v:.4g}" if isinstance(v, (int, float)) else str(v)


def regime_codes(ds: xr.Dataset) -> tuple[list, list]:
    attrs = ds["regime"].attrs
    values = [int(x) for x in np.atleast_1d(attrs.get("flag_values",
                                                      sorted(codes.REGIME_NAMES)))]
    names = attrs.get("flag_meanings", " ".join(codes.REGIME_NAMES[k] for k in values))
    return values, names.split()


def sweep_title(ds: xr.Dataset) -> str:
    """Study title (or the file's title) over the fixed parameters."""
    head = ds.attrs.get("study_title") or ds.attrs.get("title", "sweep")
    return f"{head}\n{fixed_parameters(ds)}"


# --------------------------------------------------------------------- save
def save(fig: Figure, path, dpi: int = DPI) -> Path:
    """Write ``fig`` as PNG to ``path`` atomically (temporary file, then rename)."""
    path = Path(path)
    tmp = path.parent / f".{path.name}.{uuid.uuid4().hex}.tmp.png"
    try:
        fig.savefig(tmp, dpi=dpi, format="png")
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)
    return path
