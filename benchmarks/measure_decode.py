"""Decoding throughput of the wire protocols, and the corruption figures.

    python benchmarks/measure_decode.py [--frames 200000] [--repeats 5]

Throughput: 10-channel frames (16-bit-range counts), decoded from one byte string
by `Decoder.feed` in 64 KiB chunks (as a capture reads them); the median of the
repeats, frames per second (target >= 2e5/s for taxel-cobs). Corruption: 1e5
frames, 1 % of bytes flipped or dropped: intact frames, recovered, invented.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from taxel.studies.bench import wire as W
from taxel.studies.bench.protocol import PROTOCOLS, Decoder, Frames, decode_all, encode_frames


def frames_of(n_frames: int, seed: int = 0) -> Frames:
    rng = np.random.default_rng(seed)
    k = np.arange(n_frames, dtype=np.int64)
    return Frames((k % 65536).astype(np.uint16), (k * 500 % 2 ** 32).astype(np.uint32),
                  rng.integers(-32768, 32768, (n_frames, 10)).astype(np.int32))


def throughput(data: bytes, protocol: str, n_frames: int, repeats: int) -> float:
    rates = []
    for _ in range(repeats):
        dec = Decoder(protocol, 10)
        t = time.perf_counter()
        got = 0
        for i in range(0, len(data), 1 << 16):
            got += len(dec.feed(data[i:i + (1 << 16)]))
        rates.append(n_frames / (time.perf_counter() - t))
        assert got == n_frames
    return statistics.median(rates)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--frames", type=int, default=200_000)
    ap.add_argument("--repeats", type=int, default=5)
    a = ap.parse_args()
    frames = frames_of(a.frames)
    print(f"| protocol | frames | bytes/frame | decode frames/s (median of {a.repeats}) |")
    print("|---|---|---|---|")
    for p in PROTOCOLS:
        data = b"".join(encode_frames(frames, p))
        print(f"| {p} | {a.frames} | {len(data) / a.frames:.1f} | {throughput(data, p, a.frames, a.repeats):.3g} |")
    print()
    print("| protocol | corruption | frames | intact | recovered | intact recovered | invented | dropped |")
    print("|---|---|---|---|---|---|---|---|")
    sub = frames_of(100_000, seed=1)
    sent = sub.rows()
    sent_set = set(sent)
    for p in PROTOCOLS:
        for prob in (0.001, 0.01):
            wire = W.corrupt(encode_frames(sub, p), prob, np.random.default_rng(2))
            out, c = decode_all(wire.data, p, 10)
            got = out.rows()
            got_set = set(got)
            intact = [r for r, ok in zip(sent, wire.intact) if ok]
            print(f"| {p} | {100 * prob:g} % | {len(sent)} | {len(intact)} | {len(got)} | "
                  f"{sum(r in got_set for r in intact)} | {sum(r not in sent_set for r in got)} | {c.dropped} |")


if __name__ == "__main__":
    main()
