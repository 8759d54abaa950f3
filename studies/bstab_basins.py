"""The published basin-stability case, reproduced: sweepcore's exact basin fractions of
steady sliding against the published Monte-Carlo table and the independent scipy
reference.

The case (Stender, Hoffmann & Papangelo, "The Basin Stability of Bi-Stable
Friction-Excited Oscillators", Lubricants 8(12):105, 2020; the friction case of the
bSTAB toolbox): m = k = 1, c = 0.1, r_y = 1, r_k = 0.5, v_s = 0.5, alpha1 = alpha2 = 0,
v = v_d; starts uniform in x in [-2, 2], x' in [0, 2]. Its published fraction of
steady sliding comes from 5,000 samples a point, classified by max |x'| <= 0.2 over
t in [400, 500].

What this script computes (studies/bstab_basins.toml's grid and box):

* the exact route at the published speeds and the reference's speeds, against the
  scipy fractions of studies/results/bstab_reference.json (polygon of 20001 points,
  rtol 1e-13) and the published table (difference in published errors: the stated
  0.0065 at 1.5, elsewhere the binomial error of 5,000 samples);
* the sampled route (5,000 uniform starts a point, the published count) at the
  published speeds, against the exact fraction (difference in its standard errors);
* at 1.175, 1.20 and 1.25, next to the Hopf point ln(10)/2, what the published
  classifier makes of the interior (the reference's share of interior starts that
  decay below |x'| = 0.2 by t = 400, times the exact fraction);
* the whole curve of the study (256 speeds in [1, 2]): routes, largest error, where
  the equilibrium's fraction leaves 0 and where it jumps to 1, and the time.

Run:  python studies/bstab_basins.py [--write] [--png FIG.png]   (about 15 s;
prints the table of docs/physics.md, "Basins of attraction"; --write saves
studies/results/bstab_basins.json; --png draws the curve with the published points,
docs/img/bstab_basins.png)
"""
import argparse
import datetime
import json
import platform
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
import sweepcore as sc  # noqa: E402
from sweepcore.study import load_study  # noqa: E402

OUT = ROOT / "studies" / "results" / "bstab_basins.json"
REFERENCE = ROOT / "studies" / "results" / "bstab_reference.json"
STUDY = ROOT / "studies" / "bstab_basins.toml"
SAMPLES = 5000


def _fraction(ds, v, what="basin_fraction"):
    return float(ds[what].sel(v=v, attractor="equilibrium"))


def compute():
    study = load_study(STUDY)
    b = study.basins
    box = dict(x0=b["x0"], xdot0=b["xdot0"])
    ref = json.loads(REFERENCE.read_text())["bstab"]
    speeds = [r["v"] for r in ref["rows"]]
    params = {k: v for k, v in study.grid_kwargs().items() if k != "v"}
    exact = sc.basin_stability(sc.Grid(**params, v=np.array(speeds)), **box,
                               route="exact", ftol=b["ftol"], progress=False)
    published = [r["v"] for r in ref["rows"] if "published" in r]
    t0 = time.perf_counter()
    mc = sc.basin_stability(sc.Grid(**params, v=np.array(published)), **box,
                            route="sampled", samples=SAMPLES, seed=b["seed"],
                            progress=False)
    mc_seconds = time.perf_counter() - t0
    rows = []
    for r in ref["rows"]:
        v = r["v"]
        f, e = _fraction(exact, v), _fraction(exact, v, "basin_fraction_error")
        row = dict(v=v, exact=f, exact_error=e, scipy=r["basin_fraction"],
                   exact_minus_scipy=f - r["basin_fraction"])
        if "published" in r:
            p, pe = r["published"], r["published_error"]
            s = _fraction(mc, v)
            se = _fraction(mc, v, "basin_fraction_error")
            row.update(published=p, published_error=pe, exact_minus_published=f - p,
                       in_published_errors=(f - p) / pe, sampled=s, sampled_error=se,
                       sampled_in_errors=(s - f) / se)
        if "classifier_expected" in r:
            row.update(classifier_share_inside=r["classifier_share_inside"],
                       classifier_expected=f * r["classifier_share_inside"])
        rows.append(row)

    t0 = time.perf_counter()
    curve = sc.basin_stability(study.grid(), **box, route=b["route"],
                               samples=b["samples"], ftol=b["ftol"], progress=False)
    seconds = time.perf_counter() - t0
    curve.attrs["study_title"] = study.title
    v = curve.v.values
    f = curve.basin_fraction.sel(attractor="equilibrium").values
    inside = np.flatnonzero((f > 0.0) & (f < 1.0))
    summary = dict(
        points=int(v.size), seconds=seconds, seconds_per_point=seconds / v.size,
        exact_points=int((curve.basin_route.values == 0).sum()),
        ok_points=int((curve.basin_status.values == 0).sum()),
        largest_error=float(np.nanmax(curve.basin_fraction_error.values)),
        first_bistable=float(v[inside[0]]), last_bistable=float(v[inside[-1]]),
        last_fraction=float(f[inside[-1]]),
        hopf=ref["hopf"]["closed_form"], fold=ref["fold"]["rtol=1e-12"]["v_fold"])
    return dict(rows=rows, curve=summary, curve_dataset=curve,
                sampled_seconds=mc_seconds,
                sampled_points=len(published), box=[list(b["x0"]), list(b["xdot0"])])


def table(res) -> str:
    """The markdown table of docs/physics.md ("Basins of attraction")."""
    lines = ["| v_d | sweepcore exact | scipy reference | published (5,000 samples) | "
             "(exact - published) / error | sweepcore sampled, 5,000 starts | "
             "published classifier, expected |",
             "|---|---|---|---|---|---|---|"]
    for r in res["rows"]:
        pub = (f"{r['published']:g} +- {r['published_error']:.4f}" if "published" in r
               else "-")
        dif = f"{r['in_published_errors']:+.1f}" if "published" in r else "-"
        mc = (f"{r['sampled']:.4f} +- {r['sampled_error']:.4f}" if "sampled" in r
              else "-")
        cl = f"{r['classifier_expected']:.4f}" if "classifier_expected" in r else "-"
        lines.append(f"| {r['v']:g} | {r['exact']:.6f} | {r['scipy']:.6f} | {pub} | "
                     f"{dif} | {mc} | {cl} |")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true",
                    help=f"write {OUT.relative_to(ROOT)}")
    ap.add_argument("--png", type=Path, help="draw the curve with the published "
                                             "points into this file")
    args = ap.parse_args(argv)
    res = compute()
    if args.png:
        from sweepcore.plot import plot_basins, save
        pub = [r for r in res["rows"] if "published" in r]
        fig = plot_basins(res.pop("curve_dataset"), reference={
            "published, 5,000 samples (Stender et al. 2020)": (
                [r["v"] for r in pub], [r["published"] for r in pub],
                [r["published_error"] for r in pub])})
        save(fig, args.png)
        print(f"wrote {args.png}")
    res.pop("curve_dataset", None)
    print(table(res))
    c = res["curve"]
    worst = max(abs(r["exact_minus_scipy"]) for r in res["rows"])
    print(f"\nexact - scipy: at most {worst:.2g}; sampled route "
          f"{res['sampled_points']} x {SAMPLES} starts in {res['sampled_seconds']:.1f} s")
    print(f"curve: {c['points']} speeds in {c['seconds']:.2f} s "
          f"({1e3 * c['seconds_per_point']:.1f} ms a point), {c['exact_points']} exact, "
          f"{c['ok_points']} ok, largest error {c['largest_error']:.2g}; bistable from "
          f"{c['first_bistable']:.4f} to {c['last_bistable']:.4f} (fraction "
          f"{c['last_fraction']:.4f}), Hopf {c['hopf']:.6f}, fold {c['fold']:.6f}")
    if args.write:
        res.update(generated_by="studies/bstab_basins.py", version=sc.__version__,
                   date=datetime.datetime.now(datetime.timezone.utc).isoformat(
                       timespec="seconds"),
                   machine=dict(platform=platform.platform(),
                                python=platform.python_version()))
        OUT.write_text(json.dumps(res, indent=1, allow_nan=False) + "\n")
        print(f"wrote {OUT.relative_to(ROOT)}")
    return res


if __name__ == "__main__":
    main()
