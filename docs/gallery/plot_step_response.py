"""
The step response through a resistor
====================================

``analysis.type = "transient"`` integrates the coupled model in time (Newmark)
for a force input: here a 0.5 N step with a 5 ms rise, read through the thesis's
500 MOhm input (``readout.circuit = "resistor"``). The taxel's capacitance C_p
and R give the first-order decay the thesis measured (time constants 1.7-3.1 s);
the duration is shortened to 2 s here.
"""

import matplotlib.pyplot as plt

import taxel

scene = taxel.load("thesis-pzt-step").replace(**{"analysis.duration": "2 s", "analysis.dt": "2 ms"})
step = taxel.solve(scene)
print("\n".join(step.summary()))

# %%
fig, a = plt.subplots(figsize=(7, 3.2))
a.plot(step.t, step.output[:, 0], label="pressed taxel")
a.set(xlabel="time (s)", ylabel=f"{step.label} (V)", title="0.5 N step through 500 MOhm")
b = a.twinx()
b.plot(step.t, step.force, color="0.6", ls="--", label="force")
b.set_ylabel("force (N)")
fig.tight_layout()
