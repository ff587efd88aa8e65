"""What a binding requirement costs an optimum: the search run again with that one bound
relaxed by a stated step.

A requirement binds an optimum when the search ends at its bound and would go further
if the bound let it. Each requirement the optimum is near (its margin within ACTIVE of
zero; COBYLA stops a little inside a bound) is tried: its price is what the next step of
the bound buys, found the only honest way, by searching again:

    relaxed bound   b' = b (1 + STEP)   for "<= b"  (pitch <= 6 mm -> <= 6.6 mm)
                    b' = b (1 - STEP)   for ">= b"  (sensitivity >= 0.5 V/N -> >= 0.45 V/N)

with every other requirement as it was, a local run (COBYLA) from the optimum on half the
spec's evaluation budget. A relaxation that buys less than GAIN of the objective does not
bind, and is said so. A local run from the old optimum finds at least as good a
design as the old one (it is feasible for the looser bound), so the gain it reports is a
lower bound on what the relaxation buys; the price says so. Every design is a study
point of the run's store, as the search's are (`Optimization.evaluate`).

    taxel optimize dense.toml     ->   pitch ≤ 6 mm binds: at ≤ 6.6 mm (+10 %), sensitivity 537 mV/N
                                       (+15 %) at 2 % crosstalk (+2.2 %) (... silicone above 0.3022 mm, ...)

coverage and localization_error are judged after the search (optimize.coverage), not by
it, so they are priced among the candidates (optimize.answer.prices), not here; a front's
requirements are priced among its designs the same way.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

import numpy as np

from taxel.optimize import driver

STEP = 0.10        # the relaxation's step, relative to the bound (stated on the page)
ACTIVE = 0.05      # a requirement within this of its bound (relative margin) at the optimum is tried
GAIN = 1e-3        # a relaxation buying less than this (relative, in the objective) buys nothing: it does not bind


@dataclass
class RelaxedOptimum:
    """One binding requirement's price: the optimum with its bound moved by STEP."""
    metric: str
    op: str                          # "<=" or ">="
    bound: float                     # SI
    relaxed: float                   # SI
    x: list[float]                   # the new optimum, in the variables' own units
    metrics: dict = field(default_factory=dict)
    evaluations: int = 0
    success: bool = False
    message: str = ""
    before: dict = field(default_factory=dict)   # the metrics of the design it started from

    def record(self) -> dict:
        return asdict(self)

    def _gain(self, metric: str) -> list[str]:
        """["sensitivity 537 mV/N (+15 %)", "2 % crosstalk (+2.2 %)"]: the objective's metric first."""
        from taxel.units import engineering
        out = []
        for k in dict.fromkeys((metric, "sensitivity", "crosstalk")):
            v, v0 = self.metrics.get(k), self.before.get(k)
            if v is None:
                continue
            shown = f"{100 * v:.3g} % {k}" if k == "crosstalk" else f"{k.replace('_', ' ')} " + \
                engineering(v, "V/N" if "sensitivity" in k else "", 3)
            out.append(shown + (f" ({100 * (v / v0 - 1):+.2g} %)" if v0 else ""))
        return out

    def text(self, names: list[str], units: list[str], metric: str) -> str:
        """"pitch ≤ 6 mm binds: at ≤ 6.6 mm (+10 %), sensitivity 537 mV/N (+15 %) at 2 % crosstalk
        (+2.2 %) (a local search from the chosen design, so at least this much; silicone above ...)"."""
        from dataclasses import replace
        from taxel.optimize.metrics import METRIC_TABLE
        from taxel.optimize.requirements import Requirement
        r = Requirement(self.metric, self.op, self.bound, "")
        moved = replace(r, bound=self.relaxed).text()[len(METRIC_TABLE[self.metric].label) + 1:]
        if not self.success:
            return f"{r.text()}: at {moved} ({100 * STEP:+.0f} %) the search found no design ({self.message})"
        before = self.before
        v, v0 = self.metrics.get(metric), before.get(metric)
        if v is not None and v0 and abs(v / v0 - 1) < GAIN:
            return (f"{r.text()} does not bind: at {moved} ({100 * STEP:+.0f} %) the search from the chosen "
                    f"design finds no better design")
        used = r.margin(self.metrics.get(self.metric))
        if used is not None and used >= 0:       # better, yet inside the old bound: the search's gain, not the bound's
            return (f"{r.text()} does not bind: at {moved} ({100 * STEP:+.0f} %) the best design found still meets "
                    f"it ({', '.join(self._gain(metric))}; the first search had not converged that far)")
        gain = self._gain(metric)
        design = ", ".join(f"{n.replace('_', ' ')} {v:.4g} {u}".strip() for n, u, v in zip(names, units, self.x))
        return (f"{r.text()} binds: at {moved} ({100 * STEP:+.0f} %), {' at '.join(gain)} "
                f"(a local search from the chosen design, so at least this much; {design})")


def binding(problem, optimum: driver.Result) -> list[tuple[str, str, float]]:
    """The searched requirements (metric, op, SI bound) the optimum sits at (margin < ACTIVE)."""
    out = []
    for c in problem.constraints:
        g = driver.violation(optimum.metrics, c)        # <= 0 met; -margin
        if np.isfinite(g) and -g < ACTIVE:
            out.append(c)
    return out


def relax(problem, optimum: driver.Result, step: float = STEP) -> list[RelaxedOptimum]:
    """Each binding requirement's price (module docstring) at `optimum` (the run's optimum, or
    the front design the answer chose); [] when it failed."""
    if optimum is None or not optimum.success:
        return []
    (sense, metric), = problem.spec.objective.items()
    alg = problem.spec.algorithm
    out = []
    for c in binding(problem, optimum):
        name, op, bound = c
        moved = bound * (1 + step) if op == "<=" else bound * (1 - step)
        cons = [(name, op, moved) if k == c else k for k in problem.constraints]
        r = driver.minimize(problem.evaluate, optimum.x, list(zip(problem.lo, problem.hi)), metric, cons,
                            maximize=sense == "maximize", global_alg=None, local_alg="COBYLA",
                            max_evals=max(alg.max_evaluations // 2, 6), xtol=alg.xtol)
        better = r.success and (r.fun <= optimum.fun)
        best = r if better else optimum                 # never worse than the optimum it started from
        out.append(RelaxedOptimum(name, op, bound, moved, [float(v) for v in best.x],
                              {k: v for k, v in best.metrics.items() if v is not None}, r.nfev, r.success,
                              r.message, {k: v for k, v in optimum.metrics.items() if v is not None}))
    return out


def of_record(rows: list[dict]) -> list[RelaxedOptimum]:
    return [RelaxedOptimum(**r) for r in rows]
