r"""A real first-order state space of a reduced model (fem.dynamics), with its readout.

The reduced model's losses follow the causal law of fem.constitution, so it has an
exact finite real realization (a constant loss factor E (1 + i eta) would have none:
Kramers-Kronig; see fem.constitution):

1. Internal variables. K(s) q = K_u q - sum_j K^(j) s_j, tau_j s_j' = q - s_j
   (K_u the unrelaxed stiffness, K^(j) = sum_k c_jk K_k, projected: V^T K V).
2. Condensation (exact). The basis has displacement columns d (with mass) and
   pressure/potential columns a (massless, undamped: algebraic given the s_j):
   q_a = K_u,aa^-1 (F_a f + B_a Q - K_u,ad z + sum_j K^(j)_a s_j), so

       M_d z'' + C_d z' + K_d z = F_d f + B_d Q + sum_j P_j s_j,
       q = T z + t_f f + t_Q Q + sum_j t_j s_j,     V = E q

   (K_d = K_u,dd - K_u,da K_u,aa^-1 K_u,ad; F_d, B_d, P_j = K^(j)_d - K_u,da X_j alike).
3. Modes of the unrelaxed system: K_d Phi = M_d Phi W^2, z = Phi eta; the state
   x = [W eta, eta', s_1 .. s_N] (N r internal variables), Rayleigh damping
   C_m = Phi^T C_d Phi exact. This is the port model: inputs [f, Q] (N, C), outputs
   the electrode potentials V; its FRF equals `fem.dynamics.ports` to rounding.
4. Modal truncation with a measured error (`port_model`). The port model is
   diagonalised, A = W Lambda W^-1; each mode's residue R_i = (C w_i)(w_i^-1 B)
   bounds its contribution over the band. Modes are dropped, smallest bound first,
   while the error of all dropped modes together, measured on a grid over the band
   (after static residualization: a dropped mode keeps its static part
   -R_i / lambda_i in the direct term, so the static response stays exact), stays
   below `tol` of every path's largest value; the
   kept modes become real 2 x 2 blocks [[Re l, Im l], [-Im l, Re l]] (pairs) or
   1 x 1 (real poles). Most of the N r relaxation modes are uncontrollable or
   unobservable, or sit far outside the band.
5. Readout (fem.readout) on the port model (A, [B_f B_Q], C, [D_f D_Q]), exact:
   * "open": Q = 0, y = V;
   * "charge": electrodes held at 0 V, Q = -D_Q^-1 (C x + D_f f) fed back; y = Q;
   * "resistor": Q becomes a state, Q' = -V / R, V the output;
   * "charge_amplifier": the "charge" model in series with each electrode's
     -(R_f s) / ((1 + s R_f C_f)(1 + s R_i (C_p + C_c))), C_p the static capacitance
     (fem.readout uses C_p(w), which differs above the first resonance);
   * the 50 Hz notch in series with every output.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as la

from taxel.fem.readout import Readout
from ._projection import ProjectedModel


@dataclass
class StateSpace:
    """x' = A x + B u, y = C x + D u (SI units: u in N, y in V or C)."""

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    truncation_error: float = 0.0        # measured, of the modal truncation (fem.dynamics.port_model)
    _eig: tuple | None = field(default=None, repr=False)

    @property
    def order(self) -> int:
        return self.A.shape[0]

    def modes(self):
        """(lambda, C W, W^-1 B) of the eigendecomposition A = W diag(lambda) W^-1,
        or () when W is ill conditioned (computed once)."""
        if self._eig is None and self.order == 0:
            self._eig = (np.zeros(0, complex), np.zeros((self.C.shape[0], 0)), np.zeros((0, self.B.shape[1])))
        if self._eig is None:
            lam, W = la.eig(self.A)
            self._eig = (lam, self.C @ W, np.linalg.solve(W, self.B)) if np.linalg.cond(W) < 1e8 else ()
            if self._eig and not self._modal_holds():
                self._eig = ()
        return self._eig

    def _modal_holds(self, rtol: float = 1e-6) -> bool:
        """The modal FRF against direct solves at 5 frequencies up to the fastest pole: a
        moderate cond(W) does not suffice (a charge amplifier in series with the charge
        path, SI-scaled: cond(W) 475 and the modal FRF wrong by 2-20x below 10 Hz)."""
        lam, CW, WB = self._eig
        top = max(float(np.abs(lam).max()) / (2 * np.pi), 1.0)
        eye = np.eye(self.order)
        for f in np.geomspace(1e-2, top, 5):
            s = 2j * np.pi * f
            direct = self.C @ np.linalg.solve(s * eye - self.A, self.B) + self.D
            modal = (CW / (s - lam)) @ WB + self.D
            if np.abs(modal - direct).max() > rtol * max(np.abs(direct).max(), 1e-300):
                return False
        return True

    def frf(self, freqs) -> np.ndarray:
        """H(i 2 pi f) = C (sI - A)^-1 B + D, (nf, outputs, inputs); through the
        eigendecomposition of A when it is well conditioned."""
        freqs = np.atleast_1d(np.asarray(freqs, float))
        if self.modes():
            lam, CW, WB = self.modes()
            return np.array([(CW / (2j * np.pi * f - lam)) @ WB + self.D for f in freqs])
        eye = np.eye(self.order)
        return np.array([self.C @ np.linalg.solve(2j * np.pi * f * eye - self.A, self.B) + self.D for f in freqs])

    def simulate(self, t: np.ndarray, u: np.ndarray) -> np.ndarray:
        """Outputs (nt, outputs) for inputs u (nt, inputs) at uniform times t, from rest
        at the static state of u[0]. Exact for inputs linear between samples (first-
        order hold): each mode z' = lambda z + beta(t), beta = (W^-1 B u) linear over a
        step h, is z[k+1] = E z[k] + (phi1 - phi2) beta[k] + phi2 beta[k+1] with
        E = exp(lambda h), phi1 = (E - 1) / lambda, phi2 = (E - 1 - lambda h) / (lambda^2 h),
        one first-order filter (scipy.signal.lfilter) per mode, a conjugate pair
        counted once (2 Re). A defective A: scipy.signal.lsim."""
        from scipy import signal
        t, u = np.asarray(t, float), np.asarray(u, float).reshape(len(t), -1)
        if not self.modes():
            return signal.lsim((self.A, self.B, self.C, self.D), u, t,
                               X0=-np.linalg.solve(self.A, self.B @ u[0]))[1].reshape(len(t), -1)
        lam, CW, WB = self.modes()
        h = t[1] - t[0]
        x = lam * h
        E = np.exp(x)
        small = np.abs(x) < 1e-3
        xs = np.where(small, 1.0, x)
        phi1 = np.where(small, h * (1 + x / 2 + x ** 2 / 6), (E - 1) / np.where(small, 1.0, lam))
        phi2 = np.where(small, h * (0.5 + x / 6 + x ** 2 / 24), (E - 1 - xs) / (xs * np.where(small, 1.0, lam)))
        keep = np.flatnonzero(lam.imag >= 0)
        y = u @ self.D.T
        for chunk in np.array_split(keep, max(1, len(keep) // 32)):
            Zr, Zi = np.zeros((len(chunk), len(t))), np.zeros((len(chunk), len(t)))
            for r, i in enumerate(chunk):
                b = WB[i]
                if lam[i].imag == 0:                                # a real pole: real arithmetic
                    beta = u @ b.real
                    zi = [(E[i] * (-beta[0] / lam[i]) + (phi1[i] - phi2[i]) * beta[0]).real]
                    Zr[r] = signal.lfilter([phi2[i].real, (phi1[i] - phi2[i]).real], [1.0, -E[i].real],
                                           beta, zi=zi)[0]
                    continue
                beta = u @ b.real + 1j * (u @ b.imag)
                zi = [E[i] * (-beta[0] / lam[i]) + (phi1[i] - phi2[i]) * beta[0]]    # static under u[0]
                z = 2 * signal.lfilter([phi2[i], phi1[i] - phi2[i]], [1.0, -E[i]], beta, zi=zi)[0]   # the pair: 2 Re
                Zr[r], Zi[r] = z.real, z.imag
            c = CW[:, chunk]
            y += Zr.T @ c.real.T - Zi.T @ c.imag.T
        return y


def exact_port_model(red: ProjectedModel) -> StateSpace:
    """Steps 1-3 of the module docstring: inputs [f (m), Q (na)], outputs V (na)."""
    d, a = red.u_cols, ~red.u_cols
    rel = red.relax
    ku = rel.unrelaxed()
    Ku = sum(ku.get(k, 1.0) * P for k, P in red.parts.items())
    Kj = [sum(c * red.parts[k] for k, c in rel.branch(j).items()) for j in range(rel.n)]
    r, m, na = len(d), red.F.shape[1], red.Be.shape[1]
    nd = int(d.sum())
    X = np.linalg.solve(Ku[np.ix_(a, a)], np.column_stack([Ku[np.ix_(a, d)], red.F[a], red.Be[a]]
                                                          + [K[a] for K in Kj]))
    XK, XF, XB = X[:, :nd], X[:, nd:nd + m], X[:, nd + m:nd + m + na]
    Xj = [X[:, nd + m + na + j * r: nd + m + na + (j + 1) * r] for j in range(rel.n)]
    Kda = Ku[np.ix_(d, a)]
    Kd = Ku[np.ix_(d, d)] - Kda @ XK
    Fd, Bd = red.F[d] - Kda @ XF, red.Be[d] - Kda @ XB
    Pj = [K[d] - Kda @ x for K, x in zip(Kj, Xj)]
    T = np.zeros((r, nd))
    T[d], T[a] = np.eye(nd), -XK
    tf, tQ = np.zeros((r, m)), np.zeros((r, na))
    tf[a], tQ[a] = XF, XB
    tj = []
    for x in Xj:
        t = np.zeros((r, r))
        t[a] = x
        tj.append(t)
    Md = red.M[np.ix_(d, d)]
    w2, Phi = la.eigh((Kd + Kd.T) / 2, (Md + Md.T) / 2)
    w = np.sqrt(np.maximum(w2, 0))
    if w.min() <= 0:
        raise ValueError("the reduced model has a rigid-body mode; support the sensor (supports.bottom)")
    Cd = red.alpha * red.M + red.beta * red.mech
    TP = T @ Phi
    Cm = Phi.T @ Cd[np.ix_(d, d)] @ Phi
    n, N = nd, rel.n
    nx = 2 * n + N * r
    A = np.zeros((nx, nx))
    B = np.zeros((nx, m + na))
    A[:n, n:2 * n] = np.diag(w)
    A[n:2 * n, :n] = -np.diag(w)
    A[n:2 * n, n:2 * n] = -(Cm + Cm.T) / 2
    B[n:2 * n] = Phi.T @ np.column_stack([Fd, Bd])
    G = TP / w[None, :]                                 # q per unit of W eta
    fQ = np.column_stack([tf, tQ])
    for j in range(N):
        sj = slice(2 * n + j * r, 2 * n + (j + 1) * r)
        A[n:2 * n, sj] = Phi.T @ Pj[j]
        A[sj, :n] = G / rel.tau[j]
        for i in range(N):
            A[sj, 2 * n + i * r: 2 * n + (i + 1) * r] = tj[i] / rel.tau[j]
        A[sj, sj] -= np.eye(r) / rel.tau[j]
        B[sj] = fQ / rel.tau[j]
    C = np.hstack([red.E @ G, np.zeros((na, n))] + [red.E @ t for t in tj])
    D = red.E @ fQ
    return StateSpace(A, B, C, D)


def port_model(red: ProjectedModel, band=(1.0, 2000.0), tol: float = 1e-3, points: int = 200,
               compress: float = 0.5) -> tuple[StateSpace, float]:
    """The exact port model truncated to its dominant modes (step 4); returns it and
    the measured truncation error over the band (max over paths of the largest
    |H - H_exact| relative to the path's largest |H_exact|)."""
    ex = exact_port_model(red)
    lam, W = la.eig(ex.A)
    Bm, Cm = np.linalg.solve(W, ex.B), ex.C @ W
    s = 2j * np.pi * np.geomspace(band[0], band[1], points)
    R = Cm[:, :, None] * Bm[None, :, :]                 # (na, modes, inputs) residues
    H = np.einsum("omi,fm->foi", R, 1 / (s[:, None] - lam[None, :])) + ex.D
    scale = np.abs(H).max(axis=0)                       # (outputs, inputs): each path's largest value
    scale = np.maximum(scale, 1e-300)
    # the error of dropping mode i with its static part kept: R_i (1/(s - l) + 1/l) = R_i s / (l (s - l))
    f_i = np.abs(s[:, None] / (lam[None, :] * (s[:, None] - lam[None, :]))).max(axis=0)
    bound = (np.abs(R) / scale[:, None, :]).max(axis=(0, 2)) * f_i
    first = np.flatnonzero(lam.imag >= 0)             # a pair counted once (LAPACK: the pair is i, i + 1)
    pair = lam[first].imag > 0
    if not np.allclose(lam[first[pair] + 1], lam[first[pair]].conj()):
        raise RuntimeError("eigenvalues of the real port model not in conjugate pairs")
    b = bound[first] * np.where(pair, 2.0, 1.0)
    order = first[np.argsort(b)]
    # the largest prefix of `order` whose summed error (measured on the grid, where
    # the dropped modes' contributions partly cancel) stays within tol
    err_of = s[:, None] / (lam[None, :] * (s[:, None] - lam[None, :]))     # (grid, modes)
    total, n_drop = np.zeros_like(H), 0
    for k, i in enumerate(order):
        members = [i, i + 1] if lam[i].imag > 0 else [i]
        total = total + np.einsum("omi,fm->foi", R[:, members], err_of[:, members])
        if (np.abs(total).max(axis=0) / scale).max() > (1 - compress) * tol:
            break
        n_drop = k + 1
    gone = order[:n_drop]
    drop = np.concatenate([gone, gone[lam[gone].imag > 0] + 1]).astype(int)
    keep = np.setdiff1d(np.arange(len(lam)), drop)
    D = (ex.D - np.einsum("omi,m->oi", R[:, drop], 1 / lam[drop])).real
    cplx, real = keep[lam[keep].imag != 0], keep[lam[keep].imag == 0]
    ss = _real_modal(lam[cplx], Cm[:, cplx], Bm[cplx], D)
    Hc = np.einsum("omi,fm->foi", R[:, cplx], 1 / (s[:, None] - lam[cplx][None, :])) + D
    rs = _compress(lam[real].real, Cm[:, real].real, Bm[real].real, s, H - Hc, scale, compress * tol)
    ss = StateSpace(la.block_diag(ss.A, rs.A), np.vstack([ss.B, rs.B]), np.hstack([ss.C, rs.C]), ss.D + rs.D)
    err = float((np.abs(ss.frf(s.imag / (2 * np.pi)) - H).max(axis=0) / scale).max())
    return ss, err


def _compress(lam, C, B, s, target, scale, tol) -> StateSpace:
    """The real-pole (relaxation) part, sum_i C_i B_i / (s - lam_i), reduced by balanced
    truncation with singular perturbation (the static gain kept): scaled so that every
    path counts relative to its largest value, Gramians of the diagonal system in closed
    form P_ij = (b_i . b_j) / -(lam_i + lam_j); the smallest order (bisection) whose FRF
    on the grid is within tol of `target` (the same part before compression)."""
    if len(lam) == 0:
        return StateSpace(np.zeros((0, 0)), np.zeros((0, B.shape[1])), np.zeros((C.shape[0], 0)),
                          np.zeros((C.shape[0], B.shape[1])))
    so, si = 1 / np.sqrt(scale.max(axis=1)), 1 / np.sqrt(scale.max(axis=0))
    Bs, Cs = B * si[None, :], C * so[:, None]
    S = -(lam[:, None] + lam[None, :])
    P, Q = (Bs @ Bs.T) / S, (Cs.T @ Cs) / S

    def root(X):
        w, V = la.eigh((X + X.T) / 2)
        return V * np.sqrt(np.maximum(w, 0))
    Lp, Lq = root(P), root(Q)
    U, sv, Vt = la.svd(Lq.T @ Lp)
    nz = int((sv > 1e-14 * sv[0]).sum()) if sv[0] > 0 else 0
    T = Lp @ Vt.T[:, :nz] / np.sqrt(sv[:nz])
    Ti = (U[:, :nz] / np.sqrt(sv[:nz])).T @ Lq.T
    Ab, Bb, Cb = Ti @ np.diag(lam) @ T, Ti @ Bs, Cs @ T
    f = s.imag / (2 * np.pi)

    def truncated(k):           # singular perturbation of the balanced system to order k
        X = np.linalg.solve(Ab[k:, k:], np.hstack([Ab[k:, :k], Bb[k:]])) if k < nz else np.zeros((0, k + B.shape[1]))
        Ar, Br = Ab[:k, :k] - Ab[:k, k:] @ X[:, :k], Bb[:k] - Ab[:k, k:] @ X[:, k:]
        Cr, Dr = Cb[:, :k] - Cb[:, k:] @ X[:, :k], -Cb[:, k:] @ X[:, k:]
        return StateSpace(Ar, Br / si[None, :], Cr / so[:, None], Dr / np.outer(so, si))

    def ok(k):
        return (np.abs(truncated(k).frf(f) - target).max(axis=0) / scale).max() <= tol
    lo, hi = 0, nz                # the smallest order that holds (the error falls with the order)
    while lo < hi:
        mid = (lo + hi) // 2
        lo, hi = (lo, mid) if ok(mid) else (mid + 1, hi)
    return truncated(lo)


def _real_modal(lam, Cm, Bm, D) -> StateSpace:
    """Real block-diagonal realization of the modes (a conjugate pair as one 2 x 2 block)."""
    blocks, rows, cols = [], [], []
    for i in np.flatnonzero(lam.imag >= 0):
        a, b = lam[i].real, lam[i].imag
        if b == 0:
            blocks.append(np.array([[a]]))
            rows.append(Bm[i].real[None, :])
            cols.append(Cm[:, i].real[:, None])
        else:
            blocks.append(np.array([[a, b], [-b, a]]))
            rows.append(np.vstack([2 * Bm[i].real, -2 * Bm[i].imag]))
            cols.append(np.column_stack([Cm[:, i].real, Cm[:, i].imag]))
    if not blocks:
        return StateSpace(np.zeros((0, 0)), np.zeros((0, D.shape[1])), np.zeros((D.shape[0], 0)), D)
    return StateSpace(la.block_diag(*blocks), np.vstack(rows), np.hstack(cols), D)


def series(s1: StateSpace, s2: StateSpace) -> StateSpace:
    """s2 after s1."""
    n1, n2 = s1.order, s2.order
    A = np.block([[s1.A, np.zeros((n1, n2))], [s2.B @ s1.C, s2.A]])
    return StateSpace(A, np.vstack([s1.B, s2.B @ s1.D]), np.hstack([s2.D @ s1.C, s2.C]), s2.D @ s1.D)


def diagonal_filter(num, den, k: int) -> StateSpace:
    """k copies of the SISO filter num/den side by side (controllable form)."""
    from scipy import signal
    a, b, c, d = signal.tf2ss(num, den)
    return StateSpace(np.kron(np.eye(k), a), np.kron(np.eye(k), b), np.kron(np.eye(k), c), np.kron(np.eye(k), d))


def with_readout(port: StateSpace, m: int, readout: Readout | str = "open") -> StateSpace:
    """The readout (step 5) on a port model with m force inputs."""
    A, C = port.A, port.C
    Bf, BQ, Df, DQ = port.B[:, :m], port.B[:, m:], port.D[:, :m], port.D[:, m:]
    na = DQ.shape[0]
    r = Readout(readout) if isinstance(readout, str) and readout != "charge" else readout
    if readout == "charge" or r.circuit == "charge_amplifier":
        DQi = np.linalg.inv(DQ)
        ss = StateSpace(A - BQ @ DQi @ C, Bf - BQ @ DQi @ Df, -DQi @ C, -DQi @ Df)
        if readout == "charge":
            return ss
        Cinv0 = DQ - C @ np.linalg.solve(A, BQ)          # static inverse capacitance
        Cp = np.diag(np.linalg.inv(Cinv0))
        amps = [diagonal_filter([-r.R_f, 0.0], np.polymul([r.R_f * r.C_f, 1.0], [r.R_i * (c + r.C_c), 1.0]), 1)
                for c in Cp]
        amp = StateSpace(la.block_diag(*[s.A for s in amps]), la.block_diag(*[s.B for s in amps]),
                         la.block_diag(*[s.C for s in amps]), la.block_diag(*[s.D for s in amps]))
        ss = series(ss, amp)
    elif r.circuit == "resistor":
        ss = StateSpace(np.block([[A, BQ], [-C / r.R, -DQ / r.R]]), np.vstack([Bf, -Df / r.R]),
                        np.hstack([C, DQ]), Df)
    else:
        ss = StateSpace(A, Bf, C, Df)
    if r.notch:
        w0, bw = 2 * np.pi * r.notch_frequency, r.notch_bandwidth / r.notch_frequency
        ss = series(ss, diagonal_filter([1.0, 0.0, w0 ** 2], [1.0, w0 * bw, w0 ** 2], na))
    return ss


def realize(red: ProjectedModel, readout: Readout | str = "open", band=(1.0, 2000.0), tol: float = 1e-3) -> StateSpace:
    """The real state space from the inputs (N) to the readout's outputs at every
    electrode (V; C for readout "charge"); see the module docstring. The port
    model's measured truncation error is `.truncation_error` of the result."""
    port, err = port_model(red, band, tol)
    ss = with_readout(port, red.F.shape[1], readout)
    ss.truncation_error = err
    return ss
