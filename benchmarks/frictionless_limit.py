"""How far a frictionless press of the rig's probe gets, in the axisymmetric model
(the 3D press's physics at a fraction of its cost, so fine meshes are affordable):
the thesis taxel (thesis-pzt-probe-axisymmetric), Yeoh, a 4 mm flat punch with a
0.2 mm edge radius, friction = "frictionless", force control to 1 N in one target
and along 0.2, 0.4, 0.6, 0.7, 0.8, 0.9, 1 N, on four meshes: the 3D default press
mesh's sizes (1.4 / 0.56 mm), the example's (0.5 / 0.1 mm), and that halved twice.
Prints per mesh and path the force reached, its travel, and the cause of the stop
(fem.contact.PressError's cause and summary), so the 3D press's stop (benchmarks/press_3d.py
--frictionless) can be read against the same physics on finer meshes.

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/frictionless_limit.py
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

from taxel.analyses import check, checked_layout
from taxel.scene import load

sys.path.insert(0, str(Path(__file__).parent))
from press_3d import run, stop  # noqa: E402

MESHES = {"3D default press sizes, 1.4 / 0.56 mm": (1.4e-3, 0.56e-3), "the example's, 0.5 / 0.1 mm": (0.5e-3, 0.1e-3),
          "0.25 / 0.05 mm": (0.25e-3, 0.05e-3), "0.125 / 0.025 mm": (0.125e-3, 0.025e-3)}
PATHS = {"1 N in one target": (), "along 0.2, 0.4, 0.6, 0.7, 0.8, 0.9, 1 N": (0.2, 0.4, 0.6, 0.7, 0.8, 0.9)}


def main():
    sc = load("thesis-pzt-probe-axisymmetric").replace(**{"load.friction": "frictionless"})
    print("| mesh | path | unknowns | force reached (N) | travel (mm) | stop | CPU s |\n|---|---|---|---|---|---|---|")
    for name, (h, hp) in MESHES.items():
        lay = dataclasses.replace(checked_layout(sc, check(sc)), size=h, piezo_size=hp)
        for pname, path in PATHS.items():
            r = run(sc, lay, path=path)            # press_3d.run: mesh, assemble, press to 1 N along `path`
            F, d, _, cause = stop(r)
            print(f"| {name} | {pname} | {r['n']} | {F:.3f} | {1e3 * d:.3f} | {cause} | {r['cpu']:.0f} |", flush=True)


if __name__ == "__main__":
    main()
