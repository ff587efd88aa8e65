r"""Vectorised residual and consistent tangent of the Yeoh silicone (the weak form
and its linearisation: fem.hyperelastic's docstring), for every element of a region
at once.

With the scalar shape functions N_a of the displacement element and the pressure
functions M_b, the 3x3 gradient of the vector function (a, c) is

    Grad3(N_a e_c)_{kl} = delta_{kc} dN_a/dX_l        (l < dim)
                        + delta_{c0} delta_{k2} delta_{l2} N_a / r   (axisymmetric hoop term)

collected once per region as B[e, q, kl, (a, c)] (reference configuration: total
Lagrangian, so B never changes). At a state (u, p), with dV = w_q |det J| * measure:

    F = I + sum_(a,c) B u_(a,c),   (P, A, J) = fem.constitution.stress_tangent_batched(F, p)
    r_u[e, (a,c)]          = sum_q B^T P dV
    r_p[e, b]              = sum_q M_b (J - 1 - p/K) dV
    K_uu[e, (a,c), (b,d)]  = sum_q B^T A B dV          (one batched matmul)
    K_up[e, (a,c), b]      = sum_q B^T (J F^-T) M_b dV,   K_pp[e] = -sum_q M M^T dV / K

Only the gradient components the model uses enter (2D: 4, axisymmetric: 5, 3D: 9).
No Python loop runs over elements; elements go in chunks to bound memory. The
element arrays are scattered into the eliminated matrix by fem.assembly. Equal to the
scikit-fem forms of fem.hyperelastic to round-off (tests/test_hyperelastic.py).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from skfem import ElementVector

from taxel.fem.constitution import Axisymmetric, Kinematics
from taxel.fem.assembly import scalar_quantities, weights
from taxel.fem.constitution import Yeoh, stress_tangent_batched

CHUNK = 512          # elements per batch: the per-point arrays stay in cache (1 mm 3D taxel: 0.09 s against 0.12 s at 4000)


@dataclass
class Terms:
    """Element residuals and matrices of one region at one state."""

    r_u: np.ndarray                  # (ne, nu)
    r_p: np.ndarray                  # (ne, np)
    K_uu: np.ndarray | None          # (ne, nu, nu)
    K_up: np.ndarray | None          # (ne, nu, np)
    K_pp: np.ndarray | None          # (ne, np, np)
    min_J: float


class YeohRegion:
    """The constant arrays of one Yeoh region (built once) and its state-dependent terms."""

    def __init__(self, ub, pb, law: Yeoh, kin: Kinematics, p_offset: int):
        """`ub`: the displacement basis, vector, or its scalar element (10 functions for
        a P2 tetrahedron instead of 30; the vector DOF map is derived, scikit-fem's
        ElementVector numbering: dim s + c)."""
        self.law, self.kin = law, kin
        dim = kin.dim
        self.dim = dim
        sl = slice(None)
        self.dN = np.ascontiguousarray(scalar_quantities(ub, "grad", sl))   # (ne, nq, dim, nb)
        # the same gradients as (ne, nq, nb, dim) and (ne, nb, nq * dim): constant (total Lagrangian)
        self.dNa = np.ascontiguousarray(self.dN.transpose(0, 1, 3, 2))
        self.dNb = np.ascontiguousarray(self.dN.transpose(0, 3, 1, 2)).reshape(self.dN.shape[0], -1,
                                                                            self.dN.shape[1] * dim)
        ne, nq, _, nb = self.dN.shape
        self.nb = nb
        self.w = np.ascontiguousarray(weights(ub, kin, sl))          # (ne, nq)
        self.M = scalar_quantities(pb, "value", sl)[:, :, 0, :]       # (ne, nq, npb)
        self.hoop = None
        comps = [3 * k + l for k in range(dim) for l in range(dim)]
        vector = isinstance(ub.elem, ElementVector)
        if isinstance(kin, Axisymmetric):
            r = np.asarray(ub.global_coordinates())[0]
            N = np.stack([np.asarray(ub.basis[a * dim][0].value)[0] if vector else np.asarray(ub.basis[a][0].value)
                          for a in range(nb)], axis=-1)
            self.hoop = N / r[..., None]                                # (ne, nq, nb): N_a / r
            comps.append(8)
        self.comps = np.array(comps)
        if vector:                                                     # (ne, nb*dim), (a, c) -> a*dim + c
            self.udofs = np.ascontiguousarray(ub.element_dofs.T)
        else:                       # a scalar basis: the vector DOF of (scalar DOF s, component c) is dim s + c
            self.udofs = (dim * ub.element_dofs.T[:, :, None] + np.arange(dim)).reshape(ne, nb * dim)
        self.pdofs = np.ascontiguousarray(pb.element_dofs.T) + p_offset
        self.ne = ne
        self._B = None                   # cached B when a single chunk holds the region

    def B(self, sl) -> np.ndarray:
        """(ne, nq, ncomp, nb*dim): the used 3x3 gradient components of every local function."""
        dN = self.dN[sl]
        ne, nq, dim, nb = dN.shape
        B = np.zeros((ne, nq, len(self.comps), nb, dim))
        for c in range(dim):
            for l in range(dim):
                B[:, :, c * dim + l, :, c] = dN[:, :, l, :]
        if self.hoop is not None:
            B[:, :, -1, :, 0] = self.hoop[sl]
        return B.reshape(ne, nq, len(self.comps), nb * dim)

    def gradient(self, ue, sl) -> np.ndarray:
        """(ne, nq, 3, 3) F - I from the element displacements ue (ne, nb, dim)."""
        dN = self.dN[sl]
        ne, nq = dN.shape[:2]
        H = np.zeros((ne, nq, 3, 3))
        H[:, :, :self.dim, :self.dim] = np.matmul(dN, ue[:, None]).transpose(0, 1, 3, 2)   # sum_a dN_la u_ac
        if self.hoop is not None:
            H[:, :, 2, 2] = np.einsum("eqa,ea->eq", self.hoop[sl], ue[:, :, 0])
        return H

    def terms(self, x: np.ndarray, with_tangent=True) -> Terms:
        """Element residuals (and matrices) at the full state vector x."""
        out = []
        for start in range(0, self.ne, CHUNK):
            out.append(self._chunk(x, slice(start, min(start + CHUNK, self.ne)), with_tangent))
        if len(out) == 1:
            return out[0]
        cat = (lambda k: np.concatenate([getattr(t, k) for t in out]) if with_tangent or k.startswith("r")
               else None)
        return Terms(cat("r_u"), cat("r_p"), cat("K_uu"), cat("K_up"), cat("K_pp"), min(t.min_J for t in out))

    def _chunk(self, x, sl, with_tangent):
        law = self.law
        ue = x[self.udofs[sl]].reshape(-1, self.nb, self.dim)
        ne = ue.shape[0]
        nq = self.w.shape[1]
        F = self.gradient(ue, sl) + np.eye(3)
        M = self.M[sl]
        p = np.matmul(M, x[self.pdofs[sl]][:, :, None])[..., 0]
        P, A, J, JFiT = stress_tangent_batched(F.reshape(-1, 3, 3), p.ravel(), law.C, with_tangent)
        w = self.w[sl]
        c = self.comps
        Pc = P.reshape(ne, nq, 9)[:, :, c] * w[..., None]
        r_p = np.matmul(M.transpose(0, 2, 1), ((J.reshape(ne, nq) - 1 - p / law.K) * w)[:, :, None])[..., 0]
        if self.hoop is None:            # no hoop term: through the scalar gradients, no B
            return self._scalar_chunk(sl, Pc, A, JFiT, M, w, r_p, J, with_tangent)
        if ne == self.ne:
            if self._B is None:
                self._B = self.B(sl)
            B = self._B
        else:
            B = self.B(sl)
        r_u = np.einsum("eqk,eqki->ei", Pc, B)
        if not with_tangent:
            return Terms(r_u, r_p, None, None, None, float(J.min()))
        Ac = A.reshape(ne, nq, 9, 9)[:, :, c][:, :, :, c] * w[..., None, None]
        AB = np.matmul(Ac, B)                                            # (ne, nq, nc, nu)
        nc, nu = B.shape[2], B.shape[3]
        K_uu = np.matmul(B.transpose(0, 3, 1, 2).reshape(ne, nu, nq * nc), AB.reshape(ne, nq * nc, nu))
        Jc = JFiT.reshape(ne, nq, 9)[:, :, c] * w[..., None]
        K_up = np.einsum("eqki,eqk,eqb->eib", B, Jc, M)
        K_pp = -np.einsum("eqa,eqb,eq->eab", M, M, w) / law.K
        return Terms(r_u, r_p, K_uu, K_up, K_pp, float(J.min()))

    def _scalar_chunk(self, sl, Pc, A, JFiT, M, w, r_p, J, with_tangent):
        """The terms through the scalar gradients dN (no hoop term): with F - I =
        sum_(a,c) e_c (x) dN_a u_(a,c),

            r_u[(a,c)]        = sum_q sum_l dN_la P_cl dV
            K_uu[(a,c),(b,d)] = sum_q sum_(l,m) dN_la A_(cl)(dm) dN_mb dV
            K_up[(a,c),b]     = sum_q sum_l dN_la (J F^-T)_cl M_b dV,

        two batched products each (the vector basis's 3x-sparse B never formed):
        3x fewer operations than B^T A B for P2 tetrahedra."""
        dN, dNa, dNb = self.dN[sl], self.dNa[sl], self.dNb[sl]   # (l, a); (a, l); a, (q, l)
        ne, nq, d, nb = dN.shape
        Pl = Pc.reshape(ne, nq, d, d).transpose(0, 1, 3, 2)       # (l, c)
        r_u = np.matmul(dNb, Pl.reshape(ne, nq * d, d)).reshape(ne, nb * d)
        if not with_tangent:
            return Terms(r_u, r_p, None, None, None, float(J.min()))
        c = self.comps
        Ac = A.reshape(ne, nq, 9, 9)
        if len(c) < 9:                                            # 2D: the in-plane components
            Ac = Ac[:, :, c][:, :, :, c]
        # A_(cl)(dm) w as (m, c, d) x l per point (one weighted copy), times dN (l, a): the
        # product's layout (e, (q, m), (c, d, a)) is the next product's right side as is
        Aw = np.empty((ne, nq, d, d, d, d))
        np.multiply(Ac.reshape(ne, nq, d, d, d, d).transpose(0, 1, 5, 2, 4, 3), w[:, :, None, None, None, None],
                    out=Aw)
        T = np.matmul(Aw.reshape(ne * nq, d * d * d, d), dN.reshape(ne * nq, d, nb))     # (q, m), (c, d, a)
        K = np.matmul(dNb, T.reshape(ne, nq * d, d * d * nb))                            # b, (c, d, a)
        K_uu = K.reshape(ne, nb, d, d, nb).transpose(0, 4, 2, 1, 3).reshape(ne, nb * d, nb * d)
        Jl = (JFiT.reshape(ne, nq, 9)[:, :, c] * w[..., None]).reshape(ne * nq, d, d).transpose(0, 2, 1)   # (l, c)
        G = np.matmul(dNa.reshape(ne * nq, nb, d), Jl).reshape(ne, nq, nb * d)                   # (a, c)
        K_up = np.matmul(G.transpose(0, 2, 1), M)
        K_pp = -np.matmul((M * w[..., None]).transpose(0, 2, 1), M) / self.law.K
        return Terms(r_u, r_p, K_uu, K_up, K_pp, float(J.min()))
