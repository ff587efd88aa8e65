"""The cost of the answer's friction band in the main job (taxel.jobs.friction_band), per
material and in all, on 1 and 2 workers, side by side in one run.

The folders are the main job's PZT and PVDF front records (tests/data/answer: probe-front.json
with a recommended and the thesis design); as in `taxel demo`, the study store in each folder
already holds the probe front's own 2D press of each answer design (sticking), written here
first (optimize.probe.stored_press: the same press the probe front makes; not timed), so the
band solves one 2D press per design and law not stored: with the rig's "unknown" coefficient,
the frictionless press of each design. Each configuration is run `--repeat` times on fresh
copies of the folders; the median wall time is printed with the load average.

Measured (two runs each, load 6.8-8.8 on 2 cores, four helpers running): both materials,
four frictionless 2D presses, median 174.8 s on 1 worker and 238.8 s on 2 (ratio 0.73: on a
saturated machine the second worker only adds its cluster's start); per folder 68-115 s
(PZT), 83-172 s (PVDF). Not the ~15 s the demo allows: see docs/guide/silicone-and-contact.md.

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/friction_band_job.py [--repeat 3]
writes benchmarks/out/friction_band_job.json.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import tempfile
import time
from pathlib import Path

from taxel.jobs.friction_band import friction_band
from taxel.optimize import spec as O
from taxel.optimize.probe import press_scene, stored_press
from taxel.optimize.answer_folder import FolderAnswer
from taxel.studies.store import Store

DATA = Path(__file__).resolve().parents[1] / "tests" / "data" / "answer"
NAMES = ("thesis-pzt-front", "thesis-pvdf-front")


def prepared(root: Path) -> list[Path]:
    """Copies of the front folders with the probe front's own presses of the answer's designs stored."""
    out = []
    for name in NAMES:
        folder = root / name
        shutil.copytree(DATA / name, folder)
        probe = O.load_optimization(name.replace("-front", "-probe-front"), folder)
        a = FolderAnswer.read(folder)
        store = Store(folder)
        try:
            for d in a.answer_designs(("recommended", a.reference.label)):
                stored_press(store, press_scene(probe.scene_data(d.vector(probe.names)), probe.spec.press),
                             probe.spec.press)
        finally:
            store.close()
        out.append(folder)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    base = Path(tempfile.mkdtemp(prefix="friction-band-"))
    seed = prepared(base / "seed")
    rows = {}
    for workers in (1, 2):
        runs = []
        for k in range(args.repeat):
            root = base / f"w{workers}-{k}"
            folders = [Path(shutil.copytree(f, root / f.name)) for f in seed]
            load = os.getloadavg()[0]
            per = {}
            t0 = time.perf_counter()
            for f in folders:
                t = time.perf_counter()
                rec = json.loads(friction_band(f, workers=workers).read_text())
                per[f.name] = {"seconds": time.perf_counter() - t, "presses": rec["presses"]}
            runs.append({"seconds": time.perf_counter() - t0, "load": load, "folders": per})
            each = ", ".join(f"{n} {v['seconds']:.1f} s, {v['presses']} presses" for n, v in per.items())
            print(f"workers {workers}, run {k + 1}: {runs[-1]['seconds']:.1f} s for both materials ({each}); "
                  f"load {load:.1f}", flush=True)
        rows[workers] = {"median_seconds": statistics.median(r["seconds"] for r in runs), "runs": runs}
    print("median wall for both materials: " + ", ".join(f"{w} worker(s) {r['median_seconds']:.1f} s"
                                                          for w, r in rows.items())
          + f"; ratio 1/2 workers {rows[1]['median_seconds'] / rows[2]['median_seconds']:.2f}")
    Path("benchmarks/out").mkdir(parents=True, exist_ok=True)
    Path("benchmarks/out/friction_band_job.json").write_text(json.dumps(rows, indent=1))
    shutil.rmtree(base, ignore_errors=True)


if __name__ == "__main__":
    main()
