"""The Fig. 2.5 study (7 thicknesses x 5 forces x 2 materials = 70 points, 2D plane
stress, default mesh: 0.8 % voltage accuracy, benchmarks/taxel_2d.py) with 1 and 2
workers, the speed-up, and a fully cached rerun.

With --thesis: the thesis's own model instead (studies/builtin/fig-2-5-thesis.toml,
or --study fig-2-8-thesis): the same grid with linear and Yeoh plane-stress silicone
(fem.hyperelastic), on 2 workers; prints the wall time of the run, the solve
seconds of the linear and of the Yeoh points, how many Yeoh points stopped short of
their force (and where), and the Yeoh voltage against the linear one per point.

Run: python benchmarks/study_fig25.py [--thesis [--study NAME] [--out DIR]]
"""

import argparse
import shutil
import statistics
import tempfile
import time
from pathlib import Path

from taxel.studies.execute import run
from taxel.studies.spec import load_study
from taxel.studies.store import tidy_rows


def timed_run(study, out, workers):
    t = time.perf_counter()
    summary = run(study, out, workers=workers, progress=False)
    return time.perf_counter() - t, summary


def workers_and_cache():
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


def thesis(name: str, out: Path | None):
    study = load_study(name)
    tmp = None if out else Path(tempfile.mkdtemp())
    folder = out or tmp / name
    try:
        wall, summ = timed_run(study, folder, 2)
        rows = tidy_rows(folder)
    finally:
        if tmp:
            shutil.rmtree(tmp)
    print(f"{name}: {summ.total} points ({summ.done} computed, {summ.cached} cached, {summ.failed} failed), "
          f"{wall:.1f} s wall on 2 workers")
    by = {}
    for r in rows:
        by.setdefault(r["silicone"], []).append(r)
    for label, rs in by.items():
        secs = [r.get("seconds", 0.0) for r in rs]
        stopped = [r for r in rs if r.get("stopped_at")]
        print(f"  {label:<14} {len(rs)} points, solve {sum(secs):7.1f} s in all (median {statistics.median(secs):.2f} s"
              f" per point), {len(stopped)} stopped short"
              + (f" (at {min(r['stopped_at'] for r in stopped):.3g}-{max(r['stopped_at'] for r in stopped):.3g} N)"
                 if stopped else ""))
    lin = {_key(r): r for r in by.get("linear", [])}
    key_out = "crosstalk" if "crosstalk" in rows[0] else "pressed_voltage"
    print(f"  Yeoh / linear - 1 of {key_out} (linear at the Yeoh point's reached force, V/N scaling):")
    diffs = []
    for r in sorted(by.get("Yeoh (thesis)", []), key=lambda r: (r["piezo"], *(float(str(r[k]).split()[0]) for k in
                                                                               ("silicone_thickness", "gap", "force") if k in r))):
        ref = lin.get(_key(r))
        if r["status"] != "done" or ref is None or ref["status"] != "done" or not ref.get(key_out):
            continue
        scale = (r["stopped_at"] / _force(r)) if r.get("stopped_at") else 1.0   # linear: proportional to force
        ratio = r[key_out] / (ref[key_out] * (scale if key_out == "pressed_voltage" else 1.0)) - 1
        diffs.append(ratio)
        print(f"    {r['piezo']:<5} {_rest(r):<34} {100 * ratio:+7.2f} %" + (
            f"   (stopped at {r['stopped_at']:.3g} N)" if r.get("stopped_at") else ""))
    if diffs:
        print(f"  median {100 * statistics.median(diffs):+.2f} %, range {100 * min(diffs):+.2f} to "
              f"{100 * max(diffs):+.2f} %")


def _key(r):
    return tuple((k, v) for k, v in r.items() if k in ("piezo", "silicone_thickness", "gap", "force"))


def _force(r):
    return float(str(r["force"]).split()[0])


def _rest(r):
    return ", ".join(f"{k} {r[k]}" for k in ("silicone_thickness", "gap", "force") if k in r)


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--thesis", action="store_true", help="the thesis's model (plane stress, Yeoh) beside linear")
    ap.add_argument("--study", default="fig-2-5-thesis")
    ap.add_argument("--out", type=Path, default=None, help="keep the study folder here")
    args = ap.parse_args()
    thesis(args.study, args.out) if args.thesis else workers_and_cache()
