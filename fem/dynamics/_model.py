r"""The linear dynamic model of a problem: mass, stiffness by kind, loss factors.

Equation of motion on the eliminated unknowns x of fem.assembly.elimination (supports
and the reference electrode eliminated; each other electrode one potential
whose row is its charge balance, right-hand side -Q_k):

    M x'' + C x' + K x = F f(t) + B_e Q(t)          (B_e: -1 at electrode row k)

M is the consistent mass of the displacements (pressure and potential carry
none), F the load of 1 N on the problem's footprint and f(t) the force in N. Damping:

* material (loss factors, per material: silicone shear and volumetric eta_s, piezo
  stiffness 1/Qm, permittivity tan(delta)), one causal law for every analysis
  (fem.constitution: a generalized Maxwell / Debye series fitted to the loss factor
  over the band; a constant complex modulus is not causal):
      K(w) = sum_parts kappa_part(w) K_part,  kappa(0) = 1 (the material data are
      the relaxed values), |Im kappa| / Re kappa = eta over the band;
  in time, K_u q - sum_j K^(j) s_j with the internal variables tau_j s_j' = q - s_j;
* Rayleigh, viscous: i w (alpha M + beta K_mech) (C = alpha M + beta K_mech).

With a Yeoh silicone the model is linearised about the static state under the
problem's load (the preload): K_part are then the consistent tangents at that
state (fem.hyperelastic.yeoh_terms), and responses are per newton of a small force
added on the same footprint.

Pressed by a rigid indenter (problem.indenter), the model is linearised about the
pressed state with the indenter holding it (fem.contact): the Yeoh tangents (if any)
at that state plus the contact tangent K_c (kind "contact", no loss), and the
excitation is the indenter's own motion: a travel oscillation dd enters as the load
-dr/dd dd (fem.contact.Surface.travel_derivatives), scaled per newton of the static
force-travel stiffness dF/dd of the pressed state. So at zero frequency the
response is the slope of the static voltage-force curve, dV/dF
(tests/test_contact_scene.py checks it against two static presses).

Frequency responses: fem.dynamics; transients: fem.dynamics.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from skfem import asm

from taxel.fem import assembly
from taxel.fem import linalg
from taxel.fem import constitution as rx
from taxel.fem.assembly import System, assemble
from taxel.fem.assembly import Elimination, elimination
from taxel.fem.hyperelastic import newton, yeoh_terms
from taxel.fem.contact import Press
from taxel.fem.assembly import Problem


@dataclass
class DynamicModel:
    sy: System
    red: Elimination
    parts: dict          # kind -> eliminated real sparse matrix
    relax: rx.Relaxation # the causal loss law of the lossy kinds (fem.constitution)
    M: sp.csr_matrix
    alpha: float
    beta: float
    F: np.ndarray        # eliminated load vector of 1 N of the problem's load
    Be: np.ndarray       # (n, na) unit-charge right-hand sides
    names: list[str]     # active electrodes (open model) or grounded ones (short model)
    charge_rows: sp.csr_matrix | None = None   # short model: Q = charge_rows @ x (massless rows)

    @property
    def K0(self):
        return sum(self.parts.values())

    @property
    def method(self) -> str:
        """The direct solver for this model's size and dimension (fem.linalg.resolve; a complex
        K(omega) goes to PARDISO through its real equivalent, fem.linalg.factorize)."""
        return linalg.resolve("auto", self.M.shape[0], dim=self.sy.tm.mesh.dim())

    def kappa(self, omega) -> dict:
        """kind -> complex multiplier of K_kind at angular frequency omega (1: no loss)."""
        k = self.relax.kappa(omega)
        return {n: k.get(n, 1.0) for n in self.parts}

    def K(self, omega):
        """The complex dynamic stiffness at angular frequency omega."""
        kap = self.kappa(omega)
        Kw = sum(kap[n] * P for n, P in self.parts.items())
        return (Kw - omega ** 2 * self.M + 1j * omega * self.C_rayleigh()).tocsc()

    def C_rayleigh(self):
        """The viscous (Rayleigh) damping matrix alpha M + beta K_mech."""
        return self.alpha * self.M + self.beta * sum(P for n, P in self.parts.items() if mechanical(n))

    def K_unrelaxed(self):
        """sum_k kappa_k(inf) K_k: the instantaneous stiffness (fem.constitution)."""
        ku = self.relax.unrelaxed()
        return sum(ku.get(n, 1.0) * P for n, P in self.parts.items())

    def K_branch(self, j: int):
        """K^(j) = sum_k c_jk K_k of relaxation branch j."""
        c = self.relax.branch(j)
        return sum(c[n] * self.parts[n] for n in c)


def mechanical(kind):
    return kind.split(":")[0] in ("shear", "elastic")


def model(problem: Problem, short: bool = False) -> DynamicModel:
    """The dynamic model of a problem: electrodes open (the reference grounded), or
    with `short` every electrode grounded and their charges read from the
    (massless, undamped) potential rows: Q_k = -sum of row k of K x. A
    hyperelastic problem is linearised about its static state under its load."""
    sy = assemble(problem)
    if sy.tm.layout.planes:
        raise ValueError("dynamic models are solved on the full mesh; set model.symmetry = \"full\"")
    travel_force = None
    if problem.indenter is not None:     # linearise about the pressed state, the indenter holding it
        travel_force = _pressed(sy)
    elif problem.hyperelastic:        # linearise about the static Yeoh state under the load
        x0 = newton(sy)[0]
        for kind, Kt in yeoh_terms(sy, x0, by_kind=True)[1].items():
            sy.parts[kind] = sy.parts.get(kind, 0) + Kt
        sy.preload = x0
    states = sy.electrodes.states
    names = [k for k, st in states.items() if st != "reference"]
    if short:
        sy.electrodes.states = {k: ("reference" if st == "reference" else "ground") for k, st in states.items()}
    red = elimination(sy, eliminate_grounded=True)
    P = red.P
    dyn = problem.damping
    parts, losses = {}, {}
    for kind, A in sy.parts.items():
        parts[kind] = (P.T @ A @ P).tocsr()
        what, _, region = kind.partition(":")
        mat = sy.laws[region].material if region else None
        if what in ("shear", "volumetric"):          # volumetric: the compliance 1/K of the mixed form
            losses[kind] = (dyn.silicone_loss, what == "volumetric")
        elif what == "elastic":
            losses[kind] = (dyn.piezo_loss if dyn.piezo_loss is not None else (1 / mat.Qm if mat.Qm else 0.0), False)
        elif what == "dielectric":                   # enters with a minus sign: a compliance-like term
            losses[kind] = (dyn.dielectric_loss if dyn.dielectric_loss is not None else (mat.tan_delta or 0.0), True)
    relax = rx.relaxation_law(losses, dyn.loss_band)
    M = sp.csr_matrix(sy.A.shape)
    for region, ub in sy.ubases.items():
        Mr = asm(assembly.mass(sy.laws[region].material.rho, sy.kin), ub)
        M = M + _embed(Mr, sy.offsets["u"].start, sy.A.shape[0])
    charge_rows = None
    if short:
        edofs = sy.electrodes.dofs
        S = sp.csr_matrix((np.ones(sum(len(edofs[k]) for k in names)),
                           (np.repeat(np.arange(len(names)), [len(edofs[k]) for k in names]),
                            np.concatenate([edofs[k] for k in names]))), shape=(len(names), sy.A.shape[0]))
        charge_rows = -(S @ sy.A @ P).tocsr()
    F = P.T @ sy.b / sy.applied_force
    if travel_force is not None:         # per newton of static indenter force: / dF/dd of this tangent
        dF_dd, dF_du = travel_force
        v = P @ linalg.scaled_solver(sum(parts.values()).tocsc(), red.is_u,
                                     linalg.resolve("auto", red.n, dim=sy.tm.mesh.dim()))(F)[0][:, 0]
        F = F / (dF_dd + float(dF_du @ v))
    return DynamicModel(sy, red, parts, relax, (P.T @ M @ P).tocsr(), dyn.rayleigh_alpha,
                        dyn.rayleigh_beta, F, red.unit_charges(), names if short else list(red.active),
                        charge_rows)


def _pressed(sy: System):
    """Press to the indenter's travel or force; put the tangents at the pressed state
    into sy.parts and the indenter-motion load per unit travel into sy.b; return the
    force's derivatives (dF/dd at fixed u, dF/du full-size) for the per-newton scaling."""
    ind = sy.problem.indenter
    pr = Press(sy, ind)
    pr.travel(ind.travel) if ind.travel is not None else pr.force(ind.force)
    x0, n = pr.x, sy.A.shape[0]
    if sy.yeoh:
        for kind, Kt in yeoh_terms(sy, x0, by_kind=True)[1].items():
            sy.parts[kind] = sy.parts.get(kind, 0) + Kt
    st = pr.res.state
    S = pr.surf.dofs + sy.offsets["u"].start
    sy.parts["contact"] = pr.contact_tangent()
    dr, dF_dd, dF_du = pr.surf.travel_derivatives(st, pr.eps)
    sy.b = -np.bincount(S.ravel(), dr.ravel(), minlength=n)      # per unit travel
    sy.applied_force = 1.0
    sy.preload = x0
    return dF_dd, np.bincount(S.ravel(), dF_du.ravel(), minlength=n)


def _embed(M, offset, n):
    M = sp.coo_matrix(M)
    return sp.csr_matrix((M.data, (M.row + offset, M.col + offset)), shape=(n, n))
