"""How wrong a result may be, and the model it is cheapest to trust: the error
estimate (error_estimate: discretisation, model form and material law per output)
and the model choice (model_choice: `model.fidelity = "auto"`, the cheapest rung of
the ladder whose estimated error is within `model.tolerance`).
"""

from taxel.analyses.accuracy.error_estimate import (CHEAP_3D, CHEAP_3D_ERROR, PRESS_3D_ERROR, cheapest_3d,
                                                    discretisation, estimate, estimate_frequency, output_values,
                                                    relative)
from taxel.analyses.accuracy.model_choice import Rung, choose, ladder

__all__ = ["estimate", "estimate_frequency", "discretisation", "output_values", "relative", "cheapest_3d",
           "CHEAP_3D", "CHEAP_3D_ERROR", "PRESS_3D_ERROR", "choose", "ladder", "Rung"]
