"""
One taxel in each model: plane strain, plane stress, axisymmetric, 3D
======================================================================

The same taxel and press, in the four model types of ``model.type``. The 2D
sections bracket the 3D answer (plane strain is too stiff across the depth, plane
stress too soft); the axisymmetric model is a round taxel of the same area. The 3D
model here uses a coarse mesh so that the example runs in seconds: the guide's
"Meshes and accuracy" page says how far it is from converged.
"""

import time

import matplotlib.pyplot as plt

import taxel

base = taxel.load("thesis-pzt-single-2d")
models = {
    "plane_strain": base,
    "plane_stress": base.replace(**{"model.type": "plane_stress"}),
    "axisymmetric": base.replace(**{"model.type": "axisymmetric"}),
    "3d": taxel.load("thesis-pzt-single-3d").replace(**{"mesh.size": "1.5 mm", "mesh.piezo_size": "0.8 mm"}),
}
sensitivity, seconds = {}, {}
for name, scene in models.items():
    t0 = time.perf_counter()
    result = taxel.solve(scene)
    seconds[name] = time.perf_counter() - t0
    sensitivity[name] = result.outputs()["sensitivity"]
    print(f"{name:>13}: {sensitivity[name] * 1e3:8.1f} mV/N, {result.unknowns:6d} unknowns, "
          f"{seconds[name]:.1f} s")

# %%
fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.2))
a.bar(list(sensitivity), [abs(v) * 1e3 for v in sensitivity.values()], color="C0")
a.set(ylabel="|sensitivity| (mV/N)", title="pressed-taxel open-circuit voltage per newton")
b.bar(list(seconds), list(seconds.values()), color="C1")
b.set(ylabel="wall time (s)", title="cost of one solve")
for ax in (a, b):
    ax.tick_params(axis="x", rotation=20)
fig.tight_layout()
