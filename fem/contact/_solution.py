"""The final state of a press as a Solution, and the press's residual through scikit-fem's forms (the
reference path beside the vectorised one). The final state (fem.contact.Press.solution): the open-circuit
voltages of its equilibrium, and the capacitance and short-circuit charge linearised there.

At the converged state x the tangent K = A + K_yeoh + K_c (the press's own, with the stick set
of the final state) is factorized once more (Newton stops unfactorized) and solved for the
active electrodes' unit charges: the inverse capacitance. A half or quarter model is unfolded
to the full sensor's electrodes with the full (unreduced) tangent (fem.static.unfold_solution).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from taxel.fem import hyperelastic
from taxel.fem.assembly import place
from taxel.fem.hyperelastic import yeoh_terms, yeoh_terms_skfem
from taxel.fem.static import Solution, results, unfold_solution


def final_solution(pr) -> Solution:
    """The Solution of the press `pr`'s final state (voltages open circuit; capacitance and
    short-circuit charge linearised at it), with `.contact` its PressResult."""
    sy, red = pr.sy, pr.red
    x = pr.x
    r_y, _ = yeoh_terms(sy, x, with_tangent=False) if sy.yeoh else (0.0, None)
    r = sy.A @ x + r_y
    S = pr.surf.dofs.ravel() + sy.offsets["u"].start
    r += np.bincount(S, pr.surf.element_residual(pr.res.state).ravel(), minlength=len(r))
    pr._stick = pr._sticking()           # the tangent at the final state (Newton stops unfactorized)
    pr.refactor(pr._residual(x, pr.d, pr.lam)[3])
    pr._stick = None
    X, _ = pr.solver(red.unit_charges()) if red.active else (np.zeros((red.n, 0)), None)
    Cinv = X[red.nf:, :] if red.active else np.zeros((0, 0))
    sol = results(sy, red, x, r, Cinv, pr.method, pr.o.tol)
    if sy.tm.layout.planes:            # the full sensor's electrodes, linearised at the pressed state
        sol = unfold_solution(sy, sol, red, Cinv, pr.method, K=full_tangent(pr))
    sol = dataclasses.replace(sol, applied_force=pr.res.points[-1].force)
    sol.contact = pr.res
    return sol


def full_tangent(pr):
    """The full (unreduced) tangent of the press `pr` at its current state: A + K_yeoh + K_c."""
    sy = pr.sy
    return (sy.A + (yeoh_terms(sy, pr.x)[1] if sy.yeoh else 0) + pr.contact_tangent()).tocsr()


def residual_skfem(pr, x, d, lam, tangent=True, frozen=None, fixed=None):
    """The press `pr`'s residual and tangent (Press._residual's tuple) through scikit-fem's forms
    and sparse products: the reference path beside the vectorised one (Options(assembly="skfem");
    benchmarks/contact_speed.py compares the two)."""
    sy, P = pr.sy, pr.red.P
    if pr._stick is not None:
        raise ValueError("sticking contact is assembled by the vectorised path only")
    u = x[sy.offsets["u"]]
    r_y, K_y = yeoh_terms_skfem(sy, x, with_tangent=tangent) if sy.yeoh else (0.0, 0.0)
    pr._min_J = min((hyperelastic.min_jacobian(sy.ubases[r], u, sy.kin) for r in sy.yeoh), default=1.0)
    st = pr.surf.state(u, pr.ind, d, lam, pr.eps, with_curvature=tangent, fixed=fixed)
    rc = np.zeros_like(x)
    rc[sy.offsets["u"]] = pr.surf.residual(st)
    r = P.T @ (sy.A @ x + r_y + rc)
    ref = P.T @ rc
    if not tangent:
        return r, ref, st, None
    Kc_full = place([("u", "u", pr.surf.tangent(st, pr.eps, frozen))], sy.offsets, sy.A.shape[0])
    K = (P.T @ (sy.A + K_y + Kc_full) @ P).tocsc()
    return r, ref, st, K
