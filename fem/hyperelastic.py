r"""Yeoh hyperelastic silicone in total Lagrangian form, mixed displacement-pressure.

Energy per reference volume (two-field, perturbed Lagrangian):

    W(F, p) = Psi(I1b) + p (J - 1) - p^2 / (2 K),
    Psi = C10 (I1b - 3) + C20 (I1b - 3)^2 + C30 (I1b - 3)^3,   I1b = J^(-2/3) tr(F^T F)

Stationarity in p gives p = K (J - 1), i.e. the volumetric energy U = K/2 (J - 1)^2.
We use that form because (i) it is the classic nearly incompressible penalty that
tends to J = 1 as K/C10 grows, (ii) with P1 pressure it makes the two-field
Taylor-Hood form identical to the three-field (u, p, Jbar) Hu-Washizu form with
P1 p and Jbar that FELupe uses (U' is linear in J, so the projections coincide),
and (iii) K is the user-stated modelling parameter (REFERENCE.md: no sourced
bulk modulus for Ecoflex).

Weak form (dead load t0 per reference area on the loaded top):

    R_u = \int (P_iso + p J F^-T) : Grad(du) dV - \int t0 . du dA = 0
    R_p = \int dp (J - 1 - p / K) dV = 0

with P_iso = Psi'(I1b) dI1b/dF, and the consistent tangent

    K_uu = \int Grad(du) : (A_iso + p dJF^-T/dF) : Grad(Du)
    K_up = \int J F^-T : Grad(du) Dp,     K_pp = -\int dp Dp / K
    A_iso = Psi'' dI1b/dF (x) dI1b/dF + Psi' d2I1b/dF2

Models share one 3x3 F: 3D F = I + Grad u; plane strain F = [[Grad u (2x2), 0],
[0, 1]]; axisymmetric (r, z, theta) F_33 = 1 + u_r / r. Volume measure as in
fem.forms (depth, 2 pi r). Plane stress is not offered for Yeoh: an
incompressible sheet needs F_33 = 1/J_2D and a condensed tangent; use plane
strain or axisymmetric (the issue's "own treatment": we say no and explain).

The piezo stays linear and small-strain (fem.forms): its strains are ~1e-5 at
1 N, so geometric nonlinearity there is below 1e-5 relative; the silicone-piezo
coupling is monolithic (one Newton loop over u, p, phi).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from skfem import BilinearForm, LinearForm, asm

from fem.forms import measure

I3 = np.eye(3)


# --------------------------------------------------------------------------------------
# Yeoh energy: pure functions of I1b and F (arrays with trailing quadrature axes)
# --------------------------------------------------------------------------------------

def psi(I1b, C):
    """Psi = sum_i C_i0 (I1b - 3)^i."""
    d = I1b - 3
    return C[0] * d + C[1] * d ** 2 + C[2] * d ** 3


def dpsi(I1b, C):
    """(Psi', Psi'') with respect to I1b."""
    d = I1b - 3
    return C[0] + 2 * C[1] * d + 3 * C[2] * d ** 2, 2 * C[1] + 6 * C[2] * d


def _inv_det(F):
    Fm = np.moveaxis(F, (0, 1), (-2, -1))
    J = np.linalg.det(Fm)
    Finv = np.moveaxis(np.linalg.inv(Fm), (-2, -1), (0, 1))
    return J, Finv


def stress(F, p, C):
    """First Piola-Kirchhoff stress P = P_iso + p J F^-T, with J and F^-T."""
    J, Finv = _inv_det(F)
    FiT = np.swapaxes(Finv, 0, 1)
    I1 = np.einsum("ij...,ij...->...", F, F)
    a = J ** (-2.0 / 3.0)
    dI1b = a * (2 * F - (2.0 / 3.0) * I1 * FiT)
    d1, _ = dpsi(a * I1, C)
    return d1 * dI1b + p * J * FiT, J, FiT


def tangent(F, p, C):
    """dP/dF (3,3,3,3,...) at fixed p: A_iso + p d(J F^-T)/dF.

    d(F^-T)_iJ / dF_kL = -F^-1_Jk F^-1_Li;  dJ/dF = J F^-T;  dI1/dF = 2F;
    dI1b/dF = a (2F - 2/3 I1 F^-T), a = J^-2/3, da/dF = -2/3 a F^-T.
    """
    J, Finv = _inv_det(F)
    FiT = np.swapaxes(Finv, 0, 1)
    I1 = np.einsum("ij...,ij...->...", F, F)
    a = J ** (-2.0 / 3.0)
    G = 2 * F - (2.0 / 3.0) * I1 * FiT                    # dI1b/dF = a G
    d1, d2 = dpsi(a * I1, C)
    X = np.einsum("Jk...,Li...->iJkL...", Finv, Finv)     # -d(F^-T)/dF
    II = np.einsum("ik,JL->iJkL", I3, I3)[..., None, None]
    d2I1b = (a * (2 * II - (4.0 / 3.0) * np.einsum("iJ...,kL...->iJkL...", FiT, F)
                  + (2.0 / 3.0) * I1 * X)
             - (2.0 / 3.0) * a * np.einsum("kL...,iJ...->iJkL...", FiT, G))
    A = d2 * a * a * np.einsum("iJ...,kL...->iJkL...", G, G) + d1 * d2I1b
    A += p * J * (np.einsum("iJ...,kL...->iJkL...", FiT, FiT) - X)
    return A


# --------------------------------------------------------------------------------------
# kinematics per model and the weak forms
# --------------------------------------------------------------------------------------

def grad3(u, x, model):
    """The 3x3 gradient of a vector field (for F = I + grad3(u) and its variations)."""
    g = u.grad
    if model == "3d":
        return np.asarray(g)
    G = np.zeros((3, 3) + g.shape[2:])
    G[:2, :2] = g
    if model == "axisymmetric":
        G[2, 2] = u[0] / x[0]
    return G


def deformation_gradient(u, x, model):
    return I3.reshape(3, 3, *([1] * (u.grad.ndim - 2))) + grad3(u, x, model)


def state(ub, pb, u, p, C, K, model, with_tangent=True):
    """Stress, tangent and volume terms at the quadrature points of a region, for
    the current state: computed once per assembly and handed to the forms (a form
    is evaluated once per pair of local basis functions)."""
    x = np.asarray(ub.global_coordinates())
    F = deformation_gradient(ub.interpolate(u), x, model)
    pq = np.asarray(pb.interpolate(p))
    P, J, FiT = stress(F, pq, C)
    return dict(P=P, A=tangent(F, pq, C) if with_tangent else None, JFiT=J * FiT, Jm1=J - 1 - pq / K)


@lru_cache(maxsize=32)
def _forms(model, depth, K):
    """The five forms for one model, depth and bulk modulus (state passed as arrays)."""
    def dV(w):
        return measure(w.x, model, depth)

    @LinearForm
    def r_u(v, w):
        return np.einsum("ij...,ij...->...", w.P, grad3(v, w.x, model)) * dV(w)

    @LinearForm
    def r_p(q, w):
        return q * w.Jm1 * dV(w)

    @BilinearForm
    def k_uu(du, v, w):
        return np.einsum("ij...,ijkl...,kl...->...", grad3(v, w.x, model), w.A, grad3(du, w.x, model)) * dV(w)

    @BilinearForm
    def k_up(dp, v, w):
        return dp * np.einsum("ij...,ij...->...", w.JFiT, grad3(v, w.x, model)) * dV(w)

    @BilinearForm
    def k_pp(dp, q, w):
        return -dp * q / K * dV(w)
    return r_u, r_p, k_uu, k_up, k_pp


def residual(ub, pb, st, K, model, depth):
    """(R_u, R_p) of one region for a precomputed `state`."""
    r_u, r_p, *_ = _forms(model, depth, K)
    return asm(r_u, ub, P=st["P"]), asm(r_p, pb, Jm1=st["Jm1"])


def tangent_blocks(ub, pb, st, K, model, depth):
    """(K_uu, K_up, K_pp) of one region for a precomputed `state`."""
    *_, k_uu, k_up, k_pp = _forms(model, depth, K)
    return asm(k_uu, ub, A=st["A"]), asm(k_up, pb, ub, JFiT=st["JFiT"]), asm(k_pp, pb)


def min_jacobian(ub, u, model):
    """Smallest J over the quadrature points of a basis (<= 0: an inverted element)."""
    F = deformation_gradient(ub.interpolate(u), np.asarray(ub.global_coordinates()), model)
    return float(_inv_det(F)[0].min())
