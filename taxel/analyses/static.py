"""The static solve of a scene on the model it gives: linear, Yeoh, or "auto" (the
cheapest silicone law that is accurate enough).

model.silicone = "auto" solves the linear model, estimates its voltage error as
LINEAR_ERROR_PER_STRAIN x its largest silicone strain, keeps it when the estimate
is within model.tolerance and otherwise solves Yeoh on the same mesh; the choice and
the estimate are in `StaticResult.model_note`. A solve that stops short of its load
raises fem's NewtonError or ContactError (taxel.analyses.solve returns it as a result).
"""

from __future__ import annotations

import time

from taxel.fem import assembly
from taxel.fem import static
from taxel.fem import hyperelastic
from taxel.fem import contact
from taxel.fem.hyperelastic import NewtonError
from taxel.meshing.build import TaggedMesh
from taxel.scene import Scene
from taxel.analyses.problem import problem, with_silicone
from taxel.analyses.results import StaticResult
from taxel.analyses.results.static import linear_error


def solve_model(scene: Scene, solver: str = "auto", tagged_mesh: TaggedMesh | None = None,
                scale: bool = True, newton_options: dict | None = None) -> StaticResult:
    """Solve a scene's static load case on the model it gives (model.fidelity is not
    read here: taxel.analyses.solve_static resolves "auto" by the model choice), meshing it unless
    `tagged_mesh` is given. With a Yeoh silicone, `newton_options` go to
    fem.hyperelastic.newton (tol, max_iter, first_step, stepping, line_search)."""
    t0 = time.perf_counter()
    prob = problem(scene, tagged_mesh)
    t1 = time.perf_counter()
    if scene.model.silicone != "auto":
        return _solve(scene, prob, solver, scale, newton_options, t0, t1)
    try:
        lin = _solve(scene, with_silicone(prob, "linear"), solver, scale, newton_options, t0, t1)
    except contact.ContactError as exc:      # a linear silicone under a punch can fail where Yeoh does not
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
    except (NewtonError, contact.ContactError) as exc:
        lin.model_note = (f"auto: Yeoh silicone needed (linear error about {100 * est:.2g} %) but {exc}; "
                          f"returning the LINEAR result")
        return lin
    hyper.model_note = f"auto: Yeoh silicone (the linear model would err by about {100 * est:.2g} %)"
    return hyper


def _solve(scene, prob, solver, scale, newton_options, t0, t1) -> StaticResult:
    sy = assembly.assemble(prob)
    t2 = time.perf_counter()
    if prob.indenter is not None:
        opts = {k: v for k, v in (newton_options or {}).items() if k in contact.Options.__dataclass_fields__}
        sol = contact.press(sy, prob.indenter, solver, contact.Options(**opts))
    elif prob.hyperelastic:
        sol = hyperelastic.solve_yeoh(sy, solver, **(newton_options or {}))
    else:
        sol = static.solve_linear(sy, solver, scale)
    t3 = time.perf_counter()
    return StaticResult(scene, sol, {"mesh": t1 - t0, "assemble": t2 - t1, "solve": t3 - t2, "total": t3 - t0},
                        yeoh=prob.hyperelastic)
