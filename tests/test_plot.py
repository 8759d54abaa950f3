"""Pictures: the right figure for each kind of result, labelled with units.

What is proven: unit strings render as labels; geometric axes are recognised (and
drawn on a log scale); a 2-D (v, alpha2) map carries the analytic v* curve and the
measured boundary; a regime map's legend names the regimes present with their share; regime (flag)
axes of line plots read names; every legend lies off the data (its drawn box
overlaps no axes); a failed simulation is refused;
a near-constant field is not stretched over rounding noise; 1-D sweeps, stacked
sweeps (facets, series) and simulations all draw and save a PNG.
"""
import math

import numpy as np
import xarray as xr
import pytest

import sweepcore as sc
from sweepcore import plot
from sweepcore.grid import Grid
from sweepcore.sweep import sweep

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("units, text", [
    ("kN s3 cm-3", "kN s$^3$/cm$^3$"), ("cm s-1", "cm/s"), ("s-1", "1/s"),
    ("kN s2 cm-1", "kN s$^2$/cm"), ("1", ""), ("", ""), ("cm", "cm"),
])
def test_pretty_units(units, text):
    assert plot.pretty_units(units) == text


def test_is_geometric():
    assert plot.is_geometric(np.geomspace(1e-3, 0.1, 7))
    assert not plot.is_geometric(np.linspace(1.0, 10.0, 7))
    assert not plot.is_geometric(np.array([-1.0, 1.0, 3.0]))
    assert not plot.is_geometric(np.array([1.0, 2.0]))


@pytest.fixture(scope="module")
def hopf_small():
    """A 12 x 8 (v, alpha2) map across v*, started stuck."""
    return sweep(Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, v=np.linspace(0.5, 10, 12),
                      alpha2=np.geomspace(1e-3, 0.1, 8)))


def _labels(fig):
    out = []
    for leg in [*fig.legends, *(ax.get_legend() for ax in fig.axes)]:
        if leg is not None:
            out += [t.get_text() for t in leg.get_texts()]
    return out


def test_map_has_vstar_boundary_and_regime_legend(hopf_small, tmp_path):
    fig = plot.plot_result(hopf_small)
    ax_regime, ax_amp = fig.axes[0], fig.axes[1]
    assert ax_regime.get_yscale() == "log" and ax_regime.get_xscale() == "linear"
    assert ax_regime.get_xlabel() == "belt speed $v$ [cm/s]"
    assert "kN s$^3$/cm$^3$" in ax_regime.get_ylabel()
    labels = _labels(fig)
    assert any(t.startswith("analytic $v^*") for t in labels)
    assert "measured boundary: cycle | equilibrium" in labels
    counts = {n: int((hopf_small.regime == c).sum()) for c, n in
              zip(hopf_small.regime.attrs["flag_values"],
                  hopf_small.regime.attrs["flag_meanings"].split())}
    present = [t for t in labels if "%" in t or "point" in t]
    assert len(present) == sum(1 for n in counts.values() if n)   # one entry per regime
    # the v* curve is drawn where it should be: v = sqrt(alpha1/(3 alpha2))
    vstar = [ln for ln in ax_amp.lines if ln.get_linestyle() == "--"][0]
    v, a2 = vstar.get_xdata(), vstar.get_ydata()
    ok = np.isfinite(v)
    np.testing.assert_allclose(v[ok], np.sqrt(1.0 / (3.0 * a2[ok])), rtol=1e-12)
    path = plot.save(fig, tmp_path / "map.png")
    assert path.read_bytes()[:8] == PNG_MAGIC


def test_uniform_field_is_not_stretched(hopf_small):
    ds = hopf_small.copy()
    ds["amplitude"] = ds.amplitude * 0 + 1.5 + 1e-12 * np.random.default_rng(0).random(
        ds.amplitude.shape)
    fig = plot.plot_map(ds, variables=("amplitude",))
    mesh = fig.axes[0].collections[0]
    assert mesh.norm.vmax - mesh.norm.vmin == pytest.approx(0.15)
    assert any("uniform: 1.5" in t.get_text() for t in fig.axes[0].texts)


def test_analytic_variable_keeps_its_digits(hopf_small):
    """q is a closed form (eq. 46): a spread of 1e-8 relative over a map (a
    Stribeck term at large v) is its value, drawn on a colour scale over its
    range; it was drawn as one rounded "uniform" value, the rule for measured
    observables (accuracy 1e-6)."""
    ds = hopf_small.copy()
    step = 1e-9 * np.arange(ds.sizes["v"])              # 1e-8 of q's -0.1 across v
    ds["q"] = (ds.q * 0 - 0.1 + xr.DataArray(step, dims="v")).assign_attrs(
        hopf_small.q.attrs)
    fig = plot.plot_map(ds, variables=("q",))
    mesh = fig.axes[0].collections[0]
    assert (mesh.norm.vmin, mesh.norm.vmax) == (float(ds.q.min()), float(ds.q.max()))
    assert not any("uniform" in t.get_text() for t in fig.axes[0].texts)


def test_line_figure_draws_references_and_series(tmp_path):
    ds = sweep(Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, alpha2=0.01,
                    v=np.linspace(4.0, 7.0, 9), x0=[0.0, 1.0]))
    fig = plot.plot_result(ds)
    labels = _labels(fig)
    assert r"$v/\omega$ (paper, eq. 39)" in labels
    assert "x0 = 0" in labels and "x0 = 1" in labels           # one series per start
    assert fig.axes[-1].get_xlabel() == "belt speed $v$ [cm/s]"
    plot.save(fig, tmp_path / "line.png")
    assert (tmp_path / "line.png").stat().st_size > 10_000


def test_trajectory_and_cases_figures(tmp_path):
    p = sc.Params(m=5.0, k=50.0, r_y=10.0, v=5.0)
    tr = sc.simulate(p, 6.0)
    fig = plot.plot_result(tr)
    assert len(fig.axes) == 6
    assert fig.axes[5].get_xlabel() == "slider position $x$ [cm]"
    assert any(t.startswith("abnormal stop (eq. 31)") for t in _labels(fig))
    plot.save(fig, tmp_path / "tr.png")
    fig = plot.plot_cases([tr, tr], ["a", "b"], equilibria=[p.x_eq, p.x_eq])
    assert len(fig.axes) == 6
    plot.save(fig, tmp_path / "cases.png")
    assert (tmp_path / "cases.png").read_bytes()[:8] == PNG_MAGIC


def test_friction_figure_marks_vstar():
    fig = plot.plot_friction(10.0, 1.0, 0.01)
    ax = fig.axes[0]
    v_star = math.sqrt(1.0 / 0.03)
    dots = [ln for ln in ax.lines if ln.get_marker() == "o"]
    assert sorted(float(d.get_xdata()[0]) for d in dots) == pytest.approx([-v_star, v_star])
    assert [float(d.get_ydata()[0]) for d in dots if d.get_xdata()[0] > 0] == \
        pytest.approx([10.0 - 2.0 * v_star / 3.0])


# ------------------------------------------- names on regime axes, legends off data
def _legends_clear_of_axes(fig):
    """Every legend's drawn box overlaps no axes (data area or colour bar)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    FigureCanvasAgg(fig).draw()
    legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes
                                   if ax.get_legend() is not None]
    assert legends
    for leg in legends:
        box = leg.get_window_extent()
        for ax in fig.axes:
            assert not box.overlaps(ax.get_window_extent()), \
                [t.get_text() for t in leg.get_texts()][:3]


def test_map_legends_are_off_the_maps(hopf_small):
    _legends_clear_of_axes(plot.plot_result(hopf_small))


def test_line_and_trajectory_legends_are_off_the_data(hopf_small):
    _legends_clear_of_axes(plot.plot_result(hopf_small.isel(alpha2=4)))
    _legends_clear_of_axes(plot.plot_result(sc.simulate(sc.Params(5.0, 50.0, 10.0, 5.0),
                                                       6.0)))


def test_regime_axis_of_a_line_plot_reads_names(hopf_small):
    """A 1-D regime panel has one tick per regime code, named, not 3.8 ... 4.2."""
    ds = hopf_small.isel(alpha2=4)
    fig = plot.plot_result(ds, variables=["amplitude", "regime"])
    ax = fig.axes[1]
    ticks = [int(t) for t in ax.get_yticks()]
    names = [t.get_text() for t in ax.get_yticklabels()]
    meanings = ds.regime.attrs["flag_meanings"].split()
    assert ticks == [int(v) for v in ds.regime.attrs["flag_values"]]
    assert names == [n.replace("_", " ") for n in meanings]
    # the points sit on their regime's tick
    ys = np.concatenate([c.get_offsets()[:, 1] for c in ax.collections])
    assert set(ys.astype(int)) == set(np.unique(ds.regime.values).tolist())


def test_generic_figure_names_flag_axes(hopf_small):
    ds = hopf_small.isel(alpha2=4)[["status", "n_steps"]]
    fig = plot.plot_result(ds)
    labels = [t.get_text() for t in fig.axes[0].get_yticklabels()]
    assert "ok" in labels


def test_failed_simulation_is_not_drawn():
    ds = sc.simulate(sc.Params(5.0, 50.0, 10.0, 5.0), 1.0, method="gps", dt=1.0)
    with pytest.raises(ValueError, match="failed simulation"):
        plot.plot_result(ds)


# ------------------------------------- what the API refuses, and what it draws
STRIBECK = dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.5)


@pytest.fixture(scope="module")
def stribeck_map():
    """A (v, c) map of the exponential Stribeck law: x_eq depends on v only, v_star
    on c only."""
    return sweep(Grid(**STRIBECK, v=np.linspace(0.5, 2.5, 7), c=[0.05, 0.1, 0.2]))


@pytest.fixture(scope="module")
def files(hopf_small, stribeck_map):
    """One result of every kind (tests/test_basins.py draws the basin maps)."""
    diagram = sc.bifurcation_diagram(Grid(**STRIBECK, c=0.1, v=np.linspace(1, 2, 5)),
                                     boundaries=False, unstable=False)
    return {"sweep": hopf_small, "stribeck": stribeck_map, "diagram": diagram,
            "simulation": sc.simulate(sc.Params(5.0, 50.0, 10.0, 5.0), 1.0),
            "cycles": sc.slip_cycles(Grid(**STRIBECK, c=0.1, v=[1.3, 1.6])),
            "basins": sc.basin_stability(Grid(**STRIBECK, c=0.1, v=[1.3, 1.6]),
                                         route="exact", progress=False)}


@pytest.mark.parametrize("function", ["plot_map", "plot_result", "plot_basins",
                                      "plot_hysteresis", "plot_diagram",
                                      "plot_boundaries", "plot_trajectory"])
@pytest.mark.parametrize("bad", [None, "out.nc", {}, 5], ids=["None", "str", "dict", "5"])
def test_what_is_not_a_result_is_refused_naming_ds(function, bad):
    hint = r" \(a file name: read it with sweepcore.open_result first\)" \
        if bad == "out.nc" else ""
    with pytest.raises(TypeError, match=rf"^ds must be an xarray.Dataset, a result of "
                                        rf"sweepcore, got .* of type "
                                        rf"{type(bad).__name__}{hint}$"):
        getattr(sc, function)(bad)


@pytest.mark.parametrize("function, kind, wanted", [
    ("plot_basins", "sweep", "a basin-stability result"),
    ("plot_basins", "simulation", "a basin-stability result"),
    ("plot_basins", "diagram", "a basin-stability result"),
    ("plot_basins", "cycles", "a basin-stability result"),
    ("plot_hysteresis", "sweep", "a bifurcation diagram"),
    ("plot_hysteresis", "cycles", "a bifurcation diagram"),
    ("plot_diagram", "simulation", "a bifurcation diagram"),
    ("plot_boundaries", "sweep", "located boundaries"),
    ("plot_trajectory", "diagram", "a simulation"),
])
def test_a_result_of_another_kind_is_refused_naming_both(files, function, kind, wanted):
    got = {"sweep": "a sweep", "simulation": "a simulation", "diagram":
           "a bifurcation diagram", "cycles": "a slip-cycle result"}[kind]
    with pytest.raises(ValueError, match=rf"^ds must be {wanted} .*; got {got} "):
        getattr(sc, function)(files[kind])


@pytest.mark.parametrize("kwargs, exc, message", [
    (dict(x="v", y="v"), ValueError, r"x and y are both 'v': a map needs two different "
                                     r"dimensions \(swept: "),
    (dict(x="nope"), ValueError, r"x='nope' is not a swept numeric dimension"),
    (dict(x=5), TypeError, r"x must be a dimension name \(str\), got 5"),
    (dict(variables=[]), ValueError, r"variables is empty"),
    (dict(variables=["nope", "amplitude"]), ValueError,
     r"variables: 'nope' is not a variable of the result \(has: amplitude, "),
    (dict(variables=["amplitud"]), ValueError, r"did you mean 'amplitude'\?"),
    (dict(variables=5), TypeError, r"variables must be a variable name or a sequence"),
    (dict(boundary="no"), TypeError, r"boundary must be True or False"),
    (dict(title=5), TypeError, r"title must be a str or None"),
])
def test_plot_map_names_the_argument_it_refuses(hopf_small, kwargs, exc, message):
    with pytest.raises(exc, match=message):
        plot.plot_map(hopf_small, **kwargs)


def test_one_variable_name_is_one_panel(hopf_small):
    fig = plot.plot_map(hopf_small, variables="amplitude")
    titled = [ax for ax in fig.axes if ax.get_title()]
    assert [ax.get_title() for ax in titled] == ["vibration amplitude"]
    fig = plot.plot_lines(hopf_small.isel(alpha2=4), "v", variables="period")
    assert [ax.get_ylabel() for ax in fig.axes] == ["period of the attractor $T$ [s]"]


def test_a_variable_over_one_axis_of_a_map_is_drawn_as_a_line(stribeck_map):
    """On a (v, c) map x_eq depends on v only and v* on c only: each is a line
    against its axis beside the maps, at the closed forms x_eq = (r_k + (r_y - r_k)
    exp(-v/v_s))/k and v* = v_s ln((r_y - r_k)/(v_s c)); a constant (omega) is a
    line at its value."""
    fig = plot.plot_map(stribeck_map, variables=["regime", "x_eq", "v_star", "omega"])
    titles = {ax.get_title(): ax for ax in fig.axes}
    (xeq,) = titles["steady-sliding equilibrium position (over v only)"].get_lines()
    v = np.linspace(0.5, 2.5, 7)
    np.testing.assert_array_equal(xeq.get_xdata(), v)
    np.testing.assert_allclose(xeq.get_ydata(), 0.5 + 0.5 * np.exp(-v / 0.5), rtol=1e-12)
    (vs,) = titles["analytic Hopf belt speed (the lowest) (over c only)"].get_lines()
    c = np.array([0.05, 0.1, 0.2])
    np.testing.assert_array_equal(vs.get_ydata(), c)      # c up, as on the maps
    np.testing.assert_allclose(vs.get_xdata(), 0.5 * np.log(0.5 / (0.5 * c)), rtol=1e-12)
    (om,) = titles["natural frequency sqrt(k/m) (constant)"].get_lines()
    assert set(om.get_ydata()) == {1.0}


def test_the_cli_draws_variables_over_one_axis(tmp_path, capsys):
    """``sweepcore plot --variables regime,q,x_eq`` of a (v, c) map (five values
    of c: drawn as maps, not lines) draws x_eq, which depends on v only."""
    from sweepcore.cli import main
    sweep(Grid(**STRIBECK, v=np.linspace(0.5, 2.5, 7), c=np.geomspace(0.05, 0.2, 5)),
          path=tmp_path / "s.nc").close()
    assert main(["plot", str(tmp_path / "s.nc"), "-o", str(tmp_path / "s.png"),
                 "--variables", "regime,q,x_eq"]) == 0, capsys.readouterr().err
    assert (tmp_path / "s.png").read_bytes()[:8] == PNG_MAGIC


def test_a_stribeck_map_draws_the_hopf_curve_the_file_holds(stribeck_map):
    """The file's v* over c, drawn over every map at v = v_s ln((r_y - r_k)/(v_s c))
    where it lies inside the map's speeds; its label says the Hopf point is
    subcritical (the file's first Lyapunov coefficient is positive)."""
    fig = plot.plot_map(stribeck_map)
    labels = _labels(fig)
    assert r"analytic Hopf speed $v^*$ (stored, subcritical)" in labels
    for ax in fig.axes[:2]:
        (curve,) = [ln for ln in ax.get_lines() if ln.get_linestyle() == "--"]
        v, c = curve.get_xdata(), curve.get_ydata()
        ok = np.isfinite(v)
        assert ok.sum() == 3
        np.testing.assert_allclose(v[ok], 0.5 * np.log(1.0 / c[ok]), rtol=1e-12)


@pytest.mark.parametrize("reference, message", [
    ("x", r"reference must be a dict \{label: \(x, fraction, error\)\}, got 'x'"),
    ({"a": ([1.5], [0.3], [0.01, 0.02])}, r"reference\['a'\]: x, fraction and error "
                                          r"must have equal lengths, got 1, 1, 2"),
    ({"a": ([1.5], [0.3])}, r"reference\['a'\] must be three sequences"),
    ({"a": "xyz"}, r"reference\['a'\] must hold numbers"),
    ({"a": (["p"], [0.3], [0.1])}, r"reference\['a'\] must hold numbers"),
])
def test_a_reference_table_that_cannot_be_drawn_is_refused(files, reference, message):
    with pytest.raises((TypeError, ValueError), match=message):
        plot.plot_basins(files["basins"], reference=reference)


def test_hysteresis_variable_must_be_a_scanned_variable(files):
    with pytest.raises(ValueError, match=r"variable: 'nope' is not a variable"):
        plot.plot_hysteresis(files["diagram"], variable="nope")
    with pytest.raises(ValueError, match=r"variable='v_star' is not over the scans"):
        plot.plot_hysteresis(files["diagram"], variable="v_star")


# ----------------------------------------------------- a measured friction law
TABLE_SPEED = np.array([0.0, 0.1, 0.25, 0.5, 1.0, 2.0, 4.0])      # cm/s (the README's)
TABLE_FORCE = np.array([1.0, 0.93, 0.82, 0.68, 0.55, 0.51, 0.50])  # kN


@pytest.fixture(scope="module")
def measured():
    return sc.TableLaw(TABLE_SPEED, TABLE_FORCE, static=1.1, name="measured")


def _legend_labels(fig):
    return [t.get_text() for legend in fig.legends for t in legend.get_texts()]


def test_a_table_law_sweep_is_drawn_against_its_grid_not_its_samples(measured):
    """A table law's samples lie on ``law_point`` beside the grid: never the axis a
    picture is drawn against (it was, and a sweep of one speed or over k raised
    IndexError in plot/lines.py)."""
    over_k = sweep(Grid(m=1.0, k=[1.0, 2.0], c=0.1, v=0.3, law=measured))
    fig = sc.plot_result(over_k)
    assert any("stiffness" in ax.get_xlabel() for ax in fig.axes)
    with pytest.raises(ValueError, match="single point"):
        sc.plot_result(sweep(Grid(m=1.0, k=1.0, c=0.1, v=0.3, law=measured)))


def test_a_table_law_picture_shows_the_law_and_names_only_what_it_draws(measured):
    """The friction curve the sweep ran on is drawn (the table's samples, force
    against speed); v* is named in the legend exactly where its line is drawn (the
    Hopf speed inside the belt speeds), and the averaging estimate of the paper's
    cubic law is not drawn for a measured law."""
    inside = sweep(Grid(m=1.0, k=1.0, c=0.1, v=np.linspace(0.2, 2.0, 6), law=measured))
    v_star = float(inside["v_star"])
    assert 0.2 < v_star < 2.0
    fig = sc.plot_result(inside)
    table = [line for ax in fig.axes for line in ax.get_lines()
             if np.array_equal(line.get_xdata(), TABLE_SPEED)]
    assert table and np.array_equal(table[0].get_ydata(), TABLE_FORCE)
    named = [t for t in _legend_labels(fig) if "v^*" in t]
    assert named == [f"Hopf speed $v^*$ = {v_star:.3g}"]
    drawn = [line for ax in fig.axes for line in ax.get_lines()
             if np.allclose(line.get_xdata(), v_star)]
    assert len(drawn) >= 2          # in each panel
    below = sweep(Grid(m=1.0, k=1.0, c=0.1, v=np.linspace(0.2, 0.6, 4), law=measured))
    assert not [t for t in _legend_labels(sc.plot_result(below)) if "v^*" in t]
