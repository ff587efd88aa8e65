"""Import the files labs already have into a measurement folder.

    raw byte dump (.bin, .raw, .dump, .cobs, .txt with --format raw): the rig's protocol;
        copied to raw.bin and decoded, exactly as a capture
    CSV (.csv): a header row; a time column t_us (device us) or t_s / time (s); an
        optional seq column; one column per rig channel, by name, in SI (V, N),
        as `taxel measure export` writes them
    NI TDMS (.tdms, npTDMS): the channels named as the rig's, in any one group;
        time from the channels' wf_increment (or a "time" channel, s)
    LabVIEW LVM text (.lvm): the header, then segments (own header, an X_Value
        column or Delta_X, one column per channel named as the rig's); Tab or comma
        separated, "." or "," decimals
Everything is read and checked before the folder is created: a bad file gives one
line naming it and the fix, and nothing is written.
"""

from __future__ import annotations

import csv
import io
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from taxel.studies.bench.folder import (RAW, MeasurementError, Writer, now_iso, prepare, rebuild,
                                          summary_record, write_json, SUMMARY)
from taxel.studies.bench.protocol import Counters, Frames, sequence_stats
from taxel.studies.bench.rig import Rig

FORMATS = ("raw", "csv", "tdms", "lvm")
SUFFIX = {".bin": "raw", ".raw": "raw", ".dump": "raw", ".cobs": "raw", ".csv": "csv", ".tdms": "tdms",
          ".lvm": "lvm"}


class InputFileError(MeasurementError):
    """An input file that cannot be imported; one line naming it and the fix."""


@dataclass
class Table:
    """An analog table: time (s) and SI values per rig channel, and seq if the file had it."""

    t_s: np.ndarray
    values: np.ndarray
    seq: np.ndarray | None = None
    t_us: np.ndarray | None = None


def _columns(path: Path, names: list[str], rig: Rig) -> list[int]:
    missing = [n for n in rig.names if n not in names]
    if missing:
        raise InputFileError(f"{path}: no column for channel {missing[0]!r} (columns: {', '.join(names)}); "
                           "name the columns as the rig's channels")
    return [names.index(n) for n in rig.names]


def _numbers(path: Path, rows: list[list[str]], decimal: str = ".") -> np.ndarray:
    try:
        return np.array([[float(x.replace(decimal, ".") if decimal != "." else x) for x in r] for r in rows], float)
    except ValueError as exc:
        raise InputFileError(f"{path}: a value is not a number ({exc}); the data rows must hold numbers only") from None


def _finite(path: Path, a: np.ndarray, names: list[str]) -> None:
    """Every number finite: a NaN or an infinity in a data row is refused, naming its row and column."""
    bad = np.argwhere(~np.isfinite(np.atleast_2d(a)))
    if len(bad):
        r, c = bad[0]
        raise InputFileError(f"{path}: data row {r + 1}: {names[c] if c < len(names) else f'column {c + 1}'} is "
                             f"{np.atleast_2d(a)[r, c]:g}, not a finite number; fix or remove the row")


def read_csv(path: Path, rig: Rig) -> Table:
    text = path.read_text(encoding="utf-8-sig")
    rows = [r for r in csv.reader(io.StringIO(text)) if r and not r[0].startswith("#")]
    if len(rows) < 2:
        raise InputFileError(f"{path}: no data rows; a CSV needs a header row and one row per frame")
    head = [h.strip() for h in rows[0]]
    cols = _columns(path, head, rig)
    if any(len(r) != len(head) for r in rows[1:]):
        raise InputFileError(f"{path}: rows of unequal length; every row needs {len(head)} values")
    a = _numbers(path, rows[1:])
    _finite(path, a, head)
    for k in ("seq", "t_us"):          # counters: whole numbers that fit 64 bits
        if k in head and not (np.all(np.abs(a[:, head.index(k)]) < 2.0 ** 62)
                              and np.all(a[:, head.index(k)] == np.round(a[:, head.index(k)]))):
            raise InputFileError(f"{path}: column {k}: not a whole number of the device's counter; "
                                 f"{k} holds integers (0 to 2^32)")
    if "t_us" in head:
        t_us = a[:, head.index("t_us")].astype(np.int64)
        t = np.unwrap(t_us.astype(float), period=2.0 ** 32) * 1e-6
    elif "t_s" in head or "time" in head:
        t, t_us = a[:, head.index("t_s" if "t_s" in head else "time")], None
    else:
        raise InputFileError(f"{path}: no time column; add t_us (device microseconds) or t_s (seconds)")
    seq = a[:, head.index("seq")].astype(np.int64) if "seq" in head else None
    return Table(t, a[:, cols], seq, t_us)


def read_tdms(path: Path, rig: Rig) -> Table:
    import logging

    from nptdms import TdmsFile
    with open(path, "rb") as fh:
        if fh.read(4) != b"TDSm":
            raise InputFileError(f"{path}: not a TDMS file (no TDSm lead-in); export it from LabVIEW as .tdms")
    warnings: list[str] = []

    class Keep(logging.Handler):
        def emit(self, record):
            warnings.append(record.getMessage())
    from nptdms.log import log_manager
    keep, console = Keep(logging.WARNING), log_manager.console_handler
    loggers = list(log_manager.loggers.values())
    for lg in loggers:                             # npTDMS's console warnings become our one line
        lg.removeHandler(console)
        lg.addHandler(keep)
    try:
        f = TdmsFile.read(path)
    except Exception as exc:
        raise InputFileError(f"{path}: not a readable TDMS file ({str(exc).splitlines()[0] if str(exc) else exc})") from None
    finally:
        for lg in loggers:
            lg.removeHandler(keep)
            lg.addHandler(console)
    if warnings and not any(all(n in [c.name for c in g.channels()] for n in rig.names) for g in f.groups()):
        raise InputFileError(f"{path}: not a readable TDMS file ({warnings[0]})")
    for g in f.groups():
        names = [c.name for c in g.channels()]
        if all(n in names for n in rig.names):
            data = [g[n][:] for n in rig.names]
            if len({len(d) for d in data}) != 1:
                raise InputFileError(f"{path}: group {g.name!r} has channels of unequal length")
            if "time" in names:
                t = np.asarray(g["time"][:], float)
            else:
                dt = g[rig.names[0]].properties.get("wf_increment")
                if not dt:
                    raise InputFileError(f"{path}: no wf_increment property and no 'time' channel; "
                                       "give the sampling interval")
                t = np.arange(len(data[0])) * float(dt)
            if len(t) != len(data[0]):
                raise InputFileError(f"{path}: group {g.name!r}: the time channel has {len(t)} samples and the "
                                     f"others {len(data[0])}; a cut-short file? export it again")
            return Table(t, np.column_stack(data).astype(float))
    raise InputFileError(f"{path}: no group holds all the rig's channels ({', '.join(rig.names)}); "
                       "name the TDMS channels as the rig's")


def read_lvm(path: Path, rig: Rig) -> Table:
    text = path.read_text(encoding="latin-1")
    lines = text.splitlines()
    if not lines or not lines[0].startswith("LabVIEW Measurement"):
        raise InputFileError(f"{path}: not a LabVIEW LVM file (no 'LabVIEW Measurement' first line)")
    sep, dec, i, t_parts, v_parts = "\t", ".", 0, [], []
    while i < len(lines) and "***End_of_Header***" not in lines[i]:
        tag, _, val = lines[i].partition("\t")
        if tag == "Separator":
            sep = "," if val.strip().startswith("Comma") else "\t"
        if tag == "Decimal_Separator":
            dec = val.strip() or "."
        i += 1
    i += 1
    while i < len(lines):
        seg_delta, x0 = None, 0.0
        while i < len(lines) and "***End_of_Header***" not in lines[i]:
            f = lines[i].split(sep)
            if f[0] == "Delta_X":
                seg_delta = float(f[1].replace(dec, "."))
            if f[0] == "X0":
                x0 = float(f[1].replace(dec, "."))
            i += 1
        i += 1
        if i >= len(lines):
            break
        head = [h.strip() for h in lines[i].split(sep)]
        i += 1
        rows = []
        while i < len(lines) and lines[i].strip() and not lines[i].startswith("***"):
            rows.append(lines[i].split(sep))
            i += 1
        while i < len(lines) and not lines[i].strip():
            i += 1
        if head and head[-1] == "Comment":
            head = head[:-1]
            rows = [r[:len(head)] for r in rows]
        cols = _columns(path, head, rig)
        if not rows:                    # a segment header with no data rows (a cut file): nothing to read
            continue
        a = _numbers(path, [r[:len(head)] for r in rows], dec)
        if "X_Value" in head:
            t_parts.append(a[:, head.index("X_Value")])
        elif seg_delta:
            t_parts.append(x0 + np.arange(len(a)) * seg_delta)
        else:
            raise InputFileError(f"{path}: no X_Value column and no Delta_X; cannot tell the sample times")
        v_parts.append(a[:, cols])
    if not v_parts or not sum(len(v) for v in v_parts):
        raise InputFileError(f"{path}: no data segment after the header")
    return Table(np.concatenate(t_parts), np.concatenate(v_parts))


def import_file(path: str | Path, rig: Rig, out: str | Path, fmt: str | None = None):
    """Build a measurement folder from `path`; returns the Measurement."""
    from taxel.studies.bench.folder import read
    path, out = Path(path), Path(out)
    if not path.is_file():
        raise InputFileError(f"{path}: no such file")
    fmt = fmt or SUFFIX.get(path.suffix.lower())
    if fmt not in FORMATS:
        raise InputFileError(f"{path}: unknown file type {path.suffix!r}; use .bin/.raw (byte dump), .csv, .tdms "
                           "or .lvm, or say --format raw|csv|tdms|lvm")
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise MeasurementError(f"{out}: exists and is not empty; choose a new --out folder")
    if fmt == "raw":
        from taxel.studies.bench.protocol import decode_all
        frames, counters = decode_all(path.read_bytes(), rig.port.protocol, rig.n)
        if counters.frames == 0:
            raise InputFileError(f"{path}: no valid {rig.port.protocol} frame of {rig.n} channels in it; "
                               "check the rig's protocol and channels")
        prepare(out)
        shutil.copyfile(path, out / RAW)
        write_json(out / SUMMARY, {"source": f"raw dump {path.name}", "start_time": now_iso(), "status": "imported"})
        Writer(out, rig, f"raw dump {path.name}").close()
        return rebuild(out, status="imported")
    try:
        table = {"csv": read_csv, "tdms": read_tdms, "lvm": read_lvm}[fmt](path, rig)
    except UnicodeDecodeError:
        raise InputFileError(f"{path}: not text; is it really a .{fmt} file?") from None
    if not len(table.t_s):
        raise InputFileError(f"{path}: no data rows")
    _finite(path, np.asarray(table.t_s, float)[:, None], ["time"])
    _finite(path, np.asarray(table.values, float), rig.names)
    span = np.abs(np.asarray(table.t_s, float) - table.t_s[0])
    if table.t_us is None and span.max() * 1e6 >= 2.0 ** 62:
        r = int(np.argmax(span * 1e6 >= 2.0 ** 62))
        raise InputFileError(f"{path}: data row {r + 1}: time {table.t_s[r]:g} s is {span[r]:.3g} s from the first "
                             "row, beyond any record; the time column holds seconds from the start")
    n = len(table.t_s)
    seq = (table.seq if table.seq is not None else np.arange(n)) % (1 << 16)
    t_us = table.t_us if table.t_us is not None else np.round((table.t_s - table.t_s[0]) * 1e6).astype(np.int64)
    frames = Frames(seq.astype(np.uint16), (t_us % (1 << 32)).astype(np.uint32), np.zeros((n, 0), np.int32))
    prepare(out)
    w = Writer(out, rig, f"{fmt} file {path.name}", kind="si")
    w.append(frames, table.values)
    w.close()
    c = Counters(frames=n)
    write_json(out / SUMMARY, summary_record(c, sequence_stats(frames.seq, frames.t_us), w.start_time, "imported",
                                             f"{fmt} file {path.name}", float(table.t_s[-1] - table.t_s[0])))
    return read(out)
