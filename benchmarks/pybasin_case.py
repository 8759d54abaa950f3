"""pybasin's friction case as its authors ship it, timed per belt speed.

Runs in pybasin's own environment (pybasin 0.2.0 needs Python >= 3.12 and its
``jax`` extra; ``benchmarks/pybasin_compare.py`` starts this script there as a
subprocess). Imports pybasin, JAX, torch and numpy only: no sweepcore.

The case is pybasin's ``case_studies/friction`` at its tag v0.2.0 (documented in its
docs/case-studies/friction.md), written here again from its published equations and
settings through pybasin's public API:

* x' = v, v' = -x - 2 xi v - sgn(v - v_d) mu(|v - v_d|),
  mu(s) = mu_d + mu_d (mu_sd - 1) exp(-s/v0) (+ mu_v s/v0), xi = 0.05, mu_d = 0.5,
  mu_sd = 2, mu_v = 0, v0 = 0.5 (sweepcore's m = k = 1, c = 0.1, r_y = 1, r_k = 0.5,
  v_s = 0.5); sticking as the case writes it: a stick band |v - v_d| <= 1e-4 where
  v' = -(v - v_d) unless |x + 2 xi v| exceeds the static bound mu_d mu_sd, sgn
  smoothed by tanh(200 s);
* ``UniformRandomSampler`` on x in [-2, 2], x' in [0, 2], 5,000 starts a speed;
* ``JaxSolver`` (diffrax Dopri5, rtol 1e-8, atol 1e-6, JAX's default float32
  state), t in [0, 500], 500 samples saved on [400, 500];
* features: max |x'| over the saved samples; steady sliding ("FP") if <= 0.2, else
  stick-slip ("LC"); a 1-nearest-neighbour classifier trained on the templates
  (1, 1) -> FP and (2, 2) -> LC integrated by ``TemplateIntegrator`` at the
  setup's v_d = 1.5 whatever the speed studied (as the case's v_d study does: below
  about 1.2 the start (1, 1) itself ends in stick-slip, and templates at that speed
  would give both labels one feature).

One change, so that a time is a computation: the solver's disk cache is off
(``cache_dir=None``; the shipped setting would return a rerun from disk).

    python benchmarks/pybasin_case.py --speeds 1.175,1.5 [--samples 5000] --out R.json

writes, per speed: wall and CPU seconds (the first speed's first run, which
compiles, apart), the fraction of steady sliding and its binomial error, and the
starts with their labels (``--starts`` FILE.npz).
"""
from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import time
from pathlib import Path

import numpy as np

PARAMS = dict(v_d=1.5, xi=0.05, musd=2.0, mud=0.5, muv=0.0, v0=0.5)
BOX = ((-2.0, 2.0), (0.0, 2.0))
T_SPAN, T_STEPS, T_EVAL, T_STEADY = (0.0, 500.0), 500, (400.0, 500.0), 400.0
RTOL, ATOL = 1e-8, 1e-6
THRESHOLD = 0.2
TEMPLATES = ([[1.0, 1.0], [2.0, 2.0]], ["FP", "LC"])


def case(v_d, n):
    """The estimator of the friction case at belt speed v_d with n starts."""
    import jax.numpy as jnp
    import torch
    from sklearn.neighbors import KNeighborsClassifier

    from pybasin import BasinStabilityEstimator
    from pybasin.feature_extractors.feature_extractor import FeatureExtractor
    from pybasin.sampler import UniformRandomSampler
    from pybasin.solvers import JaxSolver
    from pybasin.solvers.jax_ode_system import JaxODESystem
    from pybasin.template_integrator import TemplateIntegrator

    class Friction(JaxODESystem):
        """The friction oscillator of the case (parameters in PARAMS' order)."""

        def ode(self, t, y, p):
            v_d, xi, musd, mud, muv, v0 = (p[i] for i in range(6))
            x, v = y[0], y[1]
            s = v - v_d
            mu = mud + mud * (musd - 1.0) * jnp.exp(-jnp.abs(s) / v0) + muv * jnp.abs(s) / v0
            slipping = jnp.abs(s) > 1e-4
            breaking = jnp.abs(x + 2.0 * xi * v) > mud * musd
            slide = -x - 2.0 * xi * v - jnp.tanh(200.0 * s) * mu
            pulled = -x - 2.0 * xi * v + mud * musd * jnp.tanh(200.0 * mu)
            dx = jnp.where(slipping | breaking, v, v_d)
            dv = jnp.where(slipping, slide, jnp.where(breaking, pulled, -(v - v_d)))
            return jnp.array([dx, dv])

    class MaxSpeed(FeatureExtractor):
        """One-hot (FP, LC) from max |x'| after the transient."""

        def extract_features(self, solution):
            y = self.filter_time(solution)
            peak = torch.max(torch.abs(y[..., 1]), dim=0).values
            return torch.stack([(peak <= THRESHOLD).double(),
                                (peak > THRESHOLD).double()], dim=1)

    params = dict(PARAMS, v_d=float(v_d))
    (xl, xh), (yl, yh) = BOX
    return BasinStabilityEstimator(
        n=n, ode_system=Friction(params),
        sampler=UniformRandomSampler(min_limits=[xl, yl], max_limits=[xh, yh], device="cpu"),
        solver=JaxSolver(t_span=T_SPAN, t_steps=T_STEPS, t_eval=T_EVAL, device="cpu",
                         rtol=RTOL, atol=ATOL, cache_dir=None),
        feature_extractor=MaxSpeed(time_steady=T_STEADY),
        predictor=KNeighborsClassifier(n_neighbors=1),
        template_integrator=TemplateIntegrator(template_y0=TEMPLATES[0],
                                               labels=TEMPLATES[1], ode_params=PARAMS),
        feature_selector=None)


def run_speed(v_d, n, seed):
    """(result dict, starts (n, 2), steady-sliding labels (n,)) of one speed."""
    import torch
    torch.manual_seed(seed)
    bse = case(v_d, n)
    c0, t0 = time.process_time(), time.perf_counter()
    res = bse.run()
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    labels = np.asarray(res["labels"]) == "FP"
    p = float(labels.mean())
    return (dict(v=float(v_d), samples=n, wall_s=wall, cpu_s=cpu, fraction=p,
                 error=float(np.sqrt(p * (1 - p) / n)),
                 basin_stability={k: float(x) for k, x in res["basin_stability"].items()}),
            np.asarray(bse.y0.cpu().numpy(), dtype=float), labels)


def versions():
    from importlib.metadata import version
    out = {"python": platform.python_version()}
    for name in ("pybasin", "jax", "jaxlib", "diffrax", "torch", "numpy", "scikit-learn"):
        try:
            out[name] = version(name)
        except Exception:       # noqa: BLE001 (a missing package is reported as such)
            out[name] = None
    return out


def machine():
    model = "unknown"
    try:
        model = next(line.split(":", 1)[1].strip() for line in
                     Path("/proc/cpuinfo").read_text().splitlines()
                     if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:
        cores = os.cpu_count()
    return dict(date=datetime.datetime.now(datetime.timezone.utc).isoformat(
        timespec="seconds"), cpu_model=model, cores=cores, platform=platform.platform(),
        load_average=os.getloadavg())


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--speeds", default="1.175,1.5", help="belt speeds v_d [cm/s]")
    ap.add_argument("--samples", type=int, default=5000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", type=Path, required=True, help="JSON of the results")
    ap.add_argument("--starts", type=Path, default=None,
                    help="npz of every speed's starts and steady-sliding labels")
    args = ap.parse_args(argv)
    speeds = [float(s) for s in args.speeds.split(",")]
    info = dict(machine=machine(), versions=versions(),
                settings=dict(params=PARAMS, box=BOX, t_span=T_SPAN, t_steps=T_STEPS,
                              t_eval=T_EVAL, time_steady=T_STEADY, rtol=RTOL, atol=ATOL,
                              solver="JaxSolver (diffrax Dopri5), cache off",
                              rule=f"steady sliding if max |x'| <= {THRESHOLD}",
                              samples=args.samples, seed=args.seed))
    first, _s, _l = run_speed(speeds[0], args.samples, args.seed)  # compiles (JAX jit)
    info["first_run"] = first
    rows, arrays = [], {}
    for v in speeds:
        r, starts, labels = run_speed(v, args.samples, args.seed)
        rows.append(r)
        arrays[f"starts_{v:g}"], arrays[f"steady_{v:g}"] = starts, labels
        print(f"pybasin v_d = {v:g}: {r['wall_s']:.2f} s wall, {r['cpu_s']:.2f} s CPU, "
              f"steady sliding {r['fraction']:.4f} +- {r['error']:.4f}", flush=True)
    info["speeds"] = rows
    args.out.write_text(json.dumps(info, indent=1) + "\n")
    if args.starts is not None:
        np.savez_compressed(args.starts, **arrays)


if __name__ == "__main__":
    main()
