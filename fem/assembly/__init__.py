"""Assembly: from a `Problem` (a tagged mesh, materials, loads) to a `System`.

The `Problem` is what the FEM solves, in its own terms (the scene never reaches this
far). `assemble` builds the coupled piezoelectric + silicone matrices with the
vectorised bilinear forms; `elimination` removes the supports and floating
electrodes. The scikit-fem forms (`_reference_forms`) are the reference the
vectorised forms are tested against, and assemble the surface loads and masses.
"""


from ._bilinear import (STRAIN, Term, assemble_terms, scalar_quantities, vector_matrix, weights)
from ._constraints import Elimination, elimination, supports
from ._problem import Damping, Discretization, Indenter, PatchLoad, Problem, Supports
from ._reference_forms import (deviatoric_shear, dielectric, elastic, mass, piezo_coupling, pressure_divergence, pressure_mass)
from ._scalar_basis import LazyBasis, scalar_basis
from ._sparsity import Pattern
from ._system import System, assemble, elements, load_vector, place

__all__ = ["Damping", "Discretization", "Elimination", "Indenter", "LazyBasis", "PatchLoad", "Pattern", "Problem", "STRAIN", "Supports", "System", "Term", "assemble", "assemble_terms", "deviatoric_shear", "dielectric", "elastic", "elements", "elimination", "load_vector", "mass", "piezo_coupling", "place", "pressure_divergence", "pressure_mass", "scalar_basis", "scalar_quantities", "supports", "vector_matrix", "weights"]
