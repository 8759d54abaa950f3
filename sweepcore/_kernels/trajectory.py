"""One run of the hybrid driver, sampled at given times, with its event log (every
excitation: the autonomous belt and a forced slider alike)."""
import numpy as np
from .jit import kernel

from . import codes
from .attractor import method_status
from .driver import advance, init_state
from .excitation import prepare
from .layout import (A_XDMAX, A_XDMIN, A_XMAX, A_XMIN, NA, NS, S_MODE, S_N, S_T, S_X, S_ZD,
                     X0, XD0)


@kernel(entry=True)
def fresh_acc():
    """Accumulators with empty extrema."""
    acc = np.zeros(NA)
    acc[A_XMAX] = -np.inf
    acc[A_XMIN] = np.inf
    acc[A_XDMAX] = -np.inf
    acc[A_XDMIN] = np.inf
    return acc


@kernel
def run_trajectory(meth, p, lw, fx, o, t_samples, out_x, out_zd, out_mode, ev_t, ev_kind,
                   ev_x, ev_zd, acc):
    """Run from (p[X0], p[XD0]) at t = 0 and fill the sample and event arrays.

    ``fx``: the excitation, as the call's kernels use it (``excitation.with_work``);
    ``o``: the point's option row (``attractor.resolve_options``). Samples are the
    driver's own state at each time of ``t_samples`` (sorted, >= 0): the driver
    stops exactly there. Phase events (slip, stick, stops) are logged up to the
    buffers' length; the return value counts all of them, so a caller can retry
    with larger buffers. Returns (n_events, status, n_steps).
    """
    st = np.zeros(NS)
    status = method_status(meth, p, lw, fx, o)
    if not prepare(fx, p, lw):
        status = codes.EVENT_FAILURE
    init_state(st, p[X0], p[XD0], p, lw, fx, o)
    n_ev = 0
    cap = ev_t.shape[0]
    for i in range(t_samples.shape[0]):
        ts = t_samples[i]
        while st[S_T] < ts and status == codes.OK:
            ev, status = advance(meth, st, p, lw, fx, o, acc, ts)
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
