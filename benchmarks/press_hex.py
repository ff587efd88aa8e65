"""The 3D probe press on structured hexahedra (meshing.hexmesh) against the tetrahedral press
and the nested-mesh references: does a hexahedral mixed element reach 1 N frictionless, and
how fast and how close is the sticking press?

The scene is thesis-pzt-probe-3d (the thesis PZT taxel, quarter model, pressed to 1 N by the
rig's 4 mm flat punch with a 0.2 mm edge radius, Yeoh Ecoflex 00-30), at every friction asked
(--friction frictionless,0.2,0.5,sticking). The mesh is the scene's layout (its default press
mesh sizes) meshed by meshing.hexmesh, with the element --element (q2: Q2/P1-discontinuous, the
hexahedral default; q2p0: Q2/P0; q1: Q1/P0, mean dilatation), every size divided by --divide. Printed per press: force reached, travel,
V/F, the smallest J met in the silicone, unknowns, states, Newton iterations, factorizations,
wall and CPU time; a stop's cause. --tet also presses the scene's default tetrahedral mesh
side by side. --nest K1,K2,...: the hexahedral press at sizes / K (its own nested family).
--array: the 3x3 array pressed at its centre taxel instead. --linear: the linear 3D taxel
(thesis-pzt-single-3d) on each element at sizes / K and on the default tetrahedra, against
docs/reference_3d.json's nested reference. --layered: the layered hexahedral mesh (meshing.layered:
a quadrilateral plan graded at the rim and the taxel edges, extruded through each layer) instead of
the tensor grid.

RESULT: docs/benchmarks.md, "Hexahedra for the 3D press".

The sticking reference is benchmarks/press_3d.py's (docs/press_3d_reference.json, tetrahedra,
Richardson over six levels): -0.77981 V/N.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time
from pathlib import Path

from taxel.analyses import check, checked_layout, problem
from taxel.fem.assembly import Discretization, assemble
from taxel.fem.contact import Press, PressError
from taxel.fem.static import solve_linear
from taxel.meshing.build import build
from taxel.meshing.hexmesh import build_hex
from taxel.meshing.layered import build_layered
from taxel.scene import load

DOCS = Path(__file__).resolve().parents[1] / "docs"
REF_STICKING = json.loads((DOCS / "press_3d_reference.json").read_text())["VF"]


ARRAY = {"array.rows": 3, "array.cols": 3, "load.taxel": [1, 1]}   # --array: the 3x3 pressed at its centre


def scene(friction, array=False):
    return load("thesis-pzt-probe-3d").replace(**{"load.friction": friction, **(ARRAY if array else {})})


def pressed(sc) -> str:
    return "taxel_{}_{}".format(*sc.load.taxel)


def hex_layout(sc, divide=1.0, piezo_layers=None):
    lay = checked_layout(sc, check(sc))
    return dataclasses.replace(lay, size=lay.size / divide, piezo_size=lay.piezo_size / divide,
                               contact_size=lay.contact_size / divide,
                               piezo_layers=piezo_layers or lay.piezo_layers)


ELEMENTS = {"q2": (2, "p1"), "q2p0": (2, "p0"), "q1": (1, "p1")}   # order, hexahedral pressure


def run(sc, tm, element="q2", F=1.0):
    """Assemble and press to F; the numbers."""
    w, c = time.perf_counter(), time.process_time()
    prob = problem(sc, tagged_mesh=tm)
    order, pressure = ELEMENTS.get(element, (2, "p1"))
    prob = dataclasses.replace(prob, discretization=Discretization(order, True, pressure))
    sy = assemble(prob)
    pr = Press(sy, prob.indenter)
    min_j = [1.0]
    solve_at = pr.solve_at

    def tracked(d):                      # the smallest J of the silicone at every converged state
        pt = solve_at(d)
        pr._residual(pr.x, pr.d, pr.lam, tangent=False)
        min_j[0] = min(min_j[0], pr._min_J)
        return pt
    pr.solve_at = tracked
    out = dict(n=pr.red.n, elements=tm.mesh.nelements)
    try:
        pt = pr.force(F)
        out.update(force=pt.force, stop="reached")
    except PressError as exc:
        pt = pr.res.points[-1] if pr.res.points else None
        out.update(force=pt.force if pt else 0.0, stop=f"{exc.cause}: {exc.summary}")
    out.update(VF=pt.voltages[pressed(sc)] / pt.force if pt else None, travel=pt.travel if pt else None,
               states=len(pr.res.points), iterations=pr.res.total_iterations,
               factorizations=pr.stats["factorizations"], min_J=min_j[0],
               wall=time.perf_counter() - w, cpu=time.process_time() - c)
    return out


def row(label, r):
    vf = f"{r['VF']:.5f}" if r["VF"] is not None else "-"
    err = f"{100 * (r['VF'] / REF_STICKING - 1):+.2f} %" if (r["VF"] is not None and REF_STICKING) else "-"
    print(f"{label:34s} {r['n']:7d} {r['force']:6.3f} N  V/F {vf} ({err} vs sticking ref)  "
          f"travel {1e3 * (r['travel'] or 0):.4f} mm  min J {r['min_J']:.3f}  states {r['states']}  "
          f"Newton {r['iterations']}  fact {r['factorizations']}  wall {r['wall']:.2f} s  cpu {r['cpu']:.2f} s  "
          f"[{r['stop']}]", flush=True)


def linear(elements, divides, mesher=build_hex):
    """thesis-pzt-single-3d (linear silicone, pressure on the taxel) on hexahedra at sizes / k
    and on the default tetrahedra, against the nested tetrahedral reference."""
    ref = json.loads((DOCS / "reference_3d.json").read_text())["single"]
    base = load(ref["scene"])
    print(f"linear 3D taxel, reference {ref['reference']:.5f} V/N (chains spread {100 * ref['spread']:.2f} %)")
    for el in elements + ["tet"]:
        for k in divides if el != "tet" else [1.0]:
            sc = base.replace(**{"mesh.size": base.mesh.size / k, "mesh.piezo_size": base.mesh.piezo_size / k,
                                 "mesh.element": "hex" if el != "tet" else "tet"})
            w = time.perf_counter()
            lay = checked_layout(sc, check(sc))
            tm = mesher(lay if mesher is build_hex else dataclasses.replace(lay, piezo_layers=max(1, round(
                lay.piezo_layers * k)))) if el != "tet" else build(lay)
            prob = problem(sc, tagged_mesh=tm)
            order, pressure = ELEMENTS.get(el, (2, "p1"))
            prob = dataclasses.replace(prob, discretization=Discretization(order, True, pressure))
            sy = assemble(prob)
            sol = solve_linear(sy)
            vf = sol.voltages()[ref["pressed"]] / sc.load.force       # a quarter carries a quarter of it
            print(f"{el:5s} /{k:<5g} {sy.A.shape[0]:7d} unknowns  V/F {vf:.5f}  {100 * (vf / ref['reference'] - 1):+.2f} %  "
                  f"wall {time.perf_counter() - w:.2f} s", flush=True)


def friction(v):
    return v if v in ("frictionless", "sticking") else float(v)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--friction", default="frictionless,sticking")
    ap.add_argument("--element", default="q2", help="q2 (Q2/P1-disc), q2p0 (Q2/P0) or q1 (Q1/P0), comma-separated")
    ap.add_argument("--linear", action="store_true", help="the linear 3D taxel against docs/reference_3d.json")
    ap.add_argument("--divide", type=float, default=1.0)
    ap.add_argument("--layers", type=int, default=None, help="elements through the piezo")
    ap.add_argument("--nest", default="", help="sizes / K for each K (comma-separated)")
    ap.add_argument("--tet", action="store_true", help="the default tetrahedral press beside it")
    ap.add_argument("--array", action="store_true", help="the 3x3 array pressed at its centre taxel")
    ap.add_argument("--layered", action="store_true", help="the layered mesh (meshing.layered), not the tensor grid")
    a = ap.parse_args()
    mesher = build_layered if a.layered else build_hex
    if a.linear:
        return linear(a.element.split(","), [float(k) for k in (a.nest or "1").split(",")], mesher)
    print(f"sticking reference (tetrahedra, nested): {REF_STICKING} V/N")
    divides = [float(k) for k in a.nest.split(",")] if a.nest else [a.divide]
    for fr in a.friction.split(","):
        sc = scene(friction(fr), a.array)
        for el in a.element.split(","):
            for k in divides:
                tm = mesher(hex_layout(sc, k, a.layers))
                row(f"{'layered' if a.layered else 'hex'} {el} /{k:g} {fr}", run(sc, tm, el))
        if a.tet:
            lay = checked_layout(sc, check(sc))
            row(f"tet P2/P1 default {fr}", run(sc, build(lay)))


if __name__ == "__main__":
    main()
