"""Step response, linearity and repeatability of each taxel, from a measurement.

Definitions (t in s, v the taxel's conditioning output in V, F the load cell in N):

Step response (first-order model). A first-order chain (a resistor R across the
taxel's capacitance C_p, tau = R C_p; or a charge amplifier, tau = R_f C_f) answers
a force step F0 at t0 with
    v(t) = b + A F0 exp(-(t - t0) / tau),
the step response of the high-pass A s tau / (1 + s tau). The fitted model drives
that high-pass (bilinear, at the rig's rate) with the *measured* force minus its
initial level, so the actuator's finite rise is in the model, then the rig's
notch when its chain has one, and adds a baseline b + c (t - t0) for slow drift:
    v_model = b + c (t - t0) + notch(HP_tau(A (F - F_0))).
A, tau, b, c are fitted by nonlinear least squares (scipy.optimize.least_squares,
tau as log tau) over the record from 0.1 s before the step to its end. The 95 %
interval of tau is log tau +- 1.96 sigma, sigma^2 the (log tau, log tau) entry of
s^2 (J^T J)^-1 with J the Jacobian at the optimum and s^2 = sum(r^2) / (n - 4).
This assumes white residuals; hum and drift are not white, so the interval is a
lower bound of the true uncertainty (the tests compare with known truth instead).
R_eff = tau / C_p (resistor or open chains; C_p from the scene's lumped model);
for a charge amplifier R_f,eff = tau / C_f.

Peaks. For each event (studies.measure.events) the force peak is the largest
2 ms-averaged force above its level 15-60 ms before the event; a taxel's peak is,
after the mains hum is filtered out (events.dehum: zero-phase notches at 50, 150
and 250 Hz, applied alike to any signal compared with), its signed extreme (largest |v - baseline|, baseline the median 15-60 ms before)
from 15 ms before the event to 150 ms after its start (or its end, if sooner).
The event is assigned to the taxel with the largest |peak|.

Linearity (presses of different force): per taxel, the ordinary least-squares
line peak_v = S F_peak + v_0 over the presses assigned to it; S is the
sensitivity (V/N), R Pearson's correlation coefficient of (F_peak, peak_v), the
residuals peak_v - (S F_peak + v_0).

Repeatability (repeated impulses of nominally equal force), both common
definitions, on the |peak| voltages p_i of the pressed taxel (the thesis does
not say which it used):
    by spread:  100 % x (1 - std(p) / mean(p))        (std with n - 1)
    by range:   100 % x (1 - (max(p) - min(p)) / mean(p)).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

import numpy as np
from scipy import optimize, signal, stats

from taxel.studies.measure.events import Record, dehum, segments, smooth
from taxel.studies.measure.folder import MeasurementError
from taxel.studies.measure.rig import Conditioning


@dataclass
class StepFit:
    taxel: str
    tau_s: float
    tau_ci95_s: tuple[float, float]
    amplitude_V_per_N: float          # A: the chain's high-frequency gain per newton
    step_N: float                     # F0
    rms_residual_V: float
    R_eff_ohm: float | None = None    # tau / C_p (resistor or open chain, with a scene)
    R_f_eff_ohm: float | None = None  # tau / C_f (charge amplifier)
    fit: dict = field(default_factory=dict, repr=False)   # t0, b, c, window for plots

    def record(self) -> dict:
        return asdict(self)


@dataclass
class Linearity:
    taxel: str
    sensitivity_V_per_N: float
    intercept_V: float
    r: float
    n: int
    forces_N: list[float]
    peaks_V: list[float]
    residuals_V: list[float]

    def record(self) -> dict:
        return asdict(self)


@dataclass
class Repeatability:
    taxel: str
    n: int
    peaks_V: list[float]
    forces_N: list[float]
    mean_V: float
    std_V: float
    by_spread_pct: float              # 100 (1 - std / mean)
    by_range_pct: float               # 100 (1 - (max - min) / mean)
    force_by_spread_pct: float        # the same for the force peaks (the input's own spread)

    def record(self) -> dict:
        return asdict(self)


def _hp_notch(x: np.ndarray, tau: float, rate: float, cond: Conditioning | None) -> np.ndarray:
    b, a = signal.bilinear([tau, 0.0], [tau, 1.0], fs=rate)
    y = signal.lfilter(b, a, x)
    if cond is not None and cond.notch:
        lo, hi = cond.notch_frequency - cond.notch_bandwidth / 2, cond.notch_frequency + cond.notch_bandwidth / 2
        y = signal.sosfilt(signal.iirfilter(1, [lo, hi], btype="bandstop", ftype="butter", fs=rate, output="sos"), y)
    return y


def fit_step(rec: Record, k: int, cond: Conditioning | None, C_p: float | None = None) -> StepFit:
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

    def model(p):
        A, ltau, b, c = p
        return b + c * t[lo:] + A * _hp_notch(F, np.exp(ltau), rec.rate, cond)[lo:]

    def resid(p):
        return model(p) - v[lo:]

    p0 = np.array([A0, np.log(tau0), float(np.median(v[:max(1, lo)])), 0.0])
    res = optimize.least_squares(resid, p0, x_scale=np.array([abs(A0) or 1.0, 1.0, 0.01, 0.01]), method="lm")
    n, p = len(res.fun), len(res.x)
    s2 = 2 * res.cost / max(n - p, 1)
    try:
        cov = s2 * np.linalg.inv(res.jac.T @ res.jac)
        sig = float(np.sqrt(max(cov[1, 1], 0.0)))
    except np.linalg.LinAlgError:
        sig = float("inf")
    A, ltau, b, c = res.x
    tau = float(np.exp(ltau))
    out = StepFit(rec.names[k], tau, (float(np.exp(ltau - 1.96 * sig)), float(np.exp(ltau + 1.96 * sig))),
                  float(A), F0, float(np.sqrt(s2)),
                  fit={"t0_s": float(rec.t[i0]), "b_V": float(b), "c_V_per_s": float(c), "from_s": float(rec.t[lo])})
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


def peaks(rec: Record, segs: list[tuple[int, int]]) -> tuple[np.ndarray, np.ndarray]:
    """(force peaks (E,), signed taxel peaks (E, k)) of each event (module docstring)."""
    r = rec.rate
    fs = smooth(rec.force, max(1, int(round(2e-3 * r))))
    volts = dehum(rec.volts, r)
    Fp, Vp = [], []
    for a, b in segs:
        pa, pb = max(0, a - int(0.06 * r)), max(1, a - int(0.015 * r))
        if pb <= pa:
            continue
        Fp.append(fs[a:b].max() - np.median(rec.force[pa:pb]))
        base = np.median(volts[pa:pb], axis=0)
        w = volts[pb:min(b, a + int(0.15 * r)) + 1] - base
        j = np.argmax(np.abs(w), axis=0)
        Vp.append(w[j, np.arange(w.shape[1])])
    return np.array(Fp), np.array(Vp).reshape(len(Fp), rec.volts.shape[1])


def linearity(rec: Record, segs: list[tuple[int, int]], min_presses: int = 3) -> list[Linearity]:
    """Per taxel with at least `min_presses` presses assigned to it."""
    Fp, Vp = peaks(rec, segs)
    who = np.argmax(np.abs(Vp), axis=1) if len(Vp) else np.array([], int)
    out = []
    for k in range(len(rec.names)):
        sel = who == k
        if sel.sum() < min_presses:
            continue
        f, v = Fp[sel], Vp[sel, k]
        fit = stats.linregress(f, v)
        out.append(Linearity(rec.names[k], float(fit.slope), float(fit.intercept), float(fit.rvalue), int(sel.sum()),
                             f.tolist(), v.tolist(), (v - (fit.slope * f + fit.intercept)).tolist()))
    return out


def repeatability(rec: Record, segs: list[tuple[int, int]]) -> list[Repeatability]:
    """Per taxel that was the largest in at least two impulses."""
    Fp, Vp = peaks(rec, segs)
    who = np.argmax(np.abs(Vp), axis=1) if len(Vp) else np.array([], int)
    out = []
    for k in range(len(rec.names)):
        sel = who == k
        if sel.sum() < 2:
            continue
        p, f = np.abs(Vp[sel, k]), Fp[sel]
        m, s = float(p.mean()), float(p.std(ddof=1))
        out.append(Repeatability(rec.names[k], int(sel.sum()), p.tolist(), f.tolist(), m, s,
                                 100 * (1 - s / m), 100 * (1 - (p.max() - p.min()) / m),
                                 100 * (1 - f.std(ddof=1) / f.mean())))
    return out
