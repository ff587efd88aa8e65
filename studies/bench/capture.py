"""Capture from a serial port (pyserial: a device path or any URL it knows).

Every chunk read is appended to raw.bin and flushed to the OS before it is
decoded (fsync once a second); decoded frames go to measurement.h5 and
summary.json once a second. The capture ends after `seconds`, on Ctrl-C, on
`stop` (a threading.Event), or when the port vanishes (cable pulled, socket
closed, pty master gone): then one line says so and everything received is kept.
"""

from __future__ import annotations

import contextlib
import errno
import os
import shutil
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import serial

from taxel.studies.bench.folder import (RAW, SUMMARY, MeasurementError, Writer, now_iso, read, summary_record,
                                          write_json)
from taxel.studies.bench.protocol import Decoder, Frames, SeqStats
from taxel.studies.bench.rig import Rig
from taxel.studies.bench.stream_check import HEAD_BYTES, StreamMismatch, diagnose, mismatched

READ_SIZE = 8192
TIMEOUT = 0.05


class PortError(ValueError):
    """The rig's port cannot be opened; one line naming it and the fix."""


@dataclass
class CaptureResult:
    """A finished capture: its folder, `stats` (its summary.json), how it ended."""

    folder: Path
    stats: dict
    ended: str                 # "seconds" | "stopped" | "interrupted" | "port vanished" | "disk full"
    message: str

    def record(self) -> dict:
        """JSON-ready: the folder, how the capture ended, and summary.json."""
        return {"folder": str(self.folder), "ended": self.ended, "message": self.message, "stats": self.stats}

    def summary(self) -> list[str]:
        """For a person: the counters, the rate and the jitter in one line (two if the port vanished)."""
        s = self.stats
        lines = [f"taxel: {self.message}"] if self.ended in ("port vanished", "disk full") else []
        return lines + [f"{s['frames']} frames, {s['crc_failures']} CRC failures, {s['seq_gaps']} seq gaps "
                        f"({s['frames_lost']} frames lost), {s['resyncs']} resyncs, rate "
                        f"{(s['rate_Hz'] or 0):.2f} Hz, jitter {(s['jitter_us'] or 0):.1f} us; {self.folder}"]

    def measurement(self):
        """The captured folder, read (studies.bench.folder.read)."""
        return read(self.folder)


def open_port(rig: Rig) -> serial.SerialBase:
    url = rig.port.url
    try:
        return serial.serial_for_url(url, baudrate=rig.port.baud, timeout=TIMEOUT)
    except (serial.SerialException, OSError, ValueError) as exc:
        why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise PortError(f"port.url = {url!r}: cannot open it ({why}); check the device path or URL "
                        "and that the instrument is connected") from None


def check_out(out: Path) -> None:
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise MeasurementError(f"{out}: exists and is not empty; choose a new --out folder")


def progress_line(s: dict, elapsed: float) -> str:
    rate = f"{s['rate_Hz']:.1f} Hz" if s["rate_Hz"] else "- Hz"
    return (f"{elapsed:6.1f} s  frames {s['frames']}  rate {rate}  CRC failures {s['crc_failures']}  "
            f"other drops {s['cobs_failures'] + s['length_failures']}  seq gaps {s['seq_gaps']} "
            f"({s['frames_lost']} frames lost)")


class DiskFull(OSError):
    """No space left for raw.bin; `kept`: the bytes of the stream it holds."""

    def __init__(self, kept: int):
        super().__init__(errno.ENOSPC, "no space left on the device")
        self.kept = kept


def _write_all(raw, data: bytes) -> None:
    """Write every byte to the unbuffered raw.bin, or raise DiskFull with the size
    of the file as left (every byte up to there is intact: appends only)."""
    view = memoryview(data)
    while view:
        try:
            n = raw.write(view)
        except OSError as exc:
            if exc.errno != errno.ENOSPC:
                raise
            raise DiskFull(os.fstat(raw.fileno()).st_size) from None
        view = view[n:]


def _no_space(exc: Exception) -> bool:
    """ENOSPC, also as HDF5 reports it (an OSError whose text holds the errno)."""
    text = str(exc)
    return getattr(exc, "errno", None) == errno.ENOSPC or "errno = 28" in text or "No space left" in text


def capture(rig: Rig, out: Path, seconds: float | None = None, stop: threading.Event | None = None,
            progress: Callable[[str], None] | None = None, port: serial.SerialBase | None = None) -> CaptureResult:
    """Capture into the (new, empty) folder `out`. The port is opened before
    anything is written, so a port that does not exist leaves nothing behind."""
    out = Path(out)
    check_out(out)
    ser = port or open_port(rig)
    existed = out.exists()
    out.mkdir(parents=True, exist_ok=True)
    start, t0 = now_iso(), time.monotonic()
    source = f"capture from {rig.port.url} ({rig.port.protocol})"
    dec = Decoder(rig.port.protocol, rig.n)
    writer = Writer(out, rig, source, start_time=start)
    stats, pending = SeqStats(), []
    raw = open(out / RAW, "ab", buffering=0)   # unbuffered: every write is in the OS, or raised
    ended, message = "seconds", ""
    received, head, mismatch = 0, bytearray(), None

    def checkpoint(status: str) -> dict:
        frames = Frames.concat(pending, rig.n)
        pending.clear()
        writer.append(frames)
        stats.update(frames.seq, frames.t_us)
        s = summary_record(dec.counters, stats.record(), start, status, source, time.monotonic() - t0)
        write_json(out / SUMMARY, s)
        return s

    summary = checkpoint("capturing")
    last = time.monotonic()
    try:
        while True:
            now = time.monotonic()
            if seconds is not None and now - t0 >= seconds:
                break
            if stop is not None and stop.is_set():
                ended = "stopped"
                break
            data = ser.read(READ_SIZE)
            if data:
                _write_all(raw, data)             # to the OS before anything else: survives kill -9
                received += len(data)
                pending.append(dec.feed(data))
                if not dec.counters.frames and len(head) < HEAD_BYTES:
                    head += data[:HEAD_BYTES - len(head)]
                    if mismatched(dec.counters):          # the first packets contradict the rig file
                        raise StreamMismatch(diagnose(bytes(head), rig.port.protocol, rig.n,
                                                      f"port {rig.port.url}"))
            if now - last >= 1.0:
                try:
                    os.fsync(raw.fileno())
                    summary = checkpoint("capturing")
                except (OSError, RuntimeError) as exc:   # the HDF5 or summary.json found the disk full
                    if not _no_space(exc):
                        raise
                    raise DiskFull(os.fstat(raw.fileno()).st_size) from None
                last = now
                if progress:
                    progress(progress_line(summary, now - t0))
    except KeyboardInterrupt:
        ended, message = "interrupted", "stopped by Ctrl-C"
    except StreamMismatch as exc:
        mismatch = exc
    except DiskFull as exc:
        ended = "disk full"
        message = (f"{out}: no space left on the device after {time.monotonic() - t0:.1f} s; the "
                   f"{exc.kept} bytes received until then are kept in {RAW}: free space, then "
                   f"'taxel measure rebuild {out}'")
    except (serial.SerialException, OSError) as exc:
        ended = "port vanished"
        message = (f"port {rig.port.url} vanished after {time.monotonic() - t0:.1f} s ({str(exc).splitlines()[0]}); "
                   f"everything received is kept in {out}")
    finally:
        with contextlib.suppress(OSError):         # nothing is buffered; fsync may find the disk full
            os.fsync(raw.fileno())
        raw.close()
        try:
            ser.close()
        except Exception:
            pass
    if mismatch is not None:                        # bad input: nothing half-written is left
        writer.close()
        for f in out.iterdir():
            f.unlink() if f.is_file() else shutil.rmtree(f, ignore_errors=True)
        if not existed:
            out.rmdir()
        raise mismatch
    pending.append(dec.flush())
    if ended == "disk full":                       # no more HDF5 writes: raw.bin holds every byte written
        with contextlib.suppress(Exception):
            writer.close()
        pending.clear()
        summary = summary_record(dec.counters, stats.record(), start, ended, source, time.monotonic() - t0)
        with contextlib.suppress(OSError):
            write_json(out / SUMMARY, summary)
    else:
        summary = checkpoint({"seconds": "complete", "stopped": "complete"}.get(ended, ended))
        writer.close()
    if progress:
        progress(progress_line(summary, summary["seconds"]))
    return CaptureResult(out, summary, ended, message or f"captured {summary['frames']} frames in {out}")


def print_progress(line: str) -> None:
    print("\r" + line, end="", file=sys.stderr, flush=True)
