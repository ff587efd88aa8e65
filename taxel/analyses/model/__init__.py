"""The scene made into the finite-element model: materials by name, checked with the
mirror planes (`check`), the layered layout refused when its solve cannot fit
(geometry), the tagged mesh, and the FEM's `Problem` (problem), with the readout chain
and the damping translated too; `solve_model` is the Problem's static solve. Below this
subpackage nothing reads the scene schema; above it nothing assembles.

A function named as its module (`problem`) is reached as `taxel.analyses.problem` or
through its module (`taxel.analyses.model.problem.problem`).
"""

from taxel.analyses.model.geometry import (FAR_TAXEL, checked_layout, layout, mirror_planes, punch_grading,
                                           solve_limit, symmetry_planes, too_large)
from taxel.analyses.model.problem import (check, damping, electrode_states, indenter, mesh, readout,
                                          scene_materials, solve_model, with_silicone)

__all__ = ["check", "scene_materials", "mesh", "indenter", "with_silicone", "electrode_states", "damping", "readout",
           "solve_model", "mirror_planes", "symmetry_planes", "layout", "checked_layout", "punch_grading",
           "solve_limit", "too_large", "FAR_TAXEL"]
