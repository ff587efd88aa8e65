"""One optimization spec, run: the reference design's evaluation, then the optimum
(spec.optimize) or with [pareto] the sensitivity-crosstalk front (spec.front),
gathered into one OptimizationResult."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from taxel.optimize.result import Constraint, OptimizationResult
from taxel.optimize.spec import Optimization, OptimizeError, front, magnitude, optimize
from taxel.studies.store import Store


def reference_x(problem: Optimization) -> np.ndarray | None:
    """The spec's reference design in the variables' units, or None without one."""
    ref = problem.spec.reference
    if not ref:
        return None
    missing = [n for n in problem.names if n not in ref]
    if missing:
        raise OptimizeError(f"reference: no value for {', '.join(missing)}; give every variable, e.g. "
                            f"{missing[0]} = \"1 mm\"")
    return np.array([magnitude(ref[n], u, f"reference.{n}")[0] for n, u in zip(problem.names, problem.units)])


def reference_evaluation(problem: Optimization) -> dict | None:
    """{"x": {name: value}, metric: value, ...} of the reference design, or None."""
    x = reference_x(problem)
    if x is None:
        return None
    return {"x": dict(zip(problem.names, x.tolist())), **problem.evaluate(x)}


def run(problem: Optimization, path: str | Path | None = None, workers: int = 2) -> OptimizationResult:
    """Run `problem` (its store: problem.out): the optimum, or the front when the spec
    has [pareto] (its runs load the spec from `path` on `workers` Dask workers)."""
    reference = reference_evaluation(problem)
    (sense, metric), = problem.spec.objective.items()
    result = OptimizationResult(problem.spec.name, problem.names, list(problem.units), sense, metric,
                                [Constraint(*c) for c in problem.constraints], reference=reference,
                                requirements=dict(problem.spec.requirements))
    if problem.spec.pareto:
        if path is None:
            raise OptimizeError(f"{problem.spec.name}: a front's runs read the optimization file; pass its path")
        result.runs = front(problem, path, workers=workers)
    else:
        result.optimum = optimize(problem)
    if problem.out is not None:
        store = Store(problem.out)
        try:
            result.fem_solves = len(store.rows())
        finally:
            store.close()
    return result
