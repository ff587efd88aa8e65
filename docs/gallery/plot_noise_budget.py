"""
Noise budget of the thesis PZT taxel
====================================

The noise at the charge-amplifier output of the thesis PZT taxel on the thesis
bench (16-bit ADC over +-10 V at 2 kHz), per source: the op-amp's e_n and i_n,
the thermal noise of R_f and R_i, the piezo's dielectric loss, the ADC's
quantisation and the mains hum left after the 50 Hz notch. The transfer function
is the 3-DoF lumped model's here (fast); the main job uses the FEM sweep.
"""

import matplotlib.pyplot as plt
import numpy as np

from taxel.analyses.solves.noise import noise
from taxel.scene import load
from taxel.studies.bench.rig import load_rig

scene = load("thesis-pzt-frequency").replace(**{"readout.hum": ["5 mV", "1.5 mV", "0.5 mV"]})
res = noise(scene, load_rig("thesis-bench"), model="lumped")
print("\n".join(res.summary()))

fig, ax = plt.subplots(figsize=(7, 4))
for name, psd in sorted(res.psd.items(), key=lambda kv: -kv[1].mean()):
    ax.loglog(res.freqs, np.sqrt(psd), label=name)
ax.set(xlabel="frequency (Hz)", ylabel="V/sqrt(Hz) at the readout",
       title=f"minimum detectable force {1e3 * res.min_detectable_force:.3g} mN rms")
ax.legend(fontsize=8)
plt.show()
