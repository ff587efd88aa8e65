"""The scalar shape functions of a P1/P2 simplex on an affine mesh, and the vector
field's element matrices and CSR matrix built from them (the assembly from the scalar
basis: fem.assembly.vector_matrix and the affine strain terms of fem.assembly.assemble_terms).

A vector field u = sum u_(s, c) N_s e_c numbered nc * s + c (scikit-fem's ElementVector)
has element matrices made of nc x nc blocks, one per pair of scalar functions: they are
built from the scalar gradients (10 functions for P2 tetrahedra where scikit-fem's vector
basis evaluates 30), and scattered by one sort of the scalar DOF pairs (benchmarks/assembly_3d.py:
3.0-4.0 x FELupe's rate, set-up included).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from skfem import ElementVector
from skfem.assembly.basis.abstract_basis import AbstractBasis
from skfem.assembly.basis.cell_basis import CellBasis
from skfem.element.discrete_field import DiscreteField


def block_matrices(dN: np.ndarray, w: np.ndarray, L: np.ndarray, D: np.ndarray) -> np.ndarray:
    """(elements, a, b, c, d) element matrices of S(v)^T D S(u) for the vector field
    u = sum u_(s, c) N_s e_c from the scalar gradients dN (elements, points, dim, a)
    and weights w (elements, points): the 3 x 3 (dim x dim) block of every pair of
    scalar functions,

        K_e[a, b, c, d] = sum_{k, l} H_e[k, a, l, b] C[k, l, c, d],
        H_e = sum_q w_q dN_q^T dN_q,   C[k, l, c, d] = sum_{s, t} L[s, c, k] D[s, t] L[t, d, l]."""
    ne, nq, dim, na = dN.shape
    G = dN.transpose(0, 2, 3, 1).reshape(ne, dim * na, nq)
    H = np.matmul(G * w[:, None, :], G.transpose(0, 2, 1)).reshape(ne, dim, na, dim, na)
    C = np.einsum("sck,st,tdl->klcd", L, D, L).reshape(dim * dim, dim * dim)
    K = H.transpose(0, 2, 4, 1, 3).reshape(ne * na * na, dim * dim) @ C
    return K.reshape(ne, na, na, dim, dim)


def block_csr(rows: np.ndarray, cols: np.ndarray, blocks: np.ndarray, n_rows: int, n_cols: int,
              shape=None) -> sp.csr_matrix:
    """The CSR matrix of a vector field numbered nc * s + c (scikit-fem's ElementVector)
    from dense blocks on the scalar DOFs: rows (elements, a), cols (elements, b) scalar
    DOFs, blocks (elements, a, b, nc, nc). One sort of the scalar pairs (nc^2 fewer
    keys than the vector entries), the duplicates summed block-wise, a BSR matrix
    converted to CSR; `shape`: pad to a larger (full system) shape."""
    nc = blocks.shape[-1]
    keys = (rows[:, :, None].astype(np.int64) * n_cols + cols[:, None, :]).ravel()
    order = np.argsort(keys)
    ks = keys[order]
    starts = np.flatnonzero(np.r_[True, ks[1:] != ks[:-1]])
    # the sum of each run of equal keys: a 0/1 sparse matrix times the blocks (no gather copy)
    S = sp.csr_matrix((np.ones(len(keys)), order, np.r_[starts, len(keys)]), shape=(len(starts), len(keys)))
    vals = (S @ blocks.reshape(-1, nc * nc)).reshape(-1, nc, nc)
    u = ks[starts]
    indptr = np.r_[0, np.cumsum(np.bincount(u // n_cols, minlength=n_rows))]
    A = sp.bsr_matrix((vals, u % n_cols, indptr), shape=(nc * n_rows, nc * n_cols)).tocsr()
    if shape is not None and shape != A.shape:
        A = sp.csr_matrix((A.data, A.indices, np.r_[A.indptr, np.full(shape[0] - A.shape[0], A.nnz)]), shape=shape)
    return A


def scalar_dofs(basis) -> np.ndarray | None:
    """(elements, scalar functions) scalar DOFs s of a vector basis whose DOF of
    (function a, component c) is nc * s + c (scikit-fem's numbering, checked), else None."""
    if not isinstance(basis.elem, ElementVector):
        return None
    nc = basis.elem.dim
    ed = basis.element_dofs
    s = ed[0::nc]
    if np.any(s % nc) or any(not np.array_equal(ed[c::nc], s + c) for c in range(nc)):
        return None
    return (s // nc).T


@dataclass(frozen=True)
class ScalarBasis:
    """The scalar shape functions of a simplex element (P1 or P2) on an affine mesh,
    evaluated directly: the reference gradients once, per element J^-1 and |det J|
    (one 3 x 3 inverse each), DOFs vertices then edges (the numbering of scikit-fem's
    Basis of the same element, so a vector field's DOF is dim s + c). What scikit-fem's
    vector Basis evaluates for 30 functions at every point, for 10 on the reference."""

    elem: object               # the scalar scikit-fem element
    ref: np.ndarray            # (dim, points, functions) reference gradients
    values: np.ndarray         # (points, functions) values (the same on every element)
    W: np.ndarray              # (points,) reference quadrature weights
    Jinv: np.ndarray           # (elements, dim, dim)
    detJ: np.ndarray           # (elements,) |det J|
    dofs: np.ndarray           # (elements, functions)
    N: int

    @property
    def element_dofs(self) -> np.ndarray:
        """(functions, elements), as scikit-fem's Basis."""
        return self.dofs.T

    @property
    def dN(self) -> np.ndarray:
        """(elements, points, dim, functions) global gradients J^-T dN_ref."""
        return self.grads()

    def grads(self, sl=slice(None)) -> np.ndarray:
        """dN of the elements `sl` only."""
        return np.einsum("eki,kqa->eqia", self.Jinv[sl], self.ref)

    @property
    def w(self) -> np.ndarray:
        """(elements, points) quadrature weights times |det J|."""
        return self.detJ[:, None] * self.W[None, :]


def scalar_basis(mesh, elem, intorder: int = 4, quadrature=None, elements=None) -> ScalarBasis:
    """The ScalarBasis of a P1/P2 element on `mesh` (its `elements` only, if given) with the
    quadrature rule (points, weights) `quadrature`, or else of order `intorder`."""
    from skfem.quadrature import get_quadrature
    if elem.nodal_dofs != 1 or elem.edge_dofs > 1 or elem.facet_dofs or elem.interior_dofs:
        raise ValueError(f"scalar_basis: {type(elem).__name__} is not a P1/P2 Lagrange element")
    X, W = get_quadrature(elem.refdom, intorder) if quadrature is None else quadrature
    nb = elem.doflocs.shape[0]
    ref = np.stack([elem.lbasis(X, i)[1] for i in range(nb)], axis=-1)      # (dim, nq, nb)
    values = np.stack([elem.lbasis(X, i)[0] for i in range(nb)], axis=-1)   # (nq, nb)
    sel = slice(None) if elements is None else elements
    p, t = mesh.p, mesh.t[:, sel]
    J = np.stack([p[:, t[i + 1]] - p[:, t[0]] for i in range(p.shape[0])], axis=-1).transpose(1, 0, 2)
    t2e, nedges = (mesh.t2e, mesh.edges.shape[1]) if p.shape[0] == 3 else (mesh.t2f, mesh.facets.shape[1])
    dofs = t.T if not elem.edge_dofs else np.hstack([t.T, p.shape[1] + t2e[:, sel].T])
    N = p.shape[1] + (nedges if elem.edge_dofs else 0)
    return ScalarBasis(elem, ref, values, W, np.linalg.inv(J), np.abs(np.linalg.det(J)), np.ascontiguousarray(dofs), N)


def box_basis(mesh, elem, quadrature, elements, dofs: np.ndarray, N: int) -> ScalarBasis | None:
    """The ScalarBasis of any scikit-fem element on a hexahedral mesh whose elements are
    boxes (a tensor-product grid, meshing.hexmesh): the map from the reference cube is then
    affine, its Jacobian constant per element (checked at two points; None if not), so the
    reference gradients serve every element as for a simplex. `dofs` (elements, functions)
    and N: the basis's own scalar numbering."""
    X, W = quadrature
    nb = dofs.shape[1]
    ref = np.stack([elem.lbasis(X, i)[1] for i in range(nb)], axis=-1)      # (dim, nq, nb)
    values = np.stack([elem.lbasis(X, i)[0] for i in range(nb)], axis=-1)   # (nq, nb)
    mp = mesh.mapping()
    tind = np.arange(mesh.nelements) if elements is None else elements
    two = np.array([[0.25, 0.75], [0.25, 0.75], [0.25, 0.75]])
    DF = mp.DF(two, tind=tind)                                              # (dim, dim, ne, 2)
    if not np.allclose(DF[..., 0], DF[..., 1], rtol=1e-10, atol=1e-14 * np.abs(DF).max()):
        return None
    J = np.ascontiguousarray(DF[..., 0].transpose(2, 0, 1))                 # J[e, i, k] = dx_i / dX_k
    return ScalarBasis(elem, ref, values, W, np.linalg.inv(J), np.abs(np.linalg.det(J)),
                       np.ascontiguousarray(dofs), N)


_UNSET = object()      # LazyBasis.scalar not yet looked for (None: it does not apply)


class LazyBasis(CellBasis):
    """scikit-fem's CellBasis without its eager table of every shape function at every
    quadrature point of every element (`basis`: for vector P2 tetrahedra 30 functions x
    (3 values + 9 gradients) x 11 points, 32 kB per element, most of an assembled 3D
    model's memory: benchmarks/array_8x8.py). The table is built on first use of `basis`
    (scikit-fem's own assembly, a Yeoh region's tangent) and kept; `scalar` (the
    ScalarBasis of the same elements, numbering and quadrature rule, or None where that
    does not apply: a curved or non-simplex mesh, a MINI element) serves the assembly
    (fem.assembly) and `interpolate` (u = sum_a u_(a, c) N_a, grad u from J^-T dN_ref)
    without it. `like`: a LazyBasis of the same mesh and element whose DOF numbering and
    DOF locations (both of the whole mesh: 3 x 8 B per DOF, 24 MB per region of the 16x16
    array's quarter, 65 regions) this one shares."""

    def __init__(self, mesh, elem, elements=None, intorder: int = 4, like: "LazyBasis | None" = None):
        if like is not None and (like.mesh is not mesh or like.elem is not elem):
            raise ValueError("LazyBasis: `like` must be a basis of the same mesh and element")
        AbstractBasis.__init__(self, mesh, elem, None, intorder, None, mesh.refdom,
                               None if like is None else like.dofs, like is not None)
        if like is not None:
            self.doflocs = like.doflocs
        if elements is None:
            self.tind, self.nelems = None, mesh.nelements
        else:
            self.tind = mesh.normalize_elements(elements)
            self.nelems = len(self.tind)
        self.dx = np.abs(self.mapping.detDF(self.X, tind=self.tind)) * np.broadcast_to(self.W, (self.nelems, len(self.W)))
        self._table = None
        self._scalar = _UNSET

    @property
    def basis(self):
        if self._table is None:
            self._table = [self.elem.gbasis(self.mapping, self.X, j, tind=self.tind) for j in range(self.Nbfun)]
        return self._table

    @basis.setter
    def basis(self, value):
        self._table = value

    @property
    def scalar(self) -> ScalarBasis | None:
        if self._scalar is _UNSET:
            self._scalar = None
            m = self.mesh
            vector = isinstance(self.elem, ElementVector)
            s = scalar_dofs(self) if vector else self.element_dofs.T
            if getattr(m, "affine", False) and m.t.shape[0] == m.dim() + 1 and s is not None:
                try:
                    sb = scalar_basis(m, self.elem.elem if vector else self.elem, quadrature=self.quadrature,
                                      elements=self.tind)
                except ValueError:
                    sb = None
                if sb is not None and np.array_equal(sb.dofs, s):
                    self._scalar = sb
            elif m.t.shape[0] == 8 and m.dim() == 3 and s is not None:      # hexahedra: boxes only
                self._scalar = box_basis(m, self.elem.elem if vector else self.elem, self.quadrature, self.tind,
                                         s, self.N // (self.elem.dim if vector else 1))
        return self._scalar

    def interpolate(self, w: np.ndarray) -> DiscreteField:
        sb = self.scalar
        if sb is None or self._table is not None:
            return super().interpolate(w)
        if w.shape[0] != self.N:
            raise ValueError("Input array has wrong size.")
        vector = isinstance(self.elem, ElementVector)
        nc = self.elem.dim if vector else 1
        U = w[nc * sb.dofs[:, :, None] + np.arange(nc)]                        # (elements, a, c)
        value = np.einsum("qa,eac->ceq", sb.values, U)
        Gref = np.einsum("kqa,eac->eqkc", sb.ref, U)
        grad = np.einsum("eki,eqkc->cieq", sb.Jinv, Gref)
        return DiscreteField(value=value, grad=grad) if vector else DiscreteField(value=value[0], grad=grad[0])


def affine_blocks(sb: ScalarBasis, L: np.ndarray, D: np.ndarray, sl=slice(None)) -> np.ndarray:
    """block_matrices for affine elements without a per-point loop: J is constant per
    element, so H_e = |det J| (J^-1 x J^-1)^T R with R the reference integrals
    sum_q W_q dN_ref,q^T dN_ref,q (the same for every element, exact to round-off),
    and K_e[a, b, c, d] = sum_{K, L} R[K, L, a, b] N_e[K, L, c, d],
    N_e = |det J| sum_{k, l} Jinv[K, k] Jinv[L, l] C[k, l, c, d]: two small products per element."""
    dim, nq, na = sb.ref.shape
    R = np.einsum("kqa,q,lqb->klab", sb.ref, sb.W, sb.ref).reshape(dim * dim, na * na)
    C = np.einsum("sck,st,tdl->klcd", L, D, L)
    Jinv, det = sb.Jinv[sl], sb.detJ[sl]
    Nmat = np.einsum("eKk,eLl,klcd->eKLcd", Jinv, Jinv, C, optimize=True) * det[:, None, None, None, None]
    K = np.matmul(R.T[None], Nmat.reshape(-1, dim * dim, dim * dim))          # (ne, a b, c d)
    return K.reshape(-1, na, na, dim, dim)
