"""What ``sweepcore`` prints about a result: ``info``'s summaries of sweeps,
simulations, boundaries and diagrams, and the lines ``run``, ``simulate`` and
``boundary`` print when they finish."""
from __future__ import annotations

import math
from collections import Counter

import numpy as np

from ..labels import parameter, run_dims, run_statuses, slider_parameters


# the heading of what `describe` summarises, by the file's sweepcore_kind
KINDS = {"frequency_response": "frequency-response curve",
         "stroboscopic_diagram": "stroboscopic diagram"}


def _units(var) -> str:
    u = var.attrs.get("units", "")
    return "" if u in ("", "1") else f" {u}"


def _flag_counts(da) -> list[tuple[str, int]]:
    values = np.atleast_1d(da.attrs.get("flag_values", []))
    names = str(da.attrs.get("flag_meanings", "")).split()
    counts = Counter(np.asarray(da.values).ravel().tolist())
    out = [(name, counts.pop(int(val), 0)) for val, name in zip(values, names)]
    out += [(f"code {code}", n) for code, n in sorted(counts.items())]
    return out


def regime_line(ds) -> str:
    """One line of regime counts, e.g. ``regime: equilibrium 120, stick_slip 80``."""
    if "regime" not in ds:
        return ""
    return "regime: " + ", ".join(f"{n} {c}" for n, c in _flag_counts(ds["regime"])
                                  if c)


def status_line(ds) -> str:
    """One line of status counts, e.g. ``status: ok 65526, unresolved 8``."""
    if "status" not in ds or "time" in ds.dims:
        return ""
    return "status: " + ", ".join(f"{n} {c}" for n, c in _flag_counts(ds["status"])
                                  if c)


def _grid_dims(ds) -> tuple:
    """The sweep's axes, in the grid's order (C order of its points): the dimensions
    of its per-point variables (not a measured law's samples, ``law_point``)."""
    for var in ("regime", "status", "amplitude"):
        if var in ds:
            return tuple(ds[var].dims)
    return tuple(ds.dims)


def forced_lines(ds) -> list[str]:
    """Counts of a forced response map's classes (Hong & Liu's: zero-duration stops
    and finite sticks per response period), e.g. ``stops per period: 0 120, 2 80``;
    none for an unforced result."""
    lines = []
    for var, what in (("stops_per_period", "zero-duration stops per period"),
                      ("sticks_per_period", "finite sticks per period")):
        if var not in ds or "time" in ds.dims:
            continue
        counts = Counter(np.asarray(ds[var].values).ravel().tolist())
        lines.append(f"{what}: " + ", ".join(
            f"{'none measured' if n < 0 else n} {c}" for n, c in sorted(counts.items())))
    if "multiplicity" in ds and "time" not in ds.dims:
        m = np.asarray(ds["multiplicity"].values).ravel()
        counts = Counter(int(n) for n in m[np.isfinite(m)])
        if counts:
            lines.append("multiplicity (response period / forcing period): " + ", ".join(
                f"{n} {c}" for n, c in sorted(counts.items())))
    return lines


def describe(ds) -> str:
    """Multi-line summary of a sweep or simulation Dataset (``sweepcore info``)."""
    if "time" in ds.dims:
        return _describe_simulation(ds)
    lines = []
    dims = _grid_dims(ds)
    size = int(np.prod([ds.sizes[d] for d in dims])) if dims else 1
    shape = " x ".join(f"{d}: {ds.sizes[d]}" for d in dims)
    kind = KINDS.get(ds.attrs.get("sweepcore_kind"), "sweep")
    lines.append(f"  {kind} of {size} points ({shape})")
    for key in ("study_title", "study_file"):
        if ds.attrs.get(key):
            lines.append(f"  {key.replace('_', ' ')}: {ds.attrs[key]}")
    lines.append("  axes:")
    for d in dims:
        c = ds[d]
        vals = c.values
        spacing = c.attrs.get("spacing", "")
        if vals.dtype.kind not in "iuf":        # a categorical axis (names)
            lines.append(f"    {d:8s} {vals.size} values: "
                         + ", ".join(str(v) for v in vals))
            continue
        name = f"{c.attrs.get('long_name', '')} [{c.attrs.get('units', '')}]"
        lines.append(f"    {d:8s} {name}: {vals.size} values in [{vals.min():.6g}, {vals.max():.6g}]"
                     + (f" ({spacing})" if spacing else ""))
    fixed = [n for n in ds.coords if ds[n].ndim == 0]
    if fixed:
        lines.append("  fixed: " + ", ".join(f"{n} = {float(ds[n]):.6g}{_units(ds[n])}"
                                             for n in fixed))
    if "initial_velocity" in ds.attrs:
        lines.append(f"  start: {ds.attrs['initial_velocity']}")
    lines.extend(_data_dims(ds, dims))
    for var in ("regime", "status"):
        if var in ds:
            lines.append(f"  {var} counts:")
            for name, count in _flag_counts(ds[var]):
                if count:
                    lines.append(f"    {name:22s} {count:9d}  ({100 * count / size:.3g} %)")
    if "converged" in ds:
        n = int(np.asarray(ds["converged"].values).sum())
        lines.append(f"  converged: {n} of {size} ({100 * n / size:.6g} %)")
    lines.extend(f"  {line}" for line in forced_lines(ds))
    for var in ("amplitude", "mean", "period"):
        if var in ds:
            vals = ds[var].values
            if np.isfinite(vals).any():
                lines.append(f"  {var}: [{np.nanmin(vals):.6g}, {np.nanmax(vals):.6g}]"
                             f"{_units(ds[var])}")
    lines.extend(_boundary_lines(ds))
    lines.append("  attributes:")
    for key in ("method", "tol", "max_steps", "max_periods", "dt", "graze",
                "Conventions", "source", "history"):
        if key in ds.attrs:
            text = str(ds.attrs[key]).replace("\n", "\n" + " " * 16)
            lines.append(f"    {key:12s}{text}")
    return "\n".join(lines)


def _data_dims(ds, dims) -> list[str]:
    """What each dimension of a result that is not a grid axis holds: a measured
    law's samples (``law_point``), a stroboscopic diagram's samples (``sample``)."""
    lines = []
    for d in ds.dims:
        if d in dims:
            continue
        names = ", ".join(n for n in ds.data_vars if d in ds[n].dims)
        if ds.attrs.get("sweepcore_kind") == "stroboscopic_diagram" and d == "sample":
            along = ds.attrs.get("along", "the parameter")
            when = ds["x"].attrs.get("comment") if "x" in ds else None
            what = (f"stroboscopic samples per value of {along} ({names} at t = j T: "
                    f"{when or 'T = 2 pi/Omega, the forcing period'})")
        elif d == "law_point":
            what = f"samples of the law's table ({names})"
        else:
            long_name = ds[d].attrs.get("long_name", d) if d in ds.coords else d
            what = f"values of {long_name} ({names})"
        lines.append(f"  {d}: {ds.sizes[d]} {what}")
    return lines


def _boundary_lines(ds) -> list[str]:
    if "v_hopf_measured" not in ds or "v_star" not in ds:
        return []
    measured = ds["v_hopf_measured"]
    ok = np.isfinite(measured.values)
    if not ok.any():
        return ["  measured Hopf boundary: no switch from a cycle to equilibrium"]
    vs = ds["v_star"]
    vs = vs.isel(v=0) if "v" in vs.dims else vs
    diff = (measured - vs).values
    sel = ok & np.isfinite(diff)
    sub = _subcritical(ds, measured)
    res = ds["v_hopf_resolution"].values[sel & ~sub] if "v_hopf_resolution" in ds \
        else None
    text = ""
    if (sel & ~sub).any():
        text = (f"  measured Hopf boundary: {int(ok.sum())} of {ok.size} rows switch; "
                f"|v_measured - v*| <= {np.max(np.abs(diff[sel & ~sub])):.3g} cm s-1"
                + (" where the Hopf point is supercritical" if sub.any() else ""))
        if res is not None and res.size:
            text += f" (grid resolution +-{np.max(res):.3g})"
    lines = [text] if text else []
    if (sel & sub).any():
        d = diff[sel & sub]
        lines.append(f"  measured boundary: {int(ok.sum())} of {ok.size} rows switch "
                     "from a cycle to equilibrium; where the Hopf point is subcritical "
                     f"({int((sel & sub).sum())} rows) v_measured - v* in "
                     f"[{d.min():.3g}, {d.max():.3g}] cm s-1: above v*, as it should "
                     "be, for from the stuck start the stick-slip cycle coexists with "
                     "steady sliding above v* up to its fold (sweepcore boundary "
                     "locates both)")
    return lines + _onset_lines(ds, vs)


def _subcritical(ds, measured) -> np.ndarray:
    """Where the Hopf point of a row of the measured boundary is subcritical (the
    file's first Lyapunov coefficient > 0), over the boundary's dimensions."""
    if "first_lyapunov" not in ds:
        return np.zeros(measured.shape, bool)
    l1 = ds["first_lyapunov"]
    l1 = l1.isel(v=0) if "v" in l1.dims else l1
    return (l1 > 0).broadcast_like(measured).transpose(*measured.dims).values


def _onset_lines(ds, vs) -> list[str]:
    """The measured stick onset (as a multiple of v*) and the reversal band's edges,
    each on the rows where the map holds it."""
    lines = []
    if "v_stick_onset" in ds:
        on = ds["v_stick_onset"].values
        ok = np.isfinite(on)
        ratio = (ds["v_stick_onset"] / vs).values[ok]
        lines.append(f"  measured stick onset: {int(ok.sum())} of {ok.size} rows"
                     + (f"; v_stick_onset / v* in [{ratio.min():.4g}, {ratio.max():.4g}]"
                        if ok.any() else ""))
    for edge in ("lower", "upper"):
        name = f"v_reversal_{edge}"
        if name in ds and np.isfinite(ds[name].values).any():
            val = ds[name].values[np.isfinite(ds[name].values)]
            lines.append(f"  reversal band, {edge} edge: {val.size} rows, "
                         f"[{val.min():.4g}, {val.max():.4g}] cm s-1")
    return lines


def _excitation_line(ds) -> list[str]:
    """A forced run's excitation and its frequency ratio beta = Omega/omega (none
    for an unforced run)."""
    if "external_force" not in ds:
        return []
    F0, Om, phi, Y0 = (parameter(ds, n) for n in ("F0", "Omega", "phi", "Y0"))
    omega = math.sqrt(parameter(ds, "k") / parameter(ds, "m"))
    return [f"  excitation: F0 = {F0:.6g} kN, Omega = {Om:.6g} rad s-1 (Omega/omega = "
            f"{Om / omega:.6g}, period {2 * math.pi / Om:.6g} s), phi = {phi:.6g} rad, "
            f"Y0 = {Y0:.6g} cm"]


def _describe_simulation(ds) -> str:
    a = ds.attrs
    t = ds.time.values
    lines = [f"  simulation: {t.size} samples over t in [{t[0]:.6g}, {t[-1]:.6g}] s",
             "  slider: " + ", ".join(f"{n} = {value:.6g}{_units(ds[n])}"
                                      if n in ds.coords else f"{n} = {value:.6g}"
                                      for n, value in slider_parameters(ds)),
             *_excitation_line(ds),
             f"  start: x0 = {parameter(ds, 'x0'):.6g} cm, "
             f"xdot0 = {parameter(ds, 'xdot0'):.6g} cm s-1",
             *_run_lines(ds)]
    if "event_kind" in ds:
        counts = [(n, c) for n, c in _flag_counts(ds["event_kind"]) if c]
        lines.append("  events: " + (", ".join(f"{n} {c}" for n, c in counts)
                                     if counts else "none"))
    if not run_dims(ds):
        lines.append(f"  x over the last 20 % of the run: {_tail_range(ds)}")
    if "history" in a:
        lines.append(f"  history: {a['history']}")
    return "\n".join(lines)


def _tail_range(ds) -> str:
    """The range of x over the last 20 % of one run [cm]."""
    t = ds.time.values
    x = ds.x.transpose("time", ...).values
    tail = (t >= t[-1] - 0.2 * (t[-1] - t[0])) & np.isfinite(x)
    if not tail.any():
        return "no valid sample (the run stopped early)"
    return f"[{x[tail].min():.6g}, {x[tail].max():.6g}] cm"


def _run_lines(ds) -> list[str]:
    """Method, status and steps of a simulation; one line per run for runs stacked
    along a parameter (the parameter's values, each run's status and, when the file
    holds them per run, its steps)."""
    a = ds.attrs
    dims = run_dims(ds)
    if not dims:
        return [f"  method: {a.get('method', '?')}, status: {a.get('status', '?')}, "
                f"steps: {a.get('n_steps', '?')}"]
    d = dims[0]
    statuses = run_statuses(ds)
    steps = ds["n_steps"].values if "n_steps" in ds.data_vars else [None] * ds.sizes[d]
    lines = [f"  {ds.sizes[d]} runs along {d} ({ds[d].attrs.get('units', '?')}), method: "
             f"{a.get('method', '?')}"]
    for i, value in enumerate(ds[d].values):
        status = statuses[i] if len(statuses) == ds.sizes[d] else "?"
        step = "" if steps[i] is None else f", steps: {int(steps[i])}"
        lines.append(f"    {d} = {value:.6g}: status: {status}{step}; x over the "
                     f"last 20 % of the run: {_tail_range(ds.isel({d: i}))}")
    return lines


def simulation_summary(ds, p) -> str:
    """Summary of a fresh simulation with the slider's analytic quantities."""
    law = "" if p.law is None else f"  {p.law.describe()}\n"
    hopf = (f"v* = {p.v_star:.6g} cm s-1 ({p.criticality} Hopf point)"
            if p.criticality != "none" and math.isfinite(p.v_star) else
            "no Hopf point (no belt speed where steady sliding loses stability)")
    return (_describe_simulation(ds) + "\n" + law +
            f"  analytic: omega = {p.omega:.6g} s-1, q = {p.q:.6g} s-1 (eq. 46), "
            f"{hopf}, x_eq = {p.x_eq:.6g} cm (eq. 43)")


def _axis_lines(ds, skip=()) -> list[str]:
    """One line per swept float axis (name, units, count, range) and the fixed
    parameters, for the summaries of results other than sweeps."""
    lines = []
    for d in ds.dims:
        if d not in skip and ds[d].dtype.kind == "f":
            v = ds[d].values
            lines.append(f"    {d:8s} {ds[d].attrs.get('long_name', '')} "
                         f"[{ds[d].attrs.get('units', '')}]: {v.size} values in "
                         f"[{v.min():.6g}, {v.max():.6g}]")
    fixed = [n for n in ds.coords if ds[n].ndim == 0]
    if fixed:
        lines.append("  fixed: " + ", ".join(f"{n} = {float(ds[n]):.6g}{_units(ds[n])}"
                                             for n in fixed))
    return lines


def describe_boundaries(ds) -> str:
    """``sweepcore info`` of a boundaries or bifurcation-diagram result."""
    kind = ds.attrs["sweepcore_kind"].replace("_", " ")
    shape = ", ".join(f"{d}: {n}" for d, n in ds.sizes.items())
    lines = [f"  {kind} ({shape})", *_axis_lines(ds)]
    lines.extend(boundary_lines(ds))
    for key in ("tol", "history"):
        if key in ds.attrs:
            text = str(ds.attrs[key]).replace("\n", "\n" + " " * 12)
            lines.append(f"  {key:9s} {text}")
    return "\n".join(lines)


def boundary_lines(ds) -> list[str]:
    """Summary of a boundaries or diagram result: what was located, against v*."""
    from ..boundaries import LOCATED
    if ds.attrs.get("sweepcore_kind") == "bifurcation_diagram":
        lines = ["  " + regime_line(ds)]
        for name in ("v_hopf", "v_stick_onset", "v_hopf_subcritical", "v_fold",
                     "v_star"):
            if name in ds:
                lines.append(f"  {name} = {float(ds[name]):.10g} cm s-1")
        return lines + jump_lines(ds)
    lines = []
    for name, status, width in (("v_hopf", "hopf_status", "v_hopf_error"),
                                ("v_stick_onset", "stick_status",
                                 "v_stick_onset_width")):
        ok = ds[status].values == LOCATED
        line = f"  {name}: located at {int(ok.sum())} of {ok.size} points"
        if ok.any():
            line += f", {width} <= {np.nanmax(ds[width].values[ok]):.2g}"
        lines.append(line)
    if "v_star" not in ds:      # searched along another parameter than v
        lines.append(f"  attractors computed: {int(ds['evaluations'].sum())}")
        return lines
    hopf = ds["hopf_status"].values == LOCATED
    if hopf.any():
        dv = np.abs(ds["v_hopf"] - ds["v_star"]).values[hopf]
        lines.append(f"  |v_hopf - v*| <= {dv.max():.3g} cm s-1")
    stick = ds["stick_status"].values == LOCATED
    if stick.any():
        r = (ds["v_stick_onset"] / ds["v_star"]).values[stick]
        line = f"  v_stick_onset / v* in [{r.min():.10f}, {r.max():.10f}]"
        if "v_stick_onset_estimate" in ds:     # the file's own averaging estimate
            est = (ds["v_stick_onset_estimate"] / ds["v_star"]).values[stick]
            line += f" (averaging sqrt(4/5) = {np.max(est):.10f})"
        lines.append(line)
    lines.extend(coexistence_lines(ds))
    lines.append(f"  attractors computed: {int(ds['evaluations'].sum())}")
    return lines


def coexistence_lines(ds) -> list[str]:
    """The ends of the unstable slip cycle of a boundaries result, where located."""
    from ..boundaries import LOCATED
    lines = []
    for name, status, width in (("v_hopf_subcritical", "subcritical_status",
                                 "v_hopf_subcritical_error"),
                                ("v_fold", "fold_status", "v_fold_width")):
        if status not in ds:
            continue
        ok = ds[status].values == LOCATED
        if ok.any():
            vals = ds[name].values[ok]
            lines.append(f"  {name}: located at {int(ok.sum())} of {ok.size} points, "
                         f"in [{vals.min():.10g}, {vals.max():.10g}] cm s-1, {width} "
                         f"<= {np.nanmax(ds[width].values[ok]):.2g}")
    return lines


def jump_lines(ds) -> list[str]:
    """The regime changes of each scan of a diagram, in the scan's direction."""
    from .._kernels import codes
    along = ds.attrs.get("along", "v")
    x = ds[along].values
    names = {int(k): n for k, n in codes.REGIME_NAMES.items()}
    lines = []
    for branch in ds.branch.values:
        reg = ds.regime.sel(branch=branch).values.astype(int)
        idx = range(len(x) - 1) if branch != "down" else range(len(x) - 2, -1, -1)
        for i in idx:
            a, b = (i, i + 1) if branch != "down" else (i + 1, i)
            if reg[a] != reg[b]:
                lines.append(f"  {branch} scan: {names.get(reg[a])} -> "
                             f"{names.get(reg[b])} between {along} = {x[a]:.6g} and "
                             f"{x[b]:.6g}")
    return lines


def describe_basins(ds) -> str:
    """``sweepcore info`` of a basin-stability result."""
    shape = ", ".join(f"{d}: {n}" for d, n in ds.sizes.items()
                      if d not in ("attractor", "cycle"))
    lines = [f"  basin stability ({shape or 'one point'})",
             *_axis_lines(ds, skip=("attractor", "cycle"))]
    lines.extend(basin_lines(ds))
    if "history" in ds.attrs:
        text = str(ds.attrs["history"]).replace("\n", "\n" + " " * 12)
        lines.append(f"  history   {text}")
    return "\n".join(lines)


def basin_lines(ds, table_rows: int = 12) -> list[str]:
    """The box, the routes and statuses, each attractor's range of fractions, and
    (one swept axis of at most ``table_rows`` values) the fractions point by point."""
    x0, xd0 = (np.atleast_1d(ds.attrs.get(k, [np.nan, np.nan]))
               for k in ("x0_range", "xdot0_range"))
    lines = [f"  box: x0 in [{x0[0]:.6g}, {x0[1]:.6g}] cm, xdot0 in [{xd0[0]:.6g}, "
             f"{xd0[1]:.6g}] cm s-1; route {ds.attrs.get('route', '?')}, samples "
             f"{ds.attrs.get('samples_requested', '?')} "
             f"({ds.attrs.get('sampling', '?')})"]
    for var in ("basin_route", "basin_status"):
        counts = [f"{n} {c}" for n, c in _flag_counts(ds[var]) if c]
        lines.append(f"  {var.split('_')[1]}: " + ", ".join(counts))
    names = [str(n) for n in ds["attractor"].values]
    f, e = ds["basin_fraction"], ds["basin_fraction_error"]
    for name in names:
        vals = f.sel(attractor=name).values
        if np.isfinite(vals).any():
            lines.append(f"  {name}: fraction in [{np.nanmin(vals):.6g}, "
                         f"{np.nanmax(vals):.6g}], error <= "
                         f"{np.nanmax(e.sel(attractor=name).values):.2g}")
    if "cycle_stability" in ds:
        unstable = (ds["cycle_stability"] == 1).any("cycle")
        line = (f"  unstable slip cycles (basin boundaries) at {int(unstable.sum())} of "
                f"{unstable.size} points")
        mu = ds["cycle_floquet"].where(ds["cycle_stability"] == 1).values
        if np.isfinite(mu).any():
            line += (f", Floquet multipliers in [{np.nanmin(mu):.6g}, "
                     f"{np.nanmax(mu):.6g}]")
        lines.append(line)
    dims = [d for d in f.dims if d != "attractor"]
    if len(dims) == 1 and ds.sizes[dims[0]] <= table_rows:
        d = dims[0]
        lines.append(f"  {d:>10s} " + " ".join(f"{n:>22s}" for n in names))
        for i, x in enumerate(ds[d].values):
            cells = [f"{float(f.isel({d: i}).sel(attractor=n)):.6f} +- "
                     f"{float(e.isel({d: i}).sel(attractor=n)):.1e}" for n in names]
            lines.append(f"  {x:10.6g} " + " ".join(f"{c:>22s}" for c in cells))
    return lines
