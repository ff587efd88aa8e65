"""Analyses of a scene: the scene made into the finite-element model (problem,
geometry), the static, frequency and transient analyses (analysis, dynamic), and
their result objects (results).

    solve(scene) -> StaticResult | FrequencyResult | TransientResult   (success, stop)

The dynamic analyses (taxel.analyses.dynamic: the frequency and transient
solvers) are imported on first use, so a static solve does not load them.
"""

from __future__ import annotations

import importlib

from taxel.analyses.analysis import lumped, output_folder, solve, solve_static
from taxel.analyses.problem import solve_model
from taxel.analyses.friction_band import FrictionBand, FrictionLeg, friction_band, friction_leg
from taxel.analyses.geometry import checked_layout, layout, mirror_planes, symmetry_planes
from taxel.analyses.problem import (check, damping, electrode_states, indenter, mesh, problem, readout,
                                    scene_materials, with_silicone)
from taxel.analyses.results import (AnalysisResult, FrequencyResult, LumpedResult, ResultError, StaticResult, Stop,
                                    TransientResult, read)
from taxel.analyses.results.static import LINEAR_ERROR_PER_STRAIN, linear_error

_LAZY = {name: "taxel.analyses.dynamic" for name in
         ("force_history", "frequencies", "frequency", "lumped_model", "lumped_response", "transient")}


def __getattr__(name):
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'taxel.analyses' has no attribute {name!r}")


__all__ = ["solve", "solve_static", "solve_model", "frequency", "transient", "lumped_model", "lumped_response",
           "problem", "mesh", "readout", "check", "scene_materials", "damping", "electrode_states", "indenter",
           "with_silicone", "layout", "checked_layout", "mirror_planes", "symmetry_planes", "frequencies",
           "force_history", "linear_error", "LINEAR_ERROR_PER_STRAIN", "read", "ResultError", "AnalysisResult",
           "StaticResult", "FrequencyResult", "Stop", "TransientResult", "LumpedResult", "output_folder", "lumped",
           "FrictionBand", "FrictionLeg", "friction_band", "friction_leg"]
