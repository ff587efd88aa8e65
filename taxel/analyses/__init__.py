"""Analyses of a scene: the adapter to the finite-element model, the static,
frequency and transient analyses, and their result objects."""

from __future__ import annotations

from taxel.scene import Scene
from taxel.analyses.dynamic import (force_history, frequencies, frequency, lumped_model, lumped_response,
                                    transient)
from taxel.analyses.adapter import check, mesh, problem, readout, scene_materials
from taxel.analyses.results import (AnalysisResult, FrequencyResult, LumpedResult, ResultError, StaticResult,
                                    TransientResult, read)
from taxel.analyses.static import LINEAR_ERROR_PER_STRAIN, linear_error, solve_static

__all__ = ["solve", "solve_static", "frequency", "transient", "lumped_model", "lumped_response", "problem", "mesh",
           "readout", "check", "scene_materials", "frequencies", "force_history", "linear_error",
           "LINEAR_ERROR_PER_STRAIN", "read", "ResultError", "AnalysisResult", "StaticResult", "FrequencyResult",
           "TransientResult", "LumpedResult"]


def solve(scene: Scene, estimate: bool = False, **options) -> StaticResult | FrequencyResult | TransientResult:
    """The scene's [analysis]: a static solve (options: solver, tagged_mesh, scale,
    newton_options; `estimate`: attach the error estimate, taxel.analyses.error_estimate),
    a frequency sweep, or a transient."""
    kind = scene.analysis.type
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
