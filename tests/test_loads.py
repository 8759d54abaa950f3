"""A periodic load's shape as data (``sweepcore.PeriodicLoad``): its API, its files and
its axis.

What is proven: ``from_samples`` recovers a trigonometric polynomial from its samples
(coefficients to 1e-12, the samples to 1e-9 of the largest, ``truncation`` stated),
and refuses by name what it cannot represent; a load dimension of a Grid gives each
shape's response as a Params with that shape does; a study names a load by its
coefficients, by a CSV of samples or as an array (a dimension), and refuses a bad
one with its key and line; ``sweepcore simulate --load`` runs a slider under the
load of a CSV file, whose force the result carries.
"""
import math

import numpy as np
import pytest

import sweepcore as sc


def _series(a, b, theta):
    n = np.arange(1, len(a) + 1)
    return np.sum(np.asarray(a) * np.cos(n * theta[:, None]) +
                  np.asarray(b) * np.sin(n * theta[:, None]), -1)


# ---------------------------------------------------------------- samples
@pytest.mark.parametrize("m", [16, 17, 64])
def test_from_samples_recovers_a_trigonometric_polynomial(m):
    """Samples of p with 3 harmonics at m uniform phases: the coefficients back to
    1e-12, no more harmonics kept than p has, the truncation below 1e-9 of the
    largest sample, and p between the samples too."""
    a, b = [0.7, 0.0, -0.25], [0.1, 0.4, 0.05]
    theta = 2.0 * np.pi * np.arange(m) / m
    load = sc.PeriodicLoad.from_samples(_series(a, b, theta), name="three")
    assert load.harmonics == 3 and load.name == "three"
    np.testing.assert_allclose(load.cos, a, atol=1e-12)
    np.testing.assert_allclose(load.sin, b, atol=1e-12)
    assert load.truncation <= 1e-9 * np.max(np.abs(_series(a, b, theta)))
    fine = np.linspace(0.0, 2.0 * np.pi, 1001)
    np.testing.assert_allclose(load.values(fine), _series(a, b, fine), atol=1e-12)


def test_from_samples_keeps_the_harmonics_it_needs_and_says_how_far():
    """A square-ish wave (odd harmonics 1/n up to 31, sampled at 128 phases): the
    kept harmonics reproduce every sample to 1e-9 of the largest, and no fewer
    would."""
    theta = 2.0 * np.pi * np.arange(128) / 128
    v = sum(np.sin(n * theta) / n for n in range(1, 32, 2))
    load = sc.PeriodicLoad.from_samples(v)
    assert load.truncation <= 1e-9 * np.max(np.abs(v))
    assert np.max(np.abs(load.values(theta) - v)) == pytest.approx(load.truncation)
    assert load.harmonics == 31


@pytest.mark.parametrize("values, message", [
    (np.cos(2 * np.pi * np.arange(32) / 32) + 0.2, "mean of 0.2.*Subtract the mean"),
    ((lambda x: x - x.mean())(np.random.default_rng(1).normal(size=1000)),
     "harmonics are needed.*at most 128"),
    ([1.0, -1.0], "at least 3 samples"),
    ([1.0, float("nan"), -1.0], r"values\[1\] must be a finite number"),
    (np.zeros(8), "every sample is 0"),
])
def test_from_samples_refuses_what_it_cannot_represent(values, message):
    with pytest.raises(ValueError, match=message):
        sc.PeriodicLoad.from_samples(values)


@pytest.mark.parametrize("kwargs, error, message", [
    (dict(), ValueError, "at least one coefficient"),
    (dict(cos=[0.0, 0.0]), ValueError, "every coefficient is 0"),
    (dict(cos=[1.0, "x"]), ValueError, r"cos\[1\] must be a finite number"),
    (dict(sin=np.ones((2, 2))), TypeError, "sin must be a 1-D sequence"),
    (dict(cos=np.ones(129)), ValueError, "at most 128 harmonics"),
    (dict(cos=[1.0], name=""), ValueError, "name must be a non-empty string"),
])
def test_bad_coefficients_are_refused_by_name(kwargs, error, message):
    with pytest.raises(error, match=message):
        sc.PeriodicLoad(**kwargs)


def test_a_load_needs_its_amplitude_and_is_one_in_params():
    load = sc.PeriodicLoad(cos=[1.0, 0.5])
    with pytest.raises(ValueError, match="F0 .kN. is needed"):
        sc.Params(m=1.0, k=1.0, r_y=1.0, v=1.0, Y0=0.1, Omega=1.0, load=load)
    with pytest.raises(TypeError, match="load=\\[...\\]"):
        sc.Params(m=1.0, k=1.0, r_y=1.0, v=1.0, F0=1.0, Omega=1.0, load=[load, load])
    with pytest.raises(TypeError, match="load must be a sweepcore.PeriodicLoad"):
        sc.Params(m=1.0, k=1.0, r_y=1.0, v=1.0, F0=1.0, Omega=1.0, load="cos")


# ------------------------------------------------------------------ an axis
def test_a_load_dimension_is_each_shapes_response():
    """Grid(load=[a, b]): a dimension ``load`` labelled by the names, after the law's
    place and before the swept axes, whose every point is the Params run with that
    shape; the shapes' coefficients ride along as variables over ``load``."""
    a = sc.PeriodicLoad(cos=[1.0], name="cos")
    b = sc.PeriodicLoad(cos=[0.6, 0.0, 0.3], sin=[0.0, 0.4], name="tool")
    om = [0.9, 1.4]
    kw = dict(m=1.0, k=1.0, r_y=0.6, r_k=0.4, v_s=0.5, c=0.05, v=0.4, F0=1.0, x0=0.0,
              xdot0=0.0)
    ds = sc.sweep(sc.Grid(**kw, Omega=om, load=[a, b]), progress=False)
    assert ds.amplitude.dims == ("load", "Omega")
    assert list(ds["load"].values) == ["cos", "tool"]
    assert ds.load_cos.sel(load="tool").item() == "0.59999999999999998, 0, 0.29999999999999999"
    start = {n: kw.pop(n) for n in ("x0", "xdot0")}
    for shape in (a, b):
        for w in om:
            one = sc.attractor(sc.Params(**kw, Omega=w, load=shape), **start)
            got = ds.sel(load=shape.name, Omega=w)
            assert got["amplitude"].item() == one.amplitude
            assert got["mean"].item() == one.mean


def test_a_grid_of_loads_refuses_names_twice_and_loads_without_amplitude():
    a = sc.PeriodicLoad(cos=[1.0], name="same")
    b = sc.PeriodicLoad(sin=[1.0], name="same")
    with pytest.raises(ValueError, match="distinct names"):
        sc.Grid(m=1.0, k=1.0, r_y=1.0, v=0.5, F0=1.0, Omega=[1.0, 2.0], load=[a, b])
    with pytest.raises(ValueError, match="F0 = 0 at every point"):
        sc.Grid(m=1.0, k=1.0, r_y=1.0, v=0.5, Y0=0.2, Omega=[1.0, 2.0], load=a)


# ------------------------------------------------------------- files
STUDY = """title = "loads"
[axes]
m = 1.0
k = 1.0
r_y = 0.6
v = 0.4
c = 0.05
x0 = 0.0
xdot0 = 0.0
[excitation]
F0 = 1.0
Omega = [0.9, 1.4]
{load}
"""


def test_a_study_names_its_load_by_coefficients_samples_or_an_array(tmp_path):
    from sweepcore.study import load_study
    theta = 2.0 * np.pi * np.arange(24) / 24
    (tmp_path / "force.csv").write_text("force [1]\n" + "\n".join(
        f"{x:.17g}" for x in np.cos(theta) + 0.3 * np.sin(2 * theta)) + "\n")
    for text, want in (
            ('load = { cos = [1.0, 0.0, 0.2], sin = [0.0, 0.3], name = "tool" }',
             ([1.0, 0.0, 0.2], [0.0, 0.3, 0.0])),
            ('load = { samples = "force.csv" }', ([1.0, 0.0], [0.0, 0.3]))):
        path = tmp_path / "s.toml"
        path.write_text(STUDY.format(load=text))
        load = load_study(path).grid().load
        np.testing.assert_allclose(load.cos, want[0], atol=1e-12)
        np.testing.assert_allclose(load.sin, want[1], atol=1e-12)
    path.write_text(STUDY.format(load='load = [{ name = "a", cos = [1.0] }, '
                                      '{ name = "b", sin = [1.0] }]'))
    grid = load_study(path).grid()
    assert grid.dims[0] == "load" and [one.name for one in grid.loads] == ["a", "b"]


@pytest.mark.parametrize("text, message", [
    ('load = { cos = [0.0] }', "every coefficient is 0"),
    ('load = { samples = "none.csv" }', "cannot read the load file"),
    ('load = { cos = [1.0], samples = "force.csv" }', "not both"),
    ('load = { cosine = [1.0] }', "cosine"),
    ('load = 1.0', "must be a table"),
])
def test_a_bad_load_in_a_study_is_refused_with_its_line(tmp_path, text, message):
    from sweepcore.study import StudyError, load_study
    path = tmp_path / "s.toml"
    path.write_text(STUDY.format(load=text))
    with pytest.raises(StudyError, match=message) as err:
        load_study(path)
    assert f"{path}:13: excitation.load" in str(err.value)     # the key's line


def test_simulate_takes_a_load_file(tmp_path, monkeypatch, capsys):
    """``sweepcore simulate --load FILE.csv``: the result's external force is
    F0 p(Omega t + phi) of the file's shape; an empty path is refused by name."""
    import xarray as xr

    from sweepcore.cli import main
    monkeypatch.chdir(tmp_path)
    theta = 2.0 * np.pi * np.arange(16) / 16
    (tmp_path / "p.csv").write_text("\n".join(
        f"{x:.17g}" for x in np.cos(theta) - 0.5 * np.sin(3 * theta)))
    rc = main(["simulate", "--m", "1", "--k", "1", "--r-y", "0.4", "--v", "0.3",
               "--F0", "1.5", "--Omega", "1.1", "--phi", "0.2", "--load", "p.csv",
               "--t-end", "6", "-o", "run.nc"])
    assert rc == 0
    ds = xr.open_dataset(tmp_path / "run.nc")
    t = ds.time.values.astype(float) if ds.time.dtype.kind == "f" else \
        (ds.time.values - ds.time.values[0]) / np.timedelta64(1, "s")
    th = 1.1 * t + 0.2
    np.testing.assert_allclose(ds.external_force.values,
                               1.5 * (np.cos(th) - 0.5 * np.sin(3 * th)), atol=1e-12)
    ds.close()
    capsys.readouterr()
    assert main(["simulate", "--m", "1", "--k", "1", "--r-y", "0.4", "--v", "0.3",
                 "--F0", "1", "--Omega", "1", "--load", "", "--t-end", "1"]) != 0
    assert "--load '': the path is empty" in capsys.readouterr().err
