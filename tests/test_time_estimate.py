"""The size and the time of a call, told before it runs, and its limit.

What is proven:
* ``sc.estimate`` of a forced grid counts a forced response's variables: its
  ``output_bytes`` are the bytes of the Dataset the sweep returns (they were the
  autonomous columns' count);
* the time estimate runs the call's own points, a deterministic stratified sample
  (one index in each of ``count`` equal ranges, the same every call), each point's
  rows those of :meth:`Grid.rows`; the kernels are first run with a step budget of
  one (compiling or loading them, untimed), then timed with the sample's step cap;
  a point that reaches the cap below ``max_steps`` makes the estimate a lower bound
  ("at least"); nothing is timed with ``time=False`` or ``max_seconds=None``;
* a sweep estimated beyond ``max_seconds`` is refused (``SweepTooLong``, naming
  max_seconds and its value) and writes nothing; ``sweepcore run`` prints the
  estimate before work, refuses beyond ``--max-time`` naming it (exit 2, nothing
  written), and takes durations with units; its default is the API's;
* the analytic variables of a lazily written sweep over a law dimension are one
  call over the laws: the graph does not grow with the number of laws (a layer per
  law made a 1,000-law sweep with a path take 631 s), and its values are those of
  the in-memory path.
"""
from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import sweepcore as sc
from sweepcore import labels, timing
from sweepcore._kernels import layout

FORCED = dict(m=1.0, k=1.0, r_y=0.3, v=0.0)
STUDY = ('title = "t"\n[axes]\nm = 5.0\nk = 50.0\nr_y = 10.0\nalpha1 = 1.0\n'
         'v = { start = 0.5, stop = 10.0, num = 16 }\n'
         'alpha2 = { start = 1e-3, stop = 0.1, num = 8, spacing = "geometric" }\n')


def test_estimate_counts_a_forced_grids_variables():
    grid = sc.Grid(**{**FORCED, "v": [0.0, 0.5]}, F0=[1.0, 2.0], Omega=[0.5, 1.5, 2.5])
    est = sc.estimate(grid, time=False)
    ds = sc.sweep(grid, progress=False, max_seconds=None)
    assert est["output_bytes"] == sum(v.nbytes for v in ds.data_vars.values())
    assert "seconds" not in est


# ------------------------------------------------------------------- the sample
@pytest.mark.parametrize("size, count", [(1, 1), (7, 7), (1000, 64), (2 ** 62, 64)])
def test_the_sample_is_one_point_in_each_equal_range(size, count):
    idx = timing.sample_indices(size, count)
    assert idx.size == count
    lo = np.array([i * size // count for i in range(count)], dtype=object)
    hi = np.array([(i + 1) * size // count for i in range(count)], dtype=object)
    assert all(a <= int(i) < b for i, a, b in zip(idx, lo, hi))
    assert np.array_equal(idx, timing.sample_indices(size, count))   # deterministic


@pytest.mark.parametrize("mode", ["product", "points"])
def test_rows_at_are_the_grids_rows(mode):
    axes = dict(m=[1.0, 2.0, 3.0], k=[20.0, 30.0, 40.0], r_y=5.0, v=[0.5, 1.0, 2.0])
    grid = sc.Grid(**axes, mode=mode)
    idx = np.array([grid.size - 1, 0, grid.size // 2])
    expected = np.concatenate([grid.rows(int(i), int(i) + 1) for i in idx])
    assert np.array_equal(grid.rows_at(idx), expected, equal_nan=True)
    assert np.array_equal(grid.rows_at(np.arange(grid.size)), grid.rows(0, grid.size),
                          equal_nan=True)


def test_the_kernels_are_loaded_untimed_then_timed_with_the_cap(monkeypatch):
    calls = []
    real = timing._points

    def spy(grid, P, o):
        calls.append((P.shape[0], o[layout.O_MAX_STEPS]))
        return real(grid, P, o)
    monkeypatch.setattr(timing, "_points", spy)
    timing._TIMED.clear()
    grid = sc.Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, alpha2=0.01,
                   v=np.linspace(0.5, 10.0, 4096))
    est = sc.estimate(grid, max_steps=10 ** 6)
    assert calls[0][1] == 1.0 and calls[1][1] == timing.SAMPLE_STEPS
    assert all(a == b for a, b in zip(calls[::2], [(n, 1.0) for n, _ in calls[1::2]]))
    assert calls[-1][0] == est["timed_points"] <= grid.size / timing.SAMPLE_SHARE
    assert est["seconds"] == pytest.approx(est["seconds_per_point"] * grid.size)
    calls.clear()
    sc.estimate(grid, max_steps=10 ** 6)          # the same grid and options: kept
    assert calls == []
    sc.estimate(grid, time=False)
    sc.sweep(sc.Grid(m=5.0, k=50.0, r_y=10.0, v=[1.0, 2.0]), progress=False,
             max_seconds=None)
    assert calls == []


def test_a_point_cut_at_the_samples_steps_makes_a_lower_bound():
    # a forced point at Omega/omega = 1e-4 takes 5e5 steps (a forcing period of
    # 1e4 natural periods), more than the sample's cap
    slow = sc.Grid(m=5.0, k=50.0, c=1.0, r_y=10.0, v=2.0, F0=1.0, Omega=3.16e-4,
                   x0=0.2, xdot0=0.0)
    cut = sc.estimate(slow)
    assert cut["lower_bound"] and timing.time_text(cut).startswith("at least")
    whole = sc.estimate(slow, max_steps=timing.SAMPLE_STEPS)     # the cap is the user's
    assert not whole["lower_bound"]


# ------------------------------------------------------------------- the limit
def test_a_sweep_beyond_max_seconds_is_refused_and_writes_nothing(tmp_path):
    grid = sc.Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, alpha2=0.01,
                   v=np.linspace(0.5, 10.0, 64))
    with pytest.raises(timing.SweepTooLong, match=r"a sweep of 64 points would take "
                                                  r"(about|at least) .* more than "
                                                  r"max_seconds=1e-09"):
        sc.sweep(grid, path=tmp_path / "map.nc", max_seconds=1e-9, progress=False)
    assert list(tmp_path.iterdir()) == []
    for bad in (0, -1.0, float("nan"), "1h", True):
        with pytest.raises(ValueError, match=r"max_seconds must be a number of "
                                             r"seconds > 0 or None"):
            sc.sweep(grid, max_seconds=bad, progress=False)


def test_run_prints_the_estimate_and_refuses_beyond_max_time(tmp_path, capsys,
                                                            monkeypatch):
    from sweepcore.cli import main
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text(STUDY)
    assert main(["run", "s.toml", "-o", "m.nc", "--no-png", "--max-time", "1e-9"]) == 2
    out, err = capsys.readouterr()
    assert "sweepcore run s.toml: about" in out or "sweepcore run s.toml: at least" \
        in out
    assert "points timed here" in out
    assert "more than --max-time 1e-09" in err and "'none': no limit" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]
    assert main(["run", "s.toml", "-o", "m.nc", "--no-png", "--max-time", "2h"]) == 0


@pytest.mark.parametrize("text, seconds", [("90", 90.0), ("90s", 90.0),
                                           ("30min", 1800.0), ("2h", 7200.0),
                                           ("1d", 86400.0), ("none", None)])
def test_max_time_takes_durations(text, seconds):
    from sweepcore.cli.parser import build_parser, max_time
    assert max_time(text) == seconds
    args = build_parser().parse_args(["run", "s.toml"])
    assert args.max_time == timing.MAX_SECONDS


@pytest.mark.parametrize("text", ["0", "-5", "1x", "inf", "h"])
def test_max_time_refuses_what_is_not_a_duration(text):
    import argparse
    from sweepcore.cli.parser import max_time
    with pytest.raises(argparse.ArgumentTypeError, match=rf"got {text!r}"):
        max_time(text)


# ------------------------------------------------------------ many laws, lazily
def _laws(n):
    speed = np.linspace(0.0, 4.0, 7)
    return [sc.TableLaw(speed, 1.0 - 0.1 * speed + 1e-4 * i, name=f"t{i}")
            for i in range(n)]


def test_lazy_analytic_variables_do_not_grow_with_the_laws():
    import dask.array as dsa
    layers = {}
    for n in (3, 30):
        grid = sc.Grid(m=1.0, k=1.0, c=0.1, v=[0.5, 1.0], law=_laws(n))
        coords = {a: xr.DataArray(v) for a, v in grid.coords().items()}
        lazy = {a: xr.DataArray(dsa.from_array(c.values, chunks=2), dims=c.dims)
                if c.ndim else c for a, c in coords.items()}
        for name in ("q", "x_eq"):             # over (law, v): lazy
            da = labels.analytic(name, lazy, grid.dims, grid.laws)
            layers[n, name] = len(da.data.dask.layers)
            eager = labels.analytic(name, coords, grid.dims, grid.laws)
            np.testing.assert_array_equal(da.values, eager.values)
    assert all(layers[3, name] == layers[30, name] for name in ("q", "x_eq"))
