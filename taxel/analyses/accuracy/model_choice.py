"""`[model] fidelity = "auto"`: the cheapest model, mesh and silicone law whose
estimated error on the requested outputs (`model.outputs`) is within
`model.tolerance`.

The ladder (`ladder`), cheapest first, measured on the thesis taxels
(benchmarks/work_precision.py): plane strain on the scene's mesh (0.1-0.5 s),
axisymmetric (single taxel, centred press, no crosstalk asked), the cheapest 3D
model (estimate.CHEAP_3D: 1.5 mm / 0.6 mm, 5-10 s single, 18 s 3x3), and 3D at
1 mm / 0.4 mm (the coverage benchmark's reference). Each rung is solved with the linear silicone first;
when only the material part puts it over the tolerance, the same rung is solved
with Yeoh (not offered in plane stress). Each rung's error is estimated by
`estimate.estimate` (the cheapest-3D solve is made once and shared). The first
rung within tolerance is returned with its estimate and a note of what was
tried; when none is, the most accurate one is returned and the note says so.
Every rung is order 2: P1's two-mesh estimate is not reliable on these taxels
(pre-asymptotic, estimate.ASSUMED_ORDER).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

from taxel.scene import Scene
from taxel.analyses.accuracy import error_estimate as est
from taxel.analyses.results import StaticResult
from taxel.analyses.model.problem import solve_model


@dataclass(frozen=True)
class Rung:
    """One model of the ladder: a label and the scene changes that make it."""

    label: str
    changes: tuple[tuple[str, object], ...]


STANDARD_3D = (("mesh.size", 1e-3), ("mesh.piezo_size", 0.4e-3), ("mesh.piezo_layers", 2))


def ladder(scene: Scene) -> list[Rung]:
    """The models to try for this scene, cheapest first."""
    a, ld = scene.array, scene.load
    rungs = [Rung("plane strain", (("model.type", "plane_strain"),))]
    if a.rows * a.cols == 1 and ld.kind == "taxel" and "crosstalk" not in scene.model.outputs:
        rungs.append(Rung("axisymmetric", (("model.type", "axisymmetric"),)))
    rungs.append(Rung("3D cheapest", (("model.type", "3d"),) + tuple(est.CHEAP_3D.items())))
    rungs.append(Rung("3D", (("model.type", "3d"),) + STANDARD_3D))
    return rungs


def choose(scene: Scene, solver: str = "auto") -> StaticResult:
    """Solve `scene` (model.fidelity = "auto") on the cheapest adequate model."""
    t0 = time.perf_counter()
    tol, wanted = scene.model.tolerance, scene.model.outputs
    fixed = scene.replace(**{"model.fidelity": "fixed", "model.depth": None})
    cheap3d: StaticResult | None = None
    tried, best = [], None
    for rung in ladder(scene):
        for law in ("linear", "yeoh"):
            try:                            # the scene itself may refuse the law (no Yeoh constants)
                sc = fixed.replace(**dict(rung.changes), **{"model.silicone": law, "mesh.order": 2})
                if cheap3d is not None and sc == est.cheapest_3d(fixed):
                    res = cheap3d           # solved already for the model-form estimate
                else:
                    res = solve_model(sc, solver)
            except ValueError as exc:       # e.g. PVDF has no axisymmetric model
                tried.append(f"{rung.label} ({law}): not possible ({exc})")
                break
            if sc.model.type != "3d" and cheap3d is None and not est.no_3d_counterpart(fixed):
                cheap3d = solve_model(est.cheapest_3d(fixed), solver)
            res.error = est.estimate(sc, res, solver, cheap_3d=cheap3d)
            worst = max(res.error.outputs[k].total for k in wanted if k in res.error.outputs)
            tried.append(f"{rung.label} ({law}): {100 * worst:.2g} %")
            if best is None or worst < best[0]:
                best = (worst, res, rung.label, law)
            if worst <= tol:
                return _chosen(res, rung.label, law, worst, tol, tried, t0)
            parts = [res.error.outputs[k] for k in wanted if k in res.error.outputs]
            law_only = all(p.total - (p.material or 0) <= tol for p in parts)
            if not law_only or sc.model.type == "plane_stress":
                break                       # Yeoh cannot help this rung
    worst, res, label, law = best
    res.model_note = (f"fidelity auto: no model met the tolerance {100 * tol:g} % on {', '.join(wanted)}; "
                      f"returning the most accurate, {label} ({law} silicone, estimated {100 * worst:.2g} %). "
                      f"Tried: {'; '.join(tried)}")
    return res


def _chosen(res, label, law, worst, tol, tried, t0) -> StaticResult:
    res.model_note = (f"fidelity auto: {label}, {law} silicone: estimated error {100 * worst:.2g} % <= "
                      f"{100 * tol:g} % on {', '.join(res.scene.model.outputs)}. Tried: {'; '.join(tried)} "
                      f"({time.perf_counter() - t0:.1f} s in all)")
    return res
