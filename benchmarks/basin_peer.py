"""The Monte-Carlo baseline to beat: one basin-stability point of the published friction
case estimated the way bSTAB / pybasin do it, with scipy's solve_ivp.

Setting (bSTAB friction case; Stender, Hoffmann & Papangelo, Lubricants 8(12):105,
2020): x'' + 0.1 x' + x = -sgn(x' - v) (0.5 + 0.5 exp(-|x' - v|/0.5)), belt speed
v = 1.5; start states uniform in x in [-2, 2], x' in [0, 2]; published sample count
5,000; t in [0, 500]; classified from t >= 400 with bSTAB's rule: steady sliding if
max |x'| <= 0.2 over the samples at 100 Hz in [400, 500], else stick-slip. Integrator
as bSTAB's ode45 setting: RK45, rtol 1e-6, atol 1e-8.

Sticking is EXACT, not smoothed: each slide is one solve_ivp call with a terminal
event at x' = v (zdot = 0, approached from the slide's side); at the event the motion
sticks if |x + 0.1 v| < 1 (k x + c v against the static bound r_y = 1), else slides
on (slide-slide); a stick is closed form (x moves with the belt to the breakaway point
x = 1 - 0.1 v). So this is the published setting without the smoothing of pybasin
(tanh(50 s)) or the stick band of bSTAB (|zdot| < 1e-4). Like any sign-change
detector it misses a crossing of x' = v that starts and ends inside one step; such
grazes do not change the classification. The code is standalone (no sweepcore, no
tests/reference.py): what a scipy user would write.

Timing: ``--samples`` (default 200) starts drawn at random from the 5,000 (seed
fixed), each timed alone; the cost of the published 5,000 is extrapolated with the
median per-sample time. The fraction classified as steady sliding comes with its
binomial standard error sqrt(p (1 - p)/n). Single process, single thread.

Run:  python -m benchmarks.basin_peer [--samples 200] [--write]
      (--write saves benchmarks/results/basin_peer.json)
"""
import argparse
import datetime
import json
import math
import os
import platform
import statistics
import subprocess
import time
from pathlib import Path

import numpy as np
import scipy
from scipy.integrate import solve_ivp

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "benchmarks" / "results" / "basin_peer.json"

# the published case in sweepcore's parameters (m = k = 1)
C, R_Y, R_K, V_S = 0.1, 1.0, 0.5, 0.5
V = 1.5
BOX = ((-2.0, 2.0), (0.0, 2.0))
N_PUBLISHED = 5000
T_END, T_STAR, FS = 500.0, 400.0, 100.0
THRESHOLD = 0.2
RTOL, ATOL = 1e-6, 1e-8
SEED = 20201204
PUBLISHED = dict(fraction=0.304, error=0.0065)        # at v = 1.5


def friction(s, sgn):
    """F(s) on the side sgn of s (continued past 0 inside a step)."""
    return sgn * (R_K + (R_Y - R_K) * math.exp(-sgn * s / V_S))


def run_one(x0, xd0, v=V):
    """Integrate one start to T_END; return (max |x'| over the 100 Hz samples in
    [T_STAR, T_END], number of solve_ivp calls, number of RHS evaluations)."""
    samples = T_STAR + np.arange(int(round((T_END - T_STAR) * FS)) + 1) / FS
    x_s = (R_Y - C * v) / 1.0
    t, x, xd = 0.0, float(x0), float(xd0)
    zd = xd - v
    if zd != 0.0:
        mode = 1 if zd > 0 else -1
    else:
        load = x + C * v
        mode = -1 if load >= R_Y else (1 if load <= -R_Y else 0)
    peak, calls, nfev = 0.0, 0, 0
    while t < T_END:
        if mode == 0:                                   # stuck: x' = v until x = x_s
            t_slip = t + (x_s - x) / v
            if min(t_slip, T_END) >= T_STAR:
                peak = max(peak, abs(v))
            if t_slip >= T_END:
                break
            t, x, xd, mode = t_slip, x_s, v, -1
            continue
        sgn = mode

        def rhs(_t, y):
            return [y[1], -y[0] - C * y[1] - friction(y[1] - v, sgn)]

        def belt(_t, y):
            return y[1] - v
        belt.terminal = True
        belt.direction = -sgn

        te = samples[(samples >= t) & (samples <= T_END)]
        sol = solve_ivp(rhs, (t, T_END), [x, xd], method="RK45", rtol=RTOL, atol=ATOL,
                        events=belt, t_eval=te)
        calls += 1
        nfev += sol.nfev
        if te.size and np.size(sol.y):          # samples inside this slide
            peak = max(peak, float(np.abs(np.asarray(sol.y)[1]).max()))
        if sol.status != 1:
            break
        t, x, xd = float(sol.t_events[0][0]), float(sol.y_events[0][0][0]), v
        load = x + C * v
        mode = -1 if load >= R_Y else (1 if load <= -R_Y else 0)
    return peak, calls, nfev


def exact_check(starts, labels, v=V):
    """Classify the starts by the exact basin boundary at belt speed v (the unstable
    slip cycle, from the independent reference; not part of the timed baseline) and
    compare with ``labels`` (True: steady sliding)."""
    import sys
    from matplotlib.path import Path as MplPath
    sys.path.insert(0, str(ROOT))
    from tests.reference import (reference_basin_fraction, reference_cycle_polygon,
                                 reference_find_slip_cycles)
    p = dict(m=1.0, k=1.0, r_y=R_Y, alpha1=0.0, alpha2=0.0, c=C, r_k=R_K, v_s=V_S)
    cy = reference_find_slip_cycles(v=v, **p, n_scan=24)[-1]
    _t, x, xd = reference_cycle_polygon(v=v, a=cy["x_max"], **p)
    inside = MplPath(np.column_stack([x, xd])).contains_points(starts)
    labels = np.asarray(labels)
    return dict(exact_fraction=reference_basin_fraction(v=v, a=cy["x_max"], box=BOX,
                                                        **p)["fraction"],
                exact_steady_in_subset=int(inside.sum()),
                disagreements=int(np.sum(inside != labels)),
                inside_labelled_stick_slip=int(np.sum(inside & ~labels)),
                outside_labelled_steady=int(np.sum(~inside & labels)))


def machine():
    model = "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    try:
        commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, text=True,
                                capture_output=True, timeout=10).stdout.strip()
        dirty = bool(subprocess.run(["git", "status", "--porcelain", "--",
                                     "benchmarks/basin_peer.py"], cwd=ROOT, text=True,
                                    capture_output=True, timeout=10).stdout.strip())
    except (OSError, subprocess.SubprocessError):
        commit, dirty = None, None
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:
        cores = os.cpu_count()
    try:
        load = os.getloadavg()
    except OSError:
        load = None
    return dict(date=datetime.datetime.now(datetime.timezone.utc).isoformat(
                    timespec="seconds"),
                git_commit=commit, script_dirty=dirty, cpu_model=model, cores=cores,
                load_average_at_start=load, platform=platform.platform(),
                python=platform.python_version(), numpy=np.__version__,
                scipy=scipy.__version__)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=200,
                    help="starts timed (a random subset of the 5,000)")
    ap.add_argument("--write", action="store_true", help=f"write {OUT.relative_to(ROOT)}")
    ap.add_argument("--check-exact", action="store_true",
                    help="also classify the timed starts exactly (inside the unstable "
                         "slip cycle or not, tests/reference.py) and count disagreements")
    args = ap.parse_args(argv)
    info = machine()
    rng = np.random.default_rng(SEED)
    (xl, xh), (yl, yh) = BOX
    starts = np.column_stack([rng.uniform(xl, xh, N_PUBLISHED),
                              rng.uniform(yl, yh, N_PUBLISHED)])
    pick = rng.choice(N_PUBLISHED, size=args.samples, replace=False)
    run_one(0.1, 0.1)                                     # warm-up (imports, caches)
    times, steady, calls, nfevs, labels = [], 0, [], [], []
    t_all = time.perf_counter()
    for j, i in enumerate(pick):
        t0 = time.perf_counter()
        peak, ncall, nfev = run_one(*starts[i])
        times.append(time.perf_counter() - t0)
        steady += peak <= THRESHOLD
        labels.append(bool(peak <= THRESHOLD))
        calls.append(ncall)
        nfevs.append(nfev)
        if (j + 1) % 50 == 0:
            print(f"  {j + 1} samples, {time.perf_counter() - t_all:.0f} s", flush=True)
    wall = time.perf_counter() - t_all
    n = len(pick)
    p = steady / n
    se = math.sqrt(p * (1 - p) / n)
    med = statistics.median(times)
    res = dict(
        machine=info,
        settings=dict(case="bSTAB/pybasin friction case, m = k = 1, c = 0.1, r_y = 1, "
                           "r_k = 0.5, v_s = 0.5, alpha1 = alpha2 = 0",
                      v=V, box=BOX, t_span=[0.0, T_END], t_star=T_STAR, fs_hz=FS,
                      rule=f"steady sliding if max |x'| over [t_star, t_end] <= {THRESHOLD}",
                      method="RK45", rtol=RTOL, atol=ATOL,
                      sticking="exact (terminal events, closed-form stick)",
                      n_published=N_PUBLISHED, n_timed=n, seed=SEED),
        per_sample_median_s=med,
        per_sample_mean_s=statistics.fmean(times),
        per_sample_min_s=min(times), per_sample_max_s=max(times),
        timed_total_s=wall,
        extrapolated_total_5000_s=med * N_PUBLISHED,
        extrapolated_total_5000_from_mean_s=statistics.fmean(times) * N_PUBLISHED,
        solve_ivp_calls_median=statistics.median(calls),
        rhs_evaluations_median=statistics.median(nfevs),
        steady_sliding_fraction=p, steady_sliding_standard_error=se,
        published=PUBLISHED, load_average_at_end=os.getloadavg())
    print(f"v = {V}: {n} of {N_PUBLISHED} starts, RK45 rtol {RTOL:g} atol {ATOL:g}, "
          f"exact sticking")
    print(f"per sample: median {med:.3f} s, mean {res['per_sample_mean_s']:.3f} s "
          f"(min {min(times):.3f}, max {max(times):.3f}); solve_ivp calls median "
          f"{res['solve_ivp_calls_median']:.0f}, RHS evaluations median "
          f"{res['rhs_evaluations_median']:.0f}")
    print(f"extrapolated to {N_PUBLISHED} samples: {med * N_PUBLISHED:.0f} s "
          f"(median) / {res['extrapolated_total_5000_from_mean_s']:.0f} s (mean)")
    print(f"steady sliding: {p:.4f} +- {se:.4f} (published {PUBLISHED['fraction']} +- "
          f"{PUBLISHED['error']})")
    if args.check_exact:
        res["exact_check"] = exact_check(starts[pick], labels)
        print(f"exact check: {res['exact_check']}")
    if args.write:
        OUT.parent.mkdir(parents=True, exist_ok=True)
        OUT.write_text(json.dumps(res, indent=1) + "\n")
        print(f"wrote {OUT.relative_to(ROOT)}")
    return res


if __name__ == "__main__":
    main()
