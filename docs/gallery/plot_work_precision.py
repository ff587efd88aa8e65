"""
Work against precision, small
=============================

Which model and mesh to trust for a number is a trade of wall time against error.
``taxel work-precision SCENE`` (``taxel.work_precision``) draws the full chart:
every model type, element order, three mesh levels and both silicone laws, against
a Richardson-extrapolated fine 3D reference, cached in a store; it takes minutes.
This example draws a small one through ``taxel.solve``: the pressed taxel's
sensitivity of the single thesis taxel in plane strain, axisymmetric and 3D at a
few mesh sizes, against the finest 3D solved here (so the 3D errors are relative
to that mesh, not to a converged value).
"""

import time

import matplotlib.pyplot as plt

import taxel

single_2d = taxel.load("thesis-pzt-single-2d")
single_3d = taxel.load("thesis-pzt-single-3d")
levels = {
    "plane strain": [single_2d.replace(**{"mesh.size": f"{s} mm", "mesh.piezo_size": f"{s / 5} mm"})
                     for s in (1.0, 0.5, 0.25)],
    "axisymmetric": [single_2d.replace(**{"model.type": "axisymmetric", "mesh.size": f"{s} mm",
                                          "mesh.piezo_size": f"{s / 5} mm"}) for s in (1.0, 0.5, 0.25)],
    "3d": [single_3d.replace(**{"mesh.size": f"{s} mm", "mesh.piezo_size": f"{s * 0.4} mm"})
           for s in (3.0, 2.0, 1.5, 1.0)],
}
timed = {}
for model, scenes in levels.items():
    timed[model] = []
    for scene in scenes:
        t0 = time.perf_counter()
        s = abs(taxel.solve(scene).outputs()["sensitivity"])
        timed[model].append((time.perf_counter() - t0, s, scene.mesh.size))
reference = timed["3d"][-1][1]
print(f"reference: 3D at 1 mm, {reference:.4f} V/N")
for model, rows in timed.items():
    for seconds, s, size in rows:
        print(f"{model:>13} {size * 1e3:4.2f} mm: {s:.4f} V/N, error {abs(s / reference - 1) * 100:5.2f} %, "
              f"{seconds:.2f} s")

# %%
fig, ax = plt.subplots(figsize=(6.5, 4))
for model, rows in timed.items():
    rows = rows[:-1] if model == "3d" else rows        # the reference itself has no error here
    ax.loglog([r[0] for r in rows], [abs(r[1] / reference - 1) * 100 for r in rows], "o-", label=model)
ax.set(xlabel="wall time (s)", ylabel="error in sensitivity (%)",
       title="single PZT taxel, 1 N: error against the 1 mm 3D model")
ax.legend()
fig.tight_layout()
