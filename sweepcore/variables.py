"""Metadata of every output variable, declared once (units, long names, codes).

Used by ``attractor()``, ``sweep()`` and the netCDF writer so that a variable means
the same thing wherever it appears. Units are UDUNITS strings (CF section 3.1).
"""
from ._kernels import codes, layout

# name -> (column in the kernel's observables row, units, long_name, comment)
OBSERVABLES = {
    "amplitude": (layout.OB_AMPLITUDE, "cm", "vibration amplitude",
                  "half peak-to-peak of x on the attractor; 0 at an equilibrium"),
    "mean": (layout.OB_MEAN, "cm", "mean position",
             "time average of x over whole periods of the attractor (x_eq at an "
             "equilibrium, eq. 43)"),
    "velocity_amplitude": (layout.OB_VAMPLITUDE, "cm s-1", "velocity amplitude",
                           "half peak-to-peak of xdot on the attractor"),
    "cycle_size": (layout.OB_CYCLE_SIZE, "cm", "limit-cycle size",
                   "sqrt(area/pi) of the orbit in the (x, xdot/omega) plane; the "
                   "radius of a circle, 0 at an equilibrium"),
    "period": (layout.OB_PERIOD, "s", "period of the attractor",
               "NaN at an equilibrium or a permanent stick (no period)"),
    "stick_fraction": (layout.OB_STICK_FRACTION, "1", "fraction of the period stuck",
                       "time stuck on the belt / period"),
    "sticks_per_period": (layout.OB_STICKS_PER_PERIOD, "1", "finite sticks per period",
                          "number of sticks of finite duration in one period; -1 "
                          "where no attractor was measured (see status)"),
    "t_settle": (layout.OB_T_SETTLE, "s", "settling time",
                 "time at which the measured period of the attractor began"),
    "x_max": (layout.OB_X_MAX, "cm", "largest x on the attractor", ""),
    "x_min": (layout.OB_X_MIN, "cm", "smallest x on the attractor", ""),
    "xdot_max": (layout.OB_XDOT_MAX, "cm s-1", "largest velocity on the attractor",
                 "largest xdot over the period; a slip cycle grazes the belt when it "
                 "reaches v (stick onset)"),
    "floquet": (layout.OB_FLOQUET, "1", "Floquet multiplier of the cycle",
                "derivative of the Poincare return map (x maxima) at the slip cycle: "
                "< 1 stable, 1 at the Hopf point; 0 for stick-slip cycles (every "
                "slip starts from the breakaway point); NaN without a slip cycle"),
    "n_steps": (layout.OB_NSTEPS, "1", "integrator steps spent on the point",
                "all stepper calls, including rejected steps and event polishing"),
}

# a forced response (sweepcore.forced): the observables of its period n T, T = 2 pi /
# Omega (columns of the forced row, layout.NFOB). cycle_size is not defined for it.
FORCED_OBSERVABLES = {
    "multiplicity": (layout.OB_MULTIPLICITY, "1", "multiplicity of the response",
                     "n: the response repeats after n forcing periods 2 pi/Omega; NaN "
                     "for an aperiodic response or an unforced point"),
    "period": (layout.OB_PERIOD, "s", "period of the response",
               "n 2 pi/Omega; NaN for an aperiodic response"),
    "amplitude": (layout.OB_AMPLITUDE, "cm", "vibration amplitude",
                  "half of max x - min x over the response's period (over the sampled "
                  "periods for an aperiodic response)"),
    "mean": (layout.OB_MEAN, "cm", "mean position",
             "time average of x over the response's period"),
    "x_max": (layout.OB_X_MAX, "cm", "largest x of the response", ""),
    "x_min": (layout.OB_X_MIN, "cm", "smallest x of the response", ""),
    "xdot_max": (layout.OB_XDOT_MAX, "cm s-1", "largest velocity of the response", ""),
    "velocity_amplitude": (layout.OB_VAMPLITUDE, "cm s-1", "velocity amplitude",
                           "half of max xdot - min xdot over the response's period"),
    "sticks_per_period": (layout.OB_STICKS_PER_PERIOD, "1", "finite sticks per period",
                          "sticks of finite duration in one response period; -1 where "
                          "none was measured"),
    "stops_per_period": (layout.OB_STOPS_PER_PERIOD, "1",
                         "zero-duration stops per period",
                         "slide-slide stops (eq. 22: reversals and touches) in one "
                         "response period, counted apart from the sticks (Hong & Liu's "
                         "classification); -1 where none was measured"),
    "stick_fraction": (layout.OB_STICK_FRACTION, "1", "fraction of the period stuck",
                       "time stuck / response period"),
    "floquet": (layout.OB_FLOQUET, "1", "largest Floquet multiplier modulus",
                "largest |multiplier| of the stroboscopic map P^n at the response: < 1 "
                "stable; 0 is the second multiplier of every response with a stick"),
    "lyapunov": (layout.OB_LYAPUNOV, "s-1", "largest Lyapunov exponent",
                 "ln(floquet)/period for a periodic response; measured over 256 "
                 "forcing periods (two runs, renormalised every period) for an "
                 "aperiodic one: > 0 chaotic"),
    "lyapunov_error": (layout.OB_LYAPUNOV_ERROR, "s-1", "error of the Lyapunov exponent",
                       "standard error over 8 blocks of 32 periods; 0 for a periodic "
                       "response (its exponent is the multiplier's)"),
    "t_settle": (layout.OB_T_SETTLE, "s", "settling time",
                 "time after which the response was found (forcing periods iterated "
                 "from the start)"),
    "x_section": (layout.OB_X_SECTION, "cm", "position at the periodic point",
                  "x of the response at t = 0 mod n 2 pi/Omega, where the stroboscopic "
                  "map is taken (the load's phase phi there): a fixed point of P^n that "
                  "any integrator can check; NaN for an aperiodic response"),
    "xdot_section": (layout.OB_XDOT_SECTION, "cm s-1", "velocity at the periodic point",
                     "xdot of the response at t = 0 mod n 2 pi/Omega (see x_section)"),
    "n_steps": (layout.OB_NSTEPS, "1", "integrator steps spent on the point",
                "all stepper calls, including rejected steps, event polishing and the "
                "tangent's re-steps"),
}

# observables stored as integers (int64), counts, so that they read as counts in
# every tool (CSV "68", not "68.0"): name -> the value stored where the kernel
# measured none (NaN), or None where it always measures one
INTEGER = {"n_steps": None, "sticks_per_period": -1, "stops_per_period": -1}
REGIME = {
    "units": "1",
    "long_name": "attractor regime",
    "flag_values": sorted(codes.REGIME_NAMES),
    "flag_meanings": " ".join(codes.REGIME_NAMES[k] for k in sorted(codes.REGIME_NAMES)),
}
STATUS = {
    "units": "1",
    "long_name": "numerical status of the point",
    "flag_values": sorted(codes.STATUS_NAMES),
    "flag_meanings": " ".join(codes.STATUS_NAMES[k] for k in sorted(codes.STATUS_NAMES)),
}

# analytic quantities stored beside the measured ones
ANALYTIC = {
    "q": ("s-1", "Hopf quantity q = -(c + F'(-v))/m",
          "the equilibrium's eigenvalues solve lambda^2 - q lambda + omega^2 = 0; "
          "eq. (46), (alpha1 - 3 alpha2 v^2)/m, for the paper's law"),
    "v_star": ("cm s-1", "analytic Hopf belt speed (the lowest)",
               "where the linearised damping c + F'(-v) vanishes; sqrt(alpha1/(3 "
               "alpha2)) below eq. (51) for the paper's law; inf: steady sliding "
               "unstable at every speed, NaN: stable at every speed"),
    "v_star_2": ("cm s-1", "second analytic Hopf belt speed",
                 "NaN unless c + F'(-v) has two roots (possible only for r_k > r_y)"),
    "first_lyapunov": ("s-1 cm-2", "first Lyapunov coefficient at v_star",
                       "averaging: dA/dt = q A/2 + l1 A^3; negative: supercritical "
                       "Hopf point, positive: subcritical; NaN without a Hopf speed"),
    "x_eq": ("cm", "steady-sliding equilibrium position",
             "k x_eq = -F(-v); eq. (43) for the paper's law"),
    "omega": ("s-1", "natural frequency sqrt(k/m)", ""),
}
# beside the located boundaries (sweepcore.boundaries), along v
STICK_ONSET_ESTIMATE = ("cm s-1", "averaging estimate 2 v*/sqrt(5) of the stick onset",
                        "the averaged cycle's velocity amplitude 2 sqrt(v*^2 - v^2) "
                        "reaches v")

# slip cycles of the return-map scan (sweepcore.cycles), stable and unstable, over
# the dimension ``cycle``: name -> (column of the observables row, units, long_name,
# comment)
CYCLE_OBSERVABLES = {
    "cycle_amplitude": (layout.OB_AMPLITUDE, "cm", "amplitude of the slip cycle",
                        "half peak-to-peak of x on the cycle"),
    "cycle_mean": (layout.OB_MEAN, "cm", "mean position on the slip cycle", ""),
    "cycle_x_max": (layout.OB_X_MAX, "cm", "largest x on the slip cycle",
                    "its section point (at rest) for v > 0"),
    "cycle_x_min": (layout.OB_X_MIN, "cm", "smallest x on the slip cycle", ""),
    "cycle_xdot_max": (layout.OB_XDOT_MAX, "cm s-1", "largest velocity on the slip cycle",
                       "below v: the cycle never reaches the belt; it grazes at v"),
    "cycle_period": (layout.OB_PERIOD, "s", "period of the slip cycle", ""),
    "cycle_floquet": (layout.OB_FLOQUET, "1", "Floquet multiplier of the slip cycle",
                      "slope of the return map at the cycle: < 1 stable, > 1 unstable "
                      "(in the plane a basin boundary)"),
}
N_CYCLES = ("1", "number of slip cycles found",
            "stop-free slip cycles bracketed by the scan of the return map, stable "
            "and unstable")
CYCLE_STABILITY = "stability of the slip cycle (Floquet multiplier below or above 1)"

# basin stability (sweepcore.basins), over the grid's dimensions and ``attractor``
BASIN_FRACTION = ("1", "basin fraction of the attractor",
                  "share of the box of start states (x0, xdot0) that ends on it")
BASIN_FRACTION_ERROR = ("1", "error of the basin fraction",
                        "exact route: bound from the polygon's discretisation and the "
                        "cycle's tolerance; sampled route: binomial standard error "
                        "sqrt(f (1 - f) / N)")
N_ATTRACTORS = ("1", "number of attractors found in the box",
                "distinct attractors the starts of the point end on (unconverged and "
                "failed runs not counted)")
SAMPLES = ("1", "starts run for the point",
           "sampled route: the Monte-Carlo starts; exact route: the checks of its "
           "premise")

# a followed branch of forced responses (sweepcore.follow_response), along `point`,
# beside the forced observables it shares: name -> (units, long_name, comment)
BRANCH = {
    "floquet": ("1", "largest multiplier modulus",
                "largest |multiplier| of P^n at the periodic point (the eigenvalues of "
                "the kernels' tangent, saltation included): < 1 stable"),
    "multiplier_real": ("1", "real part of a multiplier of P^n",
                        "the two Floquet multipliers, largest modulus first (dimension "
                        "multiplier); a start stuck at t = 0 has the second exactly 0"),
    "multiplier_imag": ("1", "imaginary part of a multiplier of P^n",
                        "0 for real multipliers; a complex pair is conjugate"),
    "stable": ("1", "the response is stable", "1 where floquet < 1"),
    "special_value": ("", "parameter of the special point's event",
                      "the middle of the final bracket of a change of sticks or stops "
                      "(the point itself is the first of the new pattern), the root "
                      "of the test function of a fold, branch point, period doubling "
                      "or torus (the point itself); NaN for a regular point"),
    "special_width": ("", "error bound of special_value",
                      "half the final bracket of a pattern change, the secant's error "
                      "estimate of a test function's root; 0 for a regular point"),
    "arclength": ("1", "pseudo-arclength from the start",
                  "sum of the steps in the scaled unknowns (x/L, xdot/Lv, "
                  "parameter/its scale)"),
}
