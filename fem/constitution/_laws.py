"""Constitutive laws as the forms use them: a material cut to a model type.

PiezoLaw: stress-charge tensors (c, e, eps) cut exactly to the model type
(fem.constitution). SolidLaw: an isotropic solid in the mixed u-p split of
fem.assembly, T = 2 mu (S - beta tr S I) + p I with p = kappa div u: beta = 1/3 and
kappa = K (the deviatoric/volumetric split), or in plane stress beta = 0 and
kappa = lambda* = 2 lambda mu / (lambda + 2 mu); `c` is the model type's stiffness for
the displacement-only formulation. A solid with Yeoh data also carries its
fem.constitution.Yeoh law (used when the problem is hyperelastic).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _materials as materials
from ._kinematics import Kinematics, PlaneStress
from ._yeoh import Yeoh


@dataclass(frozen=True, eq=False)
class PiezoLaw:
    c: np.ndarray      # Pa, the model type's stiffness at constant field
    e: np.ndarray      # C/m^2
    eps: np.ndarray    # F/m, at constant strain
    material: materials.Piezo


@dataclass(frozen=True, eq=False)
class SolidLaw:
    mu: float
    lam: float
    beta: float
    kappa: float
    c: np.ndarray      # the model type's stiffness (displacement formulation)
    material: materials.Solid
    yeoh: Yeoh | None = None


def law(material, kin: Kinematics, poling: int = 1) -> PiezoLaw | SolidLaw:
    """The law of a material in a model type (poling +1 up, -1 down for a piezo).
    Raises ValueError where the model cannot hold the material (fem.constitution)."""
    if isinstance(material, materials.Piezo):
        c, e, eps = kin.reduce(material.poled([0, 0, poling]))
        return PiezoLaw(c, e, eps, material)
    mu, lam, beta, kappa = material.mu, material.lam, 1 / 3, material.K
    if isinstance(kin, PlaneStress):
        lam = 2 * lam * mu / (lam + 2 * mu)
        beta, kappa = 0.0, lam
    yeoh = Yeoh(*material.yeoh, K=material.K) if material.yeoh is not None else None
    return SolidLaw(mu, lam, beta, kappa, kin.reduce(material)[0], material, yeoh)
