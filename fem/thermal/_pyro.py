r"""The pyroelectric charge on a film's electrodes from its temperature field.

Strain-charge form with temperature (IEEE 176 extended; Nye): D = d T + eps^T E + p dT,
p the pyroelectric vector at constant stress (C/(m^2 K)), p = p3 n for a film poled
along n. A thin film of thickness t between its electrodes, short-circuited (a charge
amplifier's virtual ground holds E's integral through it at zero), lateral fields
neglected: div D = 0 makes D_z uniform through the thickness, and int E_z dz = 0 with
E_z = (D_z - d T - p_z dT) / eps33 gives D_z = <d T + p_z dT>, the mean through the
thickness (uniform eps33). The electrode above the film holds the free charge -D_z per
unit area (its surface normal into the film is -z), so

    Q_pyro = -(s p3 / t) int_V dT dV          (s = +1 poled up, -1 down)

over the film's volume: exactly -s p3 A dT for a uniformly heated film. The sign matches
the mechanics' short-circuit charge (fem: a press on PZT poled up gives +d33 F on the top
electrode): heating PZT or PVDF (both p3 < 0) gives a positive charge, as a press does on
PZT and as a release does on PVDF (d33 < 0).

Assumptions, stated: one-way coupling (temperature -> charge; no piezoelectric or
dielectric heating); the film mechanically free (the silicone is 5-7 orders of magnitude
softer), so the datasheet's constant-stress p3 applies, the secondary (thermal expansion
x piezoelectric) part included in it; the silicone's thermal stress on the film, about
E_s alpha_s dT (3e-4/K x 1e4 Pa, a few Pa per K against 62.5 kPa per newton on a 4 x 4 mm
taxel), neglected; p3, d and eps at their room-temperature values (`drift` gives the
datasheet drift of d and eps where a sheet states it).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._conduction import Conduction, ThermalModel


@dataclass(frozen=True)
class Film:
    """A pyroelectric body: its elements, p3 (C/(m^2 K)), poling sign and thickness (m)."""

    cells: np.ndarray
    pyro: float
    poling: int
    thickness: float


def pyro_weights(model: ThermalModel, film: Film) -> np.ndarray:
    """w with Q_pyro = w . (T - T0): -(s p3 / t) int_film N_i dV."""
    return -(film.poling * film.pyro / film.thickness) * model.volume_load(film.cells)


def pyro_charge(conduction: Conduction, film: Film) -> np.ndarray:
    """The short-circuit charge history (C) on the electrode above `film`."""
    w = pyro_weights(conduction.model, film)
    return (conduction.T - conduction.T[0]) @ w


def mean_temperature(conduction: Conduction, cells: np.ndarray) -> np.ndarray:
    """The volume mean temperature (K) of the elements `cells` at each time."""
    w = conduction.model.volume_load(cells)
    return conduction.T @ w / w.sum()
