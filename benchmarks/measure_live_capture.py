"""A live capture from the simulated rig over a pseudo-terminal: 10 channels x
2 kHz (thesis-bench) for 60 s; frames lost against the simulator's truth, and the
CPU the capture used (this process; the simulator runs in its own).

    python benchmarks/measure_live_capture.py [--seconds 60] [--protocol taxel-cobs]
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from taxel.studies.bench import folder as F
from taxel.studies.bench.capture import capture, open_port
from taxel.studies.bench.rig import load_rig, parse_rig


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--delay", type=float, default=3.0)
    a = ap.parse_args()
    tmp = Path(tempfile.mkdtemp(prefix="taxel-live-"))
    cmd = [sys.executable, "-m", "taxel.cli", "measure", "simulate", "thesis-bench", "--scene", "thesis-pzt-3x3-2d",
           "--input", "presses", "--pty", "--seconds", str(a.seconds), "--delay", str(a.delay),
           "--truth", str(tmp / "truth"), "--linger", "2"]
    sim = subprocess.Popen(cmd, stdout=subprocess.PIPE, text=True)
    try:
        url = None
        while url is None:
            line = sim.stdout.readline()
            if not line:
                raise SystemExit("the simulator ended before serving")
            if line.startswith("serving on "):
                url = line.split()[2]
        base = load_rig("thesis-bench")
        rig = parse_rig({**base.model_dump(), "port": {**base.port.model_dump(), "url": url}}, si_numbers=True)
        port = open_port(rig)
        r0, t0 = resource.getrusage(resource.RUSAGE_SELF), time.monotonic()
        res = capture(rig, tmp / "m", seconds=a.seconds + a.delay + 5, port=port)
        r1, wall = resource.getrusage(resource.RUSAGE_SELF), time.monotonic() - t0
        sim.wait(timeout=30)
    finally:
        if sim.poll() is None:
            sim.kill()
            sim.wait()
    truth = np.load(tmp / "truth" / "truth.npz")
    m = F.read(tmp / "m")
    sent = len(truth["seq"])
    same = len(m) == sent and np.array_equal(m.counts, truth["counts"]) and np.array_equal(m.seq, truth["seq"])
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    s = m.stats
    print(f"sent {sent} frames ({a.seconds:g} s at 2 kHz, 10 channels) over {url}")
    print(f"captured {len(m)} frames; identical to the truth: {same}; lost {sent - len(m)}; "
          f"seq gaps {s['seq_gaps']}, CRC failures {s['crc_failures']}, resyncs {s['resyncs']}")
    print(f"measured rate {s['rate_Hz']:.3f} Hz, jitter {s['jitter_us']:.2f} us; ended: {res.ended}")
    print(f"capture CPU {cpu:.2f} s over {wall:.1f} s wall = {100 * cpu / wall:.1f} % of one core; "
          f"raw.bin {os.path.getsize(tmp / 'm' / 'raw.bin')} bytes; folder {tmp / 'm'}")


if __name__ == "__main__":
    main()
