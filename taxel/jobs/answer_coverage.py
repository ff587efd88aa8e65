"""The answer's coverage and localization error (main job): for an optimization folder
whose requirements name them, the influence metrics (optimize.coverage) of the thesis
design and of the design the answer recommends (reports.answer.headline_front), again
until the recommended design has them: a recommended design that fails coverage loses
to the next candidate, which is then solved. A localization_error requirement, whose
margin the choice weighs, has every candidate of the records solved first. Each design's row goes to
OUT/coverage.json (optimize.coverage.RECORD), which the answer reads.

The metrics come from the 2D section on linear silicone (the base scene of the linear
front), whatever model the answer's sensitivity comes from: coverage asks whether a
taxel's peak clears 3 times the noise, which the 2D section's influence functions
screen for (taxel.analyses.surface.coverage states how far they are from 3D presses).
Cost: 9 static 2D solves per design not yet in the folder's influence store.
"""

from __future__ import annotations

import time
from pathlib import Path


def answer_coverage(front_dir: Path) -> float:
    """Fill OUT/coverage.json for the answer of `front_dir` (a built-in optimization's folder);
    returns the seconds it took."""
    from taxel.optimize import coverage
    from taxel.optimize import spec as O
    from taxel.reports.answer import headline_front
    t0 = time.perf_counter()
    front_dir = Path(front_dir)
    prob = O.load_optimization(front_dir.name, front_dir)
    tried: list[dict] = []
    a = headline_front(front_dir)
    if a is not None and any(q.metric in coverage.INFLUENCE_METRICS and not q.limit for q in a.requirements):
        for x in (x for x in _candidates(front_dir) if all(n in x for n in prob.names)):   # a weighed margin:
            coverage.add(front_dir, {n: x[n] for n in prob.names}, prob.influence_metrics([x[n] for n in prob.names]))
    while True:
        a = headline_front(front_dir)
        if a is None or not {q.metric for q in a.requirements} & set(coverage.INFLUENCE_METRICS):
            break
        todo = []
        for d in (a.thesis, a.recommended):
            if d is None or all(d.values.get(m) is not None for m in coverage.INFLUENCE_METRICS
                                if any(q.metric == m for q in a.requirements)):
                continue
            x = {"silicone_above": d.silicone_above_mm, "silicone_below": d.silicone_below_mm, "gap": d.gap_mm}
            if not any(coverage.same(t, x) for t in tried):
                todo.append(x)
        if not todo:
            break
        for x in todo:
            tried.append(x)
            got = prob.influence_metrics([x[n] for n in prob.names])
            coverage.add(front_dir, {n: x[n] for n in prob.names}, got)
    return time.perf_counter() - t0


def _candidates(front_dir: Path) -> list[dict]:
    """Every design of the answer's records ({variable: mm}): the probe front's and the 3D front's
    rows and their reference."""
    import json
    out: list[dict] = []
    for name, key in (("probe-front.json", "front"), ("front-3d.json", "front_3d")):
        path = Path(front_dir) / name
        if path.exists():
            rec = json.loads(path.read_text())
            for row in [rec.get("reference") or {}] + rec.get(key, []):
                x = {k.split(" (")[0]: v for k, v in row.items() if k.endswith("(mm)")}
                if x and x not in out:
                    out.append(x)
    return out
