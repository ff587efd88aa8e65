"""Supports, electrodes, and the elimination of the constrained unknowns.

Supports fix displacement DOFs (all homogeneous). Electrodes: one is the
reference (phi = 0: the common bottom "ground" of an array when it is grounded,
else the first grounded electrode, as on a plate). Every other electrode is *active*: its potential DOFs
collapse into one unknown V_k whose equation is the electrode's charge balance
(the sum of its rows), right-hand side -Q_k. The elimination x_full = P y drops
fixed displacements, unused pressure/potential DOFs and the reference electrode
(and, if asked, every grounded electrode), and collapses active electrodes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from taxel.fem.constitution import Axisymmetric
from ._problem import Problem


class ConstraintError(ValueError):
    """Supports or electrodes that cannot be applied; one line with the fix."""


@dataclass
class Electrodes:
    dofs: dict[str, np.ndarray]    # electrode -> global phi DOFs (offset applied)
    states: dict                   # electrode -> "reference" | "open" | "ground" | volts (float)

    @property
    def names(self) -> list[str]:
        return list(self.states)


def supports(problem: Problem, ub, signs: tuple[int, ...] | None = None) -> np.ndarray:
    """Constrained displacement DOFs (all homogeneous) of the problem's supports.

    On the symmetry planes of a cut layout (facets "mirror_x", "mirror_y"): with
    sign +1 (a symmetric field, the default) the normal component u.n = 0; with
    sign -1 (antisymmetric, fem.static) the tangential components."""
    tm, sup, kin = problem.mesh, problem.supports, problem.kinematics
    lay, dim = tm.layout, tm.mesh.dim()
    vertical = f"u^{dim}"
    out = []

    def dofs(name, which=None):
        if name not in tm.facets:
            return np.zeros(0, int)
        d = ub.get_dofs(tm.facets[name])
        return d.all() if which is None else d.all(which)

    if sup.bottom == "bonded":
        out.append(dofs("bottom"))
    elif sup.bottom == "rollers":
        out.append(dofs("bottom", [vertical]))
        bottom_nodes = np.unique(tm.mesh.facets[:, tm.facets["bottom"]])
        centre = np.array([lay.plan.x, lay.plan.y][: dim - 1])
        in_plane = set(range(dim - 1))
        if isinstance(kin, Axisymmetric) or in_plane <= set(lay.planes):
            pass                                   # no in-plane rigid motion is left
        elif lay.planes:                           # a 3D half cut at x = 0: only the y translation
            k = bottom_nodes[np.argmin(np.linalg.norm(tm.mesh.p[:2, bottom_nodes], axis=0))]
            out.append(np.array([ub.nodal_dofs[1, k]]))
        else:                                      # pin the in-plane rigid motion
            out.append(_pins(tm, ub, bottom_nodes, centre))
    if sup.edges == "clamped":
        out.append(dofs("edges"))
    elif sup.edges == "rollers":
        if dim == 3 and lay.plan.shape == "disk":
            raise ConstraintError("supports.edges = 'rollers' needs a rectangular plan in 3d; "
                                  "use 'clamped' or a rectangle")
        fac = tm.facets["edges"]
        if dim == 2:
            out.append(ub.get_dofs(fac).all(["u^1"]))
        else:
            mid = tm.mesh.p[:, tm.mesh.facets[:, fac]].mean(axis=1)
            on_x = np.abs(np.abs(mid[0]) - lay.plan.half) < 1e-9 * lay.plan.half
            out += [ub.get_dofs(fac[on_x]).all(["u^1"]), ub.get_dofs(fac[~on_x]).all(["u^2"])]
    elif sup.edges == "simply_supported":       # hinged along the mid-plane line
        d = dofs("edges")
        out.append(d[np.abs(ub.doflocs[dim - 1, d] - lay.midplane) < 1e-9 * lay.height])
    if isinstance(kin, Axisymmetric):
        out.append(dofs("axis", ["u^1"]))
    for k, sign in zip(lay.planes, signs or (1,) * len(lay.planes)):
        comps = [f"u^{k + 1}"] if sign > 0 else [f"u^{c + 1}" for c in range(dim) if c != k]
        out.append(dofs("mirror_" + "xy"[k], comps))
    return np.unique(np.concatenate(out or [np.zeros(0, int)])).astype(int)


def _pins(tm, ub, nodes, centre):
    """In-plane rigid-motion pins on the bottom: u_x (and u_y) at node k, and in 3D
    u_y at a node k2 on the same y line (so a free lateral expansion comes with no
    rigid rotation: harmless in a linear model, not strain-free in finite strain).
    k is the node nearest the centre among those with a partner on their y line."""
    dim = tm.mesh.dim()
    p = tm.mesh.p[: dim - 1, nodes]
    if dim == 2:
        k = nodes[np.argmin(np.abs(p[0] - centre[0]))]
        return np.array([ub.nodal_dofs[0, k]])
    tol = 1e-9 * max(np.ptp(p[0]), np.ptp(p[1]))
    y = np.round(p[1] / tol)
    _, inverse, counts = np.unique(y, return_inverse=True, return_counts=True)
    paired = counts[inverse] > 1
    cand = np.flatnonzero(paired) if paired.any() else np.arange(len(nodes))
    i = cand[np.argmin(np.linalg.norm(p[:, cand] - centre[:, None], axis=0))]
    same = np.flatnonzero(y == y[i]) if paired.any() else np.arange(len(nodes))
    j = same[np.argmax(np.abs(p[0, same] - p[0, i]))]
    return np.array([ub.nodal_dofs[0, nodes[i]], ub.nodal_dofs[1, nodes[i]], ub.nodal_dofs[1, nodes[j]]])


def default_state(name: str) -> str:
    """The state of an electrode the problem does not set: the common ground
    ("ground", a plate's "bottom") grounded, every other one open."""
    return "ground" if name in ("ground", "bottom") else "open"


def electrodes(problem: Problem, phibases, offset) -> Electrodes:
    """Global phi DOFs of each electrode, and each one's state (one is the reference)."""
    tm = problem.mesh
    names = [e.name for e in tm.layout.electrodes]
    unknown = sorted(set(problem.electrodes) - set(names))
    if unknown:
        raise ConstraintError(f"electrodes.{unknown[0]}: no such electrode; this model has: {', '.join(names)}")
    states = {name: problem.electrodes.get(name, default_state(name)) for name in names}
    if names and "ground" not in states.values():
        raise ConstraintError("electrodes: none is grounded, so the potential has no reference; "
                              "set one electrode to 'ground'")
    if names:
        grounded = [k for k, s in states.items() if s == "ground"]
        states["ground" if "ground" in grounded else grounded[0]] = "reference"   # the common ground first
    dofs = {}
    for name in names:
        d = [pb.get_dofs(tm.facets[name]).all() for pb in phibases.values() if name in tm.facets]
        dofs[name] = np.unique(np.concatenate(d)) + offset if d else np.zeros(0, int)
    return Electrodes(dofs, states)


@dataclass
class Elimination:
    """The constrained, collapsed unknowns: x_full = P y. Columns: free DOFs, then
    one potential per active electrode (whose equation is its charge balance)."""

    P: sp.csr_matrix
    nf: int
    active: list[str]
    ref: list[str]
    is_u: np.ndarray          # eliminated unknowns that are displacements

    @property
    def n(self):
        return self.nf + len(self.active)

    def unit_charges(self):
        """Right-hand sides for Q_k = 1 C on each active electrode (rhs -Q)."""
        B = np.zeros((self.n, len(self.active)))
        B[self.nf + np.arange(len(self.active)), np.arange(len(self.active))] = -1.0
        return B


def elimination(sy, eliminate_grounded: bool = False, fixed: np.ndarray | None = None,
              grounded: tuple[str, ...] = ()) -> Elimination:
    """The Elimination of an assembled fem.assembly.System.

    `fixed`: full DOFs held at zero instead of sy.fixed_u (any block); `grounded`:
    electrodes held at 0 V and eliminated (fem.static's antisymmetric classes)."""
    n = sy.A.shape[0]
    used = np.zeros(n, bool)
    used[sy.offsets["u"]] = True
    for region, pb in sy.pbases.items():
        used[sy.offsets[("p", region)].start + np.unique(pb.element_dofs)] = True
    phi0 = sy.offsets["phi"].start
    for pb in sy.phibases.values():
        used[phi0 + np.unique(pb.element_dofs)] = True
    used[sy.fixed_u if fixed is None else fixed] = False
    states, edofs = sy.electrodes.states, sy.electrodes.dofs
    held = ("reference", "ground") if eliminate_grounded else ("reference",)
    ref = [k for k, s in states.items() if s in held or k in grounded]
    active = [k for k, s in states.items() if not (s in held or k in grounded)]
    for k in ref + active:
        used[edofs[k]] = False
    free = np.flatnonzero(used)
    nf = len(free)
    col = np.full(n, -1)
    col[free] = np.arange(nf)
    for i, k in enumerate(active):
        col[edofs[k]] = nf + i
    rows = np.flatnonzero(col >= 0)
    P = sp.csr_matrix((np.ones(len(rows)), (rows, col[rows])), shape=(n, nf + len(active)))
    return Elimination(P, nf, active, ref, np.append(free < sy.offsets["u"].stop, np.zeros(len(active), bool)))
