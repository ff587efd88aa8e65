"""Static linear solve: `solve_linear` of an assembled `System` to a `Solution`.

Electrode voltages, charges and capacitances, reaction forces, the fields for
post-processing, and the mirror symmetry that solves a half or a quarter model and
unfolds its results to the whole.
"""


from ._fields import component_dofs
from ._linear import ElectrodeResult, Solution, results, solve_linear, unfold_solution
from ._symmetry import symmetry_order

__all__ = ["ElectrodeResult", "Solution", "component_dofs", "results", "solve_linear", "symmetry_order", "unfold_solution"]
