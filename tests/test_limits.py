"""Inputs of the study file and the command line refused before any work."""
import numba
import pytest

from sweepcore import cli
from sweepcore.study import StudyError, parse_study, sweep_variables
from sweepcore.variables import OBSERVABLES

STUDY = """
[axes]
m = 5.0
k = 50.0
r_y = 10.0
v = {{ start = 1.0, stop = 2.0, num = 3 }}

[plot]
variables = {variables}
"""


def test_plot_variables_must_be_variables_of_a_sweep():
    with pytest.raises(StudyError, match=r"plot\.variables.*'nosuchvar' is not a "
                       r"variable of a sweep; known: amplitude"):
        parse_study(STUDY.format(variables='["amplitude", "nosuchvar"]'))
    study = parse_study(STUDY.format(variables='["regime", "amplitude", "x_eq"]'))
    assert study.plot["variables"] == ["regime", "amplitude", "x_eq"]


def test_every_observable_is_a_known_plot_variable():
    known = sweep_variables()
    assert set(OBSERVABLES) <= set(known)
    assert {"regime", "status", "converged", "v_hopf_measured"} <= set(known)


def test_too_many_threads_are_refused_without_a_traceback(capsys):
    top = numba.config.NUMBA_NUM_THREADS
    with pytest.raises(SystemExit) as stop:
        cli.main(["--threads", str(top + 1), "info", "nothing.nc"])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert f"--threads: must be at most {top}" in err and "Traceback" not in err
