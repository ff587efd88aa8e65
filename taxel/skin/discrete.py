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
