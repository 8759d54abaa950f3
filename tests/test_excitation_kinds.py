"""Every excitation kind, checked by one shared test (as ``test_law_kinds.py`` is for laws).

The kernels learn an excitation only through its interface
(``sweepcore/_kernels/excitation.py``): the load e(t) and its rate, the loads at a
step's stages, the stick's exit and the stop rules. Each test below takes every kind
of the Python excitation table (``sweepcore.excitations.EXCITATIONS``, ``none``
apart: the autonomous belt, checked by every autonomous test) on random points and
shapes of that kind, and proves:

* the kernel's load is the Python side's, and its rate the finite difference of it
  (central differences, steps h and h/2 extrapolated: O(h^4));
* the stick's exit (``stick_exit``) on random sticks is the first time dense
  sampling of the holding force ``h(t) = e(t) - k x(t) - c v`` leaves the static
  band: every exit found, none early (a sign error in the critical phases of h'
  misses the short excursions);
* on a belt faster than the motion (Coulomb friction, never a stick) the response is
  the closed-form superposition over the harmonics, ``sum_n Re[F0 (a_n - i b_n)
  H(n Omega) e^{i n (Omega t + phi)}]`` with ``H(w) = 1/(k - m w^2 + i c w)`` and the
  anchor's force, shifted by ``sgn(v) r_k/k``, and its multiplier that of the linear
  oscillator over a period, ``exp(-c T/(2 m))`` (a coefficient dropped from the kind
  moves it);
* the engine against the independent reference (``tests/reference_forced.py``:
  scipy DOP853 at rtol 1e-12, the stick's exits from the companion matrix of h') at
  random points of every kind with loads of 2-3 harmonics, on fixed ground and on a
  belt: amplitude, mean and extremes within 1e-6 L, multiplicity, sticks and stops
  per period exact, the largest multiplier within 1e-5.

A new kind fails :func:`test_every_kind_has_a_maker` until ``MAKERS`` below makes
random points of it; then every check runs on it.
"""
import math

import numpy as np
import pytest
from numba import njit

import sweepcore as sc
from sweepcore import excitations
from sweepcore._kernels import excitation as interface
from sweepcore._kernels.excitations import none as kernel_none
from sweepcore.laws import analytic

CONTRACT = 1e-6         # the forced response's contract, of the length scale L
N_STICKS = 12           # random sticks per point
SAMPLES = 4000          # samples of the holding force per forcing period


# ------------------------------------------------------------- the kernels
@njit(cache=False)
def _loads(ex, p, lw, ts, out):
    """e(t), e'(t) at the times ts into out (4, n), for the point p: from the
    harmonics (rows 0, 1), and from inside a step of the longest length the driver
    takes, t 0.3 of the way in (rows 2, 3: the step's own rotated harmonics, where
    events are located)."""
    owner = np.zeros(interface.work_size(ex))
    fx = interface.with_work(ex, owner)
    ok = interface.prepare(fx, p, lw)
    h = interface.capped(fx, np.inf)
    cs = np.zeros(1)
    for i in range(ts.shape[0]):
        out[0, i] = interface.load(fx, ts[i] + 1e3 * h)    # leave the step
        out[0, i] = interface.load(fx, ts[i])
        out[1, i] = interface.load_rate(fx, ts[i])
        interface.step_load(fx, ts[i] - 0.3 * h, h, cs)
        out[2, i] = interface.load(fx, ts[i])
        out[3, i] = interface.load_rate(fx, ts[i])
        interface.step_load(fx, ts[i] - 2.0 * h, h, cs)   # t after the step's end
    return ok


@njit(cache=False)
def _exits(ex, p, lw, t0, x0, t_stop, out):
    """The stick's exit ``(dt, slips, mode, x)`` of every start (t0[i], x0[i])."""
    owner = np.zeros(interface.work_size(ex))
    fx = interface.with_work(ex, owner)
    interface.prepare(fx, p, lw)
    for i in range(t0.shape[0]):
        dt, slips, mode, xs = interface.stick_exit(fx, t0[i], x0[i], p, lw, t_stop[i])
        out[i, 0] = dt
        out[i, 1] = 1.0 if slips else 0.0
        out[i, 2] = mode
        out[i, 3] = xs


def _law_data(p):
    """The kernels' law data of a Params (its kind's, as a call groups it)."""
    from sweepcore import compiled
    from sweepcore.options import make_options
    ((_m, _k, _r, lw),) = compiled.groups(p.row(0.0, 0.0)[None, :], (p.friction_law,),
                                          make_options("auto"), forced=True)
    return lw


# ------------------------------------------------- random points of every kind
def _periodic(rng, v=None, law=None):
    """A point under a periodic load of 1-3 harmonics, and maybe the anchor's motion:
    ``(Params kwargs, reference kwargs)``."""
    m, k = rng.uniform(0.5, 2.0, 2)
    omega = math.sqrt(k / m)
    n = int(rng.integers(1, 4))
    a, b = rng.uniform(-1.0, 1.0, n), rng.uniform(-1.0, 1.0, n)
    r_y = rng.uniform(0.3, 1.0)
    kw = dict(m=m, k=k, c=rng.choice([0.0, rng.uniform(0.02, 0.3)]),
              v=rng.choice([0.0, rng.uniform(0.2, 1.5)]) if v is None else v,
              F0=rng.uniform(0.5, 3.0), Omega=omega * rng.uniform(0.4, 3.0),
              phi=rng.uniform(0.0, 2.0 * math.pi),
              Y0=rng.choice([0.0, rng.uniform(0.2, 1.0)]))
    kw.update(law or dict(r_y=r_y, alpha1=rng.uniform(0.0, 0.2),
                          alpha2=rng.uniform(0.0, 0.1), r_k=r_y * rng.uniform(0.6, 1.0),
                          v_s=rng.uniform(0.3, 1.0)))
    return {**kw, "load": sc.PeriodicLoad(cos=a, sin=b)}, {**kw, "cos": a, "sin": b}


MAKERS = {"periodic": _periodic}
KINDS = [name for name, _m, _cls in excitations.EXCITATIONS if name != "none"]


def test_every_kind_has_a_maker():
    assert sorted(MAKERS) == sorted(KINDS)


def _points(kind, count, seed, **fixed):
    rng = np.random.default_rng(seed)
    return [MAKERS[kind](rng, **fixed) for _ in range(count)]


# ------------------------------------------------------------------ the load
@pytest.mark.parametrize("kind", KINDS)
def test_load_is_the_python_sides_and_its_rate_the_derivative(kind):
    for i, (mine, _theirs) in enumerate(_points(kind, 6, 11)):
        p = sc.Params(**mine)
        T = 2.0 * math.pi / p.Omega
        ts = np.random.default_rng(i).uniform(-3.0 * T, 3.0 * T, 40)
        h = 1e-3 * T
        stencil = np.concatenate([ts, ts + h, ts - h, ts + 0.5 * h, ts - 0.5 * h])
        out = np.empty((4, stencil.size))
        assert _loads(p.loads[0].data(), p.row(0.0, 0.0), _law_data(p), stencil, out)
        e = out[0].reshape(5, -1)
        scale = p.loads[0].bound() * p.F0 + p.k * p.Y0 + p.c * p.Omega * p.Y0
        assert np.allclose(e[0], excitations.load(p, ts), rtol=0, atol=1e-13 * scale)
        assert np.allclose(out[2], out[0], rtol=0, atol=1e-13 * scale)
        assert np.allclose(out[3], out[1], rtol=0, atol=1e-13 * scale * p.Omega)
        d1 = (e[1] - e[2]) / (2 * h)
        d2 = (e[3] - e[4]) / h
        fd = (4.0 * d2 - d1) / 3.0                  # Richardson: O(h^4)
        rate = out[1].reshape(5, -1)[0]
        assert np.allclose(rate, fd, rtol=0, atol=1e-7 * scale * p.Omega), kind


def test_cos_sin_is_the_librarys_in_and_beyond_a_steps_turn():
    """The stages' cos and sin (``trig.cos_sin``): Taylor polynomials where a step
    turns the phase by at most 0.6 (within 2.3e-16 of the library), reduced and
    doubled beyond (within 3e-15 up to |th| = 50)."""
    from sweepcore._kernels.trig import cos_sin
    both = njit(cache=False)(lambda th: cos_sin(th))
    for top, tol in ((0.6, 2.3e-16), (50.0, 3e-15)):
        for th in np.linspace(-top, top, 4001):
            c, s = both(th)
            assert abs(c - math.cos(th)) <= tol and abs(s - math.sin(th)) <= tol, th


# ------------------------------------------------------------ the stick's exit
def _first_exit(p, t0, x0, t_stop, r_pos, r_neg):
    """The first sample time where h leaves [-r_neg, r_pos] on a dense grid, and the
    grid spacing (inf: none up to t_stop)."""
    T = 2.0 * math.pi / p.Omega
    n = int(math.ceil((t_stop - t0) / T * SAMPLES)) + 1
    t = np.linspace(t0, t_stop, n)
    h = excitations.load(p, t) - p.k * (x0 + p.v * (t - t0)) - p.c * p.v
    out = np.flatnonzero((h > r_pos) | (h < -r_neg))
    return (t[out[0]] if out.size else np.inf), t[1] - t[0], t, h


def _sticks(p, r_pos, r_neg, rng):
    """Random sticks (t0, x0) whose holding force starts inside the band: half at
    random positions, half placed so that the force's largest value over the next
    period pokes out of the band by 1e-4 of its swing (a short excursion, which a
    stick-exit search that mistakes the monotone pieces of h steps over)."""
    T = 2.0 * math.pi / p.Omega
    t0 = rng.uniform(0.0, 2.0 * T, N_STICKS)
    x0 = (excitations.load(p, t0) - p.c * p.v - rng.uniform(-r_neg, r_pos, N_STICKS)) / p.k
    for j in range(0, N_STICKS, 2):
        t = np.linspace(t0[j], t0[j] + T, SAMPLES + 1)
        g = excitations.load(p, t) - p.k * p.v * (t - t0[j]) - p.c * p.v   # h + k x0
        m = int(np.argmax(g[1:])) + 1
        x = (g[m] - r_pos - 1e-4 * (g.max() - g.min())) / p.k
        if np.all(g[:m] - p.k * x >= -r_neg) and g[0] - p.k * x <= r_pos:
            x0[j] = x
    return t0, x0


@pytest.mark.parametrize("kind", KINDS)
def test_stick_exit_is_the_first_exit_of_dense_samples(kind):
    """Every exit found, none early: the exit is no later than the first sample
    outside the band, h is at the band's edge there, every sample before it is
    inside, and an exit between samples is where h leaves the band (its rate points
    outwards). Points on fixed ground and on belts (where h' = e' - k v: a sign
    error in the critical phases cuts h at the wrong places)."""
    rng = np.random.default_rng(23)
    points = [MAKERS[kind](rng, v=v) for v in (0.0, 0.3, 0.8, 1.5) for _ in range(2)]
    for i, (mine, _theirs) in enumerate(points):
        p = sc.Params(**mine)
        lw = _law_data(p)
        r_pos, r_neg = (p.r_y, p.r_y) if p.law is None else p.law.static_limits()
        T = 2.0 * math.pi / p.Omega
        t0, x0 = _sticks(p, r_pos, r_neg, np.random.default_rng(100 + i))
        t_stop = t0 + 3.0 * T
        out = np.empty((N_STICKS, 4))
        _exits(p.loads[0].data(), p.row(0.0, 0.0), lw, t0, x0, t_stop, out)
        for j in range(N_STICKS):
            first, dt, ts, h = _first_exit(p, t0[j], x0[j], t_stop[j], r_pos, r_neg)
            t_exit = t0[j] + out[j, 0]
            if not np.isfinite(first):
                assert out[j, 1] == 0.0 or t_exit >= t_stop[j] - dt, (kind, i, j)
                continue
            assert out[j, 1] == 1.0, (kind, i, j, "an exit missed")
            assert t_exit <= first, (kind, i, j, t_exit, first, "an exit late")
            inside = ts < t_exit
            assert np.all((h[inside] <= r_pos) & (h[inside] >= -r_neg)), (kind, i, j)
            he = excitations.load(p, np.array([t_exit]))[0] - p.k * out[j, 3] - p.c * p.v
            edge = r_pos if out[j, 2] > 0 else -r_neg
            assert abs(he - edge) <= 1e-9 * (abs(edge) + p.F0), (kind, i, j)
            if t_exit < first - dt:
                # an excursion shorter than the samples' spacing: h must leave the
                # band there (its rate points outwards)
                d = 1e-7 * T
                rate = (excitations.load(p, np.array([t_exit + d]))[0] -
                        excitations.load(p, np.array([t_exit - d]))[0]) / (2 * d) - p.k * p.v
                assert rate * np.sign(edge) > 0.0, (kind, i, j, "an exit early")


# ------------------------------------------------- closed form: a fast belt
def _superposition(p, load):
    """The steady response of the linear slider m x'' + c x' + k x = e(t) + r_k
    (a belt faster than the motion, Coulomb friction r_k): ``x(t)`` on the times
    given and the largest speed, from the harmonics' complex amplitudes."""
    n = np.arange(1, load.harmonics + 1)
    w = n * p.Omega
    H = 1.0 / (p.k - p.m * w ** 2 + 1j * p.c * w)
    amp = p.F0 * (load.cos - 1j * load.sin) * np.exp(1j * n * p.phi) * H
    amp[0] += p.Y0 * (p.k + 1j * p.c * p.Omega) * H[0]      # the anchor's force

    def x(t):
        t = np.asarray(t, float)[..., None]
        return np.sum((amp * np.exp(1j * w * t)).real, -1) + p.r_k / p.k

    def xd(t):
        t = np.asarray(t, float)[..., None]
        return np.sum((1j * w * amp * np.exp(1j * w * t)).real, -1)
    return x, xd


@pytest.mark.parametrize("kind", KINDS)
def test_fast_belt_gives_the_superposition_of_the_harmonics(kind):
    """A two-tone load and the anchor's motion, Coulomb friction, a belt faster than
    every velocity of the motion: no stick, no stop; amplitude, mean and extremes
    equal the closed-form superposition (extrema by Brent on the closed form) within
    1e-8 L, the multiplier exp(-c T/(2 m)) within 1e-7."""
    from scipy.optimize import minimize_scalar
    rng = np.random.default_rng(5)
    for _ in range(3):
        mine, _theirs = MAKERS[kind](rng, law=dict(r_y=0.7))
        load = sc.PeriodicLoad(cos=[rng.uniform(0.5, 1.0), 0.0, rng.uniform(0.2, 0.5)],
                               sin=[rng.uniform(-0.5, 0.5), rng.uniform(0.2, 0.5)])
        mine.update(load=load, c=rng.uniform(0.05, 0.3), Y0=rng.uniform(0.1, 0.5))
        probe = sc.Params(**{**mine, "v": 1.0})
        x, xd = _superposition(probe, load)
        T = 2.0 * math.pi / probe.Omega
        t = np.linspace(0.0, T, 4001)
        mine["v"] = 1.5 * float(np.max(np.abs(xd(t)))) + 0.1    # faster than the motion
        p = sc.Params(**mine)
        res = sc.attractor(p, x0=0.0, xdot0=0.0)
        assert res.status == "ok" and res.regime == "slip_cycle", res
        assert (res.multiplicity, res.sticks_per_period, res.stops_per_period) == (1, 0, 0)
        i_max, i_min = np.argmax(x(t)), np.argmin(x(t))
        x_max = -minimize_scalar(lambda s: -x(s), bracket=(t[i_max] - T / 4000, t[i_max],
                                                           t[i_max] + T / 4000),
                                 tol=1e-12).fun
        x_min = minimize_scalar(x, bracket=(t[i_min] - T / 4000, t[i_min],
                                            t[i_min] + T / 4000), tol=1e-12).fun
        L = p.r_k / p.k + (load.bound() * p.F0 + p.k * p.Y0) / p.k
        assert abs(res.x_max - x_max) <= 1e-8 * L, (res.x_max, x_max)
        assert abs(res.x_min - x_min) <= 1e-8 * L, (res.x_min, x_min)
        assert abs(res.mean - p.r_k / p.k) <= 1e-8 * L
        assert res.floquet == pytest.approx(math.exp(-p.c * T / (2.0 * p.m)), abs=1e-7)


# ----------------------------------------------- the default load, in other words
def test_one_cosine_is_the_default_load_in_any_form():
    """load=None, PeriodicLoad(cos=[1]), PeriodicLoad(cos=[0.5]) at twice F0 and
    PeriodicLoad(sin=[1]) at phi + pi/2 are the same force: the same response to
    1e-9 L."""
    base = dict(m=1.0, k=1.0, r_y=1.0, r_k=0.6, v_s=0.4, c=0.05, v=0.5, Omega=1.3)
    ref = sc.attractor(sc.Params(**base, F0=1.2, phi=0.3), x0=0.0, xdot0=0.0)
    forms = [dict(F0=1.2, phi=0.3, load=sc.PeriodicLoad(cos=[1.0])),
             dict(F0=2.4, phi=0.3, load=sc.PeriodicLoad(cos=[0.5])),
             dict(F0=1.2, phi=0.3 + math.pi / 2, load=sc.PeriodicLoad(sin=[1.0]))]
    L = 1.0 + 0.5 + 1.2
    assert ref.status == "ok"
    for form in forms:
        res = sc.attractor(sc.Params(**base, **form), x0=0.0, xdot0=0.0)
        assert res.status == "ok" and res.regime == ref.regime
        for name in ("amplitude", "mean", "x_max", "x_min", "x_section"):
            assert abs(getattr(res, name) - getattr(ref, name)) <= 1e-9 * L, (form, name)


# ------------------------------------------------- against the reference
def _compare(mine, theirs):
    from reference_forced import Forced, forced_steady
    p = sc.Params(**mine)
    mod = Forced(**theirs)
    try:
        ref = forced_steady(mod, x0=0.0, xd0=0.0)
    except RuntimeError as err:           # scipy's own step-size underflow
        pytest.skip(f"reference: {err}")
    if ref["status"] != "ok":
        pytest.skip(f"reference: {ref['status']}")
    res = sc.attractor(p, x0=0.0, xdot0=0.0)
    assert res.status == "ok", res
    assert (res.multiplicity, res.sticks_per_period, res.stops_per_period) == \
        (ref["multiplicity"], ref["sticks_per_period"], ref["stops_per_period"])
    for name in ("amplitude", "mean", "x_max", "x_min"):
        assert abs(getattr(res, name) - ref[name]) <= CONTRACT * mod.L, name
    assert res.floquet == pytest.approx(ref["floquet"], abs=1e-5)


def _harmonic_points(count, seed, slow=False):
    """Points with 2-3 harmonics, half on fixed ground and half on a belt."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(count):
        for kind in KINDS:
            mine, theirs = MAKERS[kind](rng, v=0.0 if i % 2 == 0 else rng.uniform(0.2, 1.5))
            while mine["load"].harmonics < 2:
                mine, theirs = MAKERS[kind](rng, v=mine["v"])
            out.append(pytest.param(mine, theirs, id=f"{kind}-{'ground' if i % 2 == 0 else 'belt'}-{i}",
                                    marks=[pytest.mark.slow] if slow else []))
    return out


@pytest.mark.parametrize("mine, theirs", _harmonic_points(4, 2028))
def test_engine_against_the_reference_with_harmonics(mine, theirs):
    _compare(mine, theirs)


@pytest.mark.parametrize("mine, theirs", _harmonic_points(30, 91, slow=True))
def test_engine_against_the_reference_with_harmonics_soak(mine, theirs):
    _compare(mine, theirs)
