r"""Transients: Newmark on the reduced model, or full-order Newmark-Newton for Yeoh.

Linear: the Krylov-reduced model (fem.sweep.krylov, shifts 0 and half the
Nyquist frequency) with its massless pressure and potential directions condensed
exactly (`condense`), then Newmark average acceleration, optionally with a
resistor on every electrode coupled in as charge states. The force history is
in newtons (the model's load vector is per newton).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

import numpy as np
import scipy.linalg as la

from taxel.fem import linalg
from taxel.fem.assembly import assemble
from taxel.fem.constraints import reduction
from taxel.fem.dynamics import DynamicModel, model
from taxel.fem.problem import Problem
from taxel.fem.sweep import krylov, project



def newmark(M, C, K, F, f, dt, q0=None, coupling=None):
    """Newmark average acceleration (gamma = 1/2, beta = 1/4): implicit,
    unconditionally stable for M > 0, K >= 0, second order, no numerical damping.

    Dense matrices (a reduced, condensed model): M q'' + C q' + K q = F f(t) + B Q.
    coupling = (B, Gz, gf, gQ, R): charge states Q of resistive electrodes with
    Q' = -V / R, V = Gz q + gf f + gQ Q, trapezoidal in time like Newmark (so the
    pair is solved together each step). Returns q (nt, n), Q (nt, na).
    """
    n, nt = K.shape[0], len(f)
    a1, a2, a4 = 4 / dt ** 2, 4 / dt, 2 / dt
    Keff = K + a4 * C + a1 * M
    if coupling is None:
        coupling = (np.zeros((n, 0)), np.zeros((0, n)), np.zeros(0), np.zeros((0, 0)), 1.0)
    B, Gz, gf, gQ, R = coupling
    na, h = B.shape[1], dt / (2 * R)
    lu = la.lu_factor(np.block([[Keff, -B], [h * Gz, np.eye(na) + h * gQ]]))
    q = np.zeros((nt, n))
    Q = np.zeros((nt, na))
    q[0] = 0.0 if q0 is None else q0
    v = np.zeros(n)
    a = np.linalg.solve(M, F * f[0] + B @ Q[0] - K @ q[0] - C @ v) if n else v
    for k in range(nt - 1):
        V_k = Gz @ q[k] + gf * f[k] + gQ @ Q[k]
        rhs = np.concatenate([F * f[k + 1] + M @ (a1 * q[k] + a2 * v + a) + C @ (a4 * q[k] + v),
                              Q[k] - h * V_k - h * gf * f[k + 1]])
        sol = la.lu_solve(lu, rhs)
        q[k + 1], Q[k + 1] = sol[:n], sol[n:]
        a_new = a1 * (q[k + 1] - q[k]) - a2 * v - a
        v = v + dt * 0.5 * (a + a_new)
        a = a_new
    return q, Q


def condense(r, C):
    """Split the reduced model into its displacement columns (mass) and its
    pressure/potential columns (no mass, no damping: algebraic) and condense the
    latter statically. Returns the matrices of the dynamic part and the maps
    back: q = Tq z + tf f + tQ Q."""
    d = r["u_cols"]
    eye = np.eye(len(d))
    Ud, Ua = eye[:, d], eye[:, ~d]
    K = sum(P for P in r["parts"].values())
    F, Be = r["B"][:, 0], r["B"][:, 1:]
    Kaa = Ua.T @ K @ Ua
    X = np.linalg.solve(Kaa, np.column_stack([Ua.T @ K @ Ud, Ua.T @ F, Ua.T @ Be])) if Ua.shape[1] \
        else np.zeros((0, d.sum() + 1 + Be.shape[1]))
    nd = d.sum()
    XK, XF, XB = X[:, :nd], X[:, nd], X[:, nd + 1:]
    Kda = Ud.T @ K @ Ua
    return dict(M=Ud.T @ r["M"] @ Ud, C=Ud.T @ C @ Ud, K=Ud.T @ K @ Ud - Kda @ XK,
                F=Ud.T @ F - Kda @ XF, B=Ud.T @ Be - Kda @ XB,
                Tq=Ud - Ua @ XK, tf=Ua @ XF, tQ=Ua @ XB)


def transient_hyperelastic(problem: Problem, t: np.ndarray, force: np.ndarray, tol=1e-9, max_iter=12):
    """Full-order Newmark (average acceleration) with Newton at every step for a
    Yeoh silicone, open-circuit electrodes. Residual at step n+1:

        G(x) = M a(x) + C v(x) + R(x) - F(t_{n+1}) / F_0 b,   a = 4/dt^2 (x - x_n) - 4/dt v_n - a_n,
        v = 2/dt (x - x_n) - v_n,   R(x) = A_lin x + R_yeoh(x)   (dead load: b of force F_0)

    Jacobian 4/dt^2 M + 2/dt C + K_t(x). M and C act on displacements only, so the
    massless pressure and potential stay algebraic. C: the loss factors as viscous
    damping at the reference frequency, on the small-strain tangent. The tangent
    is refactorized at every iteration (full Newton)."""
    from taxel.fem.newton import NewtonError, yeoh_terms
    t0 = time.perf_counter()
    dm = model(replace(problem, hyperelastic=False))
    sy = assemble(replace(problem, hyperelastic=True))
    load = force / sy.applied_force
    red = reduction(sy, eliminate_grounded=True)
    P = red.P
    M, C = dm.M, dm.C_time()
    A_lin, b = sy.A, P.T @ sy.b
    dt = t[1] - t[0]
    a1, a2 = 4 / dt ** 2, 2 / dt
    n = red.n
    y, v, a = np.zeros(n), np.zeros(n), np.zeros(n)
    V = np.zeros((len(t), len(red.active)))
    iters = []
    for k in range(1, len(t)):
        y_new = y + dt * v
        for it in range(max_iter):
            xf = P @ y_new
            r_y, K_y = yeoh_terms(sy, xf)
            acc = a1 * (y_new - y) - a1 * dt * v - a
            vel = a2 * (y_new - y) - v
            G = M @ acc + C @ vel + P.T @ (A_lin @ xf + r_y) - load[k] * b
            J = (a1 * M + a2 * C + P.T @ (A_lin + K_y) @ P).tocsc()
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
        a, y = a_new, y_new
        V[k] = y[red.nf:]
    return Transient(t, force, V, np.zeros_like(V), list(red.active), n,
                     time.perf_counter() - t0), iters


def critical_time_step(dm: DynamicModel) -> float:
    """dt_crit = 2 / omega_max of explicit central differences for a (small) model:
    pressure and potential condensed exactly, dense generalized eigenvalues."""
    K, M = dm.K0.toarray(), dm.M.toarray()
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
    """Response to a force history (newtons at times t, uniform step). R: a resistor from every active electrode to ground (None:
    open circuit). Reduced model: Krylov basis at shift 0 plus one at half the
    Nyquist frequency; the massless pressure and potential directions condensed
    statically (`condense`), then Newmark."""
    t0 = time.perf_counter()
    dt = t[1] - t[0]
    if basis is None:
        f_top = 0.25 / dt                          # half the Nyquist frequency
        basis = krylov(dm, [0.0, 2 * np.pi * f_top], moments)
    r = project(dm, basis)
    c = condense(r, basis.T @ (dm.C_time() @ basis))
    E = r["E"]                                        # electrode potentials: V = E q
    coupling = None
    if R is not None and E.shape[0]:
        coupling = (c["B"], E @ c["Tq"], E @ c["tf"], E @ c["tQ"], R)
    z0 = np.linalg.solve(c["K"], c["F"] * force[0])
    z, Q = newmark(c["M"], c["C"], c["K"], c["F"], force, dt, q0=z0, coupling=coupling)
    q = z @ c["Tq"].T + np.outer(force, c["tf"])
    if Q.shape[1]:
        q += Q @ c["tQ"].T
    else:
        Q = np.zeros((len(t), E.shape[0]))
    if dm.charge_rows is not None:              # short circuit: V = 0, charges from the rows
        Q = q @ (dm.charge_rows @ basis).T
        V = np.zeros_like(Q)
    else:
        V = q @ r["E"].T
    return Transient(t, force, V, Q, dm.names, basis.shape[1], time.perf_counter() - t0)
