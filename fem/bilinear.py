r"""Vectorised assembly of the constant-coefficient bilinear forms of fem.forms.

Every linear form of the coupled problem (fem.forms, weak forms in its docstring)
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

from taxel.fem.kinematics import Kinematics

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
    d = kin.dim
    probe = DiscreteField(value=np.ones((d, 1, 1)), grad=np.zeros((d, d, 1, 1)))
    if np.any(kin.strain(probe, DiscreteField(value=np.ones((d, 1, 1))))):
        return None                              # the strain depends on values too
    L = np.zeros((kin.n_voigt, d, d))
    for c in range(d):
        for k in range(d):
            g = np.zeros((d, d, 1, 1))
            g[c, k] = 1.0
            L[:, c, k] = kin.strain(DiscreteField(value=np.zeros((d, 1, 1)), grad=g),
                                    DiscreteField(value=np.ones((d, 1, 1))))[:, 0, 0]
    return "grad", L


def scalar_quantities(basis, kind: str, sl) -> np.ndarray:
    """(elements, points, r, scalar functions): gradients or values of the scalar shape
    functions of a basis (component 0 of a vector basis: its functions are (a, c))."""
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
    def q(basis, kind):
        key = (id(basis), "q", kind)
        if key not in cache:
            cache[key] = scalar_quantities(basis, kind, sl)
        return cache[key]
    (kt, Lt), (kr, Lr) = lt, lr
    Qt, Qr = q(term.test, kt), q(term.trial, kr)
    w = _weights(term.trial, kin, sl, cache)
    ne, nq, rt, na = Qt.shape
    rr, nb = Qr.shape[2], Qr.shape[3]
    nc, nd = Lt.shape[1], Lr.shape[1]
    Qtw = (Qt * w[:, :, None, None]).transpose(0, 2, 3, 1).reshape(ne, rt * na, nq)
    H = np.matmul(Qtw, Qr.reshape(ne, nq, rr * nb)).reshape(ne, rt, na, rr, nb)
    C = np.einsum("scr,st,tdx->rxcd", Lt, term.D, Lr).reshape(rt * rr, nc * nd)
    K = H.transpose(0, 2, 4, 1, 3).reshape(ne * na * nb, rt * rr) @ C
    return K.reshape(ne, na, nb, nc, nd).transpose(0, 1, 3, 2, 4).reshape(ne, na * nc, nb * nd)


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
    for t in terms:
        coos.setdefault(t[0], Coo())
        regions.setdefault(t[1], []).append(t)
    for group in regions.values():
        ne = group[0][2].trial.nelems
        for start in range(0, ne, CHUNK):
            sl = slice(start, min(start + CHUNK, ne))
            cache: dict = {}
            for kind, _, term, sign, r0, c0, mirrored in group:
                Ke = sign * element_matrices(term, kin, sl, cache)
                rd = term.test.element_dofs[:, sl].T + r0        # (ne, nte)
                cd = term.trial.element_dofs[:, sl].T + c0       # (ne, ntr)
                R = np.broadcast_to(rd[:, :, None], Ke.shape)
                C = np.broadcast_to(cd[:, None, :], Ke.shape)
                coos[kind].add(R, C, Ke)
                if mirrored:
                    coos[kind].add(C, R, Ke)
    return {kind: coo.csr(shape) for kind, coo in coos.items()}
