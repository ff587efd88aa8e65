"""How far the default mesh is from the converged voltage, per model type.

For the thesis PZT taxel (1 N, linear silicone) in plane strain and
axisymmetric: a Richardson reference from nested uniform refinements of the
default mesh (4 levels, observed order), then the pressed-taxel voltage error of
the default mesh with 1, 2 and 3 elements through the piezo, and the unknowns.
`--3d` adds the 3D taxel (reference: a coarse mesh and its uniform refinement,
extrapolated with the 2D observed order; slow: minutes, about 8 GB).

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/default_mesh.py [--3d]
"""

from __future__ import annotations

import sys

import numpy as np

from taxel.analyses import mesh
from taxel.analyses import solve_static as solve
from taxel.scene import load, refined


def richardson(scene, levels=4):
    tm = mesh(scene)
    v = np.array([solve(scene, tagged_mesh=tm.refined(k) if k else tm).voltages()["taxel_0_0"]
                  for k in range(levels)])
    p = np.log2(abs(v[-2] - v[-3]) / abs(v[-1] - v[-2]))
    return v[-1] + (v[-1] - v[-2]) / (2 ** p - 1), p, v


def reference_3d(base, p):
    """3D: a coarse mesh (1 mm, 0.4 mm at the taxel, two elements through the
    piezo) and gmsh's mesh at half every size (4 through), extrapolated with the
    observed 2D order p (scikit-fem cannot refine a tetrahedral mesh with its named
    boundaries, so the two meshes are similar, not nested: an estimate)."""
    coarse = base.replace(**{"mesh.size": "1 mm", "mesh.piezo_size": "0.4 mm", "mesh.piezo_layers": 2})
    v0, v1 = (solve(refined(coarse, f)).voltages()["taxel_0_0"] for f in (1, 2))
    return v1 + (v1 - v0) / (2 ** p - 1), p, np.array([v0, v1])


def main():
    models = ["plane_strain", "axisymmetric"] + (["3d"] if "--3d" in sys.argv else [])
    print(f"{'model':<14} {'reference V':>12} {'order':>6}  " + "  ".join(
        f"{f'{k} through: err %':>18} {'unknowns':>9}" for k in (1, 2, 3)))
    p2d = None
    for model in models:
        base = load("thesis-pzt-single-2d").replace(**{"model.type": model})
        if model == "3d":
            v_ref, p, _ = reference_3d(base, p2d)
            layers = (1, 2)
        else:
            v_ref, p, _ = richardson(base.replace(**{"mesh.piezo_layers": 2}))
            p2d = p2d or p
            layers = (1, 2, 3)
        cells = []
        for k in layers:
            sol = solve(base.replace(**{"mesh.piezo_layers": k}))
            cells.append((100 * abs(sol.voltages()["taxel_0_0"] / v_ref - 1), sol.unknowns))
        print(f"{model:<14} {v_ref:>12.6f} {p:>6.2f}  " + "  ".join(f"{e:>18.3f} {n:>9}" for e, n in cells))


if __name__ == "__main__":
    main()
