"""Start-up cost of the `taxel` command, as whole processes.

    python benchmarks/cli_startup.py [--runs N]

Times, side by side in one run (median of N runs each, after one warm-up):
the bare interpreter (`python -c pass`), `taxel --help`, and a whole 2D solve
`taxel solve thesis-pzt-single-2d --json` (reading the scene, meshing, solving,
printing the record), and the solve's own time as the result records it, so the
rest is start-up. The machines are shared: read the medians and the ratios.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

TAXEL = str(Path(sys.executable).with_name("taxel"))


def wall(cmd: list[str]) -> tuple[float, str]:
    t0 = time.perf_counter()
    out = subprocess.run(cmd, capture_output=True, text=True, check=True)
    return time.perf_counter() - t0, out.stdout


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=7)
    n = ap.parse_args().runs
    cases = {"python -c pass": [sys.executable, "-c", "pass"],
             "taxel --help": [TAXEL, "--help"],
             "taxel solve thesis-pzt-single-2d --json": [TAXEL, "solve", "thesis-pzt-single-2d", "--json"]}
    times: dict[str, list[float]] = {k: [] for k in cases}
    solve_s = []
    for k, cmd in cases.items():
        wall(cmd)                                      # warm-up (file cache)
    for _ in range(n):                                 # interleaved, so drift hits every case alike
        for k, cmd in cases.items():
            t, out = wall(cmd)
            times[k].append(t)
            if k.startswith("taxel solve"):
                solve_s.append(json.loads(out)["times_s"]["total"])
    base = statistics.median(times["python -c pass"])
    print(f"{'command':<44}{'median':>9}{'min':>9}{'max':>9}{'x python':>10}")
    for k, ts in times.items():
        print(f"{k:<44}{statistics.median(ts):>8.3f}s{min(ts):>8.3f}s{max(ts):>8.3f}s"
              f"{statistics.median(ts) / base:>10.1f}")
    print(f"{'  of which the solve (mesh, assemble, solve)':<44}{statistics.median(solve_s):>8.3f}s")


if __name__ == "__main__":
    main()
