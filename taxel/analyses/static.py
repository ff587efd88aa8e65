"""The static analysis of a scene: linear, Yeoh, or "auto" (the cheapest that is
accurate enough).

model.silicone = "auto" solves the linear model, estimates its voltage error as
LINEAR_ERROR_PER_STRAIN x its largest silicone strain, keeps it when the
estimate is within model.tolerance and otherwise solves Yeoh on the same mesh;
the choice and the estimate are in `StaticResult.model_note`.
"""

from __future__ import annotations

import time

from taxel.fem import assembly, linear, newton, press
from taxel.fem.newton import NewtonError
from taxel.meshing.build import TaggedMesh
from taxel.scene import Scene
from taxel.analyses.adapter import problem, with_silicone
from taxel.analyses.results import StaticResult

# Linear silicone's taxel-voltage error per unit of its own largest silicone strain:
# the worst ratio measured over the thesis PZT and PVDF taxels, 0.05 to 0.45 N
# (benchmarks/silicone_model_error.py: 0.223 least squares, 0.257 worst).
LINEAR_ERROR_PER_STRAIN = 0.257


def solve_model(scene: Scene, solver: str = "auto", tagged_mesh: TaggedMesh | None = None,
                scale: bool = True, newton_options: dict | None = None) -> StaticResult:
    """Solve a scene's static load case on the model it gives (model.fidelity is not
    read here: `taxel.analyses.solve_static` resolves "auto" by the model choice),
    meshing it unless `tagged_mesh` is given. With a Yeoh silicone, `newton_options`
    go to fem.newton.newton (tol, max_iter, first_step, stepping, line_search)."""
    t0 = time.perf_counter()
    prob = problem(scene, tagged_mesh)
    t1 = time.perf_counter()
    if scene.model.silicone != "auto":
        return _solve(scene, prob, solver, scale, newton_options, t0, t1)
    try:
        lin = _solve(scene, with_silicone(prob, "linear"), solver, scale, newton_options, t0, t1)
    except press.ContactError as exc:      # a linear silicone under a punch can fail where Yeoh does not
        hyper = _solve(scene, with_silicone(prob, "yeoh"), solver, scale, newton_options, t0, t1)
        hyper.model_note = f"auto: Yeoh silicone (the linear press failed: {exc})"
        return hyper
    est, tol = linear_error(lin.max_silicone_strain), scene.model.tolerance
    if est <= tol:
        lin.model_note = (f"auto: linear silicone (largest strain {100 * lin.max_silicone_strain:.1f} %, "
                          f"estimated voltage error {100 * est:.2g} % <= {100 * tol:g} %)")
        return lin
    t1 = time.perf_counter()
    try:
        hyper = _solve(scene, with_silicone(prob, "yeoh"), solver, scale, newton_options, t1, t1)
    except (NewtonError, press.ContactError) as exc:
        lin.model_note = (f"auto: Yeoh silicone needed (linear error about {100 * est:.2g} %) but {exc}; "
                          f"returning the LINEAR result")
        return lin
    hyper.model_note = f"auto: Yeoh silicone (the linear model would err by about {100 * est:.2g} %)"
    return hyper


def linear_error(max_silicone_strain: float) -> float:
    """Estimated relative voltage error of a linear silicone at this largest strain."""
    return LINEAR_ERROR_PER_STRAIN * max_silicone_strain


def _solve(scene, prob, solver, scale, newton_options, t0, t1) -> StaticResult:
    sy = assembly.assemble(prob)
    t2 = time.perf_counter()
    if prob.indenter is not None:
        opts = {k: v for k, v in (newton_options or {}).items() if k in press.Options.__dataclass_fields__}
        sol = press.press(sy, prob.indenter, solver, press.Options(**opts))
    elif prob.hyperelastic:
        sol = newton.solve_yeoh(sy, solver, **(newton_options or {}))
    else:
        sol = linear.solve_linear(sy, solver, scale)
    t3 = time.perf_counter()
    return StaticResult(scene, sol, {"mesh": t1 - t0, "assemble": t2 - t1, "solve": t3 - t2, "total": t3 - t0},
                        yeoh=prob.hyperelastic)
