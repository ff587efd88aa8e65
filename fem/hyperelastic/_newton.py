"""Newton's method for the coupled Yeoh-silicone / linear-piezo system, with line
search and adaptive load stepping, that says where and why it stopped.

Residual at load factor lam (fem.hyperelastic for the Yeoh part):

    r(x, lam) = A_lin x + R_yeoh(x) - lam b,     tangent K(x) = A_lin + K_yeoh(x)

on the eliminated unknowns of fem.assembly.elimination (supports and grounded
electrodes eliminated; each open electrode one potential with zero net charge).

Each Newton step solves K dy = -r with the scaled direct solver, then backtracks
(alpha = 1, 1/2, ... 1/64) until the scaled residual norm decreases and no
element inverts (J > 0 at every quadrature point). Convergence: scaled relative
residual |D r| / |D lam b| below `tol`. Load stepping: start at `first_step`;
after a converged step grow the increment by 1.5 when it took at most 4
iterations; after a failed one return to the last converged state and halve it;
below `min_step` stop with a message that names the last converged load.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from . import _reference_forms as hyperelastic
from taxel.fem import linalg
from taxel.fem.assembly import System, place
from taxel.fem.assembly import Elimination, elimination
from taxel.fem.static import Solution, results
from taxel.fem.constitution import PlaneStress
from ._plane_stress import PlaneStressYeohRegion
from ._terms import YeohRegion


class NewtonError(RuntimeError):
    """Newton failed; the message names the last converged load, `.result` has the history,
    `.solution` the Solution at the last converged load (solve_yeoh; None before one)."""

    def __init__(self, message, result=None):
        super().__init__(message)
        self.result = result
        self.solution: Solution | None = None


@dataclass
class NewtonResult:
    converged: bool
    load_factors: list[float] = field(default_factory=list)    # converged load factors, in order
    iterations: list[int] = field(default_factory=list)        # Newton iterations per converged step
    residuals: list[list[float]] = field(default_factory=list)  # scaled relative residual, per iteration
    cutbacks: int = 0
    message: str = ""
    failed: list[tuple[float, list[float]]] = field(default_factory=list)   # (load factor, residuals)
    x: np.ndarray | None = field(default=None, repr=False)    # the state at the last converged load factor

    @property
    def total_iterations(self):
        return sum(self.iterations)


def yeoh_regions(sy: System) -> dict:
    """The vectorised Yeoh regions of a system (fem.hyperelastic; plane stress:
    fem.hyperelastic), built once and kept on it."""
    if getattr(sy, "_yeoh_regions", None) is None:
        kind = PlaneStressYeohRegion if isinstance(sy.kin, PlaneStress) else YeohRegion   # lambda3 condensed
        sy._yeoh_regions = {r: kind(sy.ubases[r], sy.pbases[r], law, sy.kin, sy.offsets[("p", r)].start)
                            for r, law in sy.yeoh.items()}
    return sy._yeoh_regions


def yeoh_terms(sy: System, x: np.ndarray, with_tangent=True, by_kind=False):
    """Full-size residual R_yeoh(x) and tangent K_yeoh(x) of every hyperelastic region
    (with `by_kind`, the tangent as {"shear:<region>", "constraint", "volumetric:<region>"},
    the kinds of fem.assembly, so that loss factors apply to it). Vectorised
    (fem.hyperelastic); `yeoh_terms_skfem` is the same through scikit-fem's forms."""
    n = sy.A.shape[0]
    r = np.zeros(n)
    parts: dict[str, sp.csr_matrix] = {}
    for region, reg in yeoh_regions(sy).items():
        t = reg.terms(x, with_tangent)
        r += np.bincount(reg.udofs.ravel(), t.r_u.ravel(), minlength=n)
        r += np.bincount(reg.pdofs.ravel(), t.r_p.ravel(), minlength=n)
        if not with_tangent:
            continue
        U, Q = reg.udofs, reg.pdofs
        parts[f"shear:{region}"] = scatter(U, U, t.K_uu, n)
        Kup = scatter(U, Q, t.K_up, n)
        parts["constraint"] = parts.get("constraint", 0) + Kup + Kup.T
        parts[f"volumetric:{region}"] = scatter(Q, Q, t.K_pp, n)
    if not with_tangent:
        return r, None
    return r, (parts if by_kind else sum(parts.values()))


def scatter(rows, cols, K, n):
    """An n x n CSR matrix from element matrices K (elements, local, local) at full rows
    and columns (elements, local); duplicates summed."""
    R = np.broadcast_to(rows[:, :, None], K.shape)
    C = np.broadcast_to(cols[:, None, :], K.shape)
    return sp.csr_matrix((K.ravel(), (R.ravel(), C.ravel())), shape=(n, n))


def yeoh_terms_skfem(sy: System, x: np.ndarray, with_tangent=True):
    """`yeoh_terms` through scikit-fem's forms (fem.hyperelastic): the reference the
    vectorised path is checked against (tests/test_hyperelastic.py)."""
    n = sy.A.shape[0]
    kin = sy.kin
    r = np.zeros(n)
    blocks = []
    u = x[sy.offsets["u"]]
    for region, law in sy.yeoh.items():
        ub, pb, pk = sy.ubases[region], sy.pbases[region], ("p", region)
        st = hyperelastic.state(ub, pb, u, x[sy.offsets[pk]], law, kin, with_tangent)
        r_u, r_p = hyperelastic.residual(ub, pb, st, law, kin)
        r[sy.offsets["u"]] += r_u
        r[sy.offsets[pk]] += r_p
        if with_tangent:
            Kuu, Kup, Kpp = hyperelastic.tangent_blocks(ub, pb, st, law, kin)
            blocks += [("u", "u", Kuu), ("u", pk, Kup), (pk, "u", Kup.T), (pk, pk, Kpp)]
    return r, (place(blocks, sy.offsets, n) if with_tangent else None)


def _min_jacobian(sy: System, x):
    return min(reg.terms(x, with_tangent=False).min_J for reg in yeoh_regions(sy).values())


def newton(sy: System, method="auto", *, tol=1e-10, max_iter=15, first_step=1.0, min_step=1e-2,
           stepping=True, line_search=True, red: Elimination | None = None):
    """Solve r(x, 1) = 0. Returns (x, NewtonResult, elimination, last scaled solver).

    Raises NewtonError when the load cannot be reached (with stepping off: at the
    first failure).
    """
    red = red or elimination(sy, eliminate_grounded=True)
    method = linalg.resolve(method, red.n, dim=sy.tm.mesh.dim())     # PARDISO for 3D sizes
    P = red.P
    b = P.T @ sy.b
    A_lin = sy.A
    x = np.zeros(sy.A.shape[0])
    res = NewtonResult(False)
    lam, step = 0.0, min(first_step, 1.0)
    solver = None

    def eliminated_residual(x, lam):
        r_y, _ = yeoh_terms(sy, x, with_tangent=False)
        return P.T @ (A_lin @ x + r_y) - lam * b

    while lam < 1.0 - 1e-12:
        target = min(1.0, lam + step)
        x_try, history, ok = x.copy(), [], False
        for it in range(max_iter):
            r_y, K_y = yeoh_terms(sy, x_try)
            r = P.T @ (A_lin @ x_try + r_y) - target * b
            K = (P.T @ (A_lin + K_y) @ P).tocsc()
            solver = linalg.scaled_solver(K, red.is_u, method)
            D = solver.D
            norm = np.linalg.norm(D * r) / max(np.linalg.norm(D * target * b), 1e-300)
            history.append(float(norm))
            if not np.isfinite(norm):
                break
            if norm < tol:
                ok = True
                break
            dy, _ = solver(-r)
            dy = dy[:, 0]
            alpha = 1.0
            while True:
                x_new = x_try + alpha * (P @ dy)
                if _min_jacobian(sy, x_new) > 0:
                    r_new = eliminated_residual(x_new, target)
                    new = np.linalg.norm(D * r_new) / max(np.linalg.norm(D * target * b), 1e-300)
                    if not line_search or new < (1 - 1e-4 * alpha) * norm or alpha <= 1 / 64:
                        break
                elif not line_search or alpha <= 1 / 64:
                    x_new = None
                    break
                alpha /= 2
            if x_new is None:
                break
            x_try = x_new
        if ok:
            x, lam = x_try, target
            res.load_factors.append(lam)
            res.iterations.append(len(history) - 1)
            res.residuals.append(history)
            if stepping and len(history) - 1 <= 4:
                step *= 1.5
            continue
        res.failed.append((target, history))
        if not stepping or step / 2 < min_step:
            last = res.load_factors[-1] if res.load_factors else 0.0
            res.message = (f"Newton did not converge at load factor {target:.4g} (last converged {last:.4g}, "
                           f"i.e. {last * sy.applied_force:.4g} N of {sy.applied_force:.4g} N): a pressure "
                           "patch on soft silicone folds the free surface at its edge at a few C10 "
                           "of pressure (a crease a load without contact cannot follow); lower "
                           "the force, or check the Yeoh set is stable at this strain")
            res.x = x
            raise NewtonError(res.message, res)
        res.cutbacks += 1
        step /= 2
    res.converged = True
    res.message = f"converged in {len(res.load_factors)} load steps, {res.total_iterations} iterations"
    return x, res, red, solver


def solve_yeoh(sy: System, method="auto", **kw) -> Solution:
    """The Solution of a hyperelastic scene (voltages open circuit, charges of
    grounded electrodes; capacitance and short-circuit charge linearised at the
    final state, where the piezo is linear and the silicone's tangent is used). Where Newton
    stops short, the NewtonError carries the Solution at its last converged load factor."""
    red = kw.pop("red", None) or elimination(sy, eliminate_grounded=True)
    try:
        x, nres, red, solver = newton(sy, method, red=red, **kw)
    except NewtonError as exc:
        nres = exc.result
        if nres is not None and nres.load_factors:
            lam = nres.load_factors[-1]
            K = (red.P.T @ (sy.A + yeoh_terms(sy, nres.x)[1]) @ red.P).tocsc()
            solver = linalg.scaled_solver(K, red.is_u, linalg.resolve(method, red.n, dim=sy.tm.mesh.dim()))
            exc.solution = _solution(sy, nres.x, lam, red, solver, method, nres)
        raise
    return _solution(sy, x, 1.0, red, solver, method, nres)


def _solution(sy, x, lam, red, solver, method, nres) -> Solution:
    """The Solution of the state x at load factor lam, with the scaled solver of its tangent."""
    r_y, _ = yeoh_terms(sy, x, with_tangent=False)
    r = sy.A @ x + r_y - lam * sy.b
    X, resid = solver(red.unit_charges()) if red.active else (np.zeros((red.n, 0)), np.zeros(1))
    Cinv = X[red.nf:, :] if red.active else np.zeros((0, 0))
    sol = results(sy, red, x, r, Cinv, linalg.resolve(method, red.n, dim=sy.tm.mesh.dim()), nres.residuals[-1][-1])
    if lam != 1.0:
        sol = dataclasses.replace(sol, applied_force=lam * sy.applied_force)
    sol.newton = nres
    return sol
