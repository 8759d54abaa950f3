"""Basin stability (sweepcore/basins.py): the exact route against the independent scipy
computation (tests/reference.py, and the values it wrote with
studies/bstab_reference.py), the sampled route against the exact one, invariants of
the plane, refusals, the file."""
import json
import math
from pathlib import Path

import numpy as np
import pytest

import sweepcore as sc
from sweepcore.cycles import clipped_area, cycle_polygon
from sweepcore._kernels import layout as L
from sweepcore import compiled
from sweepcore._kernels.cycles import MAX_CYCLES
from sweepcore.options import make_options

from reference import reference_basin_fraction, reference_slip_cycle

BSTAB = dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.5, c=0.1, alpha1=0.0, alpha2=0.0)
BOX = dict(x0=(-2.0, 2.0), xdot0=(0.0, 2.0))
REFERENCE = Path(__file__).resolve().parent.parent / "studies" / "results" / \
    "bstab_reference.json"
SUPER = dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.5, c=0.02, alpha1=0.6, alpha2=0.1)


def grid(*vs, **pars):
    return sc.Grid(**{**BSTAB, **pars}, v=np.array(vs))


@pytest.fixture(scope="module")
def exact_band():
    """The exact route at the reference's belt speeds of the bistable band."""
    rows = json.loads(REFERENCE.read_text())["bstab"]["rows"]
    vs = [r["v"] for r in rows]
    return rows, sc.basin_stability(grid(*vs), **BOX, route="exact", progress=False)


def test_exact_fractions_against_the_scipy_reference(exact_band):
    """Steady sliding's fraction = the area of the unstable cycle's interior in the
    box: against the scipy shooting + polygon computation (20001 points, rtol 1e-13,
    its own check 6e-9) at 12 speeds; the stated error bounds the difference."""
    rows, ds = exact_band
    eq = ds.basin_fraction.sel(attractor="equilibrium").values
    err = ds.basin_fraction_error.sel(attractor="equilibrium").values
    assert (ds.basin_route.values == 0).all() and (ds.basin_status.values == 0).all()
    for r, f, e in zip(rows, eq, err):
        assert abs(f - r["basin_fraction"]) <= max(e, 1e-8) + 1e-8, r["v"]
        assert abs(f - r["basin_fraction"]) <= 1e-6, r["v"]
        assert e <= 1e-6
    assert list(ds.attractor.values) == ["equilibrium", "stick_slip"]
    np.testing.assert_allclose(ds.basin_fraction.sum("attractor"), 1.0, atol=1e-12)
    assert (ds.n_attractors.values == 2).all()


def test_exact_fraction_with_every_term_of_the_law():
    """Stribeck, damping and cubic terms together (m = 2, k = 3, ...), v = 1.3: the
    reference's fraction (studies/bstab_reference.py, family rows)."""
    family = json.loads(REFERENCE.read_text())["family"]
    row = next(r for r in family["rows"] if r["v"] == 1.3)
    g = sc.Grid(**family["params"], v=np.array([1.3]))
    ds = sc.basin_stability(g, **BOX, route="exact", progress=False)
    assert int(ds.basin_status[0]) == 0
    assert float(ds.basin_fraction.sel(attractor="equilibrium")[0]) == pytest.approx(
        row["basin_fraction"], abs=1e-6)


def test_exact_fraction_against_a_live_scipy_polygon():
    """One point recomputed here by scipy (not read from a file)."""
    v = 1.6
    ds = sc.basin_stability(grid(v), **BOX, route="exact", progress=False)
    guess = float(sc.slip_cycles(grid(v)).cycle_x_max[0, 0])
    ref = reference_slip_cycle(BSTAB["m"], BSTAB["k"], BSTAB["r_y"], v, 0.0, 0.0, guess,
                               c=BSTAB["c"], r_k=BSTAB["r_k"], v_s=BSTAB["v_s"])
    bf = reference_basin_fraction(BSTAB["m"], BSTAB["k"], BSTAB["r_y"], v, 0.0, 0.0,
                                  ref["x_max"], box=((-2.0, 2.0), (0.0, 2.0)),
                                  c=BSTAB["c"], r_k=BSTAB["r_k"], v_s=BSTAB["v_s"],
                                  n=8001)
    assert float(ds.basin_fraction.sel(attractor="equilibrium")[0]) == pytest.approx(
        bf["fraction"], abs=2e-6)


@pytest.mark.parametrize("v, sampling", [(1.25, "uniform"), (1.5, "uniform"),
                                         (1.7, "grid"), (1.4, "halton")])
def test_sampled_route_agrees_with_the_exact_one(v, sampling):
    """Starts on the attractor kernel: the share ending on steady sliding is the exact
    fraction within 4 standard errors (binomial)."""
    g = grid(v)
    exact = sc.basin_stability(g, **BOX, route="exact", progress=False)
    mc = sc.basin_stability(g, **BOX, route="sampled", samples=600, sampling=sampling,
                            seed=3, progress=False)
    f = float(exact.basin_fraction.sel(attractor="equilibrium")[0])
    s = float(mc.basin_fraction.sel(attractor="equilibrium")[0])
    se = float(mc.basin_fraction_error.sel(attractor="equilibrium")[0])
    assert se == pytest.approx(math.sqrt(s * (1 - s) / int(mc.samples[0])))
    assert abs(s - f) <= 4 * se
    assert int(mc.n_attractors[0]) == 2 and int(mc.basin_route[0]) == 1
    assert float(mc.basin_fraction.sum("attractor")[0]) == pytest.approx(1.0, abs=1e-12)
    # the same attractors: stick-slip's amplitude and steady sliding's position
    for name in ("amplitude", "mean"):
        np.testing.assert_allclose(mc[name].values, exact[name].values, atol=1e-6)


def test_one_attractor_outside_the_bistable_band():
    """Below the Hopf point (1.151) steady sliding is unstable: every start ends on
    the stick-slip cycle; above the fold (1.837) on steady sliding. Both routes."""
    for route in ("exact", "sampled"):
        ds = sc.basin_stability(grid(1.1, 1.9), **BOX, route=route, samples=200,
                                progress=False)
        f = ds.basin_fraction
        assert list(ds.n_attractors.values) == [1, 1]
        assert float(f.sel(attractor="equilibrium", v=1.1)) == 0.0
        assert float(f.sel(attractor="stick_slip", v=1.1)) == 1.0
        assert float(f.sel(attractor="equilibrium", v=1.9)) == 1.0
        assert float(ds["mean"].sel(attractor="equilibrium", v=1.9)) == pytest.approx(
            float(ds.x_eq.sel(v=1.9)), abs=1e-9)
        assert (ds.basin_fraction_error.values < 1e-7).all()


def test_mirror_symmetry_of_a_negative_belt_speed():
    """(x, xdot, v) -> (-x, -xdot, -v) maps the motion onto itself: the mirrored box
    at -v has the same fractions (the scan then follows the x minima)."""
    a = sc.basin_stability(grid(1.5), x0=(-2.0, 2.0), xdot0=(0.0, 2.0), route="exact",
                           progress=False)
    b = sc.basin_stability(grid(-1.5), x0=(-2.0, 2.0), xdot0=(-2.0, 0.0),
                           route="exact", progress=False)
    assert int(b.basin_status[0]) == 0
    np.testing.assert_allclose(b.basin_fraction.values, a.basin_fraction.values,
                               atol=1e-9)


def test_a_tolerance_the_polygon_cannot_reach_is_said():
    """ftol below the cycle's own accuracy (tol L times the perimeter): 'exact' says
    polygon_not_resolved with NaN fractions, 'auto' samples instead."""
    ex = sc.basin_stability(grid(1.5), **BOX, route="exact", ftol=1e-14, progress=False)
    names = ex.basin_status.attrs["flag_meanings"].split()
    assert names[int(ex.basin_status[0])] == "polygon_not_resolved"
    assert np.isnan(ex.basin_fraction.values).all()
    auto = sc.basin_stability(grid(1.5), **BOX, ftol=1e-14, samples=40, progress=False)
    assert int(auto.basin_route[0]) == 1 and int(auto.basin_status[0]) == 0


def test_no_attractor_anywhere_is_labelled_none_not_failed(tmp_path):
    """Where no point found any attractor (the exact route, not applicable at any
    point), the one placeholder attractor is 'none' of regime 'none', never a
    'failed' attractor that no run ended on; the file keeps the label."""
    v = 0.99 * sc.Params(**SUPER, v=1.0).v_star
    ds = sc.basin_stability(sc.Grid(**SUPER, v=np.array([v])), **BOX, route="exact",
                            path=tmp_path / "b.nc", progress=False)
    for got in (ds, sc.open_result(tmp_path / "b.nc")):
        assert list(got.attractor.values) == ["none"]
        codes = dict(zip(got.attractor_regime.attrs["flag_values"].tolist(),
                         got.attractor_regime.attrs["flag_meanings"].split()))
        assert codes[int(got.attractor_regime[0])] == "none"
        assert int(got.n_attractors[0]) == 0
        assert np.isnan(got.basin_fraction.values).all()


def test_auto_route_samples_where_the_exact_one_does_not_apply():
    """A supercritical law's stable slip cycle is no basin boundary: route='exact'
    says so (NaN fractions, a status); 'auto' samples there."""
    v = 0.99 * sc.Params(**SUPER, v=1.0).v_star
    g = sc.Grid(**SUPER, v=np.array([v]))
    ex = sc.basin_stability(g, **BOX, route="exact", progress=False)
    assert ex.basin_status.attrs["flag_meanings"].split()[int(ex.basin_status[0])] == \
        "exact_route_not_applicable"
    assert np.isnan(ex.basin_fraction.values).all()
    auto = sc.basin_stability(g, **BOX, samples=50, progress=False)
    assert int(auto.basin_route[0]) == 1
    assert float(auto.basin_fraction.sel(attractor="slip_cycle")[0]) == 1.0


@pytest.mark.parametrize("points", [False, True])
def test_results_do_not_depend_on_the_chunks(points):
    """The starts are seeded by (seed, flat index): the same whatever the chunks and
    the executor, for a product grid and for scattered points."""
    g = grid(1.3, 1.45, 1.6) if not points else sc.Grid.points(
        **{k: v for k, v in BSTAB.items()}, v=np.array([1.3, 1.45, 1.6]))
    a = sc.basin_stability(g, **BOX, samples=60, route="sampled", progress=False)
    b = sc.basin_stability(g, **BOX, samples=60, route="sampled", chunks=1,
                           scheduler="synchronous", progress=False)
    np.testing.assert_array_equal(a.basin_fraction.values, b.basin_fraction.values)


def test_starts_that_do_not_settle_are_data_not_an_attractor():
    """With a time budget too short to recognise anything, the starts are counted
    under 'unconverged', the point says so, and no attractor is claimed."""
    ds = sc.basin_stability(grid(1.5), **BOX, samples=20, route="sampled",
                            max_periods=0.5, progress=False)
    names = ds.basin_status.attrs["flag_meanings"].split()
    assert names[int(ds.basin_status[0])] == "unclassified_starts"
    assert "unconverged" in list(ds.attractor.values)
    assert int(ds.n_attractors[0]) < 2
    assert float(ds.basin_fraction.sum("attractor")[0]) == pytest.approx(1.0)


# ------------------------------------------------------------------ geometry
def test_halton_points_are_the_radical_inverses():
    from sweepcore.basins import _radical_inverse
    i = np.arange(1, 9)
    np.testing.assert_allclose(_radical_inverse(i, 2),
                               [1 / 2, 1 / 4, 3 / 4, 1 / 8, 5 / 8, 3 / 8, 7 / 8, 1 / 16])
    np.testing.assert_allclose(_radical_inverse(i, 3),
                               [1 / 3, 2 / 3, 1 / 9, 4 / 9, 7 / 9, 2 / 9, 5 / 9, 8 / 9])


def test_clipped_area_against_closed_forms():
    sq = (np.array([0.0, 2.0, 2.0, 0.0]), np.array([0.0, 0.0, 2.0, 2.0]))
    assert clipped_area(*sq, ((1.0, 3.0), (-1.0, 1.0))) == (1.0, 4.0)
    assert clipped_area(*sq, ((3.0, 4.0), (0.0, 1.0)))[0] == 0.0
    assert clipped_area(*sq, ((-1.0, 5.0), (-1.0, 5.0)))[0] == 4.0
    # a concave L-shape (area 3) cut by the line x = 1.5: 1.5 + 0.5 on each side
    lx = np.array([0.0, 2.0, 2.0, 1.0, 1.0, 0.0])
    ly = np.array([0.0, 0.0, 1.0, 1.0, 2.0, 2.0])
    assert clipped_area(lx, ly, ((0.0, 1.5), (0.0, 2.0)))[0] == pytest.approx(2.5)
    assert clipped_area(lx, ly, ((1.5, 9.0), (0.0, 2.0)))[0] == pytest.approx(0.5)
    # a fine circle of radius 1 half inside: pi / 2 to the polygon's h^2
    t = np.linspace(0.0, 2 * np.pi, 4096, endpoint=False)
    area, _ = clipped_area(np.cos(t), np.sin(t), ((-2.0, 2.0), (0.0, 2.0)))
    assert area == pytest.approx(np.pi / 2, rel=1e-6)


def test_polygon_area_is_the_kernels_quadrature():
    """The whole cycle's polygon area against the kernel's own quadrature of the
    cycle (cycle_size = sqrt(area / pi) in (x, xdot / omega), from int xdot^2 dt)."""
    p = sc.Params(**BSTAB, v=1.5)
    out = np.empty((1, MAX_CYCLES, L.NOBS))
    found = np.zeros(1, np.int64)
    compiled.cycles(p.row(0.0, p.v)[None, :], (p.friction_law,), make_options(), out, found)
    assert found[0] == 1
    out = out[0]
    x, xd, _gap, ok = cycle_polygon(p.row(0.0, p.v), out[0], make_options(), 8192)
    area, _ = clipped_area(x, xd, ((-9.0, 9.0), (-9.0, 9.0)))
    assert ok and area == pytest.approx(np.pi * out[0, L.OB_CYCLE_SIZE] ** 2 * p.omega,
                                        rel=1e-6)


# ------------------------------------------------------------------ API
@pytest.mark.parametrize("kwargs, match", [
    (dict(x0=(1.0, 1.0)), "x0"), (dict(x0=(2.0, -2.0)), "x0"),
    (dict(xdot0=(0.0, np.inf)), "xdot0"), (dict(xdot0=3.0), "xdot0"),
    (dict(samples=0), "samples"), (dict(samples=2.5), "samples"),
    (dict(route="fast"), "route"), (dict(sampling="sobol2"), "sampling"),
    (dict(checks=0), "checks"), (dict(ftol=0.0), "ftol"),
    (dict(method="gps", route="exact"), "gps"), (dict(chunks=0), "chunks"),
])
def test_refusals_name_the_parameter(kwargs, match):
    with pytest.raises(ValueError, match=match):
        sc.basin_stability(grid(1.5), **{**BOX, **kwargs})


def test_a_swept_start_is_refused():
    with pytest.raises(ValueError, match="x0"):
        sc.basin_stability(sc.Grid(**BSTAB, v=1.5, x0=np.array([0.0, 1.0])))


def test_file_round_trip(tmp_path, exact_band):
    _rows, ds = exact_band
    assert sc.check_cf(ds) == []
    assert ds.basin_fraction.attrs["units"] == "1"
    assert ds.amplitude.attrs["units"] == "cm"
    path = tmp_path / "b.nc"
    sc.basin_stability(grid(1.3, 1.5), **BOX, route="exact", path=path, progress=False)
    back = sc.open_result(path)
    assert back.attrs["sweepcore_kind"] == "basins"
    assert list(back.attractor.values) == ["equilibrium", "stick_slip"]
    np.testing.assert_array_equal(
        back.basin_fraction.values,
        ds.basin_fraction.sel(v=[1.3, 1.5]).values)
    assert sc.check_cf(back) == []


# ------------------------------------------------------------------ CLI and study
STUDY = """\
title = "bSTAB case, three speeds"
[axes]
m = 1.0
k = 1.0
r_y = 1.0
r_k = 0.5
v_s = 0.5
c = 0.1
v = [1.1, 1.5, 1.9]
[basins]
x0 = [-2.0, 2.0]
xdot0 = [0.0, 2.0]
route = "exact"
path = "b.nc"
"""


def cli(argv, tmp_path, monkeypatch, capsys):
    from sweepcore.cli import main
    monkeypatch.chdir(tmp_path)
    code = main(argv)
    return code, capsys.readouterr()


def test_cli_basins_info_and_plot(tmp_path, monkeypatch, capsys, exact_band):
    """``sweepcore basins`` writes the file the API gives, its picture; ``info``
    tabulates the fractions; ``plot`` redraws it."""
    (tmp_path / "s.toml").write_text(STUDY)
    code, out = cli(["basins", "s.toml", "--png", "b.png"], tmp_path, monkeypatch,
                    capsys)
    assert code == 0, out.err
    ds = sc.open_result(tmp_path / "b.nc")
    want = sc.basin_stability(grid(1.1, 1.5, 1.9), **BOX, route="exact",
                              progress=False)
    np.testing.assert_array_equal(ds.basin_fraction.values, want.basin_fraction.values)
    assert ds.attrs["study"] == STUDY
    assert (tmp_path / "b.png").read_bytes()[:4] == b"\x89PNG"
    code, out = cli(["info", "b.nc"], tmp_path, monkeypatch, capsys)
    assert code == 0 and "basin stability (v: 3)" in out.out
    assert "unstable slip cycles (basin boundaries) at 1 of 3 points" in out.out
    mu = float(want.cycle_floquet.sel(v=1.5)[0])
    assert f"Floquet multipliers in [{mu:.6g}, {mu:.6g}]" in out.out
    f15 = float(want.basin_fraction.sel(v=1.5, attractor="equilibrium"))
    assert f"{f15:.6f}" in out.out
    code, out = cli(["plot", "b.nc", "-o", "c.png"], tmp_path, monkeypatch, capsys)
    assert code == 0 and (tmp_path / "c.png").is_file()


@pytest.mark.parametrize("old, new, key, line", [
    ('x0 = [-2.0, 2.0]', 'x0 = [2.0, -2.0]', "basins.x0", 11),
    ('route = "exact"', 'route = "quick"', "basins.route", 13),
    ('route = "exact"', 'samples = 0', "basins.samples", 13),
    ('path = "b.nc"', 'path = "b.csv"', "basins.path", 14),
    ('c = 0.1', 'c = 0.1\nx0 = [0.0, 1.0]', "axes.x0", 9),
])
def test_bad_basins_table_is_refused_with_key_and_line(old, new, key, line, tmp_path,
                                                       monkeypatch, capsys):
    (tmp_path / "s.toml").write_text(STUDY.replace(old, new))
    code, out = cli(["basins", "s.toml"], tmp_path, monkeypatch, capsys)
    assert code == 2
    assert f"s.toml:{line}: {key}:" in out.err, out.err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]


# ------------------------------------------------------------------ docs
def test_basin_and_cycle_files_are_documented(exact_band):
    """docs/variables.md lists every variable of a basin and a slip-cycle file with
    the units the file carries, and the three code tables as the code has them."""
    import re
    from sweepcore import basins, cycles
    from test_docs import DOC, _sections, _unit_rows

    doc = _sections(DOC.read_text())
    units = {}
    for heading, body in doc.items():
        if not heading.endswith("codes"):
            for name, u in _unit_rows(body).items():
                units.setdefault(name, set()).add(u)
    _rows, ds = exact_band
    for name, var in {**ds.variables, **sc.slip_cycles(grid(1.5)).variables}.items():
        assert var.attrs["units"] in units.get(name, ()), name

    def code_rows(body):
        return {int(c): n for c, n in re.findall(r"^\| (-?\d+) \| `([a-z_]+)` \|", body,
                                                 flags=re.M)}
    assert code_rows(doc["Cycle stability codes"]) == cycles.STABILITY_NAMES
    assert code_rows(doc["Basin route codes"]) == basins.ROUTE_NAMES
    assert code_rows(doc["Basin status codes"]) == basins.STATUS_NAMES


def test_physics_page_quotes_the_study_results():
    """docs/physics.md's table is the one studies/bstab_basins.py prints from its
    results file, and its numbers are the file's."""
    import importlib.util
    root = REFERENCE.parent.parent.parent
    spec = importlib.util.spec_from_file_location("bstab_basins",
                                                  root / "studies" / "bstab_basins.py")
    study = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(study)
    res = json.loads(study.OUT.read_text())
    page = (root / "docs" / "physics.md").read_text()
    assert study.table(res) in page
    rows, c = res["rows"], res["curve"]
    sampled = max(abs(r["sampled_in_errors"]) for r in rows if "sampled" in r)
    quoted = [f"{max(abs(r['exact_minus_scipy']) for r in rows):.1e}",
              f"within {sampled:.1f}",
              f"{100 * rows[0]['classifier_share_inside']:.1f} %",
              f"reports {rows[0]['classifier_expected']:.4f}",
              f"largest error\n  {c['largest_error']:.1e}",
              f"({c['first_bistable']:.4f})", f"{c['last_fraction']:.4f} at "
              f"{c['last_bistable']:.4f}"]
    for text in quoted:
        assert text in page, text
    # the exact fractions of the file are the code's (1e-6: the stated ftol)
    assert all(abs(r["exact_minus_scipy"]) <= 1e-6 for r in rows)


def test_plot_basins_curves_and_maps():
    """One swept axis: one curve per attractor (and the reference points); two: one
    map per attractor, coloured on [0, 1]."""
    from sweepcore.plot import plot_basins, plot_result
    ds = sc.basin_stability(grid(1.1, 1.3, 1.5, 1.9), **BOX, route="exact",
                            progress=False)
    fig = plot_basins(ds, reference={"published": ([1.5], [0.304], [0.0065])})
    ax = fig.axes[0]
    curves = [ln for ln in ax.get_lines() if ln.get_label() in ("equilibrium",
                                                                 "stick slip")]
    assert len(curves) == 2
    eq = next(ln for ln in curves if ln.get_label() == "equilibrium")
    np.testing.assert_array_equal(eq.get_ydata(),
                                  ds.basin_fraction.sel(attractor="equilibrium").values)
    g2 = sc.Grid(**{**BSTAB, "c": np.array([0.1, 0.12])}, v=np.array([1.3, 1.6, 1.9]))
    two = sc.basin_stability(g2, **BOX, route="exact", progress=False)
    maps = plot_result(two)
    meshes = [a.collections[0] for a in maps.axes
              if a.get_title().startswith("basin fraction:")]
    assert len(meshes) == 2 and meshes[0].get_clim() == (0.0, 1.0)


def test_basin_maps_show_where_attractors_coexist_and_the_hopf_curve():
    """Over two parameters the first map is the number of attractors a point has
    (2 where steady sliding and stick-slip coexist, between the Hopf point and the
    fold), and every map carries the Hopf speed the file holds, at
    v* = v_s ln((r_y - r_k)/(v_s c))."""
    from sweepcore.plot import plot_basins
    c = np.array([0.08, 0.1, 0.12])
    g2 = sc.Grid(**{**BSTAB, "c": c}, v=np.array([1.0, 1.3, 1.6, 2.2]))
    two = sc.basin_stability(g2, **BOX, route="exact", progress=False)
    fig = plot_basins(two)
    first = fig.axes[0]
    assert first.get_title().startswith("attractors found: where they coexist")
    mesh = first.collections[0].get_array().reshape(3, 4)      # c up, v across
    np.testing.assert_array_equal(mesh, two.n_attractors.transpose("c", "v").values)
    assert (mesh == 2).any() and (mesh == 1).any()
    vstar = 0.5 * np.log(0.5 / (0.5 * c))
    for ax in fig.axes:
        if not ax.get_title():
            continue                                # colour bars
        (curve,) = [ln for ln in ax.get_lines() if ln.get_linestyle() == "--"]
        v, cc = curve.get_xdata(), curve.get_ydata()
        np.testing.assert_array_equal(cc, c)
        np.testing.assert_allclose(v, vstar, rtol=1e-12)
