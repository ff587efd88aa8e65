"""The 3D surface map (taxel.analyses.surface.surface_map): what it costs, how well it agrees with
direct 3D solves, and what the coverage search on it costs.

    python benchmarks/surface_map.py              # 3x3 cost + coverage search + validation (12 presses)
    python benchmarks/surface_map.py --8x8        # the 8x8 array's map cost alone (surface_map_8x8.json)
    python benchmarks/surface_map.py --no-validate
    python benchmarks/surface_map.py --probe      # the probe correction alone (surface_map_probe.json)
    python benchmarks/surface_map.py --designs    # the answer's per-design cost (surface_map_designs.json)
    python benchmarks/surface_map.py --remap      # the stored direct solves against finer maps (surface_map_remap.json)

Parts, printed and written to benchmarks/results/surface_map.json:

1. cost: the thesis PZT 3x3 array's linear map (thesis-pzt-3x3-3d on the array mesh
   MESH: 2 mm / 0.8 mm, two elements through the PZT; a quarter model, four mirror
   classes), phases in wall seconds and CPU seconds, unknowns; with --8x8 the same for
   the 8x8 array (benchmarks/array_8x8.py's array) on MESH_8x8 (2.5 mm / 1 mm: the array
   mesh's 8x8 solve peaks at 3.5 GB, over this machine's share per process), written to
   results/surface_map_8x8.json.
2. coverage search: coverage and the localization error on the 3x3 map at 0.2 N, 1 mV,
   the rig's 4 mm flat punch (taxel.analyses.surface.map_metrics): median of 5 wall seconds each.
3. validation: the map against direct 3D solves (a flat 4 mm disc, 1 N, linear, the same
   mesh sizes; mirror planes where the press allows) at 12 positions: the taxel centre,
   four along the diagonal to the corner between four taxels, four along the middle row
   (taxel edge, quarter and half gap, the edge taxel's centre and its outer edge) and two
   on the corner taxel. The map is pressed with each direct solve's own load (its mesh's
   polygon of the disc, surface_map.patch_quadrature: at 2 mm / 0.8 mm the polygon has
   2.6 % less area than the disc, which moves the pressed taxel by about 1 %) and with the
   exact disc beside it. Per position: the pressed taxel's map error relative to the
   direct centre value, and the largest neighbour error relative to the pressed taxel's
   peak (its centre value) and of its value at that position, with the signs.
5. with --designs: what the main job's answer pays per design: optimize.coverage.
   influence_metrics (map, coverage, localization) of the thesis PZT and PVDF designs from
   their 2D base scenes (made 3D on optimize.coverage.MAP_MESH), wall and CPU seconds.
6. with --remap: the stored validation's direct solves (validation_3x3 of surface_map.json,
   not solved again) against the map on MESH and on finer meshes (REMAP: 1.5 / 0.6 and
   1 / 0.4 mm), each pressed with the direct solve's own polygon (its mesh made again, not
   solved): whether the map's mesh or the direct reference sets a neighbour's error.
4. with --probe: the probe correction (taxel.analyses.surface.probe_map) on the 3x3 map:
   3D presses of the rig's probe (4 mm flat punch, 0.2 mm edge, sticking, Yeoh, the press
   mesh) at two knots on the middle row (the centre: a quarter model; mid-gap: a half
   model), the factor at 0.2, 0.5 and 1 N, what each press costs, and the correction's
   error at a point between the knots (a quarter pitch from the centre) against a press there.
"""

from __future__ import annotations

import json
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

import taxel
from taxel.analyses import solve_static
from taxel.analyses.surface import map_metrics
from taxel.analyses.surface.surface_map import Footprint, build, patch_quadrature

MESH = {"mesh.size": "2 mm", "mesh.piezo_size": "0.8 mm", "mesh.piezo_layers": 2}
MESH_8x8 = {"mesh.size": "2.5 mm", "mesh.piezo_size": "1 mm", "mesh.piezo_layers": 2}
OUT = Path(__file__).parent / "results" / "surface_map.json"


def scene(n: int = 3):
    return taxel.load("thesis-pzt-3x3-3d").replace(**{**(MESH if n == 3 else MESH_8x8), "array.rows": n, "array.cols": n,
                                                      "load.taxel": [n // 2, n // 2]})


def cost(n: int = 3):
    t0, c0 = time.perf_counter(), time.process_time()
    m = build(scene(n))
    rec = {"wall_s": time.perf_counter() - t0, "cpu_s": time.process_time() - c0, **m.info,
           "load_average": os.getloadavg()[0]}
    print(f"{n}x{n} map: {rec['unknowns']} unknowns, {rec['factorizations']} factorizations, "
          f"{rec['right_hand_sides']} right-hand sides, wall {rec['wall_s']:.1f} s, CPU {rec['cpu_s']:.1f} s "
          f"(mesh {rec['seconds']['mesh']:.1f}, assemble {rec['seconds']['assemble']:.1f}, "
          f"solve {rec['seconds']['solve']:.1f}); load average {rec['load_average']:.1f}", flush=True)
    return m, rec


def search(m) -> dict:
    fp = Footprint(2e-3, "flat")
    tc, tl = [], []
    for _ in range(5):
        t0 = time.perf_counter()
        cov = map_metrics.coverage(m, 0.2, 1e-3, fp)
        tc.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        loc = map_metrics.localization(m, 0.2, 1e-3, fp)
        tl.append(time.perf_counter() - t0)
    rec = {"coverage_s": statistics.median(tc), "localization_s": statistics.median(tl), **cov.record(),
           **loc.record(), "grid": [len(cov.x), len(cov.y)]}
    print(f"coverage search {rec['coverage_s']:.2f} s (grid {len(cov.x)} x {len(cov.y)} + local search): "
          f"coverage {100 * cov.fraction:.1f} %, 3D minimum {cov.minimum:.3f}x the 3 sigma threshold at "
          f"({1e3 * cov.minimum_at[0]:.2f}, {1e3 * cov.minimum_at[1]:.2f}) mm; localization {rec['localization_s']:.2f} s: "
          f"rms {1e3 * loc.rms_m:.3f} mm, p95 {1e3 * loc.p95_m:.3f} mm, worst {1e3 * loc.worst_m:.3f} mm", flush=True)
    return rec


def positions(sc):
    a = sc.array
    w, p = a.taxel_width, a.pitch
    return {"taxel centre": (0, 0), "diagonal p/8": (p / 8, p / 8), "diagonal p/4": (p / 4, p / 4),
            "diagonal 3p/8": (3 * p / 8, 3 * p / 8), "corner of four taxels": (p / 2, p / 2),
            "taxel edge": (w / 2, 0), "row p/4": (p / 4, 0), "gap middle": (p / 2, 0),
            "edge taxel centre": (p, 0), "edge taxel outer edge": (p + w / 2, 0),
            "corner taxel centre": (p, p), "corner taxel off-centre": (p + 1.5e-3, p + 1.5e-3)}


def direct(sc, x, y, force=1.0):
    """Open-circuit voltages per newton of a flat disc press (the rig's punch as a pressure
    patch) centred at (x, y) from the array centre, every taxel open."""
    c = (sc.array.cols - 1) // 2
    s = sc.replace(**{"load.kind": "probe", "load.taxel": [c, c], "load.radius": "2 mm", "load.profile": "flat",
                      "load.offset": [float(x), float(y)], "load.force": force, "model.symmetry": "auto"})
    r = solve_static(s)
    return r.voltages(), r.solution.mesh


def validate(m, sc) -> dict:
    fp = Footprint(2e-3, "flat")
    out, centre = {}, None
    for name, (x, y) in positions(sc).items():
        t0 = time.perf_counter()
        v, tm = direct(sc, x, y)
        vd = np.array([v[k] for k in m.taxels])
        vdisc = m.press([(x, y)], 1.0, fp)[0]        # the middle taxel's offset is the plan position
        pts, w = patch_quadrature(tm)                # the direct solve's own load: its mesh's polygon
        vm = -np.linalg.solve(m.capacitance, m.charge(pts, np.column_stack([0 * w, 0 * w, -w])).sum(0))
        if centre is None:
            centre = abs(vd).max()
        k = int(np.argmax(np.abs(vd)))
        others = [i for i in range(len(vd)) if i != k]
        nb_err = max(abs(vm[i] - vd[i]) for i in others) / centre      # of the pressed taxel's peak (its centre value)
        nb_here = max(abs(vm[i] - vd[i]) for i in others) / abs(vd[k])   # of the pressed taxel's value here
        signs = all(np.sign(vm[i]) == np.sign(vd[i]) for i in others if abs(vd[i]) > 2e-3 * abs(vd[k]))
        out[name] = {"x_mm": 1e3 * x, "y_mm": 1e3 * y, "pressed": m.taxels[k], "direct_V_per_N": vd.tolist(),
                     "map_V_per_N": vm.tolist(), "map_disc_V_per_N": vdisc.tolist(),
                     "disc_pressed_error_of_centre": float((vdisc[k] - vd[k]) / centre), "pressed_error_of_centre": float((vm[k] - vd[k]) / centre),
                     "neighbour_error_of_peak": float(nb_err), "neighbour_error_of_pressed_here": float(nb_here), "signs_agree": bool(signs),
                     "direct_s": time.perf_counter() - t0}
        r = out[name]
        print(f"{name:26s} ({1e3 * x:5.2f}, {1e3 * y:5.2f}) mm  pressed {m.taxels[k]} direct {vd[k]:+.4f} map "
              f"{vm[k]:+.4f} V/N ({100 * r['pressed_error_of_centre']:+.2f} % of centre); neighbours within "
              f"{100 * nb_err:.3f} % of the peak ({100 * nb_here:.3f} % of the pressed value here), signs {'agree' if signs else 'DIFFER'}; the map's exact disc "
              f"{vdisc[k]:+.4f} ({100 * r['disc_pressed_error_of_centre']:+.2f} %); {r['direct_s']:.0f} s", flush=True)
    return out


REMAP = {"2 / 0.8 mm": MESH, "1.5 / 0.6 mm": {"mesh.size": "1.5 mm", "mesh.piezo_size": "0.6 mm", "mesh.piezo_layers": 2},
         "1 / 0.4 mm": {"mesh.size": "1 mm", "mesh.piezo_size": "0.4 mm", "mesh.piezo_layers": 2}}


def remap() -> dict:
    """The stored direct solves against maps on REMAP's meshes (module docstring, 6.)."""
    from taxel.analyses.model.problem import mesh as make_mesh
    stored = json.loads(OUT.read_text())["validation_3x3"]
    sc = scene(3)
    c = (sc.array.cols - 1) // 2
    polys = {}
    for name, (x, y) in positions(sc).items():            # each direct solve's polygon: its mesh, not solved
        s = sc.replace(**{"load.kind": "probe", "load.taxel": [c, c], "load.radius": "2 mm", "load.profile": "flat",
                          "load.offset": [float(x), float(y)], "load.force": 1.0, "model.symmetry": "auto"})
        polys[name] = patch_quadrature(make_mesh(s))
    centre = abs(np.array(stored["taxel centre"]["direct_V_per_N"])).max()
    out = {}
    for label, sizes in REMAP.items():
        t0, c0 = time.perf_counter(), time.process_time()
        m = build(sc.replace(**sizes))
        rec = {"unknowns": m.info.get("unknowns"), "wall_s": time.perf_counter() - t0,
               "cpu_s": time.process_time() - c0, "positions": {}}
        for name, (pts, w) in polys.items():
            vd = np.array(stored[name]["direct_V_per_N"])
            vm = -np.linalg.solve(m.capacitance, m.charge(pts, np.column_stack([0 * w, 0 * w, -w])).sum(0))
            k = int(np.argmax(np.abs(vd)))
            others = [i for i in range(len(vd)) if i != k]
            rec["positions"][name] = {"map_V_per_N": vm.tolist(), "pressed_error_of_centre": float((vm[k] - vd[k]) / centre),
                                      "neighbour_error_of_peak": float(max(abs(vm[i] - vd[i]) for i in others) / centre),
                                      "signs_agree": bool(all(np.sign(vm[i]) == np.sign(vd[i]) for i in others
                                                              if abs(vd[i]) > 2e-3 * abs(vd[k])))}
        worst = max(rec["positions"].items(), key=lambda kv: kv[1]["neighbour_error_of_peak"])
        print(f"map {label} ({rec['unknowns']} unknowns, {rec['cpu_s']:.0f} s CPU): pressed within "
              f"{100 * max(abs(r['pressed_error_of_centre']) for r in rec['positions'].values()):.2f} % of the centre "
              f"value, neighbours within {100 * worst[1]['neighbour_error_of_peak']:.3f} % of the peak ({worst[0]}); "
              f"corner of four taxels {100 * rec['positions']['corner of four taxels']['neighbour_error_of_peak']:.3f} %",
              flush=True)
        out[label] = rec
    return out


def probe() -> dict:
    from taxel.analyses.surface.probe_map import factor_error, probe_correction
    sc = scene(3)
    m = build(sc)
    p = sc.array.pitch
    t0, c0 = time.perf_counter(), time.process_time()
    corr, cost_ = probe_correction(sc, m, [0.0, p / 2], [0.0], [0.2, 0.5, 1.0])
    rec = {"knots_x_mm": [0.0, 1e3 * p / 2], "forces_N": corr.forces.tolist(), "factor": corr.factor[:, 0, :].tolist(),
           **cost_, "wall_s": time.perf_counter() - t0, "cpu_s": time.process_time() - c0}
    print(f"probe correction: factors at the centre {np.round(corr.factor[:, 0, 0], 4).tolist()}, mid-gap "
          f"{np.round(corr.factor[:, 0, 1], 4).tolist()} at {corr.forces.tolist()} N; presses "
          + ", ".join(f"{c['seconds']:.0f} s ({c['unknowns']} unknowns, planes {c['planes']})" for c in cost_["presses"]),
          flush=True)
    rec["between_knots"] = factor_error(sc, m, corr, [(p / 4, 0.0)])
    print(f"between knots (quarter pitch): error {np.round(100 * np.array(rec['between_knots'][0]['error']), 2).tolist()} %",
          flush=True)
    return rec


def designs() -> dict:
    from taxel.optimize.coverage import influence_metrics
    out = {}
    for name in ("thesis-pzt-3x3-2d", "thesis-pvdf-3x3-2d"):
        t0, c0 = time.perf_counter(), time.process_time()
        got = influence_metrics(taxel.load(name), 0.2, 1e-3)
        out[name] = {**got, "wall_s": time.perf_counter() - t0, "cpu_s": time.process_time() - c0,
                     "load_average": os.getloadavg()[0]}
        r = out[name]
        print(f"{name}: coverage {r['coverage']}, 3D minimum {r.get('coverage_minimum')}, localization "
              f"{r.get('localization_error')}; {r.get('unknowns')} unknowns, wall {r['wall_s']:.0f} s, CPU "
              f"{r['cpu_s']:.0f} s (load {r['load_average']:.1f})", flush=True)
    return out


def write(name: str, rec: dict) -> None:
    path = OUT.with_name(name)
    path.parent.mkdir(exist_ok=True)
    path.write_text(json.dumps(rec, indent=1, default=str))
    print(f"wrote {path}")


if __name__ == "__main__":
    for flag, name, part in (("--designs", "surface_map_designs.json", designs), ("--remap", "surface_map_remap.json", remap),
                             ("--probe", "surface_map_probe.json", probe),
                             ("--8x8", "surface_map_8x8.json", lambda: {"8x8": cost(8)[1]})):
        if flag in sys.argv:
            write(name, part())
            sys.exit(0)
    res = json.loads(OUT.read_text()) if OUT.exists() else {}
    m, res["3x3"] = cost(3)
    res["search_3x3"] = search(m)
    if "--no-validate" not in sys.argv:
        res["validation_3x3"] = validate(m, scene(3))
    OUT.parent.mkdir(exist_ok=True)
    OUT.write_text(json.dumps(res, indent=1))
    print(f"wrote {OUT}")
