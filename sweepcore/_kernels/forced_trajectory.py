"""One run of the forced driver, sampled at given times, with its event log (the
forced counterpart of ``trajectory.py``; absolute time, no restart of the clock)."""
import numpy as np

from . import codes
from .excitation import coefficients, forcing_period
from .forced_attractor import forced_options
from .forced_driver import advance_forced, initial_forced
from .jit import kernel, runtime
from .layout import NS, S_MODE, S_N, S_T, S_X, S_ZD, X0, XD0


@kernel
def run_forced_trajectory(p, lw, ex, o_in, t_samples, out_x, out_zd, out_mode, ev_t,
                          ev_kind, ev_x, ev_zd, acc):
    """Run from (p[X0], p[XD0]) at t = 0 and fill the sample and event arrays;
    returns (n_events, status, n_steps) as ``trajectory.run_trajectory``."""
    fa, fb, om = coefficients(ex, p)
    _T = forcing_period(ex, p)
    o = forced_options(p, lw, fa, fb, om, o_in)
    ws = np.empty((8, 12))
    vw = np.zeros((2, 4))
    st = np.zeros(NS)
    initial_forced(st, p[X0], p[XD0], p, lw, fa, fb, om, o)
    n_ev = 0
    cap = ev_t.shape[0]
    status = codes.OK
    for i in range(t_samples.shape[0]):
        ts = t_samples[i]
        while st[S_T] < ts and status == codes.OK:
            ev, status = advance_forced(st, p, lw, fa, fb, om, o, acc, ws, vw, ts,
                                        runtime(True), runtime(False))
            if ev == codes.EV_SLIP or ev == codes.EV_STICK or \
                    ev == codes.EV_NORMAL_STOP or ev == codes.EV_ABNORMAL_STOP:
                if n_ev < cap:
                    ev_t[n_ev] = st[S_T]
                    ev_kind[n_ev] = ev
                    ev_x[n_ev] = st[S_X]
                    ev_zd[n_ev] = st[S_ZD]
                n_ev += 1
        if status != codes.OK:
            for j in range(i, t_samples.shape[0]):
                out_x[j] = np.nan
                out_zd[j] = np.nan
                out_mode[j] = -9
            break
        out_x[i] = st[S_X]
        out_zd[i] = st[S_ZD]
        out_mode[i] = int(st[S_MODE])
    return n_ev, status, st[S_N]
