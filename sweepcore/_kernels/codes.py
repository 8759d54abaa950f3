"""The one table of integer codes shared by kernels and the Python layer.

Kernels return these integers; ``sweepcore`` turns them into names (and CF
``flag_values`` / ``flag_meanings``) with the dictionaries at the bottom.
"""

# --- methods: the table lives with the dispatch (stepper.py) -----------------
from .stepper import (DOPRI5, EXACT, GPS, METHOD_CODES, METHOD_NAMES,  # noqa: E402,F401
                      METHOD_ORDER, RK4)

# --- phases (modes of the hybrid automaton) --------------------------------
STICK = 0      # zdot == 0, x moves with the belt
SLIDE_NEG = -1  # zdot < 0 (slider slower than the belt), r_a = -r_y + ...
SLIDE_POS = 1   # zdot > 0

# --- events ----------------------------------------------------------------
EV_NONE = 0
EV_SLIP = 1           # stick -> slide, at the exact time of eq. (27)
EV_STICK = 2          # slide -> stick of finite duration (|k x| < r_y at zdot = 0)
EV_NORMAL_STOP = 3    # zero-duration stop, relative motion reverses (eq. 30)
EV_ABNORMAL_STOP = 4  # zero-duration stop, relative motion goes on in the same
                      # direction: the tangential touch of eq. (31)
EV_XMAX = 5           # not a phase change: a maximum of x (Poincare section)
EV_XMIN = 6           # not a phase change: a minimum of x
EV_STOP_TIME = 7      # the driver reached the requested time

EVENT_NAMES = {
    EV_SLIP: "slip",
    EV_STICK: "stick",
    EV_NORMAL_STOP: "normal_stop",
    EV_ABNORMAL_STOP: "abnormal_stop",
    EV_XMAX: "x_max",
    EV_XMIN: "x_min",
}
EVENT_MEANINGS = {
    "slip": "stick -> slide: |k x| reached r_y (eq. 27)",
    "stick": "slide -> stick of finite duration: zdot = 0 with |k x| < r_y",
    "normal_stop": "zero-duration stop, slide-slide reversal of the relative motion (eq. 30)",
    "abnormal_stop": "zero-duration tangential stop, slide goes on in the same direction (eq. 31)",
}

# --- status of a run or of one grid point -----------------------------------
OK = 0                # converged (attractor) / reached t_end (simulation)
UNCONVERGED = 1       # budget spent before the attractor was recognised
STEP_BUDGET = 2       # max_steps exceeded
DIVERGED = 3          # state left the finite range (|x| or |zdot| > 1e150 / NaN)
GPS_DENOMINATOR = 4   # GPS denominator ||u||^2 - tau^2 ||f||^2 not safely positive
STEP_UNDERFLOW = 5    # adaptive step fell below the floating-point resolution of t
EVENT_FAILURE = 6     # an event could not be located (root polish failed)
BAD_METHOD = 7        # method not applicable (e.g. exact with alpha2 > 0)
STEP_TOO_LARGE = 8    # fixed step dt > 1/omega: gps/rk4 cannot resolve the oscillation
UNRESOLVED = 9        # a cycle next to the Hopf point that neither the shooting solve
                      # (float64 floor of the integrator) nor the normal form resolves
                      # to the tolerance
BELOW_RESOLUTION = 10  # the attractor's size is below float64 resolution at the
                       # point's length scale: its observables carry no digits
BAD_ROW = 11          # a parameter or option row of the wrong length (layout.NP, NO)
SCALE = 12            # friction too weak per natural period to tell attractors apart,
                      # or a time scale 1/omega beyond the kernels' range (set by
                      # sweepcore.law.flag_unresolvable, not by a kernel)

STATUS_NAMES = {
    OK: "ok",
    UNCONVERGED: "unconverged",
    STEP_BUDGET: "step_budget_exceeded",
    DIVERGED: "diverged",
    GPS_DENOMINATOR: "gps_denominator_guard",
    STEP_UNDERFLOW: "step_size_underflow",
    EVENT_FAILURE: "event_location_failed",
    BAD_METHOD: "method_not_applicable",
    STEP_TOO_LARGE: "fixed_step_too_large",
    UNRESOLVED: "unresolved",
    BELOW_RESOLUTION: "below_resolution",
    BAD_ROW: "bad_kernel_row",
    SCALE: "unresolvable_scale",
}

# --- regimes of an attractor -------------------------------------------------
R_EQUILIBRIUM = 0   # steady sliding at x_eq (eq. 43), amplitude 0
R_SLIP_CYCLE = 1    # limit cycle that never sticks for a finite time
R_STICK_SLIP = 2    # limit cycle with a finite stick every period
R_NEUTRAL = 3       # constant friction: a circle whose size is set by the start
R_STUCK = 4         # permanent stick (static belt, v = 0)
R_UNBOUNDED = 5     # the motion grows without bound (e.g. alpha2 = 0, alpha1 > 0, v = 0)
R_UNCONVERGED = 6   # budget spent, attractor not recognised
R_FAILED = 7        # numerical failure (see status)
R_APERIODIC = 8     # a forced response with no period up to the limit (its Lyapunov
                    # exponent says whether it is chaotic)

REGIME_NAMES = {
    R_EQUILIBRIUM: "equilibrium",
    R_SLIP_CYCLE: "slip_cycle",
    R_STICK_SLIP: "stick_slip",
    R_NEUTRAL: "neutral",
    R_STUCK: "stuck",
    R_UNBOUNDED: "unbounded",
    R_UNCONVERGED: "unconverged",
    R_FAILED: "failed",
    R_APERIODIC: "aperiodic",
}

# --- outcome of a boundary search (sweepcore.boundaries; the Python solvers' verdicts)
B_LOCATED = 0        # found to xtol (stick onset, label changes) / fitted (Hopf)
B_ABSENT = 1         # no such change in the bracket (or the continuation lost it)
B_FAILED = 2         # an attractor the search needed failed or did not converge
B_INCONSISTENT = 3   # the smooth indicator and the regime labels disagree

SEARCH_NAMES = {
    B_LOCATED: "located",
    B_ABSENT: "absent",
    B_FAILED: "attractor_failed",
    B_INCONSISTENT: "inconsistent",
}
