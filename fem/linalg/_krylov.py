r"""An iterative solver for large coupled systems: GMRES with a block preconditioner.

The eliminated system (fem.assembly), scaled as for the direct solvers
(fem.linalg.scaling: A_s = D A D, unit displacement diagonal, unit approximate
Schur diagonals), is split into displacement unknowns u and the rest q
(mixed pressures, potentials, floating electrodes):

    A_s = [ K    C^T ]        K: elastic stiffness (SPD with the supports)
          [ C   -E   ]        E: pressure mass / kappa and dielectric (PSD)

The preconditioner is block diagonal, P = diag(K~, S~):

  * K~^-1, the displacement block: the unknowns of stiff bodies (regions more
    than STIFF_CONTRAST times stiffer than the softest: the PZT in silicone,
    1e11 vs 1e4 Pa) are solved exactly (SuperLU; they are a few per cent of
    the unknowns), the soft rest by one smoothed-aggregation AMG V-cycle
    (pyamg, rigid-body modes as near-null space), coupled by a symmetric block
    Gauss-Seidel sweep. One AMG hierarchy over both fails here: with a 1e7
    stiffness contrast CG-AMG on K did not reach 1e-6 in 500 iterations on the
    single 3D taxel, against 77 iterations on the soft block alone (measured).
  * S~^-1, the Schur complement S = E + C K^-1 C^T approximated by
    `schur_scale` (E + C diag(K)^-1 C^T) = schur_scale (E + C C^T) in the scaled
    system, factorized (SuperLU; q is small: one P1 pressure per vertex of the
    solids, the piezo potentials). For the pressure this is the lumped pressure
    mass times (1/(2 mu) + 1/kappa) up to a constant; for the potential the
    dielectric stiffness plus the piezoelectric stiffening e^2/c.

GMRES (scipy, restarted) runs on each right-hand side to `tol` in the relative
residual |A_s y - b_s| / |b_s| of the scaled system, which is recomputed at the
end and reported; if it is not reached within `maxiter` iterations a
KrylovError names the residual reached, never a quiet wrong answer.

Measured (benchmarks/taxel_3d.py --solvers pardiso superlu krylov): the mass-type Schur approximation is weak
for the thin bonded silicone layers (the inf-sup constant of a layer falls with
its thickness over its width), so GMRES needs hundreds of iterations and is
slower than PARDISO wherever PARDISO fits in memory; "auto" therefore picks it
only above AUTO_KRYLOV_ABOVE unknowns (fem.linalg): PARDISO's memory grows about as
n^(4/3) (docs/benchmarks.md, benchmarks/taxel_3d.py), and where its factors do not fit
it factorizes out of core (fem.linalg.check_fits: the 16x16 array of
benchmarks/array_8x8.py).

Tried and not adopted (the 3D taxel at mesh.size 2 mm, 10k unknowns, exact
displacement solves to isolate the Schur part): the block preconditioner above
took 181 GMRES iterations to 1e-11; the augmented-Lagrangian variant (u block
K + B^T diag(W)^-1 B, pressure block W = M / kappa lumped) 117, and 554 with a
10 x augmentation. A better pressure Schur approximation for thin bonded layers
is the open problem.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from . import _direct as linalg
from taxel.fem.constitution import PiezoLaw

STIFF_CONTRAST = 100.0


class KrylovError(RuntimeError):
    """The iterative solver did not reach its tolerance."""


@dataclass(frozen=True)
class Blocks:
    """How the eliminated unknowns split for the block preconditioner."""

    soft: np.ndarray      # eliminated indices of displacements in soft regions
    stiff: np.ndarray     # eliminated indices of displacements touching a stiff region
    other: np.ndarray     # pressures, potentials, electrode potentials
    modes: np.ndarray     # (len(soft), 3 or 6) rigid-body modes of the soft unknowns (unscaled)


def _stiffness(lw) -> float:
    return float(lw.c[0, 0]) if isinstance(lw, PiezoLaw) else 2 * lw.mu + lw.lam


def krylov_blocks(sy, red) -> Blocks:
    """The block split of an assembled System and its Elimination."""
    ub = next(iter(sy.ubases.values()))
    Pc = red.P.tocsc()
    full = Pc.indices[Pc.indptr[: red.nf]]                 # full index of each free unknown
    stiffness = {r: _stiffness(lw) for r, lw in sy.laws.items()}
    soft_min = min(stiffness.values())
    stiff_dofs = np.zeros(ub.N, bool)
    for r, s in stiffness.items():
        if s > STIFF_CONTRAST * soft_min:
            stiff_dofs[np.unique(sy.ubases[r].element_dofs)] = True
    is_u = red.is_u[: red.nf]
    u_idx = np.flatnonzero(is_u)
    is_stiff = stiff_dofs[full[u_idx]]
    soft, stiff = u_idx[~is_stiff], u_idx[is_stiff]
    other = np.concatenate([np.flatnonzero(~is_u), np.arange(red.nf, red.n)])
    comp = np.zeros(ub.N, int)
    for arr in (ub.nodal_dofs, ub.edge_dofs, ub.facet_dofs, ub.interior_dofs):
        for c in range(arr.shape[0] if arr.size else 0):
            comp[arr[c]] = c
    f = full[soft]
    c, x = comp[f], ub.doflocs[:, f]
    dim = x.shape[0]
    modes = [(c == k).astype(float) for k in range(dim)]
    for a, b in ([(0, 1)] if dim == 2 else [(0, 1), (1, 2), (0, 2)]):
        m = np.zeros(len(f))
        m[c == a], m[c == b] = -x[b, c == a], x[a, c == b]
        modes.append(m)
    return Blocks(soft, stiff, other, np.column_stack(modes))


def preconditioner(As: sp.csr_matrix, bl: Blocks, D: np.ndarray, schur_scale: float = 1.0):
    """The block preconditioner of the scaled matrix As as a LinearOperator."""
    import pyamg

    n = As.shape[0]
    S, T, Q = bl.soft, bl.stiff, bl.other
    Kss = As[S][:, S].tocsr()
    amg = pyamg.smoothed_aggregation_solver(Kss, B=bl.modes / D[S][:, None], symmetry="symmetric",
                                            max_coarse=300)
    Kst = As[S][:, T].tocsr()
    Kts = Kst.T.tocsr()
    lu_t = spla.splu(As[T][:, T].tocsc()) if len(T) else None
    U = np.concatenate([S, T])
    Cq = As[Q][:, U]
    lu_q = spla.splu((schur_scale * (abs(As[Q][:, Q]) + Cq @ Cq.T)).tocsc()) if len(Q) else None

    def apply(r):
        z = np.zeros_like(r)
        zt = lu_t.solve(r[T]) if lu_t else np.zeros(0)
        zs = amg.solve(r[S] - Kst @ zt, maxiter=1, cycle="V", tol=1e-300)
        if lu_t:
            zt = lu_t.solve(r[T] - Kts @ zs)
        z[S], z[T] = zs, zt
        if lu_q:
            z[Q] = lu_q.solve(r[Q])
        return z
    return spla.LinearOperator((n, n), apply, dtype=float), amg


def krylov_solver(A: sp.spmatrix, bl: Blocks, tol: float = 1e-10, maxiter: int = 3000, restart: int = 150,
                  schur_scale: float = 1.0):
    """Scale A like the direct solvers, build the preconditioner once; return
    solve(B) -> (X, relative residuals) running GMRES on each column of B.
    Raises KrylovError when a column does not reach `tol` within `maxiter`."""
    n = A.shape[0]
    is_u = np.zeros(n, bool)
    is_u[np.concatenate([bl.soft, bl.stiff])] = True
    D = linalg.scaling(A, is_u)
    As = (sp.diags(D) @ A @ sp.diags(D)).tocsr()
    M, amg = preconditioner(As, bl, D, schur_scale)
    iterations: list[int] = []

    def solve_(B):
        B = np.asarray(B, dtype=float).reshape(n, -1)
        Bs = D[:, None] * B
        Y = np.zeros_like(Bs)
        res = np.zeros(B.shape[1])
        for j in range(B.shape[1]):
            nb = np.linalg.norm(Bs[:, j])
            if nb == 0:
                iterations.append(0)
                continue
            count = [0]
            y = np.zeros(n)
            while True:      # restarted GMRES until the true residual is reached
                y, _ = spla.gmres(As, Bs[:, j], x0=y, rtol=tol / 10, atol=0.0, restart=restart,
                                  maxiter=max(1, (maxiter - count[0]) // restart), M=M,
                                  callback=lambda _: count.__setitem__(0, count[0] + 1), callback_type="pr_norm")
                res[j] = np.linalg.norm(Bs[:, j] - As @ y) / nb
                if res[j] <= tol or count[0] >= maxiter or not np.isfinite(res[j]):
                    break
            iterations.append(count[0])
            if not res[j] <= tol:
                raise KrylovError(f"GMRES stopped at relative residual {res[j]:.1e} after {count[0]} iterations "
                                  f"(tolerance {tol:.0e}): the block preconditioner does not fit this system; "
                                  f"use solver 'pardiso' or 'superlu'")
            Y[:, j] = y
        return D[:, None] * Y, res
    solve_.D = D
    solve_.iterations = iterations
    solve_.amg = amg
    return solve_
