"""
The frequency response through the readout
===========================================

``analysis.type = "frequency"`` sweeps the taxel's response to a harmonic force
and passes it through the readout circuit of ``[readout]``: here the thesis's
charge amplifier (C_f = 820 pF, R_f = 10 MOhm) and its 50 Hz notch, as the
built-in ``thesis-pzt-frequency`` scene says. The sweep is a reduced-order model
(``method = "reduced"``) checked against direct solves to ``analysis.tolerance``.
"""

import matplotlib.pyplot as plt
import numpy as np

import taxel

scene = taxel.load("thesis-pzt-frequency").replace(**{"analysis.points": 60})
sweep = taxel.solve(scene)
print("\n".join(sweep.summary()))
print(sweep.label, sweep.output.shape)

# %%
H = sweep.output[:, 0]
fig, (a, b) = plt.subplots(2, 1, figsize=(7, 5), sharex=True)
a.loglog(sweep.freqs, np.abs(H))
a.set(ylabel=f"|H| ({sweep.label})", title="pressed taxel through the charge amplifier and the notch")
b.semilogx(sweep.freqs, np.degrees(np.unwrap(np.angle(H))))
b.set(xlabel="frequency (Hz)", ylabel="phase (deg)")
fig.tight_layout()
