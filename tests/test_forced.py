"""The forced slider (sweepcore.forced): closed forms, invariants and the API.

Closed forms (sources in docs/physics.md, "Forced vibration"):
* Den Hartog (Phil. Mag. 9 (1930) 801-817): c = 0, v = 0, no stick: the scaled
  amplitude x0 = sqrt(V^2 - (r U)^2), V = 1/(1 - beta^2), U = tan(pi/(2 beta))/beta,
  two zero-duration stops a period; its multipliers mu = lambda^2 with
  lambda^2 - (1 + rho) cos(pi/beta) lambda + rho = 0,
  rho = (beta^2 x0 - r)/(beta^2 x0 + r).
* a belt and Coulomb friction: below F0_crit = v |k - m Omega^2 + i c Omega| / Omega
  the slider never reaches the belt: the linear response shifted by r/k; above it a
  stick every period.
Tolerances: the default tol 1e-8 is relative to the point's length scale L; the
tests ask 1e-7 of amplitudes (10 tol) and 1e-6 of multipliers (central differences
of re-runs at 1e-13: truncation ~1e-8).
"""
import math

import numpy as np
import pytest

import sweepcore as sc
from sweepcore._kernels import layout


def den_hartog(beta, r):
    """Scaled amplitude and largest multiplier modulus of Den Hartog's response."""
    V = 1.0 / (1.0 - beta ** 2)
    U = math.tan(math.pi / (2.0 * beta)) / beta
    x0 = math.sqrt(V ** 2 - (r * U) ** 2)
    rho = (beta ** 2 * x0 - r) / (beta ** 2 * x0 + r)
    lam = np.roots([1.0, -(1.0 + rho) * math.cos(math.pi / beta), rho])
    return x0, float(np.max(np.abs(lam) ** 2))


# (beta, r): no stick (r below the continuous-motion boundary)
DEN_HARTOG = [(2.0, 0.3), (1.5, 0.5), (0.8, 0.3), (3.0, 0.1), (1.2, 0.3)]


# ------------------------------------------------------------------ exactness
@pytest.mark.parametrize("beta, r", DEN_HARTOG)
def test_den_hartog_amplitude_and_multipliers(beta, r):
    """Physical units (m = 2, k = 8, F0 = 3): amplitude x0 F0/k within 1e-7
    relative, two stops and no stick a forcing period, the multiplier within 1e-6."""
    m, k, F0 = 2.0, 8.0, 3.0
    omega = math.sqrt(k / m)
    res = sc.attractor(sc.Params(m=m, k=k, r_y=r * F0, v=0.0, F0=F0, Omega=beta * omega),
                       x0=0.0, xdot0=0.0)
    x0, mu = den_hartog(beta, r)
    assert res.status == "ok" and res.regime == "slip_cycle"
    assert res.multiplicity == 1 and res.period == pytest.approx(2 * math.pi / (beta * omega))
    assert res.amplitude == pytest.approx(x0 * F0 / k, rel=1e-7)
    assert res.mean == pytest.approx(0.0, abs=1e-7 * x0 * F0 / k)
    assert (res.sticks_per_period, res.stops_per_period) == (0, 2)
    assert res.floquet == pytest.approx(mu, abs=1e-6)


def _linear(F0, m, k, c, Om):
    return F0 / math.hypot(k - m * Om * Om, c * Om)


@pytest.mark.parametrize("Om", [0.7, 1.3, 2.5])
def test_belt_below_critical_force_is_the_shifted_linear_response(Om):
    """Coulomb friction (r_k = r_y), v > 0: below F0_crit the slider never reaches
    the belt; amplitude F0/|k - m Omega^2 + i c Omega| and mean r/k."""
    m, k, c, v, r = 1.0, 1.0, 0.1, 1.0, 1.0
    crit = v * math.hypot(k - m * Om * Om, c * Om) / Om
    res = sc.attractor(sc.Params(m=m, k=k, r_y=r, v=v, c=c, F0=0.97 * crit, Omega=Om))
    assert res.status == "ok" and res.regime == "slip_cycle"
    assert res.sticks_per_period == 0 and res.stops_per_period == 0
    assert res.amplitude == pytest.approx(_linear(0.97 * crit, m, k, c, Om), rel=1e-7)
    assert res.mean == pytest.approx(r / k, rel=1e-7)
    assert res.xdot_max == pytest.approx(0.97 * v, rel=1e-7)
    above = sc.attractor(sc.Params(m=m, k=k, r_y=r, v=v, c=c, F0=1.03 * crit, Omega=Om))
    assert above.status == "ok" and above.regime == "stick_slip"
    assert above.sticks_per_period >= 1


def test_base_motion_is_its_equivalent_load():
    """y = Y0 cos(Omega t) acts as the load Y0 |k + i c Omega| cos(Omega t + atan2(c
    Omega, k)): the same response (a stick-slip one, through the breakaway root)."""
    m, k, c, v, r, Om, Y0 = 1.0, 2.0, 0.3, 0.5, 1.0, 1.1, 0.9
    base = sc.attractor(sc.Params(m=m, k=k, r_y=r, v=v, c=c, Y0=Y0, Omega=Om))
    load = sc.attractor(sc.Params(m=m, k=k, r_y=r, v=v, c=c, F0=Y0 * math.hypot(k, c * Om),
                                  phi=math.atan2(c * Om, k), Omega=Om))
    assert base.status == load.status == "ok"
    assert base.sticks_per_period == load.sticks_per_period >= 1
    for name in ("amplitude", "mean", "x_max", "x_min", "xdot_max", "floquet"):
        assert getattr(base, name) == pytest.approx(getattr(load, name), rel=1e-8,
                                                     abs=1e-9), name


def test_weak_load_on_stable_sliding_is_linear():
    """F0 -> 0 on a stable steady sliding (the paper's law above v*): amplitude
    F0/|k - m Omega^2 - i m q Omega| (c + F'(-v) = -m q), mean -> x_eq."""
    p = dict(m=5.0, k=50.0, r_y=10.0, v=8.0, alpha1=1.0, alpha2=0.01)
    Om = 2.0
    q = sc.Params(**p).q
    assert q < 0.0
    F0 = 1e-5
    res = sc.attractor(sc.Params(**p, F0=F0, Omega=Om))
    lin = F0 / abs(p["k"] - p["m"] * Om * Om - 1j * p["m"] * q * Om)
    assert res.status == "ok" and res.regime == "slip_cycle"
    assert res.amplitude == pytest.approx(lin, rel=1e-3)
    assert res.mean == pytest.approx(sc.Params(**p).x_eq, abs=1e-3 * F0)


# ------------------------------------------------------------------ invariants
def test_mirror_symmetry():
    """x -> -x, v -> -v, load -> -load (phi + pi), start mirrored: the same
    response mirrored (F is odd)."""
    p = dict(m=1.0, k=1.0, r_y=1.0, v=0.8, c=0.05, alpha1=0.2, alpha2=0.05, Omega=0.9)
    a = sc.attractor(sc.Params(**p, F0=1.5, phi=0.3), x0=0.2, xdot0=0.0)
    b = sc.attractor(sc.Params(**{**p, "v": -0.8}, F0=1.5, phi=0.3 + math.pi),
                     x0=-0.2, xdot0=0.0)
    assert a.status == b.status == "ok"
    assert (a.multiplicity, a.sticks_per_period, a.stops_per_period) == \
        (b.multiplicity, b.sticks_per_period, b.stops_per_period)
    L = 1.0 + 0.8 + 1.5
    for x, y in ((a.amplitude, b.amplitude), (a.mean, -b.mean), (a.x_max, -b.x_min),
                 (a.x_min, -b.x_max), (a.floquet, b.floquet)):
        assert x == pytest.approx(y, abs=1e-7 * L)


@pytest.mark.slow   # compiles the forced kernels for the table and Leine kinds once more
def test_every_law_kind_gives_the_coulomb_response():
    """Constant friction written three ways (the analytic law, a constant table,
    Leine's law with a vanishing delta): one forced response."""
    common = dict(m=1.0, k=1.0, v=1.0, c=0.1, F0=2.0, Omega=0.7)
    ref = sc.attractor(sc.Params(r_y=1.0, **common))
    table = sc.attractor(sc.Params(law=sc.TableLaw([0, 1, 2, 3, 4, 5, 6], [1.0] * 7),
                                   **common))
    leine = sc.attractor(sc.Params(law=sc.LeineLaw(1.0, 1e-12), **common))
    for other in (table, leine):
        assert other.status == "ok" and other.regime == ref.regime == "stick_slip"
        assert other.amplitude == pytest.approx(ref.amplitude, rel=1e-7)
        assert other.mean == pytest.approx(ref.mean, rel=1e-7)


# ------------------------------------------------------------------ hard cases
def test_neutral_family_is_flagged():
    """beta = 1/2, c = 0 (Csernak, Stepan & Shaw 2007): a continuum of responses,
    one multiplier 1: flagged, never a confident amplitude."""
    res = sc.attractor(sc.Params(m=1.0, k=1.0, r_y=0.3, v=0.0, F0=1.0, Omega=0.5),
                       x0=0.0, xdot0=0.0)
    assert res.regime == "neutral" and res.status == "unresolved" and not res.converged


def test_weak_load_on_fixed_ground_stays_stuck():
    """v = 0 and F0 below the static bound from rest inside the band: stuck."""
    res = sc.attractor(sc.Params(m=1.0, k=1.0, r_y=1.0, v=0.0, F0=0.5, Omega=1.3),
                       x0=0.1, xdot0=0.0)
    assert res.regime == "stuck" and res.status == "ok" and res.amplitude == 0.0


# ------------------------------------------------------------------ API
def test_excitation_needs_its_frequency():
    with pytest.raises(ValueError, match="Omega"):
        sc.Params(m=1.0, k=1.0, r_y=1.0, v=1.0, F0=1.0)
    with pytest.raises(ValueError, match="Omega"):
        sc.Grid(m=1.0, k=1.0, r_y=1.0, v=1.0, Y0=[0.1, 0.2])
    with pytest.raises(ValueError, match="Omega must be > 0"):
        sc.Params(m=1.0, k=1.0, r_y=1.0, v=1.0, F0=1.0, Omega=-1.0)


def test_forced_methods_refused_by_name():
    p = sc.Params(m=1.0, k=1.0, r_y=1.0, v=1.0, F0=1.0, Omega=1.0)
    with pytest.raises(ValueError, match="exact.*autonomous.*dop853"):
        sc.attractor(p, method="exact")
    with pytest.raises(ValueError, match="periods"):
        sc.attractor(p, periods=0)


def test_no_excitation_is_the_autonomous_answer():
    """F0 = Y0 = 0 with a frequency given: the autonomous attractor, bit for bit."""
    p = dict(m=5.0, k=50.0, r_y=10.0, v=3.0, alpha1=1.0, alpha2=0.01)
    a = sc.attractor(sc.Params(**p))
    b = sc.attractor(sc.Params(**p, F0=0.0, Omega=2.0, Y0=0.0))
    assert a == b


def test_response_map_dataset():
    """A Grid over Omega and F0: forced variables with units, dims in axis order;
    a row of F0 = 0 is the autonomous answer (v = 0 from rest: stuck)."""
    g = sc.Grid(m=1.0, k=1.0, r_y=0.3, v=0.0, F0=[0.0, 1.0], Omega=[1.5, 2.0], x0=0.0,
                xdot0=0.0)
    ds = sc.sweep(g, progress=False)
    assert ds.amplitude.dims == ("F0", "Omega")
    for name in ("multiplicity", "stops_per_period", "lyapunov", "floquet"):
        assert "units" in ds[name].attrs
    assert ds.Omega.attrs["units"] == "rad s-1" and ds.F0.attrs["units"] == "kN"
    assert (ds.regime.sel(F0=0.0) == 4).all()          # stuck
    x0, _mu = den_hartog(2.0, 0.3)
    assert float(ds.amplitude.sel(F0=1.0, Omega=2.0)) == pytest.approx(x0, rel=1e-7)
    assert int(ds.stops_per_period.sel(F0=1.0, Omega=2.0)) == 2


def test_simulate_carries_the_load():
    p = sc.Params(m=1.0, k=1.0, r_y=0.3, v=0.0, F0=1.0, Omega=2.0)
    ds = sc.simulate(p, 10.0, x0=0.0, xdot0=0.0)
    assert ds.attrs["status"] == "ok"
    assert np.allclose(ds.external_force, np.cos(2.0 * ds.time))
    assert "friction_work" not in ds            # the load works too: no balance


def test_excitation_columns_read_by_excitation_modules_only():
    """Only the excitation modules (and the layout) name the excitation's columns
    or its kinds' kernel data classes: the other rooms reach an excitation through
    its interface (``sweepcore/_kernels/excitation.py``) and the Python table."""
    import pathlib
    import re
    root = pathlib.Path(sc.__file__).parent
    allowed = {"_kernels/layout.py", "_kernels/excitations/periodic.py",
               "excitations/__init__.py", "excitations/periodic.py",
               "excitations/none.py", "_kernels/excitations/none.py",
               "_kernels/excitations/__init__.py", "_kernels/excitation.py"}
    from sweepcore._kernels import excitations as kernel_excitations
    classes = "|".join(row[1].__name__ for row in kernel_excitations.EXCITATIONS)
    pattern = re.compile(r"\[\s*(layout\.)?(F0|OMEGA|PHI|Y0)\s*[\],]|layout\.(F0|OMEGA|PHI|Y0)\b"
                         rf"|\b({classes})\b|excitations\.kinds\(")
    offenders = [str(f.relative_to(root)) for f in root.rglob("*.py")
                 if str(f.relative_to(root)) not in allowed and pattern.search(f.read_text())]
    assert offenders == []


# a Stribeck law on a slow belt under a moderate load: no period up to 16 forcing
# periods, a positive Lyapunov exponent (found by a sweep over Omega and F0)
CHAOTIC = dict(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.5, c=0.02, v=0.3, F0=0.7, Omega=1.1)


def test_aperiodic_response_carries_its_exponent_not_a_cycle():
    """No period up to the limit: regime aperiodic, a Lyapunov exponent above three
    of its errors, and no multiplicity, period or per-period counts."""
    res = sc.attractor(sc.Params(**CHAOTIC), x0=0.0, xdot0=0.0)
    assert res.regime == "aperiodic" and res.status == "ok"
    assert res.lyapunov > 3.0 * res.lyapunov_error > 0.0
    assert math.isnan(res.multiplicity) and math.isnan(res.period)
    assert math.isnan(res.sticks_per_period) and math.isnan(res.floquet)
    assert res.amplitude > 0.0


@pytest.mark.slow
def test_aperiodic_exponent_against_the_reference():
    """The exponent against the reference's two-trajectory estimate (200 periods):
    within three of the combined errors."""
    from reference_forced import Forced, forced_steady
    res = sc.attractor(sc.Params(**CHAOTIC), x0=0.0, xdot0=0.0)
    ref = forced_steady(Forced(**CHAOTIC), x0=0.0, xd0=0.0)
    assert ref["status"] == "aperiodic"
    err = math.hypot(res.lyapunov_error, ref["lyapunov_error"])
    assert abs(res.lyapunov - ref["lyapunov"]) <= 3.0 * err


def test_forced_rows_pass_the_scale_rule(monkeypatch):
    """The scale rule every entry shares (``sweepcore.law.flag_unresolvable``) runs
    on forced rows too: a point it calls unresolvable is flagged, never an answer
    (the rule's own magnitudes: tests/test_scales.py)."""
    from sweepcore import law
    calls = []
    real = law.unresolvable

    def every_other(P, o, laws=None, weak=True):
        calls.append(weak)
        return (np.arange(P.shape[0]) % 2 == 0) | real(P, o, laws, weak)
    monkeypatch.setattr(law, "unresolvable", every_other)
    ds = sc.sweep(sc.Grid(m=1.0, k=1.0, r_y=1.0, v=0.5, c=0.05, F0=1.0,
                          Omega=[0.8, 1.1, 1.4, 1.7]), progress=False, max_seconds=None)
    assert list(ds.status.values) == [12, 0, 12, 0] and calls and not calls[-1]
    assert (ds.regime.values[::2] == 7).all()


def test_neutral_only_where_den_hartogs_motion_exists():
    """At Omega/omega = 1/20 (= 1/(2 n)) on fixed ground, c = 0, Coulomb friction,
    the friction ratio r_y/F0 is above the continuous-motion boundary r_b(1/20): the
    responses stick several times a period, no member of the neutral family of
    Csernak, Stepan & Shaw (which holds Den Hartog's continuous motion): answered ok
    (all 232 moving cells of this column of studies/forced_map.toml were called
    neutral), equal to the reference's."""
    from reference_forced import Forced, forced_steady
    for F0 in (1.2, 3.5):
        kw = dict(m=1.0, k=1.0, r_y=1.0, v=0.0, F0=F0, Omega=0.05)
        res = sc.attractor(sc.Params(**kw), x0=0.0, xdot0=0.0)
        assert res.status == "ok" and res.regime == "stick_slip", res
        mod = Forced(**kw)
        ref = forced_steady(mod, x0=0.0, xd0=0.0, multipliers=False)
        assert res.sticks_per_period == ref["sticks_per_period"] >= 2
        assert abs(res.amplitude - ref["amplitude"]) <= 1e-6 * mod.L


def test_a_stick_carried_by_the_belt_is_no_response():
    """Started stuck on a belt, a slider is carried by v T a forcing period: its
    position's multiplier is 1, but its state moves (no fixed point, no neutral
    family). Here (m = 5, k = 50, c = 1, r_y = 10, v = 2, F0 = 1, Omega/omega = 50)
    it slips and settles into steady sliding with the load's small ripple: not
    `stuck`, which it was reported with amplitude 0."""
    p = sc.Params(m=5.0, k=50.0, c=1.0, r_y=10.0, v=2.0, F0=1.0,
                  Omega=50.0 * math.sqrt(10.0))
    res = sc.attractor(p)
    assert res.status == "ok" and res.regime == "slip_cycle" and res.amplitude > 0.0
    # the ripple of the linear response about x_eq (no stick: the belt is faster)
    ripple = p.F0 / math.hypot(p.k - p.m * p.Omega ** 2, p.c * p.Omega)
    assert res.amplitude == pytest.approx(ripple, rel=1e-6)
    assert res.mean == pytest.approx(p.x_eq, rel=1e-9)
