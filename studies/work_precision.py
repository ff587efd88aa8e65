"""The work-precision chart's data: wall time against error, one point per model,
element order, mesh level and silicone law, for one scene and force.

Outputs (magnitudes, per newton): the pressed taxel's open-circuit voltage, the
crosstalk (arrays), the pressed taxel's short-circuit charge, and the
charge-amplifier output of the pressed taxel at 10 Hz and 300 Hz (the scene's
readout values; a direct sweep at those two frequencies).

Models (`levels`): the lumped 3-DoF model; plane stress and plane strain, orders
1 and 2, three mesh levels (every size x2, x1, x1/2 of the scene's 2D mesh); the
same in axisymmetric (single PZT taxels: PVDF has no axisymmetric model); plane
strain and axisymmetric with the Yeoh silicone (order 2, three levels); 3D,
order 2, at 3, 2 and 1.5 mm elements (1.2, 0.8, 0.6 mm at the taxels, two
through the piezo). A 3D quarter model is one more entry once [model] symmetry
exists.

The reference is the finest 3D: the two finest 3D meshes (1.5 / 0.6 mm and
1 / 0.4 mm for a single taxel; 2 / 0.8 mm and 1.5 / 0.6 mm for the 3x3 array,
whose 1.25 mm mesh would take about 7 GB and 1 mm about 12 GB), extrapolated
(Richardson, order 2, their size ratio; gmsh's meshes are similar, not nested). 3D
with the Yeoh silicone costs minutes per solve, so the law's effect on the
reference is taken from 2D: the extrapolated linear 3D value times the Yeoh /
linear ratio of the finest axisymmetric (single) or plane-strain (array) model.
The charge-amplifier outputs are small-signal (linear about the unloaded state):
their reference is the 3D sweep at 1.5 mm, linear (not extrapolated).

Every solve is kept in a study store (`Store`, keyed by the scene and the code
version), with its measured wall time: the expensive 3D reference is computed
once, and a rerun only draws.
"""

from __future__ import annotations

import hashlib
import time
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

import numpy as np

from taxel.analyses import frequency, lumped_model, lumped_response, solve_static
from taxel.analyses.accuracy.error_estimate import relative
from taxel.scene import Scene, canonical, parse, refined
from taxel.schema import to_data
from taxel.studies.store import Store
from taxel.schema import electrode_name

OUTPUTS = ("voltage_per_newton", "crosstalk", "short_circuit_charge", "charge_amp_10Hz", "charge_amp_300Hz")
LABELS = {"voltage_per_newton": "pressed-taxel voltage per newton", "crosstalk": "crosstalk",
          "short_circuit_charge": "short-circuit charge per newton",
          "charge_amp_10Hz": "charge-amplifier output at 10 Hz", "charge_amp_300Hz": "charge-amplifier output at 300 Hz"}
SWEEP = {"analysis.type": "frequency", "analysis.f_min": 10.0, "analysis.f_max": 300.0, "analysis.points": 2,
         "analysis.spacing": "linear", "analysis.method": "direct", "readout.circuit": "charge_amplifier"}
MESH_3D = {"3 mm": (3e-3, 1.2e-3), "2 mm": (2e-3, 0.8e-3), "1.5 mm": (1.5e-3, 0.6e-3),
           "1.25 mm": (1.25e-3, 0.5e-3), "1 mm": (1e-3, 0.4e-3)}


@dataclass(frozen=True)
class Level:
    """One model of the chart: a label and how to make it from the scene."""

    model: str           # lumped, plane_stress, plane_strain, axisymmetric, 3d
    order: int
    mesh: str            # "x2", "x1", "x1/2" (2D sizes) or the 3D element size
    law: str             # linear or yeoh

    @property
    def label(self) -> str:
        if self.model == "lumped":
            return "lumped"
        return f"{self.model.replace('_', ' ')} P{self.order} {self.mesh} {self.law}"

    def scene(self, base: Scene) -> Scene:
        ch = {"model.type": self.model, "model.depth": None, "model.silicone": self.law, "mesh.order": self.order,
              "model.fidelity": "fixed"}
        if self.model == "3d":
            size, piezo = MESH_3D[self.mesh]
            return base.replace(**ch, **{"mesh.size": size, "mesh.piezo_size": piezo, "mesh.piezo_layers": 2})
        return refined(base.replace(**ch), {"x2": 0.5, "x1": 1.0, "x1/2": 2.0}[self.mesh])


@dataclass
class Point:
    level: Level
    seconds: float                      # wall time of the static solve (sweep: its own)
    unknowns: int
    values: dict[str, float]
    sweep_seconds: float | None = None
    errors: dict[str, float] = field(default_factory=dict)


def axisymmetric_ok(scene: Scene) -> bool:
    a = scene.array
    return a.rows * a.cols == 1 and a.piezo.upper().startswith(("PSI", "PZT"))


def levels(scene: Scene) -> list[Level]:
    """The chart's models for a scene (see the module docstring)."""
    out = [Level("lumped", 0, "-", "linear")] if scene.array.rows * scene.array.cols == 1 else []
    models = ["plane_stress", "plane_strain"] + (["axisymmetric"] if axisymmetric_ok(scene) else [])
    for m in models:
        for order in (1, 2):
            out += [Level(m, order, lev, "linear") for lev in ("x2", "x1", "x1/2")]
    for m in ("plane_strain",) + (("axisymmetric",) if axisymmetric_ok(scene) else ()):
        out += [Level(m, 2, lev, "yeoh") for lev in ("x2", "x1", "x1/2")]
    out += [Level("3d", 2, lev, "linear") for lev in ("3 mm", "2 mm", "1.5 mm")]
    return out


def finest_3d(scene: Scene) -> tuple[Level, Level]:
    single = scene.array.rows * scene.array.cols == 1
    if single:
        return Level("3d", 2, "1.5 mm", "linear"), Level("3d", 2, "1 mm", "linear")
    return Level("3d", 2, "2 mm", "linear"), Level("3d", 2, "1.5 mm", "linear")


@cache
def solver_version() -> str:
    """Hash of what a solve depends on: the FEM, the meshing, the analyses (but not
    the error estimate and the model choice, taxel.analyses.accuracy, which solve nothing themselves) and
    the scene schema; an estimator change keeps the cached work-precision solves."""
    import taxel.analyses
    import taxel.fem
    import taxel.meshing
    import taxel.scene
    import taxel.scene_tables
    h = hashlib.sha256()
    for mod in (taxel.fem, taxel.meshing, taxel.analyses):
        for f in sorted(Path(mod.__path__[0]).rglob("*.py")):
            if f.parent.name != "accuracy":         # taxel.analyses.accuracy: the estimate and the model choice
                h.update(f.read_bytes())
    h.update(Path(taxel.scene.__file__).read_bytes())
    h.update(Path(taxel.scene_tables.__file__).read_bytes())
    return h.hexdigest()[:16]


def _cached(store: Store, scene: Scene, compute) -> dict:
    """The stored result of `compute(scene)`, or None when it failed (stored too:
    a Newton stop at 1 N stays a stop on a rerun)."""
    data = to_data(scene)
    key = "wp-" + hashlib.sha256((canonical(parse({**data, "name": "point"})) + solver_version()).encode()).hexdigest()
    row = store.get(key)
    if row is not None:
        return row["result"] if row["status"] == "done" else None
    t0 = time.perf_counter()
    try:
        result = compute(parse({**data, "name": "point"}))
    except Exception as exc:            # recorded; the chart goes on without this point
        store.put(key, {"label": scene.name}, "failed", None, f"{type(exc).__name__}: {exc}"[:300],
                  time.perf_counter() - t0)
        return None
    result["seconds"] = time.perf_counter() - t0
    store.put(key, {"label": scene.name}, "done", result, seconds=result["seconds"])
    return result


def static_values(scene: Scene) -> dict:
    res = solve_static(scene)
    taxels = {k: e for k, e in res.electrodes.items() if e.state != "reference"}
    p = res.pressed or next(iter(taxels))
    f = abs(res.applied_force)
    out = {"voltage_per_newton": abs(taxels[p].voltage) / f, "short_circuit_charge": abs(taxels[p].short_circuit_charge) / f}
    if res.crosstalk is not None:
        out["crosstalk"] = res.crosstalk
    return {"values": out, "unknowns": res.unknowns}


def sweep_values(scene: Scene) -> dict:
    res = frequency(scene.replace(**SWEEP))
    p = scene.load.taxel
    k = res.names.index(electrode_name(p[0], p[1]))
    mag = np.abs(res.output[:, k])
    return {"values": {"charge_amp_10Hz": float(mag[0]), "charge_amp_300Hz": float(mag[1])}}


def lumped_values(scene: Scene) -> dict:
    lm = lumped_model(scene)
    resp = lumped_response(scene.replace(**SWEEP))
    mag = np.abs(resp.output)
    return {"values": {"voltage_per_newton": abs(lm.V_oc([1e-3])[0]) / lm.force,
                       "short_circuit_charge": abs(lm.Q_sc([1e-3])[0]) / lm.force,
                       "charge_amp_10Hz": float(mag[0]), "charge_amp_300Hz": float(mag[-1])}, "unknowns": 3}


def point(store: Store, base: Scene, level: Level, sweep: bool = True) -> Point | None:
    """One model's values and wall time (cached; None when the solve failed, e.g.
    Newton stopping where the pressed surface creases). Linear models are solved
    at 1 N: their values per newton do not depend on the force."""
    one = base.replace(**{"load.force": 1.0}) if level.law == "linear" else base
    if level.model == "lumped":
        r = _cached(store, one.replace(**{"analysis.type": "frequency", "model.depth": None,
                                          "model.type": "axisymmetric"}), lumped_values)
        return None if r is None else Point(level, r["seconds"], 3, r["values"])
    sc = level.scene(one)
    r = _cached(store, sc, static_values)
    if r is None:
        return None
    pt = Point(level, r["seconds"], r["unknowns"], dict(r["values"]))
    if sweep and level.law == "linear":
        s = _cached(store, sc.replace(**SWEEP), sweep_values)
        if s is not None:
            pt.values.update(s["values"])
            pt.sweep_seconds = s["seconds"]
    return pt


@dataclass
class WorkPrecision:
    scene: str
    force: float
    points: list[Point]
    reference: dict[str, float]
    how: str

    def pareto(self, output: str) -> list[Point]:
        """The cheapest-for-accuracy points: none is both faster and more accurate."""
        pts = sorted((p for p in self.points if output in p.errors), key=lambda p: (cost(p, output), p.errors[output]))
        front, best = [], np.inf
        for p in pts:
            if p.errors[output] < best:
                front.append(p)
                best = p.errors[output]
        return front

    def cheapest(self, output: str, tolerance: float) -> Point | None:
        ok = [p for p in self.points if p.errors.get(output, np.inf) <= tolerance]
        return min(ok, key=lambda p: cost(p, output)) if ok else None


def cost(p: Point, output: str) -> float:
    return p.sweep_seconds if output.startswith("charge_amp") and p.sweep_seconds else p.seconds


def work_precision(scene: Scene, force: float, store_dir, progress=None) -> WorkPrecision:
    """Every level's values, time and error against the reference, for `scene` at `force` (N)."""
    store = Store(store_dir)
    base = scene.replace(**{"load.force": force, "analysis.type": "static"})
    try:
        pts, failed = [], []
        for lev in levels(base):
            pt = point(store, base, lev)
            (pts.append(pt) if pt is not None else failed.append(lev.label))
            if progress:
                progress(lev, pt)
        fine_a, fine_b = finest_3d(base)
        a, b = point(store, base, fine_a), point(store, base, fine_b, sweep=False)
        ratio = MESH_3D[fine_a.mesh][0] / MESH_3D[fine_b.mesh][0]
        ref = {k: b.values[k] + (b.values[k] - a.values[k]) / (ratio ** 2 - 1) for k in b.values}
        law_model = "axisymmetric" if axisymmetric_ok(base) else "plane_strain"
        law, law_mesh = {}, None
        for mesh in ("x1/2", "x1", "x2"):         # the finest mesh on which Yeoh converges
            lin, yeoh = (point(store, base, Level(law_model, 2, mesh, law), sweep=False)
                         for law in ("linear", "yeoh"))
            if yeoh is not None:
                law = {k: yeoh.values[k] / lin.values[k] for k in yeoh.values if k in lin.values and lin.values[k]}
                law_mesh = mesh
                break
        ref = {k: v * law.get(k, 1.0) for k, v in ref.items()}
        swept = point(store, base, Level("3d", 2, "1.5 mm", "linear"))       # the finest 3D sweep
        ref.update({k: swept.values[k] for k in ("charge_amp_10Hz", "charge_amp_300Hz") if k in swept.values})
        if b.level not in {p.level for p in pts}:
            pts.append(b)
    finally:
        store.close()
    for p in pts:
        p.errors = {k: relative(v, ref[k]) for k, v in p.values.items() if k in ref}
    how = (f"reference: 3D {fine_a.mesh} and {fine_b.mesh} extrapolated (order 2), "
           + (f"times the Yeoh/linear ratio of {law_model.replace('_', ' ')} P2 {law_mesh}" if law_mesh else
              "linear (Yeoh converged on no mesh at this force: a pressure patch creases the surface)")
           + "; charge-amplifier outputs: 3D 1.5 mm, linear"
           + (f"; failed, not shown: {', '.join(failed)}" if failed else ""))
    return WorkPrecision(scene.name, force, pts, ref, how)
