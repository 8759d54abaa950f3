"""Column layout of the flat float64 arrays that kernels take and return.

A parameter row ``p`` (length ``NP``) describes one slider and its start; an option
row ``o`` (length ``NO``) describes the numerical method; the observables row
(length ``NOBS``) is what the attractor kernel writes. Names are defined once, here.
"""

# parameter row p: the slider, the analytic law's parameters and the start. Only the
# law modules (laws/analytic.py, sweepcore/laws/analytic.py) read RY, A1, A2, RK and VS
# (a test checks it); a law given as an object carries its data apart (law.py).
M = 0        # mass [kN s^2/cm]
K = 1        # stiffness [kN/cm]
RY = 2       # static friction bound r_y [kN] (the largest force sticking holds)
V = 3        # belt speed [cm/s]
A1 = 4       # linear friction-speed coefficient alpha1 [kN s/cm]
A2 = 5       # cubic friction-speed coefficient alpha2 [kN s^3/cm^3]
C = 6        # viscous damping on the slider [kN s/cm]
RK = 7       # kinetic friction level r_k [kN] (r_k = r_y: no Stribeck term)
VS = 8       # Stribeck speed v_s [cm/s]
X0 = 9       # start position [cm]
XD0 = 10     # start velocity [cm/s]
LAW = 11     # index of the row's law among the call's laws (read by Python only)
# the excitation's per-point parameters: read by the excitation modules only
# (excitations/, sweepcore/excitations/; a test checks it). F0 = Y0 = 0: no excitation.
F0 = 12      # amplitude of the load F0 p(Omega t + phi) on the slider [kN]
OMEGA = 13   # excitation frequency Omega [rad/s]
PHI = 14     # phase of the load phi [rad]
Y0 = 15      # amplitude of the anchor's motion y = Y0 cos(Omega t) [cm]
LOAD = 16    # index of the row's load shape among the call's loads (read by Python only)
NP = 17

# option row o
O_METHOD = 0     # method code (the row of stepper.METHODS; -1: "auto")
O_RTOL = 1       # relative tolerance of the adaptive method / convergence tolerance
O_DT = 2         # fixed step of gps and rk4 [s]; <= 0 means 0.02 * 2 pi / omega
O_MAX_STEPS = 3  # step budget of one run (accepted + rejected + polish steps)
O_MAX_TIME = 4   # time budget of one attractor search [periods 2 pi / omega]
O_GPS_A = 5      # shift constant a of the GPS coordinates [cm]; NaN -> length scale
O_GRAZE = 6      # relative tolerance of tangential touches (graze) and exit snaps
O_LX = 7         # the point's length scale [cm]   } filled per point by
O_LV = 8         # the point's velocity scale [cm/s] } attractor.resolve_options
O_PERIODS = 9    # a forced response: the largest multiplicity n sought (P^n)
NO = 10

# simulation state st
S_T, S_X, S_ZD, S_MODE, S_ARMED, S_H, S_N = range(7)   # S_N: stepper calls so far
S_TOUCH = 7     # 1 where the last zdot = 0 event was a tangential touch (driver)
S_SECTIONS = 8  # extrema of x: 0 stop at each, 1 stop at the section's only (the
                # attractor search, driver._section), 2 stop at none (noted only)
S_TRACK = 9     # 1: the tangent below rides along (variational equations, saltation)
S_J = 10        # the tangent: d(x, zdot)/d(start), 4 slots row by row (J11 J12 J21 J22)
NSTATE = 14     # the state proper (what a search keeps of it); then scratch:
S_STAGES = 14   # the tangent's stage slopes (variational.py), 4 a stage, 16 stages
NS = 78

# accumulators acc (reset by the caller at the start of a measured interval)
A_IX = 0        # int x dt                        [cm s]
A_IXD2 = 1      # int xdot^2 dt                   [cm^2 / s]
A_WF = 2        # int r_a xdot dt (friction work on the slider, sign: dE = -W) [kN cm]
A_TSTICK = 3    # time spent sticking             [s]
A_XMAX = 4
A_XMIN = 5
A_XDMAX = 6
A_XDMIN = 7
A_NSTICK = 8    # finite sticks begun
A_DT = 9        # duration of the interval [s], summed from step lengths so that it
                # keeps its digits when absolute times are large (after long sticks)
A_ILAW = 10     # int of the law's non-polynomial slope term (law.law_integrand) dt [s]
A_NSTOP = 11    # zero-duration stops (slide-slide) passed (the forced driver)
NA = 12
# how accumulators of consecutive intervals combine (attractor search): sums, maxima,
# minima. Every slot is in exactly one of these (a test checks it).
SUMMED = (A_IX, A_IXD2, A_WF, A_TSTICK, A_NSTICK, A_DT, A_ILAW, A_NSTOP)
MAXED = (A_XMAX, A_XDMAX)
MINNED = (A_XMIN, A_XDMIN)

# the attractor search's accumulators: one (NACC, NA) array, a row per interval
ACC_STEP = 0    # what the driver adds during one advance (cleared after each)
ACC_CYC = 1     # since the last reset (a stick-slip period being measured)
ACC_SEC = 2     # since the last section (x maximum)
ACC_LAST = 3    # the last whole return (section to section)
NACC = 4

# attractor-search state w: one array, named slots (attractor.py, sections.py).
# Flags are 0/1, counts are exact integers in float64.
W_TOL = 0          # the user's tolerance (relative to the length scale)
W_LX = 1           # length scale r_y/k + |v|/omega [cm]
W_OMEGA = 2        # natural frequency [1/s]
W_T_NAT = 3        # natural period 2 pi/omega [s]
W_T_BUDGET = 4     # sliding-time budget [s]
W_XS = 5           # breakaway point [cm]
W_NF_OK = 6        # the normal form may be used (law.normal_form_valid, not gps)
W_ODE = 7          # the method follows the ODE (not gps): certificate, Liouville slope
W_CONSERVATIVE = 8  # a conservative sliding field (law.conservative): a neutral family
W_T_OFF = 9        # absolute time of the local clock's origin [s] (reset after sticks)
W_T_SLIDE = 10     # sliding time so far [s] (only sliding counts against the budget)
W_MODE0 = 11       # phase before the last advance
W_RESET_SEEN = 12  # the motion has passed the breakaway point
W_T_CYC = 13       # absolute time of that reset [s]
W_N_SEC = 14       # sections since the last reset or jump
W_N_EV = 15        # phase events since the last section
W_SALT = 16        # log of the saltation factors since the last section
W_T_LAST = 17      # absolute time at which the last whole return began [s]
W_RTOL = 18        # integration tolerance in force (lowered for the last returns)
W_SEEDED = 19      # the motion was moved to the normal form's cycle once
W_ON_NF = 20       # ... and the last section was that jump
W_NF_FLOOR = 21    # ... whose return float64 cannot time to tol
W_JUMPED = 22      # the last section was a Newton jump ...
W_ERR_JUMP = 23    # ... from this estimated distance to the fixed point [cm]
W_E_JUMP = 24      # ... along this itinerary (phase events per return)
W_A_FROM = 25      # ... from this section point [cm]
W_E_REST = 26      # itinerary on which Newton is suspended
W_NEWTON_REST = 27  # returns to follow without Newton steps
W_A = 28           # section values, 4 slots, newest last [cm]
W_TH = 32          # their local times, 4 slots [s]
W_E = 36           # phase events in each of the last 3 returns
W_SALTH = 39       # log saltation of the last 2 returns
W_RTOLH = 41       # tolerance of the last 2 returns
W_FD_PROBE = 43    # gps (own_map_step): the last return was a probe
W_FD_A0 = 44       # ... of the base return a0 -> a1 [cm]
W_FD_A1 = 45
W_FD_DELTA = 46    # ... started at a0 + delta [cm]
W_FD_SLOPE = 47    # the slope it measured (NaN: none yet)
W_TOUCHED = 48     # a stick since the last reset began at a touch (S_TOUCH)
NW = 49

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
# a forced response's row: the columns above (OB_FLOQUET: the largest |multiplier| of
# the stroboscopic map P^n; OB_CYCLE_SIZE and OB_T_SETTLE as documented for it) and
OB_MULTIPLICITY = 15   # n: the response's period is n forcing periods
OB_STOPS_PER_PERIOD = 16  # zero-duration stops per response period
OB_LYAPUNOV = 17       # largest Lyapunov exponent [1/s] (aperiodic responses)
OB_LYAPUNOV_ERROR = 18  # its error estimate [1/s]
OB_X_SECTION = 19      # the periodic point: x [cm] and xdot [cm/s] at t = 0 mod n T,
OB_XDOT_SECTION = 20   # where the stroboscopic map is taken (NaN: no period found)
NFOB = 21
# an image of the stroboscopic map (strobe.image_point): after the NFOB columns
IM_MODE0 = 0    # the start's phase (stuck: its velocity is v, not free)
IM_MODE = 1     # the image's phase
IM_X = 2        # P^n's x [cm]
IM_XDOT = 3     # P^n's xdot [cm/s]
IM_J = 4        # its Jacobian d(x, zdot)/d(x0, zdot0), 4 slots row by row
NIM = 8
