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
from skin_3d_loads import POINTS, NodalLoads, mujoco_probe

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
    scene, m, sk = setup
    probe = mujoco_probe(scene, sk)
    assert probe["force_N"] == pytest.approx(1.0, rel=0.05)
    assert abs(probe["error"]) < 0.05                              # 2.6 % measured (benchmarks/skin_3d_accuracy.py)
