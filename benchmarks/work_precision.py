"""Section 2: work-precision of every sweepcore method (error against time per point).

(a) constant friction (alpha1 = alpha2 = 0), start stuck: the attractor is known in
    closed form (amplitude v/omega, mean r_y/k, period 2 pi/omega);
(b) alpha2 > 0: 16 test points (v in {0.5, 2, 5, 10} x alpha2 in
    {0.002, 0.01, 0.05, 0.1}) plus random map points stratified by regime
    (stick-slip, slip cycle, equilibrium), against dopri5 at tol = 1e-13 (itself
    cross-checked on a few points by the independent scipy DOP853 solver);
(c) the Hopf boundary along v at alpha2 = 0.01 as a map sees it: the largest v with a
    cycle and the smallest larger v at equilibrium (their midpoint is
    ``sweepcore.boundary``'s definition), each located by bisection for each setting,
    against the reference setting's. Between the two lies a band of points left
    unconverged by the budget (transients ~ 2/|q| near v*); its cycle-side edge moves
    with the convergence tolerance, so the error plotted is that of the equilibrium
    onset, which the energy certificate makes sharp.

Time per point is the serial kernel ``attractor_rows`` on one thread over the point
set (median of repeats), divided by the number of points.
"""
from __future__ import annotations

import math
import time

import numpy as np

from . import common
from .common import log
from sweepcore._kernels.layout import NOBS

TEST_V = (0.5, 2.0, 5.0, 10.0)
TEST_A2 = (0.002, 0.01, 0.05, 0.1)
REF = ("dopri5", {"tol": 1e-13})


def test_points():
    """The 4 x 4 test set (v, alpha2) (the peers' 17th point, v = 5,
    alpha2 = 1/75, sits exactly at v* and is used by the peer section only)."""
    v, a = np.meshgrid(TEST_V, TEST_A2, indexing="ij")
    return v.ravel(), a.ravel()


def settings(profile):
    out = [("exact", None)]
    out += [("gps", {"dt": dt}) for dt in profile["wp_gps_dt"]]
    out += [("rk4", {"dt": dt}) for dt in profile["wp_rk4_dt"]]
    out += [("dopri5", {"tol": tol}) for tol in profile["wp_dopri5_tol"]]
    out += [("dop853", {"tol": tol}) for tol in profile.get("wp_dop853_tol", [])]
    return out


def _label(method, kw):
    if kw is None:
        return method
    (k, v), = kw.items()
    return f"{method} {k}={v:g}"


def _run(P, method, kw, repeats):
    run = common.kernel()
    attractor_rows = lambda P, o, out: run(P, o, out, False)  # noqa: E731
    from sweepcore.options import make_options
    o = make_options(method, **(kw or {}))
    out = np.empty((P.shape[0], NOBS))
    attractor_rows(P[:1], o, out[:1])
    med, times, _ = common.timed(lambda: attractor_rows(P, o, out), repeat=repeats)
    return med / P.shape[0], out


def _is_regime(v, alpha2, o, regimes):
    run = common.kernel()
    attractor_rows = lambda P, o, out: run(P, o, out, False)  # noqa: E731
    P = common.rows([v], [alpha2])
    out = np.empty((1, NOBS))
    attractor_rows(P, o, out)
    return int(out[0, 8]) in regimes


def _bisect(a, b, iters, left):
    """Shrink [a, b] with left(a) true and left(b) false; returns the final (a, b)."""
    for _ in range(iters):
        m = 0.5 * (a + b)
        if left(m):
            a = m
        else:
            b = m
    return a, b


def hopf_boundary(method, kw, alpha2=0.01, lo=4.0, hi=8.0, iters=25):
    """(boundary, half-gap, v_cycle_end, v_eq_start, seconds) by two bisections."""
    from sweepcore.options import make_options
    o = make_options(method, **(kw or {}))
    t0 = time.perf_counter()
    cyc = (1, 2)
    eq = (0,)
    if not (_is_regime(lo, alpha2, o, cyc) and _is_regime(hi, alpha2, o, eq)):
        return math.nan, math.nan, math.nan, math.nan, time.perf_counter() - t0
    # last cycle: cyc(a) and not cyc(b); then the first equilibrium beyond it
    v_cyc, _ = _bisect(lo, hi, iters, lambda m: _is_regime(m, alpha2, o, cyc))
    _, v_eq = _bisect(v_cyc, hi, iters, lambda m: not _is_regime(m, alpha2, o, eq))
    return 0.5 * (v_cyc + v_eq), 0.5 * (v_eq - v_cyc), v_cyc, v_eq, time.perf_counter() - t0


def stratified_points(profile, rng):
    """Random map points, ``wp_per_regime`` of each regime (by a dopri5 1e-10 run)."""
    run = common.kernel()
    attractor_rows_parallel = lambda P, o, out: run(P, o, out, True)  # noqa: E731
    from sweepcore.options import make_options
    P = common.rows(*common.map_axes())
    pool = P[rng.choice(P.shape[0], 1500, replace=False)]
    out = np.empty((pool.shape[0], NOBS))
    attractor_rows_parallel(pool, make_options("dopri5", tol=1e-10), out)
    pick = []
    for reg in (2, 1, 0):
        cand = np.flatnonzero((out[:, 8] == reg) & (out[:, 9] == 0))
        pick += list(rng.choice(cand, min(profile["wp_per_regime"], cand.size), replace=False))
    return pool[np.sort(pick)]


def run(profile, outdir):
    run = common.kernel()
    attractor_rows_parallel = lambda P, o, out: run(P, o, out, True)  # noqa: E731
    from sweepcore.options import make_options
    from .hopf_map import scipy_check

    log("[2] work-precision")
    rng = np.random.default_rng(7)
    res = {"load_before": common.load(), "settings": [], "timing": "serial attractor_rows, "
           "1 thread, median of repeats / points"}
    # (a) constant friction
    va = np.linspace(0.5, 10.0, profile["wp_const_points"])
    Pa = common.rows(va, 0.0, alpha1=0.0, product=False)
    amp_a = va / common.OMEGA
    mean_a = common.PAPER["r_y"] / common.PAPER["k"]
    per_a = 2.0 * math.pi / common.OMEGA
    # (b) alpha2 > 0
    tv, ta = test_points()
    Pt = common.rows(tv, ta, product=False)
    Pr = stratified_points(profile, rng)
    Pb = np.vstack([Pt, Pr])
    is_test = np.zeros(Pb.shape[0], bool)
    is_test[: Pt.shape[0]] = True
    Lb = common.length_scale(Pb)
    ref = np.empty((Pb.shape[0], NOBS))
    t0 = time.perf_counter()
    attractor_rows_parallel(Pb, make_options(REF[0], **REF[1]), ref)
    res["reference"] = {"setting": _label(*REF), "seconds": time.perf_counter() - t0,
                        "regimes": common.regime_counts(ref),
                        "regimes_test_points": common.regime_counts(ref[is_test])}
    res["reference"].update(scipy_check(Pb, ref, rng, profile["scipy_per_regime"]))
    res["points"] = {"constant_friction": int(Pa.shape[0]), "alpha2": int(Pb.shape[0]),
                     "test_points": int(is_test.sum())}
    log(f"    reference {_label(*REF)} on {Pb.shape[0]} points: {res['reference']['regimes']}; "
        f"scipy check max |d amp| {res['reference']['scipy_check_max_amp_diff']}")
    vb_ref = hopf_boundary(*REF, iters=profile["wp_boundary_iters"])
    res["boundary_reference"] = dict(zip(("v_boundary", "half_gap", "v_cycle_end",
                                          "v_eq_start", "seconds"), vb_ref))
    res["boundary_reference"]["v_star"] = math.sqrt(1.0 / (3.0 * 0.01))
    log(f"    Hopf boundary (alpha2 = 0.01) reference: {vb_ref[0]:.6f} +- {vb_ref[1]:.1e}"
        f" (v* = {res['boundary_reference']['v_star']:.6f})")

    for method, kw in settings(profile):
        row = {"method": method, "setting": kw, "label": _label(method, kw)}
        tp, out = _run(Pa, method, kw, profile["wp_repeats"])
        ok = out[:, 9] == 0
        row["const"] = {
            "s_per_point": tp, "n_converged": int(ok.sum()), "n": int(Pa.shape[0]),
            "regimes": common.regime_counts(out),
            "amplitude_abs_max": float(np.nanmax(np.abs(out[ok, 0] - amp_a[ok]))) if ok.any() else None,
            "mean_abs_max": float(np.nanmax(np.abs(out[ok, 1] - mean_a))) if ok.any() else None,
            "period_abs_max": float(np.nanmax(np.abs(out[ok, 4] - per_a))) if ok.any() else None,
        }
        if method != "exact":
            tp, out = _run(Pb, method, kw, profile["wp_repeats"])
            row["alpha2"] = {"s_per_point": tp, **common.compare(out, ref, Lb),
                             "steps_per_point": float(out[:, 10].mean())}
            tpt, out_t = _run(Pt, method, kw, profile["wp_repeats"])
            row["test_points"] = {"s_per_point": tpt,
                                  **common.compare(out_t, ref[is_test], Lb[is_test])}
            vb = hopf_boundary(method, kw, iters=profile["wp_boundary_iters"])
            row["boundary"] = dict(zip(("v_boundary", "half_gap", "v_cycle_end",
                                        "v_eq_start", "seconds"), vb))
            row["boundary"]["error"] = abs(vb[0] - vb_ref[0])
            row["boundary"]["error_eq_onset"] = abs(vb[3] - vb_ref[3])
            row["boundary"]["error_cycle_end"] = abs(vb[2] - vb_ref[2])
            row["boundary"]["eq_onset_minus_v_star"] = vb[3] - math.sqrt(1.0 / 0.03)
        res["settings"].append(row)
        ea = row["const"]["amplitude_abs_max"]
        msg = f"    {row['label']:<22s} const: {row['const']['s_per_point'] * 1e6:8.1f} us/pt "\
              f"amp err {ea if ea is None else format(ea, '.2e')}"
        if "alpha2" in row:
            msg += (f" | alpha2>0: {row['alpha2']['s_per_point'] * 1e6:8.1f} us/pt amp err "
                    f"{row['alpha2']['amplitude_abs']['max']:.2e} mism "
                    f"{row['alpha2']['n_regime_mismatch']} unconv "
                    f"{row['alpha2']['n'] - row['alpha2']['n_converged']} | eq onset err "
                    f"{row['boundary']['error_eq_onset']:.2e}")
        log(msg)
    res["load_after"] = common.load()
    return res


# ------------------------------------------------------------------ the figure
COLORS = {"exact": "k", "gps": "#ee6677", "rk4": "#4477aa", "dopri5": "#228833", "dop853": "#aa3377",
          "scipy RK45 loop": "#aa3377", "numba RK4 peer": "#ccbb44"}
FLOOR = 1e-17        # errors that are exactly 0 are drawn at this floor


def _series(rows, key, err):
    by = {}
    for r in rows:
        if key not in r:
            continue
        e = err(r[key])
        if e is None or not np.isfinite(e):
            continue
        by.setdefault(r["method"], []).append((r[key]["s_per_point"], max(e, FLOOR),
                                               r["label"]))
    return by


def plot(res, peer_res, outdir):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = res["settings"]
    fig, axs = plt.subplots(2, 3, figsize=(16, 9.5), constrained_layout=True)
    panels = [
        (axs[0, 0], "test_points", lambda d: d["amplitude_abs"]["max"],
         "16 test points (4 v x 4 alpha2), alpha2 > 0: max |amplitude error| [cm]"),
        (axs[0, 1], "alpha2", lambda d: d["amplitude_abs"]["max"],
         "test + stratified map points: max |amplitude error| [cm]"),
        (axs[0, 2], "alpha2", lambda d: d["mean_abs"]["max"],
         "test + stratified map points: max |mean error| [cm]"),
        (axs[1, 0], "alpha2", lambda d: d["period_abs"]["max"],
         "cycle points: max |period error| [s]"),
        (axs[1, 1], "const", lambda d: d["amplitude_abs_max"],
         "constant friction (exact v/omega): max |amplitude error| [cm]"),
    ]
    for ax, key, err, title in panels:
        for meth, pts in _series(rows, key, err).items():
            t, e, _l = zip(*pts)
            ax.loglog(t, e, "o-", color=COLORS.get(meth), label=meth, ms=4)
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("time per point, 1 core [s]")
        ax.set_ylabel("error")
        ax.grid(True, which="major", alpha=0.3)
    # peers on the test points (their own protocol's error)
    if peer_res and "work_precision" in peer_res:
        ax = axs[0, 0]
        for name, pts in peer_res["work_precision"].items():
            good = [(p["s_per_point"], max(p["amp_err_max"], FLOOR)) for p in pts
                    if p.get("amp_err_max") is not None]
            if good:
                t, e = zip(*good)
                ax.loglog(t, e, "s--", color=COLORS.get(name), label=name + " (protocol err.)",
                          ms=5)
    axs[0, 0].axhline(1e-6, color="r", ls=":", lw=1, label="1e-6 target")
    axs[0, 0].legend(fontsize=7)
    axs[0, 1].legend(fontsize=7)
    # Hopf boundary
    ax = axs[1, 1 + 1]
    by = {}
    for r in rows:
        e = r.get("boundary", {}).get("error_eq_onset")
        if e is not None and np.isfinite(e):
            by.setdefault(r["method"], []).append((r["alpha2"]["s_per_point"], max(e, FLOOR)))
    for meth, pts in by.items():
        t, e = zip(*pts)
        ax.loglog(t, e, "o-", color=COLORS.get(meth), label=meth, ms=4)
    ax.set_title("Hopf boundary (alpha2 = 0.01): equilibrium-onset error [cm/s]",
                 fontsize=9)
    ax.set_xlabel("time per point (alpha2 > 0 set), 1 core [s]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    fig.suptitle("sweepcore work-precision (errors exactly 0 drawn at 1e-17)")
    fig.savefig(outdir / "work_precision.png", dpi=110)
    plt.close(fig)
