r"""Yeoh hyperelastic silicone in total Lagrangian form, mixed displacement-pressure.

Energy per reference volume (two-field, perturbed Lagrangian):

    W(F, p) = Psi(I1b) + p (J - 1) - p^2 / (2 K),
    Psi = C10 (I1b - 3) + C20 (I1b - 3)^2 + C30 (I1b - 3)^3,   I1b = J^(-2/3) tr(F^T F)

Stationarity in p gives p = K (J - 1), i.e. the volumetric energy U = K/2 (J - 1)^2.
We use that form because (i) it is the classic nearly incompressible penalty that
tends to J = 1 as K/C10 grows, (ii) with P1 pressure it makes the two-field
Taylor-Hood form identical to the three-field (u, p, Jbar) Hu-Washizu form with
P1 p and Jbar that FELupe uses (U' is linear in J, so the projections coincide),
and (iii) K is the user-stated modelling parameter (docs/materials.md: no sourced
bulk modulus for Ecoflex).

Weak form (dead load t0 per reference area on the loaded top):

    R_u = \int (P_iso + p J F^-T) : Grad(du) dV - \int t0 . du dA = 0
    R_p = \int dp (J - 1 - p / K) dV = 0

with P_iso = Psi'(I1b) dI1b/dF, and the consistent tangent

    K_uu = \int Grad(du) : (A_iso + p dJF^-T/dF) : Grad(Du)
    K_up = \int J F^-T : Grad(du) Dp,     K_pp = -\int dp Dp / K
    A_iso = Psi'' dI1b/dF (x) dI1b/dF + Psi' d2I1b/dF2

Models share one 3x3 F = I + H, H from the kinematics (fem.constitution): 3D
Grad u; plane strain [[Grad u (2x2), 0], [0, 0]]; axisymmetric (r, z, theta)
H_33 = u_r / r. The law itself (Psi, P, dP/dF) is fem.constitution. Plane stress is not this form: the
sheet's thickness stretch F_33 is condensed from P_33 = 0 at each quadrature
point, a displacement-only form with the Schur-complement tangent
(fem.hyperelastic).

The piezo stays linear and small-strain (fem.assembly): its strains are ~1e-5 at
1 N, so geometric nonlinearity there is below 1e-5 relative; the silicone-piezo
coupling is monolithic (one Newton loop over u, p, phi).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from skfem import BilinearForm, LinearForm, asm

from taxel.fem.constitution import Kinematics
from taxel.fem.constitution import I3, Yeoh, inv_det, stress, tangent


def deformation_gradient(u, x, kin: Kinematics):
    return I3.reshape(3, 3, *([1] * (u.grad.ndim - 2))) + kin.grad3(u, x)


def state(ub, pb, u, p, law: Yeoh, kin: Kinematics, with_tangent=True):
    """Stress, tangent and volume terms at the quadrature points of a region, for
    the current state: computed once per assembly and handed to the forms (a form
    is evaluated once per pair of local basis functions)."""
    x = np.asarray(ub.global_coordinates())
    F = deformation_gradient(ub.interpolate(u), x, kin)
    pq = np.asarray(pb.interpolate(p))
    P, J, FiT = stress(F, pq, law.C)
    return dict(P=P, A=tangent(F, pq, law.C) if with_tangent else None, JFiT=J * FiT, Jm1=J - 1 - pq / law.K)


@lru_cache(maxsize=32)
def _forms(kin: Kinematics, K: float):
    """The five forms for one kinematics and bulk modulus (state passed as arrays)."""
    def dV(w):
        return kin.measure(w.x)

    @LinearForm
    def r_u(v, w):
        return np.einsum("ij...,ij...->...", w.P, kin.grad3(v, w.x)) * dV(w)

    @LinearForm
    def r_p(q, w):
        return q * w.Jm1 * dV(w)

    @BilinearForm
    def k_uu(du, v, w):
        return np.einsum("ij...,ijkl...,kl...->...", kin.grad3(v, w.x), w.A, kin.grad3(du, w.x)) * dV(w)

    @BilinearForm
    def k_up(dp, v, w):
        return dp * np.einsum("ij...,ij...->...", w.JFiT, kin.grad3(v, w.x)) * dV(w)

    @BilinearForm
    def k_pp(dp, q, w):
        return -dp * q / K * dV(w)
    return r_u, r_p, k_uu, k_up, k_pp


def residual(ub, pb, st, law: Yeoh, kin: Kinematics):
    """(R_u, R_p) of one region for a precomputed `state`."""
    r_u, r_p, *_ = _forms(kin, law.K)
    return asm(r_u, ub, P=st["P"]), asm(r_p, pb, Jm1=st["Jm1"])


def tangent_blocks(ub, pb, st, law: Yeoh, kin: Kinematics):
    """(K_uu, K_up, K_pp) of one region for a precomputed `state`."""
    *_, k_uu, k_up, k_pp = _forms(kin, law.K)
    return asm(k_uu, ub, A=st["A"]), asm(k_up, pb, ub, JFiT=st["JFiT"]), asm(k_pp, pb)


def min_jacobian(ub, u, kin: Kinematics):
    """Smallest J over the quadrature points of a basis (<= 0: an inverted element)."""
    return smallest_jacobian(ub, u, kin)[0]


def smallest_jacobian(ub, u, kin: Kinematics) -> tuple[float, np.ndarray]:
    """(J, X): the smallest J over the quadrature points of a basis and the point's
    reference position X (m): where the silicone crushes (J <= 0: inverted)."""
    X = np.asarray(ub.global_coordinates())
    J = inv_det(deformation_gradient(ub.interpolate(u), X, kin))[0]
    e, q = np.unravel_index(np.argmin(J), J.shape)
    return float(J[e, q]), X[:, e, q]
