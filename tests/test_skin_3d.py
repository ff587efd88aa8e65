"""The skin from the 3D surface map against direct 3D FEM solves (slow: a 2 x 2 PZT array,
the minimum a skin has, on the example's 3D mesh, 1.5 mm / 0.6 mm; about 5 minutes of CPU in all).

- normal and shear loads: nodal forces on top-surface nodes around three off-centre
  positions (diagonal, gap, edge), each taxel's open-circuit voltage by direct 3D solves
  (fem.static.direct_charges, V = -C^-1 Q: not by reciprocity, not through the map)
  against the skin's held output (its open-circuit readout's static gain times W):
  within 2 % of the pressed taxel's peak (the largest voltage of 1 N pressed by the same
  nodes on the nearest taxel's centre), every taxel with the FEM's sign where it is
  above 1 % of that peak;
- the MuJoCo flat probe (2 mm radius) pressed centrally to 1 N: the pressed taxel's
  voltage at rest against the 3D FEM's static press by the same probe (taxel.solve),
  within 5 %.
"""

import numpy as np
import pytest

import taxel
from taxel.schema import electrode_name
from skin_3d_loads import POINTS, NodalLoads

pytestmark = pytest.mark.slow

SMALL = {"array.rows": 2, "array.cols": 2, "readout.circuit": "open",
         "load.taxel": [1, 1]}


@pytest.fixture(scope="module")
def setup():
    from taxel.analyses.surface.surface_map import build as map_build
    from taxel.skin.build import build
    scene = taxel.load("thesis-pzt-3x3-3d").replace(**SMALL)
    m = map_build(scene)
    return scene, m, build(scene, dt=1e-3, checks=0, surface_map=m)


@pytest.fixture(scope="module")
def loads(setup):
    return NodalLoads(*setup)                      # the full model assembled once for the three points


@pytest.mark.parametrize("where", list(POINTS))
def test_normal_and_shear_against_direct_3d_solves(setup, loads, where):
    sk = setup[2]
    c = POINTS[where](sk.pitch, sk.taxel_width)
    peak = loads.pressed_peak(c)
    for k in range(3):                                   # x, y (shear) and z (normal) alike
        v, _, V = loads.voltages(c, k)
        assert np.abs(v - V).max() < 0.02 * peak, (where, "xyz"[k], v, V, peak)
        big = np.abs(V) > 0.01 * peak
        assert np.all(np.sign(v[big]) == np.sign(V[big])), (where, "xyz"[k])


def test_mujoco_flat_probe_against_the_3d_press(setup):
    import mujoco
    from taxel.skin.mujoco import MujocoSkin, fingertip_xml
    scene, m, sk = setup
    fem = taxel.solve(scene.replace(**{"load.kind": "probe", "load.taxel": [0, 1], "load.radius": 2e-3,
                                       "load.profile": "flat", "load.offset": [0.0, 0.0], "load.force": 1.0}))
    V = fem.voltages()[electrode_name(0, 1)]
    mj = mujoco.MjModel.from_xml_path(fingertip_xml())
    d = mujoco.MjData(mj)
    skin = MujocoSkin(mj, sk, body="pad")
    b0 = mj.body("probe").pos
    for i in range(3000):                                 # pressed in 0.1 s, held 2.9 s: the loss law settles
        d.ctrl[:] = 0.0
        d.ctrl[mj.actuator("sphere_z").id] = d.ctrl[mj.actuator("edge_z").id] = 0.004
        d.ctrl[mj.actuator("probe_x").id], d.ctrl[mj.actuator("probe_y").id] = 0.007 - b0[0], 0.007 - b0[1]
        down = min(i / 100, 1.0)
        d.ctrl[mj.actuator("probe_z").id] = 0.004 * (1 - down) - 1.0 / 100 * down
        mujoco.mj_step(mj, d)
        v = skin.step(d)
    N = -skin.patches(d)[1][:, 2].sum()
    assert N == pytest.approx(1.0, rel=0.05)
    assert v[1, 1] / N == pytest.approx(V, rel=0.05)
