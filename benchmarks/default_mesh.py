"""How far the default mesh is from the converged voltage, per model type.

For the thesis PZT taxel (1 N, linear silicone) in plane strain and
axisymmetric: a Richardson reference from nested uniform refinements of the
default mesh (4 levels, observed order), then the pressed-taxel voltage error of
the default mesh with 1, 2 and 3 elements through the piezo, and the unknowns.
`--3d` adds the 3D taxel, solved as a quarter (model.symmetry = "auto"), against
the Richardson reference of benchmarks/reference_3d.py (docs/reference_3d.json:
two chains of nested quarter meshes; the error is given against both
extrapolations, whose spread bounds the reference's own error); about a minute, 3 GB.

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/default_mesh.py [--3d]
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from taxel.analyses import mesh
from taxel.analyses import solve_static as solve
from taxel.scene import load

REFERENCE = Path(__file__).resolve().parents[1] / "docs" / "reference_3d.json"


def richardson(scene, levels=4):
    tm = mesh(scene)
    v = np.array([solve(scene, tagged_mesh=tm.refined(k) if k else tm).voltages()["taxel_0_0"]
                  for k in range(levels)])
    p = np.log2(abs(v[-2] - v[-3]) / abs(v[-1] - v[-2]))
    return v[-1] + (v[-1] - v[-2]) / (2 ** p - 1), p, v


def reference_3d():
    """The 3D single-taxel reference (benchmarks/reference_3d.py) and its two extrapolations."""
    ref = json.loads(REFERENCE.read_text())["single"]
    return ref["reference"], [f["reference"] for f in ref["fits"]], [f["order"] for f in ref["fits"]]


def main():
    models = ["plane_strain", "axisymmetric"] + (["3d"] if "--3d" in sys.argv else [])
    print(f"{'model':<14} {'reference V':>12} {'order':>6}  " + "  ".join(
        f"{f'{k} through: err %':>18} {'unknowns':>9}" for k in (1, 2, 3)))
    for model in models:
        base = load("thesis-pzt-single-2d").replace(**{"model.type": model})
        if model == "3d":
            v_ref, fits, orders = reference_3d()
            p = min(orders)
            layers = (1, 2, 3)
        else:
            v_ref, p, _ = richardson(base.replace(**{"mesh.piezo_layers": 2}))
            layers = (1, 2, 3)
        cells, volts = [], []
        for k in layers:
            sol = solve(base.replace(**{"mesh.piezo_layers": k}))
            volts.append(sol.voltages()["taxel_0_0"])
            cells.append((100 * abs(volts[-1] / v_ref - 1), sol.unknowns))
        print(f"{model:<14} {v_ref:>12.6f} {p:>6.2f}  " + "  ".join(f"{e:>18.3f} {n:>9}" for e, n in cells))
        if model == "3d":
            for k, sol_v in zip(layers, volts):
                print(f"  3d, {k} through: V = {sol_v:.6f}, error against the two extrapolations " + ", ".join(
                    f"{100 * abs(sol_v / f - 1):.3f} %" for f in fits))


if __name__ == "__main__":
    main()
