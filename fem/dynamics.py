r"""The linear dynamic model of a problem: mass, stiffness by kind, loss factors.

Equation of motion on the reduced unknowns x of fem.constraints.reduction (supports
and the reference electrode eliminated; each other electrode one potential
whose row is its charge balance, right-hand side -Q_k):

    M x'' + C x' + K x = F f(t) + B_e Q(t)          (B_e: -1 at electrode row k)

M is the consistent mass of the displacements (pressure and potential carry
none), F the load of 1 N on the problem's footprint and f(t) the force in N. Damping:

* frequency domain, structural (loss factors, per material):
      K(w) = sum_parts kappa_part K_part,  kappa = 1 + i eta_s (silicone shear),
      1 / (1 + i eta_s) (silicone volumetric: the compliance of the mixed form),
      1 + i / Qm (piezo stiffness), 1 - i tan(delta) (permittivity), 1 (coupling);
      plus Rayleigh  i w (alpha M + beta K_mech);
* time domain: the same loss factors as viscous damping matched at the
  reference frequency, C = alpha M + sum_mech (beta + eta / w_ref) K_part.

With a Yeoh silicone the model is linearised about the static state under the
problem's load (the preload): K_part are then the consistent tangents at that
state (fem.newton.yeoh_terms), and responses are per newton of a small force
added on the same footprint.

Pressed by a rigid indenter (problem.indenter), the model is linearised about the
pressed state with the indenter holding it (fem.press): the Yeoh tangents (if any)
at that state plus the contact tangent K_c (kind "contact", no loss), and the
excitation is the indenter's own motion: a travel oscillation dd enters as the load
-dr/dd dd (fem.contact.Surface.travel_derivatives), scaled per newton of the static
force-travel stiffness dF/dd of the pressed state. So at zero frequency the
response is the slope of the static voltage-force curve, dV/dF
(tests/test_contact_scene.py checks it against two static presses).

Frequency responses: fem.sweep; transients: fem.timestep.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from skfem import asm

from taxel.fem import forms, linalg
from taxel.fem.assembly import System, assemble
from taxel.fem.constraints import Reduction, reduction
from taxel.fem.newton import newton, yeoh_terms
from taxel.fem.press import Press
from taxel.fem.problem import Problem


@dataclass
class DynamicModel:
    sy: System
    red: Reduction
    parts: dict          # kind -> reduced real sparse matrix
    kappa: dict          # kind -> complex loss factor multiplier
    viscous: dict        # kind -> time-domain stiffness-proportional damping coefficient (s)
    M: sp.csr_matrix
    alpha: float
    beta: float
    F: np.ndarray        # reduced load vector of 1 N of the problem's load
    Be: np.ndarray       # (n, na) unit-charge right-hand sides
    names: list[str]     # active electrodes (open model) or grounded ones (short model)
    charge_rows: sp.csr_matrix | None = None   # short model: Q = charge_rows @ x (massless rows)

    @property
    def K0(self):
        return sum(self.parts.values())

    def K(self, omega):
        """The complex dynamic stiffness at angular frequency omega."""
        Kw = sum(k * P for k, P in zip((self.kappa[n] for n in self.parts), self.parts.values()))
        mech = sum(P for n, P in self.parts.items() if mechanical(n))
        return (Kw - omega ** 2 * self.M + 1j * omega * (self.alpha * self.M + self.beta * mech)).tocsc()

    def C_time(self):
        """Viscous damping matrix for transients (loss factors matched at the reference frequency)."""
        out = self.alpha * self.M
        for n, P in self.parts.items():
            if mechanical(n):
                out = out + (self.beta + self.viscous[n]) * P
        return out


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
    red = reduction(sy, eliminate_grounded=True)
    P = red.P
    dyn = problem.damping
    w_ref = 2 * np.pi * dyn.reference_frequency
    parts, kappa, viscous = {}, {}, {}
    for kind, A in sy.parts.items():
        parts[kind] = (P.T @ A @ P).tocsr()
        what, _, region = kind.partition(":")
        mat = sy.laws[region].material if region else None
        eta = 0.0
        if what == "shear":
            eta = dyn.silicone_loss
        elif what == "volumetric":
            kappa[kind] = 1 / (1 + 1j * dyn.silicone_loss)
        elif what == "elastic":
            eta = dyn.piezo_loss if dyn.piezo_loss is not None else (1 / mat.Qm if mat.Qm else 0.0)
        elif what == "dielectric":
            tand = dyn.dielectric_loss if dyn.dielectric_loss is not None else (mat.tan_delta or 0.0)
            kappa[kind] = 1 - 1j * tand
        kappa.setdefault(kind, 1 + 1j * eta)
        viscous[kind] = eta / w_ref
    M = sp.csr_matrix(sy.A.shape)
    for region, ub in sy.ubases.items():
        Mr = asm(forms.mass(sy.laws[region].material.rho, sy.kin), ub)
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
    return DynamicModel(sy, red, parts, kappa, viscous, (P.T @ M @ P).tocsr(), dyn.rayleigh_alpha,
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
