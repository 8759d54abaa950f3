"""Hostile input to the Python API is refused before any work, naming the parameter
and the value, never as a raw TypeError/OverflowError from deep inside.

What is proven, one probe of the issue-23 battery each: integers beyond float64, a
grid too large for a flat index, a study range too large to build, the arguments of
``estimate``, ``sweep`` and ``locate_boundaries`` (types, chunks, overwrite, client
and scheduler each blamed by name).
"""
import time

import numpy as np
import pytest

import sweepcore as sc
from sweepcore.study import StudyError, parse_study

GOOD = dict(m=5.0, k=50.0, r_y=10.0, v=5.0, alpha1=1.0, alpha2=0.01)


def small_grid():
    return sc.Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, alpha2=0.01, v=[4.0, 5.0])


# ------------------------------------------------------------ numbers and sizes
@pytest.mark.parametrize("value, shown", [(10**400, "1e400"), (-10**5000, "-1e5000")],
                         ids=["1e400", "-1e5000"])
def test_integer_beyond_float64_is_refused_by_name(value, shown):
    with pytest.raises(ValueError, match=rf"m must be finite, got an integer of about "
                                         rf"{shown}, beyond the largest float64"):
        sc.Params(**{**GOOD, "m": value})


def test_integer_beyond_float64_in_an_axis_names_the_element():
    for axis in ([5.0, 10**400], np.array([5.0, 10**400], dtype=object)):
        with pytest.raises(ValueError, match=r"m must be finite.*1e400.*\(element 1 "
                                             r"of the m axis\)"):
            sc.Grid(**{**GOOD, "m": axis})


def test_grid_beyond_a_flat_index_is_refused_at_construction():
    axis = np.arange(1.0, 1e4 + 1)
    with pytest.raises(ValueError, match=r"Grid of 1e\+20 points \(m: 10000 x k: "
                                         r"10000 x r_y: 10000 x v: 10000 x alpha1: "
                                         r"10000\): more than a flat index counts"):
        sc.Grid(m=axis, k=axis, r_y=axis, v=axis, alpha1=axis)


@pytest.mark.parametrize("num", ["1_000_000_000_000", "99999999999999999999999"])
def test_study_range_too_large_is_refused_before_it_is_built(num):
    text = f"[axes]\nm = 5.0\nk = 50.0\nr_y = 10.0\nv = {{ start = 1.0, stop = 2.0, " \
           f"num = {num} }}\n"
    t0 = time.perf_counter()
    with pytest.raises(StudyError, match=r"axes: the grid has \d+ points, more than "
                                         r"50000000; split the study"):
        parse_study(text)
    # refused from the table, not after building 8 TB of linspace: no MemoryError,
    # no numpy "Maximum allowed size exceeded" (the clock only guards a hang)
    assert time.perf_counter() - t0 < 60
