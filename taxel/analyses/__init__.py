"""Analyses of a scene: the adapter to the finite-element model, the static,
frequency and transient analyses, and their result objects.

The dynamic analyses (taxel.analyses.dynamic: the frequency and transient
solvers) are imported on first use, so a static solve does not load them.
"""

from __future__ import annotations

import importlib

from taxel.scene import Scene
from taxel.analyses.adapter import check, mesh, problem, readout, scene_materials
from taxel.analyses.results import (AnalysisResult, FrequencyResult, LumpedResult, ResultError, StaticResult,
                                    TransientResult, read)
from taxel.analyses.static import LINEAR_ERROR_PER_STRAIN, linear_error, solve_model, stopped_result

_LAZY = {name: "taxel.analyses.dynamic" for name in
         ("force_history", "frequencies", "frequency", "lumped_model", "lumped_response", "transient")}


def __getattr__(name):
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'taxel.analyses' has no attribute {name!r}")


__all__ = ["solve", "solve_static", "frequency", "transient", "lumped_model", "lumped_response", "problem", "mesh",
           "readout", "check", "scene_materials", "frequencies", "force_history", "linear_error",
           "LINEAR_ERROR_PER_STRAIN", "read", "ResultError", "AnalysisResult", "StaticResult", "FrequencyResult",
           "stopped_result",
           "TransientResult", "LumpedResult"]


def solve(scene: Scene, estimate: bool = False, **options) -> StaticResult | FrequencyResult | TransientResult:
    """The scene's [analysis]: a static solve (options: solver, tagged_mesh, scale,
    newton_options; `estimate`: attach the error estimate, taxel.analyses.error_estimate),
    a frequency sweep, or a transient."""
    kind = scene.analysis.type
    if kind != "static":
        from taxel.analyses.dynamic import frequency, transient
    if kind == "frequency":
        res = frequency(scene)
        if estimate:
            from taxel.analyses.error_estimate import estimate_frequency
            res.error = estimate_frequency(scene, res)
        return res
    if kind == "transient":
        return transient(scene)
    res = solve_static(scene, **options)
    if estimate and res.error is None:
        from taxel.analyses.error_estimate import estimate as error_estimate
        res.error = error_estimate(res.scene, res, options.get("solver", "auto"))
    return res


def solve_static(scene: Scene, solver: str = "auto", **options) -> StaticResult:
    """The static analysis of a scene on the model it asks for: with model.fidelity =
    "auto" the cheapest adequate model (taxel.analyses.model_choice), else the model
    as given (taxel.analyses.static.solve_model; options: tagged_mesh, scale,
    newton_options)."""
    if scene.model.fidelity == "auto" and options.get("tagged_mesh") is None:
        from taxel.analyses.model_choice import choose
        return choose(scene, solver)
    return solve_model(scene, solver, **options)
