"""Friction laws given as objects: measured tables (TableLaw) and Leine's law.

What is proven:
* bad tables and bad law arguments are refused by name before any work;
* the quintic representation interpolates its points and converges at order 6
  (its shape: test_table_shape.py);
* a table sampled from an analytic law gives the analytic law's answers (attractor,
  Hopf speed, criticality, x_eq) within the representation's error;
* an independent scipy solution with the same interpolant (reference_law.py) agrees
  on a stick-slip cycle, a slip cycle with its Floquet multiplier and the
  equilibrium, for a table with stiction;
* Leine's law (a law kind of its own) agrees with scipy on the formula, and with a
  table of the same function;
* a second, different table compiles nothing; a law dimension gives the single-law
  sweeps bit for bit; results record the law.
"""
import math

import numpy as np
import pytest
from numba.core import event

import sweepcore as sc
from sweepcore.laws import TableLaw

import reference_law as RL

BSTAB = dict(m=1.0, k=1.0, c=0.1)                  # bSTAB's slider; its law below
STRIBECK = dict(r_y=1.0, r_k=0.5, v_s=0.5)


def bstab_force(s):
    return np.sign(s) * (0.5 + 0.5 * np.exp(-np.abs(s) / 0.5))


@pytest.fixture(scope="module")
def bstab_table():
    return TableLaw.from_function(bstab_force, speed_max=8.0, tol=1e-11, name="bstab")


# ------------------------------------------------------------------ refusals
S6 = [0.0, 0.5, 1.0, 1.5, 2.0, 3.0]
F6 = [1.0, 0.9, 0.8, 0.75, 0.7, 0.7]


@pytest.mark.parametrize("speed, force, kw, match", [
    ([0.0, 0.5, np.nan, 1.5, 2.0, 3.0], F6, {}, r"speed must be finite, got nan \(element 2\)"),
    (S6, [1.0, 0.9, np.inf, 0.75, 0.7, 0.7], {}, r"force must be finite, got inf"),
    ([0.0, 0.5, 1.5, 1.0, 2.0, 3.0], F6, {}, r"unsorted speeds 1.5 and 1.0"),
    ([0.0, 0.5, 1.0, 1.0, 2.0, 3.0], F6, {}, r"repeated speeds 1.0 and 1.0"),
    (S6[:5], F6[:5], {}, r"has 5 point\(s\); a quintic spline .* needs at least 6"),
    (S6, [1.0, 0.9, -0.1, 0.75, 0.7, 0.7], {}, r"force must be >= 0 .* got -0.1 at speed 1.0"),
    (S6, F6, {"static": 0.9}, r"static must be at least F\(0\+\) = 1.0 .* got 0.9"),
    ([0.1, 0.5, 1.0, 1.5, 2.0, 3.0], F6, {}, r"speed must start at 0"),
    (S6, F6[:5], {}, r"equal lengths, got 6 speeds and 5 forces"),
    (S6, F6, {"smoothing": -1.0}, r"smoothing must be a finite number > 0"),
    (S6, F6, {"name": ""}, r"name must be a non-empty string"),
    ("abc", F6, {}, r"speed must be a 1-D sequence"),
    ([0.0, 0.5, True, 1.5, 2.0, 3.0], F6, {}, r"speed must hold real numbers, got True"),
])
def test_bad_tables_are_refused_by_name(speed, force, kw, match):
    with pytest.raises((ValueError, TypeError), match=match):
        TableLaw(speed, force, **kw)


def test_an_asymmetric_table_needs_zero_twice_and_signs_on_each_side():
    s = [-3.0, -2.0, -1.5, -1.0, -0.5, 0.0, 0.0, 0.5, 1.0, 1.5, 2.0, 3.0]
    f = [-0.5, -0.55, -0.6, -0.65, -0.7, -0.8, 1.0, 0.9, 0.8, 0.75, 0.7, 0.7]
    law = TableLaw(s, f)
    assert not law.odd and law.static_limits() == (1.0, 0.8)
    with pytest.raises(ValueError, match=r"force must be <= 0 on the negative branch"):
        TableLaw(s, [0.1] + f[1:])
    with pytest.raises(ValueError, match="0 given twice"):
        TableLaw(s[:5] + s[6:], f[:5] + f[6:])


def test_csv_tables_state_their_units(tmp_path):
    good = tmp_path / "f.csv"
    good.write_text("speed [m/s],force [N]\n" + "".join(
        f"{s / 100},{f * 1000}\n" for s, f in zip(S6, F6)))
    law = TableLaw.from_csv(good)
    np.testing.assert_allclose(law.speed, S6)      # cm/s and kN inside
    np.testing.assert_allclose(law.force_values, F6)
    assert law.name == "f"
    bare = tmp_path / "bare.csv"
    bare.write_text("speed,force\n" + "".join(f"{s},{f}\n" for s, f in zip(S6, F6)))
    with pytest.raises(ValueError, match=r"header must state units"):
        TableLaw.from_csv(bare)
    odd = tmp_path / "odd.csv"
    odd.write_text("speed [km/h],force [kN]\n0,1\n")
    with pytest.raises(ValueError, match=r"unknown speed unit 'km/h'"):
        TableLaw.from_csv(odd)
    text = tmp_path / "text.csv"
    text.write_text("speed [cm/s],force [kN]\n0,1\nfast,2\n")
    with pytest.raises(ValueError, match=r"line 3: two numbers expected, got 'fast,2'"):
        TableLaw.from_csv(text)


def test_a_law_object_excludes_the_analytic_parameters(bstab_table):
    with pytest.raises(ValueError, match=r"law= replaces .* got r_y=1.0"):
        sc.Params(**BSTAB, r_y=1.0, v=1.0, law=bstab_table)
    with pytest.raises(ValueError, match=r"got alpha2=0.1"):
        sc.Grid(**BSTAB, v=[1.0, 2.0], alpha2=0.1, law=bstab_table)
    with pytest.raises(TypeError, match=r"law must be a friction law object .* got 'table'"):
        sc.Params(**BSTAB, v=1.0, law="table")
    with pytest.raises(ValueError, match=r"distinct names .* got 'bstab' twice"):
        sc.Grid(**BSTAB, v=[1.0, 2.0], law=[bstab_table, bstab_table])
    with pytest.raises(ValueError, match="method='exact' needs a piecewise-linear law"):
        sc.sweep(sc.Grid(**BSTAB, v=[1.0, 2.0], law=bstab_table), method="exact")


# ------------------------------------------------------------ the representation
def test_the_quintic_interpolant_converges_at_order_six():
    """Midpoint errors of the interpolant of a smooth monotone law fall as h^6 (the
    quintic Hermite pieces with slopes and curvatures of order 6 and 5, no shrink on
    resolved data); measured on halving h twice. ``deviation`` (the distance from
    the order-4 construction) is above the error everywhere on the table."""
    f = lambda s: 1.0 + 0.5 * np.exp(-s) * (1.0 + 0.5 * np.sin(s))   # noqa: E731
    errs = []
    for n in (20, 40, 80):
        s = np.linspace(0.0, 6.0, n + 1)
        law = TableLaw(s, f(s))
        assert np.array_equal(law.force(s, phase=1.0), f(s))    # it interpolates
        u = np.linspace(0.0, 6.0, 20001)                         # deviation bounds it
        assert np.abs(law.force(u, phase=1.0) - f(u)).max() <= law.deviation
        mid = 0.5 * (s[1:] + s[:-1])
        errs.append(np.abs(law.force(mid) - f(mid))[n // 4:3 * n // 4].max())
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(orders > 5.5), orders


def test_from_function_meets_its_tolerance_and_records_it(bstab_table):
    check = np.linspace(1e-6, 8.0, 20001)
    err = np.abs(bstab_table.force(check) - bstab_force(check)).max()
    assert err <= 1e-10 and bstab_table.deviation <= 1e-11
    assert bstab_table.force(0.0, phase=1.0) == pytest.approx(1.0, abs=1e-11)   # F(0+)
    assert bstab_table.force(0.0, phase=-1.0) == pytest.approx(-1.0, abs=1e-11)


# ----------------------------------------------- against the analytic law it samples
@pytest.mark.parametrize("v", [0.6, 1.4, 2.5])
def test_a_table_of_the_bstab_law_gives_the_analytic_answers(bstab_table, v):
    pa = sc.Params(**BSTAB, **STRIBECK, v=v)
    pt = sc.Params(**BSTAB, v=v, law=bstab_table)
    a, b = sc.attractor(pa), sc.attractor(pt)
    assert (a.regime, a.status) == (b.regime, b.status) == (a.regime, "ok")
    scale = 1.0 + v                                     # L = r_y/k + v/omega
    for name in ("amplitude", "mean", "x_max", "x_min"):
        assert abs(getattr(a, name) - getattr(b, name)) <= 1e-7 * scale, name
    if a.regime != "equilibrium":
        assert b.period == pytest.approx(a.period, rel=1e-7)
    assert pt.hopf_speeds[0] == pytest.approx(math.log(10) / 2, rel=1e-7)
    assert pt.criticality == pa.criticality == "subcritical"
    assert pt.x_eq == pytest.approx(pa.x_eq, abs=1e-10)
    assert pt.q == pytest.approx(pa.q, abs=1e-7)


def test_a_table_of_the_papers_law_next_to_its_hopf_point():
    """Liu's eq. (40) with the paper's values as a table: the slip cycle just below v*
    and the supercritical Hopf point."""
    par = dict(r_y=10.0, alpha1=1.0, alpha2=0.01)
    law = TableLaw.from_function(lambda s: np.sign(s) * 10.0 - s + 0.01 * s ** 3,
                                 speed_max=20.0, tol=1e-12, name="eq40")
    vs = math.sqrt(1.0 / 0.03)
    pa = sc.Params(m=5.0, k=50.0, v=0.95 * vs, **par)
    pt = sc.Params(m=5.0, k=50.0, v=0.95 * vs, law=law)
    a, b = sc.attractor(pa), sc.attractor(pt)
    assert a.regime == b.regime == "slip_cycle" and b.status == "ok"
    assert abs(a.amplitude - b.amplitude) <= 1e-7 * (10.0 / 50.0 + pa.v / pa.omega)
    assert b.floquet == pytest.approx(a.floquet, abs=1e-6)
    assert pt.v_star == pytest.approx(vs, rel=1e-9)
    assert pt.criticality == "supercritical"


def test_a_constant_table_with_damping_rests_at_its_equilibrium():
    law = TableLaw(np.linspace(0.0, 5.0, 11), np.full(11, 2.0), name="coulomb")
    p = sc.Params(m=1.0, k=4.0, c=0.3, v=1.0, law=law)
    a = sc.attractor(p)
    assert (a.regime, a.status) == ("equilibrium", "ok")
    assert a.mean == pytest.approx(2.0 / 4.0, abs=1e-13) and p.x_eq == pytest.approx(0.5)


# ------------------------------------------------- against scipy, same interpolant
@pytest.fixture(scope="module")
def stiction_table():
    """A 'measured' curve with stiction: the static force above F(0+). Its minimum
    (s = 1.51) is sampled (1.4, 1.6): the representation keeps the samples' shape,
    and a dip between samples 0.6 apart would not be there (test_table_shape.py)."""
    s = np.array([0.0, 0.05, 0.1, 0.2, 0.35, 0.5, 0.65, 0.8, 1.0, 1.2, 1.4, 1.6, 1.8,
                  2.5, 3.5, 5.0, 7.0])
    f = 0.6 + 0.35 * np.exp(-s / 0.4) + 0.02 * s
    return TableLaw(s, f, static=1.1, name="stiction")


def law_branch(law):
    """``branch(s, sgn)`` of an odd table law as represented, for the reference: F by
    the law's own numpy force (the end force held past the table), F' from its
    pieces by numpy; below zero speed continued linearly (a slide's last stages)."""
    x, c = law._pos[:2]
    slope = c[:, 1:] * np.arange(1, c.shape[1])

    def side(s):
        if s < 0.0:
            f0, d0 = side(0.0)
            return f0 + d0 * s, d0
        f = float(law.force(s, phase=1.0))
        if s >= x[-1]:
            return f, 0.0
        i = int(np.clip(np.searchsorted(x, s, side="right") - 1, 0, len(x) - 2))
        return f, float(np.polynomial.polynomial.polyval(s - x[i], slope[i]))

    def branch(s, sgn):
        if sgn > 0:
            return side(s)
        f, d = side(-s)
        return -f, d
    return branch


def _model(law, v, m=1.0, k=1.0, c=0.05):
    return RL.LawModel(m, k, v, c, law_branch(law), max(law.static_limits()))


def test_stick_slip_of_a_table_with_stiction_against_scipy(stiction_table):
    p = sc.Params(m=1.0, k=1.0, c=0.05, v=0.4, law=stiction_table)
    a = sc.attractor(p)
    ref = RL.stick_slip_cycle(_model(stiction_table, 0.4))
    assert (a.regime, a.status) == ("stick_slip", "ok")
    L = 1.1 + 0.4
    assert abs(a.amplitude - ref["amplitude"]) <= 1e-7 * L
    assert abs(a.mean - ref["mean"]) <= 1e-7 * L
    assert a.period == pytest.approx(ref["period"], rel=1e-7)
    assert a.stick_fraction == pytest.approx(ref["stick_time"] / ref["period"], abs=1e-7)


def test_unstable_slip_cycle_and_equilibrium_of_a_table_against_scipy(stiction_table):
    """The table's Hopf point is subcritical (F''' < 0 there): just above it the
    equilibrium is stable, reached from a start next to it, and an unstable slip
    cycle (Floquet multiplier > 1) bounds its basin; scipy shooting on the same
    interpolant finds it."""
    p0 = sc.Params(m=1.0, k=1.0, c=0.05, v=1.0, law=stiction_table)
    vh = p0.hopf_speeds[0]
    assert p0.criticality == "subcritical"
    damping = RL.equilibrium(_model(stiction_table, vh))["damping"]
    assert damping == pytest.approx(0.0, abs=1e-9)
    v = 1.05 * vh
    p = sc.Params(m=1.0, k=1.0, c=0.05, v=v, law=stiction_table)
    eq = RL.equilibrium(_model(stiction_table, v))
    assert p.x_eq == pytest.approx(eq["x_eq"], abs=1e-12)
    assert p.q == pytest.approx(-eq["damping"], abs=1e-10) and p.q < 0
    a = sc.attractor(p, x0=p.x_eq + 0.01, xdot0=0.0)
    assert (a.regime, a.status) == ("equilibrium", "ok")
    cyc = sc.slip_cycles(sc.Grid(m=1.0, k=1.0, c=0.05, v=v, law=stiction_table))
    assert int(cyc.n_cycles) == 1
    x_max = float(cyc.cycle_x_max.values.ravel()[0])
    ref = RL.slip_cycle(_model(stiction_table, v), x_max)
    assert abs(x_max - ref["x_max"]) <= 1e-7 * (1.1 + v)
    assert float(cyc.cycle_period.values.ravel()[0]) == pytest.approx(ref["period"],
                                                                      rel=1e-7)
    assert float(cyc.cycle_floquet.values.ravel()[0]) == pytest.approx(ref["floquet"],
                                                                       abs=1e-5)
    assert ref["floquet"] > 1.0


# ------------------------------------------------------------------ Leine's law
def leine_branch(f_s, delta):
    def branch(s, sgn):
        u = 1.0 + delta * sgn * s
        return sgn * f_s / u, -f_s * delta / (u * u)
    return branch


def test_leines_example_is_stick_slip_against_scipy():
    """Leine & Nijmeijer's example: k = m = F_s = 1, delta = 3, belt speed 0.2."""
    law = sc.LeineLaw(1.0, 3.0)
    p = sc.Params(m=1.0, k=1.0, v=0.2, law=law)
    a = sc.attractor(p)
    ref = RL.stick_slip_cycle(RL.LawModel(1.0, 1.0, 0.2, 0.0, leine_branch(1.0, 3.0), 1.0))
    assert (a.regime, a.status) == ("stick_slip", "ok")
    assert a.period == pytest.approx(ref["period"], rel=1e-7)
    assert round(a.period, 3) == 12.001
    assert abs(a.amplitude - ref["amplitude"]) <= 1e-7 * 1.2
    # the Hopf speed in closed form: c + F'(-u) = 0, (1 + delta u)^2 = F_s delta / c
    q = sc.Params(m=1.0, k=1.0, c=0.1, v=1.0, law=law)
    assert q.v_star == pytest.approx((math.sqrt(30.0) - 1.0) / 3.0, rel=1e-12)


@pytest.mark.parametrize("delta, v", [(300.0, 0.2), (3000.0, 1.0)])
def test_a_steep_leine_law_is_resolved(delta, v):
    """A steep law (its slope -F_s delta at zero speed) makes the field unstable at
    the rate delta F_s/m next to the belt speed: the steps there are bounded by the
    law's own step bound (``law.step_bound``); without it the cycle was 3e-7 L off at
    tol 1e-8. Against scipy with the same formula."""
    a = sc.attractor(sc.Params(m=1.0, k=1.0, c=0.05, v=v, law=sc.LeineLaw(1.0, delta)))
    ref = RL.stick_slip_cycle(RL.LawModel(1.0, 1.0, v, 0.05, leine_branch(1.0, delta),
                                          1.0))
    assert (a.regime, a.status) == ("stick_slip", "ok")
    assert abs(a.amplitude - ref["amplitude"]) <= 1e-8 * (1.0 + v)
    assert a.period == pytest.approx(ref["period"], rel=1e-8)


def test_a_table_of_leines_law_gives_the_law_kinds_answers():
    law = sc.LeineLaw(1.0, 3.0)
    table = TableLaw.from_function(lambda s: np.sign(s) / (1.0 + 3.0 * np.abs(s)),
                                   speed_max=4.0, tol=1e-11, name="leine-table")
    for v in (0.2, 0.9):
        a = sc.attractor(sc.Params(m=1.0, k=1.0, c=0.02, v=v, law=law))
        b = sc.attractor(sc.Params(m=1.0, k=1.0, c=0.02, v=v, law=table))
        assert a.regime == b.regime and a.status == b.status == "ok"
        assert abs(a.amplitude - b.amplitude) <= 1e-7 * (1.0 + v)


# ------------------------------------------------------------ compiled once, labelled
def test_a_second_table_compiles_nothing(bstab_table, stiction_table):
    sc.attractor(sc.Params(**BSTAB, v=1.4, law=bstab_table))        # compiled (or cached)
    other = TableLaw(np.linspace(0.0, 3.0, 7), 1.0 + 0.1 * np.linspace(0.0, 3.0, 7) ** 2,
                     name="other")
    compiled = []

    class Count(event.Listener):
        def on_start(self, ev):
            compiled.append(ev.data["dispatcher"].py_func.__qualname__)

        def on_end(self, ev):
            pass
    with event.install_listener("numba:compile", Count()):
        a = sc.attractor(sc.Params(**BSTAB, v=0.5, law=other))
        sc.attractor(sc.Params(**BSTAB, v=0.5, law=stiction_table))
    assert a.status == "ok" and compiled == []


def test_a_law_dimension_is_the_single_law_sweeps(bstab_table, stiction_table):
    v = np.array([0.4, 1.4, 2.5])
    both = sc.sweep(sc.Grid(**BSTAB, v=v, law=[bstab_table, stiction_table]),
                    progress=False)
    assert list(both.law.values) == ["bstab", "stiction"]
    for law in (bstab_table, stiction_table):
        one = sc.sweep(sc.Grid(**BSTAB, v=v, law=law), progress=False)
        for name in ("amplitude", "period", "regime", "status", "v_star", "x_eq"):
            np.testing.assert_array_equal(both[name].sel(law=law.name).values,
                                          one[name].values)
        assert one.attrs["law"] == law.name
        assert one.attrs["law_deviation"] == law.deviation
    np.testing.assert_array_equal(both.law_speed.sel(law="stiction").values[:17],
                                  stiction_table.speed)


def test_results_keep_the_law_in_the_file(tmp_path, stiction_table):
    path = tmp_path / "t.nc"
    sc.sweep(sc.Grid(**BSTAB, v=[0.4, 1.0], law=stiction_table), path=path,
             progress=False)
    ds = sc.open_result(path)
    assert ds.attrs["law_kind"] == "table" and ds.attrs["law"] == "stiction"
    np.testing.assert_array_equal(ds.law_force.values, stiction_table.force_values)
    assert ds.law_speed.attrs["units"] == "cm s-1"


# ------------------------------------------------ study files and the command line
CSV = "speed [m/s],force [N]\n" + "".join(
    f"{s / 100:.17g},{1000 * (1.0 - 0.4 * s / (1.0 + s)):.17g}\n"
    for s in [0.0, 0.1, 0.25, 0.5, 1.0, 1.5, 2.0, 3.0])


def _csv_law():
    s = np.array([0.0, 0.1, 0.25, 0.5, 1.0, 1.5, 2.0, 3.0])
    return TableLaw(s, 1.0 - 0.4 * s / (1.0 + s), name="curve")


def test_a_study_takes_its_law_from_a_csv_file(tmp_path):
    from sweepcore.study import load_study
    (tmp_path / "curve.csv").write_text(CSV)
    (tmp_path / "s.toml").write_text(
        '[axes]\nm = 1.0\nk = 1.0\nc = 0.1\nv = [0.3, 0.8]\n'
        '[law]\ntable = "curve.csv"\nstatic = 1.1\n')
    law = load_study(tmp_path / "s.toml").law
    ref = _csv_law()                                   # the same curve in kN, cm/s
    np.testing.assert_allclose(law.speed, ref.speed, rtol=1e-12)
    np.testing.assert_allclose(law.force_values, ref.force_values, rtol=1e-12)
    assert law.name == "curve" and max(law.static_limits()) == 1.1
    (tmp_path / "two.toml").write_text(
        '[axes]\nm = 1.0\nk = 1.0\nc = 0.1\nv = [0.3, 0.8]\n'
        '[[law]]\ntable = "curve.csv"\n[[law]]\nkind = "leine"\nf_s = 1.0\ndelta = 3.0\n')
    assert [x.kind for x in load_study(tmp_path / "two.toml").law] == ["table", "leine"]


@pytest.mark.parametrize("text, message", [
    ('[axes]\nm = 1.0\nk = 1.0\nr_y = 1.0\nv = 0.5\n[law]\ntable = "curve.csv"\n',
     r"s.toml:4: axes.r_y: r_y is a parameter of the analytic law; the \[law\] table "
     r"replaces it"),
    ('[axes]\nm = 1.0\nk = 1.0\nv = 0.5\n[law]\ntable = "nothing.csv"\n',
     r"s.toml:\d+: law.table: .*nothing.csv"),
    ('[axes]\nm = 1.0\nk = 1.0\nv = 0.5\n[law]\nkind = "leine"\nf_s = 1.0\n',
     r"law: the leine law needs delta"),
])
def test_a_bad_law_table_is_refused_by_key_and_line(tmp_path, text, message):
    from sweepcore.study import StudyError, load_study
    (tmp_path / "curve.csv").write_text(CSV)
    (tmp_path / "s.toml").write_text(text)
    with pytest.raises(StudyError, match=message):
        load_study(tmp_path / "s.toml")


def test_the_command_line_simulates_a_csv_law(tmp_path):
    import subprocess
    import sys
    (tmp_path / "curve.csv").write_text(CSV)
    (tmp_path / "bare.csv").write_text(CSV.split("\n", 1)[1])      # no header: no units
    cmd = [sys.executable, "-m", "sweepcore", "simulate", "--m", "1", "--k", "1", "--c",
           "0.1", "--v", "0.3", "--t-end", "20"]
    ok = subprocess.run(cmd + ["--law-table", "curve.csv", "-o", "s.nc"],
                        cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert ok.returncode == 0, ok.stderr
    ds = sc.open_result(tmp_path / "s.nc")
    assert ds.attrs["law"] == "curve" and ds.attrs["law_kind"] == "table"
    ref = sc.simulate(sc.Params(m=1.0, k=1.0, c=0.1, v=0.3, law=_csv_law()), t_end=20.0)
    np.testing.assert_allclose(ds.x.values, ref.x.values, rtol=0, atol=1e-9)
    bad = subprocess.run(cmd + ["--law-table", "bare.csv", "-o", "b.nc"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=300)
    assert bad.returncode != 0 and "units" in bad.stderr and not (tmp_path / "b.nc").exists()
    mixed = subprocess.run(cmd + ["--law-table", "curve.csv", "--r-y", "1", "-o", "m.nc"],
                           cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert mixed.returncode != 0 and "--r-y" in mixed.stderr
