"""Speed of the thesis-taxel press to 1 N in 2D plane strain (Yeoh silicone, 4 mm flat
punch, 0.2 mm edge radius, force control), before and after the vectorisation, in
one run, side by side.

  before      Options(assembly="skfem", predictor=False, fix_cycling=False): the path as
              merged before issue 14's second session (scikit-fem forms for the Yeoh and
              contact terms, sparse products with the elimination P, zero-order start of each
              travel, secant force control) -- kept callable for this comparison
  vectorised  the same Newton path, vectorised assembly (fem.hyperelastic, fem.assembly): same
              iterates, so the ratio is the assembly's alone
  frictionless  vectorised, tangent predictor dx/dd, Newton on F(d) with the path
              stiffness, Newton finishing on a recurring active set (fix_cycling)
  sticking full  the same, a sticking punch (the scene's default friction), full section
  default     the scene's defaults: sticking, model.symmetry = "auto" (a half section)

and the whole solve a user waits for (mesh, assembly, press) with the defaults.

Prints per variant: wall and CPU time, converged states, Newton iterations of the
converged states, factorizations, residual evaluations, and the CPU time in
factorization and in assembly (Press.stats); the voltage at 1 N. One run each (they take tens of seconds on this shared
2-core machine): the ratios of CPU time (process_time, less sensitive to the other
sessions' load than wall time), not the absolute times, are the result.

Run: MKL_NUM_THREADS=1 python benchmarks/contact_speed.py [--force 1.0] [--skip-before] [--axisym]
"""

import sys
import time

from taxel.analyses import problem
from taxel.fem.assembly import assemble
from taxel.fem.contact import PressError, Options, Press
from taxel.scene import load

VARIANTS = {      # name: (friction, model.symmetry, Options)
    "before": ("frictionless", "full", dict(assembly="skfem", predictor=False, fix_cycling=False)),
    "vectorised": ("frictionless", "full", dict(predictor=False, fix_cycling=False)),
    "frictionless": ("frictionless", "full", dict()),
    "sticking full": ("sticking", "full", dict()),
    "default": ("sticking", "auto", dict()),     # the scene's defaults: sticking, a half section
}


def scene(force, model="plane_strain", friction="sticking", symmetry="auto"):
    return load("thesis-pzt-single-2d").replace(**{
        "model.type": model, "model.silicone": "yeoh", "load.kind": "probe", "load.contact": True,
        "load.radius": 2e-3, "load.edge_radius": 0.2e-3, "load.force": force, "load.friction": friction,
        "model.symmetry": symmetry})


def run(force, variant, model="plane_strain"):
    friction, symmetry, opts = variant
    prob = problem(scene(force, model, friction, symmetry))
    sy = assemble(prob)
    pr = Press(sy, prob.indenter, opts=Options(**opts))
    t0, c0 = time.perf_counter(), time.process_time()
    stop = ""
    try:
        pt = pr.force(force)
        V = pt.voltages["taxel_0_0"]
    except PressError as exc:
        stop, V = str(exc), float("nan")
    return time.perf_counter() - t0, pr, V, stop, time.process_time() - c0


def main():
    force = float(sys.argv[sys.argv.index("--force") + 1]) if "--force" in sys.argv else 1.0
    model = "axisymmetric" if "--axisym" in sys.argv else "plane_strain"
    names = [n for n in VARIANTS if not (n == "before" and "--skip-before" in sys.argv)]
    rows = {}
    for name in names:
        rows[name] = run(force, VARIANTS[name], model)
    from taxel.analyses import solve_static
    whole = []                           # what a user waits for: mesh, assembly and press, defaults
    for _ in range(3):
        c0, t0 = time.process_time(), time.perf_counter()
        solve_static(scene(force, model))
        whole.append((time.process_time() - c0, time.perf_counter() - t0))
    print(f"thesis taxel, Yeoh, 4 mm punch r_e 0.2 mm, {model}, to {force} N")
    print(f"{'variant':>11} {'wall s':>7} {'CPU s':>7} {'states':>6} {'iters':>5} {'factor.':>7} {'resid.':>6} "
          f"{'factor CPU s':>12} {'assem CPU s':>11} {'V':>9}")
    for name, (t, pr, V, stop, cpu) in rows.items():
        s = pr.stats
        print(f"{name:>11} {t:7.2f} {cpu:7.2f} {len(pr.res.points):6d} {pr.res.total_iterations:5d} {s['factorizations']:7d} "
              f"{s['residuals']:6d} {s['factorize_s']:12.2f} {s['assemble_s']:11.2f} {V:9.5f}")
        if stop:
            print(f"{'':>11} stopped: {stop}")
    cpu, wall = sorted(whole)[1]
    print(f"the whole solve with the scene's defaults (taxel.solve_static: mesh, assembly, press), "
          f"median of 3: {cpu:.2f} s CPU, {wall:.2f} s wall")
    base = rows[names[0]][4]
    print("CPU-time speed-up over", names[0] + ":", ", ".join(f"{n} {base / r[4]:.2f}x" for n, r in rows.items()))
    if "vectorised" in rows and "before" in rows:
        a0, a1 = rows["before"][1].stats, rows["vectorised"][1].stats
        print(f"assembly CPU time per residual evaluation: before {1e3 * a0['assemble_s'] / a0['residuals']:.1f} ms, "
              f"vectorised {1e3 * a1['assemble_s'] / a1['residuals']:.1f} ms "
              f"({a0['assemble_s'] / a0['residuals'] / (a1['assemble_s'] / a1['residuals']):.1f}x)")


if __name__ == "__main__":
    main()
