"""Boundaries to full precision: the root solvers, the Hopf point against v*, the
stick onset against a fine grid and against an independent scipy computation of the
grazing cycle, continuation, executors and the bifurcation diagram."""
import math

import numpy as np
import pytest

import sweepcore as sc
from sweepcore import boundaries as bd
from sweepcore.boundaries.drive import _together, lockstep
from sweepcore.boundaries.graze import _graze
from sweepcore.boundaries.point import _Point
from sweepcore._kernels import codes, layout

PAPER = dict(m=5.0, k=50.0, r_y=10.0, alpha1=1.0)
TOL = 1e-10      # attractor tolerance of these tests (the default of the searches)
# Hopf point: the extrapolated root inherits the amplitude error of the samples
# (~1e-9 cm at tol 1e-12), which moves it by ~1e-10 cm/s (benchmarks/README.md).
HOPF_TOL = 1e-9


# ----------------------------------------------------------- the root solvers
@pytest.mark.parametrize("f, a, b, root", [
    (lambda x: x ** 3 - 2.0, 0.0, 3.0, 2.0 ** (1 / 3)),
    (lambda x: math.tanh(50.0 * (x - 0.3)), -1.0, 1.0, 0.3),
    (lambda x: math.exp(x) - 10.0, 0.0, 100.0, math.log(10.0)),  # far-off end
    (lambda x: (x - 1.0) * abs(x - 1.0), 0.0, 5.0, 1.0),          # kink, f' = 0
])
def test_bracketed_root_meets_xtol(f, a, b, root):
    x = bd.bracketed_root(f, a, b, xtol=1e-12)
    assert abs(x - root) <= 1e-11


def test_bracketed_root_refuses_a_non_bracket():
    with pytest.raises(ValueError, match="no bracket"):
        bd.bracketed_root(lambda x: x * x + 1.0, -1.0, 1.0, 1e-9)


def _synthetic_rows(v0, asks):
    """Observables rows of a model with stick-slip below v0 and slip cycles above
    whose indicator g = v - xdot_max = 3 (v - v0) + 2 (v - v0)^2 (smooth)."""
    rows = []
    for v, _x0, _xd0 in asks:
        r = np.full(layout.NOBS, np.nan)
        r[layout.OB_STATUS] = codes.OK
        if v > v0:
            r[layout.OB_REGIME] = codes.R_SLIP_CYCLE
            d = v - v0
            r[layout.OB_XDOT_MAX] = v - (3.0 * d + 2.0 * d * d)
        else:
            r[layout.OB_REGIME] = codes.R_STICK_SLIP
            r[layout.OB_XDOT_MAX] = v
        r[layout.OB_X_MAX] = 1.0
        rows.append(r)
    return np.array(rows)


def test_graze_solver_finds_a_known_root_faster_than_bisection():
    v0 = 4.123456789012
    pt = _Point(sc.Params(m=5.0, k=50.0, r_y=10.0, v=4.0, alpha1=1.0, alpha2=0.01).row(0.0, 4.0),
                "v")
    solver = _graze(pt, 3.0, 6.0, xtol=1e-9)
    asks, evaluations = next(solver), 0
    try:
        while True:
            evaluations += len(asks)
            asks = solver.send(_synthetic_rows(v0, asks))
    except StopIteration as stop:
        out = stop.value
    assert out["status"] == bd.LOCATED
    assert abs(out["value"] - v0) <= 1e-9
    # bisection on the labels alone needs log2(3/1e-9) = 32 evaluations
    assert evaluations <= 16


def test_lockstep_hands_each_solver_its_own_rows_and_counts_its_requests():
    """Solvers asking different numbers of values per round, one of them two nested
    solvers run together: each gets the rows of its own requests (here the
    request itself, times 10) and the count of its requests comes back."""
    def solver(values):
        got = []
        for batch in values:
            got.extend((yield list(batch)))
        return got

    nested = _together([solver([[1.0], [2.0, 3.0]]), solver([[4.0]])])
    run = lockstep([solver([[5.0, 6.0]]), nested, solver([])])
    asks, rounds = next(run), 0
    try:
        while True:
            rounds += 1
            asks = run.send([10.0 * r for _owner, r in asks])
    except StopIteration as stop:
        results, evaluations = stop.value
    assert results == [[50.0, 60.0], [[10.0, 20.0, 30.0], [40.0]], []]
    assert evaluations.tolist() == [2, 4, 0]
    assert rounds == 2


# ------------------------------------------------------------- the Hopf point
@pytest.fixture(scope="module")
def located():
    """Boundaries of the paper's slider at three alpha2 (v* = 5.77, 3.33, 2.58)."""
    grid = sc.Grid(**PAPER, v=np.linspace(1.0, 7.0, 16), alpha2=[0.01, 0.03, 0.05])
    return bd.locate_boundaries(grid, tol=TOL)


def test_hopf_point_is_vstar_where_supercritical(located):
    """q = 0 at v* is where the equilibrium loses stability (eq. 46); the averaged
    cycle is stable there (supercritical), so the cycle's A^2 vanishes at v*."""
    assert (located.hopf_status == bd.LOCATED).all()
    err = np.abs(located.v_hopf - located.v_star)
    assert float(err.max()) <= HOPF_TOL


def test_hopf_point_is_vstar_for_other_constants():
    grid = sc.Grid(m=2.0, k=30.0, r_y=5.0, alpha1=0.5, alpha2=0.02,
                   v=np.linspace(1.0, 4.0, 12))
    ds = bd.locate_boundaries(grid, tol=TOL)
    assert int(ds.hopf_status) == bd.LOCATED
    assert abs(float(ds.v_hopf - ds.v_star)) <= HOPF_TOL


def test_result_is_cf_and_carries_units(located):
    assert sc.check_cf(located) == []
    assert located.v_hopf.attrs["units"] == "cm s-1"
    assert located.v_stick_onset.attrs["units"] == "cm s-1"
    ratio = located.v_stick_onset_estimate / located.v_star
    np.testing.assert_allclose(ratio, 2 / math.sqrt(5), rtol=1e-15)


def test_boundaries_lie_between_the_labels_of_a_fine_grid(located):
    """The located Hopf point lies between the fine grid's last cycle and first
    equilibrium; the stick onset between its last stick-slip and first slip cycle."""
    p = located.sel(alpha2=0.03)
    for name, below, above in (("v_hopf", codes.R_SLIP_CYCLE, codes.R_EQUILIBRIUM),
                               ("v_stick_onset", codes.R_STICK_SLIP,
                                codes.R_SLIP_CYCLE)):
        v0 = float(p[name])
        v = v0 + np.linspace(-2e-3, 2e-3, 8) * v0      # v0 itself excluded
        ds = sc.sweep(sc.Grid(**PAPER, alpha2=0.03, v=v), tol=TOL, progress=False)
        reg = ds.regime.values
        last = v[reg == below].max()
        first = v[(reg == above) & (v > last)].min()
        assert last < v0 < first, (name, last, v0, first)


def test_stick_onset_is_located_to_xtol(located):
    assert (located.stick_status == bd.LOCATED).all()
    assert float(located.v_stick_onset_width.max()) <= 1e-9


# ---------------------------------------------------- independent: scipy grazing
def _scipy_grazing(m, k, r_y, alpha1, alpha2):
    """v where the slip cycle's largest xdot equals v, from solve_ivp with events.

    The slip cycle (relative velocity zdot = xdot - v < 0 throughout) is the fixed
    point of the return map to the maxima of x (xdot = 0, falling), found by brentq;
    its largest xdot is found by an event on the acceleration (falling through 0).
    """
    from scipy.integrate import solve_ivp
    from scipy.optimize import brentq

    omega = math.sqrt(k / m)
    vstar = math.sqrt(alpha1 / (3 * alpha2))

    def rhs(_t, y):       # y = (x, zdot), sliding with zdot < 0: sgn = -1
        x, zd = y
        return [zd + v_[0], (-k * x - (-r_y - alpha1 * zd + alpha2 * zd ** 3)) / m]

    def xdot_zero(_t, y):
        return y[1] + v_[0]
    xdot_zero.direction = -1

    def accel(_t, y):
        return rhs(0.0, y)[1]
    accel.direction = -1

    def run(x0):       # 1.5 periods from a maximum of x, at rest
        v = v_[0]
        return solve_ivp(rhs, (0.0, 1.5 * 2 * math.pi / omega), [x0, -v],
                         method="DOP853", rtol=1e-13, atol=1e-15,
                         events=(xdot_zero, accel), first_step=1e-6)

    def returned(x0):
        sol = run(x0)
        hits = [(t, y) for t, y in zip(sol.t_events[0], sol.y_events[0]) if t > 0.1]
        return hits[0][1][0] - x0

    def g(v):
        v_[0] = v
        x_eq = (r_y - alpha1 * v + alpha2 * v ** 3) / k
        a = 2 * math.sqrt(max(vstar ** 2 - v ** 2, 0.0)) / omega
        xs = brentq(returned, x_eq + 0.7 * a, x_eq + 1.3 * a, xtol=1e-14)
        sol = run(xs)
        return v - max(y[1] + v for t, y in zip(sol.t_events[1], sol.y_events[1])
                       if t < sol.t_events[0][-1])

    v_ = [0.0]
    return brentq(g, 0.88 * vstar, 0.91 * vstar, xtol=1e-12)


def test_stick_onset_agrees_with_scipy_grazing_cycle(located):
    ref = _scipy_grazing(**PAPER, alpha2=0.01)
    got = float(located.v_stick_onset.sel(alpha2=0.01))
    assert abs(got - ref) <= 1e-9, (got, ref)


def test_both_boundaries_are_located_at_low_damping():
    """alpha1/sqrt(k m) = 0.0126: the slip cycles contract by ~1 % a period, a
    motion started inside a cycle just below the grazing grows only slowly onto
    the stick-slip cycle. The stick onset must still be located, between the
    labels of independent attractors started stuck on the belt just either side,
    and the Hopf point at v*."""
    c = dict(m=5.0, k=1250.0, r_y=10.0, alpha1=1.0, alpha2=0.03)
    ds = bd.locate_boundaries(sc.Grid(**c, v=[0.5, 5.0]), scan=24, tol=TOL)
    assert int(ds.hopf_status) == bd.LOCATED
    assert abs(float(ds.v_hopf - ds.v_star)) <= HOPF_TOL
    assert int(ds.stick_status) == bd.LOCATED
    vs = float(ds.v_stick_onset)
    below = sc.attractor(sc.Params(**c, v=vs * (1 - 1e-5)), tol=TOL)
    above = sc.attractor(sc.Params(**c, v=vs * (1 + 1e-5)), tol=TOL)
    assert below.regime == "stick_slip"
    assert above.regime == "slip_cycle" and above.xdot_max < vs * (1 + 1e-5)


@pytest.mark.parametrize("damping", [0.002, 0.001])
def test_hopf_point_is_vstar_at_very_low_damping(damping):
    """Cycles within 0.5 % of v* contract by ~1e-4 a period: the kernel cannot
    resolve them at tol 1e-10 (status unresolved), so the samples must move out."""
    c = dict(m=5.0, k=1.0 / (5.0 * damping ** 2), r_y=10.0, alpha1=1.0, alpha2=0.03)
    ds = bd.locate_boundaries(sc.Grid(**c, v=[0.5, 5.0]), scan=24, tol=TOL)
    assert int(ds.hopf_status) == bd.LOCATED
    assert abs(float(ds.v_hopf - ds.v_star)) <= HOPF_TOL


def test_boundaries_along_alpha2_at_fixed_speed():
    """Along alpha2 at v = 5: q = 0 at alpha2 = alpha1/(3 v^2) = 1/75 (eq. 46), and
    the stick onset where v = (v_stick/v*) v*(alpha2), the ratio measured along v."""
    grid = sc.Grid(**PAPER, v=5.0, alpha2=np.linspace(0.005, 0.02, 16))
    ds = bd.locate_boundaries(grid, along="alpha2", tol=TOL)
    assert abs(float(ds.v_hopf) - 1.0 / 75.0) <= 1e-9
    ratio = float(bd.locate_boundaries(sc.Grid(**PAPER, alpha2=0.01,
                                               v=np.linspace(1.0, 7.0, 16)),
                                       tol=TOL).pipe(lambda d: d.v_stick_onset
                                                     / d.v_star))
    assert abs(float(ds.v_stick_onset) - ratio ** 2 / 75.0) <= 1e-10


# ------------------------------------------------------------- continuation
def test_continuation_follows_both_curves_with_few_attractors(located):
    a2 = np.geomspace(0.01, 0.05, 12)
    ds = bd.continue_boundary(sc.Grid(**PAPER, alpha2=a2, v=[1.0, 7.0]), tol=TOL)
    assert (ds.hopf_status == bd.LOCATED).all()
    assert (ds.stick_status == bd.LOCATED).all()
    assert float(np.abs(ds.v_hopf - ds.v_star).max()) <= HOPF_TOL
    assert int(ds.continued.sum()) == a2.size - 2
    assert sc.check_cf(ds) == []
    # seeded steps cost a fraction of a scan's step (32 scan points alone)
    assert float(ds.evaluations[2:].mean()) < 0.5 * float(ds.evaluations[:2].mean())
    # the same boundaries as the scan-based search where the two meet
    for a in (0.01, 0.05):
        np.testing.assert_allclose(float(ds.v_stick_onset.sel(alpha2=a)),
                                   float(located.v_stick_onset.sel(alpha2=a)),
                                   rtol=0, atol=2e-9)


def test_continuation_where_predictions_are_imperfect():
    """Over alpha1 the stick onset is not a fixed multiple of v* (the damping
    alpha1/sqrt(k m) changes), so the predictions miss by more than xtol/4 and
    the steps take their third cycles or fall back: the stick onset must still
    agree with the scan-based search at every point, and the Hopf point with v*
    within its error estimate (at alpha1 = 2, damping 0.13, the samples' cubic
    extrapolation is off by ~3e-9 cm/s, and says so)."""
    a1 = np.geomspace(0.5, 2.0, 8)
    kw = dict(m=5.0, k=50.0, r_y=10.0, alpha2=0.01)
    ds = bd.continue_boundary(sc.Grid(**kw, alpha1=a1, v=[1.0, 14.0]),
                              over="alpha1", tol=TOL)
    ref = bd.locate_boundaries(sc.Grid(**kw, alpha1=a1, v=[1.0, 14.0]), tol=TOL)
    assert (ds.hopf_status == bd.LOCATED).all()
    assert (ds.stick_status == bd.LOCATED).all()
    assert (np.abs(ds.v_hopf - ds.v_star)
            <= np.maximum(ds.v_hopf_error, HOPF_TOL)).all()
    assert float(np.abs(ds.v_hopf - ds.v_star)[:4].max()) <= HOPF_TOL
    np.testing.assert_allclose(ds.v_stick_onset, ref.v_stick_onset, rtol=0,
                               atol=2e-9)


@pytest.mark.parametrize("executor", [
    dict(scheduler="threads", chunks=1), dict(scheduler="synchronous"),
    "client", pytest.param(dict(scheduler="processes", chunks=2),
                           marks=pytest.mark.slow)])
def test_executors_give_the_same_boundaries(located, executor):
    """Every attractor is computed independently: the chunking and the executor
    cannot change a bit of the result."""
    grid = sc.Grid(**PAPER, v=np.linspace(1.0, 7.0, 16), alpha2=[0.01, 0.03, 0.05])
    if executor == "client":
        from distributed import Client, LocalCluster
        with LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                          dashboard_address=":0") as cluster, Client(cluster) as client:
            ds = bd.locate_boundaries(grid, tol=TOL, client=client, chunks=1)
    else:
        ds = bd.locate_boundaries(grid, tol=TOL, **executor)
    for name in ("v_hopf", "v_stick_onset", "transition_value"):
        np.testing.assert_array_equal(ds[name].values, located[name].values)


# ---------------------------------------------------------------- refusals
@pytest.mark.parametrize("kw, message", [
    (dict(bracket=(5.0, 1.0)), "lo < hi"),
    (dict(bracket=(-1.0, 1.0)), "v > 0"),
    (dict(xtol=0.0), "xtol"),
    (dict(along="q"), "along"),
    (dict(scan=2), "scan"),
])
def test_bad_arguments_are_refused_naming_them(kw, message):
    grid = sc.Grid(**PAPER, v=[1.0, 2.0], alpha2=0.01)
    with pytest.raises(ValueError, match=message):
        bd.locate_boundaries(grid, **kw)


# ------------------------------------------------------------ diagrams
def test_diagram_branches_agree_and_order_the_regimes():
    """Supercritical Hopf point: up and down scans follow the same attractors (no
    hysteresis) wherever both converged; along v the regimes come in the order
    stick-slip, slip cycle, equilibrium, switching at the located boundaries."""
    v = np.linspace(4.0, 7.0, 31)
    ds = sc.bifurcation_diagram(sc.Grid(**PAPER, alpha2=0.01, v=v), tol=TOL)
    assert sc.check_cf(ds) == []
    ok = (ds.status == codes.OK).all("branch").values
    assert ok.sum() >= v.size - 2
    up, down = ds.sel(branch="up"), ds.sel(branch="down")
    np.testing.assert_allclose(up.x_max.values[ok], down.x_max.values[ok], atol=1e-8)
    reg = up.regime.values
    order = {codes.R_STICK_SLIP: 0, codes.R_SLIP_CYCLE: 1, codes.R_EQUILIBRIUM: 2}
    assert all(order[a] <= order[b] for a, b in zip(reg, reg[1:]))
    hopf, stick = float(ds.v_hopf), float(ds.v_stick_onset)
    slip, eq = reg == codes.R_SLIP_CYCLE, reg == codes.R_EQUILIBRIUM
    assert v[slip].max() < hopf < v[eq].min()
    assert v[reg == codes.R_STICK_SLIP].max() < stick < v[slip].min()
    # a point of the branch is the attractor reached from an independent start
    a = sc.attractor(sc.Params(**PAPER, alpha2=0.01, v=float(v[3])), tol=TOL)
    assert abs(a.x_max - float(up.x_max[3])) <= 1e-8


# ------------------------------------------------------------------ CLI
STUDY = """
title = "boundaries test"
[axes]
m = 5.0
k = 50.0
r_y = 10.0
alpha1 = 1.0
v = { start = 1.0, stop = 7.0, num = 12 }
alpha2 = [0.01, 0.03]
[boundary]
xtol = 1e-9
"""


def test_cli_boundary_writes_located_boundaries(tmp_path, capsys):
    from sweepcore.cli import main
    study = tmp_path / "b.toml"
    study.write_text(STUDY)
    out = tmp_path / "b.nc"
    assert main(["boundary", str(study), "-o", str(out), "--png",
                 str(tmp_path / "b.png")]) == 0
    ds = sc.open_result(out)
    assert float(np.abs(ds.v_hopf - ds.v_star).max()) <= HOPF_TOL
    assert "study" in ds.attrs and (tmp_path / "b.png").stat().st_size > 0
    assert "|v_hopf - v*| <=" in capsys.readouterr().out


def test_cli_boundary_diagram(tmp_path):
    from sweepcore.cli import main
    study = tmp_path / "d.toml"
    study.write_text(STUDY.replace("alpha2 = [0.01, 0.03]", "alpha2 = 0.01")
                     + "diagram = true\n")
    assert main(["boundary", str(study), "-o", str(tmp_path / "d.nc")]) == 0
    ds = sc.open_result(tmp_path / "d.nc")
    assert ds.attrs["sweepcore_kind"] == "bifurcation_diagram"
    assert (tmp_path / "d.png").stat().st_size > 0
    assert main(["plot", str(tmp_path / "d.nc"), "-o", str(tmp_path / "e.png")]) == 0


def test_studies_without_boundary_table_need_no_bracket():
    from sweepcore.study import parse_study
    text = STUDY.replace("v = { start = 1.0, stop = 7.0, num = 12 }", "v = 5.0")
    assert parse_study(text.replace("[boundary]\nxtol = 1e-9\n", "")).boundary == {}
    with pytest.raises(ValueError, match="give bracket"):
        parse_study(text)


@pytest.mark.parametrize("line, message", [
    ("bracket = [5.0, 1.0]", "lo < hi"),
    ("bracket = [0.0, 1.0]", "v > 0"),
    ("scan = 2", "scan"),
    ("offset = 0.5", "offset"),
    ("continuation = \"m\"", "continuation"),
    ("diagram = true", "every other parameter fixed"),
    ("tolerance = 1e-9", "unknown key 'tolerance'"),
])
def test_boundary_table_refusals_name_key_and_line(line, message):
    from sweepcore.study import StudyError, parse_study
    text = STUDY + line + "\n"
    with pytest.raises(StudyError, match=message) as err:
        parse_study(text, "b.toml")
    assert err.value.line == text.splitlines().index(line) + 1
