"""The 3D thesis taxel pressed to 1 N by the 4 mm flat punch (0.2 mm edge radius), Yeoh
silicone, sticking, a quarter model: the default 3D mesh (thesis-pzt-single-3d) and two
finer ones (sizes / 1.6, / 1.6^2), the press's own discretisation error in 3D (the
observed order and a Richardson extrapolation when the three are monotone); with --frictionless, where a
frictionless punch stops (displacement control to 0.45 mm) on the default mesh or
with a finer surface over the taxel (--piezo-size).

Prints per mesh: unknowns of the quarter (after the constraints), voltage and travel at 1 N, load steps, Newton
iterations, factorizations, wall and CPU time, and the default mesh's voltage against the
finer one. One run each (minutes on a shared 2-core machine).

With --rules, the contact point rule on the 3D facets (Gauss points, the P2 edge
midpoints, the six P2 nodes lumped): Newton iterations to the first 0.1 N; then the rig's
probe press (thesis-pzt-probe-3d, the default press mesh) to 1 N, sticking, and
frictionless to 0.4 mm, with the midpoints and the nodes: V/F, the deepest P2 node in
the punch (the midpoints rule leaves the vertices free), CPU.

Run: MKL_NUM_THREADS=1 python benchmarks/contact_3d.py [--frictionless [--piezo-size 0.2e-3] | --rules]
"""

import sys
import time

import numpy as np

from taxel.analyses import problem
from taxel.fem.assembly import assemble
from taxel.fem.contact import PressError, Press
from taxel.scene import load

RATIO = 1.6        # each mesh's sizes over the next one's
MESHES = {"default (1 mm, 0.4 mm on the taxel, 2 through the PZT)": {},
          "/1.6 (0.625 mm, 0.25 mm on the taxel, 2 through)": {"mesh.size": 1e-3 / RATIO,
                                                              "mesh.piezo_size": 0.4e-3 / RATIO},
          "/1.6^2 (0.39 mm, 0.156 mm on the taxel, 2 through)": {"mesh.size": 1e-3 / RATIO ** 2,
                                                                "mesh.piezo_size": 0.4e-3 / RATIO ** 2}}


def scene(friction="sticking", **mesh):
    return load("thesis-pzt-single-3d").replace(**{
        "model.silicone": "yeoh", "load.kind": "probe", "load.contact": True, "load.radius": 2e-3,
        "load.edge_radius": 0.2e-3, "load.force": 1.0, "load.friction": friction, **mesh})


RULES = {"6 Gauss points per facet (intorder 3)": dict(rule="gauss", intorder=3),
         "3 Gauss points per facet (intorder 2)": dict(rule="gauss", intorder=2),
         "the P2 edge midpoints (rule midpoints)": dict(rule="midpoints"),
         "the six P2 nodes, HRZ-lumped (rule nodal, the 3D default)": dict(rule="nodal")}


def rules():
    """The contact points on the P2 triangle facets: the Newton iterations a quarter of the
    3D taxel (coarse mesh, linear silicone, sticking punch) takes to its first 0.1 N, with
    a budget of 10 multiplier updates per travel and 6 force-control trials."""
    from taxel.fem.contact import Options
    coarse = {"mesh.size": 1e-3, "mesh.piezo_size": 0.5e-3, "mesh.piezo_layers": 1, "model.silicone": "linear"}
    for name, opts in RULES.items():
        prob = problem(scene(**coarse))
        pr = Press(assemble(prob), prob.indenter, opts=Options(max_uzawa=10, **opts))
        t0 = time.perf_counter()
        try:
            pr.force(0.1, max_trials=6)
            end = f"0.1 N reached at {1e3 * pr.d:.4f} mm"
        except PressError as exc:
            end = f"0.1 N not reached ({exc})"
        print(f"{name}: {len(pr.trace)} Newton iterations, {time.perf_counter() - t0:.0f} s; {end}; "
              f"deepest node {1e6 * pr.node_penetration():.3g} um", flush=True)
    from taxel.analyses import check, checked_layout
    from taxel.meshing.build import build
    print("| press | rule | unknowns | travel (mm) | force (N) | V/F (V/N) | deepest node (um) | CPU s |\n"
          "|---|---|---|---|---|---|---|---|")
    for friction in ("sticking", "frictionless"):
        sc = load("thesis-pzt-probe-3d").replace(**{"load.friction": friction})
        prob = problem(sc, tagged_mesh=build(checked_layout(sc, check(sc))))
        sy = assemble(prob)
        for rule in ("midpoints", "nodal"):
            pr = Press(sy, prob.indenter, opts=Options(rule=rule))
            c = time.process_time()
            pt = pr.force(1.0) if friction == "sticking" else pr.travel(0.4e-3)
            print(f"| {friction} | {rule} | {pr.red.n} | {1e3 * pt.travel:.4f} | {pt.force:.4f} | "
                  f"{pt.voltages['taxel_0_0'] / pt.force:.5f} | {1e6 * pr.node_penetration():.3g} | "
                  f"{time.process_time() - c:.1f} |", flush=True)


def main():
    if "--rules" in sys.argv:
        rules()
        return
    if "--frictionless" in sys.argv:
        edit = {}
        if "--piezo-size" in sys.argv:           # a finer surface over the taxel, e.g. 0.2e-3 (m)
            edit["mesh.piezo_size"] = float(sys.argv[sys.argv.index("--piezo-size") + 1])
        prob = problem(scene("frictionless", **edit))
        pr = Press(assemble(prob), prob.indenter)
        try:
            pr.travel(0.45e-3, first=0.1, min_frac=0.02)
            print("frictionless: reached 0.45 mm")
        except PressError as exc:
            pt = pr.res.points[-1] if pr.res.points else None
            print(f"frictionless, 3D mesh {edit or 'default'}, {pr.red.n} unknowns: stopped ({exc}); last converged state "
                  f"{1e3 * pt.travel:.3f} mm, {pt.force:.3f} N, {pt.voltages['taxel_0_0']:.4f} V"
                  if pt else f"frictionless: no converged state ({exc})")
        return
    rows = []
    for name, edit in MESHES.items():
        prob = problem(scene(**edit))
        sy = assemble(prob)
        w, c = time.perf_counter(), time.process_time()
        pr = Press(sy, prob.indenter)
        pt = pr.force(1.0)
        rows.append((name, pr.red.n, pt, pr, time.perf_counter() - w, time.process_time() - c))
    print("3D thesis taxel (quarter), Yeoh, sticking 4 mm punch, 1 N")
    print(f"{'mesh':<52} {'unknowns':>8} {'V':>8} {'travel mm':>9} {'states':>6} {'iters':>5} {'factor.':>7} "
          f"{'wall s':>6} {'CPU s':>6}")
    for name, n, pt, pr, wall, cpu in rows:
        print(f"{name:<52} {n:8d} {pt.voltages['taxel_0_0']:8.4f} {1e3 * pt.travel:9.4f} {len(pr.res.points):6d} "
              f"{pr.res.total_iterations:5d} {pr.stats['factorizations']:7d} {wall:6.1f} {cpu:6.1f}")
    v = [r[2].voltages["taxel_0_0"] / r[2].force for r in rows]
    for k in range(1, len(v)):
        print(f"V/F of the default mesh against mesh {k}: {100 * (v[0] / v[k] - 1):+.2f} %")
    if len(v) == 3 and (v[1] - v[0]) * (v[2] - v[1]) > 0:      # Richardson on the three nested sizes
        p = np.log(abs(v[1] - v[0]) / abs(v[2] - v[1])) / np.log(RATIO)
        ref = v[2] + (v[2] - v[1]) / (RATIO ** p - 1)
        print(f"observed order {p:.2f}; extrapolated V/F {ref:.4f}; errors " +
              ", ".join(f"{100 * (x / ref - 1):+.2f} %" for x in v))


if __name__ == "__main__":
    main()
