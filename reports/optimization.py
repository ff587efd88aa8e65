"""The figures of an optimization result (optimize.result.OptimizationResult):
optimum-convergence.png for an optimum, pareto.png for a front (the reference
design marked), and the 3D coverage map of each design whose coverage the run judged
(coverage-map-*.png, reports.coverage_map). The result writes its own numbers (result.json, optimum.json,
optimum-history.csv, front.json: OptimizationResult.to_folder)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from taxel.optimize.metrics import METRIC_TABLE, axis_label
from taxel.optimize.result import OptimizationResult
from taxel.reports.figures import pyplot


def draw(result: OptimizationResult, out: Path) -> list[Path]:
    """Draw the result's figures into `out`; returns their paths."""
    out = Path(out)
    paths = []
    if result.optimum is not None:
        paths.append(convergence(result, out / "optimum-convergence.png"))
    if result.runs:
        paths.append(front(result, out / "pareto.png"))
    from taxel.reports.coverage_map import draw_folder
    return paths + draw_folder(out)          # the designs' 3D coverage maps, where the run judged coverage


def convergence(result: OptimizationResult, path: Path) -> Path:
    """The objective of every evaluation and the best so far."""
    plt = pyplot()
    vals = [h["metrics"][result.metric] for h in result.optimum.history]
    vals = np.array([v if v is not None else np.nan for v in vals], float)
    best = np.fmax.accumulate(vals) if result.sense == "maximize" else np.fmin.accumulate(vals)
    fig, ax = plt.subplots(figsize=(6.5, 3.8), constrained_layout=True)
    ax.plot(vals, ".", color="0.6", label="evaluations")
    ax.plot(best, "-", label="best so far (any feasibility)")
    ax.set_xlabel("evaluation (count)")
    ax.set_ylabel(axis_label(result.metric))
    ax.set_title(f"{result.name}: {result.sense} {result.metric}")
    ax.legend()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def front(result: OptimizationResult, path: Path) -> Path:
    """The front (nondominated runs), every evaluated feasible design and the reference design."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6.5, 4.2), constrained_layout=True)
    feasible = result.feasible_evaluations()
    ax.plot([m["crosstalk"] * 100 for m in feasible], [m["sensitivity"] for m in feasible], ".", color="0.75",
            label="evaluated feasible designs")
    nd = sorted(result.nondominated, key=lambda p: p[1])
    ax.plot([c * 100 for s, c in nd], [s for s, c in nd], "o-", label="front (epsilon-constraint)")
    ref = result.reference
    if ref and ref.get("sensitivity") is not None:
        from taxel.optimize.answer import reference_label
        ax.plot(ref["crosstalk"] * 100, ref["sensitivity"], "r*", ms=14, label=reference_label(result.name))
    ax.set_xlabel(f"{METRIC_TABLE['crosstalk'].label} (%)")
    ax.set_ylabel(axis_label("sensitivity"))
    ax.set_title(result.name)
    ax.legend(fontsize=8, loc="lower right")
    ax.grid(True, alpha=0.3)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
