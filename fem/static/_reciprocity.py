"""Reciprocity: every taxel's short-circuit charge under a force anywhere, from one
solve per driven electrode (docs/theory/surface-map.md).

The assembled operator is symmetric (the electric rows carry the usual minus sign,
fem.assembly): A = [[K, G], [G^T, -E]]. Eliminate the supports and the reference,
hold the driven electrodes' potentials (their DOFs collapse to one value each, as in
fem.assembly.elimination) and keep every other electrode floating (charge free: its
potential is an unknown whose equation is Q = 0). With P the map from the free
unknowns y (displacements, interior potentials, floating electrodes' potentials) to
the full vector and K_r = P^T A P (symmetric):

    direct:      K_r w = P^T f,          x_f = P w             (force f, driven grounded)
                 Q_j = -(A x_f)_{e_j}    (the charge balance of electrode j: the sum of its rows)
    reciprocal:  x_j = x0_j + P z_j,     K_r z_j = -P^T A x0_j (x0_j: 1 V on electrode j's DOFs)

so Q_j = -x0_j^T A P w = z_j^T K_r w = z_j^T P^T f = f . x_j: the short-circuit charge of
taxel j under any load f is the work of f on the displacement of the 1 V solve on j
(with the others grounded). A unit force along k at a point x gives Q_j = u_k^(j)(x).
The capacitance matrix comes with it: C_ij = -(A x_j)_{e_i} (the charge on i with 1 V on
j); open-circuit voltages are V = -C^-1 Q_sc.

Mirror symmetry (fem.static's classes, docs/theory/symmetry.md): 1 V on one taxel is
not symmetric, but it is a sum over the characters chi of the mirror group G of
patterns that are: with a modelled electrode a, its orbit O_a (the images i = g_i a)
and the characters that do not ground it (|O_a| of them, character orthogonality),

    e_i = (1 / |O_a|) sum_chi chi(g_i) p_chi,      p_chi = sum_{j in O_a} chi(g_j) e_j

and p_chi is solved on the cut part in class chi as "1 V on a" (its other electrodes
held at 0 V). A field of class chi at the mirror image h x of a point x of the cut part
is chi(h) S_h u(x), S_h flipping the components normal to h's planes. So
`surface_response` takes one factorization per class, one right-hand side per modelled
electrode floating in it, and unfolds every taxel's response at any surface point:

    u^(i)(h x) = (1 / |O_a|) sum_chi chi(g_i) chi(h) S_h u^(chi, a)(x).

The capacitance matrix of the full array follows from the classes' charges
(fem.static._symmetry.capacitance).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from skfem import CellBasis

from taxel.fem import linalg
from taxel.fem.assembly import System, elimination
from . import _symmetry as symmetry


# iterative refinement to the last digits (up to three back-substitutions, cheap next to the
# factorization): at fem.linalg's default 1e-13 the identity held to 1.4e-8 on a small 3D
# array, at this one to 2.7e-9 (tests/test_surface_map.py)
REFINE = 1e-16
INSIDE = 1e-8         # surface points are read this fraction of the model's extent inside it


@dataclass
class UnitVoltageFields:
    """The static states with 1 V on each driven electrode (the other driven ones
    grounded, other electrodes floating), no mechanical load."""

    driven: list[str]             # electrode names, the order of every axis below
    x: np.ndarray                 # (n_driven, n) full solution vectors (u, p, phi)
    capacitance: np.ndarray       # (n_driven, n_driven) F, C[i, j] = charge on i with 1 V on j
    residual: float               # largest relative residual of the reduced solves
    solver: str


def _reduced(sy: System, driven, fixed=None, grounded=(), cut_ok=False):
    states = sy.electrodes.states
    bad = [k for k in driven if states.get(k) is None or states[k] == "reference"]
    if bad:
        raise ValueError(f"electrodes.{bad[0]}: not a drivable electrode of this model (the reference or unknown)")
    held = tuple(driven) + tuple(k for k, s in states.items() if s == "ground" and k not in driven)
    if any(not isinstance(s, str) for k, s in states.items() if k not in held):
        raise ValueError("electrodes: a reciprocal solve takes electrodes open or grounded, not at a set voltage")
    if sy.tm.layout.planes and not cut_ok:
        raise ValueError("a direct reciprocal solve needs the full model; surface_response unfolds a cut one")
    return elimination(sy, fixed=fixed, grounded=held + tuple(grounded))


def charges(sy: System, x: np.ndarray, names) -> np.ndarray:
    """Charges (C) on electrodes `names` of full states x (n, m): minus the sum of each
    electrode's rows of A x (no load on the electric rows)."""
    Ax = sy.A @ np.asarray(x).reshape(sy.A.shape[0], -1)
    return np.array([-Ax[sy.electrodes.dofs[k]].sum(axis=0) for k in names])


def unit_voltage_fields(sy: System, driven, method: str = "auto", scale: bool = True, fixed=None,
                        grounded=()) -> UnitVoltageFields:
    """One factorization, one right-hand side per driven electrode (module docstring).
    `fixed`, `grounded`: a mirror class's DOFs and electrodes held at zero (cut models)."""
    red = _reduced(sy, driven, fixed, grounded, cut_ok=fixed is not None or not sy.tm.layout.planes)
    method = linalg.resolve(method, red.n, iterative=False, dim=sy.tm.mesh.dim())
    n = sy.A.shape[0]
    X0 = np.zeros((n, len(driven)))
    for i, k in enumerate(driven):
        X0[sy.electrodes.dofs[k], i] = 1.0
    A = (red.P.T @ sy.A @ red.P).tocsc()
    solve = linalg.scaled_solver(A, red.is_u, method, scale)
    Z, res = solve(-(red.P.T @ (sy.A @ X0)), REFINE)
    X = X0 + red.P @ Z.reshape(red.n, -1)
    C = charges(sy, X, driven)
    return UnitVoltageFields(list(driven), X.T.copy(), 0.5 * (C + C.T), float(np.max(res)), method)


def direct_charges(sy: System, f: np.ndarray, driven, method: str = "auto") -> np.ndarray:
    """(n_driven, m) short-circuit charges (C) of the driven electrodes under full load
    vectors f (n, m), every driven electrode grounded: the direct solve the reciprocal
    identity replaces (tests, validation)."""
    red = _reduced(sy, driven)
    method = linalg.resolve(method, red.n, iterative=False, dim=sy.tm.mesh.dim())
    A = (red.P.T @ sy.A @ red.P).tocsc()
    W, _ = linalg.scaled_solver(A, red.is_u, method)(red.P.T @ np.asarray(f).reshape(sy.A.shape[0], -1), REFINE)
    return charges(sy, red.P @ W.reshape(red.n, -1), driven)


def displacement_probe(sy: System, points: np.ndarray) -> sp.csr_matrix:
    """(3 n, N_u) matrix giving u_x at the n points, then u_y, then u_z, at points (3, n) of
    the mesh from the displacement block of a full state (points on the boundary are
    found within round-off; give them a hair inside)."""
    ub = next(iter(sy.ubases.values()))
    basis = CellBasis(sy.tm.mesh, ub.elem, intorder=1)
    if basis.N != sy.offsets["u"].stop - sy.offsets["u"].start:
        raise RuntimeError("displacement basis numbering differs from the assembled one")
    p = np.asarray(points, float)
    lo, hi = sy.tm.mesh.p.min(axis=1), sy.tm.mesh.p.max(axis=1)
    eps = INSIDE * (hi - lo)             # on the outline or the top: a hair inside
    p = np.clip(p, (lo + eps)[:, None], (hi - eps)[:, None])
    cells = _cells(sy.tm.mesh, basis.mapping, p)
    # scikit-fem's CellBasis.probes with these cells (its own finder, failing one point, tests every
    # element against every point: 7.6 GB on the 8x8 array's map)
    ref = basis.mapping.invF(p[:, :, None], tind=cells)
    phis = np.array([basis.elem.gbasis(basis.mapping, ref, k, tind=cells)[0] for k in range(basis.Nbfun)]).flatten()
    comp = int(np.prod(basis._base_tensor_order))
    rows = np.tile(np.arange(comp * p.shape[1], dtype=np.int64), basis.Nbfun)
    cols = basis.element_dofs[:, np.tile(cells, comp)].flatten()
    return sp.coo_matrix((phis, (rows, cols)), shape=(comp * p.shape[1], basis.N)).tocsr()


def _cells(mesh, mapping, p: np.ndarray, tol: float = 1e-9) -> np.ndarray:
    """The element holding each point (3, n): the candidates nearest by centroid, more of
    them for the points not found yet; memory O(n x candidates)."""
    from scipy.spatial import cKDTree
    tree = cKDTree(mesh.p[:, mesh.t].mean(axis=1).T)
    cells = np.full(p.shape[1], -1)
    todo = np.arange(p.shape[1])
    for k in (8, 32, 128, 512):
        k = min(k, mesh.t.shape[1])
        cand = tree.query(p[:, todo].T, k)[1].reshape(len(todo), k)
        for j in range(k):
            X = mapping.invF(p[:, todo][:, :, None], tind=cand[:, j])[..., 0]
            hit = (X >= -tol).all(axis=0) & (1 - X.sum(axis=0) >= -tol)
            cells[todo[hit]] = cand[hit, j]
            todo, cand = todo[~hit], cand[~hit]
            if not todo.size:
                return cells
    raise ValueError(f"{todo.size} surface points are outside the mesh (first at {p[:, todo[0]]} m)")


@dataclass
class SurfaceResponse:
    """Every electrode's short-circuit charge per newton of a point force at surface
    points, and the capacitance matrix, of the full array."""

    names: list[str]              # electrodes (the full array's, layout order)
    R: np.ndarray                 # (n_names, 3, n_points) C/N, force along x, y, z
    capacitance: np.ndarray       # (n_names, n_names) F
    factorizations: int
    right_hand_sides: int
    residual: float
    solver: str


def surface_response(sy: System, points: np.ndarray, method: str = "auto", scale: bool = True) -> SurfaceResponse:
    """The short-circuit charge per newton of every non-reference electrode of the full
    array for a point force along x, y, z at each of `points` (3, n) (full-model
    coordinates, on or a hair inside the mesh's top surface), from the model `sy`: the
    full model (one factorization) or a cut one (one per mirror class; module docstring)."""
    pts = np.asarray(points, float)
    lay = sy.tm.layout
    driven = [k for k, s in sy.electrodes.states.items() if s != "reference"]
    if not lay.planes:
        f = unit_voltage_fields(sy, driven, method, scale)
        M = displacement_probe(sy, pts)
        R = np.stack([(M @ x[sy.offsets["u"]]).reshape(3, -1) for x in f.x])
        return SurfaceResponse(driven, R, f.capacitance, 1, len(driven), f.residual, f.solver)
    planes = lay.planes
    h = np.array([np.where(pts[k] < 0, -1, 1) for k in planes])         # (nplanes, n) the image each point is in
    folded = pts.copy()
    for k in planes:
        folded[k] = np.abs(folded[k])
    M = displacement_probe(sy, folded)
    flip = np.ones((3, pts.shape[1]))
    for row, k in enumerate(planes):
        flip[k] = h[row]                                                 # S_h: the normal component flips
    cls = {c.signs: c for c in symmetry.classes(sy)}
    orbit = {}
    for _, model, _ in lay.images:
        orbit[model] = orbit.get(model, 0) + 1
    names = [full for full, model, _ in lay.images if model in driven]
    R = np.zeros((len(names), 3, pts.shape[1]))
    blocks, nf, nrhs, residual, solver = {}, 0, 0, 0.0, ""
    for signs in symmetry.group(planes):
        c = cls.get(signs)
        if c is None and any(s < 0 for s in signs):
            continue                                                     # no electrode floats in this class
        fixed, grounded = (None, ()) if c is None else (c.fixed, c.grounded)
        act = [a for a in driven if a not in grounded]
        f = unit_voltage_fields(sy, act, method, scale, sy.fixed_u if fixed is None else fixed, grounded)
        nf, nrhs, residual, solver = nf + 1, nrhs + len(act), max(residual, f.residual), f.solver
        blocks[signs] = (act, f.capacitance)
        chi_h = np.prod([np.where(hk < 0, s, 1) for s, hk in zip(signs, h)], axis=0)     # chi(h) per point
        for a, x in zip(act, f.x):
            u = (M @ x[sy.offsets["u"]]).reshape(3, -1) * flip * chi_h
            for i, (full, model, g) in enumerate(img for img in lay.images if img[1] in driven):
                if model == a:
                    R[i] += symmetry._character(signs, g) * u / orbit[a]
    cnames, C = symmetry.capacitance(sy, blocks)
    order = [cnames.index(k) for k in names]
    return SurfaceResponse(names, R, C[np.ix_(order, order)], nf, nrhs, residual, solver)
