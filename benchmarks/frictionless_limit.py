"""How far a frictionless press of the rig's probe gets, in the axisymmetric model
(the 3D press's physics at a fraction of its cost, so fine meshes are affordable):
the thesis taxel (thesis-pzt-probe-axisymmetric), Yeoh, a 4 mm flat punch with a
0.2 mm edge radius, friction = "frictionless", force control to 1 N in one target
and along 0.2, 0.4, 0.6, 0.7, 0.8, 0.9, 1 N, on four meshes: the 3D default press
mesh's sizes (1.4 / 0.56 mm), the example's (0.5 / 0.1 mm), and that halved twice.
Prints per mesh and path the force reached, its travel, and the cause of the stop
(fem.press.ContactError's first clause), so the 3D press's stop (benchmarks/press_3d.py
--frictionless) can be read against the same physics on finer meshes.

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/frictionless_limit.py
"""

from __future__ import annotations

import dataclasses
import time

from taxel.analyses import problem
from taxel.analyses.adapter import check, checked_layout
from taxel.fem.assembly import assemble
from taxel.fem.press import ContactError, Press
from taxel.meshing.build import build
from taxel.scene import load

MESHES = {"3D default press sizes, 1.4 / 0.56 mm": (1.4e-3, 0.56e-3), "the example's, 0.5 / 0.1 mm": (0.5e-3, 0.1e-3),
          "0.25 / 0.05 mm": (0.25e-3, 0.05e-3), "0.125 / 0.025 mm": (0.125e-3, 0.025e-3)}
PATHS = {"1 N in one target": (1.0,), "along 0.2, 0.4, 0.6, 0.7, 0.8, 0.9, 1 N": (0.2, 0.4, 0.6, 0.7, 0.8, 0.9, 1.0)}


def run(size, piezo_size, path):
    """(unknowns, force reached N, its travel m, 'reached 1 N' or the stop's cause, CPU s)."""
    sc = load("thesis-pzt-probe-axisymmetric").replace(**{"load.friction": "frictionless"})
    lay = dataclasses.replace(checked_layout(sc, check(sc)), size=size, piezo_size=piezo_size)
    t = time.process_time()
    prob = problem(sc, tagged_mesh=build(lay))
    pr = Press(assemble(prob), prob.indenter)
    cause = "reached 1 N"
    try:
        for F in path:
            pr.force(F)
    except ContactError as exc:
        text = str(exc)               # its first clause: the cause and where
        cause = text.split(":")[0] if text.startswith("Newton") else text.split(" (")[0]
    p = pr.res.points[-1] if pr.res.points else None
    return pr.red.n, p.force if p else 0.0, p.travel if p else 0.0, cause, time.process_time() - t


def main():
    print("| mesh | path | unknowns | force reached (N) | travel (mm) | stop | CPU s |\n|---|---|---|---|---|---|---|")
    for name, (h, hp) in MESHES.items():
        for pname, path in PATHS.items():
            n, F, d, cause, cpu = run(h, hp, path)
            print(f"| {name} | {pname} | {n} | {F:.3f} | {1e3 * d:.3f} | {cause} | {cpu:.0f} |", flush=True)


if __name__ == "__main__":
    main()
