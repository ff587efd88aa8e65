"""The MuJoCo adapter: the contacts on a skin body, each step, into the skin runtime.

    import mujoco
    from taxel.skin.model import SkinModel
    from taxel.skin.mujoco import MujocoSkin
    m = mujoco.MjModel.from_xml_path(fingertip_xml()); d = mujoco.MjData(m)
    skin = MujocoSkin(m, SkinModel.load("skin.npz"), body="pad", noise=True, seed=0)
    while ...:
        mujoco.mj_step(m, d)
        volts = skin.step(d)            # (rows, cols) V

The skin body's frame is the skin's frame: origin at taxel (0, 0)'s centre on the
surface, x along the columns, y along the rows, z out of the surface (the example's
pad is so). Each step reads every active contact with a geom of that body
(`d.contact[:d.ncon]`), its normal force (mujoco.mj_contactForce, the contact
frame's first component, >= 0 when pressing) and its point in the body's frame; the
shear components are not used (the skin is a normal-force sensor, taxel.skin.build).
mujoco is imported here only: the runtime (taxel.skin.runtime) never needs it.
"""

from __future__ import annotations

from importlib import resources

import numpy as np

from taxel.skin.model import SkinModel
from taxel.skin.runtime import SkinRuntime


def fingertip_xml() -> str:
    """The path of the example MJCF model: a fingertip pad carrying the thesis 3 x 3 array
    (pitch 7 mm, 4 mm taxels, 3 mm margin) and a probe, a sphere and an edge to press it."""
    return str(resources.files("taxel.skin") / "fingertip.xml")


class MujocoSkin:
    """A SkinRuntime fed by a MuJoCo model's contacts on one body (module docstring)."""

    def __init__(self, model, skin: SkinModel, body: str, noise: bool = False, seed: int | None = None):
        import mujoco
        self._mj = mujoco
        self.model = model
        self.body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, body)
        if self.body < 0:
            raise ValueError(f"body '{body}': no such body in the MuJoCo model; name the body that carries the skin")
        self.runtime = SkinRuntime(skin, noise, seed, dt=float(model.opt.timestep))
        self._f = np.zeros(6)

    def contacts(self, data) -> tuple[np.ndarray, np.ndarray]:
        """(points (m, 2) m in the skin frame, normal forces (m,) N) of the contacts on the skin body."""
        mj, m = self._mj, self.model
        R, p0 = data.xmat[self.body].reshape(3, 3), data.xpos[self.body]
        pts, fs = [], []
        for i in range(data.ncon):
            c = data.contact[i]
            if c.exclude or self.body not in (m.geom_bodyid[c.geom1], m.geom_bodyid[c.geom2]):
                continue
            mj.mj_contactForce(m, data, i, self._f)
            if self._f[0] <= 0:
                continue
            pts.append(R.T @ (c.pos - p0))
            fs.append(self._f[0])
        if not fs:
            return np.zeros((0, 2)), np.zeros(0)
        return np.array(pts)[:, :2], np.array(fs)

    def step(self, data) -> np.ndarray:
        """The taxels' voltages (rows, cols) V after this simulator step."""
        return self.runtime.step(*self.contacts(data))
