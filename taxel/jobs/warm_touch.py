"""The answer's warm touch (main job): a warm finger on the thesis design of an
optimization folder's material, through the bench's charge amplifier and notch, with the
minimum detectable force on the bench's converter with the simulated rig's mains hum (as
the answer's own, taxel.jobs.answer_readout); written to OUT/warm-touch.json (the
format of taxel.analyses.solves.warm_touch.WarmTouchResult.write), which the report shows
twice: a row in the answer (reports.warm_touch.answer_row) and a "Warm touch" section on
the folder's page with the temperature field and the output traces (reports.warm_touch.section).

Model: the thesis's single taxel of that material (thesis-pzt-single-2d,
thesis-pvdf-single-2d: plane strain, 1 mm silicone above and below) with the scene's
default [warm_touch] (a 34 C finger held 1 s on a 23 C skin, 3 s simulated): one static
solve and one 2D conduction. Against 3D the plane-strain section overstates the PZT false
force by 37 % (docs/benchmarks.md, "A warm finger"; benchmarks/warm_touch.py).

Cost: 1-3 s per design beside the static solve (docs/benchmarks.md gives the measured
seconds of `taxel demo`).
"""

from __future__ import annotations

import time
from pathlib import Path

RIG = "thesis-bench"
SCENES = {"pzt": "thesis-pzt-single-2d", "pvdf": "thesis-pvdf-single-2d"}


def thesis_scene(folder: Path):
    """The thesis design's 2D scene of an optimization folder's material (thesis-MAT-front:
    MAT), on the bench's chain with the rig's hum, with a default warm touch."""
    from taxel import api
    from taxel.jobs.answer_readout import bench_chain
    material = Path(folder).name.split("-")[1]
    return api.load(SCENES[material]).replace(readout=bench_chain(), warm_touch={})


def warm_touch(folder: Path) -> float:
    """Solve the warm touch of the folder's thesis design into FOLDER/warm-touch.json;
    the seconds it took."""
    from taxel.analyses.model.problem import solve_model
    from taxel.analyses.solves.warm_touch import warm_touch as solve
    from taxel.studies.bench.rig import load_rig
    t0 = time.perf_counter()
    scene = thesis_scene(folder)
    res = solve(scene, static=solve_model(scene), rig=load_rig(RIG))
    res.write(folder)
    s = res.summary()
    mdf = s["min_detectable_force_N"]
    seconds = time.perf_counter() - t0
    print(f"      warm touch, {scene.name}: film +{s['film_rise_K']:.2f} K, false force "
          f"{1e3 * s['false_force_N']:.3g} mN" + ("" if mdf is None else
                                                   f" ({s['ratio']:.3g} x the minimum detectable {1e3 * mdf:.3g} mN)")
          + f", {seconds:.1f} s")
    return seconds
