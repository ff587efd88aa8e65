r"""Transients: Newmark on the reduced model, or full-order Newmark-Newton for Yeoh.

Linear: the Krylov-reduced model (fem.dynamics.krylov, shifts 0 and half the
Nyquist frequency), then Newmark average acceleration, optionally with a
resistor on every electrode coupled in as charge states. The massless pressure
and potential rows are algebraic: Newmark enforces them at every step (their
mass and damping rows are zero, so their velocities never feed back). The
material losses follow fem.constitution's causal law, the same as the frequency
analysis: M q'' + C q' + K_u q - sum_j K^(j) s_j = F f + B Q, tau_j s_j' = q - s_j,
the internal variables s_j by the trapezoidal rule like Newmark (second order,
unconditionally stable). The force history is in newtons (the model's load
vector is per newton); the record starts at rest under force[0] (relaxed:
s_j = q).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

import numpy as np
import scipy.linalg as la

from taxel.fem import linalg
from taxel.fem.assembly import assemble
from taxel.fem.assembly import elimination
from ._model import DynamicModel, model
from taxel.fem.assembly import Problem
from ._sweep import krylov, project



def relaxation_weights(tau, dt):
    """(alpha_j, beta_j) of the trapezoidal internal-variable step
    s_j[k+1] = alpha_j s_j[k] + beta_j (q[k+1] + q[k])."""
    h = dt / (2 * np.asarray(tau, float))
    return (1 - h) / (1 + h), h / (1 + h)


def newmark(M, C, K, F, f, dt, q0=None, coupling=None, relax=None):
    """Newmark average acceleration (gamma = 1/2, beta = 1/4): implicit,
    unconditionally stable for M >= 0, K >= 0, second order, no numerical damping.

    Dense matrices (a reduced model): M q'' + C q' + K q - sum_j K_j s_j = F f(t) + B Q,
    relax = (K_j list, tau): internal variables tau_j s_j' = q - s_j, trapezoidal
    (K is then the unrelaxed stiffness). Rows without mass or damping are algebraic.
    coupling = (B, E, R): charge states Q of resistive electrodes with Q' = -V / R,
    V = E q, trapezoidal in time like Newmark (so the pair is solved together each
    step). Starts at rest at q0 (relaxed: s_j = q0), accelerated by any imbalance of
    F f[0] there (zero when q0 is static under f[0]).
    Returns q (nt, n), Q (nt, na).
    """
    n, nt = K.shape[0], len(f)
    a1, a2, a4 = 4 / dt ** 2, 4 / dt, 2 / dt
    Kj, tau = relax if relax is not None else ([], np.zeros(0))
    al, be = relaxation_weights(tau, dt)
    Keff = K + a4 * C + a1 * M - sum(b * Kb for b, Kb in zip(be, Kj))
    if coupling is None:
        coupling = (np.zeros((n, 0)), np.zeros((0, n)), 1.0)
    B, E, R = coupling
    na, h = B.shape[1], dt / (2 * R)
    lu = la.lu_factor(np.block([[Keff, -B], [h * E, np.eye(na)]]))
    q = np.zeros((nt, n))
    Q = np.zeros((nt, na))
    q[0] = 0.0 if q0 is None else q0
    v, a = np.zeros(n), np.zeros(n)
    S = [q[0].copy() for _ in Kj]
    heavy = np.abs(M).sum(axis=1) > 0                  # rows with mass; the others are algebraic
    K0 = K - sum(Kj) if Kj else K
    if heavy.any():                                     # a0 from the equation of motion at t = 0
        a[heavy] = np.linalg.solve(M[np.ix_(heavy, heavy)], (F * f[0] - K0 @ q[0])[heavy])
    for k in range(nt - 1):
        hist = sum((Kb @ (al_ * s + be_ * q[k]) for Kb, al_, be_, s in zip(Kj, al, be, S)), np.zeros(n))
        rhs = np.concatenate([F * f[k + 1] + M @ (a1 * q[k] + a2 * v + a) + C @ (a4 * q[k] + v) + hist,
                              Q[k] - h * (E @ q[k])])
        sol = la.lu_solve(lu, rhs)
        q[k + 1], Q[k + 1] = sol[:n], sol[n:]
        S = [al_ * s + be_ * (q[k + 1] + q[k]) for al_, be_, s in zip(al, be, S)]
        a_new = a1 * (q[k + 1] - q[k]) - a2 * v - a
        v = v + dt * 0.5 * (a + a_new)
        a = a_new
    return q, Q


def transient_hyperelastic(problem: Problem, t: np.ndarray, force: np.ndarray, tol=1e-9, max_iter=12):
    """Full-order Newmark (average acceleration) with Newton at every step for a
    Yeoh silicone, open-circuit electrodes. Residual at step n+1:

        G(x) = M a(x) + C v(x) + R(x) - F(t_{n+1}) / F_0 b,   a = 4/dt^2 (x - x_n) - 4/dt v_n - a_n,
        v = 2/dt (x - x_n) - v_n,   R(x) = A_lin x + R_yeoh(x)   (dead load: b of force F_0)

    Jacobian 4/dt^2 M + 2/dt C + K_t(x). M and C act on displacements only, so the
    massless pressure and potential stay algebraic. Losses: the causal law of
    fem.constitution on the small-strain parts, + sum_j K^(j) (x - s_j) with the
    internal variables stepped by the trapezoidal rule (as `newmark`); C the
    Rayleigh damping. The tangent is refactorized at every iteration (full Newton)."""
    from taxel.fem.hyperelastic import NewtonError, yeoh_terms
    t0 = time.perf_counter()
    dm = model(replace(problem, hyperelastic=False))
    sy = assemble(replace(problem, hyperelastic=True))
    load = force / sy.applied_force
    red = elimination(sy, eliminate_grounded=True)
    P = red.P
    M, C = dm.M, dm.C_rayleigh()
    Kj = [dm.K_branch(j) for j in range(dm.relax.n)]
    al, be = relaxation_weights(dm.relax.tau, t[1] - t[0])
    Krel = sum((1 - b_) * K for b_, K in zip(be, Kj)) if Kj else 0 * M
    A_lin, b = sy.A, P.T @ sy.b
    dt = t[1] - t[0]
    a1, a2 = 4 / dt ** 2, 2 / dt
    n = red.n
    y, v, a = np.zeros(n), np.zeros(n), np.zeros(n)
    S = [np.zeros(n) for _ in Kj]                   # internal variables (from rest, unloaded)
    V = np.zeros((len(t), len(red.active)))
    iters = []
    for k in range(1, len(t)):
        y_new = y + dt * v
        for it in range(max_iter):
            xf = P @ y_new
            r_y, K_y = yeoh_terms(sy, xf)
            acc = a1 * (y_new - y) - a1 * dt * v - a
            vel = a2 * (y_new - y) - v
            G = M @ acc + C @ vel + P.T @ (A_lin @ xf + r_y) - load[k] * b \
                + sum((K @ (y_new - al_ * s - be_ * (y_new + y)) for K, al_, be_, s in zip(Kj, al, be, S)), 0 * y)
            J = (a1 * M + a2 * C + P.T @ (A_lin + K_y) @ P + Krel).tocsc()
            solve = linalg.scaled_solver(J, red.is_u, linalg.resolve("auto", n, dim=sy.tm.mesh.dim()))
            norm = np.linalg.norm(solve.D * G) / max(np.linalg.norm(solve.D * b), 1e-300)
            if norm < tol:
                break
            y_new = y_new - solve(G)[0][:, 0]
        else:
            raise NewtonError(f"Newton did not converge at t = {t[k]:.4g} s (step {k}); "
                              "reduce analysis.dt or the force")
        iters.append(it)
        a_new = a1 * (y_new - y) - a1 * dt * v - a
        v = a2 * (y_new - y) - v
        S = [al_ * s + be_ * (y_new + y) for al_, be_, s in zip(al, be, S)]
        a, y = a_new, y_new
        V[k] = y[red.nf:]
    return Transient(t, force, V, np.zeros_like(V), list(red.active), n,
                     time.perf_counter() - t0), iters


def critical_time_step(dm: DynamicModel) -> float:
    """dt_crit = 2 / omega_max of explicit central differences for a (small) model:
    pressure and potential condensed exactly, dense generalized eigenvalues, with
    the unrelaxed (instantaneous) stiffness."""
    K, M = dm.K_unrelaxed().toarray(), dm.M.toarray()
    u = dm.red.is_u
    Kc = K[np.ix_(u, u)] - K[np.ix_(u, ~u)] @ np.linalg.solve(K[np.ix_(~u, ~u)], K[np.ix_(~u, u)])
    return float(2 / np.sqrt(la.eigvalsh(Kc, M[np.ix_(u, u)]).max()))


def central_difference(M, K, rhs, dt, n_steps):
    """Explicit central difference (conditionally stable: dt < 2 / omega_max)."""
    Minv = np.linalg.inv(M)
    q = np.zeros((n_steps + 1, K.shape[0]))
    for k in range(1, n_steps):
        q[k + 1] = 2 * q[k] - q[k - 1] + dt ** 2 * (Minv @ (rhs(k) - K @ q[k]))
    return q


@dataclass
class Transient:
    t: np.ndarray
    force: np.ndarray            # N
    V: np.ndarray                # (nt, na) electrode voltages (open or resistive readout)
    Q: np.ndarray                # (nt, na) electrode charges
    names: list[str]
    basis_size: int
    seconds: float


def transient(dm: DynamicModel, t: np.ndarray, force: np.ndarray, R: float | None = None,
              basis=None, moments: int = 8) -> Transient:
    """Response to a force history (newtons at times t, uniform step). R: a resistor
    from every active electrode to ground (None: open circuit). Reduced model:
    Krylov basis at shift 0 plus one at half the Nyquist frequency, then `newmark`
    with the internal variables of the loss law (module docstring)."""
    t0 = time.perf_counter()
    dt = t[1] - t[0]
    if basis is None:
        f_top = 0.25 / dt                          # half the Nyquist frequency
        basis = krylov(dm, [0.0, 2 * np.pi * f_top], moments)
    r = project(dm, basis)
    F = r["B"][:, 0]
    E = r["E"]                                        # electrode potentials: V = E q
    K0 = sum(r["parts"].values())
    ku = dm.relax.unrelaxed()
    Ku = sum(ku.get(k, 1.0) * P for k, P in r["parts"].items())
    Kj = [sum(c * r["parts"][k] for k, c in dm.relax.branch(j).items()) for j in range(dm.relax.n)]
    C = dm.alpha * r["M"] + dm.beta * r["mech"]
    coupling = (r["B"][:, 1:], E, R) if R is not None and E.shape[0] else None
    q0 = np.linalg.solve(K0, F * force[0])              # static (relaxed) under force[0]
    q, Q = newmark(r["M"], C, Ku, F, force, dt, q0=q0, coupling=coupling, relax=(Kj, dm.relax.tau))
    if not Q.shape[1]:
        Q = np.zeros((len(t), E.shape[0]))
    if dm.charge_rows is not None:              # short circuit: V = 0, charges from the rows
        Q = q @ (dm.charge_rows @ basis).T
        V = np.zeros_like(Q)
    else:
        V = q @ E.T
    return Transient(t, force, V, Q, dm.names, basis.shape[1], time.perf_counter() - t0)
