"""The vectorised assembly (fem.assembly) equals scikit-fem's BilinearForms, block by
block, to round-off: every model type, both element orders, mixed and
displacement-only silicone, piezo and plate layouts.

The oracle is fem/assembly/_reference_forms.py: the weak forms written once more as
scikit-fem BilinearForms (exported as fem.assembly.elastic, piezo_coupling,
dielectric, deviatoric_shear, pressure_divergence, pressure_mass, mass) and
assembled by scikit-fem's own `asm`; the library assembles with the vectorised forms
of fem/assembly/_bilinear.py, so the two are independent codes of one weak form.
FELupe is the second oracle for the 3D elastic matrix (benchmarks/assembly_3d.py)."""

import numpy as np
import pytest
import scipy.sparse as sp
from skfem import asm

from taxel.analyses import problem
from taxel.fem import assembly
from taxel.fem.assembly import assemble
from taxel.fem.constitution import PiezoLaw
from taxel.scene import load


def reference_parts(sy):
    """Every block kind assembled by scikit-fem from the forms of fem.assembly."""
    n, kin, off = sy.A.shape[0], sy.kin, sy.offsets
    parts = {}

    def put(kind, r0, c0, M, mirrored=False):
        M = sp.coo_matrix(M)
        blocks = [(M.row + r0, M.col + c0, M.data)] + ([(M.col + c0, M.row + r0, M.data)] if mirrored else [])
        for r, c, v in blocks:
            P = sp.csr_matrix((v, (r, c)), shape=(n, n))
            parts[kind] = parts[kind] + P if kind in parts else P
    for region, lw in sy.laws.items():
        ub = sy.ubases[region]
        if isinstance(lw, PiezoLaw):
            pb = sy.phibases[region]
            put(f"elastic:{region}", 0, 0, asm(assembly.elastic(lw.c, kin), ub))
            put("coupling", 0, off["phi"].start, asm(assembly.piezo_coupling(lw.e, kin), pb, ub), True)
            put(f"dielectric:{region}", off["phi"].start, off["phi"].start, -asm(assembly.dielectric(lw.eps, kin), pb))
        elif region in sy.yeoh:
            continue
        elif region in sy.pbases:
            pb, o = sy.pbases[region], off[("p", region)].start
            put(f"shear:{region}", 0, 0, asm(assembly.deviatoric_shear(lw.mu, lw.beta, kin), ub))
            put("constraint", 0, o, asm(assembly.pressure_divergence(kin), pb, ub), True)
            put(f"volumetric:{region}", o, o, -asm(assembly.pressure_mass(lw.kappa, kin), pb))
        else:
            put(f"shear:{region}", 0, 0, asm(assembly.elastic(lw.c, kin), ub))
    return parts


CASES = [
    ("thesis-pzt-single-2d", {}),
    ("thesis-pzt-single-2d", {"model.type": "axisymmetric"}),
    ("thesis-pzt-single-2d", {"model.type": "plane_stress"}),
    ("thesis-pzt-single-2d", {"mesh.order": 1}),
    ("thesis-pzt-single-2d", {"mesh.formulation": "displacement"}),
    ("thesis-pvdf-single-2d", {"mesh.order": 1, "mesh.formulation": "displacement"}),
    ("thesis-pzt-single-3d", {}),
    ("thesis-pzt-single-3d", {"mesh.order": 1}),
    ("thesis-pvdf-single-3d", {"mesh.formulation": "displacement", "mesh.size": "1 mm"}),
]


@pytest.mark.parametrize("name,changes", CASES)
def test_vectorised_blocks_equal_scikit_fem_forms(name, changes):
    sy = assemble(problem(load(name).replace(**changes)))
    ref = reference_parts(sy)
    assert set(sy.parts) == set(ref)
    for kind, R in ref.items():
        d = abs(sy.parts[kind] - R).max()
        assert d <= 1e-12 * abs(R).max(), (kind, d / abs(R).max())


def _assembly_bench():
    """benchmarks/assembly_3d.py (FELupe's assembly and the DOF map) and the 2 mm P2 mesh
    of the 3D thesis taxel; skipped without FELupe."""
    pytest.importorskip("felupe")
    import importlib.util
    from pathlib import Path
    from taxel.analyses import mesh
    spec = importlib.util.spec_from_file_location(
        "assembly_3d", Path(__file__).resolve().parents[1] / "benchmarks" / "assembly_3d.py")
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    return bench, mesh(load("thesis-pzt-single-3d").replace(**{"mesh.size": "2 mm"})).mesh


def test_3d_p2_stiffness_equals_felupe_on_the_same_mesh():
    """Independent code: FELupe's LinearElastic SolidBody on the same tetra10 mesh
    and quadrature gives the same matrix (benchmarks/assembly_3d.py maps the DOFs)."""
    bench, m = _assembly_bench()
    ub = bench.ours_setup(m)
    K = bench.ours_assemble(ub, bench.isotropic_c())
    Kfe = bench.felupe_assemble(bench.felupe_setup(*bench.felupe_points_cells(m)))
    assert bench.matrix_difference(ub, K, Kfe, m) < 1e-12


def test_scalar_basis_stiffness_equals_felupe_and_scikit_fem():
    """The affine scalar-basis path (fem.assembly.scalar_basis + vector_matrix: the
    reference integrals once, J^-1 per element, blocks scattered on the scalar DOFs)
    gives FELupe's matrix and the vector-basis assembly's on the same mesh."""
    from skfem import ElementTetP2
    from taxel.fem.assembly import vector_matrix
    from taxel.fem.assembly import scalar_basis
    from taxel.fem.constitution import Solid3D
    bench, m = _assembly_bench()
    ub = bench.ours_setup(m)
    rng = np.random.default_rng(1)
    D = rng.random((6, 6))
    D = D @ D.T                                   # a general (anisotropic) law, not only the isotropic one
    K = vector_matrix(scalar_basis(m, ElementTetP2(), 4), D, Solid3D())
    R = bench.ours_assemble(ub, D)
    assert K.shape == R.shape and abs(K - R).max() <= 1e-12 * abs(R).max()
    Kiso = vector_matrix(scalar_basis(m, ElementTetP2(), 4), bench.isotropic_c(), Solid3D())
    Kfe = bench.felupe_assemble(bench.felupe_setup(*bench.felupe_points_cells(m)))
    assert bench.matrix_difference(ub, Kiso, Kfe, m) < 1e-12


def test_scalar_basis_serves_the_yeoh_terms_as_scikit_fem_bases_do():
    """fem.hyperelastic.YeohRegion on ScalarBasis objects (P2 displacement, P1 pressure)
    gives the residual and tangent it gives on scikit-fem's scalar bases."""
    from skfem import Basis, ElementTetP1, ElementTetP2
    from taxel.analyses import mesh
    from taxel.fem.assembly import scalar_basis
    from taxel.fem.constitution import Solid3D
    from taxel.fem.constitution import Yeoh
    from taxel.fem.hyperelastic import YeohRegion
    m = mesh(load("thesis-pzt-single-3d").replace(**{"mesh.size": "2 mm"})).mesh
    law = Yeoh(7.83e3, 0.103e3, -0.8, K=2000 * 7.83e3)
    out = []
    for u, p in ((scalar_basis(m, ElementTetP2(), 4), scalar_basis(m, ElementTetP1(), 4)),
                 (Basis(m, ElementTetP2(), intorder=4), Basis(m, ElementTetP1(), intorder=4))):
        reg = YeohRegion(u, p, law, Solid3D(), 3 * u.N)
        x = 1e-7 * np.sin(np.arange(3 * u.N + p.N))        # strains ~1e-3 on 2 mm elements
        out.append(reg.terms(x))
    for k in ("r_u", "r_p", "K_uu", "K_up", "K_pp"):
        a, b = getattr(out[0], k), getattr(out[1], k)
        assert np.abs(a - b).max() <= 1e-12 * np.abs(b).max(), k


def test_lean_basis_interpolates_and_numbers_as_scikit_fem():
    """fem.assembly.LazyBasis (no table of the shape functions) interpolates a field
    through the scalar functions as scikit-fem's Basis does from its table (vector P2,
    P2, P1, on a subset of the elements), with the same DOFs; bases made `like` another
    share its numbering and DOF locations."""
    from skfem import Basis, ElementTetP1, ElementTetP2, ElementVector, MeshTet
    from taxel.fem.assembly import LazyBasis
    m = MeshTet.init_tensor(np.linspace(0, 1, 4), np.linspace(0, 2, 3), np.linspace(0, 0.5, 3))
    rng = np.random.default_rng(1)
    m = MeshTet(m.p + 0.05 * rng.standard_normal(m.p.shape), m.t)
    elems = np.arange(0, m.nelements, 2)
    for e in (ElementVector(ElementTetP2()), ElementTetP2(), ElementTetP1()):
        ref = Basis(m, e, elements=elems, intorder=4)
        first = LazyBasis(m, e, np.arange(1, m.nelements, 2), 4)
        lean = LazyBasis(m, e, elems, 4, like=first)
        assert lean.scalar is not None and lean._table is None
        assert lean.dofs is first.dofs and lean.doflocs is first.doflocs
        assert np.array_equal(lean.element_dofs, ref.element_dofs) and np.allclose(lean.doflocs, ref.doflocs)
        w = rng.standard_normal(ref.N)
        a, b = lean.interpolate(w), ref.interpolate(w)
        assert np.allclose(np.asarray(a), np.asarray(b), rtol=0, atol=1e-12 * np.abs(np.asarray(b)).max())
        assert np.allclose(a.grad, b.grad, rtol=0, atol=1e-12 * np.abs(b.grad).max())
        assert lean._table is None                          # interpolate did not build it
        assert np.allclose(lean.basis[3][0].grad, ref.basis[3][0].grad)   # built on demand, as scikit-fem's
