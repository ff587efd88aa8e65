"""The answer's coverage and localization error (main job): for an optimization folder
whose requirements name them, the influence metrics (optimize.coverage) of the thesis
design, of the design the answer recommends (optimize.answer_folder.FolderAnswer) and of each
design a priced relaxation names, again until all of them have them: a recommended
design that fails coverage loses to the next candidate, which is then solved. Both
metrics are limits (met or not), so judging in the answer's own order is exact
(optimize.coverage.judge_lazily says why): the candidates the choice never reaches are
not mapped. The owner writes each design's row to OUT/coverage.json (optimize.coverage.RECORD,
FolderAnswer.add_coverage), where it reads them.

The metrics come from each design's 3D surface map on linear silicone (optimize.coverage:
a 2D design made 3D on its array mesh, the rig's 4 mm punch as the footprint), whatever
model the answer's sensitivity comes from: the coverage minimum is searched over the
whole surface between the outer taxels, and a 100 % coverage is judged on it. A design
whose check fails gets the error in its row and is not recommended. Cost: one map per
design not yet in OUT/maps (the thesis PZT design: 46 243 unknowns, four
factorizations, about 11 s of CPU: benchmarks/surface_map.py); the main job runs each
folder's on a worker beside the presses (taxel.jobs.answer_3d.answer_designs).
"""

from __future__ import annotations

import time
from pathlib import Path


def answer_coverage(front_dir: Path) -> float:
    """Fill OUT/coverage.json for the answer of `front_dir` (a built-in optimization's folder);
    returns the seconds it took."""
    from taxel.optimize import coverage
    from taxel.optimize import spec as O
    from taxel.optimize.answer_folder import FolderAnswer
    t0 = time.perf_counter()
    front_dir = Path(front_dir)
    prob = O.load_optimization(front_dir.name, front_dir)
    tried: list = []
    while True:
        a = FolderAnswer.read(front_dir)
        if a is None or not {q.metric for q in a.requirements} & set(coverage.INFLUENCE_METRICS):
            break
        todo = []
        for d in (a.reference, a.recommended, *(d for _, d in a.priced)):
            if d is None or all(d.metrics.get(q.metric) is not None or q.metric in d.metrics.get(coverage.CHECK_ERRORS, {})
                                for q in a.requirements if q.metric in coverage.INFLUENCE_METRICS):
                continue
            if not any(d.same(t) for t in tried + todo):
                todo.append(d)
        if not todo:
            break
        for d in todo:
            tried.append(d)
            a.add_coverage(d, prob.influence_metrics(d.vector(prob.names)))
    from taxel.reports.coverage_map import draw_folder
    draw_folder(front_dir)                 # the designs' coverage maps, on the optimization page
    return time.perf_counter() - t0
