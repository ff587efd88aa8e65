r"""Coulomb friction between the rigid indenter and the silicone: the return mapping
of an augmented Lagrangian on the tangential multipliers, and its consistent tangent.

Kinematics. Each contact point has an anchor a: the indenter's material point it sat
on at the last converged load step (a rigid indenter translating by its travel d,
a(d) = a0 - d e_z). Its slip since then is the tangential part of x - a,

    s = P (x - a(d)),   P = I - n n^T     (n the indenter's normal at x, fem.contact.gap).

Coulomb's law (per point in normal contact, t_N > 0): the tangential traction t_T on
the silicone satisfies |t_T| <= mu t_N; where |t_T| < mu t_N the point sticks (s = 0),
where it slips t_T opposes the slip, t_T = -mu t_N s / |s|. Open points carry none.

Augmented Lagrangian (Simo and Laursen 1992, Comput. Struct. 42:97; Alart and Curnier
1991): with the tangential multiplier lambda_T (Pa, the last estimate of t_T) and the
penalty eps (Pa/m, the normal one), the trial traction and the return mapping are

    t_tr = P (lambda_T - eps (x - a)),            f = |t_tr| - mu t_N,
    t_T  = t_tr                   (f <= 0: stick),
    t_T  = mu t_N t_tr / |t_tr|   (f > 0:  slip),

t_N = <lambda_N - eps g>_+ the normal pressure (fem.contact). The weak form adds
to the normal contact's residual

    R_T(u; du) = - \int t_T . du dA,

and its tangent is K_T(u; du, Du) = - \int du . (dt_T/dx) Du dA with, writing
w = lambda_T - eps (x - a) and H = dn/dx,

    stick:  dt_T/dx = - eps P - (n . w) H - n (H^T w)^T
    slip:   dt_T/dx = mu e (dt_N/dx)^T + (mu t_N / |t_tr|) (I - e e^T) dt_tr/dx,
            e = t_tr / |t_tr|,  dt_N/dx = - eps n  (active points),

(dt_tr/dx the stick expression): consistent, and nonsymmetric where points slip
(the mu e (dt_N/dx)^T term; fem.linalg factorizes it in PARDISO's nonsymmetric mode).
The switch between stick and slip is decided by the return mapping at every Newton
iterate: a semi-smooth Newton method, as for the normal active set. The Uzawa update
after a converged Newton solve is lambda_T <- t_T, with the normal one; at its fixed
point stick points do not move on the indenter (s = 0 to the gap tolerance) and slip
points carry mu t_N against their slip, for any eps: the exact Coulomb conditions.
After each converged load step every point is re-anchored where it is (a0 = x + d e_z)
and keeps lambda_T = t_T (the classical incremental return mapping: the slip of a step
is measured from the step's start); the slip distance |s| of slipping points is summed
over the steps (`Coulomb.slip`, m).

Everything depends on x and d through x + d e_z (the gap, the normal and the anchor
offset), so dt/dd = (dt/dx) e_z: the travel derivatives (predictor, force control)
reuse the tangent's column. mu = 0 is frictionless; mu -> infinity sticking
without adhesion (the "sticking" law, fem.contact.Stick, also keeps tensile tractions).
Assumptions: isotropic Coulomb friction, one coefficient (static = kinetic), the
indenter rigid and translating only (no rotation). This return mapping is the Uzawa path's
(Options.solver "uzawa"); the default solve takes the same conditions as one nonsmooth
equation with the tractions as unknowns (fem.contact._alart_curnier).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# per contact point, the slip zone's states (`Coulomb.zone`, fem.contact.SlipZone)
OPEN, STICK, SLIP = 0, 1, 2


@dataclass
class Coulomb:
    """The Coulomb friction state of every contact point between load steps."""

    mu: float                 # the Coulomb coefficient (>= 0)
    a0: np.ndarray            # (dim, ...) anchors at zero travel
    lam: np.ndarray           # (dim, ...) tangential multipliers (Pa)
    slip: np.ndarray          # (...) m, slip distance summed over the converged steps

    def anchor(self, travel: float) -> np.ndarray:
        a = self.a0.copy()
        a[-1] = a[-1] - travel
        return a

    def key(self) -> bytes:
        """What a factorization depends on besides the active set (fem.contact's chord steps)."""
        return b"coulomb"

    def copy(self) -> "Coulomb":
        return Coulomb(self.mu, self.a0.copy(), self.lam.copy(), self.slip.copy())


@dataclass
class Tangential:
    """The return mapping's result at one state."""

    t: np.ndarray             # (dim, ...) Pa, tangential traction on the silicone
    dt: np.ndarray | None     # (dim, dim, ...) dt_T/dx (None without the normal's curvature)
    sliding: np.ndarray       # bool, points in normal contact that slip
    sticking: np.ndarray      # bool, points in normal contact that stick
    s: np.ndarray             # (dim, ...) m, slip since the anchor


def return_mapping(c: Coulomb, x, n, H, tn, active, eps, travel) -> Tangential:
    """t_T and dt_T/dx of every point (module docstring); `active` the points in normal
    contact, `tn` their pressure, H = dn/dx or None (no tangent)."""
    w = c.lam - eps * (x - c.anchor(travel))
    nw = (n * w).sum(axis=0)
    tr = w - n * nw
    s = -(tr - (c.lam - n * (n * c.lam).sum(axis=0))) / eps          # P (x - a)
    norm = np.sqrt((tr ** 2).sum(axis=0))
    bound = c.mu * np.where(active, np.maximum(tn, 0.0), 0.0)
    stick = active & (norm <= bound)
    slip = active & ~stick
    scale = np.divide(bound, norm, out=stick.astype(float), where=slip)     # 1 stick, mu t_N / |t_tr| slip, 0 open
    t = tr * scale
    if H is None:
        return Tangential(t, None, slip, stick, s)
    dim = x.shape[0]
    eye = np.eye(dim).reshape((dim, dim) + (1,) * (x.ndim - 1))
    P = eye - np.einsum("i...,j...->ij...", n, n)
    Hw = np.einsum("k...,kj...->j...", w, H)
    dtr = -eps * P - nw * H - np.einsum("i...,j...->ij...", n, Hw)
    e = tr / np.maximum(norm, 1e-300)
    Q = eye - np.einsum("i...,j...->ij...", e, e)
    dslip = (c.mu * np.einsum("i...,j...->ij...", e, -eps * n)
             + scale * np.einsum("ik...,kj...->ij...", Q, dtr))
    dt = np.where(stick, dtr, np.where(slip, dslip, 0.0))
    return Tangential(t, dt, slip, stick, s)


def zone(active, tang: Tangential | None) -> np.ndarray:
    """The slip zone's state per point: OPEN, STICK or SLIP (frictionless contact slips)."""
    if tang is None:
        return np.where(active, SLIP, OPEN)
    return np.where(tang.sticking, STICK, np.where(tang.sliding, SLIP, OPEN))
