"""3D assembly rate: our vectorised assembly (fem.assembly) against FELupe, side by
side in one run, on the same P2 tetrahedral mesh with the same law and quadrature.

Second table (the issue's measure, >= 1.0): linear elasticity (E = 1 MPa, nu =
0.3) on the P2 tetrahedral mesh of the 3x3 3D array at three sizes (3, 1.5 and 1 mm
far, 0.4 x that at the taxels), set-up and assembly both. Ours: the scalar P2 basis
on the affine mesh (fem.assembly.scalar_basis: 10 reference gradients once, J^-1
and |det J| per element) and the vector stiffness from it with the DOF map 3 s + c
(fem.assembly.vector_matrix: the reference integrals once, two small products per
element, 3x3 blocks summed on the scalar DOF pairs, BSR to CSR), the code the
coupled assembly uses for its vector strain terms; FELupe: `RegionQuadraticTetra`,
`FieldContainer` and `SolidBody(LinearElastic)` `assemble.matrix()`. The same
11-point rule: scikit-fem's order-4 tetrahedron rule, passed to FELupe as a
`felupe.quadrature.Scheme` (its negative centroid weight makes FELupe report a
"negative volume": silenced). The matrices are compared after mapping FELupe's
tetra10 points (vertices, then edge midpoints) onto our DOFs (max |dK| / max |K|).
Each code runs in its own fresh processes (ROUNDS per code, alternating), REPEAT
timed runs each after one untimed one; CPU medians. Rates are displacement
unknowns per second of set-up + assembly; ratios FELupe time / ours.

Also times the full coupled assembly (fem.assembly.assemble: piezo, mixed u-p
silicone, load, supports) of the built-in 3D taxel scenes.

First table (the issue's measure): the Yeoh silicone's tangent at a deformed
state, on the P2 tetrahedral mesh of the 3D taxel at three sizes (3, 1.5 and
1 mm far, 0.4 x that at the taxel). Ours: fem.hyperelastic.YeohRegion (the scalar
shape-function gradients with the vector DOF map a * 3 + c; residual, K_uu,
K_up, K_pp of the u-p form) scattered to CSR; FELupe: `Hyperelastic(yeoh)` in a
`SolidBody` on a displacement field, `assemble.matrix()` (the displacement
tangent only, so FELupe does less work than we do). The state: a smooth
displacement (`deformed`: 10 % stretch and shear, a 20 um ripple) and p = 0, where FELupe's displacement
tangent of the Yeoh energy equals our K_uu: the two are compared after the DOF
mapping (max |dK| / max |K|). "setup" is the bases / YeohRegion and FELupe's
region and field (once per mesh), "tangent" one Newton iteration's assembly
(median of REPEAT, CPU time, the two codes alternating); "pattern" our CSR pattern
of the tangent (once per mesh, as fem.contact builds it: a Newton iteration then only
fills values). The ratios are FELupe's time / ours (>= 1: we are faster), for the
tangent and for the setup.

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/assembly_3d.py [--no-linear]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
import warnings

import numpy as np
import scipy.sparse as sp
from skfem import Basis, ElementTetP2, ElementVector
from skfem.quadrature import get_quadrature
from skfem.refdom import RefTet

import taxel
from taxel.analyses import mesh as scene_mesh
from taxel.analyses import problem
from taxel.fem.assembly import assemble
from taxel.fem.constitution import Solid3D
from taxel.fem.assembly import STRAIN, Term, assemble_terms

E, NU = 1e6, 0.3
REPEAT = 9


def interleaved(ours, theirs, repeat=REPEAT):
    """((median s, result), (median s, result)) of two functions run alternately, so
    that a change in the machine's load falls on both; CPU time (process_time: the
    shared machine's other jobs do not count, single-threaded BLAS)."""
    t1, t2 = [], []
    for _ in range(repeat):
        for fn, ts in ((ours, t1), (theirs, t2)):
            t = time.process_time()
            out = fn()
            ts.append(time.process_time() - t)
            if fn is ours:
                r1 = out
            else:
                r2 = out
    return (statistics.median(t1), r1), (statistics.median(t2), r2)


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


LINEAR_SIZES = (3e-3, 1.5e-3, 1e-3)       # the 3x3 array's mesh: far size, 0.4 x that at the taxels
ROUNDS = 3                                 # fresh processes per code and size, alternating


def linear_mesh(size):
    m = scene_mesh(taxel.load("thesis-pzt-3x3-3d").replace(**{"mesh.size": size,
                                                              "mesh.piezo_size": 0.4 * size})).mesh
    m.t2e                                      # the P2 mesh's edges: input to both (FELupe's tetra10 cells)
    return m


def linear_worker(code, size):
    """Runs in a fresh process: REPEAT (set-up, assembly) CPU times of one code, as JSON."""
    from skfem import ElementTetP2
    from taxel.fem.assembly import vector_matrix
    from taxel.fem.assembly import scalar_basis
    m, c = linear_mesh(size), isotropic_c()
    points, cells = felupe_points_cells(m)
    out = []
    for _ in range(REPEAT + 1):                # the first, untimed: imports and the heap's first growth
        t0 = time.process_time()
        basis = scalar_basis(m, ElementTetP2(), 4) if code == "ours" else felupe_setup(points, cells)
        t1 = time.process_time()
        vector_matrix(basis, c, Solid3D()) if code == "ours" else felupe_assemble(basis)
        out.append((t1 - t0, time.process_time() - t1))
    print(json.dumps(out[1:]))


def linear_compare(size):
    """One row of the linear table: the 3x3 3D array's mesh at far size `size`; ours
    (the scalar P2 basis on the affine mesh, fem.assembly.scalar_basis, and the vector
    stiffness from it, fem.assembly.vector_matrix) against FELupe (region, field,
    SolidBody assembly), set-up and assembly, CPU medians over ROUNDS fresh processes
    per code, alternating (one code's memory state does not slow the other: measured,
    running after FELupe in one process tripled our time, page faults), REPEAT each
    after one untimed run (FELupe's first run in a process is several times its next)."""
    from skfem import ElementTetP2
    from taxel.fem.assembly import vector_matrix
    from taxel.fem.assembly import scalar_basis
    times = {"ours": [], "felupe": []}
    for _ in range(ROUNDS):
        for code in times:
            env = dict(os.environ, MKL_NUM_THREADS="1", OMP_NUM_THREADS="1")
            run = subprocess.run([sys.executable, __file__, "--linear-worker", code, str(size)], env=env,
                                 capture_output=True, text=True, check=True)
            times[code] += json.loads(run.stdout.strip().splitlines()[-1])
    (t_os, t_oa), (t_fs, t_fa) = (np.median(np.array(times[k]), axis=0) for k in ("ours", "felupe"))
    m = linear_mesh(size)
    K = vector_matrix(scalar_basis(m, ElementTetP2(), 4), isotropic_c(), Solid3D())
    diff = matrix_difference(ours_setup(m), K, felupe_assemble(felupe_setup(*felupe_points_cells(m))), m)
    n = K.shape[0]
    ours, theirs = t_os + t_oa, t_fs + t_fa
    print(f"{size * 1e3:>4g} mm {m.t.shape[1]:>7} {n:>8} {t_os:>8.3f} {t_oa:>8.3f} {t_fs:>8.3f} {t_fa:>8.3f} "
          f"{n / ours:>10.3g} {n / theirs:>10.3g} {theirs / ours:>7.2f} {t_fa / t_oa:>6.2f} {diff:>9.1e}", flush=True)
    return theirs / ours


YEOH_C = (7.83e3, 0.103e3, -0.8)          # Ecoflex 00-30 (REFERENCE.md), Pa
YEOH_SIZES = (3e-3, 1.5e-3, 1e-3)


def yeoh_compare(size):
    """One row of the Yeoh table at far size `size` (piezo size 0.4 x)."""
    import felupe as fe
    from skfem import ElementTetP1
    from taxel.fem.assembly import Pattern
    from taxel.fem.constitution import Yeoh
    from taxel.fem.assembly import scalar_basis
    from taxel.fem.hyperelastic import YeohRegion
    m = scene_mesh(taxel.load("thesis-pzt-single-3d").replace(**{"mesh.size": size,
                                                                "mesh.piezo_size": 0.4 * size})).mesh
    law = Yeoh(*YEOH_C, K=2000 * YEOH_C[0])

    def ours_setup():
        sb = scalar_basis(m, ElementTetP2(), 4)           # the scalar basis: 10 functions, not 30
        pb = scalar_basis(m, ElementTetP1(), 4)
        return sb, pb, YeohRegion(sb, pb, law, Solid3D(), 3 * sb.N)

    def ours_pattern(reg, n):
        """The CSR pattern of the tangent, built once per mesh (as fem.contact does)."""
        return Pattern(sp.identity(n, format="csr"), sp.csr_matrix((n, n)),
                       {"uu": pair(reg.udofs, reg.udofs), "up": pair(reg.udofs, reg.pdofs),
                        "pu": pair(reg.pdofs, reg.udofs), "pp": pair(reg.pdofs, reg.pdofs)})
    X, W = get_quadrature(RefTet, 4)
    warnings.filterwarnings("ignore", message="Negative volumes")
    points, cells = felupe_points_cells(m)

    def fe_setup():
        region = fe.RegionQuadraticTetra(fe.Mesh(points, cells, "tetra10"), quadrature=fe.quadrature.Scheme(X.T, W))
        return fe.FieldContainer([fe.Field(region, dim=3)])
    (t_os, (sb, pb, reg)), (t_fs, field) = interleaved(ours_setup, fe_setup)
    nu = 3 * sb.N
    n = nu + pb.N
    c0 = time.process_time()
    pattern = ours_pattern(reg, n)
    t_pat = time.process_time() - c0
    perm = dof_map(ours_setup_basis(m), m)
    x = np.zeros(n)
    x[perm] = deformed(points).ravel()

    def ours_tangent():
        t = reg.terms(x)
        return pattern.matrix({"uu": t.K_uu, "up": t.K_up, "pu": t.K_up.transpose(0, 2, 1), "pp": t.K_pp})
    field[0].values[:] = x[perm].reshape(-1, 3)
    umat = fe.Hyperelastic(fe.yeoh, C10=YEOH_C[0], C20=YEOH_C[1], C30=YEOH_C[2])
    (t_ot, K), (t_ft, Kfe) = interleaved(ours_tangent, lambda: fe.SolidBody(umat, field).assemble.matrix())
    Kuu = K[:nu, :nu]
    diff = mapped_difference(Kuu, Kfe, perm)
    print(f"{size * 1e3:>4g} mm {m.t.shape[1]:>7} {nu:>8} {t_os:>8.3f} {t_pat:>8.3f} {t_ot:>8.3f} {t_fs:>8.3f} "
          f"{t_ft:>8.3f} {t_ft / t_ot:>7.2f} {t_fs / t_os:>7.2f} {(t_fs + t_ft) / (t_os + t_ot):>7.2f} "
          f"{diff:>9.1e}", flush=True)
    return t_ft / t_ot


def pair(rows, cols):
    """(rows, columns) of every element-matrix entry, (elements, local, local) each."""
    shape = (rows.shape[0], rows.shape[1], cols.shape[1])
    return np.broadcast_to(rows[:, :, None], shape), np.broadcast_to(cols[:, None, :], shape)


def deformed(points):
    """A smooth displacement (m) at the points: 10 % homogeneous stretch and shear plus
    a 20 um ripple, so every quadrature point has its own F."""
    G = np.array([[0.05, 0.02, 0.0], [-0.01, 0.03, 0.02], [0.01, 0.0, -0.1]])
    return points @ G.T + 2e-5 * np.sin(points[:, [1, 2, 0]] / 2e-3)


def ours_setup_basis(m):
    return Basis(m, ElementVector(ElementTetP2()), intorder=4)


def dof_map(ub, m) -> np.ndarray:
    """Our DOF of FELupe's DOF 3 * point + c (points: vertices, then edge midpoints)."""
    nv = m.p.shape[1]
    ours = np.zeros((nv + m.edges.shape[1], 3), int)
    ours[:nv] = ub.nodal_dofs.T
    ours[nv:] = ub.edge_dofs.T
    return ours.ravel()


def mapped_difference(K, Kfe, perm):
    import scipy.sparse as sp
    Kfe = Kfe.tocoo()
    Kmap = sp.csr_matrix((Kfe.data, (perm[Kfe.row], perm[Kfe.col])), shape=K.shape)
    return abs(K - Kmap).max() / abs(K).max()


def coupled(name):
    p = problem(taxel.load(name))
    t, sy = median_time(lambda: assemble(p))
    print(f"{name:<22} {sy.A.shape[0]:>8} unknowns (before constraints): fem.assembly.assemble {t:.2f} s, "
          f"{sy.A.shape[0] / t:.3g} unknowns/s", flush=True)


def main():
    if "--linear-worker" in sys.argv:
        i = sys.argv.index("--linear-worker")
        return linear_worker(sys.argv[i + 1], float(sys.argv[i + 2]))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scenes", nargs="*", default=["thesis-pzt-single-3d", "thesis-pzt-3x3-3d"])
    ap.add_argument("--no-linear", action="store_true", help="the Yeoh table only")
    args = ap.parse_args()
    import felupe
    print(f"FELupe {felupe.__version__}; Yeoh tangent at a deformed state, P2 tetrahedra, 11-point rule both; "
          f"median of {REPEAT}; seconds")
    print(f"{'mesh':>7} {'tets':>7} {'u dofs':>8} {'ours set':>8} {'pattern':>8} {'tangent':>8} {'FE set':>8} "
          f"{'tangent':>8} {'FE/ours':>7} {'setup':>7} {'both':>7} {'max|dK|':>9}")
    ratios = [yeoh_compare(s) for s in YEOH_SIZES]
    print(f"tangent ratio FELupe / ours: {min(ratios):.2f}-{max(ratios):.2f} (>= 1: ours is faster)\n")
    if args.no_linear:
        return
    print(f"FELupe {felupe.__version__}; the 3x3 3D array's P2 tetrahedral mesh at three sizes, linear elastic, "
          f"11-point rule both; CPU s, medians of {ROUNDS} x {REPEAT}, {ROUNDS} fresh processes per code alternating; set-up = basis (ours: scalar P2) / "
          f"region + field; rates in displacement unknowns per second of set-up + assembly")
    print(f"{'mesh':>7} {'tets':>7} {'dofs':>8} {'ours set':>8} {'asm':>8} {'FE set':>8} {'asm':>8} "
          f"{'ours u/s':>10} {'FE u/s':>10} {'FE/ours':>7} {'asm':>6} {'max|dK|':>9}")
    ratios = [linear_compare(s) for s in LINEAR_SIZES]
    print(f"set-up + assembly ratio FELupe / ours: {min(ratios):.2f}-{max(ratios):.2f} (>= 1: ours is faster)")
    print("\nfull coupled assembly (piezo + mixed u-p silicone + load + supports):")
    for name in args.scenes:
        coupled(name)


if __name__ == "__main__":
    main()
