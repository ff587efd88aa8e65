"""
Crosstalk in the 3x3 array
==========================

The thesis sensor: 3x3 PZT taxels, 3 mm edge to edge. 1 N on the middle taxel;
every taxel is open circuit. The crosstalk is the largest neighbour voltage over
the pressed taxel's, in absolute value (see the glossary). A 2D cross-section
sees the middle row; the 3D model (coarse mesh, a quarter by symmetry, chosen by
``model.symmetry = "auto"``) sees all nine.
"""

import matplotlib.pyplot as plt
import numpy as np

import taxel

section = taxel.solve("thesis-pzt-3x3-2d")
print(section)
print(f"2D crosstalk: {section.crosstalk * 100:.1f} %")

array3d = taxel.load("thesis-pzt-3x3-3d").replace(**{"mesh.size": "2 mm", "mesh.piezo_size": "1 mm"})
full = taxel.solve(array3d)
print(f"3D crosstalk (coarse): {full.crosstalk * 100:.1f} %")

# %%
# The nine voltages of the 3D model, and the middle row of both models.
v = full.voltages()
grid = np.array([[v[f"taxel_{r}_{c}"] for c in range(3)] for r in range(3)]) * 1e3
fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.6))
art = a.imshow(grid, cmap="RdBu_r", vmin=-abs(grid).max(), vmax=abs(grid).max())
for (r, c), val in np.ndenumerate(grid):
    a.text(c, r, f"{val:.0f}", ha="center", va="center")
fig.colorbar(art, ax=a, label="mV")
a.set(title="3D (coarse): open-circuit voltage", xticks=range(3), yticks=range(3), xlabel="col", ylabel="row")
row2d = [section.voltages()[f"taxel_1_{c}"] * 1e3 for c in range(3)]
b.plot(range(3), row2d, "o-", label="2D cross-section")
b.plot(range(3), grid[1], "s--", label="3D, middle row")
b.set(xticks=range(3), xlabel="col", ylabel="voltage (mV)", title="middle row")
b.legend()
fig.tight_layout()
