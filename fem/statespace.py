r"""A real first-order state space of a reduced model (fem.reduced), with its readout.

1. Condensation (exact). The reduced basis has displacement columns d (with mass)
   and pressure/potential columns a (massless, undamped: algebraic). With the real
   stiffness K = sum_k K_k, eliminating q_a = K_aa^-1 (F_a f + B_a Q - K_ad z) gives

       M_d z'' + C_d z' + K_d z = F_d f + B_d Q,    V = G z + g_f f + g_Q Q

   (K_d = K_dd - K_da K_aa^-1 K_ad, F_d, B_d alike; q = T z + t_f f + t_Q Q, G = E T).
2. Modes. K_d phi = w^2 M_d phi, Phi^T M_d Phi = I: z = Phi eta, eta'' + C_m eta' + W^2 eta = ...
3. Loss factors. The frequency-domain model has a complex stiffness
   K0 + i K_im, K_im = sum_k Im(kappa_k) K_k (silicone shear eta, volumetric
   Im 1/(1 + i eta), piezo 1/Qm, permittivity -tan(delta): each term is >= 0 on
   every state, so K_im is positive semi-definite). A constant loss factor is not
   causal (its real and imaginary parts violate the Kramers-Kronig relations: no
   finite real state space reproduces it over a band; a least-squares fit of
   Maxwell terms to 1 + 0.1 i over 1 Hz-2 kHz stays 5-8 % off). So the real model
   carries it as viscous damping, to first order in the loss factors:
   * `loss="modal"` (default): H = Phi^T T^T K_im T Phi, C_m = H_ij / sqrt(w_i w_j):
     each mode's damping equals the hysteretic one at its own natural frequency
     (modal damping ratio eta_i / 2), where damping decides the response; below a
     mode the real model loses the hysteretic phase lag eta (quasi-static responses
     differ by about eta in phase and eta^2 / 2 in magnitude);
   * `loss="reference"`: C = sum_mech (eta_k / w_ref) K_k, the damping of the FEM
     transient (fem.dynamics.DynamicModel.C_time), so `simulate` reproduces it.
   Rayleigh damping alpha M + beta K_mech is viscous already and enters exactly.
4. First order, balanced: x = [W eta, eta'] so that
       x1' = W x2,   x2' = -W x1 - C_m x2 + Phi^T F_d f + Phi^T B_d Q.
5. Readout (fem.circuits), all exact for the condensed model:
   * "open": Q = 0, y = V = G Phi W^-1 x1 + g_f f;
   * "charge": electrodes held at 0 V: Q = -g_Q^-1 (G z + g_f f) (the short-circuit
     charge Q_sc of the port relation Q = Q_sc + C V) fed back into the mechanics; y = Q;
   * "resistor": Q becomes a state, Q' = -V / R, V the output;
   * "charge_amplifier": the "charge" model in series with each electrode's
     -(R_f s) / ((1 + s R_f C_f)(1 + s R_i (C_p + C_c))), C_p the static capacitance
     (fem.circuits uses C_p(w), which differs above the first resonance);
   * the 50 Hz notch in series with every output.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as la

from taxel.fem.circuits import Readout
from taxel.fem.reduced import Reduced


@dataclass
class StateSpace:
    """x' = A x + B u, y = C x + D u (SI units: u in N, y in V or C)."""

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray

    @property
    def order(self) -> int:
        return self.A.shape[0]

    def frf(self, freqs) -> np.ndarray:
        """H(i 2 pi f) = C (sI - A)^-1 B + D, (nf, outputs, inputs)."""
        freqs = np.atleast_1d(np.asarray(freqs, float))
        eye = np.eye(self.order)
        return np.array([self.C @ np.linalg.solve(2j * np.pi * f * eye - self.A, self.B) + self.D for f in freqs])

    def simulate(self, t: np.ndarray, u: np.ndarray) -> np.ndarray:
        """Outputs (nt, outputs) for inputs u (nt, inputs) at uniform times t, from rest
        at the static state of u[0]. Exact for inputs linear between samples
        (first-order hold, scipy.signal.cont2discrete); then each mode of the
        discrete system z_i[k+1] = lambda_i z_i[k] + b_i[k] is one first-order
        filter (scipy.signal.lfilter), a conjugate pair counted once (2 Re)."""
        from scipy import signal
        t, u = np.asarray(t, float), np.asarray(u, float).reshape(len(t), -1)
        Ad, Bd, Cd, Dd, _ = signal.cont2discrete((self.A, self.B, self.C, self.D), t[1] - t[0], method="foh")
        x0 = -np.linalg.solve(self.A, self.B @ u[0])
        lam, W = la.eig(Ad)
        y = u @ Dd.T
        if np.linalg.cond(W) > 1e8:                         # defective: step the real system
            x = x0
            for k in range(len(t)):
                y[k] += Cd @ x
                x = Ad @ x + Bd @ u[k]
            return y
        Winv = np.linalg.inv(W)
        b_modal, z0, c_modal = Winv @ Bd, Winv @ x0, Cd @ W
        keep = np.flatnonzero(lam.imag >= 0)
        weight = np.where(lam[keep].imag > 0, 2.0, 1.0)
        for chunk in np.array_split(np.arange(len(keep)), max(1, len(keep) // 24)):
            idx = keep[chunk]
            drive = u @ b_modal[idx].T                       # (nt, chunk) modal inputs
            for j, i in enumerate(idx):
                drive[:, j] = signal.lfilter([0.0, 1.0], [1.0, -lam[i]], drive[:, j], zi=[z0[i]])[0]
            y += (drive @ (weight[chunk][:, None] * c_modal[:, idx].T)).real
        return y


def condensed(red: Reduced, loss: str = "modal", f_cut: float | None = None):
    """(W (n,), C_m (n, n), Phi^T F_d, Phi^T B_d, G Phi W^-1, g_f, g_Q): the modal form
    of steps 1-3 of the module docstring. Modes above `f_cut` (Hz) whose damping
    force is below 1 % of their stiffness there are kept quasi-statically (static residualization: eta_j = (Phi_j^T F_d f + Phi_j^T B_d Q) / w_j^2
    added to the direct terms g_f, g_Q), so the static response stays exact."""
    d = red.u_cols
    K = sum(red.parts.values())
    Kim = sum(np.imag(red.kappa[k]) * P for k, P in red.parts.items())
    a = ~d
    Kaa = K[np.ix_(a, a)]
    X = np.linalg.solve(Kaa, np.column_stack([K[np.ix_(a, d)], red.F[a], red.Be[a]]))
    nd, m = d.sum(), red.F.shape[1]
    XK, XF, XB = X[:, :nd], X[:, nd:nd + m], X[:, nd + m:]
    Kda = K[np.ix_(d, a)]
    Kd = K[np.ix_(d, d)] - Kda @ XK
    Fd, Bd = red.F[d] - Kda @ XF, red.Be[d] - Kda @ XB
    T = np.zeros((len(d), nd))
    T[d] = np.eye(nd)
    T[a] = -XK
    tf, tQ = np.zeros((len(d), m)), np.zeros((len(d), red.Be.shape[1]))
    tf[a], tQ[a] = XF, XB
    Md = red.M[np.ix_(d, d)]
    w2, Phi = la.eigh((Kd + Kd.T) / 2, (Md + Md.T) / 2)
    w = np.sqrt(np.maximum(w2, 0))
    if w.min() <= 0:
        raise ValueError("the reduced model has a rigid-body mode; support the sensor (supports.bottom)")
    TP = T @ Phi
    viscous = red.alpha * np.eye(nd) + red.beta * (TP.T @ red.mech @ TP)
    if loss == "modal":
        H = TP.T @ Kim @ TP
        viscous = viscous + H / np.sqrt(np.outer(w, w))
    elif loss == "reference":
        viscous = viscous + TP.T @ sum(red.viscous[k] * red.parts[k] for k in red.parts
                                       if k.split(":")[0] in ("shear", "elastic")) @ TP
    else:
        raise ValueError(f"loss = '{loss}': use 'modal' or 'reference'")
    G = red.E @ TP / w[None, :]
    Fm, Bm, gf, gQ = Phi.T @ Fd, Phi.T @ Bd, red.E @ tf, red.E @ tQ
    if f_cut is not None:            # quasi-static only where the mode's damping is negligible at f_cut too
        hi = (w > 2 * np.pi * f_cut) & (np.diag(viscous) * 2 * np.pi * f_cut < 1e-2 * w ** 2)
        gf = gf + (G[:, hi] / w[hi]) @ Fm[hi]
        gQ = gQ + (G[:, hi] / w[hi]) @ Bm[hi]
        lo = ~hi
        return w[lo], ((viscous + viscous.T) / 2)[np.ix_(lo, lo)], Fm[lo], Bm[lo], G[:, lo], gf, gQ
    return w, (viscous + viscous.T) / 2, Fm, Bm, G, gf, gQ


def mechanics(w, Cm, Fm, Bm, extra=None):
    """(A, B) of x = [W eta, eta'] (step 4); `extra` (Bq, Gx, Gf): a charge feedback
    Q = Gx x + Gf f entering the mechanics through Bm."""
    n = len(w)
    A = np.block([[np.zeros((n, n)), np.diag(w)], [-np.diag(w), -Cm]])
    B = np.vstack([np.zeros_like(Fm), Fm])
    if extra is not None:
        Gx, Gf = extra
        A[n:] += Bm @ Gx
        B[n:] += Bm @ Gf
    return A, B


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


def realize(red: Reduced, readout: Readout | str = "open", loss: str = "modal",
            f_cut: float | None = None) -> StateSpace:
    """The real state space from the inputs (N) to the readout's outputs at every
    electrode (V; C for readout "charge"); see the module docstring."""
    w, Cm, Fm, Bm, G, gf, gQ = condensed(red, loss, f_cut)
    n, na = len(w), gQ.shape[0]
    r = Readout(readout) if isinstance(readout, str) and readout != "charge" else readout
    Gx = np.hstack([G, np.zeros((na, n))])
    if readout == "charge" or r.circuit == "charge_amplifier":
        gQi = np.linalg.inv(gQ)
        A, B = mechanics(w, Cm, Fm, Bm, (-gQi @ Gx, -gQi @ gf))
        ss = StateSpace(A, B, -gQi @ Gx, -gQi @ gf)
        if readout == "charge":
            return ss
        Cinv0 = gQ + G @ (Bm[:, :] / w[:, None])        # static: V = G eta + g_Q Q, eta = W^-2 Bm Q
        Cp = np.diag(np.linalg.inv(Cinv0))
        amps = [diagonal_filter([-r.R_f, 0.0], np.polymul([r.R_f * r.C_f, 1.0], [r.R_i * (c + r.C_c), 1.0]), 1)
                for c in Cp]
        amp = StateSpace(la.block_diag(*[s.A for s in amps]), la.block_diag(*[s.B for s in amps]),
                         la.block_diag(*[s.C for s in amps]), la.block_diag(*[s.D for s in amps]))
        ss = series(ss, amp)
    elif r.circuit == "resistor":
        A0, B0 = mechanics(w, Cm, Fm, Bm)
        A = np.block([[A0, np.vstack([np.zeros((n, na)), Bm])], [-Gx / r.R, -gQ / r.R]])
        ss = StateSpace(A, np.vstack([B0, -gf / r.R]), np.hstack([Gx, gQ]), gf)
    else:
        A, B = mechanics(w, Cm, Fm, Bm)
        ss = StateSpace(A, B, Gx, gf)
    if r.notch:
        w0, bw = 2 * np.pi * r.notch_frequency, r.notch_bandwidth / r.notch_frequency
        ss = series(ss, diagonal_filter([1.0, 0.0, w0 ** 2], [1.0, w0 * bw, w0 ** 2], na))
    return ss
