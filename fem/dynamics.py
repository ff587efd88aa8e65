r"""Linear dynamics of a scene: frequency response and transients at the electrodes.

Equation of motion on the reduced unknowns x of fem.solve.reduction (supports
and the reference electrode eliminated; each other electrode one potential
whose row is its charge balance, right-hand side -Q_k):

    M x'' + C x' + K x = F f(t) + B_e Q(t)          (B_e: -1 at electrode row k)

M is the consistent mass of the displacements (pressure and potential carry
none), f(t) the load history scaling the scene's force. Damping:

* frequency domain, structural (loss factors, per material):
      K(w) = sum_parts kappa_part K_part,  kappa = 1 + i eta_s (silicone shear),
      1 / (1 + i eta_s) (silicone volumetric: the compliance of the mixed form),
      1 + i / Qm (piezo stiffness), 1 - i tan(delta) (permittivity), 1 (coupling);
      plus Rayleigh  i w (alpha M + beta K_mech);
* time domain: the same loss factors as viscous damping matched at the
  reference frequency, C = alpha M + sum_mech (beta + eta / w_ref) K_part.

With a Yeoh silicone the model is linearised about the static state under the
scene's force (the preload): K_part are then the consistent tangents at that
state (fem.newton.yeoh_terms), and responses are per newton of a small force
added on the same footprint.

Port quantities. For open electrodes (Q = 0) the solution gives the
open-circuit voltages V_oc(w); unit charges give C(w)^-1. Any linear circuit
on the electrodes then follows exactly from the port relation
Q = Q_sc + C V with Q_sc = -C V_oc (fem.circuits).

Cheap sweeps. `sweep(..., method="reduced")` projects the system on a block
Krylov basis {A_s^-1 B, A_s^-1 M A_s^-1 B, ...}, A_s = K0 - s^2 M at real shifts s
(0 first), B = [F, B_e], each block also multiplied by A_s^-1 Im K (the loss
factors): moment matching of the transfer function. The reduced
answer is compared with direct solves at check frequencies (the highest and
the middle one); the basis grows (a new shift at the worst check frequency)
until the relative error of V_oc and C^-1 is below the tolerance, which the
result reports.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
from skfem import asm

from fem import forms, linsolve, materials
from fem.solve import Reduction, System, _scaling, assemble, reduction, scaled_solver
from meshing.build import TaggedMesh, build
from meshing.layout import layout
from studies.scene import Scene, user_materials


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
    F: np.ndarray        # reduced load vector of the scene's force (f = 1)
    Be: np.ndarray       # (n, na) unit-charge right-hand sides
    names: list[str]     # active electrodes (open model) or grounded ones (short model)
    charge_rows: sp.csr_matrix | None = None   # short model: Q = charge_rows @ x (massless rows)

    @property
    def K0(self):
        return sum(self.parts.values())

    def K(self, omega):
        """The complex dynamic stiffness at angular frequency omega."""
        Kw = sum(k * P for k, P in zip((self.kappa[n] for n in self.parts), self.parts.values()))
        mech = sum(P for n, P in self.parts.items() if _mechanical(n))
        return (Kw - omega ** 2 * self.M + 1j * omega * (self.alpha * self.M + self.beta * mech)).tocsc()

    def C_time(self):
        """Viscous damping matrix for transients (loss factors matched at the reference frequency)."""
        out = self.alpha * self.M
        for n, P in self.parts.items():
            if _mechanical(n):
                out = out + (self.beta + self.viscous[n]) * P
        return out


def _mechanical(kind):
    return kind.split(":")[0] in ("shear", "elastic")


def model(scene: Scene, tm: TaggedMesh | None = None, short: bool = False) -> DynamicModel:
    """The dynamic model of a scene: electrodes open (the reference grounded), or
    with `short` every electrode grounded and their charges read from the
    (massless, undamped) potential rows: Q_k = -sum of row k of K x."""
    user = user_materials(scene)
    tm = tm or build(layout(scene), user)
    hyper = scene.model.silicone == "yeoh"
    sy = assemble(scene, tm, user, hyperelastic=hyper)
    if hyper:                       # linearise about the static Yeoh state under the scene's force
        from fem.newton import newton, yeoh_terms
        x0 = newton(sy)[0]
        for kind, Kt in yeoh_terms(sy, x0, by_kind=True)[1].items():
            sy.parts[kind] = sy.parts.get(kind, 0) + Kt
        sy.preload = x0
    names = [k for k, st in sy.states.items() if st != "reference"]
    if short:
        sy.states = {k: ("reference" if st == "reference" else "ground") for k, st in sy.states.items()}
    red = reduction(sy, eliminate_grounded=True)
    P = red.P
    dyn = scene.dynamics
    w_ref = 2 * np.pi * dyn.reference_frequency
    parts, kappa, viscous = {}, {}, {}
    for kind, A in sy.parts.items():
        parts[kind] = (P.T @ A @ P).tocsr()
        what, _, region = kind.partition(":")
        mat = materials.get(tm.materials[region][0], user) if region else None
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
        rho = materials.get(tm.materials[region][0], user).rho
        Mr = asm(forms.mass(rho, scene.model.type, tm.layout.depth), ub)
        M = M + _embed(Mr, sy.offsets["u"].start, sy.A.shape[0])
    charge_rows = None
    if short:
        S = sp.csr_matrix((np.ones(sum(len(sy.electrode_dofs[k]) for k in names)),
                           (np.repeat(np.arange(len(names)), [len(sy.electrode_dofs[k]) for k in names]),
                            np.concatenate([sy.electrode_dofs[k] for k in names]))), shape=(len(names), sy.A.shape[0]))
        charge_rows = -(S @ sy.A @ P).tocsr()
    return DynamicModel(sy, red, parts, kappa, viscous, (P.T @ M @ P).tocsr(), dyn.rayleigh_alpha,
                        dyn.rayleigh_beta, P.T @ sy.b, red.unit_charges(), names if short else list(red.active),
                        charge_rows)


def _embed(M, offset, n):
    M = sp.coo_matrix(M)
    return sp.csr_matrix((M.data, (M.row + offset, M.col + offset)), shape=(n, n))


# --------------------------------------------------------------------------------------
# frequency response
# --------------------------------------------------------------------------------------

@dataclass
class PortResponse:
    """Electrode quantities over frequency, for the scene's force amplitude."""

    freqs: np.ndarray            # Hz
    V_oc: np.ndarray             # (nf, na) open-circuit voltages, V
    Cinv: np.ndarray             # (nf, na, na) inverse capacitance, 1/F
    names: list[str]
    method: str
    error: float                 # reduced: measured relative error at the check frequencies
    basis_size: int = 0
    seconds: float = 0.0
    checks: list = field(default_factory=list)

    @property
    def C(self):
        return np.linalg.inv(self.Cinv)

    @property
    def Q_sc(self):
        """Short-circuit charges, C: Q_sc = -C V_oc."""
        return -np.einsum("fij,fj->fi", self.C, self.V_oc)


def frequencies(a) -> np.ndarray:
    """The sweep frequencies of a scene's [analysis] table."""
    if a.spacing == "log":
        return np.geomspace(a.f_min, a.f_max, a.points)
    return np.linspace(a.f_min, a.f_max, a.points)


def _ports(dm: DynamicModel, X):
    nf = dm.red.nf
    return X[nf:, 0], X[nf:, 1:]


def direct(dm: DynamicModel, f_hz: float):
    """(V_oc, C^-1) at one frequency by a direct complex solve."""
    B = np.column_stack([dm.F, dm.Be]).astype(complex)
    X, _ = scaled_solver(dm.K(2 * np.pi * f_hz), dm.red, "superlu")(B)
    return _ports(dm, X)


def coupled_resistor(dm: DynamicModel, f_hz: float, R: float):
    """Electrode voltages with a resistor R on every active electrode, coupled into
    the field equations: the charge row of electrode k gets + i / (w R) V_k
    (from Q_k = -V_k / (i w R) moved to the left-hand side)."""
    w = 2 * np.pi * f_hz
    na, nf = len(dm.names), dm.red.nf
    Y = sp.csr_matrix((np.full(na, 1j / (w * R)), (nf + np.arange(na), nf + np.arange(na))), shape=dm.M.shape)
    X, _ = scaled_solver((dm.K(w) + Y).tocsc(), dm.red, "superlu")(dm.F.astype(complex))
    return X[nf:, 0]


def sweep(dm: DynamicModel, freqs, method: str = "reduced", tol: float = 1e-3, moments: int = 6,
          max_rounds: int = 4) -> PortResponse:
    t0 = time.perf_counter()
    freqs = np.asarray(freqs, float)
    na = len(dm.names)
    if method == "direct":
        V = np.zeros((len(freqs), na), complex)
        Ci = np.zeros((len(freqs), na, na), complex)
        for i, f in enumerate(freqs):
            V[i], Ci[i] = direct(dm, f)
        return PortResponse(freqs, V, Ci, dm.names, "direct", 0.0, seconds=time.perf_counter() - t0)

    checks = sorted({freqs[-1], freqs[len(freqs) // 2]})
    reference = {f: direct(dm, f) for f in checks}
    shifts, basis, err = [0.0], None, np.inf
    for _ in range(max_rounds):
        basis = _krylov(dm, shifts, moments, basis)
        red_model = _project(dm, basis)
        errs = {f: _rel_error(_reduced_ports(dm, red_model, f), reference[f]) for f in checks}
        err = max(errs.values())
        if err <= tol:
            break
        shifts.append(2 * np.pi * max(errs, key=errs.get))
    V = np.zeros((len(freqs), na), complex)
    Ci = np.zeros((len(freqs), na, na), complex)
    for i, f in enumerate(freqs):
        V[i], Ci[i] = _reduced_ports(dm, red_model, f)
    return PortResponse(freqs, V, Ci, dm.names, "reduced", float(err), basis.shape[1],
                        time.perf_counter() - t0, [(f, float(errs[f])) for f in checks])


def _rel_error(a, b):
    return max(np.abs(a[0] - b[0]).max() / np.abs(b[0]).max(), np.abs(a[1] - b[1]).max() / np.abs(b[1]).max())


def _krylov(dm: DynamicModel, shifts, moments, previous=None):
    """Orthonormal (in scaled coordinates) block Krylov basis, real, with separate
    columns for the displacement part and for the pressure/potential part of the
    Krylov vectors: its span contains the Krylov space, and the reduced mass is
    exactly zero on the second group, so `condense` is exact."""
    K0, M = dm.K0, dm.M
    # the loss factors make K complex: K = K0 + i Kim; its directions enter the basis too
    Kim = sum(np.imag(dm.kappa[k]) * P for k, P in dm.parts.items())
    D = _scaling(K0, dm.red.is_u)
    B = np.column_stack([dm.F, dm.Be])
    cols = [] if previous is None else [previous / D[:, None]]
    new_shifts = shifts if previous is None else shifts[-1:]
    for s in new_shifts:
        solve = scaled_solver((K0 - s ** 2 * M).tocsc(), dm.red, linsolve.resolve("auto", K0.shape[0]))
        W = solve(B)[0]
        for _ in range(moments):
            for Z in (W, solve(Kim @ W)[0]):
                Zs = Z / D[:, None]
                cols.append(Zs / np.maximum(np.linalg.norm(Zs, axis=0), 1e-300))
            W = solve(M @ W)[0]
    W = np.hstack(cols)
    u = dm.red.is_u
    blocks = []
    for rows in (u, ~u):          # displacements apart from pressure/potential: block-diagonal basis
        Q, R, _ = la.qr(W[rows], mode="economic", pivoting=True)
        keep = np.abs(np.diag(R)) > 1e-10 * abs(R[0, 0]) if R.size else np.zeros(0, bool)
        Z = np.zeros((len(u), keep.sum()))
        Z[rows] = Q[:, keep]
        blocks.append(Z)
    basis = D[:, None] * np.hstack(blocks)
    return basis


def _project(dm: DynamicModel, V):
    u_cols = np.abs(V[~dm.red.is_u]).sum(axis=0) == 0        # columns supported on displacements only
    return {"V": V, "u_cols": u_cols, "parts": {k: V.T @ (P @ V) for k, P in dm.parts.items()}, "M": V.T @ (dm.M @ V),
            "mech": sum(V.T @ (P @ V) for k, P in dm.parts.items() if _mechanical(k)),
            "B": V.T @ np.column_stack([dm.F, dm.Be]), "E": V[dm.red.nf:, :]}


def _reduced_ports(dm: DynamicModel, r, f_hz):
    w = 2 * np.pi * f_hz
    A = sum(dm.kappa[k] * P for k, P in r["parts"].items()) - w ** 2 * r["M"] \
        + 1j * w * (dm.alpha * r["M"] + dm.beta * r["mech"])
    X = r["E"] @ np.linalg.solve(A, r["B"])
    return X[:, 0], X[:, 1:]


# --------------------------------------------------------------------------------------
# transients
# --------------------------------------------------------------------------------------

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


def transient_hyperelastic(scene: Scene, t: np.ndarray, load: np.ndarray, tol=1e-9, max_iter=12):
    """Full-order Newmark (average acceleration) with Newton at every step for a
    Yeoh silicone, open-circuit electrodes. Residual at step n+1:

        G(x) = M a(x) + C v(x) + R(x) - f_{n+1},  a = 4/dt^2 (x - x_n) - 4/dt v_n - a_n,
        v = 2/dt (x - x_n) - v_n,   R(x) = A_lin x + R_yeoh(x)   (dead load f)

    Jacobian 4/dt^2 M + 2/dt C + K_t(x). M and C act on displacements only, so the
    massless pressure and potential stay algebraic. C: the loss factors as viscous
    damping at the reference frequency, on the small-strain tangent. The tangent
    is refactorized at every iteration (full Newton)."""
    from fem.newton import NewtonError, yeoh_terms
    t0 = time.perf_counter()
    dm = model(scene.model_copy(update={"model": scene.model.model_copy(update={"silicone": "linear"})}))
    sy = assemble(scene, dm.sy.tm, user_materials(scene), hyperelastic=True)
    red = reduction(sy, eliminate_grounded=True)
    P = red.P
    M, C = dm.M, dm.C_time()
    A_lin, b = sy.A, P.T @ sy.b
    dt = t[1] - t[0]
    a1, a2 = 4 / dt ** 2, 2 / dt
    n = red.n
    x_full = np.zeros(sy.A.shape[0])
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
            solve = scaled_solver(J, red, linsolve.resolve("auto", n))
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
    return Transient(t, load * sy.applied_force, V, np.zeros_like(V), list(red.active), n,
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


def transient(dm: DynamicModel, t: np.ndarray, load: np.ndarray, R: float | None = None,
              basis=None, moments: int = 8) -> Transient:
    """Response to a force history (load: factor on the scene's force at times t,
    uniform step). R: a resistor from every active electrode to ground (None:
    open circuit). Reduced model: Krylov basis at shift 0 plus one at half the
    Nyquist frequency; the massless pressure and potential directions condensed
    statically (`condense`), then Newmark."""
    t0 = time.perf_counter()
    dt = t[1] - t[0]
    if basis is None:
        f_top = 0.25 / dt                          # half the Nyquist frequency
        basis = _krylov(dm, [0.0, 2 * np.pi * f_top], moments)
    r = _project(dm, basis)
    c = condense(r, basis.T @ (dm.C_time() @ basis))
    E = r["E"]                                        # electrode potentials: V = E q
    coupling = None
    if R is not None and E.shape[0]:
        coupling = (c["B"], E @ c["Tq"], E @ c["tf"], E @ c["tQ"], R)
    z0 = np.linalg.solve(c["K"], c["F"] * load[0])
    z, Q = newmark(c["M"], c["C"], c["K"], c["F"], load, dt, q0=z0, coupling=coupling)
    q = z @ c["Tq"].T + np.outer(load, c["tf"])
    if Q.shape[1]:
        q += Q @ c["tQ"].T
    else:
        Q = np.zeros((len(t), E.shape[0]))
    if dm.charge_rows is not None:              # short circuit: V = 0, charges from the rows
        Q = q @ (dm.charge_rows @ basis).T
        V = np.zeros_like(Q)
    else:
        V = q @ r["E"].T
    return Transient(t, load * dm.sy.applied_force, V, Q, dm.names, basis.shape[1], time.perf_counter() - t0)


def load_history(a, t=None):
    """(t, f) of the scene's [analysis] input: f scales the scene's force."""
    if a.input == "csv":
        data = np.loadtxt(a.file, delimiter=",", comments="#", ndmin=2)
        tt = np.arange(0.0, data[-1, 0] + a.dt / 2, a.dt)
        return tt, np.interp(tt, data[:, 0], data[:, 1])       # in newtons; caller rescales
    tt = np.arange(0.0, a.duration + a.dt / 2, a.dt) if t is None else t
    if a.input == "step":
        return tt, np.clip(tt / a.rise, 0, 1)
    if a.input == "impulse":
        return tt, np.where(tt < a.width, np.sin(np.pi * tt / a.width), 0.0)
    # chirp from f0 to f1 over the duration: phase 2 pi (f0 t + (f1 - f0) t^2 / (2 T))
    return tt, np.sin(2 * np.pi * (a.f0 * tt + (a.f1 - a.f0) * tt ** 2 / (2 * a.duration)))
