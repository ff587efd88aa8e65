"""Graded structured meshes of a passive block for the contact verification
(tests/test_contact.py, benchmarks/contact_taxel.py): fine near the indenter,
geometric growth to a far boundary."""

import numpy as np
import skfem

from taxel.fem.kinematics import Axisymmetric, PlaneStrain
from taxel.fem.materials import Solid
from taxel.fem.problem import Discretization, PatchLoad, Problem
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
    kin = Axisymmetric() if tm.layout.model == "axisymmetric" else PlaneStrain(depth)
    return Problem(mesh=tm, kinematics=kin, materials={"block": material}, load=PatchLoad(force=0.0),
                   discretization=Discretization(2, True), hyperelastic=hyperelastic, indenter=indenter)
