"""One press of the thesis taxel (Yeoh silicone, 4 mm flat punch, 0.2 mm edge
radius) by force control to a target, with its converged states and, with -v,
every Newton iteration (travel, iteration, scaled residual, active points, line
search step): where and how a press stops.

Run: MKL_NUM_THREADS=1 python benchmarks/contact_trace.py MODEL FORCE [OPTIONS] [SCENE] [-s] [-v]
  MODEL   plane_strain | axisymmetric
  FORCE   N
  OPTIONS a dict of fem.contact.Options fields, e.g. "{'fix_cycling': False}"
  SCENE   a dict of scene keys, e.g. "{'mesh.piezo_size': 5e-5}"
  -s      sticking contact (default frictionless)
"""

import ast
import sys
import time

from taxel.analyses import problem
from taxel.fem.assembly import assemble
from taxel.fem.contact import PressError, Options, Press
from taxel.scene import load


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("-")]
    model, force = args[0], float(args[1])
    opts = ast.literal_eval(args[2]) if len(args) > 2 else {}
    extra = ast.literal_eval(args[3]) if len(args) > 3 else {}
    sc = load("thesis-pzt-single-2d").replace(**{
        "model.type": model, "model.silicone": "yeoh", "load.kind": "probe", "load.contact": True,
        "load.radius": 2e-3, "load.edge_radius": 0.2e-3, "load.force": force,
        "load.friction": "sticking" if "-s" in sys.argv else "frictionless", **extra})
    prob = problem(sc)
    pr = Press(assemble(prob), prob.indenter, opts=Options(**opts))
    t = time.perf_counter()
    try:
        pr.force(force)
    except PressError as exc:
        print("stopped:", exc)
    print(f"{time.perf_counter() - t:.2f} s wall, {len(pr.res.points)} states, {pr.res.total_iterations} Newton "
          f"iterations, {pr.res.failed_trials} failed trials, {len(pr.trace)} Newton steps in all; {pr.stats}")
    for p in pr.res.points:
        print(f"  travel {p.travel * 1e3:.4f} mm  F {p.force:.4f} N  V {list(p.voltages.values())[0]:.5f}  "
              f"iterations {p.iterations}  Uzawa {p.uzawa}")
    if "-v" in sys.argv:
        for s in pr.trace:
            print(f"    travel {s[0] * 1e3:.4f} it {s[1]} residual {s[2]:.2e} active {s[3]} "
                  f"step {s[4] if len(s) > 4 else ''}")


if __name__ == "__main__":
    main()
