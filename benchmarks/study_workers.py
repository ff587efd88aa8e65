"""How Dask's workers are started, side by side: a 2-worker local cluster whose
workers are forked from the caller ("fork", chosen for a single-threaded caller),
forked from a clean fork server that preloads the FEM stack ("forkserver", chosen
when the caller runs other threads) or spawned cold ("spawn"). For each: the time
to start the cluster and to run the 70-point Fig. 2.5 study on it, each run in a
fresh process, interleaved and repeated, medians; the in-process 1-worker study
is the baseline of the speed-up.

Run: python benchmarks/study_workers.py [--repeats 3]
"""

import argparse
import json
import statistics
import subprocess
import sys

CHILD = r"""
import json, sys, tempfile, time
from pathlib import Path
from taxel.studies import execute
from taxel.studies.spec import load_study
method = sys.argv[1]
study = load_study("fig-2-5")
with tempfile.TemporaryDirectory() as tmp:
    t = time.perf_counter()
    if method == "in-process":
        s = execute.run(study, Path(tmp) / "s", workers=1, progress=False)
        start = 0.0
    else:
        cluster = execute.local_cluster(2, method)
        start = time.perf_counter() - t
        execute.local_cluster = lambda n: cluster
        s = execute.run(study, Path(tmp) / "s", workers=2, progress=False)
    print(json.dumps({"start": start, "seconds": time.perf_counter() - t, "done": s.done}))
"""
METHODS = ("in-process", "fork", "forkserver", "spawn")


def once(method: str) -> tuple[float, float]:
    out = subprocess.run([sys.executable, "-c", CHILD, method], check=True,
                         capture_output=True, text=True).stdout
    rec = json.loads(out.strip().splitlines()[-1])
    assert rec["done"] == 70, rec
    return rec["start"], rec["seconds"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    n = ap.parse_args().repeats
    runs = {m: [] for m in METHODS}
    for _ in range(n):                 # interleaved, so a load change hits every method
        for m in METHODS:
            runs[m].append(once(m))
    base = statistics.median(t for _, t in runs["in-process"])
    print(f"{'start method':<12} {'cluster start':>14} {'study total':>12} {'speed-up':>9}")
    for m in METHODS:
        start = statistics.median(s for s, _ in runs[m])
        total = statistics.median(t for _, t in runs[m])
        print(f"{m:<12} {start:12.2f} s {total:10.2f} s {base / total:8.2f}x")


if __name__ == "__main__":
    main()
