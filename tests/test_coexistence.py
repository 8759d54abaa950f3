"""Coexistence of steady sliding and stick-slip: the subcritical Hopf point and the
fold at grazing located by ``locate_boundaries`` and ``continue_boundary`` against
closed forms and the independent scipy values of studies/results/bstab_reference.json
(studies/bstab_reference.py); hysteresis scans of ``bifurcation_diagram`` whose
jumps bracket them; the unstable branch; the study, CLI and picture of a diagram."""
import json
import math
from pathlib import Path

import numpy as np
import pytest

import sweepcore as sc
from sweepcore._kernels import codes

ROOT = Path(__file__).resolve().parent.parent
REF = json.loads((ROOT / "studies" / "results" / "bstab_reference.json").read_text())
BSTAB = dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.5, c=0.1, alpha1=0.0, alpha2=0.0)
FAMILY = REF["family"]["params"]
HOPF = math.log(10.0) / 2.0         # 0.1 - exp(-2 v) = 0: c + F'(-v) = 0
FOLD = REF["bstab"]["fold"]["rtol=1e-13"]["v_fold"]     # last stick-slip cycle (scipy)
LOCATED, ABSENT = sc.boundaries.LOCATED, sc.boundaries.ABSENT


def hopf_closed_form(c, r_y=1.0, r_k=0.5, v_s=0.5):
    """Root of c + F'(-v) = c - (r_y - r_k)/v_s exp(-v/v_s) (alpha1 = alpha2 = 0)."""
    return v_s * math.log((r_y - r_k) / (v_s * c))


def test_bstab_hopf_and_fold_against_the_references():
    ds = sc.locate_boundaries(sc.Grid(**BSTAB, v=np.linspace(1.0, 2.0, 5)), xtol=1e-9)
    assert sc.check_cf(ds) == []
    assert int(ds.hopf_criticality) == 2                          # subcritical
    assert int(ds.subcritical_status) == LOCATED and int(ds.fold_status) == LOCATED
    hopf, err = float(ds.v_hopf_subcritical), float(ds.v_hopf_subcritical_error)
    assert abs(hopf - HOPF) <= min(err, 1e-6 * HOPF)
    fold, width = float(ds.v_fold), float(ds.v_fold_width)
    assert abs(fold - FOLD) <= width + REF["bstab"]["fold_spread"]
    assert abs(fold - FOLD) <= 1e-6 * FOLD
    for name in ("v_hopf_subcritical", "v_fold", "v_fold_width"):
        assert ds[name].attrs["units"] == "cm s-1" and ds[name].attrs["long_name"]


def test_family_hopf_and_fold_against_the_references():
    """Stribeck, damping and cubic terms together (no closed form for the fold)."""
    ds = sc.locate_boundaries(sc.Grid(**FAMILY, v=np.linspace(0.5, 2.0, 4)), xtol=1e-9)
    ref = REF["family"]
    assert abs(float(ds.v_hopf_subcritical) - ref["hopf"]["v_hopf"]) <= \
        float(ds.v_hopf_subcritical_error)
    assert abs(float(ds.v_fold) - ref["fold"]["v_fold"]) <= float(ds.v_fold_width)


def test_supercritical_law_has_no_unstable_cycle():
    """The paper's cubic law: nothing coexists, the new boundaries are absent and
    the Hopf point is located as before."""
    ds = sc.locate_boundaries(sc.Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0,
                                      alpha2=0.01, v=np.linspace(1.0, 7.0, 12)))
    assert int(ds.hopf_criticality) == 1
    assert int(ds.subcritical_status) == ABSENT and int(ds.fold_status) == ABSENT
    assert np.isnan(float(ds.v_fold)) and np.isnan(float(ds.v_hopf_subcritical))
    assert abs(float(ds.v_hopf) - float(ds.v_star)) <= 1e-9


def test_continued_along_damping_against_closed_form_and_attractors():
    """Along c: the Hopf point against its closed form; the fold is where the
    stick-slip attractor (reached from the belt) ends, checked 1e-6 either side
    (closer, the stick-slip cycle's stick is too short to be resolved at tol)."""
    c = np.array([0.08, 0.1, 0.12])
    ds = sc.continue_boundary(sc.Grid(**{**BSTAB, "c": c}, v=np.linspace(0.8, 2.5, 6)),
                              over="c", xtol=1e-9)
    assert (ds.subcritical_status == LOCATED).all()
    assert (ds.fold_status == LOCATED).all()
    for ci, h, f in zip(c, ds.v_hopf_subcritical.values, ds.v_fold.values):
        assert h == pytest.approx(hopf_closed_form(ci), rel=1e-6)
        p = {**BSTAB, "c": float(ci)}
        below = sc.attractor(sc.Params(**p, v=f * (1 - 1e-6)), tol=1e-10)
        above = sc.attractor(sc.Params(**p, v=f * (1 + 1e-6)), tol=1e-10)
        assert below.regime == "stick_slip" and above.regime == "equilibrium"
    assert float(ds.v_fold.sel(c=0.1)) == pytest.approx(FOLD, rel=1e-8)
    assert np.all(np.diff(ds.v_fold.values) < 0)      # more damping, smaller band


# ------------------------------------------------------------------ hysteresis
@pytest.fixture(scope="module")
def diagram():
    return sc.bifurcation_diagram(sc.Grid(**BSTAB, v=np.linspace(1.0, 2.0, 41)))


def test_hysteresis_jumps_bracket_the_references(diagram):
    """The up scan stays on stick-slip up to the fold, the down scan on steady
    sliding down to the Hopf point: each jump within one scan step of its
    reference value."""
    v = diagram.v.values
    up = diagram.regime.sel(branch="up").values
    down = diagram.regime.sel(branch="down").values
    assert (up[v < FOLD] == codes.R_STICK_SLIP).all()
    assert (up[v > FOLD] == codes.R_EQUILIBRIUM).all()
    assert (down[v > HOPF] == codes.R_EQUILIBRIUM).all()
    assert (down[v < HOPF] != codes.R_EQUILIBRIUM).all()
    assert float(diagram.v_fold) == pytest.approx(FOLD, rel=1e-8)
    assert float(diagram.v_hopf_subcritical) == pytest.approx(HOPF, rel=1e-6)
    assert sc.check_cf(diagram) == []


def test_unstable_branch_lies_between_the_boundaries(diagram):
    v = diagram.v.values
    amp = diagram.unstable_amplitude.values
    inside = (v > HOPF) & (v < FOLD)
    assert np.isfinite(amp[inside]).all() and np.isnan(amp[~inside]).all()
    assert (diagram.unstable_floquet.values[inside] > 1.0).all()
    # below belt speed (stop-free) and inside the stick-slip cycle of the up scan
    assert (diagram.unstable_xdot_max.values[inside] < v[inside]).all()
    up = diagram.sel(branch="up")
    assert (diagram.unstable_amplitude.values[inside]
            < up.amplitude.values[inside]).all()
    # against the scipy shooting values of the reference file
    for row in REF["bstab"]["rows"]:
        i = np.flatnonzero(np.isclose(v, row["v"]))
        if i.size and row.get("unstable_cycle"):
            assert amp[i[0]] == pytest.approx(row["unstable_cycle"]["amplitude"],
                                              abs=1e-7)


def test_one_direction_scans(diagram):
    v = np.linspace(1.0, 2.0, 41)
    up = sc.bifurcation_diagram(sc.Grid(**BSTAB, v=v), sweep="up", boundaries=False,
                                unstable=False)
    assert list(up.branch.values) == ["up"] and "unstable_amplitude" not in up
    np.testing.assert_array_equal(up.regime.values[0],
                                  diagram.regime.sel(branch="up").values)
    down = sc.bifurcation_diagram(sc.Grid(**BSTAB, v=v), sweep="down",
                                  boundaries=False)
    assert list(down.branch.values) == ["down"]
    # from the default start (stuck on the belt) at v = 2: steady sliding, the
    # only attractor there, kept down to the Hopf point
    assert (down.regime.values[0][v > HOPF] == codes.R_EQUILIBRIUM).all()
    with pytest.raises(ValueError, match="sweep must be one of"):
        sc.bifurcation_diagram(sc.Grid(**BSTAB, v=v), sweep="sideways")


# ------------------------------------------------------------- study and CLI
def _study(tmp_path, num=41, extra=""):
    text = (ROOT / "studies" / "bstab_hysteresis.toml").read_text()
    text = text.replace("num = 201", f"num = {num}") + extra
    text = text.replace('path = "out/', f'path = "{tmp_path}/').replace(
        'png = "out/', f'png = "{tmp_path}/')
    path = tmp_path / "h.toml"
    path.write_text(text)
    return path


def test_cli_hysteresis_study_and_its_picture(tmp_path, capsys):
    from matplotlib.figure import Figure
    from sweepcore.cli import main
    study = _study(tmp_path)
    assert main(["boundary", str(study)]) == 0
    out = capsys.readouterr().out
    assert "up scan: stick_slip -> equilibrium between v = 1.825 and 1.85" in out
    assert "down scan: equilibrium -> " in out and "between v = 1.175 and 1.15" in out
    ds = sc.open_result(tmp_path / "bstab_hysteresis.nc")
    assert ds.attrs["sweep"] == "both" and (tmp_path / "bstab_hysteresis.png").is_file()
    fig = sc.plot.plot_result(ds)
    assert isinstance(fig, Figure)
    lines = fig.axes[0].get_lines()
    unstable = [ln for ln in lines if ln.get_label() == "unstable slip cycle"]
    assert len(unstable) == 1 and unstable[0].get_linestyle() == "--"
    np.testing.assert_array_equal(unstable[0].get_ydata(),
                                  ds.unstable_amplitude.values)
    for scan in ("up", "down"):
        solid = [ln for ln in lines if ln.get_label() == f"{scan} scan (stable)"]
        assert len(solid) == 1 and solid[0].get_linestyle() == "-"
    colours = {ln.get_color() for ln in lines if ln.get_linestyle() == "-"}
    markers = {ln.get_marker() for ln in lines if ln.get_linestyle() == "-"}
    assert len(colours) == 2 and len(markers) == 2       # up and down told apart
    assert main(["plot", str(tmp_path / "bstab_hysteresis.nc"), "-o",
                 str(tmp_path / "p.png")]) == 0


def test_cli_sweep_option_overrides_the_study(tmp_path):
    from sweepcore.cli import main
    study = _study(tmp_path, num=11)
    assert main(["boundary", str(study), "--sweep", "down", "--no-png", "-q"]) == 0
    ds = sc.open_result(tmp_path / "bstab_hysteresis.nc")
    assert list(ds.branch.values) == ["down"] and ds.attrs["sweep"] == "down"


@pytest.mark.parametrize("edit, message", [
    (('sweep = "both"', 'sweep = "sideways"'), "sweep"),
    (("diagram = true", "diagram = false"), "applies to a diagram"),
])
def test_study_sweep_key_is_checked(edit, message):
    from sweepcore.study import parse_study
    text = (ROOT / "studies" / "bstab_hysteresis.toml").read_text()
    assert parse_study(text).boundary["sweep"] == "both"
    with pytest.raises(ValueError, match=message):
        parse_study(text.replace(*edit))


def test_physics_section_quotes_the_results_file():
    """docs/physics.md, "Coexistence and hysteresis", carries the numbers of
    studies/results/bstab_boundaries.json (written by studies/bstab_boundaries.py),
    and they meet the references."""
    res = json.loads((ROOT / "studies" / "results" / "bstab_boundaries.json")
                     .read_text())
    text = (ROOT / "docs" / "physics.md").read_text()
    section = text.split("## Coexistence and hysteresis", 1)[1]
    assert res["reference"]["fold"] == FOLD and res["reference"]["hopf"] == HOPF
    for tol, r in res["located"].items():
        for key, err in (("v_hopf_subcritical", "v_hopf_subcritical_error"),
                         ("v_fold", "v_fold_width")):
            assert f"{r[key]:.10f} | {r[err]:.1e}" in section, (tol, key)
            ref = HOPF if key == "v_hopf_subcritical" else FOLD
            assert abs(r[key] - ref) <= r[err] + REF["bstab"]["fold_spread"]
    s = res["scans"]
    for branch, ref in (("up", FOLD), ("down", HOPF)):
        lo, hi = sorted((s[branch]["last"], s[branch]["first"]))
        assert lo < ref < hi
        assert f"v = {s[branch]['last']:.3f}" in section
        assert f"v = {s[branch]['first']:.3f}" in section
    assert f"q = {s['q_at_down_jump']:.1e} /s" in section
    assert f"{s['unstable_cycles']['points']} speeds" in section
