"""Readout: what stands between the taxel's electrodes and a number.

Circuits (charge amplifier, resistor, notch, voltage follower) as transfer functions
and in time, the noise chain (amplifier, hum, converter), and the seed's lumped model
of a taxel (a spring and a piezo capacitor), identified from the FEM.
"""


from ._circuits import Readout, amplifier_in_time, in_time, notch, notch_in_time, readout, resistor
from ._lumped import Identified, Lumped, identified, points_per_second, taxel_model
from ._noise import Amplifier, Chain, Converter, Hum, band_power, grid

__all__ = ["Amplifier", "Chain", "Converter", "Hum", "Identified", "Lumped", "Readout", "amplifier_in_time", "band_power", "in_time", "grid", "identified", "notch", "notch_in_time", "points_per_second", "readout", "resistor", "taxel_model"]
