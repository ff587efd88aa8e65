"""How wrong a static result may be: its estimated relative error on each output,
split into discretisation, model form and material law.

Outputs (`output_values`, a part of `StaticResult.outputs()`): the sensitivity
(the pressed taxel's open-circuit voltage per newton, V/N), the crosstalk
(largest neighbour |V| / pressed |V|), and the charge sensitivity (the pressed
taxel's short-circuit charge per newton, C/N). Every part is a relative error
|q_h - q| / |q| of the output q, and the total is their sum (a bound: signed
parts may cancel, the sum never undercounts them).

- **Discretisation**: two meshes of the same model. The scene's mesh (size h)
  and the same scene at every size doubled (`refined(scene, 0.5)`: 2h, half as
  many elements through the piezo). Richardson: with q_h = q + C h^p,
  e_h = |q_h - q_2h| / (2^p - 1). The order p is RICHARDSON_ORDER, the observed
  order of the voltage in 2D (benchmarks/default_mesh.py: 2.2 for P2; we take 2).
  The extra solve costs a fraction of the scene's own (about 4x fewer unknowns in
  2D, 8x in 3D). In 3D gmsh's meshes at h and 2h are similar, not nested, so the
  estimate is noisier; a 3D mesh as coarse as CHEAP_3D is given the error of
  that mesh measured against the 3D reference instead (CHEAP_3D_ERROR).
- **Model form** (2D plane strain/stress and axisymmetric against 3D): the same
  scene solved on the cheapest 3D model whose own voltage error is below 0.5 %
  (CHEAP_3D: 1.5 mm elements, 0.6 mm at the taxels, two through the piezo; as the
  quarter model that model.symmetry = "auto" picks, 0.8 s for a single taxel and 9 s
  for the 3x3 array, full 1.7 s and 20 s: benchmarks/cheap_3d_symmetry.py; a 3 mm / 1.2 mm mesh costs 0.7 s and
  6 s but errs by 0.2-3.8 % depending on the silicone thickness, which swamps a
  1 % model-form difference, measured on the thesis PZT taxel). The estimate is |q_2D / q_3D,cheap - 1| + CHEAP_3D_ERROR[output]: the
  measured difference on this very geometry, widened by how far the cheapest 3D
  mesh itself may be from the converged 3D value (measured by
  benchmarks/estimator_coverage.py over its scenes). Both solves use the linear
  silicone (a Yeoh 3D solve would cost minutes): the model-form ratio is taken
  as independent of the law.
- **Material law** (linear silicone against Yeoh): the existing strain rule,
  LINEAR_ERROR_PER_STRAIN x the largest silicone strain
  (benchmarks/silicone_model_error.py), on every output; zero for a Yeoh result.
"""

from __future__ import annotations

import time

import numpy as np

from taxel.scene import Scene, refined
from taxel.analyses.results import ErrorEstimate, FrequencyResult, OutputError, StaticResult
from taxel.analyses.static import LINEAR_ERROR_PER_STRAIN, linear_error, solve_model

OUTPUTS = ("sensitivity", "crosstalk", "charge_sensitivity")

# Richardson order per element order (the voltage's observed order in 2D is 2.2 for P2,
# benchmarks/default_mesh.py). P1/MINI has no observed order on the thesis taxels: the
# differences between levels 0.5x..4x grow (PZT -0.79, 0.51; PVDF -0.43, -0.23), and the
# coverage benchmark's P1 estimates miss by 0.34x-58x; 2 is kept and the estimate says so.
RICHARDSON_ORDER = {1: 2.0, 2: 2.0}

# The cheapest 3D model: its mesh sizes, and its relative error per output against the
# 3D reference, the worst over the scenes of benchmarks/estimator_coverage.py (x 1.2).
CHEAP_3D = {"mesh.size": 1.5e-3, "mesh.piezo_size": 0.6e-3, "mesh.piezo_layers": 2}
CHEAP_3D_ERROR = {"sensitivity": 0.005, "crosstalk": 0.05, "charge_sensitivity": 0.005}
# Under a rigid punch a 3D mesh errs more: the default 3D mesh's press voltage is +5.4 %
# off the extrapolation of three nested meshes (benchmarks/contact_3d.py, 1 N, Yeoh,
# sticking). The cheapest mesh is coarser, so this is a floor for its error there.
PRESS_3D_ERROR = 0.054


def cheap_3d_error(scene: Scene) -> dict[str, float]:
    """The cheapest 3D mesh's error per output for this scene's load."""
    if scene.load.contact:
        return {k: max(v, PRESS_3D_ERROR) for k, v in CHEAP_3D_ERROR.items()}
    return CHEAP_3D_ERROR


def output_values(result: StaticResult) -> dict[str, float]:
    """The outputs an estimate covers (OUTPUTS), of one static result (SI: V/N, ratio, C/N)."""
    out = result.outputs()
    return {k: out[k] for k in OUTPUTS if k in out}


def cheapest_3d(scene: Scene) -> Scene:
    """The scene on the cheapest 3D model (CHEAP_3D mesh, P2: CHEAP_3D_ERROR is measured
    at order 2; linear silicone, fixed fidelity)."""
    return scene.replace(**{"model.type": "3d", "model.depth": None, "model.silicone": "linear",
                            "model.fidelity": "fixed", "mesh.order": 2, **CHEAP_3D})


def is_cheap_3d(scene: Scene) -> bool:
    m = scene.mesh
    return scene.model.type == "3d" and m.size >= CHEAP_3D["mesh.size"] * 0.999 and \
        (m.piezo_size or m.size / 4) >= CHEAP_3D["mesh.piezo_size"] * 0.999


def relative(a: float, b: float) -> float:
    """|a / b - 1| (b the better value); 0 when both are 0."""
    return abs(a - b) / abs(b) if b != 0 else (0.0 if a == 0 else float("inf"))


def richardson(fine: dict, coarse: dict, order: float, ratio: float = 2.0) -> dict[str, float]:
    """Relative error of each fine value: |q_h - q_rh| / (r^p - 1) / |q_h|."""
    return {k: abs(fine[k] - coarse[k]) / (ratio ** order - 1) / abs(fine[k]) if fine[k] else 0.0
            for k in fine if k in coarse}


def law_used(result: StaticResult) -> str:
    return "yeoh" if result.yeoh else "linear"


def estimate(scene: Scene, result: StaticResult, solver: str = "auto", cheap_3d: StaticResult | None = None,
             model_form: bool = True) -> ErrorEstimate:
    """The error estimate of `result` (a static solve of `scene`); `cheap_3d` reuses
    a solve of `cheapest_3d(scene)`. Costs one coarse solve, plus one cheapest-3D
    solve for a 2D or axisymmetric result (unless given)."""
    t0 = time.perf_counter()
    vals = output_values(result)
    law = law_used(result)
    base = scene.replace(**{"model.silicone": law, "model.fidelity": "fixed"})
    how = []
    if is_cheap_3d(scene):
        disc = {k: cheap_3d_error(scene)[k] for k in vals}
        how.append("discretisation: the cheapest 3D mesh's measured error (CHEAP_3D_ERROR"
                   + (", at least PRESS_3D_ERROR under a punch)" if scene.load.contact else ")"))
    else:
        p = RICHARDSON_ORDER[scene.mesh.order]
        coarse = output_values(solve_model(refined(base, 0.5), solver))
        disc = richardson(vals, coarse, p)
        how.append(f"discretisation: Richardson, this mesh and one at twice every size, order {p:g}"
                   + ("; P1 is pre-asymptotic on the thesis taxels (the differences grow under refinement), so "
                      "this part can undercount: use order 2" if scene.mesh.order == 1 else ""))
    form: dict[str, float | None] = {k: None for k in vals}
    if scene.model.type == "3d":
        form = {k: 0.0 for k in vals}
    elif model_form and scene.array is not None:
        r3 = cheap_3d or solve_model(cheapest_3d(scene), solver)
        v3 = output_values(r3)
        err3 = cheap_3d_error(scene)
        form = {k: relative(vals[k], v3[k]) + abs(vals[k] / v3[k]) * err3[k] if k in v3 else None
                for k in vals}
        how.append(f"model form: {scene.model.type} against the cheapest 3D model of this scene "
                   f"({r3.unknowns} unknowns), widened by that mesh's measured error"
                   + (f" (under a punch at least {100 * PRESS_3D_ERROR:g} %)" if scene.load.contact else ""))
    else:
        how.append("model form: not estimated" + ("" if model_form else " (not asked)"))
    mat = linear_error(result.max_silicone_strain) if law == "linear" else 0.0
    how.append(f"material: linear silicone, {LINEAR_ERROR_PER_STRAIN} x largest strain "
               f"{100 * result.max_silicone_strain:.2g} %" if law == "linear" else "material: Yeoh (the reference law)")
    outs = {k: OutputError(v, disc.get(k), form.get(k), mat) for k, v in vals.items()}
    return ErrorEstimate(outs, how, time.perf_counter() - t0)


def sweep_values(result: FrequencyResult) -> np.ndarray:
    """|readout output| per newton of the pressed (or first) taxel at each frequency."""
    return result.sweep_values()


def estimate_frequency(scene: Scene, result: FrequencyResult) -> ErrorEstimate:
    """The error of a frequency sweep's readout output (the largest relative error
    over its frequencies): discretisation by Richardson against the sweep on a mesh
    at twice every size, model form against the cheapest 3D model's sweep (a 2D or
    axisymmetric result), plus the sweep's own measured reduction error. The
    silicone is linear in a sweep (small signal about the unloaded state): no
    material-law part."""
    from taxel.analyses.dynamic import frequency      # the sweep solvers, loaded when a sweep is estimated
    t0 = time.perf_counter()
    y = sweep_values(result)
    yc = sweep_values(frequency(refined(scene, 0.5)))
    p = RICHARDSON_ORDER[scene.mesh.order]
    disc = float(np.max(np.abs(y - yc) / (2 ** p - 1) / np.abs(y))) + result.measured_error
    how = [f"discretisation: Richardson on a mesh at twice every size, order {p:g}, the largest over "
           f"{len(y)} frequencies, plus the reduced sweep's measured error {result.measured_error:.1e}"]
    form = 0.0 if scene.model.type == "3d" else None
    if scene.model.type != "3d" and scene.array is not None:
        y3 = sweep_values(frequency(cheapest_3d(scene).replace(**{"model.silicone": scene.model.silicone})))
        form = float(np.max(np.abs(y / y3 - 1))) + CHEAP_3D_ERROR["sensitivity"]
        how.append("model form: against the cheapest 3D model's sweep, widened by that mesh's measured error")
    out = {"readout_sensitivity": OutputError(float(y.max()), disc, form, 0.0)}
    return ErrorEstimate(out, how, time.perf_counter() - t0)
