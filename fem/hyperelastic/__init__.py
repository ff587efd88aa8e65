"""Hyperelastic static solve: Newton on the Yeoh silicone coupled to the piezo.

The vectorised Yeoh residual and tangent (`yeoh_terms`) in every kinematics, the
plane-stress law with its thickness stretch condensed at each point, and `newton` /
`solve_yeoh` with load stepping. The scikit-fem forms (`_reference_forms`) are the
test oracle of the vectorised terms.
"""


from ._newton import (NewtonError, NewtonResult, newton, scatter, solve_yeoh, yeoh_regions, yeoh_terms, yeoh_terms_skfem)
from ._plane_stress import incompressible, stress_tangent, thickness_stretch
from ._reference_forms import min_jacobian, smallest_jacobian
from ._terms import YeohRegion

__all__ = ["NewtonError", "NewtonResult", "YeohRegion", "incompressible", "min_jacobian", "newton", "scatter", "smallest_jacobian", "solve_yeoh", "stress_tangent", "thickness_stretch", "yeoh_regions", "yeoh_terms", "yeoh_terms_skfem"]
