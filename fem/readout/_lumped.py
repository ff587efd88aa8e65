r"""The thesis's 3-DoF mass-spring-damper taxel (section 3.1), errata corrected.

Degrees of freedom (downward positive): x1 top silicone, x2 piezo, x3 bottom
silicone; force F on the top mass. Newton's second law (thesis eqs. 3.2, 3.6, 3.7):

    m_t x1'' = F - k_t (x1 - x2) - b_t (x1' - x2')
    m_p x2'' = k_t (x1 - x2) + b_t (x1' - x2') - k_p (x2 - x3) - b_p (x2' - x3')
    m_b x3'' = k_p (x2 - x3) + b_p (x2' - x3') - k_b x3 - b_b x3'

State X = [x1, x1', x2, x2', x3, x3']. Errata (docs/materials.md) corrected here:
the axial stiffness is k = E A / t (eq. 3.5 has E / (t A)); in the last row of A
the coefficient of x2' (state 4) is +b_p / m_b (eq. 3.9 has -(b_s + b_p)/m_s);
the output uses the piezo deformation x2 - x3 (states 3 and 5; eq. 3.13 picks
states 2 and 3).

Parameters (A = taxel area; t_t, t_p, t_b layer thicknesses):
    masses    m = rho t A of each layer (thesis eq. 3.3);
    piezo     k_p = A / (s33^E t_p), the free patch's axial stiffness (1/s33^E = Y3);
    silicone  k = E_c A / t with the bonded-block compression modulus of Gent
              and Lindley, E_c = E (1 + 2 S^2), E = 3 mu (incompressible),
              S = A / (perimeter t) the shape factor (a bonded 4 x 4 x 1 mm pad: S = 1);
    damping   b = eta k / w_ref from the loss factors (the FEM's time-domain damping).
Charge: for a laterally free patch under normal force the short-circuit charge
is d33 F_p = d33 k_p (x2 - x3). The thesis's eq. 3.12 (e33 S3 A, thickness
strain alone) holds for a laterally clamped patch instead: with
`confined=True` the model uses that form, with constrained moduli
(c33^E for the piezo, K + 4 mu / 3 for the silicone): the limit in which a 1-D
model is exact and the FEM must agree (tests/test_dynamics.py).
Open-circuit voltage: V_oc = -Q_sc / C_p with C_p = eps33^T A / t_p (free) or
eps33^S A / t_p (confined).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import scipy.linalg as la

from taxel.fem import constitution
from taxel.fem.assembly import Damping


@dataclass
class Lumped:
    m: np.ndarray          # (3,) kg: top silicone, piezo, bottom silicone
    k: np.ndarray          # (3,) N/m: top silicone, piezo, bottom silicone
    b: np.ndarray          # (3,) N s/m
    gain: float            # C/m: Q_sc = gain (x2 - x3)
    C_p: float             # F
    force: float           # N, the scene's force amplitude

    def state_space(self):
        """(A, B, C, D): input force (N), output short-circuit charge (C)."""
        (mt, mp, mb), (kt, kp, kb), (bt, bp, bb) = self.m, self.k, self.b
        A = np.array([
            [0, 1, 0, 0, 0, 0],
            [-kt / mt, -bt / mt, kt / mt, bt / mt, 0, 0],
            [0, 0, 0, 1, 0, 0],
            [kt / mp, bt / mp, -(kt + kp) / mp, -(bt + bp) / mp, kp / mp, bp / mp],
            [0, 0, 0, 0, 0, 1],
            [0, 0, kp / mb, bp / mb, -(kp + kb) / mb, -(bp + bb) / mb],
        ])
        B = np.array([[0], [1 / mt], [0], [0], [0], [0]])
        C = np.array([[0, 0, self.gain, 0, -self.gain, 0]])
        return A, B, C, np.zeros((1, 1))

    def transfer_function(self):
        """(zeros, poles, gain) of Q_sc(s) / F(s). Zeros-poles-gain rather than
        polynomials: the poles span 1e3 to 1e10 rad/s (the stiff piezo), and
        polynomial coefficients would lose every digit."""
        A, B, C, D = self.state_space()
        n = A.shape[0]
        pencil_a = np.block([[A, B], [C, D]])
        pencil_b = np.block([[np.eye(n), np.zeros((n, 1))], [np.zeros((1, n + 1))]])
        z = la.eigvals(pencil_a, pencil_b)
        z = z[np.isfinite(z)]                          # the transmission zeros
        p = np.linalg.eigvals(A)
        s0 = 1j * np.abs(p).min()
        k = self.Q_sc([s0.imag / (2 * np.pi)])[0] / self.force * np.prod(s0 - p) / np.prod(s0 - z)
        return z, p, k

    def Q_sc(self, freqs):
        """Short-circuit charge for the model's force at frequencies (Hz):
        H = C (s I - A)^-1 B, one batched 6 x 6 solve per frequency. (The modal
        form sum_i r_i / (s - lambda_i) is faster but loses 1e-5 relative here:
        the residues of the 1e10 rad/s piezo pole cancel; measured against
        50-digit arithmetic, the direct solve is within 2e-9.)"""
        A, B, C, _ = self.state_space()
        s = 2j * np.pi * np.asarray(freqs, float)
        M = s[:, None, None] * np.eye(len(A))[None] - A[None]
        x = np.linalg.solve(M, np.broadcast_to(B.astype(complex), (len(s),) + B.shape))
        return self.force * (C @ x)[:, 0, 0]

    def V_oc(self, freqs):
        return -self.Q_sc(freqs) / self.C_p


def taxel_model(piezo: constitution.Piezo, sil: constitution.Solid, width: float, t_t: float, t_p: float,
                t_b: float, force: float, dyn: Damping = Damping(), confined: bool = False) -> Lumped:
    """The lumped model of one square taxel of `width` (m): silicone t_t above,
    piezo t_p, silicone t_b below (m), loaded by `force` (N); see the module docstring."""
    A = width ** 2
    s, d, eps_T = piezo.strain_charge()
    w_ref = 2 * np.pi * dyn.reference_frequency
    eta_p = dyn.piezo_loss if dyn.piezo_loss is not None else (1 / piezo.Qm if piezo.Qm else 0.0)

    def k_silicone(t):
        if t <= 0:
            return np.inf
        if confined:
            return (sil.K + 4 * sil.mu / 3) * A / t
        S = A / (4 * width * t)                 # shape factor of a bonded square pad
        return 3 * sil.mu * (1 + 2 * S ** 2) * A / t

    if confined:
        k_p = piezo.c[2, 2] * A / t_p
        gain = piezo.e[2, 2] * A / t_p
        C_p = piezo.eps[2, 2] * A / t_p
    else:
        k_p = A / (s[2, 2] * t_p)
        gain = d[2, 2] * k_p
        C_p = eps_T[2, 2] * A / t_p
    k = np.array([k_silicone(t_t), k_p, k_silicone(t_b)])
    # a zero-thickness silicone layer: a rigid link, modelled as a very stiff spring
    k = np.where(np.isinf(k), 1e6 * k_p, k)
    m = np.array([max(sil.rho * t_t * A, 1e-3 * piezo.rho * t_p * A), piezo.rho * t_p * A,
                  max(sil.rho * t_b * A, 1e-3 * piezo.rho * t_p * A)])
    eta = np.array([dyn.silicone_loss, eta_p, dyn.silicone_loss])
    b = eta * k / w_ref + dyn.rayleigh_beta * k + dyn.rayleigh_alpha * m
    return Lumped(m, k, b, gain, C_p, force)


def points_per_second(model: Lumped, n=200_000):
    """Frequency points per second of `Q_sc` (a benchmark figure)."""
    f = np.geomspace(1, 1e4, n)
    t = time.perf_counter()
    model.Q_sc(f)
    return n / (time.perf_counter() - t)


@dataclass
class Identified:
    """A 3-DoF model identified from the FEM, and what it was fitted to."""

    model: Lumped
    compliance: float          # m/N: the FEM's static compliance of the loaded surface (open circuit)
    charge_per_newton: float   # C/N: the FEM's static short-circuit charge per newton
    first_resonance: float     # Hz: the FEM's first resonance of the charge response
    capacitance: float         # F: the FEM's static (free) capacitance
    scales: dict               # silicone stiffness and mass scales against the seed's


def identified(seed: Lumped, compliance: float, charge_per_newton: float, first_resonance: float,
               capacitance: float, loss, peak: float | None = None) -> Identified:
    """The seed's 3-DoF structure with parameters from the FEM (section 3.1's model, FEM-informed):

    * piezo stiffness k_p as the seed's (the free patch, A / (s33^E t_p));
    * charge gain from the static charge: Q_sc = gain (x2 - x3) = gain F / k_p, so
      gain = k_p Q/F (the FEM's);
    * silicone stiffnesses k_t, k_b scaled by one factor so the springs in series give the
      FEM's static compliance: 1/k_t + 1/k_p + 1/k_b = c (the 2 mm of soft silicone
      dominate c);
    * silicone masses m_t, m_b scaled by one factor so the lowest eigenfrequency
      equals the FEM's first resonance (scipy.optimize.brentq);
    * damping b = eta k / w_1, the loss factors `loss` (top silicone, piezo, bottom) as viscous
      damping matched at that resonance; with `peak` (the FEM's |Q_sc / F| at the first
      resonance, C/N) all three scaled by one factor so the model's peak equals it (the
      FEM spreads the load over more than one mode: its peak is lower than one mode's);
      C_p the FEM's static capacitance.
    Statically exact by construction (charge and compliance); dynamically a one-mode fit."""
    from scipy.optimize import brentq
    kt, kp, kb = seed.k
    rest = compliance - 1 / kp
    if rest <= 0 or charge_per_newton == 0:
        raise ValueError("the FEM's compliance is below the piezo's alone: no silicone stiffness fits it")
    s_k = (1 / kt + 1 / kb) / rest
    k = np.array([kt * s_k, kp, kb * s_k])
    w1 = 2 * np.pi * first_resonance

    def first(s_m):
        m = np.array([seed.m[0] * s_m, seed.m[1], seed.m[2] * s_m])
        K = np.array([[k[0], -k[0], 0], [-k[0], k[0] + k[1], -k[1]], [0, -k[1], k[1] + k[2]]])
        return np.sqrt(la.eigvalsh(K, np.diag(m)).min()) - w1

    s_m = brentq(first, 1e-6, 1e6, xtol=1e-12, rtol=1e-12)
    m = np.array([seed.m[0] * s_m, seed.m[1], seed.m[2] * s_m])
    b = np.asarray(loss, float) * k / w1
    model = Lumped(m, k, b, charge_per_newton * kp, capacitance, seed.force)
    s_b = 1.0
    if peak is not None:
        def excess(log_s):
            lm = Lumped(m, k, b * np.exp(log_s), model.gain, capacitance, 1.0)
            return abs(lm.Q_sc([first_resonance])[0]) - peak
        if excess(np.log(1e-3)) > 0 > excess(np.log(1e4)):
            s_b = float(np.exp(brentq(excess, np.log(1e-3), np.log(1e4), xtol=1e-10)))
        model = Lumped(m, k, b * s_b, model.gain, capacitance, seed.force)
    return Identified(model, compliance, charge_per_newton, first_resonance, capacitance,
                      {"silicone_stiffness": float(s_k), "silicone_mass": float(s_m), "damping": s_b})
