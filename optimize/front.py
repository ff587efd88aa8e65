"""The sensitivity-crosstalk front of an optimization by epsilon-constraint (each run on a
Dask worker, every evaluation written to the shared store), and the discretisation noise
of a design's metrics along one variable (optimize.spec's docstring)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from taxel.optimize import driver
from taxel.optimize.result import FrontRun
from taxel.optimize.spec import Optimization, load_optimization, optimize
from taxel.studies.execute import local_cluster


def _front_run(problem_path, out, eps, max_evals):
    """One epsilon-constraint run (on a Dask worker): maximize sensitivity s.t. crosstalk <= eps."""
    p = load_optimization(problem_path, Path(out))
    cons = [("crosstalk", "<=", eps)] if eps is not None else []
    return FrontRun(eps, optimize(p, cons, max_evals))


def front(problem: Optimization, problem_path, workers=2) -> list[FrontRun]:
    """Sensitivity vs crosstalk front by epsilon-constraint: first the unconstrained
    maximum of sensitivity (its crosstalk c_max) and the minimum of crosstalk
    (c_min), both under the [requirements], then maximize sensitivity with crosstalk <= eps_k
    for eps_k evenly in log between (`targets`); the runs are spread over Dask workers (each writes its evaluations
    to the shared store)."""
    n = problem.spec.pareto.points
    alg = problem.spec.algorithm
    best = optimize(problem)
    lowest = driver.minimize(problem.evaluate, problem.x0, list(zip(problem.lo, problem.hi)), "crosstalk",
                             problem.constraints, global_alg=None if alg.global_ == "none" else alg.global_,
                             local_alg=alg.local, max_evals=alg.max_evaluations, xtol=alg.xtol)
    c_hi, c_lo = best.metrics["crosstalk"], lowest.metrics["crosstalk"]
    eps = targets(c_lo, c_hi, n)
    return [FrontRun(c_lo, lowest)] + _spread(problem_path, problem.out, eps, alg.max_evaluations, workers) + \
        [FrontRun(c_hi, best)]


def targets(c_lo: float | None, c_hi: float | None, n: int) -> list[float]:
    """The n - 2 crosstalk bounds between the front's ends: evenly in log (crosstalk spans
    decades: an even spacing leaves the low end, where the designs differ most, empty). The ends
    are the runs under the [requirements] (the search's constraints), so a crosstalk requirement
    is the top end: the targets sit inside the user's limits."""
    if c_lo is None or c_hi is None or not c_hi > c_lo:
        return []
    if c_lo > 0:
        return list(np.geomspace(c_lo, c_hi, n)[1:-1])
    return list(np.linspace(c_lo, c_hi, n)[1:-1])


def _spread(problem_path, out, eps, max_evals, workers):
    if workers <= 1:
        return [_front_run(problem_path, out, e, max_evals) for e in eps]
    from dask.distributed import Client
    cluster = local_cluster(workers)
    client = Client(cluster)
    try:
        futs = [client.submit(_front_run, str(problem_path), str(out), e, max_evals, pure=False) for e in eps]
        return client.gather(futs)
    finally:
        client.close()
        cluster.close()


def noise(problem: Optimization, variable: str, x=None, rel_steps=(1e-4, 3e-4, 1e-3, 3e-3)):
    """Discretisation noise of the metrics along one variable: the scatter of
    f(x + h e_i) about the straight line through the neighbours, relative."""
    x = problem.x0.copy() if x is None else np.asarray(x, float)
    i = problem.names.index(variable)
    span = problem.hi[i] - problem.lo[i]
    out = {}
    for h in rel_steps:
        xs = [x.copy() for _ in range(3)]
        for k, d in enumerate((-1, 0, 1)):
            xs[k][i] = x[i] + d * h * span
        vals = [problem.evaluate(v)["sensitivity"] for v in xs]
        out[h] = abs(vals[1] - 0.5 * (vals[0] + vals[2])) / abs(vals[1])
    return out
