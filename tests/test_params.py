"""API: bad input is refused before any work, with the parameter and value named."""
import math

import numpy as np
import pytest

import sweepcore as sc

GOOD = dict(m=5.0, k=50.0, r_y=10.0, v=5.0, alpha1=1.0, alpha2=0.01)


@pytest.mark.parametrize("name,value,exc", [
    ("m", 0.0, ValueError), ("m", -1.0, ValueError), ("k", 0.0, ValueError),
    ("k", -50.0, ValueError), ("r_y", -0.1, ValueError), ("alpha2", -0.01, ValueError),
    ("m", math.nan, ValueError), ("k", math.inf, ValueError), ("v", -math.inf, ValueError),
    ("alpha1", math.nan, ValueError), ("r_y", math.nan, ValueError),
    ("m", True, TypeError), ("v", "5", TypeError), ("alpha2", 1j, TypeError),
    ("k", None, TypeError), ("v", np.bool_(True), TypeError), ("m", [5.0], TypeError),
])
def test_bad_parameter_is_named_with_its_value(name, value, exc):
    with pytest.raises(exc) as err:
        sc.Params(**{**GOOD, name: value})
    assert name in str(err.value) and repr(value) in str(err.value)


def test_negative_alpha2_message_explains_why():
    with pytest.raises(ValueError, match="unbounded"):
        sc.Params(**{**GOOD, "alpha2": -1.0})


@pytest.mark.parametrize("v", [-5.0, 0.0, 1e-9, 1e6])
def test_any_finite_belt_speed_is_accepted(v):
    assert sc.Params(**{**GOOD, "v": v}).v == v


def test_numpy_scalars_are_accepted_and_stored_as_float():
    p = sc.Params(m=np.float32(5), k=np.int64(50), r_y=10, v=5)
    assert all(type(getattr(p, n)) is float for n in ("m", "k", "r_y", "v"))


def test_params_are_immutable():
    p = sc.Params(**GOOD)
    with pytest.raises(Exception):
        p.m = 1.0


def test_derived_quantities_follow_the_paper():
    p = sc.Params(**GOOD)
    assert p.omega == pytest.approx(math.sqrt(10.0))
    assert p.q == pytest.approx(0.05)                      # eq. (46), paper: 0.05
    assert p.v_star == pytest.approx(math.sqrt(1 / 0.03))  # below eq. (51)
    assert p.x_eq == pytest.approx((10 - 5 + 0.01 * 125) / 50)   # eq. (43)
    lam = np.array(p.eigenvalues)
    np.testing.assert_allclose(lam ** 2 - p.q * lam + p.omega ** 2, 0, atol=1e-12)  # (45)
    assert sc.Params(**{**GOOD, "alpha2": 0.05}).q == pytest.approx(-0.55)
    assert sc.Params(**{**GOOD, "alpha2": 1 / 75}).q == pytest.approx(0.0, abs=1e-15)


def test_v_star_without_cubic_term():
    assert sc.Params(5, 50, 10, 5, alpha1=1.0).v_star == math.inf
    assert math.isnan(sc.Params(5, 50, 10, 5).v_star)


@pytest.mark.parametrize("kw,match", [
    (dict(t_end=0.0), "t_end"), (dict(t_end=math.nan), "t_end"),
    (dict(t_end=1.0, x0=math.inf), "x0"), (dict(t_end=1.0, xdot0="1"), "xdot0"),
    (dict(t_end=1.0, output_dt=-1.0), "output_dt"), (dict(t_end=1.0, method="euler"), "method"),
    (dict(t_end=1.0, tol=0.0), "tol"), (dict(t_end=1.0, dt=0.0), "dt"),
    (dict(t_end=1.0, max_steps=0), "max_steps"),
])
def test_simulate_refuses_bad_arguments(kw, match):
    with pytest.raises((ValueError, TypeError), match=match):
        sc.simulate(sc.Params(**GOOD), **kw)


def test_exact_method_needs_alpha2_zero():
    with pytest.raises(ValueError, match="alpha2"):
        sc.simulate(sc.Params(**GOOD), 1.0, method="exact")
    with pytest.raises(ValueError, match="alpha2"):
        sc.attractor(sc.Params(**GOOD), method="exact")


def test_attractor_refuses_bad_arguments():
    with pytest.raises(TypeError, match="params"):
        sc.attractor({"m": 5})
    with pytest.raises(ValueError, match="max_periods"):
        sc.attractor(sc.Params(**GOOD), max_periods=-1)


# ------------------------------------------------ magnitudes that overflow
@pytest.mark.parametrize("kw, quantity", [
    (dict(v=1e103), "equilibrium"),                     # |v|^3 overflows
    (dict(v=1e200, alpha2=0.01), "Hopf quantity"),      # alpha2 v^2 overflows
    (dict(m=1e-300, k=1e300), "natural frequency"),     # k/m overflows
    (dict(m=1e300, k=1e-300), "natural frequency"),     # k/m underflows to 0
    (dict(r_y=1e300, k=1e-100), "equilibrium"),         # r_y/k overflows
])
def test_magnitudes_whose_derived_quantities_overflow_are_refused(kw, quantity):
    with pytest.raises(ValueError, match=f"Params: the .*{quantity}.* float64") as err:
        sc.Params(**{**GOOD, **kw})
    name, value = next(iter(kw.items()))
    assert f"{name}={value!r}" in str(err.value)


def test_large_but_representable_magnitudes_are_accepted_with_finite_derived_values():
    p = sc.Params(m=1e-100, k=1e100, r_y=1e100, v=1e100, alpha1=1e-100, alpha2=1e-250)
    for value in (p.omega, p.q, p.x_eq):
        assert math.isfinite(value)
    # x_eq = (1e100 - 1 + 1e50)/1e100 = 1 + 1e-50, q = (1e-100 - 3e-50)/1e-100
    assert p.omega == 1e100 and p.x_eq == pytest.approx(1.0, rel=1e-15)
    assert p.q == pytest.approx(-3e50, rel=1e-15)


def test_grid_refuses_an_axis_range_whose_derived_quantities_overflow():
    from sweepcore.grid import Grid
    with pytest.raises(ValueError, match=r"Grid: the .*equilibrium.* v in \[1\.0, "
                       r"1e\+103\]"):
        Grid(m=5.0, k=50.0, r_y=10.0, v=[1.0, 1e103])
    with pytest.raises(ValueError, match="Grid: the natural frequency"):
        Grid.points(m=[1e-300, 1.0], k=[1e300, 1.0], r_y=1.0, v=1.0)


@pytest.mark.parametrize("max_steps", [2**53 + 1, 2**63, 10**30])
def test_max_steps_beyond_the_option_row_is_refused(max_steps):
    from sweepcore.options import make_options
    with pytest.raises(ValueError, match=rf"max_steps must be an integer in \[1, "
                       rf"2\*\*53\], got {max_steps}"):
        make_options(max_steps=max_steps)
    o = make_options(max_steps=2**53)
    from sweepcore._kernels import layout
    assert int(o[layout.O_MAX_STEPS]) == 2**53        # exact in the float64 row


@pytest.mark.parametrize("kw, match", [
    (dict(output_dt=5e-324), r"output_dt=5e-324 gives inf samples"),
    (dict(output_dt=1e-300), r"output_dt=1e-300 gives 1e\+300 samples"),
    (dict(max_events="a"), r"max_events must be an integer >= 1, got 'a'"),
    (dict(max_events=0), r"max_events must be an integer >= 1, got 0"),
    (dict(max_events=2.5), r"max_events must be an integer >= 1, got 2.5"),
])
def test_simulate_refuses_output_dt_and_max_events_before_simulating(kw, match,
                                                                     monkeypatch):
    import importlib
    sim = importlib.import_module("sweepcore.simulate")

    def no_run(*args):
        raise AssertionError("simulated")
    monkeypatch.setattr(sim.compiled, "trajectory", no_run)
    with pytest.raises(ValueError, match=match):
        sc.simulate(sc.Params(**GOOD), 1.0, **kw)
