r"""Contact of a rigid indenter on the top surface: geometry, gap, and the
augmented-Lagrangian contact terms with their consistent tangent (frictionless,
sticking, or Coulomb friction: fem.contact's return mapping, `_friction`).

Contact points (the press, fem.contact) are the quadrature points of the top facets, 2 per P2 edge by
default (`intorder` 3): 4 per edge over-constrain a curved punch and stall the
multiplier loop (measured once: thesis taxel, 0.02 mm travel, penalty 10 mu/h).
In 3D the points are the P2 triangles' six nodes with lumped weights (rule "nodal",
shared by neighbouring facets, fem.contact: one point per surface node): Gauss points
over-constrain the about two nodes per facet and lock the contact zone; the edge
midpoints alone (rule "midpoints") leave the vertices free to enter the punch
(benchmarks/contact_3d.py --rules).

Indenter geometry. Every shape is a *core* offset by a radius rho: a flat punch
of half-width (2D) or radius (axisymmetric, 3D) `a` with edge radius rho is the
set of points within rho of the flat core {|x_lat - c| <= a - rho, z = z_c}; a
sphere (axisymmetric, 3D) or a cylinder (2D) of radius R is the same with
rho = R and a core of zero width (its centre). With travel d (downward, from
the first touch of the undeformed top at z = z_top), z_c = z_top - d + rho.

Gap (signed distance from a surface point x = X + u to the indenter, >= 0 when
apart). The core extends upwards (the punch's wall). With L = x_lat - c,
r = |L|, q the closest core point (q_lat = L if r <= a - rho, else
(a - rho) L / r; q_z = max(z, z_c)), d = x - q:

    g = |d| - rho,   n = dg/dx = d / |d|   (outward normal of the indenter, pointing down)
    dn/dx = (I - n n^T)(I - dq/dx) / |d|,
    dq/dx = lateral block: I (r <= a - rho) or (a - rho)/r (I - e_r e_r^T);
            z: 1 above z_c (beside the wall), else 0.

Under the flat core (r <= a - rho), g = z_c - z - rho and n = -e_z exactly.
Axisymmetric: x_lat = r (the radial coordinate, c = 0); the hoop direction
carries no displacement variation, so the meridional formulas are exact.

Weak form (total Lagrangian; dA the reference area times the model's measure:
depth, 2 pi R or 1). Augmented Lagrangian energy with a multiplier estimate
lambda >= 0 (a nominal pressure, Pa) and a penalty eps (Pa/m):

    Pi_c(u) = \int 1/(2 eps) ( <lambda - eps g>_+^2 - lambda^2 ) dA
    R_c(u; du)      = - \int t_N n . du dA,      t_N = <lambda - eps g>_+
    K_c(u; du, Du)  =   \int eps H(lambda - eps g) (n . du)(n . Du) dA
                      - \int t_N du . (dn/dx) Du dA

t_N is the contact pressure (per reference area). The Heaviside factor is the
generalized derivative of <.>_+: Newton with it re-evaluated at every iterate is
the semi-smooth (active-set) Newton method, the active set being the points with
t_N > 0. The multiplier update (Uzawa) is lambda <- t_N after each converged
Newton solve; at its fixed point lambda = <lambda - eps g>_+, i.e. g >= 0,
lambda >= 0, lambda g = 0 (the exact Karush-Kuhn-Tucker conditions) for any
eps, which is why we use it rather than a pure penalty: a penalty leaves a
penetration t_N / eps that only an ill-conditioning eps removes (both measured in
tests/test_contact.py). Frictionless: no tangential traction. Assumptions: the
indenter is rigid and does not rotate; contact is checked at the quadrature
points of the top facets (Gauss-point-to-surface), or, rule "nodal", at the P2
facets' nodes with their lumped weights (node-to-surface): Simpson's 1/6, 4/6, 1/6
on an edge, and on a triangle the HRZ lumping of its consistent mass, 3/57 at each
vertex and 16/57 at each edge midpoint. A triangle's consistent weights put nothing
on its vertices (the integral of a P2 vertex function is 0), and points at its edge
midpoints alone leave the vertices free to enter the punch: 49 um on the 3D press
at 1 N (sticking), 264 um frictionless at 0.4 mm of travel (benchmarks/contact_3d.py --rules).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from skfem import BilinearForm, FacetBasis, LinearForm, asm

from taxel.fem.assembly import Indenter
from ._friction import Coulomb, Tangential, return_mapping, zone


def lateral_distance(x: np.ndarray, centre) -> np.ndarray:
    """m, the lateral distance of points x (dim, ...) from an axis through `centre` (x, y)
    (2D: |x - c|; axisymmetric: the radius)."""
    nl = x.shape[0] - 1
    c = np.asarray(centre[:nl], float).reshape((nl,) + (1,) * (x.ndim - 1))
    return np.sqrt(((x[:nl] - c) ** 2).sum(axis=0))


def gap(ind: Indenter, x: np.ndarray, z_top: float, travel: float, with_curvature=True):
    """Gap g, normal n and dn/dx at current points x (dim, ...)."""
    dim = x.shape[0]
    nl = dim - 1
    c = np.asarray(ind.centre[:nl], float).reshape((nl,) + (1,) * (x.ndim - 1))
    L = x[:nl] - c
    r = np.sqrt((L ** 2).sum(axis=0))
    zc = z_top - travel + ind.rho
    outside = r > ind.core
    scale = np.where(outside, ind.core / np.maximum(r, 1e-300), 1.0)
    above = x[nl] > zc                     # beside the punch's wall: the distance is lateral
    d = np.concatenate([L * (1 - scale), np.where(above, 0.0, x[nl] - zc)[None]])
    dist = np.sqrt((d ** 2).sum(axis=0))
    n = d / np.maximum(dist, 1e-300)
    n = np.where(outside[None], n, np.concatenate([np.zeros_like(L), -np.ones_like(r)[None]]))
    g = np.where(outside, dist, zc - x[nl]) - ind.rho
    if not with_curvature:
        return g, n, None
    eye = np.eye(dim).reshape((dim, dim) + (1,) * (x.ndim - 1))
    dq = np.zeros((dim, dim) + r.shape)
    if nl == 1:
        dq[0, 0] = np.where(outside, 0.0, 1.0)
    else:
        e = L / np.maximum(r, 1e-300)
        lat = scale * (np.eye(nl).reshape((nl, nl) + (1,) * r.ndim) - np.einsum("i...,j...->ij...", e, e))
        dq[:nl, :nl] = np.where(outside, lat, np.eye(nl).reshape((nl, nl) + (1,) * r.ndim))
    dq[nl, nl] = np.where(above, 1.0, 0.0)
    proj = eye - np.einsum("i...,j...->ij...", n, n)
    H = np.einsum("ik...,kj...->ij...", proj, eye - dq) / np.maximum(dist, 1e-300)
    H = np.where(outside, H, 0.0)
    return g, n, H


@dataclass
class ContactState:
    """Contact at the quadrature points of the top facets for one state."""

    g: np.ndarray          # m, gap (negative: penetration)
    n: np.ndarray          # indenter normal
    H: np.ndarray | None   # dn/dx
    tn: np.ndarray         # Pa, contact pressure <lambda - eps g>_+ (nominal)
    x: np.ndarray          # current positions of the points
    dA: np.ndarray         # reference area weight of each point (m^2, with the model's measure)

    fixed: np.ndarray | None = None     # a fixed active set (fem.contact), else t_N > 0
    stuck: np.ndarray | None = None     # sticking points (tied to the indenter), if any
    ts: np.ndarray | None = None        # Pa, their traction on the silicone (vector; 0 elsewhere)
    tang: Tangential | None = None      # Coulomb friction: the return mapping's tangential traction
    slip: np.ndarray | None = None      # m, Coulomb: slip distance summed over the converged steps

    @property
    def zone(self) -> np.ndarray:
        """Per point: fem.contact's OPEN (0), STICK (1) or SLIP (2); frictionless contact slips,
        sticking contact's tied points stick."""
        if self.stuck is not None:
            return np.where(self.stuck, 1, np.where(self.normal_active, 2, 0))
        return zone(self.normal_active, self.tang)

    @property
    def normal_active(self) -> np.ndarray:
        """Points in frictionless (normal) contact."""
        a = self.tn > 0 if self.fixed is None else self.fixed
        return a if self.stuck is None else a & ~self.stuck

    @property
    def active(self) -> np.ndarray:
        return self.normal_active if self.stuck is None else self.normal_active | self.stuck

    def traction(self) -> np.ndarray:
        """Pa, the indenter's traction on the silicone (dim, ...): t_N n, or t_S where stuck."""
        t = self.tn * self.n
        if self.tang is not None:
            t = t + self.tang.t
        return t if self.ts is None else t + self.ts

    @property
    def force(self) -> float:
        """N, the vertical force the silicone exerts on the indenter (up positive)."""
        return float(-(self.traction()[-1] * self.dA).sum())

    @property
    def area(self) -> float:
        """m^2 (2D: times the depth), the reference area of the material points in contact
        (under a frictionless punch material slides out, so this shrinks while the current
        contact width, `half_width`, does not)."""
        return float((self.dA * self.active).sum())

    def half_width(self, centre=(0.0, 0.0)) -> float:
        """m, the contact radius (2D: half-width) about the lateral `centre`: midway between
        the outermost active point and the next inactive point beyond it (reference positions
        plus displacement, i.e. current)."""
        r = lateral_distance(self.x, centre).ravel()
        act = self.active.ravel()
        if not act.any():
            return 0.0
        r_in = r[act].max()
        beyond = r[~act & (r > r_in)]
        return float((r_in + beyond.min()) / 2 if beyond.size else r_in)

    @property
    def max_pressure(self) -> float:
        """Pa, the largest contact pressure (nominal: per reference area)."""
        p = self.tn if self.ts is None else np.where(self.stuck, (self.ts * self.n).sum(axis=0), self.tn)
        return float(p.max(initial=0.0))

    @property
    def penetration(self) -> float:
        """m, the largest penetration (0 when none)."""
        return float(max(0.0, -self.g.min()))


@dataclass
class Stick:
    r"""Sticking contact: points tied to the indenter where they touched it.

    A stuck point's anchor moves with the indenter, a(d) = a0 - d e_z (a0: its
    position at zero travel); its traction on the silicone is the augmented
    Lagrangian t_S = lambda_S - eps (x - a(d)) (a vector: normal and tangential),
    with residual -\int t_S . du dA and tangent eps \int du . Du dA. A point sticks
    at the converged state of the load step in which it first came into contact
    (fem.contact), where it is then (on the indenter's surface to the augmented
    Lagrangian's penetration tolerance, so its traction carries over); it stays stuck (a tensile
    normal traction is an adhesive one, allowed)."""

    mask: np.ndarray          # bool per contact point
    a0: np.ndarray            # (dim, ...) anchor at zero travel
    lam: np.ndarray           # (dim, ...) multiplier (Pa)

    def anchor(self, travel: float) -> np.ndarray:
        a = self.a0.copy()
        a[-1] = a[-1] - travel
        return a

    def key(self) -> bytes:
        """What a factorization depends on besides the active set (fem.contact's chord steps)."""
        return self.mask.tobytes()


# contact points at the P2 facets' nodes, (rule, dim) -> (reference points, weights): an edge's
# three with Simpson's weights; a triangle's six HRZ-lumped (3/57 at a vertex, 16/57 at an edge
# midpoint); a triangle's edge midpoints alone (exact to degree 2, the vertices free: for comparison)
NODAL = {("nodal", 2): (np.array([[0.0, 0.5, 1.0]]), np.array([1.0, 4.0, 1.0]) / 6.0),
         ("nodal", 3): (np.array([[0.0, 1.0, 0.0, 0.5, 0.5, 0.0], [0.0, 0.0, 1.0, 0.0, 0.5, 0.5]]),
                        np.array([3.0, 3.0, 3.0, 16.0, 16.0, 16.0]) / 114.0),
         ("midpoints", 3): (np.array([[0.5, 0.5, 0.0], [0.0, 0.5, 0.5]]), np.full(3, 1.0 / 6.0))}
# the quadrilateral facets of hexahedra (meshing.hexmesh): a Q2 face's nine nodes with Simpson's
# tensor weights (1, 4, 1) x (1, 4, 1) / 36 (all positive, exact to degree 3); a Q1 face's four corners
_S = np.array([0.0, 0.5, 1.0])
NODAL_QUAD = {2: (np.array([np.repeat(_S, 3), np.tile(_S, 3)]), np.outer([1, 4, 1], [1, 4, 1]).ravel() / 36.0),
              1: (np.array([[0.0, 1.0, 0.0, 1.0], [0.0, 0.0, 1.0, 1.0]]), np.full(4, 0.25))}


class Surface:
    """The top surface's quadrature and the contact forms for one mesh and kinematics."""

    def __init__(self, mesh, element, facets, kin, z_top: float, intorder=4, rule="gauss"):
        quad = NODAL.get((rule, mesh.dim()))
        if mesh.t.shape[0] == 8:            # hexahedra: the face's nodes (Q2 or Q1)
            quad = NODAL_QUAD[2 if element.elem.maxdeg > 3 else 1] if rule == "nodal" else None
        self.fb = (FacetBasis(mesh, element, facets=facets, quadrature=quad) if quad is not None
                   else FacetBasis(mesh, element, facets=facets, intorder=intorder))
        self.kin = kin
        self.z_top = z_top
        X = np.asarray(self.fb.global_coordinates())
        self.X = X
        self.dA = np.asarray(self.fb.dx) * kin.measure(X)
        self.shape = X.shape[1:]

        def meas(w):
            return kin.measure(w.x)

        @LinearForm
        def r_c(v, w):
            return -w.tn * np.einsum("i...,i...->...", w.n, v) * meas(w)

        @BilinearForm
        def k_c(du, v, w):
            nn = w.epsH * np.einsum("i...,i...->...", w.n, v) * np.einsum("i...,i...->...", w.n, du)
            curv = w.tn * np.einsum("i...,ij...,j...->...", v, w.H, du)
            return (nn - curv) * meas(w)
        self._r, self._k = r_c, k_c
        # the vectorised terms (element arrays, scattered by fem.assembly): basis values
        # phi[f, q, i, c] of the local vector functions i at the points, their dofs
        self.phi = np.stack([np.asarray(b[0].value) for b in self.fb.basis]).transpose(2, 3, 0, 1)
        self.dofs = np.ascontiguousarray(self.fb.element_dofs.T)          # (facets, local)

    def state(self, u, ind: Indenter, travel, lam, eps, with_curvature=True, fixed=None,
              stick: Stick | Coulomb | None = None) -> ContactState:
        """The contact state; `fixed` (a boolean per point) fixes the active set: t_N = lambda - eps g
        there (even if negative) and 0 elsewhere, a smooth problem. `stick`: the sticking law's
        tied points, or the Coulomb friction state (fem.contact's return mapping)."""
        x = self.X + np.einsum("fqic,fi->cfq", self.phi, u[self.dofs])
        g, n, H = gap(ind, x, self.z_top, travel, with_curvature)
        tn = np.maximum(lam - eps * g, 0.0) if fixed is None else np.where(fixed, lam - eps * g, 0.0)
        st = ContactState(g, n, H, tn, x, self.dA)
        if fixed is not None:
            st.fixed = fixed
        if isinstance(stick, Coulomb):
            st.tang = return_mapping(stick, x, n, H, st.tn, st.normal_active, eps, travel)
            st.slip = stick.slip + np.where(st.tang.sliding, np.sqrt((st.tang.s ** 2).sum(axis=0)), 0.0)
        elif stick is not None and stick.mask.any():
            st.stuck = stick.mask
            st.tn = np.where(stick.mask, 0.0, tn)
            st.ts = np.where(stick.mask, stick.lam - eps * (x - stick.anchor(travel)), 0.0)
        return st

    def residual(self, st: ContactState) -> np.ndarray:
        return asm(self._r, self.fb, tn=st.tn, n=st.n)

    def tangent(self, st: ContactState, eps, active=None):
        """K_c; `active` overrides the Heaviside factor (a frozen active set)."""
        act = st.active if active is None else active
        return asm(self._k, self.fb, tn=st.tn, n=st.n, H=st.H, epsH=eps * act)

    # ---------------------------------------------------------------- vectorised terms
    def element_residual(self, st: ContactState) -> np.ndarray:
        """(facets, local) element residuals of R_c (= `residual`, before assembly)."""
        return -np.einsum("fq,cfq,fqic->fi", self.dA, st.traction(), self.phi)

    def element_tangent(self, st: ContactState, eps, active=None) -> np.ndarray:
        """(facets, local, local) element matrices of K_c (= `tangent`, before assembly)."""
        act = st.normal_active if active is None else active
        a = np.einsum("cfq,fqic->fqi", st.n, self.phi)                   # n . phi_i
        K = np.einsum("fqi,fq,fqj->fij", a, eps * act * self.dA, a)
        if st.stuck is not None:                                         # tied: eps phi_i . phi_j
            K += np.einsum("fqic,fq,fqjc->fij", self.phi, eps * st.stuck * self.dA, self.phi)
        if st.H is not None:
            Hphi = np.einsum("cdfq,fqjd->fqcj", st.H, self.phi)
            K -= np.einsum("fqic,fq,fqcj->fij", self.phi, st.tn * self.dA, Hphi)
        if st.tang is not None and st.tang.dt is not None:               # Coulomb: - phi_i . dt_T/dx phi_j
            dtphi = np.einsum("cdfq,fqjd->fqcj", st.tang.dt, self.phi)
            K -= np.einsum("fqic,fq,fqcj->fij", self.phi, self.dA, dtphi)
        return K

    def travel_derivatives(self, st: ContactState, eps):
        """d/d(travel) of the element residuals (facets, local) and of the force, and the
        force's element gradient dF/du (facets, local). Moving the indenter down by dd
        is moving the point up by dd: dg/dd = n_z, dn/dd = H[:, z]."""
        act = st.normal_active.astype(float)
        z = self.X.shape[0] - 1
        dtn_dd = -eps * act * st.n[z]                                  # d t_N / dd at fixed u
        dn_dd = st.H[:, z]
        dr = -np.einsum("fq,cfq,fqic->fi", dtn_dd * self.dA, st.n, self.phi) \
            - np.einsum("fq,cfq,fqic->fi", st.tn * self.dA, dn_dd, self.phi)
        dF_dd = float(-((dtn_dd * st.n[z] + st.tn * dn_dd[z]) * self.dA).sum())
        # F = -sum tn n_z dA; dtn/du_j = -eps act n . phi_j; dn_z/du_j = H[z, :] phi_j
        a = np.einsum("cfq,fqic->fqi", st.n, self.phi)
        Hz = np.einsum("dfq,fqjd->fqj", st.H[z], self.phi)
        dF_du = -np.einsum("fq,fqj->fj", -eps * act * st.n[z] * self.dA, a) \
            - np.einsum("fq,fqj->fj", st.tn * self.dA, Hz)
        if st.stuck is not None:        # t_S = lambda_S - eps (x - anchor(d)), d anchor / dd = -e_z
            w = eps * st.stuck * self.dA
            dr = dr + np.einsum("fq,fqi->fi", w, self.phi[..., z])
            dF_dd += float(w.sum())
            dF_du = dF_du + np.einsum("fq,fqj->fj", w, self.phi[..., z])
        if st.tang is not None:         # t_T depends on x + d e_z: dt_T/dd = dt_T/dx e_z
            dt = st.tang.dt
            dr = dr - np.einsum("fq,cfq,fqic->fi", self.dA, dt[:, z], self.phi)
            dF_dd -= float((dt[z, z] * self.dA).sum())
            dF_du = dF_du - np.einsum("dfq,fq,fqjd->fj", dt[z], self.dA, self.phi)
        return dr, dF_dd, dF_du
