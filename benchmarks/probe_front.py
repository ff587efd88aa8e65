"""The thesis PZT and PVDF fronts under the rig's probe (optimize.probe_front), as the
main job runs them: the linear pressure-patch front (2D search, 3D verification,
confirmation), then the probe-Yeoh front (2D presses corrected from the linear
front; with --full, 3D presses of its designs), each step timed. Prints each probe
front with its estimated errors, the movements of the linear front's designs, the
solves spent against pressing every candidate in 3D, and the wall time of each front
step (the main job's budget). The README's probe-front table is this output.

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/probe_front.py [--full] [--out DIR]
(a rerun reads every solve from the folders' stores: delete DIR to time it again)
"""

import json
import sys
import time
from pathlib import Path

from taxel.jobs.main_job import front
from taxel.optimize.probe_front import PROBE_FILE


def main():
    full = "--full" in sys.argv
    out = Path(sys.argv[sys.argv.index("--out") + 1]) if "--out" in sys.argv else Path("out/probe-front")
    seconds = {}
    for name in ("thesis-pzt-front", "thesis-pvdf-front"):
        t0 = time.perf_counter()
        front(out / name, name, small=False, full=full)
        seconds[name] = time.perf_counter() - t0
    print("\nfront, step seconds, 2D presses, 3D presses, 3D presses for every candidate, thesis dominated "
          "(linear 3D / probe), order by sensitivity unchanged")
    for name, s in seconds.items():
        rec = json.loads((out / name / PROBE_FILE).read_text())
        sp, rk = rec["spent"], rec["ranking"]
        print(f"{name}: {s:.0f} s, {sp['2D presses']}, {sp['3D presses']}, "
              f"{sp['3D solves if every candidate were pressed in 3D']}, "
              f"{rk['thesis dominated (linear 3D)']} / {rk['thesis dominated (probe)']}, "
              f"{rk['same order by sensitivity']}")


if __name__ == "__main__":
    main()
