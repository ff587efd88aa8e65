r"""Frequency response at the electrodes, direct or on a Krylov-reduced model.

Port quantities. For open electrodes (Q = 0) the solution gives the
open-circuit voltages V_oc(w) per newton; unit charges give C(w)^-1. Any linear
circuit on the electrodes then follows exactly from the port relation
Q = Q_sc + C V with Q_sc = -C V_oc (fem.readout).
Cheap sweeps. `sweep(..., method="reduced")` projects the system on a block
Krylov basis {A_s^-1 B, A_s^-1 M A_s^-1 B, ...}, A_s = K(s) the damped operator at
shifts s (0 first: K0; then complex, the loss law of fem.constitution there, real and
imaginary parts as columns), B = [F, B_e], each block also multiplied by
A_s^-1 (K_u - K0) (the directions of the losses): moment matching of the transfer function. The reduced
answer is compared with direct solves at check frequencies (the highest and
the middle one); the basis grows (a new shift at the worst check frequency)
until the relative error of V_oc and C^-1 is below the tolerance, which the
result reports.
"""


from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp

from taxel.fem import linalg
from ._model import DynamicModel, mechanical



@dataclass
class PortResponse:
    """Electrode quantities over frequency, per newton of load."""

    freqs: np.ndarray            # Hz
    V_oc: np.ndarray             # (nf, na) open-circuit voltages, V/N
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


def _ports(dm: DynamicModel, X):
    nf = dm.red.nf
    return X[nf:, 0], X[nf:, 1:]


def direct(dm: DynamicModel, f_hz: float):
    """(V_oc, C^-1) at one frequency by a direct complex solve."""
    B = np.column_stack([dm.F, dm.Be]).astype(complex)
    X, _ = linalg.scaled_solver(dm.K(2 * np.pi * f_hz), dm.red.is_u, dm.method)(B)
    return _ports(dm, X)


def coupled_resistor(dm: DynamicModel, f_hz: float, R: float):
    """Electrode voltages with a resistor R on every active electrode, coupled into
    the field equations: the charge row of electrode k gets + i / (w R) V_k
    (from Q_k = -V_k / (i w R) moved to the left-hand side)."""
    w = 2 * np.pi * f_hz
    na, nf = len(dm.names), dm.red.nf
    Y = sp.csr_matrix((np.full(na, 1j / (w * R)), (nf + np.arange(na), nf + np.arange(na))), shape=dm.M.shape)
    X, _ = linalg.scaled_solver((dm.K(w) + Y).tocsc(), dm.red.is_u, dm.method)(dm.F.astype(complex))
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
            logging.getLogger(__name__).info("sweep: %d of %d frequencies (%.4g Hz)", i + 1, len(freqs), f)
        return PortResponse(freqs, V, Ci, dm.names, "direct", 0.0, seconds=time.perf_counter() - t0)

    checks = sorted({freqs[-1], freqs[len(freqs) // 2]})
    reference = {f: direct(dm, f) for f in checks}
    shifts, basis, err = [0.0], None, np.inf
    for _ in range(max_rounds):
        basis = krylov(dm, shifts, moments, basis)
        red_model = project(dm, basis)
        errs = {f: _rel_error(_reduced_ports(dm, red_model, f), reference[f]) for f in checks}
        err = max(errs.values())
        logging.getLogger(__name__).info("sweep: Krylov basis of %d vectors, error %.2g (tolerance %.2g)",
                                         basis.shape[1], err, tol)
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


def krylov(dm: DynamicModel, shifts, moments, previous=None):
    """Orthonormal (in scaled coordinates) block Krylov basis, real, with separate
    columns for the displacement part and for the pressure/potential part of the
    Krylov vectors: its span contains the Krylov space, and the reduced mass is
    exactly zero on the second group, so `condense` is exact."""
    K0, M = dm.K0, dm.M
    # the losses make K complex: K(w) = K0 + sum_j K^(j) i w tau_j / (1 + i w tau_j); the
    # directions of their total K_u - K0 enter the basis too
    Kim = dm.K_unrelaxed() - K0
    D = linalg.scaling(K0, dm.red.is_u)
    B = np.column_stack([dm.F, dm.Be])
    cols = [] if previous is None else [previous / D[:, None]]
    new_shifts = shifts if previous is None else shifts[-1:]
    for s in new_shifts:
        # at a shift s > 0 the damped operator K(s) (complex: the loss law there), real and
        # imaginary parts as columns; at 0 the static K0
        A = (K0 - s ** 2 * M).tocsc() if s == 0 else dm.K(s)
        solve = linalg.scaled_solver(A, dm.red.is_u, linalg.resolve("auto", K0.shape[0], dim=dm.sy.tm.mesh.dim())
                                     if s == 0 else "superlu")
        W = solve(B.astype(A.dtype))[0]
        for _ in range(moments):
            for Z in (W, solve(Kim @ W)[0]):
                for P in ((Z,) if s == 0 else (Z.real, Z.imag)):
                    Zs = P / D[:, None]
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


def project(dm: DynamicModel, V):
    u_cols = np.abs(V[~dm.red.is_u]).sum(axis=0) == 0        # columns supported on displacements only
    return {"V": V, "u_cols": u_cols, "parts": {k: V.T @ (P @ V) for k, P in dm.parts.items()}, "M": V.T @ (dm.M @ V),
            "mech": sum(V.T @ (P @ V) for k, P in dm.parts.items() if mechanical(k)),
            "B": V.T @ np.column_stack([dm.F, dm.Be]), "E": V[dm.red.nf:, :]}


def _reduced_ports(dm: DynamicModel, r, f_hz):
    w = 2 * np.pi * f_hz
    kap = dm.kappa(w)
    A = sum(kap[k] * P for k, P in r["parts"].items()) - w ** 2 * r["M"] \
        + 1j * w * (dm.alpha * r["M"] + dm.beta * r["mech"])
    X = r["E"] @ np.linalg.solve(A, r["B"])
    return X[:, 0], X[:, 1:]


