"""Discrete-time forms of the skin's readout dynamics h (numpy only: the runtime's).

`first_order_hold`: d + sum_k r_k / (s - l_k) at the step dt, mode by mode in closed
form (taxel.skin.readout builds the file's Ad..Dd with it; the runtime redraws a
randomized time constant with it). `diagonal_form`: the runtime's per-mode form of a
file's Ad..Dd, checked against their impulse response.
"""

from __future__ import annotations

import numpy as np

_CHECK_STEPS = 400


def first_order_hold(lam, r, d, dt):
    """(mu, w, D): d + sum r / (s - lam) by first-order hold, mode by mode: x' = l x + r u
    with u linear over a step gives H(z) = r phi2 + r (phi1 - phi2 + phi2 E) / (z - E),
    E = e^(l dt), phi1 = (E - 1) / l, phi2 = (E - 1 - l dt) / (l^2 dt)."""
    lam = np.asarray(lam, complex)
    x = lam * dt
    E = np.exp(x)
    small = np.abs(x) < 1e-3
    xs, ls = np.where(small, 1.0, x), np.where(small, 1.0, lam)
    phi1 = np.where(small, dt * (1 + x / 2 + x ** 2 / 6), (E - 1) / ls)
    phi2 = np.where(small, dt * (0.5 + x / 6 + x ** 2 / 24), (E - 1 - xs) / (xs * ls))
    return E, r * (phi1 - phi2 + phi2 * E), float((d + (r * phi2).sum()).real)


def diagonal_form(Ad, Bd, Cd, Dd) -> tuple[np.ndarray, np.ndarray] | None:
    """(lambda (k,), w (k + 1,)) of the diagonal form (module docstring), or None if it
    does not reproduce Ad..Dd's impulse response to 1e-9 of its peak."""
    lam, V = np.linalg.eig(Ad)
    try:
        b = np.linalg.solve(V, Bd[:, 0])
    except np.linalg.LinAlgError:
        return None
    cb = (Cd[0] @ V) * b
    keep = (lam.imag >= 0) & (np.abs(cb) > 0)
    lam, w = lam[keep], np.where(lam[keep].imag > 0, 2.0, 1.0) * cb[keep]
    h_ref, x = np.empty(_CHECK_STEPS), Bd[:, 0].copy()          # impulse response: Dd, then Cd Ad^(k-1) Bd
    h_ref[0] = Dd[0, 0]
    for k in range(1, _CHECK_STEPS):
        h_ref[k], x = Cd[0] @ x, Ad @ x
    h = np.empty(_CHECK_STEPS)
    h[0] = Dd[0, 0]
    h[1:] = (lam[None, :] ** np.arange(_CHECK_STEPS - 1)[:, None] @ w).real
    if not np.all(np.isfinite(h)) or np.abs(h - h_ref).max() > 1e-9 * max(np.abs(h_ref).max(), 1e-300):
        return None
    return lam, np.append(w, Dd[0, 0])


def balanced_form(lam, w, d: float, tol: float, points: int = 4096):
    """(lambda_r, w_r, error) of the diagonal form (lambda, w, d) (`diagonal_form`'s: upper
    modes, w weighted 2 for a complex pair) cut by balanced truncation to the fewest
    states whose Hankel bound 2 sum(sigma_dropped) stays within tol of the peak |H| on the
    unit circle, re-diagonalized; error the measured max |H_r - H| / max |H| on `points`
    frequencies up to the Nyquist frequency. None when nothing can be dropped or the cut
    does not hold (conjugate pairs lost, error above tol).

    In modal coordinates (z' = L z + 1 u, v = c z + d u, every conjugate listed, c = w / 2
    for a pair) the Gramians are explicit: P_ij = 1 / (1 - L_i conj(L_j)),
    Q_ij = conj(c_i) c_j / (1 - conj(L_i) L_j) (no Lyapunov solve); square-root method:
    P = Lp Lp^H, Q = Lq Lq^H (eigh, negative round-off clipped), Lq^H Lp = U S V^H, the
    first r columns T = Lp V_r S_r^(-1/2), Ti = S_r^(-1/2) U_r^H Lq^H, A_r = Ti L T."""
    lam, w = np.asarray(lam, complex), np.asarray(w, complex)
    up = lam.imag > 0
    L = np.concatenate([lam, lam[up].conj()])
    c = np.concatenate([np.where(up, w / 2, w), (w[up] / 2).conj()])
    z = np.exp(1j * np.linspace(0.0, np.pi, points))
    H = (c[None, :] / (z[:, None] - L[None, :])).sum(axis=1) + d
    peak = np.abs(H).max()

    def factor(M):
        e, V = np.linalg.eigh((M + M.conj().T) / 2)
        return V * np.sqrt(np.clip(e, 0.0, None))

    with np.errstate(all="ignore"):
        Lp = factor(1.0 / (1.0 - L[:, None] * L[None, :].conj()))
        Lq = factor(c[:, None].conj() * c[None, :] / (1.0 - L[:, None].conj() * L[None, :]))
        U, s, Vh = np.linalg.svd(Lq.conj().T @ Lp)
    if not np.all(np.isfinite(s)) or peak == 0:
        return None
    tail = 2 * np.append(np.cumsum(s[::-1])[::-1], 0.0)
    gap = np.append(s[:-1] > s[1:] * (1 + 1e-6), True)            # never cut between equal values (a pair)
    fits = np.flatnonzero((tail[1:] <= tol * peak) & gap)
    if not len(fits) or fits[0] + 1 >= len(L):
        return None
    r = int(fits[0]) + 1
    sr = np.sqrt(s[:r])
    T = (Lp @ Vh[:r].conj().T) / sr
    Ti = (U[:, :r].conj().T @ Lq.conj().T) / sr[:, None]
    mu, X = np.linalg.eig(Ti @ (L[:, None] * T))
    try:
        wr = (c @ T @ X) * np.linalg.solve(X, Ti.sum(axis=1))
    except np.linalg.LinAlgError:
        return None
    Hr = (wr[None, :] / (z[:, None] - mu[None, :])).sum(axis=1) + d
    err = float(np.abs(Hr - H).max() / peak)
    real = np.abs(mu.imag) <= 1e-9 * np.abs(mu)
    if not np.isfinite(err) or err > tol or (mu.imag > 0)[~real].sum() != (mu.imag < 0)[~real].sum():
        return None
    keep = real | (mu.imag > 0)
    return np.where(real, mu.real, mu)[keep], np.where(real, wr.real, 2 * wr)[keep], err
