"""Static linear solve: `solve_linear` of an assembled `System` to a `Solution`.

Electrode voltages, charges and capacitances, reaction forces, the fields for
post-processing, and the mirror symmetry that solves a half or a quarter model and
unfolds its results to the whole.
"""


from ._fields import component_dofs
from ._linear import ElectrodeResult, Solution, results, solve_linear, unfold_solution
from ._symmetry import symmetry_order
from ._reciprocity import SurfaceResponse, UnitVoltageFields, charges, direct_charges, displacement_probe, surface_response, unit_voltage_fields

__all__ = ["ElectrodeResult", "Solution", "UnitVoltageFields", "charges", "component_dofs", "direct_charges", "displacement_probe",
           "results", "solve_linear", "surface_response", "SurfaceResponse", "symmetry_order", "unfold_solution", "unit_voltage_fields"]
