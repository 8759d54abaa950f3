"""Column layout of the flat float64 arrays that kernels take and return.

A parameter row ``p`` (length ``NP``) describes one slider and its start; an option
row ``o`` (length ``NO``) describes the numerical method; the observables row
(length ``NOBS``) is what the attractor kernel writes. Names are defined once, here.
"""

# parameter row p
M, K, RY, V, A1, A2, X0, XD0 = range(8)
NP = 8

# option row o
O_METHOD = 0     # method code (codes.EXACT, GPS, RK4, DOPRI5)
O_RTOL = 1       # relative tolerance of the adaptive method / convergence tolerance
O_DT = 2         # fixed step of gps and rk4 [s]; <= 0 means 0.02 * 2 pi / omega
O_MAX_STEPS = 3  # step budget of one run (accepted + rejected + polish steps)
O_MAX_TIME = 4   # time budget of one attractor search [periods 2 pi / omega]
O_GPS_A = 5      # shift constant a of the GPS coordinates [cm]; NaN -> length scale
O_GRAZE = 6      # relative tolerance of tangential touches (graze) and exit snaps
O_LX = 7         # the point's length scale [cm]   } filled per point by
O_LV = 8         # the point's velocity scale [cm/s] } attractor.resolve_options
NO = 9

# simulation state st
S_T, S_X, S_ZD, S_MODE, S_ARMED, S_H, S_N = range(7)   # S_N: stepper calls so far
NS = 7

# accumulators acc (reset by the caller at the start of a measured interval)
A_IX = 0        # int x dt                        [cm s]
A_IXD2 = 1      # int xdot^2 dt                   [cm^2 / s]
A_WF = 2        # int r_a xdot dt (friction work on the slider, sign: dE = -W) [kN cm]
A_TSTICK = 3    # time spent sticking             [s]
A_XMAX = 4
A_XMIN = 5
A_XDMAX = 6
A_XDMIN = 7
A_NSTEPS = 8    # integrator steps taken (all kinds)
A_NSTICK = 9    # finite sticks begun
A_DT = 10       # duration of the interval [s], summed from step lengths so that it
                # keeps its digits when absolute times are large (after long sticks)
NA = 11

# observables row written by the attractor kernel
OB_AMPLITUDE = 0
OB_MEAN = 1
OB_VAMPLITUDE = 2
OB_CYCLE_SIZE = 3
OB_PERIOD = 4
OB_STICK_FRACTION = 5
OB_STICKS_PER_PERIOD = 6
OB_T_SETTLE = 7
OB_REGIME = 8
OB_STATUS = 9
OB_NSTEPS = 10
OB_X_MAX = 11
OB_X_MIN = 12
OB_XDOT_MAX = 13  # largest xdot on the attractor (grazing indicator: v - xdot_max)
OB_FLOQUET = 14   # nontrivial Floquet multiplier of a slip cycle (return-map derivative)
NOBS = 15
