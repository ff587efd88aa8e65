"""Where was the array pressed, and how hard: the thesis's largest-taxel method and a
model-based estimator, against known presses, on and between taxels.

Known presses come from a JSON file: a list (or {"presses": [...]}) of
{"t": s, "position": [row, col]} with, optionally, "xy_mm": [x, y], the press's
point in mm from taxel_0_0's centre (x along the columns, y along the rows);
without it the press is on its taxel's centre. The simulator's truth.json
(positions as indices into its "positions") is read as such. A press is "on" a
taxel when its point is within pitch / 8 of the taxel's centre in x and y, else
"between" (in a gap or at a corner inside the outer taxels' centres) or "edge"
(beyond them, over the margin); `position` is then the taxel it is nearest to. Each known press is matched to the loading event on the
force channel (studies.measured.events) that starts within `window_s` after its
time (a press the force channel did not see is "missed"); F_peak is its load-cell
peak (studies.measured.peaks.peaks). The confusion matrix takes the taxel peaks of
studies.measured.peaks.peaks (each channel's own extreme). The position and force
estimates take the readings V_k of studies.measured.readings instead.

Each taxel's sensitivity S_k is calibrated on some of the on-taxel presses and both
estimators are scored on the others (studies.measured.readings), separately for on-
and between-taxel presses:
  position error = |(x, y) - press point| in mm,
  force error    = 100 % x (F - F_peak) / F_peak.

Largest-taxel estimator (the thesis's): the press is on the taxel k whose |V_k| is
largest; its point is k's centre and its force V_k / S_k. Confusion matrix C[i, j]:
presses on taxel i (its nearest taxel for a between press) estimated on taxel j
(rows the rig's taxel channels in order), on-taxel presses and between-taxel
presses apart; correct rate = trace(C) / presses, over the on-taxel presses.

Model-based estimator: (x, y, F) by least squares of
    V_(r,c) = S_(r,c) F G_r(y) G_c(x),
G the FEM's influence functions (taxel.analyses.surface.influence). The influence
functions change sign in the gaps (a press there lifts both neighbours), so the
fit has distant local minima and a start at the largest taxel can end in the
wrong gap: the fit first scans a grid every pitch / 16 over the taxels' span,
with the best force F >= 0 in closed form at each point (V is linear in F), then
refines the four lowest local minima of that scan by scipy.optimize.least_squares,
each within pitch / 8 of its grid point, and keeps the lowest. Some points stay
ambiguous: near a neighbour's zero of G (about 2.8 mm from a taxel centre in the
thesis array) a press at a corner between four taxels and its mirror image across
the array give peaks within 1 mV of each other (measured on the simulated rig), so
at the bench's noise an occasional between-taxel press lands at its mirror image:
the scores give the median and 90th percentile beside the rms.

The search stays within the taxels' span (the outer taxels' centres): beyond an
outer taxel every taxel's signal is nearly that of a press on it with less force
(G_c(x) ~ a(x) G_c(0) there: for the thesis array a press 0.5-1.7 mm beyond the edge
taxel, with the force that gives the same peak on it, differs from one on it by at
most 6 mV of a 0.4 V peak, tests/test_measure_analyze.py), and at the bench's noise a
search over the margins too sends on-taxel presses there (on the simulated rig at
1 mV: 1.3 mm rms on the taxels, force 93 % off, against 0.18 mm and 4 % within the
span; benchmarks/measure_localization_noise.py uses the latter). So with the force
unknown the nine voltages cannot place it; such presses ("edge") are estimated at the edge.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy import ndimage, optimize

from taxel.studies.measured.peaks import peaks
from taxel.studies.measured.events import Record, record, segments
from taxel.studies.bench.folder import MeasurementError, read, write_json
from taxel.studies.measured.readings import amplitudes, reading_noise, scored, sensitivities
from taxel.schema import electrode_name

JSON = "localization.json"
__all__ = ["PressEvent", "Scores", "Localization", "read_presses", "match", "largest_taxel", "model_based", "fit_press",
           "localize_folder", "amplitudes", "reading_noise", "scored", "sensitivities"]
CLASSES = ("on", "between", "edge")


@dataclass(frozen=True)
class PressEvent:
    t: float
    position: tuple[int, int]                  # the pressed (or nearest) taxel
    xy_mm: tuple[float, float] | None = None   # the press point; None: the taxel's centre

    def point_mm(self, pitch_mm: float) -> tuple[float, float]:
        return self.xy_mm if self.xy_mm is not None else (self.position[1] * pitch_mm, self.position[0] * pitch_mm)

    def on_taxel(self, pitch_mm: float | None) -> bool:
        if self.xy_mm is None or pitch_mm is None:
            return True
        x, y = self.xy_mm
        return abs(x - self.position[1] * pitch_mm) <= pitch_mm / 8 and abs(y - self.position[0] * pitch_mm) <= pitch_mm / 8


def as_press(p) -> PressEvent:
    return p if isinstance(p, PressEvent) else PressEvent(float(p[0]), tuple(p[1]))


@dataclass
class Scores:
    """Position and force errors of one estimator over one class of presses."""
    position_error_mm: list[float] = field(default_factory=list)
    force_error_pct: list[float] = field(default_factory=list)
    estimates_mm: list[list[float]] = field(default_factory=list)
    truth_mm: list[list[float]] = field(default_factory=list)

    def add(self, est_xy, true_xy, F, f):
        self.position_error_mm.append(float(np.hypot(est_xy[0] - true_xy[0], est_xy[1] - true_xy[1])))
        self.force_error_pct.append(float(100 * (F - f) / f))
        self.estimates_mm.append([float(est_xy[0]), float(est_xy[1])])
        self.truth_mm.append([float(true_xy[0]), float(true_xy[1])])

    @classmethod
    def from_record(cls, rec: dict) -> Scores:
        """The scores of their `record()`."""
        pp = rec.get("per_press") or {}
        return cls(list(pp.get("error_mm", [])), list(pp.get("force_error_pct", [])),
                   list(pp.get("estimate_mm", [])), list(pp.get("truth_mm", [])))

    def record(self) -> dict:
        e, f = np.array(self.position_error_mm), np.abs(self.force_error_pct)
        if not len(e):
            return {"presses": 0}
        return {"presses": len(e),
                "position_error_mm": {"rms": float(np.sqrt(np.mean(e ** 2))), "max": float(e.max()),
                                      "median": float(np.median(e)), "p90": float(np.percentile(e, 90))},
                "force_error_pct": {"rms": float(np.sqrt(np.mean(f ** 2))), "max": float(f.max())},
                "per_press": {"error_mm": self.position_error_mm, "force_error_pct": self.force_error_pct,
                              "estimate_mm": self.estimates_mm, "truth_mm": self.truth_mm}}


@dataclass
class Localization:
    taxels: list[str]
    confusion: np.ndarray          # (k, k) counts, on-taxel presses
    correct_rate: float            # over the matched on-taxel presses
    matched: int
    missed: int
    truth: list[int]               # per matched on-taxel press: index of the pressed taxel
    estimate: list[int]
    confusion_between: np.ndarray | None = None    # (k, k): nearest taxel vs largest, between-taxel presses
    largest: dict[str, Scores] = field(default_factory=dict)   # class -> scores (with a pitch)
    model: dict[str, Scores] = field(default_factory=dict)     # class -> scores (with a scene)
    sensitivity_V_per_N: dict = field(default_factory=dict)

    def record(self) -> dict:
        rec = {"method": "largest taxel", "taxels": self.taxels, "confusion": self.confusion.tolist(),
               "correct_rate": self.correct_rate, "matched": self.matched, "missed": self.missed,
               "truth": self.truth, "estimate": self.estimate}
        if self.confusion_between is not None:
            rec["confusion_between"] = self.confusion_between.tolist()
        if self.largest:
            rec["largest_taxel"] = {c: s.record() for c, s in self.largest.items()}
        if self.model:
            on = self.model.get("on", Scores()).record()
            rec["model_based"] = {"method": "model-based (FEM influence functions)", **on,
                                  "between": self.model.get("between", Scores()).record(),
                                  "edge": self.model.get("edge", Scores()).record(),
                                  "sensitivity_V_per_N": self.sensitivity_V_per_N}
        return rec

    def summary(self) -> list[str]:
        lines = [f"largest taxel: {100 * self.correct_rate:.1f} % correct over {self.matched} on-taxel presses "
                 f"({self.missed} not seen on the force channel)"]
        for name, scores in (("largest taxel", self.largest), ("model-based", self.model)):
            for c in CLASSES:
                r = scores.get(c, Scores()).record()
                if r["presses"]:
                    where = {"on": "on taxels", "between": "between taxels", "edge": "beyond the outer taxels"}[c]
                    lines.append(f"{name}, {where}: position error {r['position_error_mm']['rms']:.3g} mm rms "
                                 f"({r['position_error_mm']['max']:.3g} max), force {r['force_error_pct']['rms']:.3g} "
                                 f"% rms over {r['presses']} presses")
        return lines

    def write(self, folder: str | Path) -> Path:
        """localization.json in `folder` (`to_folder`)."""
        return self.to_folder(folder)

    def to_folder(self, folder: str | Path) -> Path:
        """localization.json in `folder`; returns its path."""
        write_json(Path(folder) / JSON, self.record())
        return Path(folder) / JSON

    @classmethod
    def read(cls, folder: str | Path) -> Localization:
        """The localization written in `folder` (localization.json); one-line MeasurementError if none."""
        try:
            rec = json.loads((Path(folder) / JSON).read_text())
        except (OSError, ValueError):
            raise MeasurementError(f"{folder}: no readable {JSON}; run 'taxel measure localize {folder}' first") from None
        mb = rec.get("model_based")
        model = {} if mb is None else {"on": Scores.from_record(mb), "between": Scores.from_record(mb["between"]),
                                       "edge": Scores.from_record(mb["edge"])}
        between = rec.get("confusion_between")
        return cls(rec["taxels"], np.array(rec["confusion"], int), rec["correct_rate"], rec["matched"], rec["missed"],
                   rec["truth"], rec["estimate"], None if between is None else np.array(between, int),
                   {c: Scores.from_record(r) for c, r in rec.get("largest_taxel", {}).items()}, model,
                   mb["sensitivity_V_per_N"] if mb is not None else {})


def read_presses(path) -> list[PressEvent]:
    """The known presses; one-line MeasurementError otherwise."""
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
            xy = p.get("xy_mm")
            xy = None if xy is None else (float(xy[0]), float(xy[1]))
            if xy is not None and not all(np.isfinite(xy)):
                raise ValueError
            out.append(PressEvent(float(p["t"]), (int(pos[0]), int(pos[1])), xy))
        except (KeyError, TypeError, IndexError, ValueError):
            raise MeasurementError(f"{path}: press {i} needs t (s), position [row, col] and optionally "
                                   "xy_mm [x, y] (finite numbers); fix that entry") from None
    return out


def match(rec: Record, presses, window_s: float = 0.1, with_segments: bool = False):
    """(matched [(PressEvent, F_peak, V (k,))], missed) of the known presses; with_segments adds each
    press's event (start, stop) as a fourth item."""
    segs = segments(rec)
    starts = np.array([a for a, _ in segs]) / rec.rate
    Fp, Vp = peaks(rec, segs)
    out, missed = [], 0
    for p in map(as_press, presses):
        if p.position not in rec.taxels:
            raise MeasurementError(f"press at {p.t:g} s on taxel {list(p.position)}: the rig has no channel "
                                   f"{electrode_name(*p.position)}; fix the presses file or the rig")
        j = np.flatnonzero((starts >= p.t - 1e-3) & (starts <= p.t + window_s))
        if not len(j):
            missed += 1
            continue
        out.append((p, float(Fp[j[0]]), Vp[j[0]]) + ((segs[j[0]],) if with_segments else ()))
    return out, missed


def largest_taxel(rec: Record, presses, window_s: float = 0.1, pitch_mm: float | None = None) -> Localization:
    """The largest-taxel estimator (module docstring); with the pitch also its position and force errors."""
    matched, missed = match(rec, presses, window_s)
    k = len(rec.taxels)
    C, Cb = np.zeros((k, k), int), np.zeros((k, k), int)
    truth, est = [], []
    for p, _, v in matched:
        i, e = rec.taxels.index(p.position), int(np.argmax(np.abs(v)))
        if p.on_taxel(pitch_mm):
            C[i, e] += 1
            truth.append(i)
            est.append(e)
        else:
            Cb[i, e] += 1
    n = int(C.sum())
    loc = Localization(list(rec.names), C, float(np.trace(C) / n) if n else 0.0, n, missed, truth, est,
                       Cb if Cb.any() else None)
    if pitch_mm is not None:
        matched = amplitudes(rec, match(rec, presses, window_s, True)[0], pitch_mm)
        S = sensitivities(rec, matched, pitch_mm)
        loc.sensitivity_V_per_N = {rec.names[j]: float(S[j]) for j in range(k) if np.isfinite(S[j])}
        for p, f, v in scored(matched, pitch_mm):
            j = int(np.argmax(np.abs(v)))
            if not np.isfinite(S[j]):
                continue
            r, c = rec.taxels[j]
            span = (pitch_mm * max(c for _, c in rec.taxels), pitch_mm * max(r for r, _ in rec.taxels))
            loc.largest.setdefault(_class(p, pitch_mm, span), Scores()).add(
                (c * pitch_mm, r * pitch_mm), p.point_mm(pitch_mm), v[j] / S[j], f)
    return loc


def _class(p: PressEvent, pitch_mm: float, span_mm: tuple[float, float] | None = None) -> str:
    """on (a taxel), between (in a gap, inside the taxels' span) or edge (beyond the outer taxels' centres,
    span_mm = (x_max, y_max), the last taxel centres)."""
    if p.on_taxel(pitch_mm):
        return "on"
    x, y = p.point_mm(pitch_mm)
    if span_mm is not None and not (-1e-9 <= x <= span_mm[0] + 1e-9 and -1e-9 <= y <= span_mm[1] + 1e-9):
        return "edge"
    return "between"


def fit_press(v, S, infl, rows, cols, force_hint: float = 1.0) -> tuple[float, float, float]:
    """The model-based estimate (x, y, F) in m, m, N of one press from the taxels'
    readings v (V) with sensitivities S (V/N), taxel k at (rows[k], cols[k]): the grid
    scan and the refinement of its four lowest local minima (module docstring);
    force_hint (N) bounds the start force from below (1e-3 of it)."""
    span = (cols.max() * infl.pitch, rows.max() * infl.pitch)
    gx_, gy_ = (np.linspace(0, L, int(round(16 * L / infl.pitch)) + 1) for L in span)
    Gx, Gy = infl.at(gx_), infl.at(gy_)                            # (m, n)
    M = S[None, None, :] * Gy[:, None, rows] * Gx[None, :, cols]   # (y, x, taxels): V per N at each grid point
    mm = np.einsum("yxk,yxk->yx", M, M)
    Fg = np.clip(np.einsum("yxk,k->yx", M, v) / mm, 0.0, None)       # the best force at each point
    cost = np.sum((Fg[..., None] * M - v) ** 2, axis=-1)
    local = cost <= ndimage.minimum_filter(cost, size=3, mode="nearest")
    starts = sorted(zip(cost[local], *np.nonzero(local)))[:4]

    def resid(q):
        gx, gy = infl.at(q[0]), infl.at(q[1])
        return (S * q[2] * gy[rows] * gx[cols] - v) / np.abs(v).max()
    h, res = infl.pitch / 8, None
    for _, iy, ix in starts:
        lo = [max(0.0, gx_[ix] - h), max(0.0, gy_[iy] - h), 0.0]
        hi = [min(span[0], gx_[ix] + h), min(span[1], gy_[iy] + h), np.inf]
        F0 = max(float(Fg[iy, ix]), 1e-3 * force_hint)
        r = optimize.least_squares(resid, [gx_[ix], gy_[iy], F0], bounds=(lo, hi),
                                   x_scale=[infl.pitch / 8, infl.pitch / 8, F0])
        if res is None or r.cost < res.cost:
            res = r
    return tuple(float(q) for q in res.x)


def model_based(rec: Record, presses, infl, window_s: float = 0.1, loc: Localization | None = None) -> Localization:
    """The model-based estimator (module docstring), added to `loc` (the largest-taxel result)."""
    if max(r for r, _ in rec.taxels) >= infl.n or max(c for _, c in rec.taxels) >= infl.n:
        raise MeasurementError("the influence functions cover fewer taxels than the rig has; "
                               "give the scene of the measured array")
    pitch_mm = 1e3 * infl.pitch
    loc = loc if loc is not None else largest_taxel(rec, presses, window_s, pitch_mm)
    matched = amplitudes(rec, match(rec, presses, window_s, True)[0], pitch_mm)
    S = sensitivities(rec, matched, pitch_mm, infl)
    rows = np.array([r for r, _ in rec.taxels])
    cols = np.array([c for _, c in rec.taxels])
    span = (cols.max() * infl.pitch, rows.max() * infl.pitch)
    for p, f, v in scored(matched, pitch_mm):
        x, y, F = fit_press(v, S, infl, rows, cols, f)
        cls = _class(p, pitch_mm, (1e3 * span[0], 1e3 * span[1]))
        loc.model.setdefault(cls, Scores()).add((1e3 * x, 1e3 * y), p.point_mm(pitch_mm), F, f)
    if not loc.model.get("on", Scores()).position_error_mm:
        raise MeasurementError("too few known presses to calibrate and score the model-based estimator; "
                               "press every taxel at least twice")
    return loc


def localize_folder(folder, presses_file, scene=None) -> Localization:
    """The largest-taxel result, with the model-based estimator's when a scene is given."""
    m = read(folder)
    rec, presses = record(m), read_presses(presses_file)
    if scene is None:
        return largest_taxel(rec, presses)
    from taxel.analyses.surface.influence import influence
    infl = influence(scene)
    return model_based(rec, presses, infl, loc=largest_taxel(rec, presses, pitch_mm=1e3 * infl.pitch))
