"""Step response, linearity and repeatability of each taxel, from a measurement.

Definitions (t in s, v the taxel's conditioning output in V, F the load cell in N):

Step response: studies.measured.step (a first-order fit, robust to baseline drift).

Peaks. For each event (studies.measured.events) the force peak is the largest
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

from dataclasses import asdict, dataclass

import numpy as np
from scipy import stats

from taxel.studies.measured.events import Record, dehum, smooth
from taxel.studies.measured.step import StepFit, fit_step, step_model

__all__ = ["StepFit", "fit_step", "step_model", "Linearity", "Repeatability", "peaks", "linearity",
           "repeatability"]


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
