"""Loading events in a measurement, found on its force channel.

An event is a run of samples where the load cell's force, smoothed by a moving
average over `smooth_s` (the load cell's white noise averages down by
sqrt(window)), exceeds `level` x its largest value; runs closer than `merge_s`
are one event. From the events the kind of record is recognised:
  step      the force at the end of the record is still above half its largest value;
  impulse   events shorter than 50 ms, at least 0.5 s apart (median);
  chirp     events less than 0.15 s apart (median): the raised-cosine chirp
            returns to zero once per period;
  presses   anything else (held presses of different force, possibly on different taxels).
`--input` overrides the recognition. A folder without a force channel cannot be
analysed (MeasurementError, one line).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import signal

from taxel.studies.bench.folder import Measurement, MeasurementError

KINDS = ("step", "impulse", "chirp", "presses")


@dataclass
class Record:
    """A measurement as analysis sees it: time, force, and the taxel channels in SI."""

    t: np.ndarray                 # (N,) s, from the nominal rate
    force: np.ndarray             # (N,) N
    volts: np.ndarray             # (N, k) V out of each taxel's conditioning
    names: list[str]              # the k taxel channel names
    taxels: list[tuple[int, int]]
    rate: float
    travel: np.ndarray | None = None   # (N,) m, the actuator's travel, when the rig records it

    @property
    def smooth_force(self) -> np.ndarray:
        return smooth(self.force, max(1, int(round(2e-3 * self.rate))))


def smooth(x: np.ndarray, n: int) -> np.ndarray:
    """Centred moving average over n samples (edges padded with the end values)."""
    if n <= 1:
        return x
    pad = np.pad(x, (n // 2, n - 1 - n // 2), mode="edge")
    return np.convolve(pad, np.ones(n) / n, mode="valid")


def dehum(x: np.ndarray, rate: float, mains: float = 50.0, q: float = 10.0) -> np.ndarray:
    """x (N, ...) with the mains hum and its 3rd and 5th harmonics removed: zero-phase
    second-order notches (scipy.signal.iirnotch, quality q, applied forwards and backwards)."""
    y = np.asarray(x, float)
    for h in (1, 3, 5):
        f = h * mains
        if f < 0.45 * rate:
            b, a = signal.iirnotch(f, q, fs=rate)
            y = signal.filtfilt(b, a, y, axis=0)
    return y


def record(m: Measurement) -> Record:
    """The taxel channels, the force channel and the travel channel (if any) of a measurement folder."""
    chans = m.rig.ordered()
    force = [c for c in chans if c.kind == "force"]
    if not force:
        raise MeasurementError(f"{m.folder}: the rig has no force channel; analysis needs the load cell "
                               "(add a channel named force with its sensitivity to the rig and measure again)")
    tax = [c for c in chans if c.kind == "taxel"]
    if not tax:
        raise MeasurementError(f"{m.folder}: the rig has no taxel channel (name them taxel_ROW_COL)")
    if len(m) < 10:
        raise MeasurementError(f"{m.folder}: only {len(m)} frames; capture a longer record")
    rate = m.rig.sampling.rate
    travel = [c for c in chans if c.kind == "travel"]
    return Record(np.arange(len(m)) / rate, m.values[:, force[0].index].astype(float),
                  m.values[:, [c.index for c in tax]].astype(float), [c.name for c in tax],
                  [c.taxel for c in tax], rate, m.values[:, travel[0].index].astype(float) if travel else None)


def segments(rec: Record, level: float = 0.1, merge_s: float = 5e-3) -> list[tuple[int, int]]:
    """(start, stop) sample indices of the events, in order."""
    f = rec.smooth_force
    base = np.median(f[: max(1, int(0.1 * rec.rate))])
    f = f - base
    top = f.max()
    if not top > 0:
        return []
    on = f > level * top
    edges = np.flatnonzero(np.diff(on.astype(np.int8)))
    starts = list(edges[~on[edges]] + 1) if len(edges) else []
    stops = list(edges[on[edges]] + 1) if len(edges) else []
    if on[0]:
        starts = [0] + starts
    if on[-1]:
        stops = stops + [len(f)]
    out: list[list[int]] = []
    gap = int(merge_s * rec.rate)
    for a, b in zip(starts, stops):
        if out and a - out[-1][1] <= gap:
            out[-1][1] = b
        else:
            out.append([a, b])
    return [(a, b) for a, b in out]


def kind_of(rec: Record, segs: list[tuple[int, int]]) -> str:
    """The kind of record (module docstring)."""
    if not segs:
        raise MeasurementError("the force channel never rises above its noise: no loading in this record")
    f = rec.smooth_force - np.median(rec.smooth_force[: max(1, int(0.1 * rec.rate))])
    tail = f[-max(1, len(f) // 20):]
    if np.median(tail) > 0.5 * f.max():
        return "step"
    starts = np.array([a for a, _ in segs]) / rec.rate
    widths = np.array([b - a for a, b in segs]) / rec.rate
    gaps = np.diff(starts) if len(starts) > 1 else np.array([np.inf])
    if np.median(widths) < 0.05 and np.median(gaps) > 0.5:
        return "impulse"
    if len(segs) > 10 and np.median(gaps) < 0.15:
        return "chirp"
    return "presses"
