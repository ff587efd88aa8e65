"""Graded structured meshes of a passive block for the contact verification
(tests/test_contact.py, benchmarks/contact_taxel.py): fine near the indenter,
geometric growth to a far boundary."""

import numpy as np
import skfem

from taxel.fem.constitution import Axisymmetric, PlaneStrain, Solid3D
from taxel.fem.constitution import Solid
from taxel.fem.assembly import Discretization, PatchLoad, Problem
from taxel.meshing.build import TaggedMesh
from taxel.meshing.layout import Layer, Layout, Patch


def graded(fine_to, h, length, growth=1.15):
    """0 .. fine_to uniform with step h, then steps growing by `growth` to `length`."""
    xs = list(np.linspace(0, fine_to, int(round(fine_to / h)) + 1))
    step = h
    while xs[-1] < length:
        step *= growth
        xs.append(min(xs[-1] + step, length))
    if xs[-1] - xs[-2] < 0.3 * step:
        xs.pop(-2)
    return np.array(xs)


def block(width, height, fine, h, model="axisymmetric", growth=1.15):
    """A bonded block (bottom fixed), top at z = height; axisymmetric: r in [0, width];
    plane strain: x in [-width, width]. Fine mesh (h) for |x| <= fine and within
    `fine` of the top."""
    r = graded(fine, h, width, growth)
    xs = r if model == "axisymmetric" else np.concatenate([-r[:0:-1], r])
    zs = height - graded(fine, h, height, growth)[::-1]
    m = skfem.MeshTri.init_tensor(xs, zs)
    m = skfem.MeshTri(m.p, m.t)
    x0 = xs[0]
    f = {"bottom": m.facets_satisfying(lambda x: np.isclose(x[1], 0)),
         "top": m.facets_satisfying(lambda x: np.isclose(x[1], height)),
         "axis": m.facets_satisfying(lambda x: np.isclose(x[0], 0)) if model == "axisymmetric" else np.zeros(0, int),
         "edges": m.facets_satisfying(lambda x: np.isclose(x[0], width) | np.isclose(x[0], x0))}
    f["load"] = f["top"]
    regions = {"layer0": np.arange(m.nelements)}
    plan = Patch("plan", 0.0, 0.0, width, "disk" if model == "axisymmetric" else "square")
    lay = Layout(model=model, plan=plan, plan_half_y=width, layers=(Layer("layer0", 0.0, height, "block"),),
                 electrodes=(), load=None)
    return TaggedMesh(m.with_boundaries(f), lay, regions, f, {"layer0": ("block", 1)})


def problem(tm, material: Solid, indenter, hyperelastic=False, depth=1.0):
    kin = {"axisymmetric": Axisymmetric(), "3d": Solid3D()}.get(tm.layout.model, PlaneStrain(depth))
    return Problem(mesh=tm, kinematics=kin, materials={"block": material}, load=PatchLoad(force=0.0),
                   discretization=Discretization(2, True), hyperelastic=hyperelastic, indenter=indenter)


def block3d(width, height, rim, h_rim, h_inside, slope=0.35):
    """A quarter (x, y >= 0) of a bonded block, top at z = height, meshed by gmsh with
    tetrahedra graded from `h_rim` at the quarter circle of radius `rim` on the top
    (a punch's rim, a contact zone's edge) growing by `slope` x the distance, and at
    most `h_inside` over the top inside 1.1 rim. Facets: bottom, top (= load),
    mirror_x (x = 0), mirror_y (y = 0), edges (x or y = width)."""
    import gmsh

    fresh = not gmsh.isInitialized()
    if fresh:
        gmsh.initialize(readConfigFiles=False, interruptible=False)
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("block3d")
    try:
        occ = gmsh.model.occ
        box = occ.addBox(0, 0, 0, width, width, height)
        disk = occ.addDisk(0, 0, height, rim, rim)
        quarter = occ.addRectangle(0, 0, height, 2 * rim, 2 * rim)
        cut, _ = occ.intersect([(2, disk)], [(2, quarter)])
        occ.fragment([(3, box)], cut)
        occ.synchronize()
        arcs = []
        for _, t in gmsh.model.getEntities(1):
            a, b = gmsh.model.getParametrizationBounds(1, t)
            xyz = np.reshape(gmsh.model.getValue(1, t, [0.5 * (a[0] + b[0])]), 3)
            if abs(xyz[2] - height) < 1e-9 * height and abs(np.hypot(xyz[0], xyz[1]) - rim) < 1e-9 * rim:
                arcs.append(t)
        f = gmsh.model.mesh.field
        dist = f.add("Distance")
        f.setNumbers(dist, "CurvesList", arcs)
        f.setNumber(dist, "Sampling", 200)
        thr = f.add("MathEval")
        f.setString(thr, "F", f"{h_rim} + {slope} * F{dist}")
        box_f = f.add("Box")
        f.setNumber(box_f, "VIn", h_inside)
        f.setNumber(box_f, "VOut", width)
        for k, v in (("XMin", -1), ("XMax", 1.1 * rim), ("YMin", -1), ("YMax", 1.1 * rim),
                     ("ZMin", height - 0.5 * rim), ("ZMax", 2 * height)):
            f.setNumber(box_f, k, v)
        mn = f.add("Min")
        f.setNumbers(mn, "FieldsList", [thr, box_f])
        f.setAsBackgroundMesh(mn)
        for opt in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
            gmsh.option.setNumber(f"Mesh.{opt}", 0)
        # gmsh options are global to the process: a taxel mesh built before (meshing.build)
        # leaves Mesh.MeshSizeMax at its `size`, which would mesh this 300-radii block at it
        gmsh.option.setNumber("Mesh.MeshSizeMax", width)
        gmsh.option.setNumber("Mesh.MeshSizeMin", 0.0)
        gmsh.model.mesh.generate(3)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        _, nodes = gmsh.model.mesh.getElementsByType(4)
    finally:
        gmsh.model.remove()
    index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    t = index[nodes.astype(np.int64)].reshape(-1, 4).T
    used = np.unique(t)
    renum = np.full(len(tags), -1, dtype=np.int64)
    renum[used] = np.arange(len(used))
    m = skfem.MeshTet(np.ascontiguousarray(coords.reshape(-1, 3)[used].T), np.ascontiguousarray(renum[t]))
    return quarter_block(m, width, height)


def quarter_block(m, width, height) -> TaggedMesh:
    """A quarter block's mesh (x, y in [0, width], z in [0, height]) tagged for fem.contact:
    bottom, top (= load), the mirror planes x = 0 and y = 0, the outer edges; one layer."""
    tol = 1e-9 * width
    f = {"bottom": m.facets_satisfying(lambda x: np.abs(x[2]) < tol),
         "top": m.facets_satisfying(lambda x: np.abs(x[2] - height) < tol),
         "mirror_x": m.facets_satisfying(lambda x: np.abs(x[0]) < tol),
         "mirror_y": m.facets_satisfying(lambda x: np.abs(x[1]) < tol),
         "edges": m.facets_satisfying(lambda x: (np.abs(x[0] - width) < tol) | (np.abs(x[1] - width) < tol))}
    f["load"] = f["top"]
    regions = {"layer0": np.arange(m.nelements)}
    lay = Layout(model="3d", plan=Patch("plan", 0.0, 0.0, width), plan_half_y=width,
                 layers=(Layer("layer0", 0.0, height, "block"),), electrodes=(), load=None, planes=(0, 1))
    return TaggedMesh(m.with_boundaries(f), lay, regions, f, {"layer0": ("block", 1)})
