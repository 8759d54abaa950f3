"""A periodic load on the slider and a harmonic motion of the anchor (the kind
``periodic``): the load's shape as data, :class:`PeriodicLoad`.

    m x'' + c (x' - y') + k (x - y) + F(x' - v) = F0 p(Omega t + phi),
    y = Y0 cos(Omega t),
    p(theta) = sum_{n=1}^{N} a_n cos(n theta) + b_n sin(n theta).

The shape p is one period per unit load (a cutting force with its tooth-passing
harmonics, an unbalance with a second harmonic, a force measured over one period);
``load=None`` is one cosine (Hong & Liu, J. Sound Vib. 229 (2000) 1171-1192, the
harmonic load of the paper's eq. 4). The kernels see the load and the anchor's
motion as one trigonometric polynomial of time (``sweepcore/_kernels/excitations/
periodic.py``); a new shape is new data and compiles nothing.
"""
from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from .._kernels.excitations import periodic as _kernel
from ..laws.base import check_name, real

NAME = "periodic"
MAX_HARMONICS = 128     # harmonics a shape holds (the kernels' cost grows with them)
REPRESENT = 1e-9        # from_samples: the samples reproduced to this of their largest


class PeriodicLoad:
    """The shape p of a periodic load per unit amplitude: the load on the slider is
    ``F0 p(Omega t + phi)`` [kN] with F0, Omega and phi keywords of ``Params`` and
    axes of ``Grid``.

    Parameters
    ----------
    cos, sin : sequences of float
        ``a_1, a_2, ...`` and ``b_1, b_2, ...`` of
        ``p(theta) = sum_n a_n cos(n theta) + b_n sin(n theta)`` (dimensionless, n
        from 1; the shorter is padded with zeros). No constant term: a constant force
        F only moves the spring's rest position by F/k.
    name : str, optional
        A label (the ``load`` coordinate of a sweep over several shapes).

    Attributes
    ----------
    truncation : float
        The largest difference between the represented shape and the samples it was
        made from (``from_samples``; 0 for coefficients given).
    """

    kind = NAME

    def __init__(self, cos=(), sin=(), name=None):
        a = _coefficients("cos", cos)
        b = _coefficients("sin", sin)
        n = max(a.size, b.size)
        if n == 0:
            raise ValueError("PeriodicLoad needs at least one coefficient (cos=[...] or "
                             "sin=[...]): p(theta) = sum_n a_n cos(n theta) + "
                             "b_n sin(n theta), n >= 1")
        a = np.pad(a, (0, n - a.size))
        b = np.pad(b, (0, n - b.size))
        nonzero = np.flatnonzero((a != 0.0) | (b != 0.0))
        if nonzero.size == 0:
            raise ValueError("PeriodicLoad: every coefficient is 0 (no load); give F0 = 0 "
                             "for an unloaded slider")
        n = int(nonzero[-1]) + 1
        if n > MAX_HARMONICS:
            raise ValueError(f"PeriodicLoad holds at most {MAX_HARMONICS} harmonics, got "
                             f"{n}: drop the small high harmonics")
        self.cos = a[:n].copy()
        self.sin = b[:n].copy()
        self.cos.setflags(write=False)
        self.sin.setflags(write=False)
        self.name = check_name(name) if name is not None else _default_name(self.cos,
                                                                            self.sin)
        self.truncation = 0.0

    @classmethod
    def from_samples(cls, values, name=None) -> PeriodicLoad:
        """The shape from one period of samples at uniform phases ``theta_j = 2 pi j /
        M`` (j = 0 .. M-1, the sample at 2 pi not repeated): their Fourier
        coefficients, the smallest number of harmonics that reproduces every sample to
        ``1e-9`` of the largest (``truncation`` says how far). Refused where that
        cannot be: a mean (a constant force) beyond that, or more than
        ``MAX_HARMONICS`` harmonics needed."""
        v = _coefficients("values", values)
        if v.size < 3:
            raise ValueError(f"from_samples needs at least 3 samples of one period, got "
                             f"{v.size}")
        scale = float(np.max(np.abs(v)))
        if scale == 0.0:
            raise ValueError("from_samples: every sample is 0 (no load)")
        m = v.size
        c = np.fft.rfft(v) / m
        mean = float(c[0].real)
        if abs(mean) > REPRESENT * scale:
            raise ValueError(
                f"from_samples: the samples have a mean of {mean:.6g} ({abs(mean) / scale:.3g}"
                f" of the largest): a periodic load averages to 0 over a period. Subtract "
                f"the mean (a constant force F moves the spring's rest position by F/k) "
                f"and give the rest")
        a = 2.0 * c[1:].real
        b = -2.0 * c[1:].imag
        if m % 2 == 0:                  # the Nyquist harmonic is counted once
            a[-1] *= 0.5
            b[-1] = 0.0
        theta = 2.0 * np.pi * np.arange(m) / m
        for n in range(1, a.size + 1):
            err = float(np.max(np.abs(_series(a[:n], b[:n], theta) - (v - mean))))
            if err <= REPRESENT * scale:
                break
        if n > MAX_HARMONICS:
            raise ValueError(f"from_samples: {n} harmonics are needed to reproduce the "
                             f"{m} samples to {REPRESENT:g} of their largest; at most "
                             f"{MAX_HARMONICS} are held (smooth the samples or give "
                             "fewer)")
        load = cls(a[:n], b[:n], name=name)
        load.truncation = float(np.max(np.abs(load.values(theta) - v)))
        return load

    @classmethod
    def from_csv(cls, path, name=None) -> PeriodicLoad:
        """Samples of one period from a CSV file, one value per row (a first row that
        is not a number is a header), as :meth:`from_samples`."""
        path = Path(path)
        if str(path) in ("", "."):
            raise ValueError("the load file's path is empty")
        try:
            with open(path, newline="") as fh:
                rows = [r for r in csv.reader(fh) if r and any(x.strip() for x in r)]
        except OSError as err:
            raise ValueError(f"cannot read the load file {str(path)!r}: "
                             f"{err.strerror or err}") from None
        values = []
        for i, r in enumerate(rows, start=1):
            try:
                values.append(float(r[-1]))
            except ValueError:
                if i == 1:
                    continue            # a header
                raise ValueError(f"{str(path)!r} line {i}: a number expected, got "
                                 f"{','.join(r)!r}") from None
        load = cls.from_samples(values, name=name or path.stem)
        load.source = str(path)
        return load

    # ------------------------------------------------------------ kernels' view
    def data(self):
        """The kernel data (``sweepcore/_kernels/excitations/periodic.py``)."""
        return _kernel.Periodic(np.array(self.cos, np.float64),
                                np.array(self.sin, np.float64), np.zeros(0))

    # ------------------------------------------------------------ Python's view
    def values(self, theta) -> np.ndarray:
        """p(theta), dimensionless."""
        return _series(self.cos, self.sin, np.asarray(theta, np.float64))

    def force(self, params, t) -> np.ndarray:
        """The excitation of ``params`` (F0, Omega, phi, Y0; this shape) as one force on
        the slider [kN] at the times t [s]: ``F0 p(Omega t + phi) + k Y0 cos(Omega t)
        - c Omega Y0 sin(Omega t)``."""
        w = params.Omega * np.asarray(t, np.float64)
        return (params.F0 * self.values(w + params.phi) + params.k * params.Y0 * np.cos(w)
                - params.c * params.Omega * params.Y0 * np.sin(w))

    def derivative(self, theta) -> np.ndarray:
        """dp/dtheta."""
        n = np.arange(1, self.cos.size + 1)
        th = np.asarray(theta, np.float64)[..., None]
        return np.sum(n * (self.sin * np.cos(n * th) - self.cos * np.sin(n * th)), -1)

    @property
    def harmonics(self) -> int:
        return int(self.cos.size)

    def attrs(self) -> dict:
        out = {"load": self.name, "load_kind": self.kind,
               "load_cos": ", ".join(f"{x:.17g}" for x in self.cos),
               "load_sin": ", ".join(f"{x:.17g}" for x in self.sin),
               "load_truncation": self.truncation}
        if getattr(self, "source", None):
            out["load_source"] = self.source
        return out

    def describe(self) -> str:
        return (f"periodic load {self.name!r}: {self.harmonics} harmonic"
                f"{'s' if self.harmonics > 1 else ''}, |p| <= {self.bound():.4g}"
                + (f", samples reproduced to {self.truncation:.2g}" if self.truncation
                   else ""))

    def bound(self) -> float:
        """A bound of |p| (the sum of the harmonics' amplitudes)."""
        return float(np.sum(np.hypot(self.cos, self.sin)))

    def fingerprint(self) -> bytes:
        """Bytes that identify the shape exactly (a resumed sweep's grid match)."""
        return b"".join([self.name.encode(), self.cos.astype("<f8").tobytes(), b"|",
                         self.sin.astype("<f8").tobytes()])

    def __eq__(self, other):
        return isinstance(other, PeriodicLoad) and self.fingerprint() == other.fingerprint()

    def __hash__(self):
        return hash(self.fingerprint())

    def __repr__(self):
        return (f"PeriodicLoad(cos={self.cos.tolist()!r}, sin={self.sin.tolist()!r}, "
                f"name={self.name!r})")


def _coefficients(name: str, values) -> np.ndarray:
    """A 1-D array of finite reals, refused by name."""
    if isinstance(values, (str, bytes)) or np.ndim(values) > 1:
        raise TypeError(f"{name} must be a 1-D sequence of real numbers, got {values!r}")
    seq = np.atleast_1d(np.asarray(values, dtype=object)) if np.ndim(values) else \
        np.asarray([values], dtype=object)
    out = np.empty(seq.size)
    for i, x in enumerate(seq):
        out[i] = real(f"{name}[{i}]", x, "")
    return out


def _series(a, b, theta):
    n = np.arange(1, len(a) + 1)
    th = np.asarray(theta, np.float64)[..., None]
    return np.sum(a * np.cos(n * th) + b * np.sin(n * th), -1)


def _default_name(a, b) -> str:
    terms = []
    for n, (an, bn) in enumerate(zip(a, b), start=1):
        arg = "theta" if n == 1 else f"{n} theta"
        for coef, fn in ((an, "cos"), (bn, "sin")):
            if coef:
                terms.append(f"{coef:g} {fn}({arg})" if coef != 1.0 else f"{fn}({arg})")
    text = " + ".join(terms[:4]) + (" + ..." if len(terms) > 4 else "")
    return text


HARMONIC = PeriodicLoad(cos=[1.0], name="cos")    # load=None: F0 cos(Omega t + phi)


def run(P: np.ndarray, laws, loads, o: np.ndarray, out: np.ndarray, parallel: bool) -> None:
    """The steady response of every row into ``out`` (n, NFOB): the stroboscopic
    search (``sweepcore/_kernels/strobe.py``) on each group of rows that share a
    method, a law kind and a load (``sweepcore.compiled.responses``)."""
    from .. import compiled, law
    compiled.responses(P, laws, loads, o, out, parallel)
    # the scale rule every entry shares, its time scales: the natural one
    # (law.unresolvable) and the forcing period's
    law.flag_unresolvable(P, o, out, laws, weak=False)
    _flag_slow_forcing(P, out)
    _flag_neutral(P, laws, loads, out)


def _flag_slow_forcing(P: np.ndarray, out: np.ndarray) -> None:
    """A forcing time 1/Omega beyond the kernels' range (``law.TIME_SCALE_MAX``, as
    the natural time's): status unresolvable_scale, regime failed."""
    from .. import law
    from .._kernels import codes, layout
    with np.errstate(all="ignore"):
        bad = ~(1.0 / P[:, layout.OMEGA] <= law.TIME_SCALE_MAX)
    out[bad, layout.OB_STATUS] = codes.SCALE
    out[bad, layout.OB_REGIME] = codes.R_FAILED


def _flag_neutral(P: np.ndarray, laws, loads, out: np.ndarray) -> None:
    """Den Hartog's slider (constant friction, c = 0, v = 0, one harmonic) at
    Omega/omega = 1/(2 n) where his continuous motion exists (the friction ratio
    below the continuous-motion boundary r_b): a neutral family of responses
    (``theory.neutral_family``; Csernak, Stepan & Shaw 2007), whose member a start
    picks only on the time scale of a multiplier 1; its numbers are flagged, never a
    confident amplitude (regime neutral, status unresolved). The search's own
    multiplier there is 1 to the accuracy of its Jacobian, not exactly (which makes
    its error estimate large: status unresolved, or ok where the estimate passed);
    the kernels name no response neutral themselves, and a response that sticks
    where no continuous motion exists (r above r_b) is no member of the family."""
    from .. import law
    from .._kernels import codes, layout
    from .theory import continuous_motion_boundary, neutral_family
    m, k, om = P[:, layout.M], P[:, layout.K], P[:, layout.OMEGA]
    one = np.array([loads[int(i)].harmonics == 1 for i in P[:, layout.LOAD]])
    with np.errstate(all="ignore"):
        family = np.asarray(neutral_family(m, k, om, P[:, layout.C], P[:, layout.V]))
        shape = [loads[int(i)] for i in P[:, layout.LOAD]]
        a = np.array([s.cos[0] - 1j * s.sin[0] for s in shape])
        force = np.abs(P[:, layout.F0] * a * np.exp(1j * P[:, layout.PHI]) +
                       k * P[:, layout.Y0])
        r = law.per_law(P, laws, "static_bound") / force
        family &= one & (r < continuous_motion_boundary(om / np.sqrt(k / m)))
    family &= law.per_law(P, laws, "conservative", bool)
    family &= out[:, layout.OB_REGIME] != codes.R_STUCK
    family &= np.isin(out[:, layout.OB_STATUS], (codes.OK, codes.UNRESOLVED))
    out[family, layout.OB_REGIME] = codes.R_NEUTRAL
    out[family, layout.OB_STATUS] = codes.UNRESOLVED
