"""The main job's time, stage by stage: `taxel demo` run as a whole process (as `make demo`
runs it, MKL_NUM_THREADS=1), its stage lines (each prints its own seconds) collected into
one table with the load average before and during (sampled every 10 s), and the
process's wall time and its own CPU time (its Dask workers' is not counted). docs/getting-started.md quotes it.

    python benchmarks/demo_time.py [--out /tmp/demo-time] [--no-answer-3d]
"""

from __future__ import annotations

import argparse
import os
import re
import resource
import subprocess
import sys
import threading
import time
from pathlib import Path

STAGE = re.compile(r"(\d+(?:\.\d+)?) s\b")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="/tmp/demo-time")
    ap.add_argument("--no-answer-3d", dest="answer_3d", action="store_false")
    a = ap.parse_args()
    taxel = Path(sys.executable).with_name("taxel")
    cmd = [str(taxel), "demo", "--out", a.out] + ([] if a.answer_3d else ["--no-answer-3d"])
    env = {**os.environ, "MKL_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
    loads, done = [os.getloadavg()[0]], threading.Event()

    def sample():
        while not done.wait(10):
            loads.append(os.getloadavg()[0])
    threading.Thread(target=sample, daemon=True).start()
    t0 = time.perf_counter()
    out = subprocess.run(cmd, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    done.set()
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    lines = [ln for ln in out.stdout.splitlines() if "it/s" not in ln and "point/s" not in ln]
    print(f"{' '.join(cmd)}: exit {out.returncode}, {wall:.0f} s wall, {ru.ru_utime + ru.ru_stime:.0f} s CPU "
          f"(the job's own process: its Dask workers are not counted); load average {loads[0]:.1f} before, {min(loads):.1f}-{max(loads):.1f} "
          f"during ({len(loads)} samples)")
    for ln in lines:
        if STAGE.search(ln) or ln.startswith("["):
            print("  " + ln.strip())
    if out.returncode:
        print(out.stderr[-2000:])


if __name__ == "__main__":
    main()
