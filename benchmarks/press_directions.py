"""The 3D press's reference settled by direction (issue 57): each size that matters refined on
its own and together, on the single taxel and the 3x3 quarter pressed at its centre.

The press is the answer's own: the rig's probe (a sticking 4 mm flat punch, 0.2 mm edge radius)
pressing Yeoh silicone to 1 N, a quarter model, force control (taxel.analyses.model.problem.solve_model,
the path `taxel solve` and optimize.answer_press take), the free silicone mesh (Layout.free). A mesh
is five numbers (Mesh): the far size, the in-plane size at the piezo's edges (`edge`,
Layout.piezo_size), the size under the punch's rounded edge (`rim`, Layout.contact_size; the mesher
uses min(rim, edge) there), the piezo's elements through its thickness (`layers`) and the distance
over which the sizes grow to the far size (`grow`, m: Layout.growth x size). Directions: one
number divided by k from a base mesh, the others kept ("plane": size and edge); "sizes": every size /
k, the layers and the distance kept (benchmarks/press_3d.py's Family); "joint": every size / k, the
distance kept, the layers x k. Every run is appended to the JSON (--out, default docs/press_3d_directions.json)
as it finishes, so a stopped run keeps what it had and runs can go side by side.

What `taxel.scene.refined` does to the default press mesh, in these numbers: size and edge / k,
rim max(0.2 mm, edge / 2 / k) (taxel.analyses.model.geometry.punch_grading floors it at the edge
radius), grow / k (the growth factor is kept, so the graded zone narrows), layers round(k).

    python benchmarks/press_directions.py --case single --direction rim --levels 1,1.41,2,2.83,4
    python benchmarks/press_directions.py --case 3x3 --base 1.4,0.56,0.28,1,2.8 --direction joint --levels 1
    python benchmarks/press_directions.py --summary          # orders and Richardson from the JSON

Run with MKL_NUM_THREADS=1 OMP_NUM_THREADS=1. RESULT: docs/benchmarks.md ("The 3D press's
reference settled", 2026-11-29) and the JSON.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import sys
import time
from pathlib import Path

DOCS = Path(__file__).resolve().parents[1] / "docs"
OUT = DOCS / "press_3d_directions.json"
DEFAULT = (1.4e-3, 0.56e-3, 0.28e-3, 1, 2.8e-3)     # the default press mesh (taxel.scene.DEFAULT_PRESS_MESH)


@dataclasses.dataclass(frozen=True)
class Mesh:
    """A free press mesh: sizes in m, `layers` elements through the piezo."""
    size: float
    edge: float
    rim: float
    layers: int
    grow: float

    def divided(self, direction: str, k: float) -> "Mesh":
        """This mesh with `direction` refined by k (module docstring)."""
        if direction == "joint":
            return Mesh(self.size / k, self.edge / k, self.rim / k, max(1, round(self.layers * k)), self.grow)
        if direction == "sizes":            # every size, layers and distance kept (press_3d.py's Family)
            return dataclasses.replace(self, size=self.size / k, edge=self.edge / k, rim=self.rim / k)
        if direction == "plane":            # every in-plane size but the rim's
            return dataclasses.replace(self, size=self.size / k, edge=self.edge / k)
        if direction == "layers":
            return dataclasses.replace(self, layers=max(1, round(self.layers * k)))
        if direction == "refined":          # taxel.scene.refined's path
            return Mesh(self.size / k, self.edge / k, max(0.2e-3, self.edge / 2 / k), max(1, round(self.layers * k)),
                        self.grow / k)
        return dataclasses.replace(self, **{direction: getattr(self, direction) / k})


def scene(case: str):
    from taxel.scene import load
    sc = load("thesis-pzt-probe-3d")
    if case == "3x3":
        sc = sc.replace(**{"array.rows": 3, "array.cols": 3, "load.taxel": [1, 1]})
    return sc


def layout(sc, m: Mesh):
    from taxel.analyses import check, checked_layout
    lay = checked_layout(sc, check(sc))
    return dataclasses.replace(lay, size=m.size, piezo_size=m.edge, contact_size=m.rim, piezo_layers=m.layers,
                               free=True, growth=m.grow / m.size)


def run(case: str, m: Mesh) -> dict:
    """One whole press (mesh, assembly, force-controlled press, solution); its numbers."""
    from taxel.analyses.model.problem import solve_model
    from taxel.meshing.build import build
    sc = scene(case)
    w, c = time.perf_counter(), time.process_time()
    res = solve_model(sc, tagged_mesh=build(layout(sc, m)))
    out = res.outputs()
    st = res.contact.stats
    return dict(n=res.unknowns, VF=abs(out["sensitivity"]), crosstalk=out.get("crosstalk"),
                cpu=time.process_time() - c, wall=time.perf_counter() - w, iterations=res.contact.total_iterations,
                factorizations=st["factorizations"], load=os.getloadavg()[0])


def record(path: Path, row: dict):
    """Append a run to the JSON (re-read first: another run may have written meanwhile)."""
    rows = json.loads(path.read_text())["runs"] if path.exists() else []
    rows.append(row)
    path.write_text(json.dumps({"script": "benchmarks/press_directions.py", "runs": rows}, indent=1) + "\n")


def summary(path: Path):
    """Per case, base and direction: the levels, the last three's order and Richardson value."""
    sys.path.insert(0, str(Path(__file__).parent))
    from press_speed import richardson
    rows = json.loads(path.read_text())["runs"]
    groups: dict[tuple, list] = {}
    for r in rows:
        groups.setdefault((r["case"], tuple(r["base"]), r["direction"]), []).append(r)
    for (case, base, direction), rs in sorted(groups.items()):
        rs = sorted({r["k"]: r for r in rs}.values(), key=lambda r: r["k"])
        print(f"\n{case}, base {base}, {direction}:")
        for r in rs:
            print(f"  k {r['k']:.3g}: {r['n']} unknowns, V/F {r['VF']:.5f} V/N"
                  + (f", crosstalk {100 * r['crosstalk']:.4f} %" if r.get("crosstalk") else "") + f", {r['cpu']:.1f} s")
        if len(rs) >= 3:
            p, v = richardson([1 / r["k"] for r in rs[-3:]], [r["VF"] for r in rs[-3:]])
            print("  last three: " + (f"order {p:.2f}, V/F {v:.5f} V/N ({100 * (v / rs[0]['VF'] - 1):+.2f} % from k 1)"
                                       if p else "not monotone"))


def settle(path: Path):
    """--write-reference: docs/press_reference.json, the single taxel's and the 3x3's references with
    their uncertainties, from the nested family (docs/press_3d_reference.json), the directions run
    here and the 3x3 / single-taxel ratios of docs/answer_press_error.json (module docstring)."""
    ref = json.loads((DOCS / "press_3d_reference.json").read_text())
    rows = json.loads(path.read_text())["runs"]
    v = abs(ref["VF"])
    lo, hi = sorted(abs(b) for b in ref["bracket"].values())
    # the parts of the single taxel's uncertainty (relative, one standard uncertainty each)
    parts = {
        "extrapolation (half the order-1 / order-2 bracket of the fit)": (hi - lo) / 2 / v,
        "fit's start level (orders 1.11-2.03 from / 0.71 ... / 2: V_ref 0.77933-0.78112, half the range)":
            (0.78112 - 0.77933) / 2 / v,
        "elements through the piezo beyond the family's 4 (4 -> 8 at / 1: 0.095 %)": 0.00095,
        "load path (16 travel steps against force control at / 1: 0.05 %)": 0.0005,
        "the piezo's corner (one-off ball refinement at / 1: 0.14 %)": 0.0014,
    }
    u_single = sum(x ** 2 for x in parts.values()) ** 0.5
    ans = json.loads((DOCS / "answer_press_error.json").read_text())["designs"]["thesis-pzt-probe-front"]
    rho = ans["rho"]
    joint = {r["k"]: r for r in rows if r["case"] == "3x3" and r["direction"] == "joint"}
    # rho's move from the default press mesh to every size / sqrt 2: the answer's runs, and the issue-46
    # runs of benchmarks/press_speed.py (0.98695 -> 0.98605); the larger, extrapolated at the family's order
    rho_move = max(abs(rho[1] / rho[0] - 1), abs(0.98605 / 0.98695 - 1))
    from taxel.optimize.answer_press import R
    u_rho = R * rho_move
    out = {
        "script": "benchmarks/press_directions.py --write-reference",
        "quantity": "|V/F| of the pressed taxel, V/N: the rig's probe (sticking 4 mm flat punch, 0.2 mm edge), "
                    "Yeoh, 1 N, quarter model",
        "single": {"VF": v, "uncertainty": u_single, "parts": parts,
                   "from": "docs/press_3d_reference.json (eight nested levels to 424k unknowns, fit over six: "
                           f"order {ref['order']:.2f})"},
        "3x3": {"VF": v * rho[1], "uncertainty": (u_single ** 2 + u_rho ** 2) ** 0.5,
                "rho": rho, "rho_uncertainty": u_rho,
                "from": "the single taxel's reference x rho = V_3x3 / V_single on the same mesh (its move under "
                        "refinement extrapolated at the family's order, docs/answer_press_error.json)"},
    }
    if joint:
        out["3x3"]["joint_levels"] = {f"{k:.3g}": joint[k]["VF"] for k in sorted(joint)}
    (DOCS / "press_reference.json").write_text(json.dumps(out, indent=1) + "\n")
    print(json.dumps(out, indent=1))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--case", choices=("single", "3x3"), default="single")
    ap.add_argument("--base", default=",".join(f"{v:g}" for v in (1.4, 0.56, 0.28, 1, 2.8)),
                    help="size, edge, rim (mm), layers, grow (mm) of the base mesh")
    ap.add_argument("--direction", choices=("size", "edge", "rim", "layers", "grow", "plane", "sizes", "joint", "refined"),
                    default="joint")
    ap.add_argument("--levels", default="1", help="divisors k")
    ap.add_argument("--out", default=str(OUT))
    ap.add_argument("--summary", action="store_true")
    ap.add_argument("--write-reference", action="store_true")
    ap.add_argument("--sizes", action="store_true")
    a = ap.parse_args()
    if a.summary:
        summary(Path(a.out))
        return
    if a.sizes:
        s, e, r, n, g = (float(v) for v in a.base.split(","))
        sizes(a.case, Mesh(s * 1e-3, e * 1e-3, r * 1e-3, int(n), g * 1e-3))
        return
    if a.write_reference:
        settle(Path(a.out))
        return
    s, e, r, n, g = (float(v) for v in a.base.split(","))
    base = Mesh(s * 1e-3, e * 1e-3, r * 1e-3, int(n), g * 1e-3)
    for k in (float(v) for v in a.levels.split(",")):
        m = base.divided(a.direction, k)
        res = run(a.case, m)
        row = dict(case=a.case, base=[s, e, r, int(n), g], direction=a.direction, k=k,
                   mesh=[1e3 * m.size, 1e3 * m.edge, 1e3 * m.rim, m.layers, 1e3 * m.grow], **res)
        record(Path(a.out), row)
        print(json.dumps(row), flush=True)



def sizes(case: str, base: Mesh, ks=(1.0, 2 ** 0.5, 2.0)):
    """--sizes: no press; the median element size (the edge of a regular tetrahedron of the
    element's volume) of the silicone by distance from the punch's rim circle at the top surface,
    along `refined`'s path and along the sizes divided with the distance kept ("sizes"): how much
    each path refines the graded zone."""
    import numpy as np
    from taxel.meshing.build import build
    sc = scene(case)
    bins = (0.0, 0.2e-3, 0.5e-3, 1.0e-3, 2.0e-3, 4.0e-3)
    print("| path | k | unknowns (P2 nodes x 3) | " + " | ".join(f"{1e3 * a:g}-{1e3 * b:g} mm" for a, b in
                                                          zip(bins[:-1], bins[1:])) + " |")
    for path in ("refined", "sizes"):
        for k in ks:
            tm = build(layout(sc, base.divided(path, k)))
            m, lay = tm.mesh, tm.layout
            P = m.p[:, m.t]
            vol = np.abs(np.einsum("ij,ij->j", P[:, 1] - P[:, 0], np.cross(P[:, 2] - P[:, 0], P[:, 3] - P[:, 0],
                                                                             axis=0))) / 6
            h = (6 * 2 ** 0.5 * vol) ** (1 / 3)
            c = P.mean(axis=1)
            r = np.hypot(c[0] - lay.load.x, c[1] - lay.load.y)
            d = np.hypot(r - lay.load.half, c[2] - lay.height)
            sil = tm.regions["silicone"]
            cells = [np.median(h[sil][(d[sil] >= a) & (d[sil] < b)]) for a, b in zip(bins[:-1], bins[1:])]
            print(f"| {path} | {k:.3g} | {m.nvertices + m.nedges} nodes | "
                  + " | ".join(f"{1e3 * x:.3f}" for x in cells) + " |", flush=True)

if __name__ == "__main__":
    sys.exit(main())
