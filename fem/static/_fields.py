"""Fields of a solved state: vertex displacement and potential, element-mean
strain and stress, and the largest principal strain in the passive solids.

Stress: T = c S + e^T grad(phi) in the piezo (stress-charge form, E = -grad phi);
T = 2 mu (S - beta tr S I) + p I in the solids (fem.assembly), with p the mixed
pressure, or lam tr S in the displacement formulation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from taxel.fem.constitution import Axisymmetric, PlaneStress, Solid3D
from taxel.fem.constitution import PiezoLaw


@dataclass(repr=False)
class Fields:
    u: np.ndarray            # (nvertices, dim) vertex displacements, m
    phi: np.ndarray          # (nvertices,) vertex potential, V (0 outside the piezo)
    strain: np.ndarray       # (nelements, n_voigt) element-mean Voigt strain (engineering shear)
    stress: np.ndarray       # (nelements, n_voigt) element-mean stress, Pa
    max_strain: float  # largest |principal strain| of element means in the passive solids
    x: np.ndarray            # the full solution vector [u, p..., phi]

def component_dofs(ub, c):
    """All displacement DOFs of component c (nodal, edge or facet, interior)."""
    out = [ub.nodal_dofs[c]]
    if ub.facet_dofs.size and ub.mesh.dim() == 2:
        out.append(ub.facet_dofs[c])
    if ub.edge_dofs.size and ub.mesh.dim() == 3:
        out.append(ub.edge_dofs[c])
    if ub.interior_dofs.size:
        out.append(ub.interior_dofs[c])
    return np.concatenate(out)


def fields(sy, x) -> Fields:
    """Vertex values of u and phi, element-mean strain and stress, and the largest
    |principal strain| of the element-mean strains in the silicone (element means
    rather than point values: the strain is singular at taxel and load corners,
    so a point maximum grows without bound under refinement)."""
    kin, mesh = sy.kin, sy.tm.mesh
    u = x[sy.offsets["u"]]
    phi = x[sy.offsets["phi"]]
    ub0 = next(iter(sy.ubases.values()))
    nS = kin.n_voigt
    strain_cell = np.zeros((mesh.nelements, nS))
    stress_cell = np.zeros((mesh.nelements, nS))
    max_strain = 0.0
    for region, law in sy.laws.items():
        ub = sy.ubases[region]
        elems = sy.tm.regions[region]
        S = kin.strain(ub.interpolate(u), np.asarray(ub.global_coordinates()))      # (nS, ne, nq)
        if isinstance(law, PiezoLaw):
            g = sy.phibases[region].interpolate(phi).grad
            T = np.einsum("ij,j...->i...", law.c, S) + np.einsum("ki,k...->i...", law.e, g)
        else:
            wts = np.array(kin.shear_weights)
            tr = kin.divergence(S)
            beta = law.beta
            if region in sy.pbases:
                p = np.asarray(sy.pbases[region].interpolate(x[sy.offsets[("p", region)]]))
            else:
                p, beta = law.lam * tr, 0.0
            normal = np.zeros(nS)
            normal[: kin.normal] = 1
            T = 2 * law.mu * (wts[:, None, None] * S - beta * normal[:, None, None] * tr) + normal[:, None, None] * p
        strain_cell[elems] = S.mean(axis=2).T
        if region in sy.soft:
            max_strain = max(max_strain, max_principal(strain_cell[elems].T, kin, law.mu, law.lam))
        stress_cell[elems] = T.mean(axis=2).T
    vertex_u = u[ub0.nodal_dofs].T
    phi_vertex = np.zeros(mesh.nvertices)
    for pb in sy.phibases.values():
        phi_vertex[pb.nodal_dofs[0]] = phi[pb.nodal_dofs[0]]
    return Fields(vertex_u, phi_vertex, strain_cell, stress_cell, float(max_strain), x)


def max_principal(S, kin, mu, lam):
    """max |principal strain| of Voigt strains S (nS, ...); in plane stress the
    thickness strain -lam/(lam + 2 mu) (S_xx + S_zz) counts too."""
    if isinstance(kin, Solid3D):
        E = np.array([[S[0], S[5] / 2, S[4] / 2], [S[5] / 2, S[1], S[3] / 2], [S[4] / 2, S[3] / 2, S[2]]])
        extra = None
    else:
        axisym = isinstance(kin, Axisymmetric)
        xx, zz, xz = (S[0], S[2], S[3]) if axisym else (S[0], S[1], S[2])
        E = np.array([[xx, xz / 2], [xz / 2, zz]])
        extra = S[1] if axisym else -lam / (lam + 2 * mu) * (xx + zz) if isinstance(kin, PlaneStress) else None
    ev = np.linalg.eigvalsh(np.moveaxis(E, (0, 1), (-2, -1)))
    m = np.abs(ev).max()
    return float(max(m, np.abs(extra).max()) if extra is not None else m)
