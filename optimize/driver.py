"""nlopt behind one entry point and one result object (scipy.optimize's shape).

    minimize(evaluate, x0, bounds, objective, constraints, ...) -> Result

`evaluate(x)` returns a dict of named metrics for a design x; the objective and
each constraint read from it, so one (expensive) evaluation serves nlopt's
separate objective and constraint calls at the same x (memoised here).
Constraints are `(metric, "<=" | ">=", bound)`. The search runs in normalised
coordinates u in [0, 1]^n (x = lo + u (hi - lo)): one initial step and one
tolerance fit every variable.

Strategy: a global pass (DIRECT-L, or its original constrained variant when
there are constraints, or ISRES) on part of the budget, then a local polish
from the best feasible point (COBYLA with constraints; BOBYQA or Sbplx with
bounds only) on the rest.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import nlopt
import numpy as np

GLOBAL = {"DIRECT": (nlopt.GN_DIRECT_L, nlopt.GN_ORIG_DIRECT_L), "ISRES": (nlopt.GN_ISRES, nlopt.GN_ISRES)}
LOCAL = {"COBYLA": nlopt.LN_COBYLA, "BOBYQA": nlopt.LN_BOBYQA, "SBPLX": nlopt.LN_SBPLX}


@dataclass
class Result:
    x: np.ndarray                 # best feasible design (or least infeasible)
    fun: float                    # objective there (as minimised: -value for maximize)
    metrics: dict                 # every metric there
    constraints: dict             # name -> g (<= 0 is satisfied)
    nfev: int                     # distinct evaluations
    success: bool
    message: str
    history: list[dict] = field(default_factory=list)    # every evaluation: x, metrics, phase

    @property
    def feasible(self):
        return all(g <= 1e-9 for g in self.constraints.values())


class _Memo:
    def __init__(self, evaluate, lo, hi):
        self.evaluate, self.lo, self.hi = evaluate, lo, hi
        self.cache, self.history, self.phase = {}, [], "global"

    def x(self, u):
        return self.lo + np.clip(u, 0, 1) * (self.hi - self.lo)

    def __call__(self, u):
        key = tuple(np.round(np.asarray(u, float), 12))
        if key not in self.cache:
            x = self.x(np.asarray(u, float))
            m = self.evaluate(x)
            self.cache[key] = m
            self.history.append({"x": x.tolist(), "metrics": m, "phase": self.phase})
        return self.cache[key]


def violation(metrics, con) -> float:
    """The relative violation g of constraint `con` = (metric, "<=" | ">=", bound) at
    `metrics`: g <= 0 is satisfied; inf when the metric is missing."""
    name, op, bound = con
    v = metrics[name]
    if v is None or not np.isfinite(v):
        return np.inf
    scale = max(abs(bound), 1e-12)
    return (v - bound) / scale if op == "<=" else (bound - v) / scale


def minimize(evaluate, x0, bounds, objective: str, constraints=(), maximize=False,
             global_alg: str | None = "DIRECT", local_alg: str = "COBYLA", max_evals: int = 40,
             global_fraction: float = 0.5, xtol: float = 1e-3, initial_step: float = 0.1,
             seed: int = 0) -> Result:
    lo, hi = (np.asarray(b, float) for b in zip(*bounds))
    if np.any(hi <= lo):
        raise ValueError("empty bounds: every variable needs max > min")
    n = len(lo)
    memo = _Memo(evaluate, lo, hi)
    sign = -1.0 if maximize else 1.0
    cons = list(constraints)
    if cons and local_alg != "COBYLA":
        raise ValueError(f"{local_alg} handles bounds only; use COBYLA with constraints")
    nlopt.srand(seed)

    def run(alg, u0, budget, step):
        # the budget held here, not by nlopt alone: the constrained DIRECT (GN_ORIG_DIRECT_L)
        # does not count the calls at points violating a constraint, and ran 201 evaluations on
        # a budget of 20 in the thesis PZT front (637 on 20 in a test, tests/test_optimize.py)
        start, cap = len(memo.history), max(budget, 1)

        def at(u):
            if len(memo.history) - start >= cap and tuple(np.round(np.asarray(u, float), 12)) not in memo.cache:
                raise nlopt.ForcedStop
            return memo(u)

        def f(u, grad):
            v = at(u)[objective]
            return sign * v if v is not None and np.isfinite(v) else 1e30

        opt = nlopt.opt(alg, n)
        opt.set_lower_bounds(np.zeros(n))
        opt.set_upper_bounds(np.ones(n))
        opt.set_min_objective(f)
        for c in cons:
            opt.add_inequality_constraint(lambda u, grad, c=c: violation(at(u), c), 0.0)
        # nlopt's own count includes the calls answered from the cache (a local run starts at
        # the best point already evaluated): with it at `cap` a budget of 7 gave 6 designs
        opt.set_maxeval(cap + len(memo.cache))
        opt.set_xtol_rel(xtol)
        opt.set_xtol_abs(xtol)
        if step is not None:
            opt.set_initial_step(step)
        try:
            u = opt.optimize(np.clip(u0, 0, 1))
            return u, nlopt_message(opt.last_optimize_result())
        except nlopt.ForcedStop:
            return None, nlopt_message(nlopt.MAXEVAL_REACHED)
        except (nlopt.RoundoffLimited, RuntimeError, ValueError) as exc:
            return None, f"stopped: {type(exc).__name__}"

    u0 = (np.asarray(x0, float) - lo) / (hi - lo)
    memo(u0)                                           # the start is always evaluated
    messages = []
    if global_alg:
        if global_alg not in GLOBAL:
            raise ValueError(f"unknown global algorithm '{global_alg}'; use one of {', '.join(GLOBAL)} or none")
        alg = GLOBAL[global_alg][1 if cons else 0]
        _, msg = run(alg, u0, int(max_evals * global_fraction), None)
        messages.append(f"{global_alg}: {msg}")
    if local_alg not in LOCAL:
        raise ValueError(f"unknown local algorithm '{local_alg}'; use one of {', '.join(LOCAL)}")
    memo.phase = "local"
    best_u = _best(memo, objective, cons, sign)
    remaining = max_evals - len(memo.history)
    if remaining > 0:
        _, msg = run(LOCAL[local_alg], best_u, remaining, initial_step)
        messages.append(f"{local_alg}: {msg}")
    best_u = _best(memo, objective, cons, sign)
    m = memo(best_u)
    g = {f"{c[0]} {c[1]} {c[2]:g}": violation(m, c) for c in cons}
    if m[objective] is None:                  # every evaluation failed: say so, do not crash
        return Result(memo.x(best_u), float("inf"), m, g, len(memo.history), False,
                      "; ".join(messages + ["no design could be evaluated (every evaluation failed)"]), memo.history)
    ok = all(v <= 1e-9 for v in g.values())
    return Result(memo.x(best_u), sign * m[objective], m, g, len(memo.history), ok,
                  "; ".join(messages) + ("" if ok else "; no feasible design found"), memo.history)


def _best(memo, objective, cons, sign):
    """The best feasible evaluated point, or the least infeasible one."""
    best, best_key = None, None
    for key, m in memo.cache.items():
        viol = sum(max(violation(m, c), 0.0) for c in cons)
        v = m[objective]
        val = sign * v if v is not None and np.isfinite(v) else np.inf
        k = (viol > 1e-9, viol if viol > 1e-9 else val)
        if best_key is None or k < best_key:
            best, best_key = key, k
    return np.array(best)


def nlopt_message(code):
    return {nlopt.SUCCESS: "success", nlopt.STOPVAL_REACHED: "stop value reached",
            nlopt.FTOL_REACHED: "ftol reached", nlopt.XTOL_REACHED: "xtol reached",
            nlopt.MAXEVAL_REACHED: "evaluation budget used", nlopt.MAXTIME_REACHED: "time limit"}.get(code, str(code))


def pareto_front(points, maximize_first=True):
    """Non-dominated subset of (f1, f2) pairs: f1 maximised (or minimised), f2 minimised."""
    pts = sorted(points, key=lambda p: (-p[0] if maximize_first else p[0], p[1]))
    front, best2 = [], np.inf
    for p in pts:
        if p[1] < best2 - 1e-15:
            front.append(p)
            best2 = p[1]
    return front
