"""Sparse direct solvers behind one interface: `factorize(A, method)(B) -> X`.

Methods: "superlu" (scipy, installs everywhere: the fallback), "pardiso" (MKL
PARDISO through pypardiso), "umfpack" (scikit-umfpack, if installed). "auto"
picks SuperLU below 15 000 unknowns and PARDISO above (when it imports): measured
on the 2D taxel (benchmarks/taxel_2d.py), SuperLU wins on small systems (PARDISO
has a ~0.3 s floor here) and PARDISO on large ones (33 000 unknowns: 0.43 s vs
2.9 s).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

METHODS = ("auto", "superlu", "pardiso", "umfpack")


def available(method: str) -> bool:
    if method in ("auto", "superlu"):
        return True
    try:
        __import__({"pardiso": "pypardiso", "umfpack": "scikits.umfpack"}[method])
        return True
    except ImportError:
        return False


AUTO_PARDISO_ABOVE = 15_000


def resolve(method: str, n: int = 0) -> str:
    if method == "auto":
        return "pardiso" if n > AUTO_PARDISO_ABOVE and available("pardiso") else "superlu"
    if method not in METHODS:
        raise ValueError(f"unknown linear solver '{method}'; use one of {', '.join(METHODS)}")
    if not available(method):
        raise ValueError(f"linear solver '{method}' is not installed; use 'superlu' or 'auto'")
    return method


def factorize(A: sp.spmatrix, method: str = "auto"):
    """A solve function for A (factorized once; accepts a vector or a matrix of RHS,
    real or complex). Complex matrices use SuperLU."""
    if np.iscomplexobj(A.data if sp.issparse(A) else A):
        lu = spla.splu(sp.csc_matrix(A), permc_spec="COLAMD")
        return lambda B: lu.solve(np.asarray(B, dtype=complex))
    real = _factorize_real(A, method)

    def solve(B):
        B = np.asarray(B)
        if np.iscomplexobj(B):
            return real(B.real) + 1j * real(B.imag)
        return real(B)
    return solve


def _factorize_real(A, method):
    method = resolve(method, A.shape[0])
    A = sp.csc_matrix(A)
    if method == "superlu":
        lu = spla.splu(A, permc_spec="COLAMD")
        return lambda B: lu.solve(np.asarray(B, dtype=float))
    if method == "pardiso":
        import pypardiso
        # real nonsymmetric mode: its pivoting keeps the backward error at round-off here;
        # the symmetric-indefinite mode (-2) perturbs pivots and stalled at 1e-10 on 3D taxels
        solver = pypardiso.PyPardisoSolver(mtype=11)
        Ar = sp.csr_matrix(A)
        solver.factorize(Ar)
        return lambda B: solver.solve(Ar, np.asarray(B, dtype=float))
    from scikits.umfpack import splu
    lu = splu(A)
    return lambda B: lu.solve(np.asarray(B, dtype=float))
