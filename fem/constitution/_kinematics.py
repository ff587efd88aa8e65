r"""Kinematics of each model type: strain, volume measure and 3x3 gradient.

One object per model type replaces the model string: the forms, the Yeoh law and
the field recovery ask it, and nothing else branches on the model.

    model          mesh coords   strain (Voigt, engineering shear)               measure
    Solid3D        x, y, z       [u1,1, u2,2, u3,3, u2,3+u3,2, u1,3+u3,1, u1,2+u2,1]  dx
    PlaneStrain    x, z          [ux,x, uz,z, ux,z + uz,x]                        depth dA
    PlaneStress    x, z          [ux,x, uz,z, ux,z + uz,x]                        depth dA
    Axisymmetric   r, z          [ur,r, ur / r, uz,z, ur,z + uz,r]  (rr, tt, zz, rz)  2 pi r dA

The measures make every integral a 3D one: forces are in N and charges in C for
the whole body. The 3x3 gradient (for F = I + H in finite strain) is Grad u in
3D; in plane strain Grad u padded with zeros (F33 = 1); axisymmetric
(r, z, theta) with H33 = u_r / r.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _materials as materials


@dataclass(frozen=True)
class Kinematics:
    name = ""                  # the model type's name, for records and material reductions
    dim = 2                    # mesh dimension
    normal = 2                 # how many leading Voigt components are normal strains
    shear_weights = (1.0, 1.0, 0.5)   # S(u) : S(v) = sum w_i S_i(u) S_i(v)

    @property
    def n_voigt(self) -> int:
        return len(self.shear_weights)

    @property
    def vertical(self) -> int:
        """Index of the vertical (thickness, z) displacement component."""
        return self.dim - 1

    def strain(self, u, x):
        """Voigt strain of a vector DiscreteField, shape (n_voigt, ...)."""
        g = u.grad
        return np.array([g[0, 0], g[1, 1], g[0, 1] + g[1, 0]])

    def divergence(self, S):
        """Trace of the strain: the sum of the normal components of S."""
        return S[: self.normal].sum(axis=0)

    def measure(self, x):
        """The factor of dA (or dx) that makes an integral a 3D one."""
        return 1.0

    def grad3(self, u, x):
        """The 3x3 gradient of a vector field (for F = I + grad3(u) and its variations)."""
        g = u.grad
        G = np.zeros((3, 3) + g.shape[2:])
        G[:2, :2] = g
        return G

    def reduce(self, material):
        """(c, e, eps) of a material in this model (fem.constitution, exact reductions)."""
        return materials.model_tensors(material, self.name)


@dataclass(frozen=True)
class PlaneStrain(Kinematics):
    depth: float = 1.0         # out-of-plane depth, m
    name = "plane_strain"

    def measure(self, x):
        return self.depth


@dataclass(frozen=True)
class PlaneStress(PlaneStrain):
    name = "plane_stress"


@dataclass(frozen=True)
class Axisymmetric(Kinematics):
    name = "axisymmetric"
    normal = 3
    shear_weights = (1.0, 1.0, 1.0, 0.5)

    def strain(self, u, x):
        g = u.grad
        return np.array([g[0, 0], u[0] / x[0], g[1, 1], g[0, 1] + g[1, 0]])

    def measure(self, x):
        return 2 * np.pi * x[0]

    def grad3(self, u, x):
        G = super().grad3(u, x)
        G[2, 2] = u[0] / x[0]
        return G


@dataclass(frozen=True)
class Solid3D(Kinematics):
    name = "3d"
    dim = 3
    normal = 3
    shear_weights = (1.0, 1.0, 1.0, 0.5, 0.5, 0.5)

    def strain(self, u, x):
        g = u.grad
        return np.array([g[0, 0], g[1, 1], g[2, 2], g[1, 2] + g[2, 1], g[0, 2] + g[2, 0], g[0, 1] + g[1, 0]])

    def grad3(self, u, x):
        return np.asarray(u.grad)


def kinematics(name: str, depth: float = 1.0) -> Kinematics:
    """The kinematics of a model type by name."""
    if name == "plane_strain":
        return PlaneStrain(depth)
    if name == "plane_stress":
        return PlaneStress(depth)
    if name == "axisymmetric":
        return Axisymmetric()
    if name == "3d":
        return Solid3D()
    raise ValueError(f"unknown model type {name!r}; use plane_strain, plane_stress, axisymmetric or 3d")
