"""The silicone's modulus scale and loss factor, from a press with the actuator's travel recorded.

Why not from the bench's chirp. In the lumped taxel (fem.readout) the force reaches
the piezo through the silicone in series, so the quasi-static charge per newton
does not depend on the silicone, and the stack's resonances lie above 10 kHz: over
the bench's 0-100 Hz a 1.2 x modulus changes |V / F| by 0.15 % at 100 Hz and
0.0015 % at 10 Hz (benchmarks/measure_identifiability.py), against H1's ~1 %.
`identifiability` puts numbers on it (the Fisher information below).

What does identify them: the dynamic stiffness the actuator sees,
    K(f) = F(f) / delta(f) = 1 / X1(f),   X1 the lumped model's top displacement per newton
(state-space output x1, the top silicone's mass), measured as H1 from the travel
delta (input) to the load cell's force F (output) over a chirp (studies.measured.frf
conventions: Welch, Hann, 50 % overlap). Below the resonances the stack is the
silicone layers and the piezo in series, the piezo ~10^3 x stiffer, so
|K| ~ s_E k_sil (the modulus scale at full sensitivity) and
arg K ~ atan(eta f / f_ref): the lumped (and FEM time-domain) damping is viscous,
b = eta k / (2 pi f_ref), f_ref the scene's dynamics.reference_frequency.
Model: the lumped taxel of the scene with the silicone's mu, K (and Yeoh C_i)
scaled by s_E and its loss factor eta:  K_m(f; s_E, eta) = 1 / X1(f).
Fit, in the time domain: the measured force against the modelled one, K_m applied
to the measured travel (zero-padded FFT), both less their medians before the chirp,
    F(t) = IFFT(K_m(f; s_E, eta) FFT(delta))(t) + c
over the chirp's span, by scipy.optimize.least_squares (unknowns log s_E, log eta,
c); 95 % intervals exp(p +- 1.96 sigma), sigma^2 from s^2 (J^T J)^-1, s^2 =
sum(r^2) / (n - 3): the residual is the load cell's white noise, so the interval is
honest (a fit to the Welch H1 instead carried its 0.2 % smooth bias: eta 2.6 % off
with an interval of +-0.05 %). H1 of the stiffness (`stiffness`) is for the plot,
the band and the identifiability figures.
The travel is the actuator's: the load cell and the frame are taken as rigid.

Identifiability (`identifiability`): for a modelled measurement log H(f; theta)
(complex: real and imaginary parts of log H, i.e. log-magnitude and phase) with
independent errors of relative size sigma(f) per frequency, the Fisher
information is I = J^T diag(1 / sigma^2) J, J = d log H / d theta (central
differences in theta = log parameters); the Cramer-Rao bound cov = I^-1 gives
each parameter's smallest relative standard deviation and their correlations.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
from scipy import optimize, signal

from taxel.analyses.surface.bench_model import compliance, loss_factor, scaled_model
from taxel.studies.measured.events import Record
from taxel.studies.bench.folder import MeasurementError
from taxel.studies.measured.frf import chirp_span


@dataclass
class Stiffness:
    """The measured dynamic stiffness F / delta (H1 from the travel to the force)."""
    freqs: np.ndarray
    K: np.ndarray                  # N/m, complex
    coherence: np.ndarray
    n_segments: int


@dataclass
class SiliconeFit:
    modulus_scale: float
    modulus_scale_ci95: tuple[float, float]
    loss_factor: float
    loss_factor_ci95: tuple[float, float]
    band_Hz: tuple[float, float]   # where the stiffness's coherence exceeds 0.99
    rms_residual_pct: float        # of the force, relative to its rms over the chirp
    correlation: float             # between log s_E and log eta at the optimum

    def record(self) -> dict:
        return asdict(self)


def stiffness(rec: Record, resolution: float = 1.0) -> Stiffness:
    """H1 from the travel to the force over the chirp's span (module docstring)."""
    if rec.travel is None:
        raise MeasurementError("this record has no travel channel; record the actuator's travel "
                               "(a channel named travel with its sensitivity, e.g. \"1 V/mm\")")
    a, b = chirp_span(rec)
    n = int(round(rec.rate / resolution))
    if b - a < 4 * n:
        raise MeasurementError(f"the chirp lasts {(b - a) / rec.rate:.3g} s, too short for {resolution:g} Hz "
                               f"resolution; record at least {4 * n / rec.rate:.3g} s")
    x, y = rec.travel[a:b], rec.force[a:b]
    kw = dict(fs=rec.rate, nperseg=n, noverlap=n // 2, window="hann", detrend="constant")
    f, Pxx = signal.welch(x, **kw)
    _, Pxy = signal.csd(x, y, **kw)
    _, coh = signal.coherence(x, y, **kw)
    return Stiffness(f, Pxy / np.where(Pxx > 0, Pxx, np.inf), coh, (b - a - n) // (n // 2) + 1)


def fit(rec: Record, scene, st: Stiffness | None = None) -> SiliconeFit:
    """s_E and eta from the force and travel records (module docstring)."""
    if rec.travel is None:
        raise MeasurementError("this record has no travel channel; record the actuator's travel "
                               "(a channel named travel with its sensitivity, e.g. \"1 V/mm\")")
    a, b = chirp_span(rec)
    pre = slice(0, max(1, a - int(0.05 * rec.rate)))
    d = rec.travel - np.median(rec.travel[pre])
    y = rec.force - np.median(rec.force[pre])
    n = 2 * len(d)
    f = np.fft.rfftfreq(n, 1 / rec.rate)
    D = np.fft.rfft(d, n)
    scale = float(np.std(y[a:b])) or 1.0

    def model(p):
        K = 1.0 / compliance(scaled_model(scene, np.exp(p[0]), np.exp(p[1])), f)
        return np.fft.irfft(D * K, n)[:len(d)]

    def resid(p):
        return (model(p)[a:b] + p[2] - y[a:b]) / scale

    eta0 = loss_factor(scaled_model(scene), scene)
    m1 = model([0.0, np.log(max(eta0, 1e-3))])[a:b]                # the start: s_E by linear regression
    X = np.column_stack([m1, np.ones(len(m1))])
    (s0, c0), *_ = np.linalg.lstsq(X, y[a:b], rcond=None)
    # differences of 1e-4 in the log parameters: the 6 x 6 solves of the stiff lumped model
    # (poles 1e3-1e10 rad/s) carry ~1e-9 relative noise, which a default 1e-8 step turns into the gradient
    res = optimize.least_squares(resid, [np.log(max(s0, 1e-3)), np.log(max(eta0, 1e-3)), c0], method="lm",
                                 diff_step=1e-4)
    s2 = 2 * res.cost / max(len(res.fun) - 3, 1)
    try:
        cov = s2 * np.linalg.inv(res.jac.T @ res.jac)
    except np.linalg.LinAlgError:
        cov = np.full((3, 3), np.inf)
    sig = np.sqrt(np.clip(np.diag(cov), 0, None))
    ci = [(float(np.exp(res.x[i] - 1.96 * sig[i])), float(np.exp(res.x[i] + 1.96 * sig[i]))) for i in range(2)]
    corr = float(cov[0, 1] / (sig[0] * sig[1])) if np.all(sig[:2] > 0) and np.all(np.isfinite(sig)) else float("nan")
    st = st or stiffness(rec)
    ok = (st.coherence > 0.99) & (st.freqs >= 10 * st.freqs[1])
    return SiliconeFit(float(np.exp(res.x[0])), ci[0], float(np.exp(res.x[1])), ci[1],
                       (float(st.freqs[ok].min()), float(st.freqs[ok].max())) if ok.any() else (0.0, 0.0),
                       float(100 * np.sqrt(np.mean(res.fun ** 2))), corr)


@dataclass
class Identifiability:
    names: list[str]
    sd_rel: np.ndarray             # (p,) Cramer-Rao relative standard deviation of each parameter
    correlation: np.ndarray        # (p, p)
    sensitivity: np.ndarray        # (p,) largest |d log H / d log theta| over the band

    def record(self) -> dict:
        return {"parameters": self.names, "cramer_rao_sd_pct": (100 * self.sd_rel).tolist(),
                "correlation": self.correlation.tolist(), "max_sensitivity": self.sensitivity.tolist()}


def identifiability(model, theta: dict, freqs, sigma) -> Identifiability:
    """Fisher information of log H(f; theta) (module docstring); model(freqs, **theta) -> complex H,
    theta positive parameters, sigma (scalar or per frequency) the relative error of H."""
    names = list(theta)
    x0 = np.log([theta[k] for k in names])
    h = 1e-3

    def logH(x):
        return np.log(model(freqs, **dict(zip(names, np.exp(x)))))
    cols = []
    for i in range(len(x0)):
        d = np.zeros(len(x0))
        d[i] = h
        cols.append((logH(x0 + d) - logH(x0 - d)) / (2 * h))
    J = np.array(cols).T                                            # (f, p) complex
    w = 1.0 / np.broadcast_to(np.asarray(sigma, float), (len(freqs),))
    Jr = np.vstack([J.real * w[:, None], J.imag * w[:, None]])
    cov = np.linalg.pinv(Jr.T @ Jr)
    sd = np.sqrt(np.clip(np.diag(cov), 0, None))
    corr = cov / np.outer(sd, sd) if np.all(sd > 0) else np.full_like(cov, np.nan)
    return Identifiability(names, sd, corr, np.abs(J).max(axis=0))
