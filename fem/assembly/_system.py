"""Assembly of the coupled linear system of a Problem (weak forms: fem.assembly).

Unknowns: displacement u everywhere (P2, or P1 + bubble with order 1 and mixed
solids), one P1 pressure per solid region (mixed u-p), and the electric
potential phi only in the piezo bodies. The full vector is [u, p_region..., phi].

The matrix is kept split by kind ("elastic:<region>" piezo stiffness,
"coupling", "dielectric:<region>", "shear:<region>" / "volumetric:<region>"
solids, "constraint" the u-p coupling), so that dynamics can give each kind its
own loss factor; A is their sum. With `problem.hyperelastic`, solid regions with
Yeoh data are left out of A: fem.hyperelastic adds their state-dependent residual and
tangent.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from skfem import (ElementHex0, ElementHex1, ElementHex2, ElementTetMini, ElementTetP1, ElementTetP2,
                   ElementTriMini, ElementTriP1, ElementTriP2, ElementVector, FacetBasis, MeshHex, asm)

from . import _constraints as constraints
from . import _reference_forms as forms
from taxel.fem.constitution import Kinematics
from taxel.fem.constitution import PiezoLaw, SolidLaw, law
from ._problem import Problem
from ._hex import ElementHexP1Disc
from ._bilinear import GRAD, STRAIN, VALUE, Term, assemble_terms
from ._scalar_basis import LazyBasis
from taxel.fem.constitution import Yeoh
from taxel.meshing.build import TaggedMesh


@dataclass
class System:
    problem: Problem
    A: sp.csr_matrix              # full (unconstrained) matrix
    b: np.ndarray                 # full load vector
    offsets: dict                 # block -> slice in the full vector
    ubases: dict                  # region -> restricted displacement basis
    pbases: dict                  # solid region -> restricted pressure basis
    phibases: dict                # piezo region -> restricted potential basis
    laws: dict                    # region -> PiezoLaw | SolidLaw
    fixed_u: np.ndarray           # constrained displacement DOFs (value 0)
    electrodes: constraints.Electrodes
    applied_force: float          # N, total downward load
    yeoh: dict[str, Yeoh] = field(default_factory=dict)   # regions solved as Yeoh (hyperelastic)
    parts: dict = field(default_factory=dict)             # A split by kind
    preload: np.ndarray | None = None                     # state a dynamic model is linearised about

    @property
    def kin(self) -> Kinematics:
        return self.problem.kinematics

    @property
    def tm(self) -> TaggedMesh:
        return self.problem.mesh

    @property
    def soft(self) -> set[str]:
        """The passive solid regions (the silicone), Yeoh data or not: their largest
        strain decides between a linear and a Yeoh silicone."""
        return {r for r, lw in self.laws.items() if isinstance(lw, SolidLaw)}


def elements(dim: int, order: int, mixed: bool, hex: bool = False, pressure: str = "p1"):
    """(displacement, pressure, potential) elements. Tetrahedra and triangles: P2 / P1
    (Taylor-Hood), or MINI / P1 with order 1. Hexahedra (`hex`, a structured mesh,
    meshing.hexmesh): Q2 / P1-discontinuous with order 2, Q1 / P0 (mean dilatation) with order 1;
    the pressure discontinuous (docs/theory/contact.md). `pressure`: "p0" gives Q2 / P0."""
    if hex:
        if order == 2:
            return ElementVector(ElementHex2()), ElementHex0() if pressure == "p0" else ElementHexP1Disc(), ElementHex2()
        return ElementVector(ElementHex1()), ElementHex0(), ElementHex1()
    tri = dim == 2
    if order == 2:
        eu = ElementTriP2() if tri else ElementTetP2()
        return ElementVector(eu), ElementTriP1() if tri else ElementTetP1(), eu
    p1 = ElementTriP1() if tri else ElementTetP1()
    eu = (ElementTriMini() if tri else ElementTetMini()) if mixed else p1
    return ElementVector(eu), p1, p1


def assemble(problem: Problem) -> System:
    """The full linear system, its load, supports and electrodes."""
    tm, kin, disc = problem.mesh, problem.kinematics, problem.discretization
    mesh = tm.mesh
    hexa = isinstance(mesh, MeshHex)
    eu, ep, ephi = elements(mesh.dim(), disc.order, disc.mixed, hexa, disc.hex_pressure)
    q = 4 if not hexa else 2 * disc.order + 1     # Gauss 2 / 3 points per direction: Q1 / Q2 exact
    # LazyBasis: no table of the shape functions at every point (32 kB per P2 tetrahedron);
    # one DOF numbering and one set of DOF locations per element for all regions
    first: dict[int, LazyBasis] = {}

    def basis(elem, elems):
        b = LazyBasis(mesh, elem, elems, q, first.get(id(elem)))
        first.setdefault(id(elem), b)
        return b
    ubases, pbases, phibases, laws, yeoh = {}, {}, {}, {}, {}
    for region, (mname, poling) in tm.materials.items():
        try:
            lw = laws[region] = law(problem.materials[mname], kin, poling)
        except ValueError as exc:
            raise ValueError(f"{mname}: {exc}") from None
        elems = tm.regions[region]
        ubases[region] = basis(eu, elems)
        if isinstance(lw, PiezoLaw):
            phibases[region] = basis(ephi, elems)
            continue
        if disc.mixed and lw.kappa != 0:    # kappa = 0 (plane stress, nu = 0): p = 0, nothing to constrain
            pbases[region] = basis(ep, elems)
        if problem.hyperelastic and lw.yeoh is not None:
            yeoh[region] = lw.yeoh

    Nu = next(iter(ubases.values())).N
    Np1 = next(iter(pbases.values())).N if pbases else 0
    Nphi = next(iter(phibases.values())).N if phibases else 0
    offsets = {"u": slice(0, Nu)}
    n = Nu
    for region in pbases:
        offsets[("p", region)] = slice(n, n + Np1)
        n += Np1
    offsets["phi"] = slice(n, n + Nphi)
    n += Nphi

    terms = []                     # (kind, region, Term, sign, row offset, column offset, mirrored)
    o_u, o_phi = offsets["u"].start, offsets["phi"].start
    for region, lw in laws.items():
        ub = ubases[region]
        if isinstance(lw, PiezoLaw):
            phib = phibases[region]
            terms += [(f"elastic:{region}", region, Term(ub, STRAIN, lw.c, ub, STRAIN), 1.0, o_u, o_u, False),
                      ("coupling", region, Term(ub, STRAIN, lw.e.T, phib, GRAD), 1.0, o_u, o_phi, True),
                      (f"dielectric:{region}", region, Term(phib, GRAD, lw.eps, phib, GRAD), -1.0, o_phi, o_phi,
                       False)]
        elif region in yeoh:
            continue
        elif region in pbases:
            pb, o_p = pbases[region], offsets[("p", region)].start
            normal = np.zeros((kin.n_voigt, 1))
            normal[: kin.normal] = 1.0
            dev = 2 * lw.mu * (np.diag(kin.shear_weights) - lw.beta * normal @ normal.T)
            terms += [(f"shear:{region}", region, Term(ub, STRAIN, dev, ub, STRAIN), 1.0, o_u, o_u, False),
                      ("constraint", region, Term(ub, STRAIN, normal, pb, VALUE), 1.0, o_u, o_p, True),
                      (f"volumetric:{region}", region, Term(pb, VALUE, np.array([[1 / lw.kappa]]), pb, VALUE),
                       -1.0, o_p, o_p, False)]
        else:
            terms.append((f"shear:{region}", region, Term(ub, STRAIN, lw.c, ub, STRAIN), 1.0, o_u, o_u, False))
    parts = assemble_terms(terms, kin, (n, n))
    A = sum(parts.values()) if parts else sp.csr_matrix((n, n))

    b, force = load_vector(problem, eu, n)
    fixed_u = constraints.supports(problem, next(iter(ubases.values())))
    electrodes = constraints.electrodes(problem, phibases, offsets["phi"].start)
    logging.getLogger(__name__).info("assembled: %d elements, %d unknowns, %d matrix entries",
                                     mesh.nelements, n, A.nnz)
    return System(problem, A, b, offsets, ubases, pbases, phibases, laws, fixed_u, electrodes, force,
                  yeoh, parts)


def place(blocks, offsets, n) -> sp.csr_matrix:
    """An n x n matrix from (row block, column block, matrix) triples."""
    coo = [sp.coo_matrix(M) for *_, M in blocks]
    if not coo:
        return sp.csr_matrix((n, n))
    rows = np.concatenate([m.row + offsets[r].start for (r, _, _), m in zip(blocks, coo)])
    cols = np.concatenate([m.col + offsets[c].start for (_, c, _), m in zip(blocks, coo)])
    vals = np.concatenate([m.data for m in coo])
    return sp.csr_matrix((vals, (rows, cols)), shape=(n, n))


def load_vector(problem: Problem, eu, n):
    """Full load vector (downward traction on the "load" facets) and the total force (N).

    A force F is spread as p(x) = F s(x) / int s, s the profile (1, or the
    Hertzian sqrt(1 - r^2/a^2) over the load patch), so the resultant is F exactly."""
    tm, kin, ld = problem.mesh, problem.kinematics, problem.load
    lay = tm.layout
    fb = FacetBasis(tm.mesh, eu, facets=tm.facets["load"], intorder=4)
    patch = lay.load

    def shape(x):
        if patch is None or ld.profile == "flat":
            return np.ones_like(x[0])
        rho = np.hypot(x[0] - patch.x, x[1] - patch.y) if kin.dim == 3 else np.abs(x[0] - patch.x)
        return np.sqrt(np.clip(1 - (rho / patch.half) ** 2, 0, None))

    unit = forms.resultant(shape, kin).assemble(fb)
    if ld.force is None:
        p0, force = ld.pressure, ld.pressure * unit
    else:
        p0, force = ld.force / unit, ld.force
    b = np.zeros(n)
    b[:fb.N] = asm(forms.surface_pressure(lambda x: p0 * shape(x), kin), fb)
    return b, float(force)
