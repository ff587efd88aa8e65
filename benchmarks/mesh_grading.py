"""Error against unknowns for the mesh grading choices (thesis PZT taxel, 1 N):
which mesh reaches 0.5 % in the pressed-taxel voltage for the fewest unknowns.

The choices (meshing.layout.Layout): the far size `size`, the size at the taxel
and load edges `piezo_size`, the distance over which the size grows from one to
the other (`growth` x size), the largest size inside a taxel (`taxel_cap` x
piezo_size) and the elements through the piezo (`piezo_layers`). Plane strain is
measured against the Richardson value of 4 nested refinements of the default mesh
(as benchmarks/default_mesh.py), 3D (quarter model) against
benchmarks/reference_3d.py (docs/reference_3d.json). Prints every point (its signed
error; the chart and the summary take its magnitude), the
cheapest within 0.5 % per model, the default's point, and draws
docs/mesh-grading.png (error against unknowns; the default marked).

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/mesh_grading.py [--no-3d]
"""

from __future__ import annotations

import itertools
import json
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

from taxel.analyses import solve_static as solve
from taxel.analyses import layout
from taxel.analyses import scene_materials
from taxel.meshing.build import build
from taxel.scene import load

sys.path.insert(0, str(Path(__file__).parent))
from default_mesh import richardson  # noqa: E402

DOCS = Path(__file__).resolve().parents[1] / "docs"
TARGET = 0.5


def point(scene, **choice):
    lay = replace(layout(scene, scene_materials(scene)), **choice)
    sol = solve(scene, tagged_mesh=build(lay))
    return sol.unknowns, sol.voltages()["taxel_0_0"]


def sweep(scene, grid, v_ref, label):
    rows = []
    for values in itertools.product(*grid.values()):
        choice = dict(zip(grid, values))
        if choice["piezo_size"] > choice["size"]:
            continue
        n, v = point(scene, **choice)
        rows.append((choice, n, 100 * abs(v / v_ref - 1)))
        c, signed = choice, 100 * (v / v_ref - 1)
        print(f"{label:<12} size {1e3 * c['size']:.2f} piezo {1e3 * c['piezo_size']:.3f} mm  growth {c['growth']:g}  "
              f"cap {c['taxel_cap']:g}  through {c['piezo_layers']}  {n:>7} unknowns  {signed:+.3f} %", flush=True)
    return rows


def main():
    scene2 = load("thesis-pzt-single-2d").replace(**{"model.type": "plane_strain"})
    v2, p2 = richardson(scene2)
    print(f"plane strain reference {v2:.6f} V (observed order {p2:.2f})")
    out = {"plane strain": sweep(scene2, {
        "size": [0.5e-3, 1e-3, 2e-3], "piezo_size": [0.05e-3, 0.1e-3, 0.2e-3], "growth": [1.0, 2.0, 4.0],
        "taxel_cap": [2.0, 8.0], "piezo_layers": [1, 2, 3]}, v2, "plane strain")}
    default = {"plane strain": point(scene2)}
    if "--no-3d" not in sys.argv:
        ref = json.loads((DOCS / "reference_3d.json").read_text())["single"]["reference"]
        scene3 = load("thesis-pzt-single-3d").replace(**{"model.symmetry": "quarter"})
        out["3d quarter"] = sweep(scene3, {
            "size": [1e-3, 2e-3], "piezo_size": [0.2e-3, 0.4e-3], "growth": [1.0, 2.0],
            "taxel_cap": [2.0, 4.0], "piezo_layers": [1, 2]}, ref, "3d quarter")
        default["3d quarter"] = point(scene3)
        default["3d quarter"] = (default["3d quarter"][0], 100 * abs(default["3d quarter"][1] / ref - 1))
    default["plane strain"] = (default["plane strain"][0], 100 * abs(default["plane strain"][1] / v2 - 1))
    print()
    for model, rows in out.items():
        ok = [r for r in rows if r[2] <= TARGET]
        best = min(ok, key=lambda r: r[1]) if ok else None
        n, e = default[model]
        print(f"{model}: the scene's mesh {n} unknowns, {e:.3f} %")
        if best:
            c = best[0]
            print(f"{model}: cheapest within {TARGET} %: {best[1]} unknowns, {best[2]:.3f} % "
                  f"(size {1e3 * c['size']:g} mm, piezo {1e3 * c['piezo_size']:g} mm, growth {c['growth']:g}, "
                  f"cap {c['taxel_cap']:g}, {c['piezo_layers']} through)")
    chart(out, default)


def chart(out, default):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(out), figsize=(5.5 * len(out), 4.2), layout="constrained", squeeze=False)
    for ax, (model, rows) in zip(axes[0], out.items()):
        for layers, marker in ((1, "v"), (2, "o"), (3, "s")):
            pts = np.array([(n, e) for c, n, e in rows if c["piezo_layers"] == layers])
            if len(pts):
                ax.loglog(pts[:, 0], pts[:, 1], marker, alpha=0.6, label=f"{layers} through the piezo")
        n, e = default[model]
        ax.loglog([n], [e], "k*", ms=14, label="the scene's mesh")
        ax.axhline(TARGET, color="r", lw=0.8, ls="--", label=f"{TARGET} %")
        ax.set_xlabel("unknowns")
        ax.set_ylabel("pressed-taxel voltage error (%)")
        ax.set_title(f"thesis PZT taxel, {model}", fontsize=10)
        ax.legend(fontsize=8)
    fig.savefig(DOCS / "mesh-grading.png", dpi=110)
    print(f"wrote {DOCS / 'mesh-grading.png'}")


if __name__ == "__main__":
    main()
