"""Checks of an optimization's [resolution], [robust] and [requirements] tables, made
when it is loaded: each problem is one line naming the key and the fix."""

from __future__ import annotations

from taxel.optimize.requirements import read
from taxel.optimize.resolution import NOISE_METRICS, band_hz, force_n, load_rig_of
from taxel.optimize.robust import ROBUST_METRICS, parts
from taxel.scene import Scene, SceneError, parse
from taxel.studies.requirements import RequirementError
from taxel.studies.tolerance import ToleranceError


def check_robust(problem, error) -> None:
    """Validate the tables of `problem` (optimize.spec.Optimization) and read its
    requirements into problem.requirements; raise `error` (one line) otherwise."""
    spec = problem.spec
    used = problem.used
    robust_used = sorted(set(ROBUST_METRICS) & used)
    if robust_used and spec.robust is None:
        raise error(f"{robust_used[0]} needs a [robust] table: percentile, samples, seed and "
                    "[[robust.parameters]] with path and tolerance")
    if "yield" in used and not spec.requirements:
        raise error("yield needs a [requirements] table, e.g. crosstalk = \"<= 8 %\"")
    for name, text in spec.requirements.items():
        if name in ROBUST_METRICS or name == "localization_error":
            raise error(f"requirements.{name}: a part's requirement must be one of sensitivity, crosstalk, "
                        f"max_strain, the geometric or the noise metrics")
        try:                             # the one grammar, its unit checked against the metric's
            r = read({name: text})[0]
        except RequirementError as exc:
            raise error(str(exc)) from None
        problem.requirements[name] = (r.op, r.bound)
    data = problem.scene_data(problem.x0)
    if spec.robust is not None:
        for p in spec.robust.parameters:
            if p.path.split(".")[0] not in Scene.model_fields:
                raise error(f"robust.parameters '{p.name}': unknown scene path '{p.path}'")
        names = [p.name for p in spec.robust.parameters]
        if len(set(names)) < len(names):
            raise error("robust.parameters: two parameters have the same name; give one a label = \"...\"")
        try:
            _, _, scenes = parts(spec.robust, data)
            parse({**scenes[0], "name": "part"})
        except (ToleranceError, SceneError) as exc:
            raise error(f"robust.{str(exc).splitlines()[0]}") from None
    if set(NOISE_METRICS) & (used | set(problem.requirements)):
        try:
            band_hz(spec.resolution)
            force_n(spec.resolution, parse({**data, "name": "start"}))
            load_rig_of(spec.resolution)
        except ValueError as exc:
            raise error(str(exc)) from None
