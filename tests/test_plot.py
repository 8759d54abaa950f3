"""Pictures: the right figure for each kind of result, labelled with units.

What is proven: unit strings render as labels; geometric axes are recognised (and
drawn on a log scale); a 2-D (v, alpha2) map carries the analytic v* curve and the
measured boundary; a regime map's legend names the regimes present with their share;
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
    for ax in fig.axes:
        leg = ax.get_legend()
        if leg is not None:
            out += [t.get_text() for t in leg.get_texts()]
    return out


def test_map_has_vstar_boundary_and_regime_legend(hopf_small, tmp_path):
    fig = plot.figure_for(hopf_small)
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
    fig = plot.map_figure(ds, variables=("amplitude",))
    mesh = fig.axes[0].collections[0]
    assert mesh.norm.vmax - mesh.norm.vmin == pytest.approx(0.15)
    assert any("uniform: 1.5" in t.get_text() for t in fig.axes[0].texts)


def test_line_figure_draws_references_and_series(tmp_path):
    ds = sweep(Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, alpha2=0.01,
                    v=np.linspace(4.0, 7.0, 9), x0=[0.0, 1.0]))
    fig = plot.figure_for(ds)
    labels = _labels(fig)
    assert r"$v/\omega$ (paper, eq. 39)" in labels
    assert "x0 = 0" in labels and "x0 = 1" in labels           # one series per start
    assert fig.axes[-1].get_xlabel() == "belt speed $v$ [cm/s]"
    plot.save(fig, tmp_path / "line.png")
    assert (tmp_path / "line.png").stat().st_size > 10_000


def test_trajectory_and_cases_figures(tmp_path):
    p = sc.Params(m=5.0, k=50.0, r_y=10.0, v=5.0)
    tr = sc.simulate(p, 6.0)
    fig = plot.figure_for(tr)
    assert len(fig.axes) == 6
    assert fig.axes[5].get_xlabel() == "slider position $x$ [cm]"
    assert any(t.startswith("abnormal stop (eq. 31)") for t in _labels(fig))
    plot.save(fig, tmp_path / "tr.png")
    fig = plot.cases_figure([tr, tr], ["a", "b"], equilibria=[p.x_eq, p.x_eq])
    assert len(fig.axes) == 6
    plot.save(fig, tmp_path / "cases.png")
    assert (tmp_path / "cases.png").read_bytes()[:8] == PNG_MAGIC


def test_friction_figure_marks_vstar():
    fig = plot.friction_figure(10.0, 1.0, 0.01)
    ax = fig.axes[0]
    v_star = math.sqrt(1.0 / 0.03)
    dots = [ln for ln in ax.lines if ln.get_marker() == "o"]
    assert sorted(float(d.get_xdata()[0]) for d in dots) == pytest.approx([-v_star, v_star])
    assert [float(d.get_ydata()[0]) for d in dots if d.get_xdata()[0] > 0] == \
        pytest.approx([10.0 - 2.0 * v_star / 3.0])
