"""Section 4: the peers, rerun in the same process, on the same points.

The peers answer a fixed-horizon protocol, the usual way such maps are computed:
integrate every point from its start to t = 200 s and take amplitude = (max - min)/2
and the mean of x sampled at t = 150 + 0.01 j. Their error is measured against the
same protocol computed by the independent event-driven scipy DOP853 at a tight
tolerance, and "events right" = the same number of stick/slip/stop events.

Peers (``peers.py``, written here from the physics, sharing no code with sweepcore):
* scipy ``solve_ivp`` RK45, terminal events at zdot = 0 and restarts, rtol = atol;
* a hand-written numba RK4 at a fixed step (the fastest peer we wrote), events located by
  Illinois on the step's own polynomial, prange over points.

Points: 17 (4 x 4 in v and alpha2, plus v = 5, alpha2 = 1/75, which
sits exactly at v*), all starting stuck (x0 = 0, xdot0 = v) as in the map (a start at
rest, x0 = xdot0 = 0, costs the same per point over a fixed horizon).

sweepcore is timed on the same points (serial kernel, 1 core) and its error is taken
against its own tight reference (dopri5 tol 1e-13): it computes the attractor, not a
sampled window. The difference between the protocol's answer and the attractor's is
reported too: it is the protocol's own modelling error (sampling at 0.01 s, and
transients that have not died by t = 150 s near v*).
"""
from __future__ import annotations

import time

import numpy as np

from . import common
from .common import log
from sweepcore._kernels.layout import NOBS


def peer_points(n):
    from .work_precision import test_points
    v, a = test_points()
    v = np.append(v, 5.0)
    a = np.append(a, 1.0 / 75.0)
    if n < v.size:                  # quick: an even spread over the set
        sel = np.unique(np.linspace(0, v.size - 1, n).round().astype(int))
        v, a = v[sel], a[sel]
    return common.rows(v, a, product=False)


def _scipy_loop(P, method, tol):
    from . import peers
    res = []
    t0 = time.perf_counter()
    for p in P:
        res.append(peers.scipy_protocol(p, method, rtol=tol, atol=tol))
    return (time.perf_counter() - t0) / P.shape[0], res


def _numba_peer(P, dt, threads=1, repeats=1):
    import numba
    from . import peers
    out = np.empty((P.shape[0], 5))
    peers.numba_rk4_protocol(P[:1], dt, out[:1])
    n_max = numba.config.NUMBA_NUM_THREADS
    numba.set_num_threads(threads)
    try:
        med, _t, _ = common.timed(lambda: peers.numba_rk4_protocol(P, dt, out), repeat=repeats)
    finally:
        numba.set_num_threads(n_max)
    return med, out


def run(profile, outdir, hopf_res=None):
    run = common.kernel()
    attractor_rows = lambda P, o, out: run(P, o, out, False)  # noqa: E731
    attractor_rows_parallel = lambda P, o, out: run(P, o, out, True)  # noqa: E731
    from sweepcore.options import make_options

    log("[4] peers")
    res = {"load_before": common.load()}
    P = peer_points(profile["peer_points"])
    n = P.shape[0]
    res["points"] = [{"v": p[3], "alpha2": p[5]} for p in P]
    ref_tol = profile["peer_ref_tol"]
    t_ref, ref = _scipy_loop(P, "DOP853", ref_tol)
    ref_amp = np.array([r["amplitude"] for r in ref])
    ref_ev = np.array([r["events"] for r in ref])
    res["protocol_reference"] = {"solver": f"scipy DOP853 rtol=atol={ref_tol:g}, events",
                                 "s_per_point": t_ref}
    log(f"    protocol reference DOP853 {ref_tol:g}: {t_ref:.2f} s/point")

    wp = {"scipy RK45 loop": [], "numba RK4 peer": []}
    for tol in profile["peer_rk45_tols"]:
        tp, rr = _scipy_loop(P, "RK45", tol)
        amp = np.array([r["amplitude"] for r in rr])
        ev = np.array([r["events"] for r in rr])
        err = np.abs(amp - ref_amp)
        wp["scipy RK45 loop"].append({"setting": f"rtol=atol={tol:g}", "tol": tol,
                                      "s_per_point": tp, "points_per_s": 1.0 / tp,
                                      "amp_err_max": float(err.max()),
                                      "events_right": int((ev == ref_ev).sum()), "n": n})
        log(f"    scipy RK45 {tol:g}: {tp:.3f} s/point, max amp err {err.max():.2e}, "
            f"events right {(ev == ref_ev).sum()}/{n}")
    for dt in profile["peer_rk4_dt"]:
        tp, out = _numba_peer(P, dt, threads=1, repeats=profile["peer_numba_repeats"])
        tp /= n
        err = np.abs(out[:, 0] - ref_amp)
        right = int((out[:, 2] == ref_ev).sum())
        wp["numba RK4 peer"].append({"setting": f"dt={dt:g}", "dt": dt, "s_per_point": tp,
                                     "points_per_s": 1.0 / tp, "amp_err_max": float(err.max()),
                                     "events_right": right, "n": n,
                                     "steps_per_point": float(out[:, 3].mean())})
        log(f"    numba RK4 peer dt={dt:g}: {tp * 1e3:.3f} ms/point, max amp err "
            f"{err.max():.2e}, events right {right}/{n}")
    res["work_precision"] = wp

    # sweepcore on the same points: 1 core, its own reference
    o = make_options("auto", tol=1e-8)
    out = np.empty((n, NOBS))
    attractor_rows(P[:1], o, out[:1])
    med, _t, _ = common.timed(lambda: attractor_rows(P, o, out), repeat=5)
    at_vstar = np.isclose(P[:, 3] * P[:, 3] * 3.0 * P[:, 5], P[:, 4])   # q = 0 exactly
    med_off = med
    if at_vstar.any() and (~at_vstar).any():
        Po = np.ascontiguousarray(P[~at_vstar])
        oo = np.empty((Po.shape[0], NOBS))
        med_off, _t, _ = common.timed(lambda: attractor_rows(Po, o, oo), repeat=5)
        med_off *= n / Po.shape[0]
    sref = np.empty((n, NOBS))
    attractor_rows_parallel(P, make_options("dopri5", tol=1e-13), sref)
    cmp = common.compare(out, sref, common.length_scale(P))
    res["sweepcore_same_points"] = {"setting": "auto tol=1e-8", "s_per_point": med / n,
                                    "s_per_point_without_v_star_point": med_off / n,
                                    **cmp, "status": [common.REGIMES[int(r)] for r in out[:, 8]]}
    # the protocol's own modelling error: its (exact) answer against the attractor's
    conv = sref[:, 9] == 0
    res["protocol_vs_attractor_amp_max"] = float(np.max(np.abs(ref_amp[conv] - sref[conv, 0])))
    log(f"    sweepcore tol 1e-8 on the same points: {med / n * 1e6:.1f} us/point, max amp "
        f"err {cmp['amplitude_abs']['max']:.2e} ({cmp['n_compared']}/{n} compared); "
        f"protocol vs attractor {res['protocol_vs_attractor_amp_max']:.1e} cm")

    # the best peer on the map (2 threads): whole map (full) or a subsample (quick)
    nv, na = profile["map_shape"]
    Pm = common.rows(*common.map_axes(nv, na))
    m = min(profile["peer_map_points"], Pm.shape[0])
    rng = np.random.default_rng(3)
    Ps = Pm if m == Pm.shape[0] else Pm[np.sort(rng.choice(Pm.shape[0], m, replace=False))]
    import numba
    tmap, outm = _numba_peer(Ps, 0.01, threads=numba.config.NUMBA_NUM_THREADS, repeats=1)
    res["numba_peer_map"] = {"dt": 0.01, "points_run": m, "n_map": Pm.shape[0],
                             "seconds_run": tmap,
                             "map_seconds": tmap * Pm.shape[0] / m,
                             "measured_or_extrapolated": "measured" if m == Pm.shape[0]
                             else "extrapolated from a random subsample",
                             "steps_total_run": float(outm[:, 3].sum())}
    log(f"    numba RK4 peer on the map: {tmap:.2f} s for {m} points -> "
        f"{res['numba_peer_map']['map_seconds']:.1f} s for the map "
        f"({res['numba_peer_map']['measured_or_extrapolated']})")

    # ratios at matched or better error
    scipy8 = next((r for r in wp["scipy RK45 loop"] if r["tol"] == 1e-8), wp["scipy RK45 loop"][0])
    ratios = {"scipy_setting": scipy8["setting"], "scipy_s_per_point_1core": scipy8["s_per_point"],
              "scipy_amp_err_max": scipy8["amp_err_max"],
              "sweepcore_same_points_s_per_point_1core": med / n,
              "per_point_1core_ratio": scipy8["s_per_point"] / (med / n)}
    if hopf_res is not None:
        h = hopf_res["headline"]
        npts = hopf_res["grid"]["n_points"]
        cores = 2
        ratios.update({
            "map_points_per_s_sweepcore_2cores": h["points_per_s"],
            "map_points_per_s_scipy_2cores_ideal": cores / scipy8["s_per_point"],
            "map_ratio_sweepcore_over_scipy": h["points_per_s"] * scipy8["s_per_point"] / cores,
            "scipy_map_hours_2cores_ideal": npts * scipy8["s_per_point"] / cores / 3600.0,
            "map_ratio_sweepcore_over_numba_peer": res["numba_peer_map"]["map_seconds"] / h["median_s"],
            "sweepcore_map_amp_err_max":
                hopf_res["accuracy"]["map"]["1e-08"]["amplitude_abs"]["max"],
        })
    res["ratios"] = ratios
    log(f"    ratios: {ratios}")
    res["load_after"] = common.load()
    return res
