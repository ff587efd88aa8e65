"""The analyses of a scene and the models made from its solves: `solve` (analysis: the
static, frequency and transient analyses, a stop returned as the result, the result
folder), the numbers at the readout (at_readout), the frequency and transient solvers
(dynamic), the noise budget (noise), the reduced-order model and its exports (reduced,
reduced_export), the FEM-informed lumped model (lumped_fem), the crosstalk weights
(crosstalk), the friction band (friction_band), the warm touch (warm_touch: a warm
finger's heat, the films' pyroelectric charge and the readout beside the press) and the
code version caches key on (version).

The dynamic solvers, the noise budget and the reduced-order model are imported on
first use, so a static solve does not load them. A function named as its module
(`at_readout`, `noise`, `friction_band`) is reached through its module
(`taxel.analyses.solves.noise.noise`; `taxel.analyses.friction_band` is the function).
"""

from __future__ import annotations

import importlib

from taxel.analyses.solves.analysis import lumped, output_folder, solve, solve_static
from taxel.analyses.solves.crosstalk import cache_dir, profile, weights
from taxel.analyses.solves.friction_band import FrictionBand, FrictionLeg, friction_leg
from taxel.analyses.solves.version import code_version

_LAZY = {**{name: "taxel.analyses.solves.dynamic" for name in
            ("force_history", "frequencies", "frequency", "lumped_model", "lumped_response", "transient")},
         **{name: "taxel.analyses.solves.noise" for name in
            ("chain", "design_noise", "quasi_static_noise", "with_readout")},
         **{name: "taxel.analyses.solves.reduced" for name in
            ("ReducedModel", "OnePort", "cached", "one_port", "read_folder", "reduce")},
         **{name: "taxel.analyses.solves.lumped_fem" for name in ("FemTargets", "informed", "targets")},
         "WarmTouchResult": "taxel.analyses.solves.warm_touch"}


def __getattr__(name):
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'taxel.analyses.solves' has no attribute {name!r}")


__all__ = ["solve", "solve_static", "lumped", "output_folder", "cache_dir", "profile", "weights",
           "FrictionBand", "FrictionLeg", "friction_leg", "code_version", *_LAZY]
