"""A predicted localization accuracy map of a design, before anything is built.

For a press of force F at (x, y) the taxel peaks are modelled as in
studies.measured.localize, V_(r,c) = S F G_r(y) G_c(x) (S one sensitivity for every
taxel, V per N at its own centre; G the FEM's influence functions), plus white
noise of rms sigma on every peak. The Cramer-Rao bound of an unbiased estimate of
(x, y, F) is the inverse Fisher information, cov = sigma^2 (J^T J)^-1 with
J = dV/d(x, y, F) (central differences, h = pitch / 1000); the map is the
predicted position error sqrt(cov_xx + cov_yy) in mm over a grid of press
positions (every pitch / 8 over the taxels' span) and the force error
100 % x sqrt(cov_FF) / F. It ignores the estimator's bounds and bias (which is
why presses far from any taxel can do worse than predicted) and any gain spread.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from taxel.analyses.surface.influence import Influence


@dataclass
class AccuracyMap:
    x_mm: np.ndarray
    y_mm: np.ndarray
    position_error_mm: np.ndarray    # (ny, nx)
    force_error_pct: np.ndarray      # (ny, nx)
    noise_V: float
    sensitivity_V_per_N: float
    force_N: float

    def at_taxels(self, pitch_mm: float) -> np.ndarray:
        """The predicted position errors at the taxel centres."""
        ix = [int(np.argmin(np.abs(self.x_mm - c * pitch_mm))) for c in range(int(round(self.x_mm.max() / pitch_mm)) + 1)]
        iy = [int(np.argmin(np.abs(self.y_mm - r * pitch_mm))) for r in range(int(round(self.y_mm.max() / pitch_mm)) + 1)]
        return self.position_error_mm[np.ix_(iy, ix)]

    def record(self) -> dict:
        return {"x_mm": self.x_mm.tolist(), "y_mm": self.y_mm.tolist(),
                "position_error_mm": self.position_error_mm.tolist(), "force_error_pct": self.force_error_pct.tolist(),
                "noise_V": self.noise_V, "sensitivity_V_per_N": self.sensitivity_V_per_N, "force_N": self.force_N}


def peaks_model(infl: Influence, rows: int, cols: int, S: float, p) -> np.ndarray:
    """(rows * cols,) modelled peaks for press p = (x, y, F), taxels in row-major order."""
    gx, gy = infl.at(p[0]), infl.at(p[1])
    return S * p[2] * np.outer(gy[:rows], gx[:cols]).ravel()


def accuracy_map(infl: Influence, rows: int, cols: int, sensitivity: float, noise_V: float,
                 force: float = 1.0) -> AccuracyMap:
    """The Cramer-Rao map (module docstring)."""
    xs = np.arange(0, 8 * (cols - 1) + 1) * infl.pitch / 8
    ys = np.arange(0, 8 * (rows - 1) + 1) * infl.pitch / 8
    h = infl.pitch / 1000
    pos = np.full((len(ys), len(xs)), np.nan)
    frc = np.full((len(ys), len(xs)), np.nan)
    for i, y in enumerate(ys):
        for j, x in enumerate(xs):
            p = np.array([x, y, force])
            J = np.column_stack([(peaks_model(infl, rows, cols, sensitivity, p + d) -
                                  peaks_model(infl, rows, cols, sensitivity, p - d)) / (2 * d.sum())
                                 for d in (np.array([h, 0, 0]), np.array([0, h, 0]), np.array([0, 0, force * 1e-3]))])
            try:
                cov = noise_V ** 2 * np.linalg.inv(J.T @ J)
            except np.linalg.LinAlgError:
                continue
            pos[i, j] = 1e3 * np.sqrt(max(cov[0, 0] + cov[1, 1], 0.0))
            frc[i, j] = 100 * np.sqrt(max(cov[2, 2], 0.0)) / force
    return AccuracyMap(1e3 * xs, 1e3 * ys, pos, frc, noise_V, sensitivity, force)


NOISE_V = 1e-3      # the simulated thesis bench's white noise at the ADC (studies.bench.signals.Settings)


@dataclass
class LocalizationError:
    """The design metric localization_error (localization_error below)."""
    rms_m: float                 # rms over the map of the predicted position error
    max_m: float
    sensitivity_V_per_N: float
    solves: int                  # static FEM solves it took (0: all cached)


def localization_error(scene, noise_V: float = NOISE_V, solve=None, per_pitch: int = 8,
                       force: float | None = None) -> LocalizationError:
    """The predicted position error of a design, a metric for the optimizer.

    The influence functions over the taxels' span (taxel.analyses.surface.influence, every
    pitch / per_pitch, no margins, mirror symmetry: 9 static solves for a 3-taxel row at per_pitch 8, against
    17 without the mirror; coarser sampling is cheaper but puts the bound 0.7-9 x off), then
    `localization_error_of`. benchmarks/measure_influence_cost.py measures the solves and the error of
    per_pitch 2 and 4 against 8. `solve` (scene -> {electrode: V}) lets the optimizer keep every
    press position in a study store."""
    from taxel.analyses.surface.influence import influence
    arr = scene.array
    if arr is None or arr.cols < 2:
        raise ValueError("localization_error needs a taxel array with at least two columns")
    return localization_error_of(influence(scene, per_pitch=per_pitch, edges=False, solve=solve), scene, noise_V,
                                 force)


def localization_error_of(infl: Influence, scene, noise_V: float = NOISE_V,
                          force: float | None = None) -> LocalizationError:
    """The Cramer-Rao map above of the influence functions `infl` (every pitch / 8 over the
    taxels, white noise noise_V on every peak, S the mean open-circuit sensitivity of the
    row's taxels pressed at their centres) at `force` (default the scene's load.force; the
    error scales as 1 / force), and its rms over the map in m. It compares designs on the
    peaks' open-circuit voltage, as the sensitivity metric does: a readout chain's gain
    scales signal and the noise referred to its input alike only if the noise is the
    chain's own."""
    arr = scene.array
    S = float(np.mean(np.abs(infl.sensitivity)))
    F = float(force if force is not None else (scene.load.force or 1.0))
    amap = accuracy_map(infl, min(arr.rows, arr.cols), arr.cols, S, noise_V, F)    # separable: rows take G of the row
    e = amap.position_error_mm[np.isfinite(amap.position_error_mm)]
    if not len(e):
        raise ValueError("the Cramer-Rao map is singular everywhere: the taxels' voltages do not depend on position")
    return LocalizationError(float(1e-3 * np.sqrt(np.mean(e ** 2))), float(1e-3 * e.max()), S, infl.solves)
