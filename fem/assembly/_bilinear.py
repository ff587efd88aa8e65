r"""Vectorised assembly of the constant-coefficient bilinear forms of fem.assembly.

Every linear form of the coupled problem (fem.assembly, weak forms in its docstring)
is, at a quadrature point, a product of a test operator, a constant matrix and a
trial operator:

    a(u, v) = \int (B_test v)^T D (B_trial u) dV

    form                test op      D                                    trial op
    elastic             S (strain)   c                                    S
    piezo_coupling      S            e^T                                  grad
    dielectric          grad         eps                                  grad
    deviatoric_shear    S            2 mu (diag(w) - beta n n^T)          S
    pressure_divergence S            n (the trace: 1 on normal strains)   value
    pressure_mass       value        1 / kappa                            value

with dV = (quadrature weight) |det J| * kin.measure(x) (depth, 2 pi r or 1).
The operator of each local basis function at each quadrature point is
evaluated once per basis (the Voigt strain by the kinematics object itself, so
every model type is covered), stacked as an array (elements, points, rows,
local functions), and shared by all the forms that use it. The element matrices
of a form are then one batched matrix product over all elements,

    K_e = sum_q  B_test,eq^T (w_eq D) B_trial,eq      (numpy matmul, no Python loop over elements)

and all element matrices of one kind go into one COO -> CSR conversion. This is
what scikit-fem's BilinearForm computes too, but its kernel is called once per
pair of local functions (900 calls for a P2 tetrahedron, each re-evaluating the
strain of both functions); here the strains are evaluated 30 times and the
pairs are a matrix product. Where the operator is linear in the scalar shape
functions' gradients or values (every model type but the axisymmetric strain,
which has u_r / r), the element matrices go through the scalar functions
(`factored_matrices`): for vector P2 tetrahedra 3-6 x fewer operations, the
last product one BLAS call for all elements. Elements are processed in chunks
to bound memory.
The matrices equal scikit-fem's to round-off (tests/test_bilinear.py).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from skfem import ElementVector
from skfem.element.discrete_field import DiscreteField

from taxel.fem.constitution import Kinematics
from ._scalar_basis import LazyBasis, ScalarBasis, affine_blocks, block_csr, block_matrices, scalar_basis, scalar_dofs

CHUNK = 4000          # elements per batch: bounds the operator arrays (30 x 6 x 11 x 8 B each)


@dataclass(frozen=True)
class Operator:
    """Which quantity of a basis function a form uses at the quadrature points."""

    kind: str        # "strain" | "grad" | "value"


STRAIN, GRAD, VALUE = Operator("strain"), Operator("grad"), Operator("value")


def _sliced(df, sl) -> DiscreteField:
    return DiscreteField(value=np.asarray(df)[..., sl, :], grad=df.grad[..., sl, :])


def operator(basis, op: Operator, kin: Kinematics, sl=slice(None)) -> np.ndarray:
    """(elements, points, rows, local functions) values of `op` of every local basis
    function of `basis` on the elements `sl`."""
    x = None
    if op is STRAIN:
        gx = basis.global_coordinates()
        x = DiscreteField(value=np.asarray(gx)[..., sl, :])
    cols = []
    for fn in basis.basis:
        f = _sliced(fn[0], sl)
        if op is STRAIN:
            cols.append(kin.strain(f, x))                  # (nS, ne, nq)
        elif op is GRAD:
            cols.append(f.grad)                            # (dim, ne, nq)
        else:
            cols.append(np.asarray(f)[None])               # (1, ne, nq)
    return np.stack(cols, axis=-1).transpose(1, 2, 0, 3)   # (ne, nq, rows, nloc)


def weights(basis, kin: Kinematics, sl=slice(None)) -> np.ndarray:
    """(elements, points) quadrature weights times |det J| times the model's measure."""
    measure = kin.measure(np.zeros((kin.dim, 1, 1)))
    if isinstance(basis, ScalarBasis):
        if np.ndim(measure) != 0:
            raise ValueError("weights: a ScalarBasis carries no points for a varying measure (axisymmetric)")
        return float(measure) * basis.w[sl]
    if np.ndim(measure) == 0:                  # a constant measure: no points needed
        return float(measure) * basis.dx[sl]
    x = np.asarray(basis.global_coordinates())[..., sl, :]
    return basis.dx[sl] * np.broadcast_to(kin.measure(x), basis.dx[sl].shape)


@dataclass
class Term:
    """One form: test basis and operator, constant D, trial basis and operator."""

    test: object
    test_op: Operator
    D: np.ndarray
    trial: object
    trial_op: Operator


class Coo:
    """Accumulates (rows, cols, values) of element matrices; one CSR at the end."""

    def __init__(self):
        self.rows, self.cols, self.vals = [], [], []

    def add(self, rows, cols, vals):
        self.rows.append(rows.ravel())
        self.cols.append(cols.ravel())
        self.vals.append(vals.ravel())

    def csr(self, shape) -> sp.csr_matrix:
        if not self.vals:
            return sp.csr_matrix(shape)
        r, c, v = (np.concatenate(a) for a in (self.rows, self.cols, self.vals))
        return sp.csr_matrix((v, (r, c)), shape=shape)


def lifting(basis, op: Operator, kin: Kinematics):
    """(Q kind, L) when `op` of this basis is linear in the gradients (or values) of
    its scalar shape functions: op_s(function (a, c)) = sum_r L[s, c, r] Q_r(a), Q
    the scalar gradients ("grad") or values ("value"). None where it is not (the
    axisymmetric strain also has u_r / r): then the generic path is used."""
    if op is VALUE:
        return (None if isinstance(basis.elem, ElementVector) else ("value", np.ones((1, 1, 1))))
    if op is GRAD:
        return None if isinstance(basis.elem, ElementVector) else ("grad", np.eye(kin.dim)[:, None, :])
    if not isinstance(basis.elem, ElementVector):
        return None
    L = strain_lifting(kin)
    return None if L is None else ("grad", L)


def scalar_quantities(basis, kind: str, sl) -> np.ndarray:
    """(elements, points, r, scalar functions): gradients or values of the scalar shape
    functions of a basis (component 0 of a vector basis: its functions are (a, c))."""
    if isinstance(basis, LazyBasis) and basis.scalar is not None:
        basis = basis.scalar
    if isinstance(basis, ScalarBasis):
        if kind == "grad":
            return basis.grads(sl)
        ne = len(range(basis.detJ.shape[0])[sl])
        return np.broadcast_to(basis.values[None, :, None, :], (ne,) + basis.values.shape[:1] + (1,)
                               + basis.values.shape[1:])
    nc = basis.elem.dim if isinstance(basis.elem, ElementVector) else 1
    fns = [basis.basis[a * nc][0] for a in range(len(basis.basis) // nc)]
    if kind == "grad":
        q = [f.grad[0][..., sl, :] if nc > 1 else f.grad[..., sl, :] for f in fns]
        return np.stack(q, axis=-1).transpose(1, 2, 0, 3)
    q = [np.asarray(f)[..., sl, :] for f in fns]
    return np.stack(q, axis=-1)[:, :, None, :]


def factored_matrices(term: Term, lt, lr, kin, sl, cache) -> np.ndarray:
    """Element matrices through the scalar shape functions: with op = L Q,

        K_e[(a, c), (b, d)] = sum_{r, r'} H_e[(r, a), (r', b)] C[(r, r'), (c, d)],
        H_e = sum_q w_q Q_test,q^T Q_trial,q,   C = L_test^T D L_trial,

    one small batched product per element (functions x points x functions) and
    one BLAS product with C for all elements; 3-6 x fewer operations than the
    generic path for vector P2 elements."""
    (kt, Lt), (kr, Lr) = lt, lr
    Qt, Qr = _q(term.test, kt, sl, cache), _q(term.trial, kr, sl, cache)
    w = _weights(term.trial, kin, sl, cache)
    ne, nq, rt, na = Qt.shape
    rr, nb = Qr.shape[2], Qr.shape[3]
    nc, nd = Lt.shape[1], Lr.shape[1]
    Qtw = (Qt * w[:, :, None, None]).transpose(0, 2, 3, 1).reshape(ne, rt * na, nq)
    H = np.matmul(Qtw, Qr.reshape(ne, nq, rr * nb)).reshape(ne, rt, na, rr, nb)
    C = np.einsum("scr,st,tdx->rxcd", Lt, term.D, Lr).reshape(rt * rr, nc * nd)
    K = H.transpose(0, 2, 4, 1, 3).reshape(ne * na * nb, rt * rr) @ C
    return K.reshape(ne, na, nb, nc, nd).transpose(0, 1, 3, 2, 4).reshape(ne, na * nc, nb * nd)


def strain_lifting(kin: Kinematics):
    """L (n_voigt, dim, dim) with strain_s(N_a e_c) = sum_k L[s, c, k] dN_a/dx_k, or
    None when the strain also depends on values (the axisymmetric u_r / r)."""
    d = kin.dim
    probe = DiscreteField(value=np.ones((d, 1, 1)), grad=np.zeros((d, d, 1, 1)))
    if np.any(kin.strain(probe, DiscreteField(value=np.ones((d, 1, 1))))):
        return None
    L = np.zeros((kin.n_voigt, d, d))
    for c in range(d):
        for k in range(d):
            g = np.zeros((d, d, 1, 1))
            g[c, k] = 1.0
            L[:, c, k] = kin.strain(DiscreteField(value=np.zeros((d, 1, 1)), grad=g),
                                    DiscreteField(value=np.ones((d, 1, 1))))[:, 0, 0]
    return L


def vector_matrix(sb: ScalarBasis, D: np.ndarray, kin: Kinematics, shape=None) -> sp.csr_matrix:
    """The matrix of int S(v)^T D S(u) dV over a ScalarBasis's elements, u the vector
    field of its element (DOF dim s + c). Not for the axisymmetric strain (u_r / r)."""
    L = strain_lifting(kin)
    if L is None:
        raise ValueError("vector_matrix: this strain depends on values (axisymmetric); use assemble_terms")
    return block_csr(sb.dofs, sb.dofs, affine_blocks(sb, L, D), sb.N, sb.N, shape)


def _weights(basis, kin, sl, cache):
    if ("w", id(basis)) not in cache:
        cache[("w", id(basis))] = weights(basis, kin, sl)
    return cache[("w", id(basis))]


def element_matrices(term: Term, kin: Kinematics, sl, cache: dict) -> np.ndarray:
    """(elements, test functions, trial functions) element matrices of a term on `sl`."""
    def op(basis, o):
        key = (id(basis), o.kind)
        if key not in cache:
            cache[key] = operator(basis, o, kin, sl)
        return cache[key]
    lt, lr = lifting(term.test, term.test_op, kin), lifting(term.trial, term.trial_op, kin)
    if lt is not None and lr is not None:
        return factored_matrices(term, lt, lr, kin, sl, cache)
    Bt = op(term.test, term.test_op)
    Br = op(term.trial, term.trial_op)
    w = _weights(term.trial, kin, sl, cache)
    DB = np.matmul(term.D, Br) * w[..., None, None]          # (ne, nq, a, ntr)
    ne, nq, a, ntr = DB.shape
    nte = Bt.shape[-1]
    return np.matmul(Bt.transpose(0, 3, 1, 2).reshape(ne, nte, nq * a), DB.reshape(ne, nq * a, ntr))


def assemble_terms(terms: list[tuple], kin: Kinematics, shape) -> dict[str, sp.csr_matrix]:
    """CSR matrices by kind from terms (kind, region, term, sign, row offset,
    column offset, mirrored): each term's element matrices times `sign`, placed at
    the offsets, and if `mirrored` also transposed (the symmetric partner block of a
    coupling). Terms of one region share the chunk loop and the operators."""
    coos: dict[str, Coo] = {}
    regions: dict[str, list] = {}
    L = strain_lifting(kin)
    blocked: dict[str, list] = {}      # vector-vector strain terms: dense blocks on the scalar DOFs
    for t in terms:
        kind, _, term, _, r0, c0, mirrored = t
        if (L is not None and term.test is term.trial and term.test_op is STRAIN and term.trial_op is STRAIN
                and r0 == c0 == 0 and not mirrored and scalar_dofs(term.test) is not None):
            blocked.setdefault(kind, [])
        else:
            coos.setdefault(kind, Coo())
        regions.setdefault(t[1], []).append(t)
    shared: dict = {}
    for group in regions.values():
        ne = group[0][2].trial.nelems
        for start in range(0, ne, CHUNK):
            sl = slice(start, min(start + CHUNK, ne))
            cache: dict = {}
            for kind, _, term, sign, r0, c0, mirrored in group:
                if kind in blocked:
                    if start == 0:
                        blocked[kind].append(_affine_term(term, sign, L, kin, shared))
                    if blocked[kind][0] is None:            # not affine: the points' gradients
                        blocked[kind].append((term.test, scalar_dofs(term.test)[sl], sign * block_matrices(
                            _q(term.trial, "grad", sl, cache), _weights(term.trial, kin, sl, cache), L, term.D)))
                    continue
                Ke = sign * element_matrices(term, kin, sl, cache)
                rd = term.test.element_dofs[:, sl].T + r0        # (ne, nte)
                cd = term.trial.element_dofs[:, sl].T + c0       # (ne, ntr)
                R = np.broadcast_to(rd[:, :, None], Ke.shape)
                C = np.broadcast_to(cd[:, None, :], Ke.shape)
                coos[kind].add(R, C, Ke)
                if mirrored:
                    coos[kind].add(C, R, Ke)
    out = {kind: coo.csr(shape) for kind, coo in coos.items()}
    for kind, chunks in blocked.items():
        chunks = chunks[1:] if chunks[0] is None else chunks
        basis = chunks[0][0]
        ns = basis.N // basis.elem.dim
        s = np.concatenate([c[1] for c in chunks])
        out[kind] = block_csr(s, s, np.concatenate([c[2] for c in chunks]), ns, ns, shape)
    return out


def _affine_term(term: Term, sign: float, L, kin: Kinematics, shared: dict):
    """(basis, scalar DOFs, blocks) of a vector-vector strain term by affine_blocks, or
    None where that does not apply (curved or non-simplex mesh, a measure varying over
    the element, a numbering that differs from scalar_basis's). The scalar basis uses
    the term's basis's own quadrature rule."""
    b = term.test
    m = b.mesh
    measure = kin.measure(np.zeros((kin.dim, 1, 1)))
    if not getattr(m, "affine", False) or m.t.shape[0] != m.dim() + 1 or np.ndim(measure) != 0:
        return None
    s = scalar_dofs(b)
    if isinstance(b, LazyBasis):
        sb = b.scalar
        return None if sb is None else (b, s, (sign * float(measure)) * affine_blocks(sb, L, term.D))
    X, W = b.quadrature
    key = (id(m), type(b.elem.elem).__name__, X.tobytes(), W.tobytes())
    if key not in shared:
        try:
            shared[key] = scalar_basis(m, b.elem.elem, quadrature=(X, W))
        except ValueError:
            shared[key] = None
    sb = shared[key]
    tind = slice(None) if b.tind is None else b.tind
    if sb is None or not np.array_equal(sb.dofs[tind], s):
        return None
    return b, s, (sign * float(measure)) * affine_blocks(sb, L, term.D, tind)


def _q(basis, kind, sl, cache):
    key = (id(basis), "q", kind)
    if key not in cache:
        cache[key] = scalar_quantities(basis, kind, sl)
    return cache[key]
