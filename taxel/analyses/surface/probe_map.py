"""The rig's probe on the Yeoh silicone, as a correction of the linear surface map.

The linear map (taxel.analyses.surface.surface_map) is the small-force limit. At the rig's load
the silicone is stretched and the punch's contact is what it is, so at a coarse grid of
knots (x_k, y_l) the map is corrected by 3D presses of the rig's probe (a rigid flat
punch with a rounded edge, sticking, on Yeoh silicone, force-controlled): the factor

    f(x, y, F) = V_best^press(x, y, F) / (F v_best^map(x, y))

the pressed best taxel's open-circuit voltage of the press at force F over the linear
map's voltage per newton for the punch's face (a flat disc of the probe's radius) at
the same point. Every converged state of a press's load path gives the factor at its
force, so one press per knot gives f at every force up to the press's. Between knots
the factor is interpolated bilinearly (ProbeCorrection.at); its error is measured by
presses between knots (`factor_error`).

Cost: a press off the array's mirror planes is a full-model press (centred on a mirror
plane: a half model; on the array's centre: a quarter), each a Newton solve with contact
on the press mesh (taxel.scene.DEFAULT_PRESS_MESH); benchmarks/surface_map.py --probe
measures it.
"""

from __future__ import annotations

import time

import numpy as np

from taxel.analyses.surface.surface_map import Footprint, ProbeCorrection, SurfaceMap

PROBE = {"shape": "flat", "radius": 2e-3, "edge_radius": 2e-4, "friction": "sticking"}


def press_scene(scene, x: float, y: float, force: float, probe: dict | None = None):
    """The 3D scene of the rig's probe pressed at plan point (x, y) (from the array's
    centre) to `force` N on the Yeoh silicone, on the default press mesh."""
    from taxel.scene import DEFAULT_PRESS_MESH
    p = {**PROBE, **(probe or {})}
    a = scene.array
    pitch = a.pitch
    r, c = (a.rows - 1) // 2, (a.cols - 1) // 2
    cx, cy = (c - (a.cols - 1) / 2) * pitch, ((a.rows - 1) / 2 - r) * pitch
    return scene.replace(**{
        "model.type": "3d", "model.silicone": "yeoh", "model.symmetry": "auto", "model.fidelity": "fixed",
        "analysis.type": "static", "mesh.size": DEFAULT_PRESS_MESH[0], "mesh.piezo_size": DEFAULT_PRESS_MESH[1],
        "mesh.piezo_layers": DEFAULT_PRESS_MESH[2], "mesh.extruded": False,
        "load.kind": "probe", "load.contact": True, "load.taxel": [r, c], "load.offset": [x - cx, y - cy],
        "load.force": force, "load.shape": p["shape"], "load.radius": p["radius"],
        "load.edge_radius": p["edge_radius"], "load.friction": p["friction"], "electrodes": {}})


def press_factor(scene, m: SurfaceMap, x: float, y: float, forces, probe: dict | None = None) -> dict:
    """The factor at (x, y) for each of `forces` (N, ascending; interpolated along the
    press's load path), from one 3D press to the largest; with its cost."""
    from taxel.analyses.solves.analysis import solve_static
    p = {**PROBE, **(probe or {})}
    forces = np.asarray(forces, float)
    t0 = time.perf_counter()
    res = solve_static(press_scene(scene, x, y, float(forces[-1]), p))
    seconds = time.perf_counter() - t0
    fp = Footprint(p["radius"], "flat")
    v_map = m.press([(x, y)], 1.0, fp)[0]
    best = int(np.argmax(np.abs(v_map)))
    pts = res.solution.contact.points
    F = np.array([q.force for q in pts])
    V = np.array([q.voltages[m.taxels[best]] for q in pts])
    v = np.interp(forces, F, V)
    return {"factor": v / (forces * v_map[best]), "taxel": m.taxels[best], "seconds": seconds,
            "unknowns": res.solution.unknowns, "planes": list(res.solution.mesh.layout.planes)}


def probe_correction(scene, m: SurfaceMap, kx, ky, forces, probe: dict | None = None) -> tuple[ProbeCorrection, dict]:
    """The ProbeCorrection on knots kx x ky (m, plan coordinates) at `forces`, and what it cost."""
    p = {**PROBE, **(probe or {})}
    fac = np.zeros((len(forces), len(ky), len(kx)))
    cost = []
    for j, y in enumerate(ky):
        for i, x in enumerate(kx):
            got = press_factor(scene, m, x, y, forces, p)
            fac[:, j, i] = got["factor"]
            cost.append({"x_mm": 1e3 * x, "y_mm": 1e3 * y, **{k: got[k] for k in ("seconds", "unknowns", "planes")}})
    return ProbeCorrection(np.asarray(kx, float), np.asarray(ky, float), np.asarray(forces, float), fac,
                           Footprint(p["radius"], "flat")), {"presses": cost}


def factor_error(scene, m: SurfaceMap, corr: ProbeCorrection, points, probe: dict | None = None) -> list[dict]:
    """The correction's error between its knots: at each point, the corrected map's best-taxel
    voltage against a 3D press there, relative to the press's, at every force of `corr`."""
    out = []
    for x, y in points:
        got = press_factor(scene, m, x, y, corr.forces, probe)
        interp = np.array([corr.at([(x, y)], f)[0] for f in corr.forces])
        out.append({"x_mm": 1e3 * x, "y_mm": 1e3 * y, "forces_N": corr.forces.tolist(),
                    "error": (interp / got["factor"] - 1).tolist(), "seconds": got["seconds"]})
    return out
