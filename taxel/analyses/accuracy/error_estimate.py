"""How wrong a static result may be: its estimated relative error on each output,
split into discretisation, model form and material law.

Outputs (`output_values`, a part of `StaticResult.outputs()`): the sensitivity
(the pressed taxel's open-circuit voltage per newton, V/N), the crosstalk
(largest neighbour |V| / pressed |V|), and the charge sensitivity (the pressed
taxel's short-circuit charge per newton, C/N). Every part is a relative error
|q_h - q| / |q| of the output q, and the total is their sum (a bound: signed
parts may cancel, the sum never undercounts them).

- **Discretisation** (`discretisation`): Richardson, q_h = q + C h^p, with the
  order p taken from the meshes where the assumed order (ASSUMED_ORDER, 2 for P2)
  is not reached. The thesis taxels are not in the assumed regime: the piezo's
  edges make the fields singular and the voltage converges at order about 1
  (MEASURED_ORDER), so a two-mesh estimate at order 2 would undercount. The
  method follows the cost of refining (each nested refinement multiplies the
  unknowns by 2^dim), against NESTED_BUDGET unknowns for the finest mesh:
  1. "three nested meshes": this mesh and its two uniform refinements (h, h/2,
     h/4, `TaggedMesh.refined`). The observed order p_obs = log2(d1 / d2) of the
     differences d1 = q_h - q_h/2, d2 = q_h/2 - q_h/4; p = min(ASSUMED, p_obs),
     at least MIN_ORDER (differences that do not shrink are pre-asymptotic: p =
     MIN_ORDER, a wide bound, and the estimate says so); the error is
     SAFETY_THREE_MESH |q_h - q_inf| with q_inf = q_h/4 + (q_h/4 - q_h/2) / (2^p - 1).
  2. "two nested meshes, widened": h and h/2 only; p = min(ASSUMED, the lowest
     order measured for this model type, MEASURED_ORDER), error d1 2^p / (2^p - 1).
  3. "coarser mesh, widened": the scene re-meshed at twice every size
     (`refined(scene, 0.5)`, 2^dim fewer unknowns; not nested: gmsh's meshes at h
     and 2h are similar, so the estimate is noisier) with p = MEASURED_ORDER:
     |q_h - q_2h| / (2^p - 1). In 3D (a 3D refinement costs 8x the unknowns
     and more than 8x the time) this is done per direction instead,
     "through and in-plane parts, widened" (`_split_3d`): the same plan mesh with
     twice the elements through the piezo, and the plan at twice every in-plane
     size with the same elements through, each by Richardson at p, the two
     added in absolute value. The reason: on the thesis taxel the two parts have
     opposite signs and about equal size, so coarsening both at once measures
     the one-element-through regime instead of this mesh; added in absolute
     value they are a bound that does not rely on the cancellation. Cost: solves
     of about 1.4x and 0.25x this mesh's unknowns.
  A 3D mesh as coarse as CHEAP_3D is given the error of that mesh measured
  against the 3D reference instead (CHEAP_3D_ERROR). The record says which
  (`ErrorEstimate.method`, `ErrorEstimate.order`).

  "Bounds within 3x" means 1 <= estimate / |true| <= 3, with the true error
  against a nested Richardson reference (benchmarks/estimator_coverage.py --types,
  tests/test_error_estimate.py). In 2D that reference is far better than the
  errors. In 3D the extrapolations of docs/reference_3d.json's nested chains
  (benchmarks/reference_3d.py) spread by more than the default mesh's whole
  error, so the true error is taken as the largest |error| against any of the
  chains' extrapolations (the error the reference cannot rule out): against the
  chains' mean alone a mesh's error can sit near zero by cancellation. The
  measured coverage, per model type and over 22 scenes, is in
  docs/guide/meshes-and-accuracy.md ("The estimator, checked"); its history in CHANGELOG.md.
- **Model form** (2D plane strain/stress and axisymmetric against 3D): the same
  scene solved on the cheapest 3D model whose own voltage error is below 0.5 %
  (CHEAP_3D: 1.5 mm elements, 0.6 mm at the taxels, two through the piezo, as the
  quarter model that model.symmetry = "auto" picks; benchmarks/cheap_3d_symmetry.py;
  a coarser 3D mesh errs by more than the model-form difference it would measure).
  The estimate is |q_2D / q_3D,cheap - 1| + CHEAP_3D_ERROR[output]: the measured
  difference on this very geometry, widened by how far the cheapest 3D mesh itself
  may be from the converged 3D value (measured by benchmarks/estimator_coverage.py
  over its scenes). Both solves use the linear silicone (a Yeoh 3D solve would cost
  minutes): the model-form ratio is taken as independent of the law.
- **Material law** (linear silicone against Yeoh): the existing strain rule,
  LINEAR_ERROR_PER_STRAIN x the largest silicone strain
  (benchmarks/silicone_model_error.py), on every output; zero for a Yeoh result on a
  built-in silicone (its Yeoh set is the reference law); not estimated for a Yeoh result
  on a user silicone (`material`: the user's constants are the law, not a measured one).
"""

from __future__ import annotations

import time

import numpy as np

from taxel.scene import Scene, refined, scene_material_names
from taxel.analyses.results import ErrorEstimate, FrequencyResult, OutputError, StaticResult
from taxel.analyses.model.problem import solve_model
from taxel.analyses.results.static import LINEAR_ERROR_PER_STRAIN, linear_error

OUTPUTS = ("sensitivity", "crosstalk", "charge_sensitivity")

# The assumed (a priori) Richardson order per element order: 2 for P2 on smooth fields.
# P1/MINI has no observed order on the thesis taxels: the differences between levels
# 0.5x..4x grow (PZT -0.79, 0.51; PVDF -0.43, -0.23); 2 is kept and the estimate says so.
ASSUMED_ORDER = {1: 2.0, 2: 2.0}
# The lowest observed order of the pressed-taxel voltage per model type, from nested
# refinements of the thesis taxel's 0.5 mm / 0.1 mm mesh (h .. h/8): plane stress 0.98,
# plane strain and axisymmetric 1.22 (1.07-1.10 over h .. h/4), each taken a little
# lower; 3D: the press's nested chain 1.32 (benchmarks/contact_3d.py), the 3x3 array's 1.50
# and the single taxel's four chains 0.96-1.56 after the edge fix (benchmarks/reference_3d.py),
# taken as 1.0 (the 2D edge singularity's order; the lowest chain's 0.96 is within 5 % of it).
# benchmarks/estimator_coverage.py prints each estimate against the true error.
MEASURED_ORDER = {"plane_stress": 0.95, "plane_strain": 1.1, "axisymmetric": 1.1, "3d": 1.0}
MIN_ORDER = 0.5            # pre-asymptotic differences: the widest bound the estimate gives
# The three-mesh estimate is Richardson's error times Roache's safety factor for a
# three-grid study (the grid convergence index, Roache 1994: 1.25): the observed order
# over h..h/4 runs above the asymptotic one on these taxels (plane strain from 1 mm:
# 1.3 over h..h/4, 1.2 below), so the unwidened value fell 4 % short.
SAFETY_THREE_MESH = 1.25
# The finest nested mesh an estimate may solve, in unknowns (2D P2: the default single
# taxel's h/4 is 72k unknowns, 2-6 s; a Yeoh or contact solve costs a Newton loop).
NESTED_BUDGET = {"linear": 100_000, "nonlinear": 25_000}
# What a P2 unknown costs against a 2D one (denser rows: a 3D solve of n unknowns
# takes about as long as a 2D one of 4n, benchmarks/work_precision.py).
UNKNOWN_COST = {2: 1, 3: 4}

# The cheapest 3D model: its mesh sizes, and its relative error per output against the
# 3D reference, the worst over the scenes of benchmarks/estimator_coverage.py (x 1.2).
CHEAP_3D = {"mesh.size": 1.5e-3, "mesh.piezo_size": 0.6e-3, "mesh.piezo_layers": 2}
CHEAP_3D_ERROR = {"sensitivity": 0.005, "crosstalk": 0.05, "charge_sensitivity": 0.005}
# Under a rigid punch (benchmarks/press_3d.py, the thesis taxel at the rig's probe, 1 N, Yeoh,
# sticking; docs/press_3d_reference.json): the press's nested family (the size field / 0.71 ... / 3.36,
# eight levels) reads -0.79738 ... -0.78243 V/N; Richardson fitted over the six levels from / 1.41,
# order 1.35: -0.77981 V/N (largest residual 2.2e-4 V/N; at orders 1 / 2 -0.77812 / -0.78136). The
# default press mesh (taxel.scene.DEFAULT_PRESS_MESH, -0.78635 V/N) is 0.84 % from it: times the
# three-mesh safety factor (SAFETY_THREE_MESH), a floor where the press has no estimate of its own;
# since 2026-11-29 the 0.84 % plus the reference's uncertainty, 0.30 % (docs/press_reference.json,
# benchmarks/press_directions.py), times the factor: 1.43 % (it was 1.05 %, which did not hold the
# reference with its uncertainty).
PRESS_3D_ERROR = 0.0143
# CHEAP_3D's mesh (extruded, 1.5 mm / 0.6 mm, 2 through the piezo) under the punch: -0.79956 V/N,
# 2.53 % from the Richardson value, times the same factor.
CHEAP_3D_PRESS_ERROR = 0.0316


def cheap_3d_error(scene: Scene) -> dict[str, float]:
    """The cheapest 3D mesh's error per output for this scene's load."""
    if scene.load.contact:
        return {k: max(v, CHEAP_3D_PRESS_ERROR) for k, v in CHEAP_3D_ERROR.items()}
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


def no_3d_counterpart(scene: Scene) -> str | None:
    """Why a 2D scene has no cheapest 3D model to compare with, or None: a cylinder
    pressing in plane strain is infinitely long; no 3D probe is that cylinder."""
    from taxel.scene import SceneError
    try:
        cheapest_3d(scene)
    except SceneError as exc:
        if scene.load.shape == "cylinder":
            return ("a cylinder pressing a plane-strain section is infinitely long and has no 3D model "
                    "(a 3D press takes a flat punch or a sphere); the error shown is discretisation and material")
        return f"this scene has no 3D model ({str(exc).splitlines()[0]})"
    return None


def is_cheap_3d(scene: Scene) -> bool:
    """The scene is on the CHEAP_3D mesh itself (whose error CHEAP_3D_ERROR was measured;
    a coarser mesh errs more and is estimated by Richardson)."""
    m = scene.mesh
    return scene.model.type == "3d" and abs(m.size / CHEAP_3D["mesh.size"] - 1) < 1e-3 and \
        abs((m.piezo_size or m.size / 4) / CHEAP_3D["mesh.piezo_size"] - 1) < 1e-3 and \
        m.piezo_layers == CHEAP_3D["mesh.piezo_layers"] and m.order == 2


def relative(a: float, b: float) -> float:
    """|a / b - 1| (b the better value); 0 when both are 0."""
    return abs(a - b) / abs(b) if b != 0 else (0.0 if a == 0 else float("inf"))


def richardson(fine: dict, coarse: dict, order: float, ratio: float = 2.0) -> dict[str, float]:
    """Relative error of each fine value: |q_h - q_rh| / (r^p - 1) / |q_h|."""
    return {k: abs(fine[k] - coarse[k]) / (ratio ** order - 1) / abs(fine[k]) if fine[k] else 0.0
            for k in fine if k in coarse}


def law_used(result: StaticResult) -> str:
    return "yeoh" if result.yeoh else "linear"


def observed_order(q1: float, q2: float, q4: float) -> float | None:
    """The order of q_h, q_h/2, q_h/4 (None where the differences do not shrink
    monotonically: pre-asymptotic or at round-off)."""
    d1, d2 = q1 - q2, q2 - q4
    if d1 == 0 or d2 == 0 or d1 * d2 < 0 or abs(d2) >= abs(d1):
        return None
    return float(np.log2(d1 / d2))


def discretisation(scene: Scene, result: StaticResult, vals: dict[str, float], solver: str = "auto",
                   budget: int | None = None) -> tuple[dict[str, float], str, float, str]:
    """The discretisation part of each output: (errors, method, order of the first
    output, the line that says how). See the module docstring for the three methods."""
    dim = 3 if scene.model.type == "3d" else 2
    n, growth = result.unknowns * UNKNOWN_COST[dim], 2 ** dim
    law = "linear" if scene.model.silicone == "linear" and not scene.load.contact else "nonlinear"
    budget = NESTED_BUDGET[law] if budget is None else budget
    assumed = ASSUMED_ORDER[scene.mesh.order]
    measured = min(assumed, MEASURED_ORDER[scene.model.type])
    tm = None
    if growth * n <= budget:
        tm = result.mesh
        if tm is None:
            from taxel.analyses.model.problem import mesh     # a stored result has no mesh: mesh the scene again
            tm = mesh(scene)
    p1 = " P1 is pre-asymptotic on the thesis taxels (the differences grow under refinement): use order 2." \
        if scene.mesh.order == 1 else ""
    if tm is not None and growth ** 2 * n <= budget:
        q2 = output_values(solve_model(scene, solver, tagged_mesh=tm.refined(1)))
        q4 = output_values(solve_model(scene, solver, tagged_mesh=tm.refined(2)))
        disc, orders = {}, {}
        for k, q in vals.items():
            if k not in q2 or k not in q4:
                continue
            p_obs = observed_order(q, q2[k], q4[k])
            p = MIN_ORDER if p_obs is None else max(MIN_ORDER, min(assumed, p_obs))
            q_inf = q4[k] + (q4[k] - q2[k]) / (2 ** p - 1)
            disc[k], orders[k] = SAFETY_THREE_MESH * relative(q, q_inf), (p, p_obs)
        p, p_obs = orders.get(next(iter(vals)), (MIN_ORDER, None))
        seen = "; ".join(f"{k} {'not asymptotic' if o is None else f'{o:.2f}'}" for k, (_, o) in orders.items())
        return disc, "three nested meshes", p, (
            f"discretisation: three nested meshes (this one and two uniform refinements), Richardson at the "
            f"observed order where it is below the assumed {assumed:g} (observed: {seen}; at least {MIN_ORDER:g}), "
            f"times the safety factor {SAFETY_THREE_MESH:g}." + p1)
    if tm is not None:
        q2 = output_values(solve_model(scene, solver, tagged_mesh=tm.refined(1)))
        widen = 2 ** measured / (2 ** measured - 1)
        disc = {k: abs(q - q2[k]) * widen / abs(q) if q else 0.0 for k, q in vals.items() if k in q2}
        return disc, "two nested meshes, widened", measured, (
            f"discretisation: this mesh and its uniform refinement, widened by the lowest order measured in "
            f"{scene.model.type}, {measured:g} (the three-mesh check would cost {growth ** 2 * n} "
            f"2D-equivalent unknowns, over the budget of {budget})." + p1)
    if dim == 3:
        return _split_3d(scene, vals, solver, measured, growth * n, budget)
    coarse = output_values(solve_model(refined(scene, 0.5), solver))
    disc = richardson(vals, coarse, measured)
    return disc, "coarser mesh, widened", measured, (
        f"discretisation: this mesh and one at twice every size (not nested), Richardson at the lowest order "
        f"measured in {scene.model.type}, {measured:g} (a nested refinement would cost {growth * n} "
        f"2D-equivalent unknowns, over the budget of {budget})." + p1)


def _split_3d(scene: Scene, vals: dict[str, float], solver: str, order: float, cost: int,
              budget: int) -> tuple[dict[str, float], str, float, str]:
    """The 3D discretisation error as two parts added in absolute value: through the
    piezo (the same plan mesh with twice the elements through the piezo: the plan is
    extruded, so only the through-thickness size changes) and in plane (the plan at
    twice every in-plane size, the same elements through), each by Richardson at
    `order`. The two have opposite signs on the thesis taxels (more elements through
    raise |V|, a finer plan lowers it), so a coarsening of both at once, as in 2D,
    lets them cancel or, from two elements through to one, measures the one-element
    regime (1.4 % off) instead of this mesh."""
    m = scene.mesh
    through = output_values(solve_model(refined(scene, 2, in_plane=False), solver))
    plan = output_values(solve_model(refined(scene, 0.5, through=False), solver))
    a, b = richardson(through, vals, order), richardson(vals, plan, order)
    # a is relative to the finer value (through); rescaled to this mesh's value
    disc = {k: a.get(k, 0.0) * (abs(through[k] / v) if k in through and v else 1.0) + b.get(k, 0.0)
            for k, v in vals.items() if k in through or k in plan}
    first = next(iter(vals))
    return disc, "through and in-plane parts, widened", order, (
        f"discretisation: two parts added in absolute value (they have opposite signs and may cancel), each by "
        f"Richardson at the lowest order measured in 3d, {order:g}: through the piezo (the same plan, "
        f"{2 * m.piezo_layers} elements through: {100 * a.get(first, 0):.2g} % on {first}) and in plane (twice "
        f"every in-plane size, not nested: {100 * b.get(first, 0):.2g} %) (a nested refinement would cost {cost} "
        f"2D-equivalent unknowns, over the budget of {budget}).")


def estimate(scene: Scene, result: StaticResult, solver: str = "auto", cheap_3d: StaticResult | None = None,
             model_form: bool = True, budget: int | None = None) -> ErrorEstimate:
    """The error estimate of `result` (a static solve of `scene`); `cheap_3d` reuses
    a solve of `cheapest_3d(scene)`. Costs the discretisation's extra solves
    (`discretisation`; `budget` overrides NESTED_BUDGET), plus one cheapest-3D
    solve for a 2D or axisymmetric result (unless given)."""
    t0 = time.perf_counter()
    vals = output_values(result)
    law = law_used(result)
    base = scene.replace(**{"model.silicone": law, "model.fidelity": "fixed"})
    how = []
    order: float | None = None
    if is_cheap_3d(scene):
        disc = {k: cheap_3d_error(scene)[k] for k in vals}
        method = "cheapest 3D mesh, measured"
        how.append("discretisation: the cheapest 3D mesh's measured error (CHEAP_3D_ERROR"
                   + (", at least CHEAP_3D_PRESS_ERROR under a punch)" if scene.load.contact else ")"))
    else:
        disc, method, order, line = discretisation(base, result, vals, solver, budget)
        how.append(line)
    form: dict[str, float | None] = {k: None for k in vals}
    if scene.model.type == "3d":
        form = {k: 0.0 for k in vals}
    elif model_form and scene.array is not None and (why := no_3d_counterpart(scene)):
        how.append(f"model form: not estimated: {why}")
    elif model_form and scene.array is not None:
        r3 = cheap_3d or solve_model(cheapest_3d(scene), solver)
        v3 = output_values(r3)
        err3 = cheap_3d_error(scene)
        form = {k: relative(vals[k], v3[k]) + abs(vals[k] / v3[k]) * err3[k] if k in v3 else None
                for k in vals}
        how.append(f"model form: {scene.model.type} against the cheapest 3D model of this scene "
                   f"({r3.unknowns} unknowns), widened by that mesh's measured error"
                   + (f" (under a punch at least {100 * CHEAP_3D_PRESS_ERROR:g} %)" if scene.load.contact else ""))
    else:
        how.append("model form: not estimated" + ("" if model_form else " (not asked)"))
    mat, line = material(scene, law, result.max_strain)
    how.append(line)
    outs = {k: OutputError(v, disc.get(k), form.get(k), mat) for k, v in vals.items()}
    return ErrorEstimate(outs, how, time.perf_counter() - t0, method, order)


def user_silicone(scene: Scene) -> str | None:
    """The name of the user solid (a [materials] table) the scene's silicone is, if it is one."""
    names = scene_material_names(scene)
    silicone = names[-1] if scene.array is not None else None
    for n in ([silicone] if silicone else names):
        rec = scene.materials.get(n)
        if isinstance(rec, dict) and rec.get("kind") == "solid":
            return n
    return None


def material(scene: Scene, law: str, max_strain: float) -> tuple[float | None, str]:
    """The material-law part of every output's error and the line that says how.

    Linear silicone: LINEAR_ERROR_PER_STRAIN x the largest strain (linear against Yeoh,
    measured on Ecoflex 00-30, benchmarks/silicone_model_error.py). Yeoh with a built-in
    silicone: 0, its Yeoh set is the reference law (fitted to a published tension test,
    fem.constitution). Yeoh with a user silicone: not estimated (None): the user's
    constants are the law, and how far they are from the real material taxel cannot
    measure; rating them exact would hide it (a user's fit, taxel material fit-yeoh,
    reports its own residual)."""
    user = user_silicone(scene)
    if law == "linear":
        where = f" (measured on Ecoflex 00-30; '{user}' is the user's)" if user else ""
        return linear_error(max_strain), (f"material: linear silicone, {LINEAR_ERROR_PER_STRAIN} x largest strain "
                                          f"{100 * max_strain:.2g} %{where}")
    if user:
        return None, (f"material: not estimated: the Yeoh law of the user silicone '{user}' (its C10, C20, C30) is "
                      "taken as given; its error against the real material is not known here (fit the constants "
                      "to a tension test of it: taxel material fit-yeoh reports the fit's residual)")
    return 0.0, "material: Yeoh (the reference law, fitted to a published tension test)"


def sweep_values(result: FrequencyResult) -> np.ndarray:
    """|readout output| per newton of the pressed (or first) taxel at each frequency."""
    return result.sweep_values()


def estimate_frequency(scene: Scene, result: FrequencyResult, frequency) -> ErrorEstimate:
    """The error of a frequency sweep's readout output (the largest relative error
    over its frequencies): discretisation by Richardson against the sweep on a mesh
    at twice every size, model form against the cheapest 3D model's sweep (a 2D or
    axisymmetric result), plus the sweep's own measured reduction error. The
    silicone is linear in a sweep (small signal about the unloaded state): no
    material-law part. `frequency(scene)` is the sweep solver (taxel.analyses.solves.dynamic's,
    handed in by the analysis that made `result`: the estimate sits below the solves)."""
    t0 = time.perf_counter()
    y = sweep_values(result)
    yc = sweep_values(frequency(refined(scene, 0.5)))
    p = min(ASSUMED_ORDER[scene.mesh.order], MEASURED_ORDER[scene.model.type])
    disc = float(np.max(np.abs(y - yc) / (2 ** p - 1) / np.abs(y))) + result.measured_error
    how = [f"discretisation: Richardson on a mesh at twice every size, the measured order {p:g}, the largest over "
           f"{len(y)} frequencies, plus the reduced sweep's measured error {result.measured_error:.1e}"]
    form = 0.0 if scene.model.type == "3d" else None
    if scene.model.type != "3d" and scene.array is not None and (why := no_3d_counterpart(scene)):
        how.append(f"model form: not estimated: {why}")
    elif scene.model.type != "3d" and scene.array is not None:
        y3 = sweep_values(frequency(cheapest_3d(scene).replace(**{"model.silicone": scene.model.silicone})))
        form = float(np.max(np.abs(y / y3 - 1))) + CHEAP_3D_ERROR["sensitivity"]
        how.append("model form: against the cheapest 3D model's sweep, widened by that mesh's measured error")
    out = {"readout_sensitivity": OutputError(float(y.max()), disc, form, 0.0)}
    return ErrorEstimate(out, how, time.perf_counter() - t0)
