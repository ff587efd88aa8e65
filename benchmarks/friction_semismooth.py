"""Frictionless and Coulomb presses in 3D to the rig's load: the default solve (Options.solver
"auto": the penalty Newton inside the Uzawa loop, and a step it stops in again by the semi-smooth
Newton on the Alart-Curnier conditions, fem.contact._alart_curnier) against the Uzawa path alone
("uzawa", the path before) and the semi-smooth Newton alone ("semismooth"), side by side (issue 57).

The rig's probe (a 4 mm flat punch, 0.2 mm edge radius) presses the thesis PZT taxel
(thesis-pzt-probe-3d: "single") or the 3x3 array at its centre taxel ("3x3"), Yeoh Ecoflex,
(or the plane-strain probe example, thesis-pzt-probe-2d: "2d"),
quarter models, the default press mesh, force control to 1 N, with load.friction = frictionless,
0.1, 0.3, 1.0 (and sticking, for scale: the Uzawa path, the same in both). Per press: the force
reached (where a press stops: the force of its last converged state and the cause), V/F, load
states, Newton iterations, factorizations, CPU seconds; and the ratio of the two solvers' CPU.
--divide K: every size of the press mesh divided by K (taxel.scene.refined), for a two-level
estimate of each law's own discretisation error.

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/friction_semismooth.py
       [--cases single,3x3] [--laws frictionless,0.1,0.3,1.0] [--solvers auto,uzawa,semismooth] [--divide K]
writes benchmarks/out/friction_semismooth[_K].json (--write: docs/friction_semismooth.json too).
Measured: docs/benchmarks.md, "Friction that converges".
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from taxel.analyses import problem
from taxel.fem.assembly import assemble
from taxel.fem.contact import Options, Press, PressError
from taxel.scene import load

sys.path.insert(0, str(Path(__file__).resolve().parent))
from press_speed import scene  # noqa: E402

OUT = Path(__file__).resolve().parent / "out"
DOCS = Path(__file__).resolve().parents[1] / "docs"


def law(text: str):
    return text if text in ("frictionless", "sticking") else float(text)


def press(sc, friction, solver: str) -> dict:
    """One press to 1 N (mesh and assembly outside the clock); its numbers."""
    prob = problem(sc.replace(**{"load.friction": friction, "load.force": 1.0}))
    sy = assemble(prob)
    c = time.process_time()
    pr = Press(sy, prob.indenter, opts=Options(solver=solver))
    stop = None
    try:
        pr.force(1.0)
    except PressError as exc:
        stop = f"{exc.cause}: {exc.summary}"
    cpu = time.process_time() - c
    p = pr.res.points[-1] if pr.res.points else None
    V = p.voltages[next(iter(p.voltages))] if p else None
    return dict(friction=friction, solver=solver, unknowns=pr.red.n, force_N=p.force if p else 0.0,
                VF=V / p.force if p else None, travel_m=p.travel if p else 0.0, stop=stop, states=len(pr.res.points),
                newton=pr.res.total_iterations, factorizations=pr.stats["factorizations"],
                failed_trials=pr.res.failed_trials, cpu_s=cpu)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cases", default="single,3x3")
    ap.add_argument("--laws", default="frictionless,0.1,0.3,1.0")
    ap.add_argument("--solvers", default="auto,uzawa")
    ap.add_argument("--divide", type=float, default=None)
    ap.add_argument("--write", action="store_true")
    ap.add_argument("--out", default=None, help="another JSON file (runs in parallel processes)")
    a = ap.parse_args()
    tag = "" if a.divide is None else f"_{a.divide:g}"
    path = OUT / f"friction_semismooth{tag}.json"
    rows = json.loads(path.read_text()) if path.exists() else []
    if a.out is not None:
        path = Path(a.out)
    for case in a.cases.split(","):
        sc = scene(case) if case != "2d" else load("thesis-pzt-probe-2d")
        if a.divide is not None:
            from taxel.scene import refined
            sc = refined(sc, a.divide)
        for f in map(law, a.laws.split(",")):
            for solver in a.solvers.split(","):
                r = {"case": case, "divide": a.divide or 1.0, **press(sc, f, solver)}
                print(json.dumps(r), flush=True)
                rows = [q for q in rows if (q["case"], q["friction"], q["solver"], q["divide"])
                        != (case, f, solver, r["divide"])] + [r]
                OUT.mkdir(exist_ok=True)
                path.write_text(json.dumps(rows, indent=1))
    if a.write:
        (DOCS / f"friction_semismooth{tag}.json").write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
