"""Dynamics: frequency and time response of the taxel with its readout.

The dynamic model (mass, damping by causal relaxation, the electrodes' ports), the
frequency sweep (direct and Krylov-projected), time stepping (Newmark, central
difference, hyperelastic transients), the reduced-order model and its state-space
realization.
"""


from ._model import DynamicModel, model
from ._projection import ProjectedModel, build, direct_ports, ports
from ._statespace import StateSpace, realize
from ._sweep import PortResponse, coupled_resistor, direct, sweep
from ._timestep import (Transient, central_difference, critical_time_step, newmark, transient, transient_hyperelastic)

__all__ = ["DynamicModel", "PortResponse", "ProjectedModel", "StateSpace", "Transient", "build", "central_difference", "coupled_resistor", "critical_time_step", "direct", "direct_ports", "model", "newmark", "ports", "realize", "sweep", "transient", "transient_hyperelastic"]
