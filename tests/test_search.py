"""The attractor search's pieces on synthetic inputs: the pure Newton decision on a
section history, the accumulator layout, and the entry kernels' row checks.

``sections.newton_decision`` is pure (numbers in, an action out), so every branch is
driven here by a hand-made history whose right answer follows from the map it
describes: a linear return map ``P(a) = a* + lam (a - a*)`` has slope lam and its
Newton step from any a0 lands on a* exactly.
"""
import math

import numpy as np
import pytest

from sweepcore._kernels import codes, entries, layout, sections as S, stepper
from sweepcore._kernels.jit import python_callable
from sweepcore._kernels.laws.analytic import Polynomial
from sweepcore.options import make_options

TOL, LX, XE = 1e-8, 1.0, 0.0
newton_decision = python_callable(S.newton_decision)


def decide(a0, a1, dP, e1=0, e2=0, rtol_h0=1e-8, rtol_h1=1e-8, rtol=1e-8,
           after_jump=False, err_jump=0.0, rest=0, nf_here=False, on_nf=False,
           a_nf=math.nan):
    return newton_decision(a0, a1, dP, XE, e1, e2, rtol_h0, rtol_h1, rtol, TOL, LX,
                           after_jump, err_jump, rest, nf_here, on_nf, a_nf)


def linear_return(a0, a_star, lam):
    return a_star + lam * (a0 - a_star)


def test_newton_step_of_a_linear_map_lands_on_its_fixed_point():
    a0, a_star, lam = 1.0, 0.8, 0.5
    action, value, rtol, rest, err0 = decide(a0, linear_return(a0, a_star, lam), lam,
                                             rtol_h1=1e-10, rtol=1e-10)
    assert action == S.NEWTON_JUMP
    assert value == pytest.approx(a_star, rel=1e-15)
    assert err0 == pytest.approx(a0 - a_star, rel=1e-14)     # |F| / (1 - P')


def test_a_return_at_the_fixed_point_is_accepted_with_its_slope_as_multiplier():
    a_star, lam = 0.8, 0.5
    a0 = a_star + 1e-10
    action, value, *_ = decide(a0, linear_return(a0, a_star, lam), lam,
                               rtol_h1=2e-9, rtol=2e-9)
    assert action == S.ACCEPT and value == lam


def test_acceptance_waits_for_returns_computed_finely_enough():
    """The integrator's noise is amplified by 1/(1 - P'): the returns must be
    computed at rtol <= tol (1 - P')/2 before a residual is believed; a coarser
    tolerance is lowered to 90 % of that (the slope moves in its last digits between
    iterates; the bound must hold for the accepted return) and Newton goes on."""
    a_star, lam = 0.8, 0.9
    a0 = a_star + 1e-10
    action, _v, rtol, *_ = decide(a0, linear_return(a0, a_star, lam), lam,
                                  rtol_h1=1e-8, rtol=1e-8)
    assert action != S.ACCEPT
    assert rtol == pytest.approx(0.9 * 0.5 * TOL * (1 - lam))


def test_newton_iterates_keep_the_users_tolerance_until_the_last_two_returns():
    """Far from the fixed point a Newton jump keeps the tolerance in force; once the
    iterate after next is predicted within the acceptance bound (Newton's error
    squares), the returns from here on are computed at 90 % of tol (1 - P')/2."""
    a_star, lam = 0.8, 0.5
    for a0, lowered in ((1.0, False), (a_star + 1e-6, True)):
        action, _v, rtol, *_ = decide(a0, linear_return(a0, a_star, lam), lam,
                                      rtol_h1=1e-8, rtol=1e-8)
        assert action == S.NEWTON_JUMP
        assert rtol == (pytest.approx(0.9 * 0.5 * TOL * (1 - lam)) if lowered else 1e-8)


def test_an_expanding_return_is_followed():
    action, *_ = decide(1.0, 1.1, 1.5)
    assert action == S.EXPAND


def test_a_step_is_clamped_to_halving_the_distance_to_x_eq():
    # a map whose fixed point (0.1) is closer to x_eq than half the distance of a1
    a0, a_star, lam = 1.0, 0.1, 0.3
    a1 = linear_return(a0, a_star, lam)
    action, value, *_ = decide(a0, a1, lam, rtol_h1=1e-12, rtol=1e-12)
    assert action == S.NEWTON_JUMP and value == pytest.approx(XE + 0.5 * (a1 - XE))


def test_no_newton_step_across_a_change_of_itinerary():
    a0, a_star, lam = 1.0, 0.8, 0.5
    action, *_ = decide(a0, linear_return(a0, a_star, lam), lam, e1=0, e2=2,
                        rtol_h1=1e-12, rtol=1e-12)
    assert action == S.FOLLOW


def test_newton_steps_from_the_first_whole_return_after_a_partial_one():
    """The return before a0 that ends the start's transient has an unknown itinerary
    (-1): the slope of the whole return a0 -> a1 is used at once."""
    a0, a_star, lam = 1.0, 0.8, 0.5
    action, value, *_ = decide(a0, linear_return(a0, a_star, lam), lam, e1=-1, e2=2,
                               rtol_h1=1e-12, rtol=1e-12)
    assert action == S.NEWTON_JUMP and value == pytest.approx(a_star, rel=1e-14)


def test_a_jump_that_did_not_halve_the_distance_rests_newton_for_three_returns():
    a0, a_star, lam = 1.0, 0.8, 0.5
    action, _v, _r, rest, err0 = decide(a0, linear_return(a0, a_star, lam), lam,
                                        rtol_h0=1e-12, rtol_h1=1e-12, rtol=1e-12,
                                        after_jump=True, err_jump=0.3)
    assert action == S.FOLLOW and rest == 3 and err0 >= 0.5 * 0.3
    action, _v, _r, rest, _e = decide(a0, linear_return(a0, a_star, lam), lam,
                                      rtol_h1=1e-12, rtol=1e-12, rest=3)
    assert action == S.FOLLOW and rest == 2


def test_an_unresolved_slope_lowers_the_tolerance_then_reports_neutral():
    """A slope within the integrator's noise of 1: tighten by 100x down to the
    float64 floor; there, with returns that stand still, the regime is unknown."""
    action, _v, rtol, *_ = decide(1.0, 1.0 - 1e-15, 1.0 - 1e-12)
    assert action == S.FOLLOW and rtol == pytest.approx(1e-10)
    floor = S.RTOL_FLOOR
    action, value, *_ = decide(1.0, 1.0 - 1e-15, 1.0 - 1e-15, rtol_h1=floor, rtol=floor)
    assert action == S.NEUTRAL and value == 1.0 - 1e-15


def test_next_to_the_hopf_point_the_normal_form_decides_where_valid():
    slope = 1.0 - 1e-7        # tol (1 - P')/2 = 5e-16 < the float64 floor of 1e-14
    action, value, *_ = decide(1.0, 1.0 - 1e-9, slope, nf_here=True, a_nf=0.5)
    assert action == S.NF_JUMP and value == 0.5
    action, *_ = decide(1.0, 1.0 - 1e-9, slope, nf_here=True, on_nf=True, a_nf=0.5,
                        rtol_h1=1e-9)
    assert action == S.ACCEPT_NF
    # where the normal form is not valid (a Stribeck law, gps, subcritical): no jump
    action, *_ = decide(1.0, 1.0 - 1e-9, slope, nf_here=False, a_nf=0.5)
    assert action not in (S.NF_JUMP, S.ACCEPT_NF)


def test_every_accumulator_slot_is_combined_exactly_once():
    slots = layout.SUMMED + layout.MAXED + layout.MINNED
    assert sorted(slots) == list(range(layout.NA))


@pytest.mark.parametrize("bad", ["p", "o", "out"])
def test_entry_kernel_refuses_rows_of_the_wrong_length(bad):
    p = np.zeros(layout.NP + (1 if bad == "p" else 0))
    p[[layout.M, layout.K, layout.RY, layout.V, layout.RK, layout.XD0]] = 1.0
    o = make_options()
    if bad == "o":
        o = np.append(o, 0.0)
    out = np.zeros((1, layout.NOBS + (2 if bad == "out" else 0)))
    entries.entry("attractor_rows", stepper.DOP853)(p[None, :], Polynomial(), o, out)
    assert out[0, layout.OB_STATUS] == codes.BAD_ROW
    assert out[0, layout.OB_REGIME] == codes.R_FAILED
