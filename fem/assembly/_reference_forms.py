r"""Weak forms of linear piezoelectricity and of the nearly incompressible silicone.

Strong form (no body force, no free charge), stress-charge constitutive law:

    div T = 0,   div D = 0,   T = c S(u) + e^T grad(phi),   D = e S(u) - eps grad(phi)

with S the (Voigt, engineering-shear) strain and E = -grad(phi). Multiplying by
test functions v, psi and integrating by parts:

    \int S(v) . c S(u) + S(v) . e^T grad(phi)  = \int_{Gamma_t} t . v
    \int grad(psi) . e S(u) - grad(psi) . eps grad(phi) = -sum_k psi_k Q_k

where Q_k is the free charge on electrode k (the surface integral of D.n over
the electrode, with psi constant psi_k on it). The coupled matrix is symmetric
and indefinite:

    [ K_uu     K_uphi ] [ u   ]   [ f  ]
    [ K_uphi^T -K_phiphi ] [ phi ] = [ -Q ]

Silicone, mixed u-p (perturbed Lagrangian), T = 2 mu (S - beta tr S I) + p I,
p = kappa div u:

    \int 2 mu (S(v) : S(u) - beta div v div u) + p div v = \int t . v
    \int q div u - q p / kappa                              = 0

with beta = 1/3, kappa = K (the deviatoric/volumetric split: the same split as
the Yeoh form of fem.hyperelastic, so both discretize the small-strain limit
identically), which stays well posed as K -> infinity (Taylor-Hood P2/P1 or
MINI P1+bubble/P1 are inf-sup stable). In plane stress beta = 0 and kappa is
the plane-stress lambda* = 2 lambda mu / (lambda + 2 mu), which stays bounded (a
thin sheet is not incompressible in its plane), so plane stress does not lock.

The strain vector S and the volume measure dV of each model type come from its
kinematics object (fem.constitution): every form takes one, `kin`.
"""

from __future__ import annotations

import numpy as np
from skfem import BilinearForm, Functional, LinearForm

def elastic(c, kin):
    """K_uu: \\int S(v) . c S(u)."""
    @BilinearForm
    def form(u, v, w):
        Su, Sv = kin.strain(u, w.x), kin.strain(v, w.x)
        return np.einsum("i...,ij,j...->...", Sv, c, Su) * kin.measure(w.x)
    return form


def piezo_coupling(e, kin):
    """K_uphi: \\int S(v) . e^T grad(phi); trial phi (scalar), test v (vector)."""
    @BilinearForm
    def form(phi, v, w):
        return np.einsum("i...,ki,k...->...", kin.strain(v, w.x), e, phi.grad) * kin.measure(w.x)
    return form


def dielectric(eps, kin):
    """K_phiphi: \\int grad(psi) . eps grad(phi)."""
    @BilinearForm
    def form(phi, psi, w):
        return np.einsum("i...,ij,j...->...", psi.grad, eps, phi.grad) * kin.measure(w.x)
    return form


def deviatoric_shear(mu, beta, kin):
    """\\int 2 mu (S(v) : S(u) - beta tr S(v) tr S(u)): the unprojected part of the
    mixed silicone form (beta = 1/3: the deviatoric split, 0 in plane stress)."""
    wts = np.array(kin.shear_weights)

    @BilinearForm
    def form(u, v, w):
        Su, Sv = kin.strain(u, w.x), kin.strain(v, w.x)
        return 2 * mu * (np.einsum("i,i...,i...->...", wts, Su, Sv)
                         - beta * kin.divergence(Su) * kin.divergence(Sv)) * kin.measure(w.x)
    return form


def pressure_divergence(kin):
    """B: \\int p div v; trial p (scalar), test v (vector)."""
    @BilinearForm
    def form(p, v, w):
        return p * kin.divergence(kin.strain(v, w.x)) * kin.measure(w.x)
    return form


def pressure_mass(kappa, kin):
    """M / kappa: \\int p q / kappa."""
    @BilinearForm
    def form(p, q, w):
        return p * q / kappa * kin.measure(w.x)
    return form


def surface_pressure(profile, kin):
    """\\int -p(x) n_z . v over the loaded top (n_z = +1): a downward traction.

    `profile(x)` gives the pressure (Pa) at the quadrature points.
    """
    @LinearForm
    def form(v, w):
        return -profile(w.x) * v[kin.vertical] * kin.measure(w.x)
    return form


def resultant(profile, kin):
    """\\int p(x) over a facet set: the total force of a pressure profile (N)."""
    @Functional
    def form(w):
        return profile(w.x) * kin.measure(w.x)
    return form


def mass(rho, kin):
    """M: \\int rho v . u."""
    @BilinearForm
    def form(u, v, w):
        return rho * np.einsum("i...,i...->...", u, v) * kin.measure(w.x)
    return form
