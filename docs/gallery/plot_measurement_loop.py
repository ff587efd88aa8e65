"""
The measurement loop on the simulated rig
=========================================

``taxel.measure`` is the bench side: a rig file (port, protocol, ADC, channels,
conditioning), capture or import into a measurement folder, export, and the
analysis of the record against the model. Without a bench, the simulated rig
plays one: the models' signals through the rig's chain (conditioning,
quantisation, noise, 50 Hz hum) as the bytes the microcontroller would send.
Here: a step on the thesis bench, imported from those bytes, then fitted.
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

import taxel.measure as tm

folder = Path(tempfile.mkdtemp(prefix="taxel-measure-"))
bench = tm.load_rig("thesis-bench")
sim = tm.simulate(bench, "thesis-pzt-3x3-2d", "step", seconds=2, crosstalk=False)
sim.to_folder(folder / "step")                    # stream.bin (the bytes sent) and the truth beside it
m = tm.import_file(folder / "step" / "stream.bin", bench, folder / "m")
print("\n".join(m.summary()))
fit = tm.analyze(folder / "m", "thesis-pzt-3x3-2d")
print("\n".join(fit.summary()))

# %%
# The device's microsecond clock (u32, as received), from the first frame.
t = (m.t_us.astype("int64") - int(m.t_us[0])) * 1e-6
fig, (a, b) = plt.subplots(2, 1, figsize=(7, 4.5), sharex=True)
names = m.rig.names
for i, name in enumerate(names):
    if name.startswith("taxel_"):
        a.plot(t, m.values[:, i], lw=0.7, label=name)
a.set(ylabel="conditioned output (V)", title="the simulated thesis bench: a step")
a.legend(fontsize=7, ncol=3)
b.plot(t, m.values[:, names.index("force")], color="k", lw=0.7)
b.set(xlabel="time (s)", ylabel="load cell (N)")
fig.tight_layout()
