r"""The Yeoh law: one definition shared by the finite-element solver and the fit.

Strain energy per reference volume, isochoric part (I1b = J^(-2/3) tr(F^T F)):

    Psi(I1b) = C10 (I1b - 3) + C20 (I1b - 3)^2 + C30 (I1b - 3)^3
    Psi'  = C10 + 2 C20 (I1b - 3) + 3 C30 (I1b - 3)^2,   Psi'' = 2 C20 + 6 C30 (I1b - 3)

Finite strain (fem.hyperelastic): first Piola-Kirchhoff stress P = Psi' dI1b/dF +
p J F^-T and its tangent dP/dF at fixed pressure p (arrays with trailing
quadrature axes).

Homogeneous incompressible modes (J = 1, I1b = I1), stretch lam along the
loading direction, nominal stress P = 2 g(lam) W'(I1) (docs/materials.md):

    uniaxial:     I1 = lam^2 + 2/lam,        g = lam - lam^-2
    equibiaxial:  I1 = 2 lam^2 + lam^-4,     g = lam - lam^-5
    pure shear:   I1 = lam^2 + 1 + lam^-2,   g = lam - lam^-3

Stability in a mode: W'(I1) > 0 and dP/dlam > 0 (fem.constitution scans it).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

MODES = ("uniaxial", "equibiaxial", "pure shear")


@dataclass(frozen=True)
class Yeoh:
    """Yeoh coefficients (Pa) and, for the compressible FEM form, the bulk modulus K (Pa)."""

    C10: float
    C20: float = 0.0
    C30: float = 0.0
    K: float | None = None

    @property
    def C(self) -> tuple[float, float, float]:
        return self.C10, self.C20, self.C30

    @property
    def mu(self) -> float:
        """Initial shear modulus, 2 C10."""
        return 2 * self.C10


# --------------------------------------------------------------------------------------
# finite strain: pure functions of I1b and F
# --------------------------------------------------------------------------------------

I3 = np.eye(3)


# --------------------------------------------------------------------------------------
# Yeoh energy: pure functions of I1b and F (arrays with trailing quadrature axes)
# --------------------------------------------------------------------------------------

def psi(I1b, C):
    """Psi = sum_i C_i0 (I1b - 3)^i."""
    d = np.asarray(I1b, float) - 3
    return C[0] * d + C[1] * d ** 2 + C[2] * d ** 3


def dpsi(I1b, C):
    """(Psi', Psi'') with respect to I1b."""
    d = np.asarray(I1b, float) - 3
    return C[0] + 2 * C[1] * d + 3 * C[2] * d ** 2, 2 * C[1] + 6 * C[2] * d


def inv_det(F):
    Fm = np.moveaxis(F, (0, 1), (-2, -1))
    J = np.linalg.det(Fm)
    Finv = np.moveaxis(np.linalg.inv(Fm), (-2, -1), (0, 1))
    return J, Finv


def stress(F, p, C):
    """First Piola-Kirchhoff stress P = P_iso + p J F^-T, with J and F^-T."""
    J, Finv = inv_det(F)
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
    J, Finv = inv_det(F)
    FiT = np.swapaxes(Finv, 0, 1)
    I1 = np.einsum("ij...,ij...->...", F, F)
    with np.errstate(invalid="ignore"):        # J <= 0 in a line-search trial: NaN, rejected by the caller's J check
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
# homogeneous incompressible deformations
# --------------------------------------------------------------------------------------

def mode_kinematics(mode: str, lam):
    """(I1, dI1/dlam, g, dg/dlam) of a mode, with P = 2 g(lam) W'(I1(lam))."""
    lam = np.asarray(lam, float)
    if mode == "uniaxial":
        return lam**2 + 2 / lam, 2 * lam - 2 / lam**2, lam - lam**-2, 1 + 2 * lam**-3
    if mode == "equibiaxial":
        return 2 * lam**2 + lam**-4, 4 * lam - 4 * lam**-5, lam - lam**-5, 1 + 5 * lam**-6
    if mode == "pure shear":
        return lam**2 + 1 + lam**-2, 2 * lam - 2 * lam**-3, lam - lam**-3, 1 + 3 * lam**-4
    raise ValueError(f"unknown deformation mode '{mode}'; known: {', '.join(MODES)}")


def nominal_stress(mode: str, lam, C10, C20, C30):
    """Nominal stress P(lam) of an incompressible Yeoh solid, Pa.

    uniaxial P = 2 (lam - lam^-2) W'(lam^2 + 2/lam); equibiaxial P = 2 (lam - lam^-5)
    W'(2 lam^2 + lam^-4); pure shear P = 2 (lam - lam^-3) W'(lam^2 + 1 + lam^-2).
    """
    I1, _, g, _ = mode_kinematics(mode, lam)
    return 2.0 * g * dpsi(I1, (C10, C20, C30))[0]


def nominal_tangent(mode: str, lam, C10, C20, C30):
    """dP/dlam = 2 (g' W'(I1) + g W''(I1) dI1/dlam), with P = 2 g(lam) W'(I1(lam))."""
    I1, dI1, g, dg = mode_kinematics(mode, lam)
    d1, d2 = dpsi(I1, (C10, C20, C30))
    return 2.0 * (dg * d1 + g * d2 * dI1)


def is_stable(mode: str, lam, C10, C20, C30):
    """Drucker-like stability of the Yeoh law at stretch lam in a mode.

    Stable where W'(I1) > 0 (positive slope of the energy in I1, i.e. positive
    initial-shear-like stiffness 2 W') and the nominal stress rises with stretch,
    dP/dlam > 0. (W'' may be negative where both hold: convexity of W in I1 is
    sufficient, not necessary, for these homogeneous modes.)
    """
    I1, *_ = mode_kinematics(mode, lam)
    return (dpsi(I1, (C10, C20, C30))[0] > 0) & (nominal_tangent(mode, lam, C10, C20, C30) > 0)


def instability_reason(mode: str, lam, C10, C20, C30) -> str:
    """Which condition fails at lam: 'W\\'(I1) <= 0', 'dP/dlam <= 0', or '' if stable."""
    I1, *_ = mode_kinematics(mode, lam)
    if dpsi(I1, (C10, C20, C30))[0] <= 0:
        return "W'(I1) <= 0"
    if nominal_tangent(mode, lam, C10, C20, C30) <= 0:
        return "dP/dlam <= 0"
    return ""


# --------------------------------------------------------------------------------------
# batched form (leading batch axis, N x 3 x 3): the vectorised assembly (fem.hyperelastic)
# --------------------------------------------------------------------------------------

def inv_det_batched(F):
    """(J, F^-1) of F (N, 3, 3) by the adjugate (no LAPACK call per matrix)."""
    a, b, c = F[:, 0, 0], F[:, 0, 1], F[:, 0, 2]
    d, e, f = F[:, 1, 0], F[:, 1, 1], F[:, 1, 2]
    g, h, i = F[:, 2, 0], F[:, 2, 1], F[:, 2, 2]
    adj = np.empty_like(F)
    adj[:, 0, 0], adj[:, 0, 1], adj[:, 0, 2] = e * i - f * h, c * h - b * i, b * f - c * e
    adj[:, 1, 0], adj[:, 1, 1], adj[:, 1, 2] = f * g - d * i, a * i - c * g, c * d - a * f
    adj[:, 2, 0], adj[:, 2, 1], adj[:, 2, 2] = d * h - e * g, b * g - a * h, a * e - b * d
    J = a * adj[:, 0, 0] + b * adj[:, 1, 0] + c * adj[:, 2, 0]
    return J, adj / J[:, None, None]


def stress_tangent_batched(F, p, C, with_tangent=True):
    """(P, A, J, J F^-T) for F (N, 3, 3), p (N,): the same quantities as `stress` and
    `tangent` (A as (N, 9, 9), rows iJ, columns kL), batch axis first."""
    J, Finv = inv_det_batched(F)
    FiT = Finv.transpose(0, 2, 1)
    I1 = np.einsum("nij,nij->n", F, F)
    with np.errstate(invalid="ignore"):        # J <= 0 in a line-search trial: NaN, rejected by the caller's J check
        a = J ** (-2.0 / 3.0)
    G = 2 * F - (2.0 / 3.0) * I1[:, None, None] * FiT
    d1, d2 = dpsi(a * I1, C)
    JFiT = J[:, None, None] * FiT
    P = d1[:, None, None] * a[:, None, None] * G + p[:, None, None] * JFiT
    if not with_tangent:
        return P, None, J, JFiT
    N = len(J)
    f, Gf, Ff = FiT.reshape(N, 9), G.reshape(N, 9), F.reshape(N, 9)
    # A = s2 G(x)G + s1 (2 I - 4/3 f(x)F + 2/3 I1 X - 2/3 G(x)f) + pJ (f(x)f - X), s1 = Psi' a,
    # s2 = Psi'' a^2, grouped as two outer products, one scaled X and the diagonal
    # (fewer N x 9 x 9 temporaries)
    s1, s2, pJ = d1 * a, d2 * a * a, p * J
    A = Gf[:, :, None] * (s2[:, None] * Gf - (2.0 / 3.0) * s1[:, None] * f)[:, None, :]
    A += f[:, :, None] * (pJ[:, None] * f - (4.0 / 3.0) * s1[:, None] * Ff)[:, None, :]
    A += np.einsum("nJk,nLi->niJkL", Finv * ((2.0 / 3.0) * s1 * I1 - pJ)[:, None, None], Finv).reshape(N, 9, 9)
    A[:, np.arange(9), np.arange(9)] += 2 * s1[:, None]
    return P, A, J, JFiT
