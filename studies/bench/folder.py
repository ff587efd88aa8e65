"""The measurement folder: what a capture, an import or a rebuild leaves.

    DIR/raw.bin           the exact bytes received, appended and flushed before they are decoded
                          (captures and raw-dump imports only)
    DIR/rig.json          the validated rig the data was taken with
    DIR/measurement.h5    the decoded frames (HDF5, below)
    DIR/summary.json      counters, rate and jitter, start time, status; rewritten (atomically) every second

measurement.h5 (HDF5 through h5py): one row per accepted frame, in stream order:
    /seq     (N,)   uint16   as received
    /t_us    (N,)   uint32   as received (device microseconds, wrapping at 2^32)
    /counts  (N, n) int32    ADC counts, columns in channel-index order   (serial sources)
 or /si      (N, n) float64  channel values in SI as in the file (V, N)    (analog files: TDMS, LVM, CSV)
    attributes: format = "taxel-measurement v1", channels (names), units, volts_per_si, rig (JSON),
                source, start_time.
Why HDF5: resizable chunked datasets take the frames as they come (one append a
second), typed arrays keep u16/u32/i32 exactly, attributes keep the rig beside
the data, and it opens in MATLAB, LabVIEW, Origin and h5py without this tool.
A file left half-written by kill -9 is rebuilt from raw.bin (`rebuild`).
"""

from __future__ import annotations

import datetime as dt
import json
import os
from dataclasses import dataclass
from pathlib import Path

import h5py
import numpy as np

from taxel.studies.bench.protocol import Counters, Decoder, Frames, sequence_stats
from taxel.studies.bench.rig import Rig, RigError, parse_rig

FORMAT = "taxel-measurement v1"
H5, RAW, SUMMARY, RIG = "measurement.h5", "raw.bin", "summary.json", "rig.json"


class MeasurementError(ValueError):
    """A folder that is not a readable measurement; one line with the fix."""


def now_iso() -> str:
    return dt.datetime.now(dt.timezone.utc).isoformat(timespec="milliseconds")


def prepare(out: Path) -> Path:
    """An empty (or new) output folder; refuses to mix with an existing measurement."""
    out = Path(out)
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise MeasurementError(f"{out}: exists and is not empty; choose a new --out folder")
    out.mkdir(parents=True, exist_ok=True)
    return out


def write_json(path: Path, data: dict) -> None:
    """Atomic: a reader (or a kill) sees the old or the new file, never half of one."""
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(data, indent=1))
    os.replace(tmp, path)


def summary_record(counters: Counters, stats: dict, start_time: str, status: str, source: str,
                   seconds: float | None = None) -> dict:
    """The summary.json record; `stats` from protocol.SeqStats.record() (or sequence_stats)."""
    return {"frames": counters.frames, "crc_failures": counters.crc_failures,
            "cobs_failures": counters.cobs_failures, "length_failures": counters.length_failures,
            "seq_gaps": stats["seq_gaps"], "frames_lost": stats["frames_lost"], "resyncs": counters.resyncs,
            "bytes": counters.bytes, "truncated_bytes": counters.truncated_bytes, "rate_Hz": stats["rate_Hz"], "jitter_us": stats["jitter_us"],
            "start_time": start_time, "seconds": seconds, "status": status, "source": source}


class Writer:
    """Appends frames to measurement.h5 by chunks (resizable datasets), flushing each append."""

    def __init__(self, out: Path, rig: Rig, source: str, kind: str = "counts", start_time: str | None = None):
        self.out, self.rig, self.kind = Path(out), rig, kind
        self.start_time = start_time or now_iso()
        (self.out / RIG).write_text(rig.model_dump_json(indent=1))
        self.h5 = h5py.File(self.out / H5, "w")
        n = rig.n
        self.h5.attrs.update(format=FORMAT, channels=rig.names, units=[c.unit for c in rig.ordered()],
                             volts_per_si=rig.volts_per_si(), rig=rig.model_dump_json(), source=source,
                             start_time=self.start_time)
        chunk = 4096
        self.h5.create_dataset("seq", (0,), np.uint16, maxshape=(None,), chunks=(chunk,), fletcher32=True)
        self.h5.create_dataset("t_us", (0,), np.uint32, maxshape=(None,), chunks=(chunk,), fletcher32=True)
        dtype = np.int32 if kind == "counts" else np.float64
        self.h5.create_dataset(kind, (0, n), dtype, maxshape=(None, n), chunks=(chunk, n), fletcher32=True)
        self.h5.flush()
        self.n_rows = 0

    def append(self, frames: Frames, values: np.ndarray | None = None) -> None:
        m = len(frames)
        if not m:
            return
        a, b = self.n_rows, self.n_rows + m
        for name, data in (("seq", frames.seq), ("t_us", frames.t_us),
                           (self.kind, frames.counts if values is None else values)):
            ds = self.h5[name]
            ds.resize(b, axis=0)
            ds[a:b] = data
        self.n_rows = b
        self.h5.flush()

    def close(self) -> None:
        self.h5.close()


@dataclass
class Measurement:
    """A measurement folder, read: the frames, the rig, and `stats`, its summary.json (frames, failures,
    rate, jitter, start time, status)."""

    folder: Path
    rig: Rig
    seq: np.ndarray
    t_us: np.ndarray
    counts: np.ndarray | None          # ADC counts (serial sources), else None
    values: np.ndarray                 # (N, n) SI: V out of each taxel's conditioning, N for the force
    stats: dict                        # summary.json

    def si(self) -> np.ndarray:
        return self.values

    def __len__(self) -> int:
        return len(self.seq)

    def record(self) -> dict:
        """JSON-ready: the folder, the channels and their units, the frame count and summary.json."""
        return {"folder": str(self.folder), "channels": self.rig.names, "units": [c.unit for c in self.rig.ordered()],
                "frames": len(self), "counts": self.counts is not None, "stats": self.stats}

    def summary(self) -> list[str]:
        """For a person: frames, channels and the decoder's counters."""
        s = self.stats
        lines = [f"{self.folder}: {len(self)} frames of {self.rig.n} channels ({', '.join(self.rig.names)})"]
        if "crc_failures" in s:
            lines.append(f"  {s['crc_failures']} CRC failures, {s.get('seq_gaps', 0)} seq gaps "
                         f"({s.get('frames_lost', 0)} frames lost), {s.get('resyncs', 0)} resyncs; {s.get('status', '')}")
        return lines

    def to_folder(self, folder: str | Path) -> Path:
        """A copy of this measurement folder at `folder` (a new or empty folder); returns it."""
        import shutil
        out = prepare(Path(folder))
        for name in (RIG, H5, SUMMARY, RAW):
            if (self.folder / name).exists():
                shutil.copyfile(self.folder / name, out / name)
        return out

    @classmethod
    def read(cls, folder: str | Path) -> "Measurement":
        """The measurement folder `folder` (`read`)."""
        return read(folder)


def read_rig(folder: str | Path) -> Rig:
    """The rig a measurement folder was taken with (its rig.json); one-line MeasurementError if none."""
    folder = Path(folder)
    try:
        return parse_rig(json.loads((folder / RIG).read_text()), str(folder / RIG), si_numbers=True)
    except (OSError, json.JSONDecodeError):
        raise MeasurementError(f"{folder}: no readable {RIG}; this is not a measurement folder") from None


def read(folder: str | Path) -> Measurement:
    """A measurement folder; a missing or damaged measurement.h5 is one line pointing to `rebuild`."""
    folder = Path(folder)
    if not folder.is_dir():
        raise MeasurementError(f"{folder}: no such measurement folder")
    rig = read_rig(folder)
    try:
        with h5py.File(folder / H5, "r") as f:
            seq, t_us = f["seq"][:], f["t_us"][:]
            counts = f["counts"][:] if "counts" in f else None
            si = (rig.counts_to_volts(counts.astype(np.float64)) / rig.volts_per_si()[None, :]
                  if counts is not None else f["si"][:])
    except (OSError, KeyError):
        # never rebuilt here: a capture still running holds the file (HDF5 locks it), and
        # rebuilding under it would fight its writer
        if not (folder / RAW).exists():
            raise MeasurementError(f"{folder}: {H5} is unreadable and there is no {RAW} to rebuild it from") from None
        raise MeasurementError(f"{folder}: {H5} is unreadable (a capture still writing it, or one killed mid-write); "
                               f"wait for the capture, or run 'taxel measure rebuild {folder}'") from None
    summary = json.loads((folder / SUMMARY).read_text()) if (folder / SUMMARY).exists() else {}
    return Measurement(folder, rig, seq, t_us, counts, si, summary)


def rebuild(folder: str | Path, status: str | None = None) -> Measurement:
    """Decode raw.bin again into a fresh measurement.h5 and summary.json (after kill -9, or to check).
    The summary's status says so, unless `status` is given."""
    folder = Path(folder)
    rig = read_rig(folder)
    raw = folder / RAW
    if not raw.exists():
        raise MeasurementError(f"{folder}: no {RAW}; only captures and raw-dump imports can be rebuilt")
    old = {}
    try:
        old = json.loads((folder / SUMMARY).read_text())
    except (OSError, json.JSONDecodeError):
        pass
    dec = Decoder(rig.port.protocol, rig.n)
    parts = []
    with open(raw, "rb") as f:
        while chunk := f.read(1 << 20):
            parts.append(dec.feed(chunk))
    dec.flush()
    frames = Frames.concat(parts, rig.n)
    w = Writer(folder, rig, old.get("source", "rebuilt from raw.bin"), start_time=old.get("start_time"))
    w.append(frames)
    w.close()
    status = status or f"rebuilt from raw.bin (was: {old.get('status', 'unknown')})"
    summary = summary_record(dec.counters, sequence_stats(frames.seq, frames.t_us), old.get("start_time") or now_iso(),
                             status, old.get("source", "raw.bin"), old.get("seconds"))
    write_json(folder / SUMMARY, summary)
    return read(folder)


__all__ = ["Measurement", "MeasurementError", "Writer", "read", "rebuild", "prepare", "write_json",
           "summary_record", "now_iso", "read_rig", "RigError"]
