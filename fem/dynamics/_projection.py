r"""A Krylov-reduced dynamic model with several force inputs, kept (not thrown away
after a sweep).

The full model (fem.dynamics) with m force inputs, load vectors F = [F_1 .. F_m]
(each per newton), and the electrodes' unit-charge right-hand sides B_e:

    (sum_k kappa_k(w) K_k - w^2 M + i w (alpha M + beta K_mech)) x = F f + B_e Q,   V = E x

is projected on a real basis V (`basis`: block Krylov spaces of the damped operator at
complex-valued shifts, every load column in the block: moment matching of all
m + na transfer functions at the shifts):

    (sum_k kappa_k(w) V^T K_k V - w^2 V^T M V + i w (...)) q = V^T F f + V^T B_e Q,   V_el = E V q.

The causal loss law kappa_k(w) (fem.constitution) is kept, so `ports` is the reduced
form of exactly the model fem.dynamics solves, and fem.dynamics realizes it exactly. The basis grows greedily (`build`): shifts at
0 Hz and f_max, then at the frequency of the largest residual in the full model,
until the open-circuit voltages of every input and the inverse capacitance agree
with a direct solve there within `tol` (relative to the largest entry).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace

import numpy as np
import scipy.linalg as la

from taxel.fem import linalg
from ._model import DynamicModel
from taxel.fem.constitution import Relaxation
from ._sweep import project


@dataclass
class ProjectedModel:
    """The projected second-order model (all matrices dense, basis coordinates)."""

    parts: dict            # kind -> (r, r) real
    relax: Relaxation      # the causal loss law (fem.constitution)
    M: np.ndarray          # (r, r)
    mech: np.ndarray       # (r, r) the mechanical parts (Rayleigh beta acts on them)
    alpha: float
    beta: float
    F: np.ndarray          # (r, m) inputs, per newton
    Be: np.ndarray         # (r, na) unit charges
    E: np.ndarray          # (na, r) electrode potentials
    u_cols: np.ndarray     # (r,) bool: columns on displacements only (the rest massless)
    names: list[str]       # electrodes
    error: float           # measured relative error at the check frequencies
    checks: list = field(default_factory=list)     # (f, error)
    seconds: float = 0.0

    @property
    def order(self) -> int:
        return self.M.shape[0]

    def kappa(self, w: float) -> dict:
        k = self.relax.kappa(w)
        return {n: k.get(n, 1.0) for n in self.parts}

    def dynamic_stiffness(self, w: float) -> np.ndarray:
        kap = self.kappa(w)
        K = sum(kap[k] * P for k, P in self.parts.items())
        return K - w ** 2 * self.M + 1j * w * (self.alpha * self.M + self.beta * self.mech)


def direct_ports(dm: DynamicModel, loads: np.ndarray, f_hz: float):
    """(V_oc (na, m), C^-1 (na, na)) at one frequency by a direct complex solve of the full model."""
    B = np.column_stack([loads, dm.Be]).astype(complex)
    X, _ = linalg.scaled_solver(dm.K(2 * np.pi * f_hz), dm.red.is_u, dm.method)(B)
    E = X[dm.red.nf:]
    return E[:, :loads.shape[1]], E[:, loads.shape[1]:]


def ports(red: ProjectedModel, freqs) -> tuple[np.ndarray, np.ndarray]:
    """Reduced (V_oc (nf, na, m), C^-1 (nf, na, na)) over frequencies (Hz)."""
    freqs = np.atleast_1d(np.asarray(freqs, float))
    m = red.F.shape[1]
    V = np.zeros((len(freqs), len(red.names), m), complex)
    Ci = np.zeros((len(freqs), len(red.names), len(red.names)), complex)
    rhs = np.column_stack([red.F, red.Be])
    for i, f in enumerate(freqs):
        X = red.E @ np.linalg.solve(red.dynamic_stiffness(2 * np.pi * f), rhs)
        V[i], Ci[i] = X[:, :m], X[:, m:]
    return V, Ci


def _error(a, b):
    return max(np.abs(a[0] - b[0]).max() / np.abs(b[0]).max(), np.abs(a[1] - b[1]).max() / np.abs(b[1]).max())


def basis(dm: DynamicModel, loads: np.ndarray, shifts_hz, moments: int, previous=None) -> np.ndarray:
    """Real basis spanning the block Krylov spaces {A_j^-1 B, (A_j^-1 M) A_j^-1 B, ...} of
    the damped operator A_j = K(w_j) (complex: loss factors and Rayleigh at the shift
    w_j = 2 pi f_j), B = [F, B_e]: real and imaginary parts as columns, displacement
    and pressure/potential rows apart (as fem.dynamics.krylov, so the reduced mass is
    zero on the second group and the condensation exact). Moment matching in w^2
    about each shift with the losses exact (fem.dynamics.krylov expands about real
    shifts and carries the losses to first order)."""
    D = linalg.scaling(dm.K0, dm.red.is_u)
    B = np.column_stack([loads, dm.Be]).astype(complex)
    cols = [] if previous is None else [previous / D[:, None]]
    for f in shifts_hz:
        solve = linalg.scaled_solver(dm.K(2 * np.pi * f), dm.red.is_u, dm.method)
        W = solve(B)[0]
        for _ in range(moments):
            for Z in (W.real, W.imag):
                Zs = Z / D[:, None]
                cols.append(Zs / np.maximum(np.linalg.norm(Zs, axis=0), 1e-300))
            W = solve(dm.M @ W)[0]
    W = np.hstack(cols)
    u = dm.red.is_u
    blocks = []
    for rows in (u, ~u):
        Q, R, _ = la.qr(W[rows], mode="economic", pivoting=True)
        keep = np.abs(np.diag(R)) > 1e-10 * abs(R[0, 0]) if R.size else np.zeros(0, bool)
        Z = np.zeros((len(u), keep.sum()))
        Z[rows] = Q[:, keep]
        blocks.append(Z)
    return D[:, None] * np.hstack(blocks)


def residuals(dm: DynamicModel, red: "ProjectedModel", V: np.ndarray, loads: np.ndarray, freqs) -> np.ndarray:
    """Relative residual ||K(w) V q - b|| / ||b|| of the reduced solution in the full
    model (scaled rows), the worst column, at each frequency: where to look next."""
    D = linalg.scaling(dm.K0, dm.red.is_u)
    B = np.column_stack([loads, dm.Be])
    rhs = np.column_stack([red.F, red.Be])
    out = []
    for f in freqs:
        w = 2 * np.pi * f
        q = np.linalg.solve(red.dynamic_stiffness(w), rhs)
        R = D[:, None] * (dm.K(w) @ (V @ q) - B)
        out.append((np.linalg.norm(R, axis=0) / np.linalg.norm(D[:, None] * B, axis=0)).max())
    return np.array(out)


def build(dm: DynamicModel, loads: np.ndarray, f_max: float, f_min: float = 1.0, tol: float = 1e-4,
          moments: int = 4, max_rounds: int = 8, grid: int = 40) -> ProjectedModel:
    """The reduced model of `dm` driven by the columns of `loads` (n, m). Greedy: shifts
    at 0 Hz and f_max, then, each round, the frequency of the largest residual
    (`residuals`, on `grid` log-spaced points over [f_min, f_max]) is solved
    directly; the measured error there (open-circuit voltages of every input and
    C^-1, relative to the largest entry) stops the loop below `tol`, else becomes
    the next shift. The record keeps every checked frequency and its error."""
    t0 = time.perf_counter()
    loads = np.asarray(loads, float).reshape(dm.F.shape[0], -1)
    fgrid = np.geomspace(f_min, f_max, grid)
    shifts, V, checks = [0.0, float(f_max)], None, []
    new = list(shifts)
    for _ in range(max_rounds):
        V = basis(dm, loads, new, moments, V)
        red = _project(dm, loads, V)
        res = residuals(dm, red, V, loads, fgrid)
        f_star = float(fgrid[np.argmax(res)])
        err = _error(tuple(x[0] for x in ports(red, [f_star])), direct_ports(dm, loads, f_star))
        checks.append((f_star, float(err)))
        if err <= tol:
            break
        new = [f_star]
        shifts.append(f_star)
    red.error, red.checks, red.seconds = checks[-1][1], checks, time.perf_counter() - t0
    return red


def _project(dm: DynamicModel, loads: np.ndarray, V: np.ndarray) -> ProjectedModel:
    r = project(replace(dm, F=loads), V)
    m = loads.shape[1]
    return ProjectedModel(r["parts"], dm.relax, r["M"], r["mech"] if not np.isscalar(r["mech"]) else
                   np.zeros_like(r["M"]), dm.alpha, dm.beta, r["B"][:, :m], r["B"][:, m:], r["E"], r["u_cols"],
                   list(dm.names), np.inf)
