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
# The potential in the cross-section: the field lives in the piezo layer (the
# silicone is an insulator that carries no charge here), the displacement is
# drawn 20 times enlarged.
mesh, fields = result.mesh.mesh, result.fields
x, y = mesh.p * 1e3
scale = 20.0
fig, ax = plt.subplots(figsize=(8, 3))
ax.triplot(x + scale * fields.u[:, 0] * 1e3, y + scale * fields.u[:, 1] * 1e3, mesh.t.T, lw=0.2, color="0.6")
art = ax.tripcolor(x, y, mesh.t.T, fields.phi, shading="gouraud", cmap="RdBu_r")
fig.colorbar(art, ax=ax, label="potential (V)")
ax.set(xlabel="x (mm)", ylabel="z (mm)", aspect="equal",
       title=f"open-circuit voltage {result.voltages()['taxel_0_0'] * 1e3:.0f} mV for 1 N")
ax.set_ylim(y.min() - 0.2, y.max() + 0.2)
fig.tight_layout()
