"""
A reduced model of the 3 x 3 array
==================================

The 2D section of the thesis's 3 x 3 PZT array (the row through the pressed taxel)
reduced to a state space with three force inputs and three voltage outputs through a
500 Mohm input. The reduced model's FRF (loss factors kept complex) is compared with
direct FEM solves, the real state space (loss factors as modal viscous damping) is
shown beside it, and a press on the middle taxel is simulated.
"""

import matplotlib.pyplot as plt
import numpy as np

import taxel
from taxel.analyses.solves import reduced as R
from taxel.analyses import problem
from taxel.fem import dynamics
from taxel.fem import dynamics as fr

scene = taxel.load("thesis-pzt-3x3-2d").replace(**{"readout.circuit": "resistor"})
model = taxel.reduce(scene)
print("\n".join(model.summary()))

f = np.geomspace(1, 2000, 150)
H = model.frf(f)
Hss = model.state_space().frf(f)
dm = dynamics.model(problem(scene))
loads = R.taxel_loads(dm)[0]
f_check = np.geomspace(1, 2000, 12)
pairs = [fr.direct_ports(dm, loads, x) for x in f_check]
Hd = R.port_readout(f_check, np.array([p[0] for p in pairs]), np.array([p[1] for p in pairs]),
                    model.red.names, model.readout)

fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4))
for i, c in zip(range(3), ("C0", "C1", "C2")):
    ax.loglog(f, np.abs(H[:, i, 1]), c, label=f"{model.output_names[i]} (frf)")
    ax.loglog(f, np.abs(Hss[:, i, 1]), c + "--", lw=0.8)
    ax.loglog(f_check, np.abs(Hd[:, i, 1]), c + "o", ms=4)
ax.set_xlabel("frequency (Hz)")
ax.set_ylabel("|V / F| (V/N), middle taxel pressed")
ax.set_title("reduced (lines), state space (dashed), direct FEM (dots)", fontsize=9)
ax.legend(fontsize=7)

t = np.arange(0, 2.0, 1 / 2000)
force = np.zeros((len(t), 3))
force[:, 1] = np.clip((t - 0.1) / 0.005, 0, 1) * 1.0        # a 1 N step on the middle taxel
y = model.simulate(t, force)
for i in range(3):
    bx.plot(t, y[:, i], label=model.output_names[i])
bx.set_xlabel("time (s)")
bx.set_ylabel("voltage (V)")
bx.set_title("1 N step on the middle taxel, 500 Mohm input", fontsize=9)
bx.legend(fontsize=7)
fig.tight_layout()
plt.show()
