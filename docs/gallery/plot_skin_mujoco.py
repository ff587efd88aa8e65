"""
A taxel skin in MuJoCo: volts from contacts
===========================================

The thesis 3x3 PZT array (500 Mohm readout) as a MuJoCo sensor. ``taxel.skin``
builds its skin file from the FEM (the influence of a press at any point on every
taxel, the taxel's reduced dynamics through its readout, the noise budget); the
example fingertip model (``taxel/skin/fingertip.xml``) carries the array on its pad,
and four presses follow one another: a flat probe on the middle taxel, an edge
along the gap between the first two columns, a sphere between two rows, and the
sphere slipping across the middle row. Each simulator step,
``taxel.skin.mujoco.MujocoSkin`` reads the contacts on the pad (points and normal
forces) and the numpy runtime returns the nine voltages, here with the chain's
noise. A piezo taxel reports the force's change, not the force: the voltages decay
while a press is held (the readout's high-pass, tau = R C_p) and swing negative when
it is released. (A coarse mesh, 1 mm / 0.2 mm, keeps the gallery quick.)
"""

import matplotlib.pyplot as plt
import mujoco
import numpy as np

import taxel
from taxel.skin.mujoco import MujocoSkin, fingertip_xml

scene = taxel.load("thesis-pzt-3x3-2d").replace(
    **{"readout.circuit": "resistor", "readout.R": 5e8, "mesh.size": "1 mm", "mesh.piezo_size": "0.2 mm"})
skin = taxel.build_skin(scene, dt=1e-3, checks=2)
print(f"{skin.rows} x {skin.cols} skin, {skin.Ad.shape[0]} states, influence interpolation error "
      f"{skin.influence_error:.1e}, readout: {skin.readout}")

m = mujoco.MjModel.from_xml_path(fingertip_xml())
d = mujoco.MjData(m)
sensor = MujocoSkin(m, skin, body="pad", noise=True, seed=0)

p = skin.pitch
# (indenter, x, y, peak force N, x at the end (a slip) or None)
presses = [("probe", p, p, 1.0, None), ("edge", p / 2, p, 1.0, None), ("sphere", p, p / 2, 1.5, None),
           ("sphere", 0.0, p, 1.0, 2 * p)]
SEG = 0.6                      # s per press
T = SEG * len(presses)


def control(t):
    """The actuators' controls at time t: the active indenter over its point, lowered onto
    the pad, pressed (its z spring: ctrl = -F / 100 N/m), released and lifted; the others
    wait beside the pad, lifted."""
    ctrl = np.zeros(m.nu)
    k = min(int(t / SEG), len(presses) - 1)
    name, x, y, F, x_end = presses[k]
    s = t - k * SEG
    for other in ("probe", "sphere", "edge"):
        ctrl[m.actuator(f"{other}_z").id] = 0.004
    body0 = m.body(name).pos
    if x_end is not None:
        x = x + (x_end - x) * np.clip((s - 0.25) / 0.2, 0, 1)
    ctrl[m.actuator(f"{name}_x").id] = x - body0[0]
    ctrl[m.actuator(f"{name}_y").id] = y - body0[1]
    down = np.clip((s - 0.06) / 0.06, 0, 1) * np.clip((0.52 - s) / 0.04, 0, 1)    # lower, then lift
    ramp = np.clip((s - 0.15) / 0.05, 0, 1) * np.clip((0.48 - s) / 0.05, 0, 1)    # press, then release
    ctrl[m.actuator(f"{name}_z").id] = 0.004 * (1 - down) - 0.02 / 100 * down - (F - 0.02) / 100 * ramp
    return ctrl


steps = int(round(T / m.opt.timestep))
t = np.arange(steps) * m.opt.timestep
force, volts = np.zeros(steps), np.zeros((steps, 3, 3))
for i in range(steps):
    d.ctrl[:] = control(t[i])
    mujoco.mj_step(m, d)
    pts, f = sensor.contacts(d)
    force[i] = f.sum()
    volts[i] = sensor.runtime.step(pts, f)

# %%
# The contact force MuJoCo computes on the pad, and the nine taxels' voltages.
fig, (a, b) = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
a.plot(t, force, "k")
a.set(ylabel="contact normal force (N)")
for k, (name, _x, _y, _F, x_end) in enumerate(presses):
    a.text(k * SEG + 0.02, 0.9 * force.max(), "sphere slip" if x_end is not None else name)
for r in range(3):
    for c in range(3):
        b.plot(t, 1e3 * volts[:, r, c], lw=0.8, label=f"taxel ({r}, {c})")
b.set(xlabel="time (s)", ylabel="readout output (mV)")
b.legend(ncol=3, fontsize=7)
fig.tight_layout()
