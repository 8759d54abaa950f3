"""The forced slider in study files, on the command line, in pictures and curves.

What is proven:
* an ``[excitation]`` table gives the Grid's F0, Omega, phi, Y0 axes (scalars,
  arrays, ranges as in ``[axes]``); a missing Omega, an unknown key (with "did you
  mean"), a value out of range, an excitation key in ``[axes]``, a forced study with
  a ``[boundary]`` table and ``periods`` out of range are refused with the key and
  its line;
* ``sweepcore simulate --F0 --Omega`` runs the forced slider: its ``external_force``
  is the closed form F0 cos(Omega t + phi) + k Y0 cos(Omega t) to rounding; an
  excitation without --Omega is refused (exit 2) naming Omega;
* ``sweepcore run`` on a forced study writes the map and its picture, ``info``
  counts its stops per period as the file holds them, ``plot`` draws it;
* frequency-response curves: across the critical load of a belt with Coulomb
  friction the curve jumps from the linear amplitude (closed form, 1e-7) to a
  sticking response, in both sweeps; on Den Hartog's oscillator (one response at each
  frequency) the up and down sweeps agree and both equal Den Hartog's closed-form
  amplitude to 1e-7 relative; the start handed to the next point is a fixed point
  of the stroboscopic map (one more period returns to it within 1e-6 of the
  amplitude); the stroboscopic diagram of a period-T response is one point per
  parameter value;
* the map's classes (counts, stuck, not ok) are drawn from the data as built here,
  and the continuous-motion boundary is drawn only in Den Hartog's case.
"""
from __future__ import annotations

import math
import sys
import textwrap
import types

import numpy as np
import pytest
import xarray as xr

import sweepcore as sc
from sweepcore.study import StudyError, parse_study

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"

BASE = textwrap.dedent("""\
    title = "forced"
    [axes]
    m = 1.0
    k = 1.0
    r_y = 0.3
    v = 0.0
    """)


def den_hartog_amplitude(beta, r):
    """Den Hartog (1930): scaled amplitude x0 = sqrt(V^2 - (r U)^2) of the steady
    motion without sticks (c = 0, v = 0, F0 = k = m = 1, r = r_y/F0)."""
    V = 1.0 / (1.0 - beta ** 2)
    U = math.tan(math.pi / (2.0 * beta)) / beta
    return math.sqrt(V ** 2 - (r * U) ** 2)


# ------------------------------------------------------------------ study files
def test_excitation_table_gives_the_grid_axes():
    s = parse_study(BASE + textwrap.dedent("""\
        [excitation]
        F0 = { start = 0.5, stop = 2.0, num = 4 }
        Omega = [0.5, 1.5, 2.5]
        phi = 0.25
        [solver]
        periods = 8
        """), "f.toml")
    grid = s.grid()
    assert grid.forced and grid.dims == ("F0", "Omega") and grid.shape == (4, 3)
    np.testing.assert_array_equal(grid.axis("F0"), np.linspace(0.5, 2.0, 4))
    np.testing.assert_array_equal(grid.axis("Omega"), [0.5, 1.5, 2.5])
    assert grid.axis("phi") == 0.25 and s.options == {"periods": 8}


@pytest.mark.parametrize("extra, where, message", [
    ("[excitation]\nF0 = 1.0\n", ":7: excitation: ", "Omega (the excitation "
     "frequency [rad s-1], > 0) is required with F0"),
    ("[excitation]\nF0 = 1.0\nOmegaa = 2.0\n", ":9: excitation.Omegaa: ",
     "unknown key 'Omegaa' in [excitation]; did you mean 'Omega'?"),
    ("[excitation]\nF0 = 1.0\nOmega = -2.0\n", ":9: excitation.Omega: ",
     "Omega must be > 0 [rad s-1], got -2.0"),
    ("[excitation]\nY0 = 1.0\nOmega = { start = 1.0, stop = 2.0 }\n",
     ":9: excitation.Omega: ", "a range needs start, stop and num; 'num' is missing"),
    ("F0 = 2.0\n", ":7: axes.F0: ", "F0 is a key of the excitation: move it to an "
     "[excitation] table"),
    ("[excitation]\nF0 = 1.0\nOmega = 2.0\n[boundary]\n", ":10: boundary: ",
     "[boundary] applies to the unforced slider"),
    ("[solver]\nperiods = 40\n", ":8: solver.periods: ",
     "must be an integer in [1, 19], got 40"),
])
def test_bad_excitation_refused_with_key_and_line(extra, where, message):
    with pytest.raises(StudyError) as err:
        parse_study(BASE + extra, "f.toml")
    assert str(err.value).startswith("f.toml" + where + message), str(err.value)


def test_forced_study_refuses_an_autonomous_method():
    with pytest.raises(StudyError, match="solver.method: method 'exact' is not "
                                         "available for a forced slider"):
        parse_study(BASE + '[excitation]\nF0 = 1.0\nOmega = 2.0\n[solver]\n'
                           'method = "exact"\n', "f.toml")


# ------------------------------------------------------------------ command line
def run_in_process(argv, tmp_path, monkeypatch, capsys):
    from sweepcore.cli import main
    monkeypatch.chdir(tmp_path)
    code = main(argv)
    return code, capsys.readouterr()


def test_simulate_flags_drive_the_slider(tmp_path, monkeypatch, capsys):
    """--F0 --Omega --phi --Y0 reach the slider: the stored external force is the
    closed form of the load plus the anchor's spring force (c = 0)."""
    code, out = run_in_process(
        ["simulate", "--m", "1", "--k", "2", "--r-y", "0.3", "--v", "0", "--F0", "1.5",
         "--Omega", "2.5", "--phi", "0.4", "--Y0", "0.2", "--t-end", "10", "-o",
         "run.nc", "--png", "run.png"], tmp_path, monkeypatch, capsys)
    assert code == 0, out.err
    assert "excitation: F0 = 1.5 kN, Omega = 2.5 rad s-1" in out.out
    ds = xr.open_dataset(tmp_path / "run.nc", decode_times=False,
                         decode_timedelta=False)
    t = ds.time.values
    expect = 1.5 * np.cos(2.5 * t + 0.4) + 2.0 * 0.2 * np.cos(2.5 * t)
    np.testing.assert_allclose(ds.external_force.values, expect, rtol=0, atol=1e-12)
    assert float(ds.F0) == 1.5 and float(ds.Omega) == 2.5
    assert (tmp_path / "run.png").read_bytes()[:8] == PNG_MAGIC


def test_simulate_on_fixed_ground_names_the_load_and_draws_forces(tmp_path,
                                                                  monkeypatch, capsys):
    """At v = 0 the summary says there is no Hopf point (it printed "v* = nan
    ... (none Hopf point)"); the picture's title names F0 and Omega with their
    units, and its top row draws the load and the friction force instead of x and
    xdot again (z = x - v t is x there)."""
    code, out = run_in_process(
        ["simulate", "--m", "1", "--k", "1", "--r-y", "0.3", "--v", "0", "--F0", "1",
         "--Omega", "0.8", "--t-end", "20", "-o", "run.nc"], tmp_path, monkeypatch,
        capsys)
    assert code == 0, out.err
    analytic = next(ln for ln in out.out.splitlines() if "analytic:" in ln)
    assert "nan" not in analytic and "no Hopf point" in analytic
    ds = sc.open_result(tmp_path / "run.nc")
    fig = sc.plot_trajectory(ds)
    title = fig._suptitle.get_text()
    assert "$F_0$ = 1 kN" in title and r"$\Omega$ = 0.8 rad/s" in title
    top = [ln.get_ydata() for ax in fig.axes[:3] for ln in ax.lines]
    assert not any(np.array_equal(y, ds[n].values) for y in top for n in ("x", "xdot"))
    assert any(np.array_equal(y, ds.external_force.values) for y in top)
    assert any(np.array_equal(y, ds.r_a.values) for y in top)


def test_simulate_excitation_without_frequency_refused(tmp_path, monkeypatch, capsys):
    code, out = run_in_process(
        ["simulate", "--m", "1", "--k", "1", "--r-y", "0.3", "--v", "0", "--F0", "1",
         "-o", "run.nc"], tmp_path, monkeypatch, capsys)
    assert code == 2
    assert "the excitation frequency Omega [rad s-1] is required with F0=1.0" in out.err
    assert not (tmp_path / "run.nc").exists()


def test_run_info_plot_of_a_forced_study(tmp_path, monkeypatch, capsys):
    """A 2 x 2 forced map: run writes it and its picture; info's stops-per-period
    counts are those of the file; plot redraws it."""
    (tmp_path / "f.toml").write_text(BASE + textwrap.dedent("""\
        [excitation]
        F0 = [0.2, 1.0]
        Omega = [2.0, 3.0]
        [output]
        path = "f.nc"
        """))
    code, out = run_in_process(["run", "f.toml"], tmp_path, monkeypatch, capsys)
    assert code == 0, out.err
    assert (tmp_path / "f.png").read_bytes()[:8] == PNG_MAGIC
    ds = sc.open_result(tmp_path / "f.nc")
    assert ds.stops_per_period.dims == ("F0", "Omega")
    # F0 = 0.2 < r_y = 0.3: the slider never leaves its start; F0 = 1.0 with
    # r/F0 = 0.3 below the continuous-motion boundary: two stops, no stick
    assert list(ds.regime.sel(F0=0.2).values) == [4, 4]           # stuck
    assert list(ds.stops_per_period.sel(F0=1.0).values) == [2, 2]
    values, counts = np.unique(ds.stops_per_period.values, return_counts=True)
    expect = ", ".join(f"{'none measured' if v < 0 else v} {c}"
                       for v, c in zip(values, counts))
    code, out = run_in_process(["info", "f.nc"], tmp_path, monkeypatch, capsys)
    assert code == 0
    assert f"zero-duration stops per period: {expect}" in out.out
    assert "Omega    excitation frequency [rad s-1]: 2 values" in out.out
    code, out = run_in_process(["plot", "f.nc", "-o", "again.png"], tmp_path,
                               monkeypatch, capsys)
    assert code == 0 and (tmp_path / "again.png").read_bytes()[:8] == PNG_MAGIC


# ------------------------------------------------------------------ curves
DH = sc.Params(m=1.0, k=1.0, r_y=0.3, v=0.0, F0=1.0, Omega=2.0)


def test_info_names_stroboscopic_samples_and_study_files(tmp_path, monkeypatch,
                                                         capsys):
    """info calls a stroboscopic diagram's samples what they are (x at t = j T),
    not a law's table; given a study file, info, plot and export say to run it,
    with the command and the result the study writes (not "write it again")."""
    ds = sc.stroboscopic_diagram(DH, "Omega", [2.0, 2.5], periods=3, transient=2)
    sc.write_netcdf(ds, tmp_path / "s.nc")
    code, out = run_in_process(["info", "s.nc"], tmp_path, monkeypatch, capsys)
    assert code == 0, out.err
    line = next(ln for ln in out.out.splitlines() if ln.startswith("  sample:"))
    assert "law" not in line
    assert line.startswith("  sample: 3 stroboscopic samples per value of Omega (x, "
                           "xdot at t = j T")
    (tmp_path / "f.toml").write_text(BASE + textwrap.dedent("""\
        [excitation]
        F0 = 1.0
        Omega = [2.0, 3.0]
        [output]
        path = "out/f.nc"
        """))
    for command in ("info", "plot", "export"):
        argv = [command, "f.toml"] + (["--csv", "f.csv"] if command == "export" else [])
        code, out = run_in_process(argv, tmp_path, monkeypatch, capsys)
        assert code == 2
        assert "f.toml is a study file, not a result file: run it with `sweepcore run " \
            "f.toml` (it writes out/f.nc), then `sweepcore " + command + " out/f.nc" \
            in out.err
        assert "write it again" not in out.err


def test_frequency_response_sweeps_agree_on_den_hartog():
    """Den Hartog's oscillator has one response at each frequency: both sweeps find
    it, each at the closed-form amplitude to 1e-7 relative, and nothing coexists."""
    Om = np.array([1.6, 2.0, 2.6])
    ds = sc.frequency_response(DH, Om, xdot0=0.0)
    assert (ds.status.values == 0).all() and not ds.coexisting.values.any()
    expect = [den_hartog_amplitude(w, 0.3) for w in Om]
    for s in ("up", "down"):
        np.testing.assert_allclose(ds.amplitude.sel(sweep=s).values, expect, rtol=1e-7)
    np.testing.assert_array_equal(ds.stops_per_period.values, 2)
    # the down sweep's first point started from the up sweep's last response
    assert ds.start_x.sel(sweep="down", Omega=2.6) == ds.start_x.sel(sweep="down",
                                                                     Omega=2.6)
    assert abs(float(ds.start_x.sel(sweep="down", Omega=2.6))) <= expect[-1] * (1 + 1e-6)


def test_frequency_response_jumps_at_the_critical_load():
    """A belt (v = 1), Coulomb friction, damping: where F0 < F0_crit(Omega) =
    v |k - m Omega^2 + i c Omega| / Omega the slider never reaches the belt and both
    sweeps find the linear amplitude F0 / |k - m Omega^2 + i c Omega| (1e-7
    relative); where F0 > F0_crit it sticks (the jump of the curve), in both."""
    m, k, c, v, F0 = 1.0, 1.0, 0.1, 1.0, 0.15
    p = sc.Params(m=m, k=k, r_y=1.0, v=v, c=c, F0=F0, Omega=1.0)
    Om = np.array([0.8, 0.9, 0.97, 1.0])
    ds = sc.frequency_response(p, Om, x0=1.0, xdot0=0.9)
    assert (ds.status.values == 0).all() and not ds.coexisting.values.any()
    for w in Om:
        crit = v * math.hypot(k - m * w * w, c * w) / w
        for s in ("up", "down"):
            pt = ds.sel(sweep=s, Omega=w)
            if F0 < crit:
                assert int(pt.sticks_per_period) == 0
                assert float(pt.amplitude) == pytest.approx(
                    F0 / math.hypot(k - m * w * w, c * w), rel=1e-7)
            else:
                assert int(pt.sticks_per_period) >= 1


def test_settled_state_is_on_the_stroboscopic_cycle():
    """The start handed to the next point is a fixed point of the stroboscopic map
    of a period-T response: one more forcing period returns to it."""
    from sweepcore.response_curves import settled_state
    res = sc.attractor(DH, x0=0.0, xdot0=0.0)
    x, xd = settled_state(DH, res, 0.0, 0.0)
    T = 2 * math.pi / DH.Omega
    run = sc.simulate(DH, t_end=T, x0=x, xdot0=xd, output_dt=T)
    scale = den_hartog_amplitude(2.0, 0.3)
    assert abs(float(run.x[-1]) - x) < 1e-6 * scale
    assert abs(float(run.xdot[-1]) - xd) < 1e-6 * scale * DH.Omega
    assert abs(x) <= res.amplitude * (1 + 1e-9)


def test_stroboscopic_diagram_of_period_one_responses():
    """A period-T response is one point per value: the samples agree to 1e-6 of
    the amplitude, and lie inside [x_min, x_max] of the response."""
    Om = np.array([1.8, 2.4])
    ds = sc.stroboscopic_diagram(DH, "Omega", Om, periods=4, transient=150)
    assert (ds.status.values == 0).all() and ds.x.dims == ("Omega", "sample")
    for w in Om:
        xs = ds.x.sel(Omega=w).values
        amp = den_hartog_amplitude(w, 0.3)
        assert np.ptp(xs) < 1e-6 * amp
        assert np.all(np.abs(xs) <= amp * (1 + 1e-6))


def test_curve_arguments_refused():
    with pytest.raises(ValueError, match="direction must be one of"):
        sc.frequency_response(DH, [1.0, 2.0], direction="upward")
    with pytest.raises(ValueError, match="params must be a forced slider"):
        sc.frequency_response(sc.Params(m=1, k=1, r_y=0.3, v=0.0), [1.0, 2.0])
    with pytest.raises(ValueError, match="name must be a parameter of Params"):
        sc.stroboscopic_diagram(DH, "omega2", [1.0, 2.0])
    with pytest.raises(ValueError, match="Omega must be a 1-D array of >= 2"):
        sc.frequency_response(DH, [2.0])


# ------------------------------------------------------------------ pictures
def _fake_map(v=0.0, c=0.0):
    """A 2 x 3 forced map built here: counts, a stuck cell, a cell not ok."""
    F0, Om = np.array([0.5, 2.0]), np.array([0.5, 1.0, 2.0])
    stops = np.array([[-1, 2, 2], [0, 2, 2]])
    return xr.Dataset(
        {"stops_per_period": (("F0", "Omega"), stops),
         "sticks_per_period": (("F0", "Omega"), np.array([[-1, 0, 0], [4, 0, 0]])),
         "multiplicity": (("F0", "Omega"), np.array([[1.0, 1.0, 1.0], [2.0, 1, 1]])),
         "amplitude": (("F0", "Omega"), np.array([[0.0, 1, 2], [3, 4, 5]])),
         "regime": (("F0", "Omega"), np.array([[4, 1, 1], [2, 1, 1]], np.int8)),
         "status": (("F0", "Omega"), np.array([[0, 0, 9], [0, 0, 0]], np.int8))},
        {"F0": ("F0", F0, {"units": "kN"}), "Omega": ("Omega", Om, {"units": "rad s-1"}),
         "v": v, "c": c, "r_y": 1.0, "r_k": 1.0, "alpha1": 0.0, "alpha2": 0.0,
         "Y0": 0.0, "omega": 1.0})


def test_map_classes_follow_the_data():
    from sweepcore.plot.forced import _classes
    cls, order = _classes(_fake_map(), "stops_per_period")
    names = np.array(order)[cls]
    assert names.tolist() == [["stuck", "2", "not ok"], ["0", "2", "2"]]
    cls, order = _classes(_fake_map(), "multiplicity")
    assert np.array(order)[cls].tolist() == [["stuck", "1", "not ok"], ["2", "1", "1"]]


def test_map_of_chosen_variables_names_them_and_masks_stuck_points():
    """A forced map of chosen variables is titled by them (it kept the study's
    title), and a stuck point, which has no multiplier (the file holds floquet 1
    there), is masked in the colour map, drawn grey and named in the legend."""
    from sweepcore.plot.forced import plot_forced_map
    ds = _fake_map().assign(floquet=(("F0", "Omega"), np.array([[1.0, 0.2, 0.3],
                                                                [0.0, 0.5, 0.6]])))
    ds.floquet.attrs["long_name"] = "largest Floquet multiplier modulus"
    ds.amplitude.attrs["long_name"] = "vibration amplitude"
    ds.attrs["study_title"] = "Forced response map: stops and sticks per cycle"
    stuck = (ds.regime == 4).values
    fig = plot_forced_map(ds, variables=("amplitude", "floquet"))
    head = fig._suptitle.get_text().splitlines()[0]
    assert head.startswith("vibration amplitude and largest Floquet multiplier "
                           "modulus over")
    ax = next(a for a in fig.axes if a.get_title().startswith("largest Floquet"))
    drawn = np.ma.getmaskarray(ax.collections[0].get_array()).reshape(stuck.shape)
    assert drawn[stuck].all()                   # no value where it is stuck
    grey = np.ma.getmaskarray(ax.collections[1].get_array()).reshape(stuck.shape)
    assert (~grey == stuck).all()               # the grey layer: the stuck cells
    assert any(t.get_text().startswith("stuck: no motion, no floquet")
               for t in ax.get_legend().get_texts())


def test_frequency_response_picture_shows_the_load_and_the_multiplicity():
    """A frequency-response curve built here: its title names the load F0 with its
    unit, and a count per response period of a response repeating every 13
    forcing periods reads "6 per 13 T" (it read as 6 sticks a period), once for
    the two sweeps that agree; a period-T point gets no such mark."""
    from sweepcore.plot.forced import plot_frequency_response
    two = ("sweep", "Omega")
    ds = xr.Dataset(
        {"amplitude": (two, np.array([[1.0, 1.1], [1.0, 1.1]])),
         "sticks_per_period": (two, np.array([[1, 6], [1, 6]])),
         "multiplicity": (two, np.array([[1.0, 13.0], [1.0, 13.0]])),
         "status": (two, np.zeros((2, 2), np.int8))},
        {"sweep": ["up", "down"], "Omega": ("Omega", [1.06, 1.08],
                                             {"units": "rad s-1"}),
         "m": 1.0, "k": 1.0, "r_y": 1.0, "v": 1.0, "F0": 0.15, "phi": 0.0, "Y0": 0.0},
        {"sweepcore_kind": "frequency_response", "title": "curve"})
    ds.sticks_per_period.attrs["long_name"] = "finite sticks per period"
    fig = plot_frequency_response(ds, ("amplitude", "sticks_per_period"))
    assert "$F_0$ = 0.15 kN" in fig._suptitle.get_text()
    marks = [t.get_text() for t in fig.axes[1].texts]
    assert marks == ["6 per 13 T"]
    assert "per response period" in fig.axes[1].get_ylabel()


def test_continuous_motion_boundary_only_in_den_hartogs_case(monkeypatch):
    """With a theory module giving r_b(beta), F0 = r / r_b(Omega/omega) on fixed
    ground without damping; nothing on a belt or with damping."""
    from sweepcore.plot.forced import continuous_motion_boundary, plot_forced_map
    fake = types.ModuleType("sweepcore.excitations.theory")
    fake.continuous_motion_boundary = lambda beta: 0.5 + 0.0 * np.asarray(beta)
    monkeypatch.setitem(sys.modules, "sweepcore.excitations.theory", fake)
    import sweepcore.excitations as exc
    monkeypatch.setattr(exc, "theory", fake, raising=False)
    Om = np.array([0.5, 1.0, 2.0])
    np.testing.assert_allclose(continuous_motion_boundary(_fake_map(), Om), 2.0)
    assert continuous_motion_boundary(_fake_map(v=1.0), Om) is None
    assert continuous_motion_boundary(_fake_map(c=0.1), Om) is None
    fig = plot_forced_map(_fake_map())
    assert len(fig.axes[0].lines) == 1          # the boundary over the first panel


# ------------------------------------------------------------------ docs
def test_every_forced_variable_is_documented():
    """docs/variables.md lists every variable of a forced sweep, simulation,
    frequency-response curve and stroboscopic diagram with the units the files
    carry (a new variable fails here until it is documented)."""
    from test_docs import DOC, _sections, _unit_rows
    units = {}
    for heading, body in _sections(DOC.read_text()).items():
        if not heading.endswith("codes"):
            for name, u in _unit_rows(body).items():
                units.setdefault(name, set()).add(u)
    results = [
        sc.sweep(sc.Grid(m=1.0, k=1.0, r_y=0.3, v=0.0, F0=1.0, Omega=[2.0, 2.5]),
                 progress=False),
        sc.simulate(DH, 3.0),
        sc.frequency_response(DH, [2.0, 2.5], xdot0=0.0),
        sc.stroboscopic_diagram(DH, "Omega", [2.0, 2.5], periods=2, transient=2)]
    for ds in results:
        for name, var in ds.variables.items():
            assert name in units, f"{name} is not in docs/variables.md"
            assert var.attrs["units"] in units[name], (name, var.attrs["units"])


def test_coexistence_is_two_different_ok_responses():
    """Built here: different regimes, multiplicities or periodic amplitudes mark two
    responses; two aperiodic samples, agreeing ones, or a point not ok do not."""
    from sweepcore.response_curves import coexisting
    nan = np.nan
    ds = xr.Dataset({
        "regime": (("sweep", "Omega"), np.array([[1, 1, 8, 1, 8, 1],
                                                 [1, 1, 1, 1, 8, 2]])),
        "multiplicity": (("sweep", "Omega"), np.array([[1, 1, nan, 1, nan, 1],
                                                       [1, 1, 1, 2, nan, 1.0]])),
        "amplitude": (("sweep", "Omega"), np.array([[1.0, 1.0, 2.0, 1.0, 2.0, 1.0],
                                                    [1.0 + 1e-9, 1.5, 1.0, 1.0, 2.5,
                                                     3.0]])),
        "status": (("sweep", "Omega"), np.array([[0, 0, 0, 0, 0, 9],
                                                 [0, 0, 0, 0, 0, 0]]))})
    assert coexisting(ds).tolist() == [False, True, True, True, False, False]
