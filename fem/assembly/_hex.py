r"""Hexahedral mixed elements for the nearly incompressible silicone (meshing.hexmesh's
structured meshes): Q2 / P1-discontinuous (order 2) and Q1 / P0 (order 1, mean dilatation).

Why. Under a flat punch the top layer of Taylor-Hood (P2 / P1) tetrahedra crushes before 1 N
frictionless (J down to 0.05 at the rim, docs/benchmarks.md), whatever the load path, penalty
or contact rule. A discontinuous pressure constrains each element's own volume change only,
not a continuous field of it shared with the neighbours; it is what the codes that press rubber
use on hexahedra (Abaqus C3D20H / C3D8H, FEBio's three-field hexahedra, FELupe's Q2 / P1-disc).
Measured (benchmarks/press_hex.py): Q1 / P0 takes the frictionless press to 1 N (J 0.18);
Q2 / P1-disc crushes too (0.556 N, J 0.073), and is the more accurate of the two per unknown
(sticking: +1.83 % at 29 686 unknowns against Q1 / P0's +4.94 % at 19 657).

Weak form (the same as the tetrahedra's, fem.hyperelastic): find u in [Q2]^3 (or [Q1]^3) and
p in P1-disc (or P0) with

    \int P(F, p) : Grad v dV = (contact, supports)                 for all v,
    \int (J - 1 - p / K) q dV = 0                                   for all q,

P = dW_iso/dF + p J F^-T (fem.constitution's Yeoh law, bulk modulus K). Because q is
discontinuous, the second equation holds element by element: on each element p is the
L2 projection of K (J - 1) onto P1 (or its mean, P0: p = K (mean J - 1), the mean
dilatation of Simo, Taylor and Pister 1985). The pair is inf-sup stable: Q2 / P1-disc
(Boffi, Brezzi and Fortin 2013, sec. 8.7), Q2 / P0 too but its single pressure per element
constrains the volume only on average (on the linear 3D taxel it reads 3.2 % low at the default
sizes against +2.4 % for P1-disc, and converges slower: benchmarks/press_hex.py --linear);
Q1 / P0 is not (its checkerboard pressure mode is harmless for the displacement).

Condensation. With element pressures local, K_pp is block diagonal (4 x 4 or 1 x 1 per
element, -\int M M^T dV / K) and the pressures could be eliminated element by element,
K_uu - K_up K_pp^-1 K_pu, before the sparse factorization. Here they are kept as unknowns (4 per
element, a tenth of the Q2 unknowns) and PARDISO's fill-reducing ordering is free to eliminate
them first (each couples one element's displacements only); condensing them by hand was not
built or measured.

P1-disc basis: 1, X - 1/2, Y - 1/2, Z - 1/2 on the reference cube [0, 1]^3. On the box
elements of meshing.hexmesh the map is affine, so these span P1 in x, y, z. The Yeoh terms
(fem.hyperelastic) and the linear forms (fem.assembly) take any scikit-fem basis; on box
elements they go through the scalar basis (fem.assembly's box_basis) as on simplices.
"""

from __future__ import annotations

import numpy as np
from skfem.element import ElementH1
from skfem.refdom import RefHex


class ElementHexP1Disc(ElementH1):
    """The discontinuous linear pressure of a hexahedron: 1, X - 1/2, Y - 1/2, Z - 1/2 on the
    reference cube (P1, not Q1: the Q2/P1-discontinuous pair is inf-sup stable, Boffi, Brezzi and
    Fortin 2013, sec. 8.7), all four interior (no continuity between elements). On the box
    elements of meshing.hexmesh the map is affine, so these span P1 in x, y, z too."""

    interior_dofs = 4
    maxdeg = 1
    dofnames = ["u"] * 4
    doflocs = np.full((4, 3), 0.5)
    refdom = RefHex

    def lbasis(self, X, i):
        if i == 0:
            return np.ones(X.shape[1:]), np.zeros_like(X)
        if i > 3:
            self._index_error()
        grad = np.zeros_like(X)
        grad[i - 1] = 1.0
        return X[i - 1] - 0.5, grad
