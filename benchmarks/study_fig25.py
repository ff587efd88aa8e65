"""The Fig. 2.5 study (7 thicknesses x 5 forces x 2 materials = 70 points, 2D plane
stress, default mesh: 0.8 % voltage accuracy, benchmarks/taxel_2d.py) with 1 and 2
workers, the speed-up, and a fully cached rerun.

Run: python benchmarks/study_fig25.py
"""

import shutil
import tempfile
import time
from pathlib import Path

from taxel.studies.execute import run
from taxel.studies.spec import load_study


def timed_run(study, out, workers):
    t = time.perf_counter()
    summary = run(study, out, workers=workers, progress=False)
    return time.perf_counter() - t, summary


def main():
    study = load_study("fig-2-5")
    tmp = Path(tempfile.mkdtemp())
    try:
        t1, s1 = timed_run(study, tmp / "one", 1)
        t2, s2 = timed_run(study, tmp / "two", 2)
        tc, sc = timed_run(study, tmp / "two", 2)
    finally:
        shutil.rmtree(tmp)
    n = len(study.points())
    print(f"Fig. 2.5 grid: {n} points")
    print(f"{'1 worker (in-process)':<28} {t1:7.2f} s   {s1.done} computed")
    print(f"{'2 workers (local Dask)':<28} {t2:7.2f} s   {s2.done} computed   speed-up {t1 / t2:.2f}x")
    print(f"{'cached rerun':<28} {tc:7.2f} s   {sc.cached} cached, {sc.done} computed")


if __name__ == "__main__":
    main()
