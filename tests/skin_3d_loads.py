"""The 3D skin and direct 3D solves under the same nodal loads (tests/test_skin_3d.py,
benchmarks/skin_3d_accuracy.py): 1 N spread over the top-surface nodes within 1.6 mm of
a point, along x, y or z; each taxel's open-circuit voltage by direct solves
(fem.static.direct_charges, V = -C^-1 Q: not by reciprocity), by the surface map (its
spline) and by the skin (its held output: the readout's static gain times W)."""

import numpy as np

from taxel.analyses.model.problem import problem
from taxel.analyses.surface.surface_map import map_scene
from taxel.fem import assembly, static
from taxel.schema import electrode_name
from taxel.skin.runtime import SkinRuntime

# the three off-centre points, skin frame (p the pitch, w the taxel width)
POINTS = {"diagonal": lambda p, w: (0.25 * p, 0.25 * p), "gap": lambda p, w: (0.5 * p, 0.0),
          "edge": lambda p, w: (-(w / 2 + 1.5e-3), 0.0)}


class NodalLoads:
    def __init__(self, scene, m, sk):
        self.m, self.sk = m, sk
        self.sy = sy = assembly.assemble(problem(map_scene(scene.replace(**{"model.symmetry": "full"}))))
        self.driven = [k for k, s in sy.electrodes.states.items() if s != "reference"]
        self.ub = next(iter(sy.ubases.values()))
        self.top = np.unique(sy.tm.mesh.facets[:, sy.tm.facets["top"]])
        self.xy = sy.tm.mesh.p[:2, self.top].T
        p = sk.pitch
        self.shift = np.array([(sk.cols - 1) * p / 2, (sk.rows - 1) * p / 2])     # map frame -> skin frame
        self.gain = float((sk.Cd @ np.linalg.solve(np.eye(len(sk.Ad)) - sk.Ad, sk.Bd) + sk.Dd)[0, 0])
        self.rt = SkinRuntime(sk)
        self.order = [self.driven.index(electrode_name(sk.rows - 1 - r, c)) for r in range(sk.rows)
                      for c in range(sk.cols)]
        self.mo = [m.index(self.driven[i]) for i in self.order]
        self.C = m.capacitance[np.ix_(self.mo, self.mo)]

    def voltages(self, c, k) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(skin, map, FEM) open-circuit voltages (taxels,) in the skin's order for 1 N along k
        over the top nodes within 1.6 mm of c (skin frame)."""
        nodes = self.top[np.hypot(*(self.xy - (np.asarray(c) - self.shift)).T) <= 1.6e-3]
        assert len(nodes) >= 3
        pts = self.sy.tm.mesh.p[:2, nodes].T
        F = np.zeros((self.sy.A.shape[0], 1))
        F[[self.ub.nodal_dofs[k, n] for n in nodes], 0] = 1.0 / len(nodes)
        V = -np.linalg.solve(self.C, static.direct_charges(self.sy, F, self.driven)[:, 0][self.order])
        f = np.zeros((len(nodes), 3))
        f[:, k] = 1.0 / len(nodes)
        return self.gain * self.rt.loads(pts + self.shift, f).ravel(), self.m.voltage(pts, f).sum(axis=0)[self.mo], V

    def pressed_peak(self, c) -> float:
        """The largest |V_FEM| of 1 N pressed by the same nodes on the centre of the taxel nearest c."""
        sk = self.sk
        near = np.round(np.clip(np.array(c) / sk.pitch, 0, [sk.cols - 1, sk.rows - 1])) * sk.pitch
        return float(np.abs(self.voltages(near, 2)[2]).max())


def mujoco_probe(scene, sk) -> dict:
    """The MuJoCo flat probe pressed centrally to 1 N (held 2.9 s) through MujocoSkin against the
    3D FEM's static press by the same probe (taxel.solve), the pressed taxel's V/N."""
    import mujoco
    import taxel
    from taxel.skin.mujoco import MujocoSkin, fingertip_xml
    fem = taxel.solve(scene.replace(**{"load.kind": "probe", "load.taxel": [0, 1], "load.radius": 2e-3,
                                       "load.profile": "flat", "load.offset": [0.0, 0.0], "load.force": 1.0}))
    V = fem.voltages()[electrode_name(0, 1)]                     # the skin's taxel (1, 1): its row flipped
    mj = mujoco.MjModel.from_xml_path(fingertip_xml())
    d = mujoco.MjData(mj)
    skin = MujocoSkin(mj, sk, body="pad")
    b0 = mj.body("probe").pos
    for i in range(3000):
        d.ctrl[:] = 0.0
        d.ctrl[mj.actuator("sphere_z").id] = d.ctrl[mj.actuator("edge_z").id] = 0.004
        d.ctrl[mj.actuator("probe_x").id], d.ctrl[mj.actuator("probe_y").id] = 0.007 - b0[0], 0.007 - b0[1]
        down = min(i / 100, 1.0)
        d.ctrl[mj.actuator("probe_z").id] = 0.004 * (1 - down) - 1.0 / 100 * down
        mujoco.mj_step(mj, d)
        v = skin.step(d)
    N = -skin.patches(d)[1][:, 2].sum()
    pts, f, _ = skin.contacts(d)
    gain = float((sk.Cd @ np.linalg.solve(np.eye(len(sk.Ad)) - sk.Ad, sk.Bd) + sk.Dd)[0, 0])
    return {"skin_V_per_N": float(v[1, 1] / N), "fem_V_per_N": float(V), "error": float(v[1, 1] / N / V - 1),
            "rim_points_V_per_N": float(gain * skin.runtime.loads(pts, f)[1, 1] / N), "force_N": float(N)}
