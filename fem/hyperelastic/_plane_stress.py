r"""Yeoh silicone in plane stress: the out-of-plane stretch condensed at every point.

A thin sheet in the (x, z) plane, free on its faces y = +-t/2 (the thesis's 2D
COMSOL model of Figs. 2.5-2.9). The in-plane deformation gradient F2 (2x2) comes
from the displacement; the thickness stretch lambda3 is not a displacement
unknown but is fixed, point by point, by the traction-free faces, P33 = 0:

    F = [[F2, 0], [0, lambda3]],   J = J2 lambda3,   J2 = det F2

Energy (per reference volume) of the tool's nearly incompressible Yeoh law
(fem.hyperelastic: the two-field form with p eliminated, p = K (J - 1)):

    W(F) = Psi(I1b) + K/2 (J - 1)^2,   I1b = J^(-2/3) (tr(F2^T F2) + lambda3^2)

Condensation. The sheet's energy is W2(F2) = W(F2, lambda3(F2)) with lambda3 the
stationary point dW/dF33 = P33(F2, lambda3) = 0. Written out (G = dI1b/dF / a,
a = J^(-2/3), Psi' = dPsi/dI1b):

    P33 = Psi' a (2 lambda3 - 2 I1 / (3 lambda3)) + K (J - 1) J2 = 0

solved at each quadrature point by a local Newton in e = J - 1 (lambda3 = (1 + e) / J2;
start e = 0, the incompressible value; dP33/de = A3333 / J2 > 0 on the stable branch).
Because P33 = 0 there, the first derivative of W2 is the in-plane block of the
3D stress (the envelope theorem), P2_ab = P_ab, and the second derivative is the
Schur complement of the 3D tangent A = dP/dF of the full law (A at fixed p of
fem.constitution plus K (J F^-T) (x) (J F^-T), the p = K (J - 1) variation):

    dlambda3 / dF_cd = -A_33cd / A_3333
    A2_abcd = A_abcd - A_ab33 A_33cd / A_3333          (a, b, c, d in-plane)

symmetric, the consistent tangent of the condensed law. Exactly incompressible
(Yeoh.K None or infinite): lambda3 = 1/J2 in closed form, I1 = tr(C2) + J2^-2,
W2 = Psi(I1) and

    P2 = Psi'(I1) G,  G = 2 F2 - 2 J2^-2 F2^-T
    A2 = Psi'' G (x) G + Psi' (2 II + 4 J2^-2 F2^-T (x) F2^-T + 2 J2^-2 X),
    X_abcd = F2^-1_bc F2^-1_da

Weak form (total Lagrangian, reference thickness t = the model's depth, dead
load t0 per reference area on the loaded edge):

    R_u = \int_A t P2(F2) : Grad(du) dA - \int t t0 . du ds = 0
    K_uu = \int_A t Grad(du) : A2 : Grad(Du) dA

a displacement-only form: the in-plane sheet is compressible (lambda3 takes up
the volume change), so it does not lock and needs no pressure field. The
assembly gives a mixed silicone a pressure field (fem.assembly); here it is held
at p = 0 by its own mass term (-\int q p / mu dA, no coupling), so the
element-mean stress of fem.static for such a region is 2 mu S, not the Yeoh
stress. The piezo stays linear with its exact plane-stress reduction
(fem.constitution). Assumptions: the sheet stays thin (no out-of-plane bending),
the load is dead (per reference area); the strain energy, K and the Yeoh
constants are the 3D law's, so a homogeneous uniaxial state equals the 3D bar's.
Units SI (stresses and K in Pa, t in m). Verified against the incompressible closed forms (fem.constitution.nominal_stress) and
against a thin 3D slab: tests/test_yeoh_plane_stress.py.
"""

from __future__ import annotations

import math

import numpy as np

from taxel.fem.constitution import Kinematics
from taxel.fem.constitution import Yeoh, dpsi
from ._terms import Terms

CHUNK = 4000


class CondensationError(ArithmeticError):
    """The local Newton for lambda3 did not converge at some point."""


def incompressible(law: Yeoh) -> bool:
    return law.K is None or math.isinf(law.K)


def thickness_stretch(F2, law: Yeoh, tol=1e-13, max_iter=40):
    """(lambda3, J - 1) (N,) with P33 = 0 for in-plane gradients F2 (N, 2, 2); NaN where
    J2 <= 0 or where the local Newton does not converge (the caller rejects such a state).

    The local unknown is e = J - 1 (lambda3 = (1 + e) / J2), so that the volumetric
    stress p = K e carries no cancellation error (K eps J would be ~1e-9 Pa at the
    tool's K, above the global Newton's tolerance at small loads)."""
    J2 = F2[:, 0, 0] * F2[:, 1, 1] - F2[:, 0, 1] * F2[:, 1, 0]
    ok = J2 > 0
    e = np.full(len(J2), np.nan)
    e[ok] = 0.0
    if incompressible(law):
        return (1 + e) / J2, e
    K, C = law.K, law.C
    trC2 = np.einsum("nij,nij->n", F2, F2)
    scale = 2 * C[0]
    todo = np.flatnonzero(ok)
    for _ in range(max_iter):
        if todo.size == 0:
            break
        j2, tc, ee = J2[todo], trC2[todo], e[todo]
        l = (1 + ee) / j2
        I1 = tc + l * l
        a = (1 + ee) ** (-2.0 / 3.0)
        d1, d2 = dpsi(a * I1, C)
        G33 = 2 * l - 2 * I1 / (3 * l)
        g = d1 * a * G33 + K * ee * j2
        dg_dl = d2 * a * a * G33 ** 2 + d1 * a * (2.0 / 3.0 - 2 * G33 / (3 * l) + 2 * I1 / (3 * l * l)) + K * j2 * j2
        step = -g / (dg_dl / j2)
        new = ee + step
        while np.any(bad := ~(new > -1)):          # keep lambda3 positive: halve the step there
            step[bad] /= 2
            new = ee + step
        e[todo] = new
        done = (np.abs(g) <= tol * scale) | (np.abs(step) <= 1e-16)
        todo = todo[~done]
    e[todo] = np.nan
    return (1 + e) / J2, e


def stress_tangent(F2, law: Yeoh, with_tangent=True):
    """(P2 (N, 2, 2), A2 (N, 4, 4) or None, J (N,), lambda3 (N,)) of the condensed
    plane-stress law at in-plane gradients F2 (N, 2, 2); rows/columns of A2 are
    the flattened (a, b) = 00, 01, 10, 11."""
    l3, e = thickness_stretch(F2, law)
    if incompressible(law):
        return (*_incompressible(F2, law.C, l3, with_tangent), l3)
    return (*_compressible(F2, law.C, law.K, l3, e, with_tangent), l3)


def _compressible(F2, C, K, l3, e, with_tangent):
    """(P2, A2, J) of the condensed law W = Psi(I1b) + K/2 (J - 1)^2 at lambda3 (P33 = 0),
    written out for the block-diagonal F (fem.constitution's dP/dF restricted to it; with
    X_iJkL = F^-1_Jk F^-1_Li, G = 2F - 2/3 I1 F^-T, p = K (J - 1)):

        A_ab,cd = Psi'' a^2 G_ab G_cd + Psi' a (2 II - 4/3 F^-T (x) F - 2/3 G (x) F^-T + 2/3 I1 X)
                  + (p J + K J^2) F^-T (x) F^-T - p J X
        A_ab,33 = Psi'' a^2 G_ab G33 - Psi' a (4/3 lambda3 F^-T_ab + 2/3 G_ab / lambda3)
                  + (p J + K J^2) F^-T_ab / lambda3
        A_33,33 = Psi'' a^2 G33^2 + Psi' a (2/3 + 2/3 I1 / lambda3^2 - 2/3 G33 / lambda3) + K J^2 / lambda3^2

    (2D arrays only, no 3x3 law per point: the region's terms 3 x cheaper on a thesis point,
    cProfile; tests/test_yeoh_plane_stress.py compares it with the 3x3 law fem.constitution)."""
    N = len(F2)
    J = 1 + e
    J2 = J / l3
    Finv = np.empty_like(F2)
    Finv[:, 0, 0], Finv[:, 1, 1] = F2[:, 1, 1] / J2, F2[:, 0, 0] / J2
    Finv[:, 0, 1], Finv[:, 1, 0] = -F2[:, 0, 1] / J2, -F2[:, 1, 0] / J2
    FiT = Finv.transpose(0, 2, 1)
    I1 = np.einsum("nij,nij->n", F2, F2) + l3 * l3
    with np.errstate(invalid="ignore"):
        a = J ** (-2.0 / 3.0)
    d1, d2 = dpsi(a * I1, C)
    G = 2 * F2 - (2.0 / 3.0) * I1[:, None, None] * FiT
    pJ = K * e * J
    P2 = (d1 * a)[:, None, None] * G + pJ[:, None, None] * FiT
    if not with_tangent:
        return P2, None, J
    g, f, Ff = G.reshape(N, 4), FiT.reshape(N, 4), F2.reshape(N, 4)
    X = np.einsum("nJk,nLi->niJkL", Finv, Finv).reshape(N, 4, 4)
    ff = f[:, :, None] * f[:, None, :]
    da, vol = d1 * a, pJ + K * J * J
    A = (d2 * a * a)[:, None, None] * g[:, :, None] * g[:, None, :]
    A += da[:, None, None] * (2 * np.eye(4) - (4.0 / 3.0) * f[:, :, None] * Ff[:, None, :]
                              - (2.0 / 3.0) * g[:, :, None] * f[:, None, :] + (2.0 / 3.0) * I1[:, None, None] * X)
    A += vol[:, None, None] * ff - pJ[:, None, None] * X
    G33 = 2 * l3 - (2.0 / 3.0) * I1 / l3
    c = ((d2 * a * a * G33)[:, None] * g - da[:, None] * ((4.0 / 3.0) * l3[:, None] * f + (2.0 / 3.0) * g / l3[:, None])
         + (vol / l3)[:, None] * f)
    A33 = d2 * a * a * G33 ** 2 + da * (2.0 / 3.0 + (2.0 / 3.0) * I1 / l3 ** 2 - (2.0 / 3.0) * G33 / l3) \
        + K * J * J / l3 ** 2
    return P2, A - c[:, :, None] * c[:, None, :] / A33[:, None, None], J


def _incompressible(F2, C, l3, with_tangent):
    """(P2, A2, J = 1) of the exactly incompressible sheet, lambda3 = 1/J2 (module docstring)."""
    N = len(F2)
    J2 = 1.0 / l3
    Finv = np.empty_like(F2)
    Finv[:, 0, 0], Finv[:, 1, 1] = F2[:, 1, 1] / J2, F2[:, 0, 0] / J2
    Finv[:, 0, 1], Finv[:, 1, 0] = -F2[:, 0, 1] / J2, -F2[:, 1, 0] / J2
    FiT = Finv.transpose(0, 2, 1)
    m = l3 * l3                                         # J2^-2
    I1 = np.einsum("nij,nij->n", F2, F2) + m
    d1, d2 = dpsi(I1, C)
    G = 2 * F2 - 2 * m[:, None, None] * FiT
    P2 = d1[:, None, None] * G
    J = np.where(np.isfinite(l3), 1.0, np.nan)
    if not with_tangent:
        return P2, None, J
    g, f = G.reshape(N, 4), FiT.reshape(N, 4)
    X = np.einsum("nbc,nda->nabcd", Finv, Finv).reshape(N, 4, 4)
    A2 = d2[:, None, None] * g[:, :, None] * g[:, None, :] + d1[:, None, None] * (
        2 * np.eye(4) + m[:, None, None] * (4 * f[:, :, None] * f[:, None, :] + 2 * X))
    return P2, A2, J


class PlaneStressYeohRegion:
    """One Yeoh region of a plane-stress model: constant arrays built once, and its
    element residuals and matrices at a state (the interface of fem.hyperelastic.YeohRegion,
    which fem.hyperelastic calls)."""

    def __init__(self, ub, pb, law: Yeoh, kin: Kinematics, p_offset: int):
        self.law = law
        nb = len(ub.basis) // 2
        self.nb = nb
        fns = [ub.basis[2 * a][0] for a in range(nb)]                      # component 0 of node a
        self.dN = np.stack([np.asarray(f.grad[0]) for f in fns], axis=-1).transpose(1, 2, 0, 3)  # (ne, nq, 2, nb)
        x = np.asarray(ub.global_coordinates())
        self.w = ub.dx * np.broadcast_to(kin.measure(x), ub.dx.shape)       # (ne, nq)
        self.ne = self.dN.shape[0]
        self.udofs = np.ascontiguousarray(ub.element_dofs.T)                # (ne, 2 nb): (a, c) -> 2 a + c
        self.hold = None
        if pb is not None:                                                  # the assembly's pressure: held at 0
            M = np.stack([np.asarray(pb.basis[b][0].value) for b in range(len(pb.basis))], axis=-1)
            self.hold = -np.einsum("eqa,eqb,eq->eab", M, M, self.w) / law.mu
            self.pdofs = np.ascontiguousarray(pb.element_dofs.T) + p_offset
        else:
            self.pdofs = np.zeros((self.ne, 0), int)
        B = np.zeros((self.ne, self.dN.shape[1], 4, nb, 2))
        for c in range(2):
            for l in range(2):
                B[:, :, 2 * c + l, :, c] = self.dN[:, :, l, :]
        self.B = B.reshape(self.ne, self.dN.shape[1], 4, 2 * nb)            # (ne, nq, (c, l), (a, c))
        self._last = None                                                   # (ue, r_u, min J) of the last state

    def terms(self, x: np.ndarray, with_tangent=True) -> Terms:
        """Element residuals (and matrices) at the full state vector x."""
        ue = x[self.udofs]                                                  # (ne, 2 nb)
        ne, nq = self.w.shape
        if not with_tangent and self._last is not None and np.array_equal(self._last[0], ue):
            r_u, min_J = self._last[1:]          # fem.hyperelastic's line search asks twice per trial state
        else:
            r_u, K_uu, min_J = self._element_terms(ue, with_tangent)
            self._last = (ue, r_u, min_J)
        npb = self.pdofs.shape[1]
        p = x[self.pdofs] if npb else np.zeros((ne, 0))
        r_p = np.einsum("eab,eb->ea", self.hold, p) if npb else p
        if not with_tangent:
            return Terms(r_u, r_p, None, None, None, min_J)
        return Terms(r_u, r_p, K_uu, np.zeros((ne, 2 * self.nb, npb)),
                     self.hold if npb else np.zeros((ne, 0, 0)), min_J)

    def _element_terms(self, ue, with_tangent):
        """(r_u, K_uu or None, min J) from the element displacements ue (ne, 2 nb)."""
        ne, nq = self.w.shape
        K_uu = np.empty((ne, 2 * self.nb, 2 * self.nb)) if with_tangent else None
        r_u = np.empty((ne, 2 * self.nb))
        min_J = np.inf
        for s in range(0, ne, CHUNK):
            sl = slice(s, min(s + CHUNK, ne))
            B, w = self.B[sl], self.w[sl]
            F2 = (np.matmul(B, ue[sl][:, None, :, None])[..., 0] + np.array([1.0, 0, 0, 1])).reshape(-1, 2, 2)
            P2, A2, J, _ = stress_tangent(F2, self.law, with_tangent)
            min_J = min(min_J, float(np.min(J)) if np.all(np.isfinite(J)) else -np.inf)
            r_u[sl] = np.matmul((P2.reshape(-1, nq, 4) * w[..., None])[:, :, None, :], B)[:, :, 0, :].sum(axis=1)
            if with_tangent:
                AB = np.matmul(A2.reshape(-1, nq, 4, 4) * w[..., None, None], B)
                n = sl.stop - sl.start
                K_uu[sl] = np.matmul(B.transpose(0, 3, 1, 2).reshape(n, -1, nq * 4), AB.reshape(n, nq * 4, -1))
        return r_u, K_uu, min_J
