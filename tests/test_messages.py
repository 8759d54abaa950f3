"""Refusals from the Python API name the parameter, its unit and the likely fix.

What is proven: a misspelt keyword of ``Params``, ``Grid`` or ``simulate`` gets "did
you mean" with the right name (and the list of names), while ``Params``'s signature,
positional use and validation are unchanged; a setting of ``simulate`` out of range
names its unit.
"""
import inspect

import numpy as np
import pytest

import sweepcore as sc


@pytest.mark.parametrize("typo, right", [("alpha_1", "alpha1"), ("alpah2", "alpha2"),
                                         ("ry", "r_y"), ("mass", None)])
def test_params_keyword_typo_did_you_mean(typo, right):
    with pytest.raises(TypeError) as err:
        sc.Params(m=5.0, k=50.0, r_y=10.0, v=5.0, **{typo: 1.0})
    text = str(err.value)
    assert f"unexpected keyword argument {typo!r}" in text
    if right:
        assert f"did you mean {right!r}?" in text
    else:
        assert "did you mean" not in text
    assert "(allowed: m, k, r_y, v, alpha1, alpha2, c, r_k, v_s, law, F0, Omega, phi, " \
        "Y0, load)" in text


@pytest.mark.parametrize("call, right", [
    (lambda: sc.Grid(m=5.0, k=50.0, r_y=10.0, v=[1.0, 2.0], alpha_2=0.1), "alpha2"),
    (lambda: sc.simulate(sc.Params(5.0, 50.0, 10.0, 5.0), t_ned=3.0), "t_end"),
])
def test_grid_and_simulate_keyword_typos_did_you_mean(call, right):
    with pytest.raises(TypeError, match=f"did you mean {right!r}"):
        call()


def test_params_signature_and_behaviour_unchanged():
    """The positional order of the analytic law's parameters holds; ``law`` (a law
    object instead of them) comes after them, the excitation's keywords last, the
    load's shape after them."""
    assert list(inspect.signature(sc.Params).parameters) == \
        ["m", "k", "r_y", "v", "alpha1", "alpha2", "c", "r_k", "v_s", "law", "F0", "Omega",
         "phi", "Y0", "load"]
    p = sc.Params(5.0, 50.0, 10.0, 5.0, 1.0, alpha2=0.01)
    assert (p.m, p.k, p.r_y, p.v, p.alpha1, p.alpha2) == (5.0, 50.0, 10.0, 5.0, 1.0, 0.01)
    with pytest.raises(ValueError, match=r"m must be > 0 \[kN s2 cm-1\], got -1"):
        sc.Params(m=-1, k=1, r_y=1, v=1)


@pytest.mark.parametrize("kwargs, message", [
    (dict(t_end=-1.0), r"t_end must be > 0 \[s\], got -1.0"),
    (dict(t_end=1.0, output_dt=0.0), r"output_dt must be > 0 \[s\], got 0.0"),
])
def test_simulate_settings_name_their_units(kwargs, message):
    with pytest.raises(ValueError, match=message):
        sc.simulate(sc.Params(m=5.0, k=50.0, r_y=10.0, v=5.0), **kwargs)


@pytest.mark.parametrize("f, speed, value", [
    (lambda s: 1.0 / s, 1e-300, 1e300),            # infinite at 0: asked at 1e-300
    (lambda s: 1.0 / s + 0.5, 1e-300, 1e300),
    (lambda s: 1.0 / (s - 2.0), 2.0, float("inf"))])
def test_from_function_says_which_speed_gave_what(f, speed, value):
    """A function infinite or beyond 1e100 kN somewhere on the range is refused
    with the speed and the value (it said "f holds 1e+300 kN" only), and the way
    out for a law infinite at 0: sample it from a small speed s0."""
    with np.errstate(divide="ignore"), pytest.raises(ValueError) as err:
        sc.TableLaw.from_function(f, 8.0)
    text = str(err.value)
    assert text.startswith(f"f({speed!r} cm/s) = ")
    assert float(text.split(" = ")[1].split(" kN")[0]) == pytest.approx(value)
    assert "from_function(lambda s: f(np.maximum(s, s0)), ...)" in text


def test_from_csv_refuses_a_large_file_before_reading_it(tmp_path, monkeypatch):
    """A CSV file above the table's byte limit is refused at once by its size,
    naming the file, its bytes and the limit (a 100 MB file was read for 41 s,
    then refused by its row count); the reader is never called."""
    from sweepcore.laws import table
    path = tmp_path / "big.csv"
    path.write_text("speed [cm/s],force [kN]\n" + "0.5,1.0\n" * 40)
    monkeypatch.setattr(table, "MAX_BYTES", 100)
    monkeypatch.setattr(table.csv, "reader", lambda *a, **k: pytest.fail("read"))
    with pytest.raises(ValueError) as err:
        sc.TableLaw.from_csv(path)
    size = path.stat().st_size
    assert f"the friction table {str(path)!r} is {size:,} bytes; a table's file " \
        "holds at most 100 " in str(err.value)
