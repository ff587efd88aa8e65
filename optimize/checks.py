"""Checks of an optimization's [resolution], [robust] and [requirements] tables, made
when it is loaded: each problem is one line naming the key and the fix."""

from __future__ import annotations

import numpy as np

from taxel.optimize.coverage import INFLUENCE_METRICS
from taxel.optimize.metrics import geometry
from taxel.optimize.requirements import LIMITS, read
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
    if "yield" in used and not set(spec.requirements) - set(ROBUST_METRICS):
        raise error("yield needs a part's requirement under [requirements], e.g. crosstalk = \"<= 8 %\"")
    for name, text in spec.requirements.items():
        if name in INFLUENCE_METRICS and "yield" in used:
            raise error(f"requirements.{name}: the yield counts parts on their own static solves, and {name} "
                        "takes 9 more per part; judge it on the design (drop the yield) or drop this requirement")
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


def numeric_path(path: str) -> str | None:
    """None when the dotted scene path ends at a number (a quantity, a float or an
    int field of the scene schema, or a user material's constant); else what it is."""
    import types
    import typing
    from pydantic import BaseModel
    model, keys = Scene, path.split(".")
    for i, key in enumerate(keys):
        field = model.model_fields.get(key) if model is not None else None
        if field is None:
            if model is None:
                return None
            return f"is not in the scene ('{key}' is not a key of {'.'.join(keys[:i]) or 'the scene'})"
        ann = field.annotation
        args = [a for a in typing.get_args(ann) if a is not type(None)] \
            if typing.get_origin(ann) in (typing.Union, types.UnionType) else [ann]
        ann = args[0] if len(args) == 1 else ann
        if isinstance(ann, type) and issubclass(ann, BaseModel):
            model = ann
            continue
        rest = keys[i + 1:]
        if key == "materials":          # materials.NAME.CONSTANT: a user material's SI number
            return None if len(rest) == 2 and rest[1] != "kind" else \
                "is not a material constant (materials.NAME.CONSTANT, e.g. materials.gel.E)"
        if rest:
            return f"goes inside '{'.'.join(keys[:i + 1])}', which is not a table"
        if ann is int:
            return "holds a whole number (a count), which a continuous optimizer cannot vary"
        if ann is float or (typing.get_origin(ann) is typing.Annotated and typing.get_args(ann)[0] is float):
            return None
        return f"is not a number (it holds {_describe(ann)})"
    return "is a table, not a number"


def _describe(ann) -> str:
    import typing
    if ann is str:
        return "a name"
    if typing.get_origin(ann) is typing.Literal:
        return "one of " + ", ".join(map(repr, typing.get_args(ann)))
    if ann is bool:
        return "true or false"
    return "a list or a table" if typing.get_origin(ann) in (tuple, list, dict) else str(ann)


def check_feasible(problem, error) -> None:
    """Geometric constraints that no design within the bounds can meet: say so now (`error`, one line)."""
    corners = [problem.lo + (problem.hi - problem.lo) * np.array(c)
               for c in np.ndindex(*(2,) * len(problem.lo))]
    for metric, op, bound in problem.constraints:
        if metric not in LIMITS:
            continue
        vals = [geometry(parse({**problem.scene_data(x), "name": "c"}))[metric] for x in corners]
        best = min(vals) if op == "<=" else max(vals)
        if (op == "<=" and best > bound) or (op == ">=" and best < bound):
            raise error(f"requirements.{metric} {op} {bound:g} cannot be met within the variable bounds "
                                f"(best possible {best:g}); widen the bounds or relax the constraint")
