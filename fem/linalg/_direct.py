"""Linear algebra: sparse direct solvers behind one interface, and the scaled
solve of the coupled saddle-point system.

`factorize(A, method)(B) -> X`.

Scaling (`scaled_solver`). Stiffnesses span 1e4 Pa (silicone) to 1e11 Pa (PZT)
and the dielectric block is ~1e-8: the matrix is scaled symmetrically,
A_s = D A D, with unit displacement diagonals and unit approximate
Schur-complement diagonals for pressure and potential (`scaling`), then
factorized; iterative refinement reuses the factors, and the relative residual
|A_s y - b_s| / |b_s| is reported.

Methods: "superlu" (scipy, installs everywhere: the fallback), "pardiso" (MKL
PARDISO through pypardiso), "umfpack" (scikit-umfpack, if installed), "krylov"
(GMRES with a block AMG preconditioner, fem.linalg: static linear solves only). "auto"
picks SuperLU below 15 000 unknowns and PARDISO above (when it imports): measured
on the 2D taxel (benchmarks/taxel_2d.py), SuperLU wins on small systems (PARDISO
has a ~0.3 s floor here) and PARDISO on large ones (33 000 unknowns: 0.43 s vs
2.9 s). In 3D the fill makes PARDISO pay from about 3 000 unknowns (4 000: 1.7 s
vs 2.1 s; 8 400: 1.2 s vs 2.8 s, quarter taxel models), so 3D uses PARDISO above that.
PARDISO factorizes out of core when its analysis says the factors do not fit the
memory budget (fem/linalg/_memory.py: `check_fits`, `MEMORY_CAP`). Single-precision factors (MKL iparm[27])
with double-precision refinement were tried (a one-off trial, not scripted) and dropped: on the 3x3 3D array (33k
unknowns) the refined residual stayed at 0.19-3.7 and the voltages were wrong (the
scaled coupled system is too ill-conditioned for float32).
"""

from __future__ import annotations

import glob
import logging
import os
import sys
import weakref

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ._memory import FIX, MemoryLimitError, analysis_bytes, check_fits

METHODS = ("auto", "superlu", "pardiso", "umfpack", "krylov")


def available(method: str) -> bool:
    if method in ("auto", "superlu"):
        return True
    try:
        if method == "pardiso":
            _pypardiso()
        else:
            __import__({"umfpack": "scikits.umfpack", "krylov": "pyamg"}[method])
        return True
    except ImportError:
        return False


def _pypardiso():
    """pypardiso, imported with PYPARDISO_MKL_RT naming MKL's runtime library where it is
    installed beside this Python (sys.prefix's lib or Library/bin, or the base Python's under a venv
    with system site-packages; a user's own setting kept).
    Without it pypardiso walks all of sys.prefix (glob '**/*mkl_rt*') at its import and again
    at its first solver: two walks of 0.86 s of wall time in cProfile of the 3D probe press on a
    loaded machine (file-system time: `farm-bench` of `taxel solve thesis-pzt-probe-3d --json`
    against the code before, 3 pairs at load 7, system CPU 0.63 against 0.99 s, total CPU
    0.98 x, the wall times within the load's noise)."""
    if "PYPARDISO_MKL_RT" not in os.environ:
        found = sorted((f for prefix in dict.fromkeys((sys.prefix, sys.base_prefix))   # a venv over a system Python
                        for f in glob.glob(os.path.join(prefix, "lib", "libmkl_rt.*"))
                        + glob.glob(os.path.join(prefix, "Library", "bin", "mkl_rt*.dll"))), key=len)
        if found:
            os.environ["PYPARDISO_MKL_RT"] = found[0]
    import pypardiso
    return pypardiso


AUTO_PARDISO_ABOVE = 15_000
AUTO_PARDISO_ABOVE_3D = 3_000   # 3D fill: PARDISO 1.2 s vs SuperLU 2.8 s at 8.4k unknowns, even at 4k (taxel_3d)
# static solves above this go to GMRES (fem.linalg); below, PARDISO, out of core where its factors
# do not fit (check_fits; the 16x16 array's 794k unknowns, benchmarks/array_8x8.py)
AUTO_KRYLOV_ABOVE = 1_500_000
log = logging.getLogger(__name__)


def resolve(method: str, n: int = 0, iterative: bool = False, dim: int | None = None) -> str:
    """The solver a method name stands for at n unknowns of a `dim`-dimensional mesh;
    `iterative`: the caller (the static linear solve) can use the Krylov solver of fem.linalg.
    "auto" needs `dim` (3D fill makes PARDISO pay at a fifth of the 2D size), so a
    factorization is handed a resolved name, never "auto"."""
    if method == "auto":
        if dim is None:
            raise ValueError("linear solver 'auto' depends on the mesh's dimension: resolve it with "
                             "linalg.resolve(method, n, dim=...) before factorizing")
        if iterative and n > AUTO_KRYLOV_ABOVE and available("krylov"):
            return "krylov"
        above = AUTO_PARDISO_ABOVE_3D if dim == 3 else AUTO_PARDISO_ABOVE
        return "pardiso" if n > above and available("pardiso") else "superlu"
    if method == "krylov" and not iterative:
        raise ValueError("linear solver 'krylov' solves static linear problems only; use 'pardiso' or 'superlu'")
    if method not in METHODS:
        raise ValueError(f"unknown linear solver '{method}'; use one of {', '.join(METHODS)}")
    if not available(method):
        raise ValueError(f"linear solver '{method}' is not installed; use 'superlu' or 'auto'")
    return method


def symmetric_matrix(A: sp.csr_matrix) -> bool:
    """A equals its transpose to round-off (1e-14 of its largest entry)."""
    d = abs(A - A.T)
    return d.nnz == 0 or d.max() <= 1e-14 * abs(A).max()


def numeric_factorization(solver, A) -> None:
    """PARDISO's numerical factorization (phase 22) after check_fits's analysis
    (phase 11), marked as pypardiso's factorization of A (its `factorize` runs phase
    12, which repeats the analysis: 27 % of a factorization's CPU time on the 3x3 3D
    array's 51k-unknown quarter, 5.1 s against 3.7 s, identical factors)."""
    pypardiso = _pypardiso()
    solver.factorized_A = solver._hash_csr_matrix(A)      # (not a copy of A: 0.35 GB at 16x16)
    solver.set_phase(22)
    try:
        solver._call_pardiso(A, np.zeros((A.shape[0], 1)))
    except pypardiso.pardiso_wrapper.PyPardisoError as exc:
        if exc.args and exc.args[0] in (-2, -9):            # MKL: not enough memory (-9: out of core)
            raise MemoryLimitError(f"the direct solve of {A.shape[0]} unknowns ran out of memory while factorizing "
                                   f"(PARDISO error {exc.args[0]}); {FIX}") from None
        raise
    log.info("PARDISO factorized %d unknowns", A.shape[0])


def in_core_bytes(A: sp.spmatrix) -> float:
    """Bytes PARDISO's analysis says a factorization of the symmetric matrix A needs in
    core (`analysis_bytes` on its upper triangle, symmetric-indefinite mode; nothing factorized)."""
    pypardiso = _pypardiso()
    probe = pypardiso.PyPardisoSolver(mtype=-2)
    try:
        return analysis_bytes(probe, sp.csr_matrix(sp.triu(A)))
    finally:
        probe.free_memory(True)


def factorize(A: sp.spmatrix, method: str = "auto"):
    """A solve function for A (factorized once; accepts a vector or a matrix of RHS,
    real or complex). A complex matrix (a damped frequency-domain operator) goes to
    SuperLU, or with "pardiso" to its real equivalent (`_factorize_complex`)."""
    if np.iscomplexobj(A.data if sp.issparse(A) else A):
        if resolve(method, A.shape[0]) == "pardiso":
            return _factorize_complex(A)
        lu = spla.splu(sp.csc_matrix(A), permc_spec="COLAMD")
        return lambda B: lu.solve(np.asarray(B, dtype=complex))
    real = _factorize_real(A, method)

    def solve(B):
        B = np.asarray(B)
        if np.iscomplexobj(B):
            return real(B.real) + 1j * real(B.imag)
        return real(B)
    return solve


def _factorize_complex(A):
    r"""A complex A = A_r + i A_i by PARDISO (pypardiso takes real matrices only) through
    its real equivalent: A x = b with x = x_r + i x_i is

        [A_r   A_i] [ x_r]   [b_r]
        [A_i  -A_r] [-x_i] = [b_i],

    symmetric when A is (a complex-symmetric damped stiffness), so the symmetric-indefinite
    mode applies. On the 3x3 3D array's full 3 mm model, charge amplifier at 10 and 300 Hz
    (benchmarks/complex_solve.py, one run): SuperLU takes 3.7x the wall time and 1.5x the
    peak memory (220 s and 3.9 GB against 60 s and 2.7 GB); the outputs agree to 1.2e-9."""
    A = sp.csr_matrix(A)
    n = A.shape[0]
    real = _factorize_real(sp.bmat([[A.real, A.imag], [A.imag, -A.real]], format="csr"), "pardiso")

    def solve(B):
        B = np.asarray(B, dtype=complex)
        Y = real(np.concatenate([B.real, B.imag]))
        return Y[:n] - 1j * Y[n:]
    return solve


def _factorize_real(A, method):
    method = resolve(method, A.shape[0])
    A = sp.csc_matrix(A)
    if method == "superlu":
        lu = spla.splu(A, permc_spec="COLAMD")
        return lambda B: lu.solve(np.asarray(B, dtype=float))
    if method == "pardiso":
        pypardiso = _pypardiso()
        # a symmetric matrix (every linear static system, a Yeoh tangent): the symmetric-
        # indefinite mode on its upper triangle, half the factors' memory and 0.62 x the CPU
        # time of the nonsymmetric mode on the 3x3 3D array's 51k-unknown quarter (2.2 s
        # against 3.6 s, 0.36 against 0.70 GB), the same residuals after refinement
        # (2.8e-12 / 1.6e-14 against 2.4e-12 / 1.5e-14 on its load and unit charges) and
        # solutions within 3e-9; a nonsymmetric one (a sticking contact's tangent): mode 11
        Ar = sp.csr_matrix(A)
        symmetric = symmetric_matrix(Ar)
        solver = pypardiso.PyPardisoSolver(mtype=-2 if symmetric else 11)
        os.environ.setdefault("PYPARDISO_MKL_RT", solver.libmkl._name)    # found elsewhere: no second walk
        if symmetric:
            Ar = sp.csr_matrix(sp.triu(Ar))
        Ar.sort_indices()
        check_fits(solver, Ar)          # phase 11: the ordering and symbolic factorization
        numeric_factorization(solver, Ar)

        def solve(B):
            B = np.asarray(B, dtype=float)
            solver.set_phase(33)
            return solver._call_pardiso(Ar, np.asfortranarray(B.reshape(Ar.shape[0], -1))).reshape(B.shape)
        # pypardiso has no finalizer: MKL keeps the factors until phase -1, so a process that
        # factorizes many times (a study worker, the classes of a symmetric model) would grow
        weakref.finalize(solve, solver.free_memory, True)
        return solve
    from scikits.umfpack import splu
    lu = splu(A)
    return lambda B: lu.solve(np.asarray(B, dtype=float))


def scaled_solver(A: sp.spmatrix, is_u: np.ndarray, method: str, scale: bool = True, D=None):
    """Factorize D A D once; return solve(B) -> (X, relative residuals), with
    iterative refinement reusing the factors. `D`: the scaling, if already computed."""
    n = A.shape[0]
    if D is None:
        D = scaling(A, is_u) if scale else np.ones(n)
    As = (sp.diags(D) @ A @ sp.diags(D)).tocsc()
    factor = factorize(As, method)

    def solve_(B, rtol=1e-13):
        return refined_solve(factor, As, D, B, rtol)
    solve_.D = D
    return solve_


def refined_solve(factor, As, D, B, rtol=1e-13):
    """X = D Y with (D A D) Y = D B solved by `factor` and up to three steps of iterative
    refinement on the scaled system, until the relative residual is below `rtol`;
    returns (X, relative residuals per column). (A residual that stalls above `rtol`,
    as the 3x3 3D array's load column at 2e-12, still gets its three steps: stopping at
    the stall moved the 2D taxel's voltage by 1e-9, past the solvers' agreement.)"""
    B = np.asarray(B).reshape(As.shape[0], -1)
    Bs = D[:, None] * B
    Y = factor(Bs).reshape(Bs.shape)
    for _ in range(3):
        R = Bs - As @ Y
        norm_b = np.linalg.norm(Bs, axis=0)
        res = np.linalg.norm(R, axis=0) / np.where(norm_b > 0, norm_b, 1.0)    # zero rhs: zero error
        if res.max() < rtol:
            break
        Y = Y + factor(R).reshape(Bs.shape)
    X = D[:, None] * Y
    if not np.all(np.isfinite(X)):
        raise RuntimeError("linear solve produced non-finite values: the system is singular "
                           "(check the supports and that every piezo body touches a grounded electrode)")
    return X, res


def scaling(A, is_u):
    """Symmetric diagonal scaling D (A_s = D A D) for the coupled saddle-point system.

    Displacement rows: D_i = 1/sqrt(A_ii), so K_uu gets a unit diagonal.
    Pressure and potential rows: D_i = 1/sqrt(s_i), s_i = |A_ii| + sum_j A_ij^2 / A_jj
    over displacement columns j: the diagonal of the Schur complement
    |A_qq| + B K_uu^-1 B^T with K_uu replaced by its diagonal. Scaling by row
    maxima instead leaves that Schur complement at ~1e-16 for a steel plate or a
    PZT patch (coupling entries dominate the rows) and loses every digit.
    """
    diag = np.abs(A.diagonal())    # |.|: a hyperelastic tangent may lose definiteness mid-Newton
    is_u = np.append(is_u, np.zeros(A.shape[0] - len(is_u), bool))      # electrode unknowns
    s = diag.astype(float)
    if (~is_u).any():
        Aqu = A[~is_u][:, is_u]
        s[~is_u] += np.asarray(abs(Aqu).power(2) @ (1.0 / np.maximum(diag[is_u], 1e-300))).ravel()
    if not (s > 0).all():
        raise RuntimeError("the system has an empty row: a region without stiffness or an unconnected unknown")
    return 1.0 / np.sqrt(s)


class Refactorizer:
    """Scaled solves (as `scaled_solver`) of a sequence of matrices with one sparsity
    pattern, such as the tangents of a Newton sequence: with PARDISO the analysis
    (phase 11: fill-reducing ordering, symbolic factorization, memory check) runs
    once per pattern and each matrix gets only its numeric factorization (phase 22);
    other methods factorize each matrix in full. The scaling D A D multiplies the
    stored entries, so the pattern is kept (explicit zeros included). A symmetric
    matrix (a press's tangent: Yeoh, piezo and contact terms are all symmetric,
    the sticking ones too) is factorized in PARDISO's symmetric-indefinite mode on
    its upper triangle, as `factorize` does (half the factors, 0.6 x the CPU time;
    benchmarks/press_3d.py); the triangle's and the transpose's positions in the data
    array are found once per pattern. One set of factors at a time: a solve function
    of an earlier matrix raises once a later one is factorized."""

    def __init__(self, method: str):
        self.method = method
        self._solver, self._pattern, self._generation = None, None, 0
        self._maps = None                 # (pattern, rows, transpose permutation or None, upper triangle)

    def _map(self, A):
        """Per pattern: the row of every entry, the permutation of the data array that
        transposes it (None if the pattern is not structurally symmetric), and the upper
        triangle: the positions of its entries in the data array, its indices and indptr."""
        key = (A.shape[0], A.indptr.tobytes(), A.indices.tobytes())
        if self._maps is None or self._maps[0] != key:
            rows = np.repeat(np.arange(A.shape[0]), np.diff(A.indptr))
            T = sp.csr_matrix((np.arange(1, A.nnz + 1, dtype=float), A.indices, A.indptr), shape=A.shape).T.tocsr()
            T.sort_indices()
            same = T.nnz == A.nnz and np.array_equal(T.indptr, A.indptr) and np.array_equal(T.indices, A.indices)
            perm = (T.data - 1).astype(np.int64) if same else None
            upper = np.flatnonzero(A.indices >= rows)
            indptr = np.concatenate([[0], np.cumsum(np.bincount(rows[upper], minlength=A.shape[0]))])
            self._maps = (key, rows, perm, (upper, A.indices[upper], indptr.astype(A.indptr.dtype)))
        return self._maps

    def __call__(self, A: sp.spmatrix, is_u: np.ndarray, D=None):
        if self.method != "pardiso":
            return scaled_solver(A, is_u, self.method, D=D)
        pypardiso = _pypardiso()
        A = sp.csr_matrix(A)
        A.sort_indices()
        if D is None:
            D = scaling(A, is_u)
        key, rows, perm, upper = self._map(A)
        data = A.data * D[rows] * D[A.indices]
        As = sp.csr_matrix((data, A.indices, A.indptr), shape=A.shape)
        symmetric = perm is not None and (np.abs(data - data[perm]).max(initial=0.0)
                                          <= 1e-14 * np.abs(data).max(initial=0.0))
        if symmetric:                     # the upper triangle, its pattern from the map
            positions, indices, indptr = upper
            Af = sp.csr_matrix((data[positions], indices, indptr), shape=A.shape)
        else:
            Af = As
        key = key + (symmetric,)
        if self._pattern != key:
            if self._solver is not None:
                self._solver.free_memory(True)
            self._solver = pypardiso.PyPardisoSolver(mtype=-2 if symmetric else 11)
            os.environ.setdefault("PYPARDISO_MKL_RT", self._solver.libmkl._name)
            weakref.finalize(self, self._solver.free_memory, True)
            check_fits(self._solver, Af)                             # phase 11
            self._pattern = key
        s = self._solver
        s.set_phase(22)
        s._call_pardiso(Af, np.zeros((A.shape[0], 1)))
        self._generation += 1
        generation = self._generation

        def factor(B):
            if generation != self._generation:
                raise RuntimeError("a solve with factors that a later factorization replaced")
            s.set_phase(33)
            return s._call_pardiso(Af, np.asfortranarray(np.asarray(B, dtype=float).reshape(A.shape[0], -1)))

        def solve_(B, rtol=1e-13):
            return refined_solve(factor, As, D, B, rtol)
        solve_.D = D
        # the symmetric-indefinite factorization's inertia (positive, negative eigenvalues;
        # iparm 22 and 23): fem.contact reads stability from it
        solve_.inertia = (int(s.get_iparm(22)), int(s.get_iparm(23))) if symmetric else None
        return solve_
