"""The static linear solve: one factorization, every electrode quantity.

With the active electrodes collapsed (fem.assembly), one factorization of the
eliminated matrix gives, by back-substitution:

    x_f        load, all active electrodes open (Q = 0): open-circuit voltages V_f
    X_k        unit charge on electrode k:        column k of C^-1
    C          the capacitance matrix (clamped by the supports, free elsewhere)
    Q_sc = -C V_f   short-circuit charges (what a charge amplifier integrates)

and the state the problem asks for (each electrode open, grounded or at a
voltage) follows from the n x n relation V = V_f + C^-1 Q without another
factorization. Tests also check equilibrium of the reactions and agreement
between solvers.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from taxel.fem import linalg
from . import _symmetry as symmetry
from taxel.fem.assembly import System
from taxel.fem.assembly import Elimination, elimination
from ._fields import Fields, component_dofs, fields
from taxel.fem.constitution import Axisymmetric
from taxel.meshing.build import TaggedMesh


@dataclass
class ElectrodeResult:
    name: str
    state: str                    # open | ground | reference | "<V> V"
    voltage: float                # V, under the problem's electrode states
    charge: float                 # C, under the problem's electrode states
    short_circuit_charge: float   # C, this and every other active electrode grounded
    capacitance: float | None     # F, self capacitance with the others grounded; None for the reference


@dataclass
class Solution:
    electrodes: dict[str, ElectrodeResult]
    applied_force: float          # N, total downward load
    reaction: np.ndarray          # N, total support reaction (x, [y,] z); axisymmetric: (0, z)
    max_strain: float       # largest |principal strain| of element means in the passive solids
    unknowns: int
    solver: str
    residual: float               # relative residual |A x - b| / |b| of the scaled system
    mesh: TaggedMesh
    fields: Fields = field(repr=False)
    newton: object = None         # fem.hyperelastic.NewtonResult for a hyperelastic solve
    contact: object = None        # fem.contact.PressResult for a press by a rigid indenter
    # the Maxwell capacitance matrix (F) of the non-reference electrodes, in this order
    capacitance_names: list[str] = field(default_factory=list)
    capacitance_matrix: np.ndarray | None = field(default=None, repr=False)

    def voltages(self) -> dict[str, float]:
        return {k: e.voltage for k, e in self.electrodes.items() if e.state != "reference"}


def _solve(sy: System, red: Elimination, method: str, scale: bool, rhs, K=None):
    A = (red.P.T @ (sy.A if K is None else K) @ red.P).tocsc()
    solver = linalg.krylov_solver(A, linalg.krylov_blocks(sy, red)) if method == "krylov" else \
        linalg.scaled_solver(A, red.is_u, method, scale)
    return solver(rhs)


def solve_linear(sy: System, method: str = "auto", scale: bool = True) -> Solution:
    """The linear static Solution of an assembled system (of a cut, mirror-symmetric
    layout: the full sensor's electrodes, see fem.static)."""
    red = elimination(sy)
    nf, na = red.nf, len(red.active)
    method = linalg.resolve(method, red.n, iterative=True, dim=sy.tm.mesh.dim())
    X, res = _solve(sy, red, method, scale, np.column_stack([red.P.T @ sy.b, red.unit_charges()]))
    # open-circuit voltages, capacitance matrix, and the state the problem asks for
    Vf, Cinv = X[nf:, 0], X[nf:, 1:]
    states = sy.electrodes.states
    fixedV = [i for i, k in enumerate(red.active) if states[k] != "open"]
    Q = np.zeros(na)
    if fixedV:
        Vset = np.array([0.0 if states[red.active[i]] == "ground" else states[red.active[i]] for i in fixedV])
        Q[fixedV] = np.linalg.solve(Cinv[np.ix_(fixedV, fixedV)], Vset - Vf[fixedV])
    x = red.P @ (X[:, 0] + X[:, 1:] @ Q)
    r = sy.A @ x - sy.b
    sol = results(sy, red, x, r, Cinv, method, float(res.max()))
    return unfold_solution(sy, sol, red, Cinv, method, scale) if sy.tm.layout.planes else sol


def unfold_solution(sy: System, sol: Solution, red: Elimination, Cinv, method, scale=True, K=None) -> Solution:
    """The full sensor's Solution from a symmetric (half or quarter) model's. `K`: the
    full (not eliminated) matrix the capacitance is linearised with (default the linear
    sy.A; a pressed state's tangent, fem.contact)."""
    blocks = {symmetry.group(sy.tm.layout.planes)[0]: (red.active, np.linalg.inv(Cinv))}
    residual = sol.residual
    for cls in symmetry.classes(sy):
        rc = elimination(sy, fixed=cls.fixed, grounded=cls.grounded)
        X, res = _solve(sy, rc, method, scale, rc.unit_charges(), K)
        blocks[cls.signs] = (rc.active, np.linalg.inv(X[rc.nf:, :]))
        residual = max(residual, float(res.max()))
    names, C = symmetry.capacitance(sy, blocks)
    return replace(sol, electrodes=symmetry.unfold_electrodes(sy, sol.electrodes, C, names),
                   capacitance_names=names, capacitance_matrix=C,
                   applied_force=symmetry.symmetry_order(sy) * sol.applied_force,
                   reaction=symmetry.unfold_reaction(sy, sol.reaction), residual=residual)


def results(sy: System, red: Elimination, x, r, Cinv, solver: str, residual: float) -> Solution:
    """Per-electrode numbers, reactions and fields from a solved state.

    x: full solution; r: full residual (A x - b: reactions at supports, charges at
    electrodes); Cinv: inverse capacitance matrix of the active electrodes.
    """
    na = len(red.active)
    C = np.linalg.inv(Cinv) if na else np.zeros((0, 0))
    states, edofs = sy.electrodes.states, sy.electrodes.dofs
    V = np.array([x[edofs[k][0]] for k in red.active])
    electrodes = {}
    for i, k in enumerate(red.active):
        st = states[k]
        q = 0.0 if st == "open" else float(-r[edofs[k]].sum())    # open: Q = 0 exactly
        qsc = float(q - (C @ V)[i])                                # Q = Q_sc + C V
        electrodes[k] = ElectrodeResult(k, st if isinstance(st, str) else f"{st:g} V", float(V[i]), q,
                                        qsc, float(C[i, i]))
    for k in red.ref:                          # grounded: the charge is the residual of its rows
        q = float(-r[edofs[k]].sum())
        electrodes[k] = ElectrodeResult(k, states[k], 0.0, q, q, None)
    if len(red.ref) == 1 and red.active:       # charge is conserved: the one grounded electrode
        ref = electrodes[red.ref[0]]           # carries minus the others' (exactly, not to round-off)
        ref.charge = -sum(electrodes[k].charge for k in red.active)
        ref.short_circuit_charge = -sum(electrodes[k].short_circuit_charge for k in red.active)
    dim = sy.tm.mesh.dim()
    ub = next(iter(sy.ubases.values()))
    reaction = np.array([r[np.intersect1d(sy.fixed_u, component_dofs(ub, c))].sum() for c in range(dim)])
    if isinstance(sy.kin, Axisymmetric):
        reaction[0] = 0.0           # radial support forces cancel around the circle
    f = fields(sy, x)
    return Solution(electrodes, sy.applied_force, reaction, f.max_strain, red.n, solver, residual,
                    sy.tm, f, capacitance_names=list(red.active), capacitance_matrix=C)
