"""Constitution: what each material is and how it responds.

The piezoelectric and solid material data (`Piezo`, `Solid`, the library and user
tables), the model types' kinematics (plane strain, plane stress, axisymmetric, 3D),
the linear laws in each kinematics (`PiezoLaw`, `SolidLaw`), the Yeoh hyperelastic
law and its fit to uniaxial data, and the causal viscoelastic relaxation that holds
the loss factors over a band. Nothing here knows a mesh.
"""


from ._kinematics import (Axisymmetric, Kinematics, PlaneStrain, PlaneStress, Solid3D, kinematics)
from ._laws import PiezoLaw, SolidLaw, law
from ._materials import ECOFLEX_UNIAXIAL_CSV, EPS0, Piezo, Solid, get, library, model_tensors
from ._tensors import poling_rotation, rotate, strain_to_stress_charge
from ._relaxation import Relaxation, relaxation_law, ripple
from ._user_materials import from_record
from ._yeoh import (I3, MODES, Yeoh, dpsi, inv_det, nominal_stress, nominal_tangent, psi, stress, stress_tangent_batched, tangent)
from ._yeoh_fit import (COMPRESSION_STRETCH, fit_yeoh, stability_limit, stability_losses, uniaxial_stress)

__all__ = ["Axisymmetric", "COMPRESSION_STRETCH", "ECOFLEX_UNIAXIAL_CSV", "EPS0", "I3", "Kinematics", "MODES", "Piezo", "PiezoLaw", "PlaneStrain", "PlaneStress", "Relaxation", "Solid", "Solid3D", "SolidLaw", "Yeoh", "dpsi", "fit_yeoh", "from_record", "get", "inv_det", "kinematics", "law", "library", "model_tensors", "nominal_stress", "nominal_tangent", "poling_rotation", "psi", "relaxation_law", "ripple", "rotate", "stability_limit", "stability_losses", "strain_to_stress_charge", "stress", "stress_tangent_batched", "tangent", "uniaxial_stress"]
