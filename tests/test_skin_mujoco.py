"""The MuJoCo adapter on the example fingertip (fast: no FEM): a sphere pressed with a
known force at a known point of the pad reads back as that force at that point, and the
voltages are the runtime's for those contacts."""

import mujoco
import numpy as np
import pytest

from taxel.skin.mujoco import MujocoSkin, fingertip_xml
from test_skin import first_order_skin


def pressed(x, y, F, steps=400):
    m = mujoco.MjModel.from_xml_path(fingertip_xml())
    d = mujoco.MjData(m)
    skin = MujocoSkin(m, first_order_skin(), body="pad")
    b0 = m.body("sphere").pos
    for i in range(steps):
        d.ctrl[:] = 0.0
        d.ctrl[m.actuator("probe_z").id] = d.ctrl[m.actuator("edge_z").id] = 0.004
        d.ctrl[m.actuator("sphere_x").id] = x - b0[0]
        d.ctrl[m.actuator("sphere_y").id] = y - b0[1]
        down = min(i / 100, 1.0)
        d.ctrl[m.actuator("sphere_z").id] = 0.004 * (1 - down) - F / 100 * down
        mujoco.mj_step(m, d)
        v = skin.step(d)
    return skin, d, v


def test_contacts_on_the_pad_are_the_pressing_force_at_its_point():
    skin, d, v = pressed(0.007, 0.0035, 0.8)
    pts, f = skin.contacts(d)
    m = skin.model
    spring = -d.actuator_force[m.actuator("sphere_z").id]
    assert spring == pytest.approx(0.8, rel=0.05)             # kp (target - z): the sphere sinks a little
    assert f.sum() == pytest.approx(spring, rel=0.01)         # at rest, gravity off: the contact carries it
    centre = (pts * f[:, None]).sum(axis=0) / f.sum()
    assert centre == pytest.approx([0.007, 0.0035], abs=2e-4)


def test_voltages_are_the_runtimes_for_those_contacts():
    skin, d, v = pressed(0.0105, 0.007, 0.5)
    # the first-order skin (h = S / (1 + s tau), tau = 50 ms) at rest after 400 ms: v = S u
    pts, f = skin.contacts(d)
    u = skin.runtime.loads(pts, f).reshape(3, 3)
    assert np.abs(v - 0.8 * u).max() < 0.02 * np.abs(v).max()
    # halfway between taxels (1, 1) and (1, 2) on the tent influence: half the force on each
    assert u[1, 1] == pytest.approx(f.sum() / 2, rel=0.05) and u[1, 2] == pytest.approx(f.sum() / 2, rel=0.05)


def test_unknown_body_and_other_step_are_refused():
    m = mujoco.MjModel.from_xml_path(fingertip_xml())
    with pytest.raises(ValueError, match="no such body"):
        MujocoSkin(m, first_order_skin(), body="palm")
    m.opt.timestep = 2e-3
    with pytest.raises(ValueError, match="discretized at"):
        MujocoSkin(m, first_order_skin(), body="pad")
