"""The MuJoCo adapter on the example fingertip (fast: no FEM): a sphere pressed with a
known force at a known point of the pad reads back as that force at that point, and the
voltages are the runtime's for those contacts."""

import mujoco
import numpy as np
import pytest

from taxel.skin.mujoco import MujocoSkin, fingertip_xml
from test_skin import first_order_skin


def pressed(x, y, F, steps=400, body="sphere", drag=0.0, skin_model=None):
    """Press `body` with F newtons at (x, y) on the pad; then, with `drag`, move it by
    `drag` m along x over the last 100 steps (sliding: friction 0.3)."""
    m = mujoco.MjModel.from_xml_path(fingertip_xml())
    d = mujoco.MjData(m)
    skin = MujocoSkin(m, skin_model or first_order_skin(), body="pad")
    b0 = m.body(body).pos
    for i in range(steps):
        d.ctrl[:] = 0.0
        for other in {"probe", "sphere", "edge"} - {body}:
            d.ctrl[m.actuator(f"{other}_z").id] = 0.004
        d.ctrl[m.actuator(f"{body}_x").id] = x - b0[0] + drag * max(0.0, (i - steps + 100) / 100)
        d.ctrl[m.actuator(f"{body}_y").id] = y - b0[1]
        down = min(i / 100, 1.0)
        d.ctrl[m.actuator(f"{body}_z").id] = 0.004 * (1 - down) - F / 100 * down
        mujoco.mj_step(m, d)
        v = skin.step(d)
    return skin, d, v


def test_contacts_on_the_pad_are_the_pressing_force_at_its_point():
    skin, d, v = pressed(0.007, 0.0035, 0.8)
    pts, f, _ = skin.contacts(d)
    m = skin.model
    spring = -d.actuator_force[m.actuator("sphere_z").id]
    assert spring == pytest.approx(0.8, rel=0.05)             # kp (target - z): the sphere sinks a little
    assert -f[:, 2].sum() == pytest.approx(spring, rel=0.01)  # at rest, gravity off: the contact carries it (f_z < 0)
    centre = (pts * f[:, 2:]).sum(axis=0) / f[:, 2].sum()
    assert centre == pytest.approx([0.007, 0.0035], abs=2e-4)
    P, F = skin.patches(d)                                    # Hertz's disc: the same force, under the sphere
    assert np.allclose(F.sum(axis=0), f.sum(axis=0)) and len(P) > len(pts)
    assert (P * F[:, 2:]).sum(axis=0) / F[:, 2].sum() == pytest.approx(centre, abs=2e-4)


def test_a_flat_probe_is_its_disc_not_its_rim_points():
    skin, d, v = pressed(0.007, 0.007, 1.0, body="probe")
    pts, f, _ = skin.contacts(d)
    assert len(pts) >= 3 and np.hypot(*(pts - 0.007).T).min() > 1.5e-3       # MuJoCo: points on the rim
    P, F = skin.patches(d)
    assert np.hypot(*(P - 0.007).T).max() <= 2e-3 + 1e-5                    # the 2 mm disc under the probe
    # the tent skin's pressed taxel: the load times the tent's mean over the disc (a fine grid), not the rim's
    g = np.linspace(-2e-3, 2e-3, 401)
    X, Y = np.meshgrid(g, g)
    inside = X ** 2 + Y ** 2 <= 4e-6
    mean_tent = ((1 - np.abs(X) / 7e-3) * (1 - np.abs(Y) / 7e-3))[inside].mean()
    u = skin.runtime.loads(P, F).reshape(3, 3)
    N = -F[:, 2].sum()
    assert u[1, 1] == pytest.approx(N * mean_tent, rel=0.01)
    rim = skin.runtime.loads(pts, f).reshape(3, 3)
    assert rim[1, 1] < 0.95 * u[1, 1]                                       # the rim: 2 mm off, on the tent's slope


def test_a_drag_gives_the_shear_channel():
    skin, d, v = pressed(0.007, 0.007, 1.0, body="probe", drag=0.003)
    P, F = skin.patches(d)
    fx, fz = F[:, 0].sum(), F[:, 2].sum()
    assert fx > 0.2 * -fz                                                   # sliding at friction 0.3: the pad is dragged +x
    u_shear = skin.runtime.loads(P, F * [1, 1, 0]).reshape(3, 3)
    assert u_shear[1, 1] > 0 and u_shear.sum() == pytest.approx(0.5 * fx, rel=1e-6)    # the tents (a partition of 1): 0.5 fx


def test_voltages_are_the_runtimes_for_those_contacts():
    skin, d, v = pressed(0.0105, 0.007, 0.5)
    # the first-order skin (h = S / (1 + s tau), tau = 50 ms) at rest after 400 ms: v = S u
    P, F = skin.patches(d)
    u = skin.runtime.loads(P, F).reshape(3, 3)
    assert np.abs(v - 0.8 * u).max() < 0.02 * np.abs(v).max()
    # halfway between taxels (1, 1) and (1, 2) on the tent influence (a partition of 1): the force is
    # all seen, as much by each of the two
    N = -F[:, 2].sum()
    assert u.sum() == pytest.approx(N, rel=1e-6) and u[1, 1] == pytest.approx(u[1, 2], rel=0.01)


def test_unknown_body_and_other_step_are_refused():
    m = mujoco.MjModel.from_xml_path(fingertip_xml())
    with pytest.raises(ValueError, match="no such body"):
        MujocoSkin(m, first_order_skin(), body="palm")
    m.opt.timestep = 2e-3
    with pytest.raises(ValueError, match="discretized at"):
        MujocoSkin(m, first_order_skin(), body="pad")
