"""The Fig. 2.5 study in 3D (the built-in `fig-2-5-3d`: 70 points, PZT and PVDF,
quarter models) on 2 workers (local Dask), timed; the pressed-taxel voltages of
the PZT points at 1 N next to the 2D plane-stress study's (`fig-2-5`, one worker),
so the 3D/2D ratio is seen.

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/study_fig25_3d.py [--workers 2]
"""

import argparse
import shutil
import tempfile
import time
from pathlib import Path

from taxel.studies.execute import run
from taxel.studies.spec import load_study
from taxel.studies.store import tidy_rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args()
    tmp = Path(tempfile.mkdtemp())
    try:
        study = load_study("fig-2-5-3d")
        t = time.perf_counter()
        s3 = run(study, tmp / "3d", workers=args.workers, progress=False)
        t3 = time.perf_counter() - t
        t = time.perf_counter()
        s2 = run(load_study("fig-2-5"), tmp / "2d", workers=1, progress=False)
        t2 = time.perf_counter() - t
        print(f"fig-2-5-3d: {len(study.points())} points, {s3.done} computed, {s3.failed} failed, "
              f"{t3:.1f} s on {args.workers} workers ({t3 / max(s3.done, 1):.2f} s per point)")
        print(f"fig-2-5 (2D plane stress): {s2.done} computed in {t2:.1f} s on 1 worker")
        rows = {}
        for name in ("3d", "2d"):
            for r in tidy_rows(tmp / name):
                rows.setdefault((r["piezo"], r["silicone_thickness"], r["force"]), {})[name] = r["pressed_voltage"]
        print(f"{'piezo':<6} {'k':>8} {'3D V':>9} {'2D V':>9} {'2D/3D':>6}   (1 N)")
        for (piezo, k, f), v in sorted(rows.items(), key=lambda x: (str(x[0][0]), str(x[0][1]))):
            force = f if isinstance(f, (int, float)) else float(str(f).split()[0])
            if "3d" in v and "2d" in v and abs(force - 1) < 1e-9:
                print(f"{piezo:<6} {str(k):>8} {v['3d']:>9.4f} {v['2d']:>9.4f} {v['2d'] / v['3d']:>6.2f}")
    finally:
        shutil.rmtree(tmp)


if __name__ == "__main__":
    main()
