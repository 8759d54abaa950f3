"""Refusals from the Python API name the parameter, its unit and the likely fix.

What is proven: a misspelt keyword of ``Params``, ``Grid`` or ``simulate`` gets "did
you mean" with the right name (and the list of names), while ``Params``'s signature,
positional use and validation are unchanged; a setting of ``simulate`` out of range
names its unit.
"""
import inspect

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
        "Y0)" in text


@pytest.mark.parametrize("call, right", [
    (lambda: sc.Grid(m=5.0, k=50.0, r_y=10.0, v=[1.0, 2.0], alpha_2=0.1), "alpha2"),
    (lambda: sc.simulate(sc.Params(5.0, 50.0, 10.0, 5.0), t_ned=3.0), "t_end"),
])
def test_grid_and_simulate_keyword_typos_did_you_mean(call, right):
    with pytest.raises(TypeError, match=f"did you mean {right!r}"):
        call()


def test_params_signature_and_behaviour_unchanged():
    """The positional order of the analytic law's parameters holds; ``law`` (a law
    object instead of them) comes after them, the excitation's keywords last."""
    assert list(inspect.signature(sc.Params).parameters) == \
        ["m", "k", "r_y", "v", "alpha1", "alpha2", "c", "r_k", "v_s", "law", "F0", "Omega",
         "phi", "Y0"]
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
