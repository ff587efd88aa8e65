"""
The sensitivity-crosstalk front, and its check in 3D
====================================================

An optimization with a ``[pareto]`` table finds the front of sensitivity against
crosstalk: for each crosstalk bound, the most sensitive design (epsilon
constraints, nlopt). This one is small (3 bounds, few evaluations, the 2D section
of the 3x3 array); the built-in ``thesis-pzt-front`` is the full one, and the main
job (``make demo``) verifies and corrects it in 3D. Here each front design is
simply solved again on a coarse 3D quarter model, through the public API: the 2D
section overstates crosstalk (about 3 times for this PZT array).
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

import taxel

folder = Path(tempfile.mkdtemp(prefix="taxel-front-"))
(folder / "front.toml").write_text('''
description = "a small PZT front: sensitivity against crosstalk, 2D"
base = "thesis-pzt-3x3-2d"
reference = {silicone_above = "1 mm", gap = "3 mm"}

[variables]
silicone_above = {path = "array.silicone_above", min = "0.3 mm", max = "1.7 mm", start = "1 mm"}
gap = {path = "array.gap", min = "1 mm", max = "5 mm", start = "3 mm"}

[objective]
maximize = "sensitivity"

[pareto]
points = 3

[algorithm]
global = "none"
local = "COBYLA"
max_evaluations = 10
''')
front = taxel.run_optimization(folder / "front.toml", folder / "out", workers=1)
print("\n".join(front.summary()))

# %%
# Each front design again in 3D (a coarse quarter model: a few seconds each).
coarse_3d = {"model.type": "3d", "mesh.size": "2 mm", "mesh.piezo_size": "1 mm"}
points_2d, points_3d = [], []
for run in front.runs:
    design = {f"array.{name}": f"{x} {unit}" for name, x, unit in zip(front.names, run.result.x, front.units)}
    scene = taxel.load("thesis-pzt-3x3-2d").replace(**design)
    in_3d = taxel.solve(scene.replace(**coarse_3d))
    points_2d.append((run.result.metrics["crosstalk"], run.result.metrics["sensitivity"]))
    points_3d.append((in_3d.outputs()["crosstalk"], abs(in_3d.outputs()["sensitivity"])))
    print(design, f"2D: {points_2d[-1][1]:.3f} V/N, {points_2d[-1][0] * 100:.1f} %;",
          f"3D: {points_3d[-1][1]:.3f} V/N, {points_3d[-1][0] * 100:.1f} %")

fig, ax = plt.subplots(figsize=(6.5, 4))
for pts, style, label in ((points_2d, "o-", "front, 2D section"), (points_3d, "s--", "same designs, 3D (coarse)")):
    c, s = zip(*sorted(pts))
    ax.plot([x * 100 for x in c], s, style, label=label)
ax.set(xlabel="crosstalk (%)", ylabel="sensitivity (V/N)", title="sensitivity-crosstalk front")
ax.legend()
fig.tight_layout()
