r"""Causal material damping: a generalized Maxwell (Prony) law fitted to a loss factor.

Why not a constant loss factor. A modulus E (1 + i eta) with eta constant at every
frequency (hysteretic damping) is not causal: its real and imaginary parts must be
Hilbert transforms of each other (the Kramers-Kronig relations), and a loss
eta held over a band forces the real part to rise through it, about
E(w2) / E(w1) = (w2 / w1)^(2 atan(eta) / pi) (1.6 x over 1 Hz-2 kHz for eta = 0.1).
So no finite real state space and no time integrator reproduces the hysteretic law,
and a frequency analysis with it disagrees with any transient. One causal law is used
instead by the frequency analysis, the transient and the reduced model alike.

The law. Every part kind k with a loss (silicone shear and volumetric, piezo
stiffness, permittivity) has the multiplier of its real matrix K_k

    kappa_k(s) = 1 + sum_j c_jk s tau_j / (1 + s tau_j),    s = i w,

N relaxation times tau_j = 1 / (2 pi f_j), f_j log-spaced over the law's band widened
by a factor `margin` at each end (shared by every kind). A modulus (shear, piezo
stiffness) has c_jk = g_j >= 0: a standard-linear-solid (Maxwell) branch each,
stiffening with frequency. A compliance (the silicone's volumetric 1/K of the mixed
form, the permittivity) has c_jk = -g_j, sum_j g_j < 1: Debye relaxation, the bulk
modulus stiffens and the permittivity falls with frequency. Both are passive
(Im kappa has the sign of a loss at every frequency) and kappa_k(0) = 1: the
material data are the relaxed (static) values, so static analyses are the zero-
frequency limit of the dynamic ones. The weights g_j >= 0 are the non-negative
least-squares solution of |Im kappa| = eta Re kappa on a log grid over the band
(linear in g): the loss factor is the project's eta within `ripple` over the band
(measured and returned), falling off outside it as every causal solid's does.

Time domain (fem.dynamics, fem.dynamics): with s_j = q / (1 + s tau_j) (the
displacement, or potential, low-pass filtered at tau_j),

    K(s) q = K_u q - sum_j K^(j) s_j,   tau_j s_j' = q - s_j,
    K^(j) = sum_k c_jk K_k,   K_u = sum_k kappa_k(inf) K_k (the unrelaxed stiffness),

exact: the internal variables s_j are the memory of the Prony series.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import nnls

BAND = (1.0, 2000.0)       # Hz: where the loss factor is held (the project's dynamic band)
BRANCHES = 6               # relaxation times over the widened band
MARGIN = 2.0               # relaxation frequencies from BAND[0] / MARGIN to BAND[1] * MARGIN


@dataclass(frozen=True)
class Relaxation:
    """The law of every lossy part kind: kappa_k(s) = 1 + sum_j c_jk s tau_j / (1 + s tau_j)."""

    tau: np.ndarray                                  # (N,) s
    weights: dict = field(default_factory=dict)      # kind -> (N,) c_jk (signed: + modulus, - compliance)
    band: tuple = BAND
    losses: dict = field(default_factory=dict)       # kind -> (eta, compliance): what the law was fitted to

    def kappa(self, w: float) -> dict:
        """kind -> complex multiplier at angular frequency w (kinds without loss: 1)."""
        x = 1j * w * self.tau
        h = x / (1 + x)
        return {k: complex(1 + c @ h) for k, c in self.weights.items()}

    def unrelaxed(self) -> dict:
        """kind -> kappa_k(infinity) = 1 + sum_j c_jk."""
        return {k: float(1 + c.sum()) for k, c in self.weights.items()}

    def branch(self, j: int) -> dict:
        """kind -> c_jk of branch j (K^(j) = sum_k c_jk K_k)."""
        return {k: float(c[j]) for k, c in self.weights.items()}

    @property
    def n(self) -> int:
        return len(self.tau)

    def to_data(self) -> dict:
        return {"tau": self.tau.tolist(), "weights": {k: c.tolist() for k, c in self.weights.items()},
                "band": list(self.band), "losses": {k: [float(e), bool(c)] for k, (e, c) in self.losses.items()}}

    @classmethod
    def from_data(cls, d: dict) -> "Relaxation":
        return cls(np.asarray(d["tau"], float), {k: np.asarray(c, float) for k, c in d["weights"].items()},
                   tuple(d["band"]), {k: (e, c) for k, (e, c) in d.get("losses", {}).items()})


def times(band=BAND, n: int = BRANCHES, margin: float = MARGIN) -> np.ndarray:
    """Relaxation times (s): n frequencies log-spaced over [band[0] / margin, band[1] * margin]."""
    return 1 / (2 * np.pi * np.geomspace(band[0] / margin, band[1] * margin, n))


def fit(eta: float, compliance: bool, tau: np.ndarray, band=BAND, points: int = 200) -> np.ndarray:
    """Signed weights c (N,) whose loss factor |Im kappa| / Re kappa is eta over the band
    (non-negative least squares; module docstring). eta = 0: no relaxation."""
    if eta == 0:
        return np.zeros(len(tau))
    x = 2 * np.pi * np.geomspace(*band, points)[:, None] * tau[None, :]
    a, b = x / (1 + x ** 2), x ** 2 / (1 + x ** 2)          # Im, Re of s tau / (1 + s tau)
    g = nnls(a + eta * b if compliance else a - eta * b, np.full(points, eta))[0]
    if compliance and g.sum() >= 1:
        raise ValueError(f"loss factor {eta:g} is too large for a causal compliance over {band[0]:g}-{band[1]:g} Hz "
                         "(its unrelaxed value would be negative); use a smaller loss factor")
    return -g if compliance else g


def relaxation_law(losses: dict, band=BAND, n: int = BRANCHES) -> Relaxation:
    """The law of the part kinds in `losses` (kind -> (eta, compliance)); the same fit
    is shared between kinds with the same (eta, compliance)."""
    tau = times(band, n)
    memo = {}
    weights = {}
    for kind, (eta, compliance) in losses.items():
        key = (float(eta), bool(compliance))
        if key not in memo:
            memo[key] = fit(*key, tau, band)
        if np.any(memo[key]):
            weights[kind] = memo[key]
    return Relaxation(tau if weights else np.zeros(0), weights, tuple(band),   # no loss: no internal variables
                      {k: (float(e), bool(c)) for k, (e, c) in losses.items()})


def ripple(rel: Relaxation, kind: str, eta: float, band=None, points: int = 400) -> float:
    """The largest relative deviation of the kind's loss factor from eta over the band."""
    band = band or rel.band
    f = np.geomspace(*band, points)
    k = np.array([rel.kappa(2 * np.pi * x).get(kind, 1.0) for x in f])
    return float(np.abs(np.abs(k.imag) / k.real / eta - 1).max())
