"""The cost of the answer's friction band in the main job (taxel.jobs.friction_band), per
material and in all: each folder on its own pool of 2 workers (friction_band: one cluster
per folder) against both folders' presses in one pool of 2 (friction_bands,
one task per design and law: how `taxel demo` runs them), side by side in one run.

The folders are the main job's PZT and PVDF front records (tests/data/answer: probe-front.json
with a recommended and the thesis design); as in `taxel demo`, the study store in each folder
already holds the probe front's own 2D press of each answer design (sticking), written here
first (optimize.probe.stored_press: the same press the probe front makes; not timed), so the
band solves one 2D press per design and law not stored: with the rig's "unknown" coefficient,
the frictionless press of each design. Each configuration is run `--repeat` times on fresh
copies of the folders; the median wall time is printed with the load average.

Measured before (two runs each, load 6.8-8.8 on 2 cores, four helpers running): both
materials, four frictionless 2D presses, median 174.8 s on 1 worker and 238.8 s on 2 (ratio
0.73: on a saturated machine the second worker only adds its cluster's start). The per-folder
against one-pool numbers: docs/benchmarks.md ("The main job's time").

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

from taxel.jobs.friction_band import friction_band, friction_bands
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
    for mode in ("per folder", "one pool"):
        runs = []
        for k in range(args.repeat):
            root = base / f"{mode.replace(' ', '-')}-{k}"
            folders = [Path(shutil.copytree(f, root / f.name)) for f in seed]
            load = os.getloadavg()[0]
            t0 = time.perf_counter()
            if mode == "per folder":
                outs = [friction_band(f, workers=2) for f in folders]
            else:
                outs = friction_bands(folders, workers=2)
            presses = sum(json.loads(o.read_text())["presses"] for o in outs)
            runs.append({"seconds": time.perf_counter() - t0, "load": load, "presses": presses})
            print(f"{mode}, run {k + 1}: {runs[-1]['seconds']:.1f} s for both materials ({presses} presses); "
                  f"load {load:.1f}", flush=True)
        rows[mode] = {"median_seconds": statistics.median(r["seconds"] for r in runs), "runs": runs}
    print("median wall for both materials on 2 workers: " + ", ".join(
        f"{m} {r['median_seconds']:.1f} s" for m, r in rows.items())
        + f"; ratio per folder / one pool {rows['per folder']['median_seconds'] / rows['one pool']['median_seconds']:.2f}")
    Path("benchmarks/out").mkdir(parents=True, exist_ok=True)
    Path("benchmarks/out/friction_band_job.json").write_text(json.dumps(rows, indent=1))
    shutil.rmtree(base, ignore_errors=True)


if __name__ == "__main__":
    main()
