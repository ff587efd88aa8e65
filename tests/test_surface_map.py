"""The surface map (taxel.analyses.surface.surface_map, fem.static.surface_response): the
reciprocity identity against direct solves, the mirror classes against the full model,
the map's sampling and files."""

import numpy as np
import pytest

import taxel
from taxel.analyses.model.problem import problem
from taxel.analyses.surface.surface_map import Footprint, SurfaceMap, build, map_scene
from taxel.fem import assembly, static

SMALL = {"array.rows": 1, "array.cols": 2, "mesh.size": "4 mm", "mesh.piezo_size": "2 mm", "array.margin": "2 mm", "load.taxel": [0, 0]}


@pytest.fixture(scope="module")
def small_full():
    sc = map_scene(taxel.load("thesis-pzt-3x3-3d").replace(**SMALL, **{"model.symmetry": "full"}))
    return assembly.assemble(problem(sc))


def test_reciprocity_point_forces(small_full):
    """The short-circuit charge of taxel j under a unit force along k at a top-surface
    node (direct solves, every taxel grounded) equals u_k there with 1 V on j: normal and
    shear, to 1e-8 of the largest charge."""
    sy = small_full
    driven = [k for k, s in sy.electrodes.states.items() if s != "reference"]
    # SuperLU for both sides: the identity is exact, so what is compared is the solvers' round-off;
    # PARDISO's refined residual stalls near 1e-12, which leaves a shear entry ~1e-8 of the largest
    # charge (measured 1.1e-8 against SuperLU's 2.6e-9)
    f = static.unit_voltage_fields(sy, driven, "superlu")
    ub = next(iter(sy.ubases.values()))
    top = np.unique(sy.tm.mesh.facets[:, sy.tm.facets["top"]])
    nodes = np.random.default_rng(1).choice(top, 3, replace=False)
    dofs = [ub.nodal_dofs[k, nd] for nd in nodes for k in range(3)]
    F = np.zeros((sy.A.shape[0], len(dofs)))
    F[dofs, np.arange(len(dofs))] = 1.0
    Q = static.direct_charges(sy, F, driven, "superlu")
    R = f.x[:, dofs]
    assert np.abs(Q).max() > 0
    scale = np.abs(Q).max()                  # relative to the largest charge of the set: the direct
    for k in range(3):                       # solves' residual stalls at 1e-12 (a unit nodal force)
        cols = slice(k, None, 3)             # x, y (shear) and z (normal) separately
        assert np.abs(Q[:, cols]).max() > 1e-2 * scale
        assert np.abs(Q[:, cols] - R[:, cols]).max() <= 1e-8 * scale
    # a distributed load: the scene's own pressure, f . x_j against the direct solve
    Qb = static.direct_charges(sy, sy.b, driven, "superlu")[:, 0]
    assert np.allclose(f.x @ sy.b, Qb, rtol=1e-8, atol=0)
    # the capacitance matrix against the linear solve's
    sol = static.solve_linear(sy)
    order = [sol.capacitance_names.index(k) for k in driven]
    Cs = sol.capacitance_matrix[np.ix_(order, order)]
    assert np.abs(f.capacitance - Cs).max() <= 1e-9 * np.abs(Cs).max()


def test_probe_matches_nodal_values(small_full):
    """The surface probe reads the P2 field at the nodes (a hair inside the top)."""
    sy = small_full
    ub = next(iter(sy.ubases.values()))
    x = np.random.default_rng(2).standard_normal(sy.offsets["u"].stop)
    top = np.unique(sy.tm.mesh.facets[:, sy.tm.facets["top"]])[:5]
    pts = sy.tm.mesh.p[:, top].copy()
    pts[2] -= 1e-9 * pts[2]
    u = (static.displacement_probe(sy, pts) @ x).reshape(3, -1)
    assert np.allclose(u, x[ub.nodal_dofs[:, top]], rtol=0, atol=1e-6 * np.abs(x).max())


def test_map_file_round_trip(tmp_path):
    x = np.linspace(-1e-2, 1e-2, 11)
    R = np.random.default_rng(0).standard_normal((2, 3, 11, 11)) * 1e-12
    m = SurfaceMap(x, x, ("taxel_0_0", "taxel_0_1"), R, np.diag([1e-9, 2e-9]), info={"scene": "s"},
                   centres=np.array([[-1e-3, 0], [1e-3, 0]]))
    back = SurfaceMap.from_file(m.to_file(tmp_path / "m.npz"))
    for name in ("x", "y", "charge_per_newton", "capacitance", "centres"):
        assert np.array_equal(getattr(back, name), getattr(m, name))
    assert back.taxels == m.taxels and back.info == m.info
    with pytest.raises(ValueError, match="not a surface map file"):
        SurfaceMap.from_file(tmp_path / "missing.npz")
    # linear in the force, a footprint averages the point responses
    p = np.array([[1e-3, 2e-3]])
    assert np.allclose(m.charge(p, (0, 0, -2.0)), 2 * m.charge(p, (0, 0, -1.0)))
    assert np.allclose(m.voltage(p, (1.0, 0, 0)), -np.linalg.solve(m.capacitance, m.charge(p, (1.0, 0, 0)).T).T)
    off, w = Footprint(1e-3, "round").quadrature()
    assert np.isclose(w.sum(), 1) and np.abs(off).max() < 1e-3


@pytest.mark.slow       # one 3x3 map and six direct 3D solves (three of them full models), minutes
def test_map_agrees_with_direct_solves_on_the_thesis_array():
    """The thesis PZT 3x3 array on its array mesh (2 mm / 0.8 mm, two elements through the
    PZT): the map against direct 3D solves of a flat 4 mm disc (1 N, linear, every taxel open)
    at the centre, along the diagonal, at the corner between four taxels, mid-gap, at the
    edge taxel's outer edge and off the corner taxel's centre (benchmarks/surface_map.py does
    twelve). The map is pressed with each solve's own load (its mesh's polygon of the disc,
    patch_quadrature): the pressed taxel within 2 % of its centre value (its peak), every other
    taxel within 0.3 % of that peak (the issue's goal is 0.2 %: met at eleven of the twelve
    positions of the benchmark, 0.22 % at the corner between four taxels, where the four
    read alike), with the same sign where it is above 0.2 %."""
    from taxel.analyses import solve_static
    from taxel.analyses.surface.surface_map import patch_quadrature
    sc = taxel.load("thesis-pzt-3x3-3d").replace(**{"mesh.size": "2 mm", "mesh.piezo_size": "0.8 mm"})
    m = build(sc)
    w, p = 4e-3, 7e-3
    centre = None
    for x, y in [(0, 0), (p / 4, p / 4), (p / 2, p / 2), (p / 2, 0), (p + w / 2, 0), (p + 1.5e-3, p + 1.5e-3)]:
        s = sc.replace(**{"load.kind": "probe", "load.taxel": [1, 1], "load.radius": "2 mm", "load.profile": "flat",
                          "load.offset": [x, y], "model.symmetry": "auto"})
        r = solve_static(s)
        vd = np.array([r.voltages()[k] for k in m.taxels])
        pts, wts = patch_quadrature(r.solution.mesh)
        vm = -np.linalg.solve(m.capacitance, m.charge(pts, np.column_stack([0 * wts, 0 * wts, -wts])).sum(0))
        centre = centre or abs(vd).max()
        k = int(np.argmax(np.abs(vd)))
        assert abs(vm[k] - vd[k]) <= 0.02 * centre, (x, y)
        for i in range(len(vd)):
            if i != k:
                assert abs(vm[i] - vd[i]) <= 3e-3 * centre, (x, y, m.taxels[i])
                if abs(vd[i]) > 2e-3 * centre:
                    assert np.sign(vm[i]) == np.sign(vd[i]), (x, y, m.taxels[i])
