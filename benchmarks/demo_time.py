"""The main job's time, stage by stage: `taxel demo` run as a whole process (as `make demo`
runs it, MKL_NUM_THREADS=1), its stage lines (each prints its own seconds) collected into
one table with the load average before and during (sampled every 10 s), and the
process's wall time and the CPU time of its whole process tree (psutil, every 0.5 s: each
process's last reading summed, its Dask workers included; a process living under 0.5 s may
be missed), beside the job's own (its waited-for children's rusage, which misses the Dask
workers). A cold cache: XDG_CACHE_HOME is an empty folder (a fresh clone's). On a machine
shared with other jobs the wall time is not the job's: the quiet projection is the CPU time
of each step over the workers it has. docs/getting-started.md quotes it.

    python benchmarks/demo_time.py [--out /tmp/demo-time] [--no-answer-3d]
"""

from __future__ import annotations

import argparse
import os
import tempfile
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
    import psutil
    cache = tempfile.mkdtemp(prefix="taxel-cold-cache-")
    env = {**os.environ, "MKL_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "XDG_CACHE_HOME": cache}
    loads, done, cpu = [os.getloadavg()[0]], threading.Event(), {}

    def sample():
        while not done.wait(10):
            loads.append(os.getloadavg()[0])

    def tree(pid):
        while not done.wait(0.5):
            try:
                procs = [psutil.Process(pid)] + psutil.Process(pid).children(recursive=True)
            except psutil.NoSuchProcess:
                continue
            for q in procs:
                try:
                    t = q.cpu_times()
                    cpu[(q.pid, q.create_time())] = t.user + t.system
                except psutil.NoSuchProcess:
                    pass
    threading.Thread(target=sample, daemon=True).start()
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    threading.Thread(target=tree, args=(proc.pid,), daemon=True).start()
    stdout, stderr = proc.communicate()
    out = subprocess.CompletedProcess(cmd, proc.returncode, stdout, stderr)
    wall = time.perf_counter() - t0
    done.set()
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    lines = [ln for ln in out.stdout.splitlines() if "it/s" not in ln and "point/s" not in ln]
    print(f"{' '.join(cmd)}: exit {out.returncode}, {wall:.0f} s wall, {sum(cpu.values()):.0f} s CPU of the process "
          f"tree ({len(cpu)} processes; {ru.ru_utime + ru.ru_stime:.0f} s by the job's rusage, which misses its Dask "
          f"workers), a cold cache; load average {loads[0]:.1f} before, {min(loads):.1f}-{max(loads):.1f} "
          f"during ({len(loads)} samples)")
    for ln in lines:
        if STAGE.search(ln) or ln.startswith("["):
            print("  " + ln.strip())
    if out.returncode:
        print(out.stderr[-2000:])


if __name__ == "__main__":
    main()
