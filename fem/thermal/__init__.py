"""Thermal: transient heat conduction through the stack and the pyroelectric charge.

The conduction model on the mechanics' tagged mesh (each region's conductivity and heat
capacity; Robin surfaces: a warm body's contact conductance, convection elsewhere), the
theta-method time stepping with its energy balance, the pyroelectric charge on the
electrode above a film from its temperature field, and the closed forms the solver is
checked against (semi-infinite solid, two-layer slab). One-way: temperature makes
charge; nothing here knows the mechanics or the readout.
"""

from ._closed_forms import semi_infinite, two_layer_film_mean
from ._conduction import Conduction, Heat, Surface, ThermalModel, conduct
from ._pyro import Film, mean_temperature, pyro_charge, pyro_weights

__all__ = ["Conduction", "Film", "Heat", "Surface", "ThermalModel", "conduct", "mean_temperature", "pyro_charge",
           "pyro_weights", "semi_infinite", "two_layer_film_mean"]
