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
the reduced lambda* = 2 lambda mu / (lambda + 2 mu), which stays bounded (a
thin sheet is not incompressible in its plane), so plane stress does not lock.

Models and the strain vector (mesh coordinates x, z; r, z axisymmetric):

    3d            S = [u1,1, u2,2, u3,3, u2,3 + u3,2, u1,3 + u3,1, u1,2 + u2,1]
    plane         S = [ux,x, uz,z, ux,z + uz,x]               (x-z plane)
    axisymmetric  S = [ur,r, ur / r, uz,z, ur,z + uz,r]        (rr, tt, zz, rz)

Volume measure: dx (3d), depth * dA (plane), 2 pi r dA (axisymmetric), so all
forces are in N and charges in C for the whole (3D-equivalent) body.
"""

from __future__ import annotations

import numpy as np
from skfem import BilinearForm, Functional, LinearForm

PLANE = ("plane_strain", "plane_stress")


def strain(u, x, model):
    """Voigt strain (engineering shear) of a vector DiscreteField, shape (nS, ...)."""
    g = u.grad
    if model == "3d":
        return np.array([g[0, 0], g[1, 1], g[2, 2], g[1, 2] + g[2, 1], g[0, 2] + g[2, 0], g[0, 1] + g[1, 0]])
    if model == "axisymmetric":
        return np.array([g[0, 0], u[0] / x[0], g[1, 1], g[0, 1] + g[1, 0]])
    return np.array([g[0, 0], g[1, 1], g[0, 1] + g[1, 0]])


def divergence(S, model):
    """Trace of the strain: the sum of the normal components of S."""
    return S[:3].sum(axis=0) if model in ("3d", "axisymmetric") else S[0] + S[1]


def shear_weights(model):
    """Weights w with S(u) : S(v) = sum w_i S_i(u) S_i(v) (engineering shears: 1/2)."""
    return {"3d": [1, 1, 1, .5, .5, .5], "axisymmetric": [1, 1, 1, .5]}.get(model, [1, 1, .5])


def measure(x, model, depth):
    """The factor of dA (or dx) that makes an integral a 3D one."""
    if model == "axisymmetric":
        return 2 * np.pi * x[0]
    if model in PLANE:
        return depth
    return 1.0


def elastic(c, model, depth):
    """K_uu: \\int S(v) . c S(u)."""
    @BilinearForm
    def form(u, v, w):
        Su, Sv = strain(u, w.x, model), strain(v, w.x, model)
        return np.einsum("i...,ij,j...->...", Sv, c, Su) * measure(w.x, model, depth)
    return form


def piezo_coupling(e, model, depth):
    """K_uphi: \\int S(v) . e^T grad(phi); trial phi (scalar), test v (vector)."""
    @BilinearForm
    def form(phi, v, w):
        return np.einsum("i...,ki,k...->...", strain(v, w.x, model), e, phi.grad) * measure(w.x, model, depth)
    return form


def dielectric(eps, model, depth):
    """K_phiphi: \\int grad(psi) . eps grad(phi)."""
    @BilinearForm
    def form(phi, psi, w):
        return np.einsum("i...,ij,j...->...", psi.grad, eps, phi.grad) * measure(w.x, model, depth)
    return form


def deviatoric_shear(mu, beta, model, depth):
    """\\int 2 mu (S(v) : S(u) - beta tr S(v) tr S(u)): the unprojected part of the
    mixed silicone form (beta = 1/3: the deviatoric split, 0 in plane stress)."""
    wts = np.array(shear_weights(model))

    @BilinearForm
    def form(u, v, w):
        Su, Sv = strain(u, w.x, model), strain(v, w.x, model)
        return 2 * mu * (np.einsum("i,i...,i...->...", wts, Su, Sv)
                         - beta * divergence(Su, model) * divergence(Sv, model)) * measure(w.x, model, depth)
    return form


def pressure_divergence(model, depth):
    """B: \\int p div v; trial p (scalar), test v (vector)."""
    @BilinearForm
    def form(p, v, w):
        return p * divergence(strain(v, w.x, model), model) * measure(w.x, model, depth)
    return form


def pressure_mass(kappa, model, depth):
    """M / kappa: \\int p q / kappa."""
    @BilinearForm
    def form(p, q, w):
        return p * q / kappa * measure(w.x, model, depth)
    return form


def surface_pressure(profile, model, depth, dim):
    """\\int -p(x) n_z . v over the loaded top (n_z = +1): a downward traction.

    `profile(x)` gives the pressure (Pa) at the quadrature points.
    """
    @LinearForm
    def form(v, w):
        return -profile(w.x) * v[dim - 1] * measure(w.x, model, depth)
    return form


def resultant(profile, model, depth):
    """\\int p(x) over a facet set: the total force of a pressure profile (N)."""
    @Functional
    def form(w):
        return profile(w.x) * measure(w.x, model, depth)
    return form


def mass(rho, model, depth):
    """M: \\int rho v . u."""
    @BilinearForm
    def form(u, v, w):
        return rho * np.einsum("i...,i...->...", u, v) * measure(w.x, model, depth)
    return form
