"""
A single taxel in 2D
====================

The thesis PZT taxel (PSI-5H4E, 4 mm wide, 0.127 mm thick, in 1 mm of Ecoflex
00-30 above and below) as a plane-strain cross-section, pressed by 1 N spread over
its top. ``taxel.solve`` returns a ``StaticResult``: its electrode table, its
outputs (``sensitivity`` is the pressed taxel's open-circuit voltage per newton)
and the fields on the mesh it solved.
"""

import matplotlib.pyplot as plt

import taxel

scene = taxel.load("thesis-pzt-single-2d")
result = taxel.solve(scene)
print(result)
print(result.outputs())

# %%
# The vertical displacement in the cross-section (the press sinks the silicone
# above the taxel), and the potential through the piezo's thickness at its
# centre: it falls from the floating top electrode to the grounded bottom one.
import numpy as np

mesh, fields = result.mesh.mesh, result.fields
x, z = mesh.p * 1e3
fig, (a, b) = plt.subplots(1, 2, figsize=(10, 3.4), width_ratios=[3, 1])
art = a.tripcolor(x, z, mesh.t.T, fields.u[:, 1] * 1e6, shading="gouraud", cmap="viridis")
fig.colorbar(art, ax=a, label="vertical displacement (um)")
a.set(xlabel="x (mm)", ylabel="z (mm)", xlim=(-6, 6), aspect="equal", title="1 N on the taxel")
centre = (np.abs(x) < 1e-9) & (fields.phi != 0)
order = np.argsort(z[centre])
b.plot(fields.phi[centre][order], z[centre][order], "o-")
b.set(xlabel="potential (V)", ylabel="z (mm)", title="through the piezo at x = 0")
fig.tight_layout()
