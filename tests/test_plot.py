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
