"""3D assembly rate: our vectorised assembly (fem.bilinear) against FELupe, side by
side in one run, on the same P2 tetrahedral mesh with the same law and quadrature.

Mesh: the gmsh mesh of a built-in 3D scene (all its elements, one material).
Law: isotropic linear elasticity (E = 1 MPa, nu = 0.3): ours the Voigt form
S(v) . c S(u) of fem.forms.elastic, FELupe `LinearElastic` in a `SolidBody`.
Quadrature: scikit-fem's order-4 tetrahedron rule (11 points), passed to FELupe
as a `felupe.quadrature.Scheme`, so both integrate the same points (the rule has a
negative centroid weight, which FELupe reports as a "negative volume": silenced).

The two stiffness matrices are compared after mapping FELupe's tetra10 points
(vertices, then edge midpoints; left-handed cells reordered) onto our DOFs: they
agree to round-off, so both codes assemble the same thing.

Times are medians of REPEAT runs: "setup" is the basis (skfem Basis: shape
function gradients at the quadrature points) or region (FELupe Region) and the
field; "assembly" the stiffness matrix from them (CSR / FELupe's sparse matrix).
Rates are displacement unknowns per second of setup + assembly.

Also times the full coupled assembly (fem.assembly.assemble: piezo, mixed u-p
silicone, load, supports) of the built-in 3D taxel scenes.

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/assembly_3d.py
"""

from __future__ import annotations

import argparse
import statistics
import warnings
import time

import numpy as np
from skfem import Basis, ElementTetP2, ElementVector
from skfem.quadrature import get_quadrature
from skfem.refdom import RefTet

import taxel
from taxel.analyses import mesh as scene_mesh
from taxel.analyses import problem
from taxel.fem.assembly import assemble
from taxel.fem.kinematics import Solid3D
from taxel.fem.bilinear import STRAIN, Term, assemble_terms

E, NU = 1e6, 0.3
REPEAT = 3


def median_time(fn, repeat=REPEAT):
    out, times = None, []
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), out


def isotropic_c():
    lam, mu = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
    n = np.array([1, 1, 1, 0, 0, 0.0])
    return lam * np.outer(n, n) + mu * np.diag([2, 2, 2, 1, 1, 1.0])


def ours_setup(m):
    return Basis(m, ElementVector(ElementTetP2()), intorder=4)


def ours_assemble(ub, c):
    return assemble_terms([("K", "all", Term(ub, STRAIN, c, ub, STRAIN), 1.0, 0, 0, False)],
                          Solid3D(), (ub.N, ub.N))["K"]


def felupe_points_cells(m):
    """tetra10 points and cells of a skfem MeshTet (edge midpoints as skfem numbers
    its edges), left-handed cells reordered (gmsh gives none)."""
    nv = m.p.shape[1]
    points = np.vstack([m.p.T, m.p[:, m.edges].mean(axis=1).T])
    cells = np.vstack([m.t, nv + m.t2e]).T
    a, b, c, d = (m.p[:, m.t[i]] for i in range(4))
    vol = np.einsum("ij,ij->j", np.cross(b - a, c - a, axis=0), d - a)
    cells[vol < 0] = cells[vol < 0][:, [0, 2, 1, 3, 6, 5, 4, 7, 9, 8]]
    return points, cells


def felupe_setup(points, cells):
    import felupe as fe
    X, W = get_quadrature(RefTet, 4)
    warnings.filterwarnings("ignore", message="Negative volumes")      # the rule's negative weight
    region = fe.RegionQuadraticTetra(fe.Mesh(points, cells, "tetra10"), quadrature=fe.quadrature.Scheme(X.T, W))
    return fe.FieldContainer([fe.Field(region, dim=3)])


def felupe_assemble(field):
    import felupe as fe
    return fe.SolidBody(fe.LinearElastic(E=E, nu=NU), field).assemble.matrix()


def matrix_difference(ub, K, Kfe, m):
    """max |K - P Kfe P^T| / max |K|, P mapping FELupe point DOFs to ours."""
    nv = m.p.shape[1]
    ours = np.zeros((nv + m.edges.shape[1], 3), int)
    ours[:nv] = ub.nodal_dofs.T
    ours[nv:] = ub.edge_dofs.T
    perm = ours.ravel()                      # FELupe DOF 3 * point + c -> our DOF
    Kfe = Kfe.tocoo()
    import scipy.sparse as sp
    Kmap = sp.csr_matrix((Kfe.data, (perm[Kfe.row], perm[Kfe.col])), shape=K.shape)
    return abs(K - Kmap).max() / abs(K).max()


def compare(name):
    m = scene_mesh(taxel.load(name)).mesh
    c = isotropic_c()
    t_ub, ub = median_time(lambda: ours_setup(m))
    t_asm, K = median_time(lambda: ours_assemble(ub, c))
    points, cells = felupe_points_cells(m)
    t_fs, field = median_time(lambda: felupe_setup(points, cells))
    t_fa, Kfe = median_time(lambda: felupe_assemble(field))
    diff = matrix_difference(ub, K, Kfe, m)
    n = ub.N
    ours_total, fe_total = t_ub + t_asm, t_fs + t_fa
    print(f"{name:<22} {m.t.shape[1]:>7} {n:>8} {t_ub:>7.2f} {t_asm:>7.2f} {t_fs:>7.2f} {t_fa:>7.2f} "
          f"{n / ours_total:>10.3g} {n / fe_total:>10.3g} {fe_total / ours_total:>6.2f} "
          f"{t_fa / t_asm:>6.2f} {diff:>9.1e}", flush=True)


def coupled(name):
    p = problem(taxel.load(name))
    t, sy = median_time(lambda: assemble(p))
    print(f"{name:<22} {sy.A.shape[0]:>8} unknowns (before constraints): fem.assembly.assemble {t:.2f} s, "
          f"{sy.A.shape[0] / t:.3g} unknowns/s", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scenes", nargs="*", default=["thesis-pzt-single-3d", "thesis-pzt-3x3-3d"])
    args = ap.parse_args()
    import felupe
    print(f"FELupe {felupe.__version__}; P2 tetrahedra, linear elastic, 11-point rule both; "
          f"median of {REPEAT}; rates in displacement unknowns per second of setup + assembly")
    print(f"{'mesh':<22} {'tets':>7} {'dofs':>8} {'ours:setup':>7} {'asm':>7} {'FE:setup':>7} {'asm':>7} "
          f"{'ours u/s':>10} {'FE u/s':>10} {'FE/ours':>6} {'asm':>6} {'max|dK|':>9}")
    for name in args.scenes:
        compare(name)
    print("\nfull coupled assembly (piezo + mixed u-p silicone + load + supports):")
    for name in args.scenes:
        coupled(name)


if __name__ == "__main__":
    main()
