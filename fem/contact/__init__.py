"""Contact: a rigid indenter pressing the top surface (`Press`).

The indenter's gap and contact surface (augmented Lagrangian, frictionless,
sticking, or Coulomb friction by a return mapping), the semi-smooth Newton on the Alart-Curnier
conditions (frictionless and Coulomb, the tractions as unknowns), the penalty Newton with its continuation, the load path (travel steps,
then force control), and the records a press leaves (`PressPoint`, `PressResult`,
and `PressError` with its typed cause when a press stops short).
"""


from ._friction import OPEN, SLIP, STICK, Coulomb
from ._geometry import Surface, gap
from ._press import Press
from ._drive import press
from ._records import PressError, Options, SlipZone, StopCause

__all__ = ["OPEN", "SLIP", "STICK", "Coulomb", "Options", "Press", "PressError", "SlipZone", "StopCause", "Surface", "gap", "press"]
