"""Files of an optimization run: optimum.json, history.csv, convergence.png, pareto.png."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np

from taxel.optimize.driver import _g, pareto_front
from taxel.reports.figures import pyplot


# the metrics' axis labels, in the units the metrics are in
METRIC_AXES = {"sensitivity": "sensitivity (V/N)", "crosstalk": "crosstalk (ratio)",
               "max_strain": "largest silicone strain (ratio)", "total_thickness": "total thickness (m)",
               "footprint": "footprint (m)", "gap": "gap (m)"}


def write_run(problem, result, out: Path, tag="optimum"):
    rec = {"x": dict(zip(problem.names, map(float, result.x))), "units": dict(zip(problem.names, problem.units)),
           "objective": result.fun,
           "metrics": result.metrics, "constraints": result.constraints, "evaluations": result.nfev,
           "success": result.success, "message": result.message}
    (out / f"{tag}.json").write_text(json.dumps(rec, indent=1))
    with open(out / f"{tag}-history.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        keys = sorted(result.history[0]["metrics"]) if result.history else []
        w.writerow(["evaluation", "phase", *problem.names, *keys])
        for i, h in enumerate(result.history):
            w.writerow([i, h["phase"], *h["x"], *[h["metrics"][k] for k in keys]])
    _convergence(problem, result, out / f"{tag}-convergence.png")
    return rec


def _convergence(problem, result, path):
    plt = pyplot()
    (sense, metric), = problem.spec.objective.items()
    vals = [h["metrics"][metric] for h in result.history]
    vals = np.array([v if v is not None else np.nan for v in vals], float)
    best = np.fmax.accumulate(vals) if sense == "maximize" else np.fmin.accumulate(vals)
    fig, ax = plt.subplots(figsize=(6.5, 3.8), constrained_layout=True)
    ax.plot(vals, ".", color="0.6", label="evaluations")
    ax.plot(best, "-", label="best so far (any feasibility)")
    ax.set_xlabel("evaluation (count)")
    ax.set_ylabel(METRIC_AXES.get(metric, f"{metric} (SI)"))
    ax.set_title(f"{problem.spec.name}: {sense} {metric}")
    ax.legend()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def write_front(problem, runs, reference, out: Path):
    plt = pyplot()
    pts = [(r.metrics["sensitivity"], r.metrics["crosstalk"], eps, r) for eps, r in runs
           if r.success and r.metrics["sensitivity"] is not None]
    nd = pareto_front([(s, c) for s, c, *_ in pts])
    rows = [{"crosstalk_bound": eps, "sensitivity_V_per_N": s, "crosstalk": c,
             **{f"{n} ({u})": float(v) for n, u, v in zip(problem.names, problem.units, r.x)}}
            for s, c, eps, r in pts]
    (out / "front.json").write_text(json.dumps({"front": rows, "reference": reference}, indent=1))
    fig, ax = plt.subplots(figsize=(6.5, 4.2), constrained_layout=True)
    allh = [h["metrics"] for _, r in runs for h in r.history if h["metrics"]["sensitivity"] is not None]
    feasible = [m for m in allh if all(_g(m, c) <= 1e-9 for c in problem.constraints)]
    ax.plot([m["crosstalk"] * 100 for m in feasible], [m["sensitivity"] for m in feasible], ".", color="0.75",
            label="evaluated feasible designs")
    ax.plot([c * 100 for s, c in sorted(nd, key=lambda p: p[1])], [s for s, c in sorted(nd, key=lambda p: p[1])],
            "o-", label="front (epsilon-constraint)")
    if reference:
        ax.plot(reference["crosstalk"] * 100, reference["sensitivity"], "r*", ms=14, label="thesis design")
    ax.set_xlabel("crosstalk (%)")
    ax.set_ylabel("sensitivity (V/N)")
    ax.set_title(problem.spec.name)
    ax.legend(fontsize=8, loc="lower right")
    ax.grid(True, alpha=0.3)
    fig.savefig(out / "pareto.png", dpi=120)
    plt.close(fig)
    return rows, nd
