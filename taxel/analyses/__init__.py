"""Analyses of a scene, one subpackage per job; each re-exports its public names
(`__all__`) and imports only the ones below it (the import contract in
`.ci/importlinter.toml`):

    surface    influence functions, coverage, the predicted localization error,
       |       the bench's taxel models
    solves     solve (static, frequency, transient), the numbers at the readout, the
       |       noise budget, the reduced-order model, the FEM-informed lumped model,
       |       the crosstalk weights, the friction band
    accuracy   the error estimate and the model choice (model.fidelity = "auto")
       |
    model      the scene made into the FEM's Problem: materials, layout, mesh, Problem
       |
    results    the result objects and their folders

    solve(scene) -> StaticResult | FrequencyResult | TransientResult   (success, stop)

The dynamic analyses (taxel.analyses.solves.dynamic: the frequency and transient
solvers) are imported on first use, so a static solve does not load them.
"""

from __future__ import annotations

import importlib

from taxel.analyses.solves.analysis import lumped, output_folder, solve, solve_static
from taxel.analyses.model.problem import solve_model
from taxel.analyses.solves.friction_band import FrictionBand, FrictionLeg, friction_band, friction_leg
from taxel.analyses.model.geometry import checked_layout, layout, mirror_planes, symmetry_planes
from taxel.analyses.model.problem import (check, damping, electrode_states, indenter, mesh, problem, readout,
                                          scene_materials, with_silicone)
from taxel.analyses.results import (AnalysisResult, FrequencyResult, LumpedResult, ResultError, StaticResult, Stop,
                                    TransientResult, read)
from taxel.analyses.results.static import LINEAR_ERROR_PER_STRAIN, linear_error

_LAZY = {name: "taxel.analyses.solves.dynamic" for name in
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
