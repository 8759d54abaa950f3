"""Conventions a new user relies on, from Python and from the command line.

What is proven:
* the global options ``--threads`` and ``--traceback`` work after the subcommand
  as well as before it;
* ``sweepcore run STUDY -o OUT.nc`` replaces the study's outputs as a whole: the
  picture goes beside OUT.nc, not to the study's own png path (which may name a
  directory that exists only where the study lives);
* every name a user types gets "did you mean": keywords of every public function
  (``sweep(tolerance=...)`` names sweep and suggests ``tol``), plot and export
  variables, map axes, command-line options;
* the plotting API is exported from ``sweepcore`` without importing matplotlib on
  ``import sweepcore``.
"""
from __future__ import annotations

import inspect
import re
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import sweepcore as sc
from sweepcore.cli import build_parser, main

SMALL = textwrap.dedent("""\
    [axes]
    m = 5.0
    k = 50.0
    r_y = 10.0
    v = { start = 1.0, stop = 5.0, num = 3 }
    [solver]
    method = "exact"
    [output]
    path = "out/small.nc"
    png = "out/small.png"
    """)


@pytest.mark.parametrize("argv", [
    ["--threads", "1", "info", "r.nc"], ["info", "--threads", "1", "r.nc"],
    ["info", "r.nc", "--threads", "1"]])
def test_threads_before_or_after_the_subcommand(argv):
    assert build_parser().parse_args(argv).threads == 1


def test_traceback_after_the_subcommand_and_defaults():
    p = build_parser()
    assert p.parse_args(["info", "--traceback", "r.nc"]).traceback is True
    args = p.parse_args(["info", "r.nc"])
    assert args.threads is None and args.traceback is False


@pytest.fixture
def thread_settings(monkeypatch):
    """Environment and numba thread count restored after a ``--threads`` run."""
    import os

    import numba
    from sweepcore.cli.parser import THREAD_VARIABLES
    for name in THREAD_VARIABLES:
        if name in os.environ:
            monkeypatch.setenv(name, os.environ[name])
        else:
            monkeypatch.delenv(name, raising=False)
    n = numba.get_num_threads()
    yield
    numba.set_num_threads(n)


def test_run_with_threads_after_the_subcommand(tmp_path, monkeypatch, capsys,
                                               thread_settings):
    """In a process whose numba threads already run (the suite's), --threads limits
    them without touching NUMBA_NUM_THREADS, which numba re-reads at every
    compilation and would refuse (a later compile raised)."""
    import os

    import numba
    numba.get_num_threads()                  # numba's thread pool is launched
    before = os.environ.get("NUMBA_NUM_THREADS")
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text(SMALL.replace("out/", ""))
    assert main(["run", "--threads", "1", "s.toml", "-q"]) == 0
    assert (tmp_path / "small.nc").is_file()
    assert os.environ.get("NUMBA_NUM_THREADS") == before
    assert numba.get_num_threads() == 1
    numba.njit(lambda x: x + 1)(1)          # a compilation after it still works


def test_output_option_replaces_the_study_outputs_as_a_whole(tmp_path, monkeypatch,
                                                             capsys):
    """The study lives elsewhere and names out/small.png; -o puts both files here."""
    where = tmp_path / "studies"
    where.mkdir()
    study = where / "small.toml"
    study.write_text(SMALL)
    run = tmp_path / "elsewhere"
    run.mkdir()
    monkeypatch.chdir(run)
    assert main(["run", str(study), "-o", "x.nc", "-q"]) == 0, capsys.readouterr().err
    assert (run / "x.nc").is_file() and (run / "x.png").is_file()
    assert not (run / "out").exists()
    # without -o the study's own paths (relative to where the command runs) apply
    assert main(["run", str(study), "-q"]) == 2
    assert "directory 'out' of 'out/small.nc' does not exist" in capsys.readouterr().err


PUBLIC = [(sc.sweep, "tolerance", "tol"), (sc.attractor, "tolerance", "tol"),
          (sc.simulate, "tolerance", "tol"), (sc.estimate, "chunk", "chunks"),
          (sc.locate_boundaries, "xtl", "xtol"), (sc.continue_boundary, "ovr", "over"),
          (sc.bifurcation_diagram, "max_step", "max_steps"),
          (sc.hopf_boundary, "axs", "axis"), (sc.open_result, "pth", "path"),
          (sc.write_netcdf, "pth", "path"), (sc.check_cf, "dss", "ds")]


@pytest.mark.parametrize("fn, typo, right", PUBLIC, ids=[f[0].__name__ for f in PUBLIC])
def test_public_keyword_typos_name_the_function_and_suggest(fn, typo, right):
    """Refused before any work, as the caller's function, with the right name."""
    args = [object()] * sum(p.default is p.empty and p.kind == p.POSITIONAL_OR_KEYWORD
                            for p in inspect.signature(fn).parameters.values())
    with pytest.raises(TypeError) as err:
        fn(*args, **{typo: 1})
    text = str(err.value)
    assert text.startswith(f"{fn.__name__}() got an unexpected keyword argument "
                           f"'{typo}'; did you mean '{right}'?"), text
    assert "make_options" not in text


def test_every_public_function_checks_its_keywords():
    """Each public function of sweepcore (and the plotting API) refuses a typo with
    "did you mean"; a new public function without the check fails here."""
    for name in sc.__all__:
        fn = getattr(sc, name)
        if not inspect.isfunction(fn):
            continue
        with pytest.raises(TypeError, match="did you mean|allowed"):
            fn(no_such_keyword_xyz=1)


def test_keyword_check_keeps_signatures():
    assert list(inspect.signature(sc.sweep).parameters)[:3] == ["grid", "method", "tol"]
    assert "options" in inspect.signature(sc.attractor).parameters


def test_plot_variable_typo_is_suggested(tmp_path, capsys):
    ds = sc.sweep(sc.Grid(m=5.0, k=50.0, r_y=10.0, v=[1.0, 2.0, 3.0],
                          alpha2=0.0, alpha1=0.0), path=tmp_path / "r.nc")
    ds.close()
    assert main(["plot", str(tmp_path / "r.nc"), "--variables", "amplitud"]) == 2
    err = capsys.readouterr().err
    assert "'amplitud' is not a variable" in err and "did you mean 'amplitude'?" in err
    assert main(["export", str(tmp_path / "r.nc"), "--csv", str(tmp_path / "r.csv"),
                 "--variables", "regim"]) == 2
    assert "did you mean 'regime'?" in capsys.readouterr().err


def test_map_axis_typo_is_suggested(tmp_path, capsys):
    ds = sc.sweep(sc.Grid(m=5.0, k=[40.0, 50.0, 60.0], r_y=10.0, v=[1.0, 2.0, 3.0]),
                  path=tmp_path / "r.nc")
    ds.close()
    assert main(["plot", str(tmp_path / "r.nc"), "--x", "kk"]) == 2
    assert "did you mean 'k'?" in capsys.readouterr().err
    assert main(["plot", str(tmp_path / "r.nc"), "--x", "v", "--y", "v"]) == 2
    assert "two different axes" in capsys.readouterr().err


@pytest.mark.parametrize("argv, hint", [
    (["simulate", "--tolerance", "1e-3"], "did you mean --tol?"),
    (["run", "--threds", "2", "s.toml"], "did you mean --threads?"),
    (["boundary", "s.toml", "--ovr", "m.nc"], "did you mean --over?")])
def test_option_typos_are_suggested(argv, hint, capsys):
    assert main(argv) == 2
    assert hint in capsys.readouterr().err


def test_plotting_api_is_exported_lazily():
    code = ("import sys, sweepcore as sc; assert 'matplotlib' not in sys.modules; "
            "from sweepcore import plot_map; import sweepcore.plot as p; "
            "assert plot_map is p.plot_map and sc.plot_result is p.plot_result; "
            "assert 'matplotlib' in sys.modules")
    subprocess.run([sys.executable, "-c", code], check=True)
    for name in sc.PLOTS:
        assert name in sc.__all__ and name in dir(sc)
    with pytest.raises(AttributeError, match="did you mean 'plot_map'"):
        sc.plot_mapp


def test_plot_api_draws_a_sweep():
    ds = sc.sweep(sc.Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, v=np.linspace(1, 8, 5),
                          alpha2=[0.005, 0.01, 0.02, 0.04]))
    fig = sc.plot_map(ds)
    assert len(fig.axes) >= 2


def test_sweep_files_suit_xarray_and_csv(tmp_path, capsys):
    """v is the last dimension (xarray's default 2-D plot puts it on x), geometric
    axes say so, regime carries its flag names, n_steps is an integer in the file
    and in the CSV, and the history has one timestamp format."""
    import re

    import xarray as xr
    sc.sweep(sc.Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, v=np.linspace(1, 8, 5),
                     alpha2=np.geomspace(0.005, 0.04, 4)), path=tmp_path / "r.nc").close()
    with xr.open_dataset(tmp_path / "r.nc") as ds:
        assert ds.amplitude.dims[-1] == "v"
        mesh = ds.amplitude.plot()
        assert mesh.axes.get_xlabel().startswith("belt speed")
        assert ds.alpha2.attrs["spacing"] == "geometric"
        assert "stick_slip" in ds.regime.attrs["flag_meanings"].split()
        assert ds.n_steps.dtype == np.int64
        stamp = ds.attrs["history"].split()[0]
    assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\+00:00", stamp), stamp
    assert main(["export", str(tmp_path / "r.nc"), "--csv", str(tmp_path / "r.csv")]) == 0
    import csv
    with open(tmp_path / "r.csv") as f:
        row = next(csv.DictReader(f))
    assert re.fullmatch(r"\d+", row["n_steps"]), row["n_steps"]


def test_sticks_per_period_is_a_count_in_the_file_and_the_csv(tmp_path):
    """A count is stored as int64 (-1 where no attractor was measured: status not
    ok), so the CSV says "1", not "1.0"; stick-slip sticks once a period, an
    equilibrium never."""
    import csv
    grid = sc.Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, alpha2=0.01, v=[2.0, 8.0])
    sc.sweep(grid, path=tmp_path / "r.nc").close()
    sc.sweep(grid, path=tmp_path / "f.nc", max_steps=5).close()     # budget: failed
    ds, failed = sc.open_result(tmp_path / "r.nc"), sc.open_result(tmp_path / "f.nc")
    assert ds.sticks_per_period.dtype == np.int64
    regimes = dict(zip(ds.regime.attrs["flag_values"].tolist(),
                       ds.regime.attrs["flag_meanings"].split()))
    assert [regimes[int(r)] for r in ds.regime] == ["stick_slip", "equilibrium"]
    assert ds.sticks_per_period.values.tolist() == [1, 0]
    assert (failed.status.values != 0).all()
    assert failed.sticks_per_period.values.tolist() == [-1, -1]
    assert main(["export", str(tmp_path / "r.nc"), "--csv", str(tmp_path / "r.csv")]) == 0
    with open(tmp_path / "r.csv") as f:
        assert [row["sticks_per_period"] for row in csv.DictReader(f)] == ["1", "0"]


def test_faceted_maps_share_one_colour_scale():
    """Rows of a faceted map (a third swept axis) use one colour scale per
    variable: the same colour is the same amplitude in every row."""
    from matplotlib.collections import QuadMesh
    ds = sc.sweep(sc.Grid(m=[2.0, 5.0], k=50.0, r_y=10.0, alpha1=1.0,
                          v=np.linspace(1, 8, 5), alpha2=np.geomspace(0.005, 0.04, 4)))
    fig = sc.plot_map(ds, variables=("amplitude",))
    clims = {m.get_clim() for ax in fig.axes for m in ax.collections
             if isinstance(m, QuadMesh)}
    assert len(clims) == 1, clims
    lo, hi = clims.pop()
    assert lo == float(ds.amplitude.min()) and hi == float(ds.amplitude.max())


def test_boundary_picture_has_a_legend_of_the_regime_colours():
    import xarray as xr
    over = sc.sweep(sc.Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, v=np.linspace(1, 10, 8),
                            alpha2=np.geomspace(0.01, 0.04, 3)))
    curves = sc.continue_boundary(sc.Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0,
                                          v=[0.5, 14.0], alpha2=[0.01, 0.02, 0.04]))
    assert isinstance(curves, xr.Dataset)
    fig = sc.plot_boundaries(curves, over=over)
    names = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert any(n.startswith("regime: stick slip") for n in names), names
    assert "Hopf point (located)" in names


def test_info_and_plot_handle_a_bifurcation_diagram(tmp_path, capsys):
    ds = sc.bifurcation_diagram(sc.Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0,
                                        alpha2=0.01, v=np.linspace(4.0, 7.0, 7)))
    sc.write_netcdf(ds, tmp_path / "d.nc")
    assert main(["info", str(tmp_path / "d.nc")]) == 0
    assert "bifurcation diagram" in capsys.readouterr().out
    assert main(["plot", str(tmp_path / "d.nc"), "-o", str(tmp_path / "d.png")]) == 0
    assert (tmp_path / "d.png").stat().st_size > 10_000


@pytest.mark.parametrize("call, hint", [
    (lambda g: sc.sweep(g, method="dopri"), "did you mean 'dopri5'?"),
    (lambda g: sc.sweep(g, scheduler="thread"), "did you mean 'threads'?"),
    (lambda g: sc.locate_boundaries(g, along="vv"), "did you mean 'v'?"),
    (lambda g: sc.bifurcation_diagram(g, along="vv"), "did you mean 'v'?"),
    (lambda g: sc.hopf_boundary(sc.sweep(g), axis="vv"), "did you mean 'v'?")])
def test_names_given_as_values_get_did_you_mean(call, hint):
    grid = sc.Grid(m=5.0, k=50.0, r_y=10.0, v=[1.0, 2.0], alpha1=1.0, alpha2=0.01)
    with pytest.raises(ValueError, match=re.escape(hint)):
        call(grid)


def test_study_choice_typo_is_suggested(tmp_path, capsys):
    (tmp_path / "s.toml").write_text(SMALL.replace('"exact"', '"dopri"'))
    assert main(["run", str(tmp_path / "s.toml"), "-o", str(tmp_path / "s.nc")]) == 2
    assert "did you mean 'dopri5'?" in capsys.readouterr().err
