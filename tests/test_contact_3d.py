"""3D contact against closed forms, on the quarter model (two symmetry planes):
a sphere and a flat punch pressed into a bonded linear block (fem.contact,
fem.contact with the 3D contact points, the P2 triangles' nodes, HRZ-lumped).

Closed forms, linear elastic half-space, E* = E / (1 - nu^2) (Johnson 1985, 4.2, 3.1):
  Hertz (sphere R, travel d):        F = 4/3 E* R^1/2 d^3/2,  a = sqrt(R d)
  Boussinesq (flat punch radius a):  F = 2 a E* d
The half-space is a quarter block of 300 contact radii, tetrahedra graded from the
contact's edge on the top (tests/contact_meshes.block3d). Measured during development
(one run each, the numbers the tests bound by 2 %):
  Hertz, d/R = 0.004, a/10 at the contact edge: F +1.47 %, contact radius -0.79 %
  (with the edge midpoints as contact points: +1.5 %, +1.1 %; 100 a: F +2.0 %, the finite block);
  Boussinesq, sharp punch, a/16 at the rim: F +1.18 %, contact radius +1.04 %
  (the edge midpoints: +1.4 %, +1.1 %; 100 a; a/32 at the rim: +1.2 %, +0.5 %).
"""

import numpy as np
import pytest

from contact_meshes import block3d, problem
from taxel.fem.assembly import assemble
from taxel.fem.assembly import Indenter
from taxel.fem.constitution import Solid
from taxel.fem.contact import Press

MU, NU = 10e3, 0.3
K_BULK = 2 * MU * (1 + NU) / (3 * (1 - 2 * NU))
E_STAR = 2 * MU * (1 + NU) / (1 - NU ** 2)
MAT = Solid("block", MU, K_BULK, 1000.0)


def pressed(ind, a, h_rim, h_inside):
    tm = block3d(300 * a, 300 * a, a, h_rim, h_inside)
    pr = Press(assemble(problem(tm, MAT, ind)), ind)
    assert pr.G == 4                                   # a quarter: forces and areas x 4
    return pr, pr.travel(ind.travel, first=1.0)


@pytest.mark.slow
def test_hertz_sphere_on_a_block_in_3d():
    R = 10e-3
    d = 0.004 * R
    a = np.sqrt(R * d)
    pr, pt = pressed(Indenter("sphere", R, travel=d), a, a / 10, a / 8)
    assert pt.force == pytest.approx(4 / 3 * E_STAR * np.sqrt(R) * d ** 1.5, rel=0.02)   # measured +1.47 %
    assert pr.res.state.half_width() == pytest.approx(a, rel=0.02)                      # measured -0.79 %
    assert pt.penetration <= 1e-3 * d


@pytest.mark.slow   # a 3D press (about 9 s of CPU); the 2D and axisymmetric Boussinesq presses stay in the fast tier (test_contact.py)
def test_boussinesq_flat_punch_in_3d():
    a = 1e-3
    d = 1e-3 * a
    pr, pt = pressed(Indenter("flat", a, 0.0, travel=d), a, a / 16, a / 5)
    assert pt.force == pytest.approx(2 * a * E_STAR * d, rel=0.02)                     # measured +1.18 %
    assert pr.res.state.half_width() == pytest.approx(a, rel=0.02)                     # measured +1.04 %


@pytest.mark.slow      # 10 s of CPU; the 3D Boussinesq punch stays in the fast tier
def test_no_node_of_the_top_enters_the_punch_on_the_probe_press():
    """The rig's probe press in 3D (thesis-pzt-probe-3d, sticking, 1 N): every P2 node of
    the top surface stays out of the punch to the penetration tolerance (1e-3 of the travel),
    the vertices too. With the edge midpoints as the contact points (rule "midpoints") the
    vertices were free: the deepest 49 um in, 12 % of the travel (benchmarks/contact_3d.py --rules)."""
    from taxel.analyses import problem as scene_problem
    from taxel.scene import load
    prob = scene_problem(load("thesis-pzt-probe-3d"))
    pr = Press(assemble(prob), prob.indenter)
    pt = pr.force(1.0)
    assert pr.node_penetration() < 1e-3 * pt.travel
