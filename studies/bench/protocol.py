"""The two wire protocols (docs/serial-protocol.md): encoding and streaming decoding.

taxel-cobs v1: each frame is a COBS-encoded packet (the `cobs` package, the
framing of the PacketSerial Arduino library) followed by one 0x00. The packet is
little-endian: version 0x01 (u8), seq (u16), t_us (u32), n (u8, 1-64), n samples
(i32 ADC counts), CRC-16/CCITT-FALSE (u16) over everything before it.
taxel-ascii v1: one line per frame, `seq,t_us,c0,...,c{n-1}*HH` + `\\n` or
`\\r\\n`, HH the XOR of every byte before the `*` in two uppercase hex digits.

The XOR checksum of taxel-ascii is blind to two equal characters dropped from
one line (x ^ x = 0) and to two flips with the same mask: under heavy corruption
it lets some damaged lines through (measured in tests/test_measure_protocol.py);
taxel-cobs's CRC-16 does not. Prefer taxel-cobs where the link is noisy.

A decoder takes bytes in chunks of any size (a frame may straddle chunks) and
returns the accepted frames as arrays; a bad frame is dropped and counted, and
decoding resumes at the next delimiter (0x00 or newline). CRC-16/CCITT-FALSE is
`binascii.crc_hqx(data, 0xFFFF)` (poly 0x1021, init 0xFFFF, not reflected,
xorout 0; check value crc("123456789") = 0x29B1, tested).
"""

from __future__ import annotations

import binascii
import struct
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from cobs import cobs

Protocol = Literal["taxel-cobs", "taxel-ascii"]
PROTOCOLS = ("taxel-cobs", "taxel-ascii")
VERSION = 1
HEADER = struct.Struct("<BHIB")       # version, seq, t_us, n
MAX_CHANNELS = 64
HEX = {c: i for i, c in enumerate(b"0123456789ABCDEF")}   # uppercase, as the protocol says


def crc16(data: bytes) -> int:
    """CRC-16/CCITT-FALSE of `data`."""
    return binascii.crc_hqx(data, 0xFFFF)


@dataclass
class Frames:
    """Decoded frames in stream order: seq (u16) and t_us (u32) as received, counts (N, n) i32."""

    seq: np.ndarray
    t_us: np.ndarray
    counts: np.ndarray

    @classmethod
    def empty(cls, n: int) -> Frames:
        return cls(np.zeros(0, np.uint16), np.zeros(0, np.uint32), np.zeros((0, n), np.int32))

    @classmethod
    def concat(cls, parts: list[Frames], n: int) -> Frames:
        parts = [p for p in parts if len(p)]
        if not parts:
            return cls.empty(n)
        return cls(np.concatenate([p.seq for p in parts]), np.concatenate([p.t_us for p in parts]),
                   np.concatenate([p.counts for p in parts]))

    def __len__(self) -> int:
        return len(self.seq)

    def __getitem__(self, index) -> Frames:
        return Frames(self.seq[index], self.t_us[index], self.counts[index])

    def rows(self) -> list[tuple]:
        """(seq, t_us, *counts) per frame: for set comparisons in tests."""
        return [(int(s), int(t), *map(int, c)) for s, t, c in zip(self.seq, self.t_us, self.counts)]


@dataclass
class Counters:
    """What a decoder saw: frames accepted and every kind of drop."""

    frames: int = 0
    crc_failures: int = 0          # the packet decoded but its CRC (cobs) or checksum (ascii) is wrong
    cobs_failures: int = 0         # not valid COBS (cobs) / not a parsable line (ascii)
    length_failures: int = 0       # wrong length, version or channel count
    resyncs: int = 0               # times bytes were discarded up to the next delimiter
    bytes: int = 0
    truncated_bytes: int = 0       # an incomplete last frame when the stream ended (not a failure)

    @property
    def dropped(self) -> int:
        return self.crc_failures + self.cobs_failures + self.length_failures


# --- encoding -------------------------------------------------------------

def packet(seq: int, t_us: int, counts) -> bytes:
    """One taxel-cobs v1 packet, before COBS."""
    counts = np.asarray(counts, "<i4")
    body = HEADER.pack(VERSION, seq & 0xFFFF, t_us & 0xFFFFFFFF, len(counts)) + counts.tobytes()
    return body + struct.pack("<H", crc16(body))


def encode_cobs(seq: int, t_us: int, counts) -> bytes:
    """One frame on the wire: COBS(packet) + 0x00."""
    return cobs.encode(packet(seq, t_us, counts)) + b"\x00"


def encode_ascii(seq: int, t_us: int, counts, crlf: bool = False) -> bytes:
    """One taxel-ascii v1 line."""
    body = ",".join([str(seq & 0xFFFF), str(t_us & 0xFFFFFFFF)] + [str(int(c)) for c in counts]).encode()
    x = 0
    for b in body:
        x ^= b
    return body + b"*%02X" % x + (b"\r\n" if crlf else b"\n")


def encode_frames(frames: Frames, protocol: Protocol) -> list[bytes]:
    """The wire bytes of each frame, in order (a list, so a simulator can tell frames apart)."""
    enc = encode_cobs if protocol == "taxel-cobs" else encode_ascii
    return [enc(int(s), int(t), c) for s, t, c in zip(frames.seq, frames.t_us, frames.counts)]


# --- decoding -------------------------------------------------------------

@dataclass
class Decoder:
    """Streaming decoder for one protocol and channel count n (from the rig).

    feed(chunk) -> the frames completed by this chunk. The first segment of a
    stream joined mid-frame fails and counts as a resync, like any bad frame.
    """

    protocol: Protocol
    n: int
    counters: Counters = field(default_factory=Counters)
    _tail: bytes = b""

    def __post_init__(self):
        if not 1 <= self.n <= MAX_CHANNELS:
            raise ValueError(f"channel count must be 1-{MAX_CHANNELS}, got {self.n}")
        self._plen = HEADER.size + 4 * self.n + 2
        self._dtype = np.dtype([("version", "u1"), ("seq", "<u2"), ("t_us", "<u4"), ("n", "u1"),
                                ("counts", "<i4", (self.n,)), ("crc", "<u2")])

    def feed(self, chunk: bytes) -> Frames:
        self.counters.bytes += len(chunk)
        delim = b"\x00" if self.protocol == "taxel-cobs" else b"\n"
        parts = (self._tail + chunk).split(delim)
        self._tail = parts.pop()
        if self.protocol == "taxel-cobs":
            return self._cobs(parts)
        return self._ascii(parts)

    def flush(self) -> Frames:
        """End of stream: an incomplete last frame (the capture stopped mid-frame) is
        counted in truncated_bytes, not as a failure."""
        self.counters.truncated_bytes = len(self._tail)
        self._tail = b""
        return Frames.empty(self.n)

    def _cobs(self, parts: list[bytes]) -> Frames:
        good = []
        c = self.counters
        plen, head = self._plen, bytes([VERSION])
        decode, crc_hqx = cobs.decode, binascii.crc_hqx
        for p in parts:
            if not p:                      # back-to-back delimiters: an empty frame, nothing lost
                continue
            try:
                d = decode(p)
            except cobs.DecodeError:
                c.cobs_failures += 1
                c.resyncs += 1
                continue
            if len(d) != plen or d[7] != self.n or d[:1] != head:
                c.length_failures += 1
                c.resyncs += 1
                continue
            if crc_hqx(d[:-2], 0xFFFF) != (d[-2] | d[-1] << 8):
                c.crc_failures += 1
                c.resyncs += 1
                continue
            good.append(d)
        c.frames += len(good)
        if not good:
            return Frames.empty(self.n)
        rec = np.frombuffer(b"".join(good), self._dtype)
        return Frames(rec["seq"].copy(), rec["t_us"].copy(), rec["counts"].copy())

    def _ascii(self, parts: list[bytes]) -> Frames:
        rows = []
        c = self.counters
        for line in parts:
            line = line.rstrip(b"\r")
            if not line:
                continue
            body, star, hh = line.rpartition(b"*")
            parts_ = body.split(b",") if star else []
            fields = check = None
            if star and len(hh) == 2 and all(HEX.get(h) is not None for h in hh) and all(
                    (f[1:] if f[:1] == b"-" else f).isdigit() for f in parts_):   # strict: no '+', ' ', '_'
                fields = [int(x) for x in parts_]
                check = int(hh, 16)
            if fields is None or check is None:
                c.cobs_failures += 1
                c.resyncs += 1
                continue
            x = int(np.bitwise_xor.reduce(np.frombuffer(body, np.uint8))) if body else 0
            if x != check:
                c.crc_failures += 1
                c.resyncs += 1
                continue
            if (len(fields) != 2 + self.n or not 0 <= fields[0] < 1 << 16 or not 0 <= fields[1] < 1 << 32
                    or any(not -(1 << 31) <= v < 1 << 31 for v in fields[2:])):
                c.length_failures += 1
                c.resyncs += 1
                continue
            rows.append(fields)
        c.frames += len(rows)
        if not rows:
            return Frames.empty(self.n)
        a = np.array(rows, np.int64)
        return Frames(a[:, 0].astype(np.uint16), a[:, 1].astype(np.uint32), a[:, 2:].astype(np.int32))


def decode_all(data: bytes, protocol: Protocol, n: int) -> tuple[Frames, Counters]:
    """Decode a whole byte string (a raw.bin or a dump)."""
    dec = Decoder(protocol, n)
    frames = dec.feed(data)
    dec.flush()
    return frames, dec.counters


@dataclass
class SeqStats:
    """Sequence gaps (frames lost on the wire, from seq with wrap-around), and the
    sample rate and its jitter from the device clock (t_us with wrap-around), kept
    as running sums so that a long capture costs the same every second."""

    seq_gaps: int = 0
    frames_lost: int = 0
    _last: tuple[int, int] | None = None
    _m: int = 0
    _sum: float = 0.0
    _sum2: float = 0.0

    def update(self, seq: np.ndarray, t_us: np.ndarray) -> SeqStats:
        if not len(seq):
            return self
        s, t = seq.astype(np.int64), t_us.astype(np.int64)
        if self._last is not None:
            s, t = np.concatenate([[self._last[0]], s]), np.concatenate([[self._last[1]], t])
        self._last = (int(s[-1]), int(t[-1]))
        dseq = np.diff(s) % (1 << 16)
        dt = np.diff(t) % (1 << 32)
        ok = dseq > 0
        self.seq_gaps += int(np.count_nonzero(dseq != 1))
        self.frames_lost += int(np.sum(dseq[ok] - 1))
        per = dt[ok] / dseq[ok]                      # us per frame, each interval
        self._m += len(per)
        self._sum += float(per.sum())
        self._sum2 += float((per ** 2).sum())
        return self

    def record(self) -> dict:
        out = {"seq_gaps": self.seq_gaps, "frames_lost": self.frames_lost, "rate_Hz": None, "jitter_us": None}
        if self._m and self._sum > 0:
            mean = self._sum / self._m
            out["rate_Hz"] = 1e6 / mean
            out["jitter_us"] = float(np.sqrt(max(self._sum2 / self._m - mean ** 2, 0.0)))
        return out


def sequence_stats(seq: np.ndarray, t_us: np.ndarray) -> dict:
    """SeqStats of a whole record."""
    return SeqStats().update(np.asarray(seq), np.asarray(t_us)).record()
