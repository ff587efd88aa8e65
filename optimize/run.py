"""One optimization spec, run: the reference design's evaluation, then the optimum
(spec.optimize) or with [pareto] the sensitivity-crosstalk front (optimize.front),
gathered into one OptimizationResult."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from taxel.optimize.result import Constraint, OptimizationResult
from taxel.optimize import coverage
from taxel.optimize.front import front
from taxel.optimize.relax import relax
from taxel.optimize.spec import Optimization, OptimizeError, magnitude, optimize
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


def run(problem: Optimization, path: str | Path | None = None, workers: int = 2,
        influence: str = "answer") -> OptimizationResult:
    """Run `problem` (its store: problem.out): the optimum, or the front when the spec
    has [pareto] (its runs load the spec from `path` on `workers` Dask workers). The
    influence metrics only [requirements] names (`required_influence_metrics`): of the
    reference design and the designs the run's answer reaches (`influence` "answer"), or
    of the reference design only ("reference": for a caller that judges another answer's
    designs itself, as the main job does the probe front's: taxel.jobs.answer_coverage).
    With "answer", each requirement binding the run's own answer is priced by searching
    again (optimize.relax); with "reference" the answer is the caller's, and so are its prices
    (the main job's cheap fronts spent 17-18 evaluations each on a price nobody read)."""
    reference = reference_evaluation(problem)
    (sense, metric), = problem.spec.objective.items()
    result = OptimizationResult(problem.spec.name, problem.names, list(problem.units), sense, metric,
                                [Constraint(*c) for c in problem.constraints], reference=reference,
                                requirements=dict(problem.spec.requirements),
                                paths={n: v.path for n, v in problem.spec.variables.items()})
    if problem.spec.pareto:
        if path is None:
            raise OptimizeError(f"{problem.spec.name}: a front's runs read the optimization file; pass its path")
        result.runs = front(problem, path, workers=workers)
    else:
        result.optimum = optimize(problem)
    required_influence_metrics(problem, result, influence)
    if influence == "answer":           # what each binding requirement costs the run's own answer; the main
        result.prices = relax(problem, chosen_run(result))     # job's answer is priced by its answer step
    if problem.out is not None:
        store = Store(problem.out)
        try:
            result.fem_solves = len(store.rows())
        finally:
            store.close()
    return result


def chosen_run(result: OptimizationResult):
    """The optimizer's run (driver.Result) of the design the answer chooses (optimize.answer):
    the optimum, or the front run it picks; None when it picks the reference or none."""
    from taxel.optimize.answer import Answer, si
    chosen = Answer.of(result).chosen
    if chosen is None or chosen.label == "reference":
        return None
    runs = [result.optimum] if result.optimum is not None else [r.result for r in result.runs]
    for r in runs:
        if r is not None and all(abs(si(v, u) - chosen.x[n]) <= 1e-12 * max(abs(chosen.x[n]), 1e-300)
                                 for n, u, v in zip(result.names, result.units, r.x)):
            return r
    return None


def required_influence_metrics(problem: Optimization, result: OptimizationResult, influence: str = "answer") -> None:
    """coverage and localization_error that only a [requirements] line names (optimize.coverage):
    computed after the search, lazily (coverage.judge_lazily), for the reference design and the
    design the answer's choice picks among the front's (or the optimum), added to their metrics
    and written to OUT/coverage.json, where the answer reads them; `influence` "reference": the
    reference design's only (the run's own choice then shows them "not evaluated")."""
    if influence not in ("answer", "reference"):
        raise ValueError(f"influence: 'answer' or 'reference', not {influence!r}")
    from taxel.optimize.requirements import implied, read
    need = set(coverage.INFLUENCE_METRICS) & set(problem.spec.requirements)
    if not need or need <= problem.used:
        return
    ref = result.reference if result.reference and result.reference.get("sensitivity") is not None else None
    runs = [r.result for r in result.runs] if result.runs else [result.optimum]
    designs = ([(np.array([ref["x"][n] for n in problem.names]), ref)] if ref else []) + \
        [(r.x, r.metrics) for r in runs if r is not None and r.metrics.get("sensitivity") is not None]
    if influence == "reference":
        designs = designs[:1] if ref else []
    if not designs:
        return
    reqs = implied(read(problem.spec.requirements), ref or {})

    def compute(i: int) -> dict:
        x, metrics = designs[i]
        got = problem.influence_metrics(x, metrics)
        if problem.out is not None:
            x_mm = {n: float(v) for n, v, u in zip(problem.names, x, problem.units) if u == "mm"}
            coverage.add(problem.out, x_mm, got)
        return {k: got.get(k) for k in (*coverage.INFLUENCE_METRICS, *coverage.WEAKEST, "error")}
    coverage.judge_lazily([m for _, m in designs], reqs, compute, always=[0] if ref else [])
