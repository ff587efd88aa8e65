"""The first-order step fit of a taxel, robust to baseline drift.

Model (t in s, v the taxel's conditioning output in V, F the load cell in N). A
first-order chain (a resistor R across the taxel's capacitance C_p, tau = R C_p; or
a charge amplifier, tau = R_f C_f) answers a force step F0 at t0 with
    v(t) = b + A F0 exp(-(t - t0) / tau),
the step response of the high-pass A s tau / (1 + s tau). The fitted model drives
that high-pass (bilinear, at the rig's rate) with the *measured* force minus its
initial level, so the actuator's finite rise is in the model, then through the
rig's notch when its chain has one, plus a baseline b + c (t - t0):
    m(t; A, tau, b, c) = b + c (t - t0) + notch(HP_tau(A (F - F_0))).

Noise. What is left, e = v - m, is not white: besides white ADC noise and mains
hum, the baseline drifts (temperature, the charge amplifier's bias current), a
random walk whose power sits at the seconds-long time scales of tau itself. A
white-residual fit then weighs every sample alike and its Jacobian interval is
far too narrow (at 20 mV rms drift tau was 40-50 % off with a claimed +-1 %:
benchmarks/measure_step_drift.py). So, "drift" (the default):
  1. data and model are averaged over blocks of a whole number of mains periods
     (20 ms at 50 Hz, more if the record would give over 1000 blocks), which
     removes the hum and its harmonics, over the whole record from its start (the
     pre-step segment shows the drift alone);
  2. the block residuals are modelled as white noise plus a drift: a random walk
     from the record's start (intensity q, V/sqrt(s)) through a first-order
     low-pass of corner fc (a thermal drift has a finite bandwidth; fc = inf is
     the plain walk), a Gaussian process with covariance
        Sigma = s^2 (I + lam K_fc),   K_fc = dt G G^T,  G_jk = 1 - a^(j - k + 1) (j >= k),
     a = exp(-2 pi fc dt), dt the block length, s^2 the white variance, q^2 = lam s^2;
  3. given the residual r, (lam, fc) maximise the concentrated log-likelihood
        -n/2 log(r^T (I + lam K)^-1 r / n) - 1/2 log det(I + lam K)
     over lam (bounded scalar search) for each fc of 0.05, 0.1, 0.2, 0.5, 1, 2, 5 Hz
     and inf (K = U diag(d) U^T once per fc, so each lam costs O(n^2)), s^2 concentrated out;
  4. (A, log tau, b, c) are refitted by nonlinear least squares
     (scipy.optimize.least_squares) on the whitened residuals
     diag(1 + lam d)^(-1/2) U^T r: generalised least squares; 3-4 repeat three times.
The 95 % interval of tau is log tau +- 1.96 sigma, sigma^2 the (log tau, log tau)
entry of s^2 (J_w^T J_w)^-1, J_w the Jacobian of the whitened residuals, s^2 =
sum(w^2) / (n - 4): the interval of a GLS fit with the noise's own correlation.
Its coverage over seeded simulations is counted by benchmarks/measure_step_drift.py.

A lower bound on what one step can give: for a random-walk drift of intensity q
(V / sqrt(s)) and a decay of amplitude a = A F0, the Fisher information of tau
from the decay's slope is a^2 / (4 tau^3 q^2), so sd(tau) / tau >= 2 q sqrt(tau) / a
(12-16 % for the simulator's default 20 mV rms drift over 12 s, 1.7-3.1 s and a
0.3 V step). No fit recovers tau to 2 % from one such step; the interval says so.

"white" is the former fit, kept for the benchmark's comparison: raw samples from
0.1 s before the step, white residuals, s^2 = sum(r^2) / (n - 4).

R_eff = tau / C_p (resistor or open chains; C_p from the scene's lumped model);
for a charge amplifier R_f,eff = tau / C_f.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Literal

import numpy as np
from scipy import optimize, signal
from scipy.linalg import toeplitz

from taxel.studies.measured.events import Record, segments, smooth
from taxel.studies.bench.folder import MeasurementError
from taxel.studies.bench.rig import Conditioning

Noise = Literal["drift", "white"]


@dataclass
class StepFit:
    taxel: str
    tau_s: float
    tau_ci95_s: tuple[float, float]
    amplitude_V_per_N: float          # A: the chain's high-frequency gain per newton
    step_N: float                     # F0
    rms_residual_V: float             # s: the white part ("drift") or the residuals ("white")
    R_eff_ohm: float | None = None    # tau / C_p (resistor or open chain, with a scene)
    R_f_eff_ohm: float | None = None  # tau / C_f (charge amplifier)
    noise_model: str = "drift"
    drift_V_per_sqrt_s: float | None = None   # q, the fitted random walk's intensity
    drift_corner_Hz: float | None = None      # fc, its low-pass corner (inf: a plain random walk)
    fit: dict = field(default_factory=dict, repr=False)   # t0, b, c, window for plots

    def record(self) -> dict:
        return asdict(self)


def _hp_notch(x: np.ndarray, tau: float, rate: float, cond: Conditioning | None) -> np.ndarray:
    b, a = signal.bilinear([tau, 0.0], [tau, 1.0], fs=rate)
    y = signal.lfilter(b, a, x)
    if cond is not None and cond.notch:
        lo, hi = cond.notch_frequency - cond.notch_bandwidth / 2, cond.notch_frequency + cond.notch_bandwidth / 2
        y = signal.sosfilt(signal.iirfilter(1, [lo, hi], btype="bandstop", ftype="butter", fs=rate, output="sos"), y)
    return y


CORNERS_HZ = (0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0, np.inf)


class DriftNoise:
    """Sigma = s^2 (I + lam K_fc), the drift a random walk through a first-order
    low-pass of corner fc (module docstring, steps 2-3), at block times t."""

    def __init__(self, t: np.ndarray, corners=CORNERS_HZ):
        dt = float(t[1] - t[0]) if len(t) > 1 else 1.0
        i = np.arange(len(t))
        self.eig = []
        for fc in corners:
            a = float(np.exp(-2 * np.pi * fc * dt))
            g = 1.0 - a ** (i + 1)                 # the low-pass's response to one walk step
            G = toeplitz(g, np.zeros(len(t)))
            d, U = np.linalg.eigh(dt * (G @ G.T))
            self.eig.append((float(fc), np.clip(d, 0.0, None), U))
        self.k, self.lam = len(corners) - 1, 0.0

    @property
    def corner_Hz(self) -> float:
        return self.eig[self.k][0]

    def fit(self, r: np.ndarray) -> None:
        """lam and fc by maximum likelihood, s^2 concentrated out."""
        n, best = len(r), (np.inf, self.k, 0.0)
        for k, (_, d, U) in enumerate(self.eig):
            z2 = (U.T @ r) ** 2

            def nll(loglam):
                w = 1.0 + np.exp(loglam) * d
                return 0.5 * n * np.log(np.sum(z2 / w) / n) + 0.5 * np.sum(np.log(w))
            lo = -np.log(max(d.max(), 1e-300)) - 10
            res = optimize.minimize_scalar(nll, bounds=(lo, lo + 35), method="bounded")
            cand = (res.fun, k, float(np.exp(res.x))) if res.fun < nll(lo) else (nll(lo), k, 0.0)
            best = min(best, cand)
        _, self.k, self.lam = best

    def whiten(self, r: np.ndarray) -> np.ndarray:
        _, d, U = self.eig[self.k]
        return (U.T @ r) / np.sqrt(1.0 + self.lam * d)


def _blocks(x: np.ndarray, m: int) -> np.ndarray:
    n = len(x) // m
    return x[:n * m].reshape(n, m).mean(axis=1)


def fit_step(rec: Record, k: int, cond: Conditioning | None, C_p: float | None = None,
             noise: Noise = "drift", mains: float = 50.0, max_blocks: int = 1000) -> StepFit:
    """The first-order step fit of taxel channel k (module docstring)."""
    segs = segments(rec, level=0.5)
    if not segs:
        raise MeasurementError("no step on the force channel")
    i0 = segs[0][0]
    n_pre = max(1, int(0.1 * rec.rate))
    lo = max(0, i0 - n_pre)
    F = rec.force - np.median(rec.force[:max(1, i0 - int(0.02 * rec.rate))])
    F0 = float(np.median(rec.force[i0 + int(0.05 * rec.rate):]) - np.median(rec.force[:max(1, lo)]))
    v = rec.volts[:, k]
    t = rec.t - rec.t[i0]
    # initial tau: the time the smoothed response takes to fall to 1/e of its extreme
    vs = smooth(v - np.median(v[lo:i0] if i0 > lo else v[:1]), max(1, int(0.01 * rec.rate)))
    j = i0 + int(np.argmax(np.abs(vs[i0:i0 + int(0.5 * rec.rate)])))
    below = np.flatnonzero(np.abs(vs[j:]) < np.abs(vs[j]) / np.e)
    tau0 = max((below[0] if len(below) else len(vs) - j) / rec.rate, 2.0 / rec.rate)
    A0 = vs[j] / F0 if F0 else 1.0
    if noise == "drift":
        m = max(1, int(round(rec.rate / mains)))
        m *= int(np.ceil(len(v) / m / max_blocks))
        start = 0
        y, tb = _blocks(v, m), _blocks(t, m)
        gp = DriftNoise(tb)
    else:
        m, start = 1, lo
        y, tb = v[lo:], t[lo:]

    def model(p):
        A, ltau, b, c = p
        hp = A * _hp_notch(F, np.exp(ltau), rec.rate, cond)[start:]
        return b + c * tb + (_blocks(hp, m) if m > 1 else hp)

    white = True

    def resid(p):
        r = model(p) - y
        return r if white else gp.whiten(r)

    p0 = np.array([A0, np.log(tau0), float(np.median(v[:max(1, lo)])), 0.0])
    xs = np.array([abs(A0) or 1.0, 1.0, 0.01, 0.01])
    res = optimize.least_squares(resid, p0, x_scale=xs, method="lm")
    if noise == "drift":
        white = False
        for _ in range(3):
            gp.fit(model(res.x) - y)
            res = optimize.least_squares(resid, res.x, x_scale=xs, method="lm")
    n, p = len(res.fun), len(res.x)
    s2 = 2 * res.cost / max(n - p, 1)
    try:
        cov = s2 * np.linalg.pinv(res.jac.T @ res.jac)
        sig = float(np.sqrt(max(cov[1, 1], 0.0)))
    except np.linalg.LinAlgError:
        sig = float("inf")
    A, ltau, b, c = res.x
    tau = float(np.exp(ltau))
    out = StepFit(rec.names[k], tau, (float(np.exp(ltau - 1.96 * sig)), float(np.exp(ltau + 1.96 * sig))),
                  float(A), F0, float(np.sqrt(s2)), noise_model=noise,
                  fit={"t0_s": float(rec.t[i0]), "b_V": float(b), "c_V_per_s": float(c),
                       "from_s": float(rec.t[start]), "block_samples": m})
    if noise == "drift":
        out.drift_V_per_sqrt_s = float(np.sqrt(gp.lam * s2))
        out.drift_corner_Hz = gp.corner_Hz
    if cond is not None and cond.circuit == "charge_amplifier":
        out.R_f_eff_ohm = tau / cond.C_f
    elif C_p:
        out.R_eff_ohm = tau / C_p
    return out


def step_model(rec: Record, fit: StepFit, cond: Conditioning | None) -> np.ndarray:
    """The fitted step model over the whole record (for plots)."""
    i0 = int(round(fit.fit["t0_s"] * rec.rate))
    F = rec.force - np.median(rec.force[:max(1, i0 - int(0.02 * rec.rate))])
    return (fit.fit["b_V"] + fit.fit["c_V_per_s"] * (rec.t - fit.fit["t0_s"])
            + fit.amplitude_V_per_N * _hp_notch(F, fit.tau_s, rec.rate, cond))
