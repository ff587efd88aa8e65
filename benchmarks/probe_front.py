"""The thesis PZT and PVDF fronts under the rig's probe (optimize.probe_front), as the
main job runs them: the linear pressure-patch front (2D search, 3D verification,
confirmation), then the probe-Yeoh front (2D presses corrected from the linear
front; --presses-3d N: N of its front designs pressed in 3D; with --full, the whole
front and the thesis design pressed in 3D), each step timed. Prints each probe
front with its estimated errors (per 3D-pressed design its estimator's error and
whether it is within 2 %), the movements of the linear front's designs, the
solves spent against pressing every candidate in 3D, and the wall time of each front
step (the main job's budget). The probe-front table of docs/guide/optimization.md is this output.

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/probe_front.py [--full | --presses-3d N]
     [--only thesis-pzt-front] [--out DIR]
(a rerun reads every solve from the folders' stores: delete DIR to time it again)
"""

import json
import sys
import time
from pathlib import Path

from taxel.jobs.main_job import front
from taxel.optimize.probe_front import PROBE_FILE

MISS = "product estimate's largest miss (sensitivity, crosstalk)"


def main():
    full = "--full" in sys.argv
    out = Path(sys.argv[sys.argv.index("--out") + 1]) if "--out" in sys.argv else Path("out/probe-front")
    n3 = int(sys.argv[sys.argv.index("--presses-3d") + 1]) if "--presses-3d" in sys.argv else 0
    names = [sys.argv[sys.argv.index("--only") + 1]] if "--only" in sys.argv else ["thesis-pzt-front", "thesis-pvdf-front"]
    seconds = {}
    for name in names:
        t0, c0 = time.perf_counter(), time.process_time()
        front(out / name, name, small=False, full=full, presses_3d=n3)
        seconds[name] = (time.perf_counter() - t0, time.process_time() - c0)
    print("\nfront, step seconds (wall, this process's CPU), 2D presses, 3D presses, 3D presses for every candidate, thesis dominated "
          "(linear 3D / probe), order by sensitivity unchanged")
    for name, s in seconds.items():
        rec = json.loads((out / name / PROBE_FILE).read_text())
        sp, rk = rec["spent"], rec["ranking"]
        print(f"{name}: {s[0]:.0f} s, {s[1]:.0f} s, {sp['2D presses']}, {sp['3D presses']}, "
              f"{sp['3D solves if every candidate were pressed in 3D']}, "
              f"{rk['thesis dominated (linear 3D)']} / {rk['thesis dominated (probe)']}, "
              f"{rk['same order by sensitivity']}")
        if sp["3D presses"]:
            print(f"  {sp['3D presses']} 3D presses in {sp['3D press seconds']:.0f} s on {rec['press_3d_model']}; "
                  f"the estimate's largest miss (sensitivity, crosstalk): "
                  f"{sp[MISS]}")
            for r in rec["front"] + [rec["reference"]]:
                if r.get("how") == "3D press":
                    before = r.get("estimate before the 3D press (V/N, crosstalk)")
                    print(f"  3D press {r['x']}: {r['sensitivity (V/N)']:.4f} V/N, {100 * r['crosstalk']:.3g} %, "
                          f"estimated error {100 * r['estimated error']:.2f} % "
                          f"({'within' if r['within 2 %'] else 'above'} 2 %)"
                          + (f", estimated before {before[0]:.4f} V/N, {100 * before[1]:.3g} %" if before else ""))


if __name__ == "__main__":
    main()
