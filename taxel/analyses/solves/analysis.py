"""One analysis of a scene: `solve` runs its [analysis] (static, frequency, transient)
and returns its result, whether or not a static solve reached its load.

The static analysis resolves model.fidelity = "auto" by the model choice
(taxel.analyses.accuracy.model_choice), attaches the error estimate when asked
(taxel.analyses.accuracy.error_estimate), and otherwise solves the model as given
(taxel.analyses.model.problem.solve_model).

A static solve that stops short of its load (a Yeoh Newton under a pressure patch,
where the silicone creases; a press, where it measured a stop cause) is returned as
its last converged state, `success` False and `stop` saying what was asked, what was
reached and why, like scipy.optimize's OptimizeResult. `solve_static` and
`problem.solve_model` are the building blocks that raise instead (fem's NewtonError,
PressError): the model choice, the error estimate and the analyses that need the
full load use them.
"""

from __future__ import annotations

import contextlib
import shutil
import tempfile
from pathlib import Path

from taxel.fem.contact import PressError
from taxel.fem.hyperelastic import NewtonError
from taxel.scene import Scene, load, replace
from taxel.analyses.results import FrequencyResult, StaticResult, Stop, TransientResult
from taxel.analyses.model.problem import solve_model


def solve(scene: Scene | str | Path | dict, estimate: bool = False, out: str | Path | None = None,
          **options) -> StaticResult | FrequencyResult | TransientResult:
    """The scene's analysis ([analysis] type): StaticResult, FrequencyResult or
    TransientResult, returned whether or not a static solve reached its load
    (`result.success`; `result.stop` says what was asked, what was reached and why).
    `scene`: a Scene, a TOML file, a built-in example name or a dict (SI numbers).
    With `out`, the result's folder is written there too (`result.to_folder`, whole or
    not at all: a folder that cannot be made fails before the solve). Options:
    estimate (attach the error estimate, taxel.analyses.accuracy.error_estimate); static:
    solver ("auto", "superlu", "pardiso", "krylov"), tagged_mesh, scale,
    newton_options. Raises SceneError for bad input, and RuntimeError where not even
    the first load step of a static solve converged (there is no state to return)."""
    scene = scene if isinstance(scene, Scene) else load(scene)
    if out is not None:
        return _written(out, lambda: solve(scene, estimate, **options))
    kind = scene.analysis.type
    if kind == "frequency":
        from taxel.analyses.solves.dynamic import frequency
        res = frequency(scene)
        if estimate:
            from taxel.analyses.accuracy.error_estimate import estimate_frequency
            res.error = estimate_frequency(scene, res, frequency)
        return res
    if kind == "transient":
        from taxel.analyses.solves.dynamic import transient
        return transient(scene)
    try:
        res = solve_static(scene, **options)
        stopped = False
    except (NewtonError, PressError) as exc:
        res, stopped = _stopped(scene, exc), True
    if scene.readout.circuit != "open":    # a scene naming a readout: its numbers too
        from taxel.analyses.solves.at_readout import at_readout
        res.readout = at_readout(res)
    if stopped:
        return res
    if estimate and res.error is None:
        from taxel.analyses.accuracy.error_estimate import estimate as error_estimate
        res.error = error_estimate(res.scene, res, options.get("solver", "auto"))
    return res


def lumped(scene: Scene | str | Path | dict, out: str | Path | None = None):
    """The 3-DoF lumped model's frequency response to a scene (a LumpedResult); with
    `out`, its folder is written there too, as `solve` writes one."""
    from taxel.analyses.solves.dynamic import lumped_response
    scene = scene if isinstance(scene, Scene) else load(scene)
    return lumped_response(scene) if out is None else _written(out, lambda: lumped_response(scene))


def _written(out: str | Path, compute):
    """`compute()`'s result, its folder written to `out` whole or not at all (a folder that
    cannot be made fails before the work)."""
    with output_folder(Path(out)) as tmp:
        res = compute()
        res.to_folder(tmp)
    return res


@contextlib.contextmanager
def output_folder(path, replace: bool = False):
    """A folder written whole or not at all: the work goes to a temporary sibling
    that is renamed to `path` at the end and removed on failure, together with any
    parent folders made for it. An existing folder is updated in place, or, with
    `replace`, swapped for the new one only when it is complete.
    Raises ValueError (one line) when `path` cannot be a folder."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise ValueError(f"{path}: exists and is not a folder; choose another output folder")
    if path.is_dir() and not replace:
        yield path
        return
    made = [p for p in reversed(path.parents) if not p.exists()]
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.", dir=path.parent))
    except OSError as exc:
        for p in reversed(made):
            shutil.rmtree(p, ignore_errors=True)
        raise ValueError(f"{path}: cannot create the output folder ({exc.strerror or exc}); "
                         "choose a writable place") from None
    try:
        yield tmp
        if path.is_dir():
            old = Path(tempfile.mkdtemp(prefix=f".{path.name}.old.", dir=path.parent))
            path.rename(old / path.name)
            tmp.rename(path)
            shutil.rmtree(old, ignore_errors=True)
        else:
            tmp.rename(path)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        for p in reversed(made):
            shutil.rmtree(p, ignore_errors=True)
        raise


def solve_static(scene: Scene, solver: str = "auto", **options) -> StaticResult:
    """The static analysis of a scene to its full load on the model it asks for: with
    model.fidelity = "auto" the cheapest adequate model (taxel.analyses.accuracy.model_choice),
    else the model as given (`solve_model`; options: tagged_mesh, scale, newton_options).
    Raises fem's NewtonError or PressError where it stops short (`solve` returns that)."""
    if scene.model.fidelity == "auto" and options.get("tagged_mesh") is None:
        from taxel.analyses.accuracy.model_choice import choose
        return choose(scene, solver)
    return solve_model(scene, solver, **options)


def _stopped(scene: Scene, exc: NewtonError | PressError) -> StaticResult:
    """The last converged state of a static solve of `scene` that stopped short of its load
    with `exc` (its `.solution`), as a StaticResult whose `stop` gives the load asked for and
    why it stopped, and whose scene carries the load reached; `exc` is raised again where no
    state converged. Not a new solve to that load: a press depends on its path (the 2D probe
    example, frictionless, asked for 3 N stops past 1.62 N, and pressed to 1.62 N in one
    target stops at 1.27 N: benchmarks/stopped_press.py)."""
    if exc.solution is None:
        raise exc
    ld = scene.load
    key = "pressure" if ld.kind == "pressure" else "travel" if ld.travel is not None else "force"
    requested = getattr(ld, key)
    if isinstance(exc, NewtonError):
        reached, cause = exc.result.load_factors[-1] * requested, None
    else:
        last = exc.result.points[-1]
        reached, cause = (last.travel if key == "travel" else last.force), exc.cause
    return StaticResult(replace(scene, **{f"load.{key}": reached}), exc.solution,
                        yeoh=scene.model.silicone != "linear",
                        stop=Stop(requested, key, str(exc).splitlines()[0], cause))
