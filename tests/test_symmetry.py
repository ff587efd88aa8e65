"""Symmetric (half, quarter) models against the full model on exactly mirrored meshes.

The full mesh is the cut mesh mirrored across its planes with the plane nodes
merged (meshing.mirror), so both discretizations are the same: voltages,
charges, capacitances and displacements must agree to round-off (1e-8)."""

import numpy as np
import pytest

from taxel.analyses import layout
from taxel.analyses import mesh, problem, scene_materials
from taxel.analyses import solve_static
from taxel.fem import assembly
from taxel.fem import static
from taxel.meshing.mirror import unfold_mesh
from taxel.analyses import check, symmetry_planes
from taxel.scene import SceneError, load


def _pair(scene, sym):
    """(symmetric solution, full solution on the mirrored mesh)."""
    cut_scene = scene.replace(**{"model.symmetry": sym})
    full_scene = scene.replace(**{"model.symmetry": "full"})
    tm = mesh(cut_scene)
    assert tm.layout.planes
    full_tm = unfold_mesh(tm, layout(full_scene, scene_materials(full_scene)))
    sym_sol = static.solve_linear(assembly.assemble(problem(cut_scene, tm)), "superlu")
    full_sol = static.solve_linear(assembly.assemble(problem(full_scene, full_tm)), "superlu")
    return sym_sol, full_sol


def _close(a, b, rel=1e-8):
    assert abs(a - b) <= rel * max(abs(b), 1e-300), (a, b)


def _compare(sym_sol, full_sol):
    assert set(sym_sol.electrodes) == set(full_sol.electrodes)
    vmax = max(abs(e.voltage) for e in full_sol.electrodes.values())
    qmax = max(abs(e.short_circuit_charge) for e in full_sol.electrodes.values())
    for k, f in full_sol.electrodes.items():
        s = sym_sol.electrodes[k]
        assert abs(s.voltage - f.voltage) <= 1e-8 * vmax, (k, s.voltage, f.voltage)
        assert abs(s.charge - f.charge) <= 1e-8 * qmax
        assert abs(s.short_circuit_charge - f.short_circuit_charge) <= 1e-8 * qmax, k
        if f.capacitance is not None:
            _close(s.capacitance, f.capacitance)
    # the whole Maxwell capacitance matrix, mutual terms included
    cs, cf = sym_sol.capacitance_matrix, full_sol.capacitance_matrix
    assert sorted(sym_sol.capacitance_names) == sorted(full_sol.capacitance_names)
    at = [sym_sol.capacitance_names.index(k) for k in full_sol.capacitance_names]
    assert np.abs(cs[np.ix_(at, at)] - cf).max() <= 1e-8 * np.abs(cf).max()
    off = ~np.eye(len(cf), dtype=bool)
    if off.any() and np.abs(cf[off]).max() > 0:       # the mutual terms on their own scale
        assert np.abs(cs[np.ix_(at, at)] - cf)[off].max() <= 1e-6 * np.abs(cf[off]).max()
    _close(sym_sol.applied_force, full_sol.applied_force, 1e-12)
    _close(sym_sol.reaction[-1], full_sol.reaction[-1])
    # displacements at every node of the cut mesh (the same node in the mirrored mesh)
    ps, pf = sym_sol.mesh.mesh.p, full_sol.mesh.mesh.p
    scale = 1e-9 * np.abs(pf).max()
    index = {tuple(k): i for i, k in enumerate(np.round(pf.T / scale).astype(np.int64))}
    at = np.array([index[tuple(k)] for k in np.round(ps.T / scale).astype(np.int64)])
    us, uf = sym_sol.fields.u, full_sol.fields.u[at]
    assert np.abs(us - uf).max() <= 1e-8 * np.abs(uf).max()
    assert np.abs(uf).max() > 0


@pytest.mark.parametrize("name,sym,edit", [
    ("thesis-pzt-single-3d", "quarter", {"mesh.size": "2 mm", "mesh.piezo_size": "1 mm", "mesh.piezo_layers": 1}),
    # the 3x3 arrays in 3D: 19-25 s of CPU each, slow (the single 3D taxel and the 2D half stay fast)
    pytest.param("thesis-pzt-3x3-3d", "quarter", {"mesh.size": "3 mm", "mesh.piezo_size": "1.5 mm",
                                                  "mesh.piezo_layers": 1}, marks=pytest.mark.slow),
    pytest.param("thesis-pzt-3x3-3d", "half", {"mesh.size": "3 mm", "mesh.piezo_size": "1.5 mm", "mesh.piezo_layers": 1,
                                               "load.taxel": [0, 1], "electrodes.taxel_2_0": "ground",
                                               "electrodes.taxel_2_2": "ground"}, marks=pytest.mark.slow),
    ("thesis-pzt-3x3-2d", "half", {"electrodes.taxel_1_0": "ground", "electrodes.taxel_1_2": "ground"}),
])
def test_symmetric_model_equals_the_mirrored_full_model(name, sym, edit):
    sym_sol, full_sol = _pair(load(name).replace(**edit), sym)
    _compare(sym_sol, full_sol)


def test_auto_picks_the_largest_symmetry_the_scene_allows():
    assert symmetry_planes(load("thesis-pzt-single-3d")) == (0, 1)
    assert symmetry_planes(load("thesis-pzt-3x3-3d")) == (0, 1)
    three = load("thesis-pzt-3x3-3d")
    assert symmetry_planes(three.replace(**{"load.taxel": [0, 1]})) == (0,)            # centred in x only
    assert symmetry_planes(three.replace(**{"load.taxel": [0, 0]})) == ()              # off centre: full
    assert symmetry_planes(three.replace(**{"model.symmetry": "full"})) == ()
    assert symmetry_planes(three.replace(**{"load.kind": "between", "load.taxel": [1, 0],
                                            "load.neighbour": [1, 1]})) == (1,)      # between columns 0 and 1
    assert symmetry_planes(three.replace(**{"electrodes.taxel_0_0": "ground"})) == ()
    assert symmetry_planes(three.replace(**{"analysis.type": "frequency"})) == ()
    assert symmetry_planes(load("thesis-pzt-single-2d")) == ()                        # 2D: full unless asked
    assert symmetry_planes(load("thesis-pzt-single-2d").replace(**{"model.symmetry": "half"})) == (0,)
    with pytest.raises(SceneError, match="model.symmetry"):
        check(three.replace(**{"model.symmetry": "quarter", "load.taxel": [0, 1]}))


def test_auto_solves_a_quarter_and_reports_every_taxel():
    res = solve_static(load("thesis-pzt-3x3-3d").replace(**{"mesh.size": "3 mm", "mesh.piezo_size": "1.5 mm",
                                                            "mesh.piezo_layers": 1}))
    sol = res.solution
    assert sol.mesh.layout.planes == (0, 1)
    assert len(sol.mesh.layout.taxels) == 4
    assert sorted(sol.electrodes) == sorted([f"taxel_{r}_{c}" for r in range(3) for c in range(3)] + ["ground"])
    assert sol.applied_force == pytest.approx(1.0)
    assert sol.reaction[-1] == pytest.approx(1.0, rel=1e-6)
    v = {k: e.voltage for k, e in sol.electrodes.items()}
    assert v["taxel_0_0"] == v["taxel_2_2"] and v["taxel_0_1"] == v["taxel_2_1"]
    assert v["taxel_1_1"] < 0 < v["taxel_0_1"]


def test_an_indenter_centred_between_four_taxels_is_a_quarter():
    four = load("thesis-pzt-3x3-3d").replace(**{"array.rows": 2, "array.cols": 2, "load.kind": "probe",
                                                "load.radius": "2 mm", "load.taxel": [1, 0]})
    assert symmetry_planes(four.replace(**{"load.offset": ["3.5 mm", "3.5 mm"]})) == (0, 1)
    assert symmetry_planes(four.replace(**{"load.offset": ["3.5 mm", "-3.5 mm"]})) == (0,)
    assert symmetry_planes(four.replace(**{"load.offset": ["3 mm", "3.5 mm"]})) == (1,)


def _press_pair(scene, sym, travel):
    """(symmetric press, full press on the mirrored mesh), both to the same travel."""
    from dataclasses import replace

    from taxel.fem.contact import Options, press
    # the multipliers converged far below the default penetration bound (gap_tol 1e-3 of the
    # travel), so that the comparison measures the symmetry, not where each run's Uzawa loop
    # stopped: at the default the quarter and the full press differ by 4.8e-6 in voltage and
    # 5.8e-6 in force (2026-11-29), at gap_tol 1e-7 by 1e-10
    opts = Options(gap_tol=1e-7)
    out = []
    for s in (sym, "full"):
        sc = scene.replace(**{"model.symmetry": s})
        tm = mesh(scene.replace(**{"model.symmetry": sym}))
        if s == "full":
            tm = unfold_mesh(tm, layout(sc, scene_materials(sc)))
        prob = problem(sc, tm)
        prob = replace(prob, indenter=replace(prob.indenter, force=None, travel=travel))
        out.append(press(assembly.assemble(prob), prob.indenter, opts=opts))   # the default linear solver (PARDISO in 3D)
    return out


@pytest.mark.parametrize("name,sym,edit,travel", [
    # the 3D presses: 18 s (single taxel, Yeoh) and 57 s (3x3) of CPU, slow; the 2D half press stays fast
    pytest.param("thesis-pzt-single-3d", "quarter", {"mesh.size": "2 mm", "mesh.piezo_size": "1 mm",
                                                     "mesh.piezo_layers": 1, "model.silicone": "yeoh",
                                                     "load.friction": "sticking"}, 0.3e-3, marks=pytest.mark.slow),
    pytest.param("thesis-pzt-3x3-3d", "quarter", {"mesh.size": "3 mm", "mesh.piezo_size": "1.5 mm",
                                                  "mesh.piezo_layers": 1, "load.friction": "sticking"}, 0.1e-3,
                 marks=pytest.mark.slow),
    ("thesis-pzt-single-2d", "half", {"model.silicone": "yeoh"}, 0.2e-3),
])
def test_symmetric_press_equals_the_mirrored_full_press(name, sym, edit, travel):
    """A rigid flat punch (4 mm, 0.2 mm edge) centred on the pressed taxel, by travel: the
    half or quarter press (force and contact area x |G|, the capacitance matrix from the
    antisymmetric classes linearised with the pressed state's tangent) equals the full
    press on the mirrored mesh, to the Newton and multiplier tolerances."""
    scene = load(name).replace(**{"load.kind": "probe", "load.contact": True, "load.radius": "2 mm",
                                  "load.edge_radius": "0.2 mm"}, **edit)
    s, f = _press_pair(scene, sym, travel)
    vmax = max(abs(e.voltage) for e in f.electrodes.values())
    for k, e in f.electrodes.items():
        assert abs(s.electrodes[k].voltage - e.voltage) <= 1e-6 * vmax, (k, s.electrodes[k].voltage, e.voltage)
        if e.capacitance is not None:
            _close(s.electrodes[k].capacitance, e.capacitance, 1e-6)
    _close(s.applied_force, f.applied_force, 1e-6)
    _close(s.contact.points[-1].area, f.contact.points[-1].area, 1e-9)
    _close(s.reaction[-1], f.reaction[-1], 1e-6)
    cs, cf = s.capacitance_matrix, f.capacitance_matrix
    at = [s.capacitance_names.index(k) for k in f.capacitance_names]
    assert np.abs(cs[np.ix_(at, at)] - cf).max() <= 1e-6 * np.abs(cf).max()
    assert f.applied_force > 0.05
