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
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

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

    def write(self, folder: Path) -> Path:
        write_json(Path(folder) / JSON, self.record())
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


def localize_folder(folder, presses_file) -> Localization:
    m = read(folder)
    return largest_taxel(record(m), read_presses(presses_file))
