"""Readings of the taxels for localization: one value per taxel and press, the
sensitivities calibrated on some presses, the others scored.

Readings. A press's V_k is read at one time per taxel: a channel's own extreme
picks the largest excursion of its noise too, which inflates the small neighbour
signals that carry the position (by ~3 sigma, 10-15 % of a neighbour's 7 %
crosstalk at 1 mV). So V_k is the dehummed signal minus its median 15-60 ms
before the event, averaged over 5 ms around t50 + lag_k, t50 the time the force
reaches half its peak and lag_k the median delay of taxel k's own extreme after
t50 over its calibration presses (a linear functional of the signal: unbiased).

Sensitivities S_k (peak V per N pressed at taxel k's centre) are calibrated on
each taxel's 1st, 3rd, 5th, ... on-taxel press (the median of V_k / F_peak, divided
by G_r(y) G_c(x) at the press's known point when the influence functions are at
hand: an on-taxel press may be up to pitch / 8 off the centre; a taxel
with none gets the median of the others, so its gain spread becomes error); the estimators
(studies.measured.localize) are scored on every other press: each taxel's 2nd, 4th, ...
on-taxel press and every between-taxel press.
"""

from __future__ import annotations

import numpy as np

from taxel.studies.measured.events import Record, dehum


def amplitudes(rec: Record, matched, pitch_mm: float) -> list:
    """The matched presses with V_k read at one time per taxel (module docstring): unbiased by noise."""
    r = rec.rate
    volts = dehum(rec.volts, r)
    f = rec.smooth_force
    ms = lambda s: int(round(s * 1e-3 * r))                       # noqa: E731
    ref, base = [], []
    for p, F, v, (a, b) in matched:
        pa, pb = max(0, a - ms(60)), max(1, a - ms(15))
        level = np.median(rec.force[pa:pb])
        i50 = a + int(np.argmax(f[a:b] - level >= 0.5 * F)) if b > a else a
        ref.append(i50)
        base.append(np.median(volts[pa:pb], axis=0))
    k = len(rec.taxels)
    lags: dict[int, list[int]] = {}
    for i in _split_index(matched, pitch_mm):
        p, _, _, (a, b) = matched[i]
        j = rec.taxels.index(p.position)
        lo, hi = max(0, ref[i] - ms(15)), min(len(volts), min(b, a + ms(150)) + 1)
        lags.setdefault(j, []).append(lo + int(np.argmax(np.abs(volts[lo:hi, j] - base[i][j]))) - ref[i])
    lag = np.array([np.median(lags[j]) if j in lags else np.nan for j in range(k)])
    lag[~np.isfinite(lag)] = np.median(lag[np.isfinite(lag)]) if np.isfinite(lag).any() else 0
    lag = lag.astype(int)
    out = []
    for (p, F, _, seg), i50, b0 in zip(matched, ref, base):
        idx = np.clip(i50 + lag, ms(2), len(volts) - ms(2) - 1)
        v = np.array([volts[i - ms(2):i + ms(2) + 1, j].mean() for j, i in enumerate(idx)]) - b0
        out.append((p, F, v))
    return out


def reading_noise(noise_V: float, rate: float) -> float:
    """The white part of the noise on one V_k reading (a mean of the samples within 2 ms of its time):
    the per-sample noise over sqrt(samples); for the Cramer-Rao map of taxel.analyses.surface.localization."""
    return noise_V / np.sqrt(2 * int(round(2e-3 * rate)) + 1)


def _split_index(matched, pitch_mm: float) -> list[int]:
    """Indices of the calibration presses of _split."""
    seen, idx = {}, []
    for i, m in enumerate(matched):
        if m[0].on_taxel(pitch_mm):
            n = seen[m[0].position] = seen.get(m[0].position, -1) + 1
            if n % 2 == 0:
                idx.append(i)
    return idx


def _split(matched, pitch_mm: float):
    """(calibration, scored): each taxel's on-taxel presses alternate between the two, in time order,
    starting with calibration; every between-taxel press is scored."""
    cal, score, seen = [], [], {}
    for m in matched:
        if not m[0].on_taxel(pitch_mm):
            score.append(m)
            continue
        n = seen[m[0].position] = seen.get(m[0].position, -1) + 1
        (cal if n % 2 == 0 else score).append(m)
    return cal, score


def sensitivities(rec: Record, matched, pitch_mm: float, infl=None) -> np.ndarray:
    """S_k from each taxel's calibration presses, V_k / (F_peak G_r(y) G_c(x)) at the known point (G = 1
    without influence functions); a taxel without one gets the others' median."""
    ratios: dict[int, list[float]] = {}
    for p, f, v in _split(matched, pitch_mm)[0]:
        k = rec.taxels.index(p.position)
        g = 1.0
        if infl is not None:
            x, y = p.point_mm(pitch_mm)
            g = float(infl.at(1e-3 * y)[p.position[0]] * infl.at(1e-3 * x)[p.position[1]])
        ratios.setdefault(k, []).append(v[k] / (f * g))
    S = np.full(len(rec.taxels), np.nan)
    for k, r in ratios.items():
        S[k] = float(np.median(r))
    if np.isfinite(S).any():
        S[~np.isfinite(S)] = float(np.median(S[np.isfinite(S)]))
    return S


def scored(matched, pitch_mm: float):
    """The presses not used for calibration."""
    return _split(matched, pitch_mm)[1]
