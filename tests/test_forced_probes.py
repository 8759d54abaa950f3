"""The probes of the forced interface (issue 44): every hostile input refused by
name, with its value and the limit, before any work; nothing left behind.

What is proven:
* an excitation frequency the forced kernels cannot resolve (Omega/omega outside
  ``FORCING_RATIO``, a forcing period below ``FORCING_PERIOD_MIN``, 5e-324 whose
  period is infinite) and an excitation beyond the drivers' finite range (F0 or Y0
  of 1e300) are refused naming Omega, F0 or Y0, the value and the limit, by Params,
  Grid (per point in ``Grid.points``, over the extremes of a product, which it
  holds) and the study's ``[excitation]`` table; values inside the limits pass;
* F0, phi and Y0 of None are refused naming them (their default is 0), Omega of
  None (no excitation) is not;
* a phase beyond 2 pi (``phi = 90``: degrees) is refused with its value in radians,
  by Params, Grid (naming the element), the study file (naming the line) and the
  command line; 2 pi itself and -pi pass;
* a swept Omega without F0 or Y0, or a swept phi without F0, changes nothing and is
  refused by name (it was a bare KeyError); the study of ``F0 = 0, Omega = [1, 2]``
  is refused before anything is written (no ``.partial`` store left);
* ``frequency_response`` and ``stroboscopic_diagram`` refuse complex, object and
  string values, a direction that is not one of the three names, a start that is
  not a number, and every value the slider cannot take, naming the argument, before
  any work; ``transient + periods`` beyond one simulation's samples is refused
  naming transient and periods, and a diagram beyond the memory by the size rule
  (``sweepcore.sizing.refuse_unaffordable``), not by a MemoryError.
"""
from __future__ import annotations

import importlib
import math
import re

import numpy as np
import pytest

import sweepcore as sc
from sweepcore import params as sp
from sweepcore.sizing import SweepTooLarge
from sweepcore.study import StudyError, parse_study

SLIDER = dict(m=5.0, k=50.0, r_y=10.0, v=2.0)
OMEGA = math.sqrt(50.0 / 5.0)          # the slider's natural frequency [1/s]
LOW, HIGH = sp.FORCING_RATIO
STUDY = ('title = "probe"\n[axes]\nm = 5.0\nk = 50.0\nr_y = 10.0\nv = 2.0\n'
         '[excitation]\n')


# ------------------------------------------------------------ the forcing's range
@pytest.mark.parametrize("Omega", [5e-324, 0.5 * LOW * OMEGA, 2.0 * HIGH * OMEGA,
                                   1e300])
def test_an_unresolvable_frequency_is_refused_with_the_limit(Omega):
    with pytest.raises(ValueError, match=rf"Params: Omega={re.escape(repr(Omega))} "
                                         r"\[rad s-1\].*the forced kernels resolve "
                                         r"Omega/omega in \[1e-08, 1e\+12\]"):
        sc.Params(**SLIDER, F0=1.0, Omega=Omega)


def test_frequencies_inside_the_limits_pass():
    for r in (1.01 * LOW, 1.0, 0.99 * HIGH):
        assert sc.Params(**SLIDER, F0=1.0, Omega=r * OMEGA).Omega == r * OMEGA
    # an unforced slider does not use Omega: nothing to refuse
    assert sc.Params(**SLIDER, Omega=5e-324).forced is False


def test_a_forcing_period_below_the_drivers_step_floor_is_refused():
    # a light slider: the ratio is fine, the period 2 pi/Omega [s] is not
    m = 5e-30
    Omega = 10.0 * math.sqrt(50.0 / m)
    assert 2 * math.pi / Omega < sp.FORCING_PERIOD_MIN
    with pytest.raises(ValueError, match=r"forcing period 2 pi/Omega = .* s, shorter "
                                         r"than the 1e-13 s"):
        sc.Params(m=m, k=50.0, r_y=10.0, v=2.0, F0=1.0, Omega=Omega)


@pytest.mark.parametrize("name", ["F0", "Y0"])
def test_an_excitation_beyond_the_finite_state_is_refused(name):
    with pytest.raises(ValueError, match=rf"length .* is 2e\+298 cm|length .* is "
                                         rf"1e\+300 cm") as err:
        sc.Params(**SLIDER, Omega=1.0, **{name: 1e300})
    assert f"{name}=1e+300" in str(err.value) and "1e+150" in str(err.value)
    assert sc.Params(**SLIDER, Omega=1.0, **{name: 1e100}).forced


def test_grid_checks_the_forcing_per_point_or_over_the_product():
    m, Omega = [5.0, 5e-10], [1e-3, 1.0]      # each point's ratio is fine ...
    assert sc.Grid.points(m=m, k=50.0, r_y=10.0, v=2.0, F0=1.0, Omega=Omega).size == 2
    # ... the product holds (m = 5e-10, Omega = 1e-3): 3.2e-9 times omega
    with pytest.raises(ValueError, match=r"Grid: Omega=0.001 .* is 3.16e-09 times"):
        sc.Grid(m=m, k=50.0, r_y=10.0, v=2.0, F0=1.0, Omega=Omega)
    with pytest.raises(ValueError, match=r"Grid: Omega=0.001 .* is 3.16e-09 times"):
        sc.Grid.points(m=m, k=50.0, r_y=10.0, v=2.0, F0=1.0, Omega=Omega[::-1])


def test_the_study_refuses_the_forcing_at_its_table():
    with pytest.raises(StudyError, match=r"s.toml:7: excitation: Omega=1e-12 .*"
                                         r"Omega/omega in \[1e-08"):
        parse_study(STUDY + "F0 = 1.0\nOmega = 1e-12\n", "s.toml")
    with pytest.raises(StudyError, match=r"s.toml:7: excitation: the excitation's "
                                         r"length .* F0=1e\+300"):
        parse_study(STUDY + "F0 = 1e300\nOmega = 1.0\n", "s.toml")


# ------------------------------------------------------------------ None and units
@pytest.mark.parametrize("name", ["F0", "phi", "Y0"])
def test_none_is_refused_where_the_default_is_zero(name):
    with pytest.raises(TypeError, match=rf"{name} must be a real number \[.*\], got "
                                        r"None: leave it out for its default 0.0"):
        sc.Params(**SLIDER, **{"F0": 1.0, "Omega": 1.0, name: None})


def test_none_frequency_is_no_excitation():
    assert sc.Params(**SLIDER, Omega=None).forced is False


@pytest.mark.parametrize("phi", [90, -180.0, 7.0])
def test_a_phase_in_degrees_is_refused_with_its_radians(phi):
    radians = f"{math.radians(phi):.6g}"
    with pytest.raises(ValueError, match=rf"phi is a phase in radians, \|phi\| <= 2 pi "
                                         rf".*got {float(phi)!r}; if that is {phi:g} "
                                         rf"degrees, give phi = {radians}"):
        sc.Params(**SLIDER, F0=1.0, Omega=1.0, phi=phi)
    with pytest.raises(ValueError, match=r"phi is a phase in radians.*\(element 1 of "
                                         r"the phi axis\)"):
        sc.Grid(**SLIDER, F0=1.0, Omega=1.0, phi=[0.0, phi])
    with pytest.raises(StudyError, match=r"s.toml:10: excitation.phi: phi is a phase "
                                         r"in radians"):
        parse_study(STUDY + f"F0 = 1.0\nOmega = 1.0\nphi = {float(phi)}\n", "s.toml")


def test_a_phase_of_a_whole_turn_passes():
    assert sc.Params(**SLIDER, F0=1.0, Omega=1.0, phi=2 * math.pi).phi == 2 * math.pi
    assert sc.Params(**SLIDER, F0=1.0, Omega=1.0, phi=-math.pi).phi == -math.pi
    grid = sc.Grid(**SLIDER, F0=1.0, Omega=1.0, phi=np.linspace(0.0, 2 * math.pi, 5))
    assert grid.size == 5


def test_simulate_refuses_a_phase_in_degrees(capsys):
    from sweepcore.cli import main
    code = main(["simulate", "--m", "5", "--k", "50", "--r-y", "10", "--v", "2",
                 "--F0", "1", "--Omega", "1", "--phi", "90"])
    assert code == 2
    assert "phi is a phase in radians" in capsys.readouterr().err


@pytest.mark.parametrize("flag, value", [("--F0", "1e300"), ("--Y0", "1e300"),
                                         ("--Omega", "1e300")])
def test_simulate_names_the_input_that_cannot_be_simulated(capsys, flag, value):
    from sweepcore.cli import main
    forcing = ["--F0", "1", "--Omega", "1"]
    i = forcing.index(flag) if flag in forcing else None
    if i is None:
        forcing += [flag, value]
    else:
        forcing[i + 1] = value
    code = main(["simulate", "--m", "5", "--k", "50", "--r-y", "10", "--v", "2",
                 *forcing])
    err = capsys.readouterr().err
    assert code == 2
    assert f"{flag[2:]}=1e+300" in err
    assert "diverged" not in err.split("error:")[0]       # a refusal, not a failure


# ---------------------------------------------------------- axes that change nothing
@pytest.mark.parametrize("kw, name", [
    (dict(F0=0.0, Omega=[1.0, 2.0, 3.0]), "Omega"),
    (dict(phi=[0.0, 1.0, 2.0]), "phi"),
    (dict(Y0=1.0, Omega=1.0, phi=[0.0, 1.0]), "phi")])
def test_a_swept_axis_that_changes_nothing_is_refused(kw, name):
    with pytest.raises(ValueError, match=rf"Grid: {name} is swept \(\d values in .*\) "
                                         r"but .*every value would give the same "
                                         rf"result.*or leave {name} out"):
        sc.Grid(**SLIDER, **kw)


def test_a_forced_axis_is_swept_where_it_acts():
    grid = sc.Grid(**SLIDER, F0=[0.0, 1.0], Omega=[1.0, 2.0], phi=[0.0, 1.0])
    assert grid.dims == ("F0", "Omega", "phi")
    assert grid.rows(0, grid.size).shape[0] == 8


def test_a_study_sweeping_an_idle_frequency_is_refused_and_leaves_nothing(tmp_path,
                                                                          capsys):
    from sweepcore.cli import main
    study = tmp_path / "idle.toml"
    study.write_text(STUDY + "F0 = 0.0\nOmega = [1.0, 2.0]\n"
                     f'[output]\npath = "{tmp_path / "idle.nc"}"\n')
    code = main(["run", str(study), "--no-png"])
    err = capsys.readouterr().err
    assert code == 2
    assert "excitation.Omega: Omega is swept but nothing excites the slider" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["idle.toml"]


# ------------------------------------------------------------- curves and diagrams
FORCED = sc.Params(**SLIDER, F0=1.0, Omega=1.0)


@pytest.mark.parametrize("kw, exc, match", [
    (dict(Omega=np.array([1 + 1j, 2.0])), TypeError,
     r"Omega must hold real numbers, got \(1\+1j\) of type complex"),
    (dict(Omega=np.array([1.0, "a"], dtype=object)), TypeError,
     r"Omega must hold real numbers, got 'a' of type str"),
    (dict(Omega=["1", "2"]), TypeError, r"Omega must hold real numbers, got '1'"),
    (dict(Omega="12"), TypeError, r"Omega must be a 1-D array of >= 2 values, got '12'"),
    (dict(Omega=[1.0, 1.0]), ValueError, r"Omega axis has the duplicated value 1.0"),
    (dict(Omega=[1.0, 1e-12]), ValueError, r"Omega=1e-12 .*Omega/omega in"),
    (dict(Omega=[1.0, 2.0], direction=["up"]), ValueError,
     r"direction must be one of \('up', 'down', 'both'\), got \['up'\] of type list"),
    (dict(Omega=[1.0, 2.0], x0="0"), TypeError, r"x0 must be a real number, got '0'"),
    (dict(Omega=[1.0, 2.0], xdot0=float("nan")), ValueError, r"xdot0 must be finite")])
def test_frequency_response_refuses_by_name_before_work(kw, exc, match, monkeypatch):
    from sweepcore import response_curves
    monkeypatch.setattr(response_curves, "_follow", _no_work)
    with pytest.raises(exc, match=match):
        sc.frequency_response(FORCED, **kw)


def _no_work(*args, **kwargs):
    raise AssertionError("a response was computed")


@pytest.mark.parametrize("kw, exc, match", [
    (dict(transient=10 ** 9), ValueError, r"transient \+ periods = 1,000,000,000 \+ 32 "
                                          r"forcing periods.*at most 10,000,000"),
    (dict(periods=10 ** 9), ValueError, r"transient \+ periods = 400 \+ "
                                        r"1,000,000,000"),
    (dict(values=np.linspace(1.0, 2.0, 10 ** 6), periods=10 ** 6), SweepTooLarge,
     r"a stroboscopic diagram of 1,000,000 values with periods=1,000,000 .*needs "
     r"about .* of memory"),
    (dict(name="phi", values=[0.0, 90.0]), ValueError, r"phi is a phase in radians"),
    (dict(x0=None), TypeError, r"x0 must be a real number, got None")])
def test_stroboscopic_diagram_refuses_by_name_before_work(kw, exc, match, monkeypatch):
    monkeypatch.setattr(importlib.import_module("sweepcore.simulate"), "simulate",
                        _no_work)
    args = {"name": "Omega", "values": [1.0, 2.0], **kw}
    with pytest.raises(exc, match=match):
        sc.stroboscopic_diagram(FORCED, args.pop("name"), args.pop("values"), **args)
