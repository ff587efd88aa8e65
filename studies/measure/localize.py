"""Which taxel was pressed: the thesis's largest-taxel method, against known presses.

Presses at known positions come from a JSON file: a list (or {"presses": [...]})
of {"t": s, "position": [row, col]}; the simulator's truth.json (positions as
indices into its "positions") is read as such. Each known press is matched to
the loading event on the force channel (studies.measure.events) that starts
within `window_s` after its time (a press the force channel did not see is
"missed"). Its taxel peaks are those of studies.measure.analyze.peaks.

Largest-taxel estimator: the press is on the taxel whose |peak| is largest.
Confusion matrix C[i, j]: presses on taxel i estimated on taxel j (rows the
rig's taxel channels in order); correct rate = trace(C) / number of matched presses.

Model-based estimator: position (x, y) and force F of a press from all the taxel
peaks V_k, by least squares (scipy.optimize.least_squares) of
    V_(r,c) = S_(r,c) F G_r(y) G_c(x),
G the FEM's influence functions (studies.measure.influence), S_k each taxel's
sensitivity (peak V per N pressed at its centre), started at the largest taxel
and kept within half a pitch of it (else, at low signal-to-noise, the fit
escapes into a gap, where G is small, with a large force).
S_k is calibrated on the even-numbered known presses (the median of V_k / F_peak
over the presses on taxel k) and the estimator is scored on the odd-numbered
ones: position error = |(x, y) - press position| in mm, force error =
100 % x (F - F_peak) / F_peak with F_peak the load cell's.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy import optimize

from taxel.studies.measure.analyze import peaks
from taxel.studies.measure.events import Record, record, segments
from taxel.studies.measure.folder import MeasurementError, read, write_json

JSON = "localization.json"


@dataclass
class Localization:
    taxels: list[str]
    confusion: np.ndarray          # (k, k) counts
    correct_rate: float            # over the matched presses
    matched: int
    missed: int
    truth: list[int]               # per matched press: index of the pressed taxel
    estimate: list[int]

    def record(self) -> dict:
        return {"method": "largest taxel", "taxels": self.taxels, "confusion": self.confusion.tolist(),
                "correct_rate": self.correct_rate, "matched": self.matched, "missed": self.missed,
                "truth": self.truth, "estimate": self.estimate}

    def summary(self) -> list[str]:
        return [f"largest taxel: {100 * self.correct_rate:.1f} % correct over {self.matched} presses "
                f"({self.missed} not seen on the force channel)"]

    def write(self, folder: Path, model: "ModelBased | None" = None) -> Path:
        rec = self.record()
        if model is not None:
            rec["model_based"] = model.record()
        write_json(Path(folder) / JSON, rec)
        return Path(folder) / JSON


def read_presses(path) -> list[tuple[float, tuple[int, int]]]:
    """(t, (row, col)) of each known press; one-line MeasurementError otherwise."""
    path = Path(path)
    try:
        data = json.loads(path.read_text())
    except OSError:
        raise MeasurementError(f"{path}: no such presses file; give a JSON list of {{t, position: [row, col]}} "
                               "or the simulator's truth.json") from None
    except json.JSONDecodeError as exc:
        raise MeasurementError(f"{path}: not JSON ({exc.msg} at line {exc.lineno}); fix the file") from None
    positions = data.get("positions") if isinstance(data, dict) else None
    items = data.get("presses") if isinstance(data, dict) else data
    if not isinstance(items, list) or not items:
        raise MeasurementError(f"{path}: no presses; give a list of {{t, position: [row, col]}} (or {{presses: [...]}})")
    out = []
    for i, p in enumerate(items):
        try:
            pos = p["position"]
            if isinstance(pos, int):
                pos = positions[pos]
            out.append((float(p["t"]), (int(pos[0]), int(pos[1]))))
        except (KeyError, TypeError, IndexError, ValueError):
            raise MeasurementError(f"{path}: press {i} needs t (s) and position [row, col]; fix that entry") from None
    return out


def largest_taxel(rec: Record, presses: list[tuple[float, tuple[int, int]]], window_s: float = 0.1) -> Localization:
    """The largest-taxel estimator's confusion matrix (module docstring)."""
    segs = segments(rec)
    starts = np.array([a for a, _ in segs]) / rec.rate
    _, Vp = peaks(rec, segs)
    k = len(rec.taxels)
    C = np.zeros((k, k), int)
    truth, est, missed = [], [], 0
    for t, pos in presses:
        if pos not in rec.taxels:
            raise MeasurementError(f"press at {t:g} s on taxel {list(pos)}: the rig has no channel "
                                   f"taxel_{pos[0]}_{pos[1]}; fix the presses file or the rig")
        j = np.flatnonzero((starts >= t - 1e-3) & (starts <= t + window_s))
        if not len(j):
            missed += 1
            continue
        i, e = rec.taxels.index(pos), int(np.argmax(np.abs(Vp[j[0]])))
        C[i, e] += 1
        truth.append(i)
        est.append(e)
    n = int(C.sum())
    return Localization(list(rec.names), C, float(np.trace(C) / n) if n else 0.0, n, missed, truth, est)


@dataclass
class ModelBased:
    position_error_mm: list[float]     # per scored press
    force_error_pct: list[float]
    estimates_mm: list[list[float]]    # (x, y) per scored press, from taxel_0_0's centre
    truth_mm: list[list[float]]
    sensitivity_V_per_N: dict

    def record(self) -> dict:
        e, f = np.array(self.position_error_mm), np.abs(self.force_error_pct)
        return {"method": "model-based (FEM influence functions)", "presses": len(e),
                "position_error_mm": {"rms": float(np.sqrt(np.mean(e ** 2))), "max": float(e.max()),
                                      "median": float(np.median(e))},
                "force_error_pct": {"rms": float(np.sqrt(np.mean(f ** 2))), "max": float(f.max())},
                "per_press": {"error_mm": self.position_error_mm, "force_error_pct": self.force_error_pct,
                              "estimate_mm": self.estimates_mm, "truth_mm": self.truth_mm},
                "sensitivity_V_per_N": self.sensitivity_V_per_N}

    def summary(self) -> list[str]:
        r = self.record()
        return [f"model-based: position error {r['position_error_mm']['rms']:.3g} mm rms "
                f"({r['position_error_mm']['max']:.3g} max), force {r['force_error_pct']['rms']:.3g} % rms "
                f"over {r['presses']} presses (sensitivities from the other {len(self.sensitivity_V_per_N)} taxels' "
                "calibration presses)"]


def model_based(rec: Record, presses: list[tuple[float, tuple[int, int]]], infl, window_s: float = 0.1) -> ModelBased:
    """The model-based estimator, calibrated on even presses and scored on odd ones (module docstring)."""
    if max(r for r, _ in rec.taxels) >= infl.n or max(c for _, c in rec.taxels) >= infl.n:
        raise MeasurementError("the influence functions cover fewer taxels than the rig has; "
                               "give the scene of the measured array")
    segs = segments(rec)
    starts = np.array([a for a, _ in segs]) / rec.rate
    Fp, Vp = peaks(rec, segs)
    matched = []
    for t, pos in presses:
        j = np.flatnonzero((starts >= t - 1e-3) & (starts <= t + window_s))
        if len(j) and pos in rec.taxels:
            matched.append((pos, Fp[j[0]], Vp[j[0]]))
    ratios: dict[int, list[float]] = {}
    for pos, f, v in matched[0::2]:
        k = rec.taxels.index(pos)
        ratios.setdefault(k, []).append(v[k] / f)
    S = np.full(len(rec.taxels), np.nan)
    for k, r in ratios.items():
        S[k] = float(np.median(r))
    rows = np.array([r for r, _ in rec.taxels])
    cols = np.array([c for _, c in rec.taxels])
    ok = np.isfinite(S)
    errs, ferr, est, tru = [], [], [], []
    for pos, f, v in matched[1::2]:
        if not ok[rec.taxels.index(pos)]:
            continue
        k0 = int(np.argmax(np.where(ok, np.abs(v), -1)))

        def resid(p):
            gx, gy = infl.at(p[0]), infl.at(p[1])
            return (S[ok] * p[2] * gy[rows[ok]] * gx[cols[ok]] - v[ok]) / np.abs(v[ok]).max()
        p0 = [cols[k0] * infl.pitch, rows[k0] * infl.pitch, max(v[k0] / S[k0], 1e-3 * f)]
        h = infl.pitch / 2                     # within half a pitch of the largest taxel (on it, or between it and a neighbour)
        lo = [max(infl.x[0], p0[0] - h), max(infl.x[0], p0[1] - h), 0.0]
        hi = [min(infl.x[-1], p0[0] + h), min(infl.x[-1], p0[1] + h), np.inf]
        res = optimize.least_squares(resid, p0, bounds=(lo, hi),
                                     x_scale=[infl.pitch / 4, infl.pitch / 4, abs(p0[2]) or 1.0])
        x, y, F = res.x
        tx, ty = pos[1] * infl.pitch, pos[0] * infl.pitch
        errs.append(float(1e3 * np.hypot(x - tx, y - ty)))
        ferr.append(float(100 * (F - f) / f))
        est.append([float(1e3 * x), float(1e3 * y)])
        tru.append([float(1e3 * tx), float(1e3 * ty)])
    if not errs:
        raise MeasurementError("too few known presses to calibrate and score the model-based estimator; "
                               "press every taxel at least twice")
    return ModelBased(errs, ferr, est, tru, {rec.names[k]: float(S[k]) for k in range(len(S)) if ok[k]})


def localize_folder(folder, presses_file, scene=None):
    """(largest-taxel Localization, ModelBased or None without a scene)."""
    m = read(folder)
    rec, presses = record(m), read_presses(presses_file)
    loc = largest_taxel(rec, presses)
    mb = None
    if scene is not None:
        from taxel.studies.measure.influence import influence
        mb = model_based(rec, presses, influence(scene))
    return loc, mb
