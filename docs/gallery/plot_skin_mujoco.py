"""
A taxel skin in MuJoCo: volts from contacts, normal and shear
=============================================================

The thesis 3x3 PZT array (500 Mohm readout) as a MuJoCo sensor. ``taxel.skin``
builds its skin file from the FEM: the 3D surface map (every taxel's charge per
newton of a force along x, y and z at every point of the surface, by reciprocity:
one 3D solve per electrode class), the taxel's reduced dynamics through its readout
(its 2D section), the noise budget. The example fingertip model
(``taxel/skin/fingertip.xml``) carries the array on its pad, and five presses follow one
another: a flat probe on the middle taxel, an edge along the gap between the first two
columns, a sphere between two rows, the sphere slipping across the middle row, and the
flat probe pressed on the middle taxel and dragged 2 mm along x (friction 0.3: a
tangential load on the skin). Each simulator step ``taxel.skin.mujoco.MujocoSkin``
turns the contacts on the pad into the pressure over the touching geom's footprint
(normal and tangential) and the numpy runtime returns the nine voltages, here with
the chain's noise. A piezo taxel reports the force's change, not the force: the
voltages decay while a press is held (the readout's high-pass, tau = R C_p) and swing
negative when it is released; the drag's tangential force loads the taxels on either
side of the probe with opposite signs.
"""

import matplotlib.pyplot as plt
import mujoco
import numpy as np

import taxel
from taxel.skin.mujoco import MujocoSkin, fingertip_xml

scene = taxel.load("thesis-pzt-3x3-3d").replace(**{"readout.circuit": "resistor", "readout.R": 5e8})
skin = taxel.build_skin(scene, dt=1e-3)
print(f"{skin.rows} x {skin.cols} skin from the {skin.spatial}; {skin.Ad.shape[0]} states; interpolation error "
      f"{skin.influence_error:.1e} of the peak; readout: {skin.readout}, within 1 % and 1 degree of the solver's "
      f"sweep up to {skin.band:.0f} Hz")

m = mujoco.MjModel.from_xml_path(fingertip_xml())
d = mujoco.MjData(m)
sensor = MujocoSkin(m, skin, body="pad", noise=True, seed=0)

p = skin.pitch
# (indenter, x, y, peak force N, x at the end (a slip) or None)
presses = [("probe", p, p, 1.0, None), ("edge", p / 2, p, 1.0, None), ("sphere", p, p / 2, 1.5, None),
           ("sphere", 0.0, p, 1.0, 2 * p), ("probe", p, p, 1.0, p + 2e-3)]
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
force, shear, volts = np.zeros(steps), np.zeros(steps), np.zeros((steps, 3, 3))
for i in range(steps):
    d.ctrl[:] = control(t[i])
    mujoco.mj_step(m, d)
    pts, f = sensor.patches(d)                 # the footprints' points and forces (skin frame, a press f_z < 0)
    force[i], shear[i] = -f[:, 2].sum(), f[:, 0].sum()
    volts[i] = sensor.runtime.step(pts, f)

# The drag's tangential load alone, held (the readout's static gain times W's shear plane):
# the taxels beside the probe along x see it with opposite signs.
pts_drag, f_drag = np.array([[p, p]]), np.array([[1.0, 0.0, 0.0]])
u_drag = sensor.runtime.loads(pts_drag, f_drag)
print("a 1 N tangential load (+x) at the middle taxel's centre: the force each taxel of the middle row sees",
      np.round(u_drag[1], 3), "N (pressing it: 1 N on its own taxel)")

# %%
# The contact force MuJoCo computes on the pad, and the nine taxels' voltages.
fig, (a, b) = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
a.plot(t, force, "k", label="normal (pressing)")
a.plot(t, shear, "C3", label="tangential, x")
a.set(ylabel="contact force on the pad (N)")
a.legend(fontsize=7, loc="center right")
for k, (name, _x, _y, _F, x_end) in enumerate(presses):
    a.text(k * SEG + 0.02, 0.9 * force.max(), f"{name} slip" if x_end is not None else name)
for r in range(3):
    for c in range(3):
        b.plot(t, 1e3 * volts[:, r, c], lw=0.8, label=f"taxel ({r}, {c})")
b.set(xlabel="time (s)", ylabel="readout output (mV)")
b.legend(ncol=3, fontsize=7)
fig.tight_layout()
