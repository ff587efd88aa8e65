"""Design optimization of a taxel array: an optimization TOML, evaluated by the FEM
through the study machinery (every design is a study point: cached in the same
SQLite store and reused by later runs).

    name = "thesis-pzt-front"
    base = "thesis-pzt-3x3-2d"
    reference = {silicone_above = "1 mm", silicone_below = "1 mm", gap = "3 mm"}   # marked on plots

    [variables]                                   # name = {path, min, max, start}
    silicone_above = {path = "array.silicone_above", min = "0.2 mm", max = "1.8 mm", start = "1 mm"}
    silicone_below = {path = "array.silicone_below", min = "0.2 mm", max = "1.8 mm", start = "1 mm"}
    gap = {path = "array.gap", min = "1 mm", max = "5 mm", start = "3 mm"}

    [objective]
    maximize = "sensitivity"                      # or minimize = "crosstalk"

    [constraints]                                 # metric = "<= value" or ">= value"
    total_thickness = "<= 2 mm"

    [pareto]                                      # optional: the epsilon-constraint front
    points = 7                                    # maximize sensitivity s.t. crosstalk <= eps_k

    [press]                                       # optional: the rig's probe press as the model
    radius = "2 mm"                               # (optimize.probe: probe, force, silicone law)

    [algorithm]
    global = "DIRECT"                             # DIRECT | ISRES | none
    local = "COBYLA"                              # COBYLA | BOBYQA | SBPLX
    max_evaluations = 40
    xtol = 0.02                                   # in normalised variables (see the noise note)

Metrics: sensitivity (|V| of the pressed taxel per newton, open circuit, V/N),
readout_sensitivity and readout_crosstalk (through the base scene's [readout] chain,
taxel.analyses.at_readout; with it min_detectable_force is the chain's own, unless
[resolution] asks for a rig's),
tangent_sensitivity (the small-signal slope |dV/dF| there: equal to sensitivity on the
linear model; under a [press], optimize.probe), crosstalk (largest
neighbour-to-pressed voltage ratio), max_strain (largest
silicone strain), localization_error (the predicted rms position error of a press
over the array, m: the Cramer-Rao bound of taxel.analyses.localization from the FEM
influence functions at the rig's white noise `noise`, default 1 mV on each taxel
peak; 9 more static solves per design for a 3-taxel row, kept in OUT/influence/),
and geometric ones without FEM: total_thickness (silicone above + piezo + below,
m), footprint (array width along x, m), gap (m), pitch (taxel width + gap, m).

[requirements] states what the sensor must meet (optimize.requirements): the
yield's spec and the answer's (the report recommends the design meeting every
requirement with the largest margin).

Discretisation noise: the mesh is rebuilt for every design, so the objective
jitters at the level of the discretisation error's variation with geometry.
`noise()` measures it (benchmarks/optimize_front.py: about 1e-4 relative on the
default 2D mesh for steps of 1e-3 of the range); the tolerance xtol = 0.02 of
the range and the local initial step (0.1) sit well above it.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Literal

import numpy as np
from pydantic import ConfigDict, Field, model_validator

from taxel.optimize import driver
from taxel.optimize.metrics import METRIC_TABLE, METRICS, PLAIN
from taxel.optimize.probe import PROBE_METRICS, ProbePress, press_scene, stored_press
from taxel.optimize.requirements import LIMITS

READOUT_METRICS = ("readout_sensitivity", "readout_crosstalk")   # with a [readout] in the base scene
from taxel.optimize.resolution import NOISE_METRICS, Resolution
from taxel.optimize.robust import ROBUST_METRICS, Robust
from taxel.optimize.result import FrontRun
from taxel import units as U
from taxel.schema import Fraction, Name, Strict, dimensionless_value
from taxel.scene import Scene, SceneError, parse
from taxel.studies.evaluate import evaluate_safely
from taxel.studies.execute import local_cluster
from taxel.studies.spec import read_spec, set_value
from taxel.studies.store import Store

BUILTIN = Path(__file__).parent / "builtin"


class OptimizeError(SceneError):
    """An optimization file that cannot be run; one line with the fix."""


class Variable(Strict):
    path: str
    min: Any
    max: Any
    start: Any = None


class Algorithm(Strict):
    global_: Literal["DIRECT", "ISRES", "none"] = Field("DIRECT", alias="global")
    local: Literal["COBYLA", "BOBYQA", "SBPLX"] = "COBYLA"
    max_evaluations: int = Field(40, ge=2, le=10000)
    xtol: Fraction = 0.02


class Pareto(Strict):
    points: int = Field(7, ge=2, le=50)


class OptimizationSpec(Strict):
    model_config = ConfigDict(populate_by_name=True)
    name: Name = "optimization"
    description: str = ""
    base: str
    reference: dict[str, Any] = {}
    variables: dict[str, Variable] = Field(min_length=1)
    objective: dict[Literal["maximize", "minimize"], Literal[METRICS]]
    constraints: dict[Literal[METRICS], str] = {}
    pareto: Pareto | None = None
    algorithm: Algorithm = Algorithm()
    noise: Any = "1 mV"                       # localization_error: white noise on each taxel peak
    resolution: Resolution = Resolution()     # the noise metrics' rig, band and force (optimize.resolution)
    robust: Robust | None = None              # the robust metrics' tolerances (optimize.robust)
    requirements: dict[Literal[METRICS], str] = {}   # the yield's spec, e.g. crosstalk = "<= 8 %"
    press: ProbePress | None = None                # the rig's probe press as the model (optimize.probe)

    @model_validator(mode="after")
    def _check(self):
        if len(self.objective) != 1:
            raise ValueError("objective: give exactly one of maximize = ... or minimize = ...")
        return self


@dataclass
class Optimization:
    spec: OptimizationSpec
    base: dict
    lo: np.ndarray
    hi: np.ndarray
    x0: np.ndarray
    units: list[str]
    constraints: list[tuple[str, str, float]]
    out: Path | None = None
    requirements: dict = field(default_factory=dict)     # metric -> (op, SI bound)

    @property
    def names(self):
        return list(self.spec.variables)

    def scene_data(self, x) -> dict:
        data = json.loads(json.dumps(self.base))
        for (name, var), value, unit in zip(self.spec.variables.items(), x, self.units):
            set_value(data, var.path, f"{value:.9g} {unit}" if unit else float(value))
        return data

    def evaluate(self, x) -> dict:
        """All metrics of design x, from the store when this design was solved before; the
        robust ones (optimize.robust) when the spec asks for them."""
        data = self.scene_data(x)
        metrics = self.point(data, dict(zip(self.names, map(float, x))))
        if "localization_error" in self.used and metrics["sensitivity"] is not None:
            metrics["localization_error"] = _localization_error(parse({**data, "name": "design"}), self.noise_V,
                                                                self.out)
        if set(ROBUST_METRICS) & self.used:
            from taxel.optimize.robust import robust_metrics
            metrics.update(robust_metrics(self.spec.robust, self.requirements, data, self.point))
        return metrics

    def point(self, data: dict, params: dict) -> dict:
        """The metrics of one scene (a design or one of its parts): geometry, FEM (stored), noise."""
        scene = parse({**data, "name": "design"})
        metrics = {**_geometry(scene), **dict.fromkeys(("sensitivity", "tangent_sensitivity", "crosstalk", "max_strain",
                                                        "localization_error", *NOISE_METRICS, *READOUT_METRICS))}
        if self.spec.press is not None:
            return {**metrics, **self._pressed(data, params)}
        outputs = ("voltage", "crosstalk", "max_strain")
        if self.out is None:
            status, result, _ = evaluate_safely(data, outputs)
        else:
            store = Store(self.out)
            try:
                status, result, _ = store.get_or_compute(data, outputs, params)
            finally:
                store.close()
        if status != "done":
            return metrics
        v = result["voltage"].get(result["pressed"])
        metrics.update(sensitivity=abs(v) / result["force"] if v is not None else None,
                       tangent_sensitivity=abs(v) / result["force"] if v is not None else None,   # linear: V ~ F
                       crosstalk=result.get("crosstalk"), max_strain=result.get("max_strain"))
        named = result.get("outputs") or {}          # a scene naming a readout: its numbers (analyses.at_readout)
        metrics.update({k: named.get(k) for k in (*READOUT_METRICS, "min_detectable_force") if named.get(k) is not None})
        if set(NOISE_METRICS) & (self.used | set(self.requirements)):
            from taxel.optimize.resolution import noise_metrics
            metrics.update(noise_metrics(scene, result.get("outputs") or {}, self.spec.resolution, self.rig))
        return metrics

    def _pressed(self, data: dict, params: dict) -> dict:
        """The press metrics of one design under the [press] probe (optimize.probe), stored."""
        store = Store(self.out) if self.out is not None else None
        try:
            status, result, _ = stored_press(store, press_scene(data, self.spec.press), self.spec.press, params)
        finally:
            if store is not None:
                store.close()
        if status != "done":
            return {}
        return {k: result[k] for k in PROBE_METRICS}

    def linear(self) -> "Optimization":
        """The same problem on the cheap level: the base scene's own load on linear silicone
        (no [press]); same store folder, so its designs are the linear front's."""
        return replace(self, spec=self.spec.model_copy(update={"press": None}))

    @property
    def rig(self):
        """The [resolution] rig (loaded once)."""
        if not hasattr(self, "_rig"):
            from taxel.optimize.resolution import load_rig_of
            self._rig = load_rig_of(self.spec.resolution)
        return self._rig

    @property
    def used(self) -> set[str]:
        return set(self.spec.objective.values()) | {c[0] for c in self.constraints}

    @property
    def noise_V(self) -> float:
        return magnitude(self.spec.noise, "V", "noise")[0]


def _localization_error(scene, noise_V: float, out: Path | None) -> float | None:
    """The design's localization_error (m); each press position a point of the OUT/influence store."""
    from taxel.schema import to_data
    from taxel.analyses.localization import localization_error
    store = Store(out / "influence") if out is not None else None

    def solve(s):
        data = to_data(s)
        status, result, error = store.get_or_compute(data, ("voltage",)) if store is not None else \
            evaluate_safely(data, ("voltage",))
        if status != "done":
            raise RuntimeError(error)
        return result["voltage"]
    try:
        return localization_error(scene, noise_V, solve).rms_m
    except (RuntimeError, ValueError):
        return None
    finally:
        if store is not None:
            store.close()


def _geometry(scene) -> dict:
    a = scene.array
    return {"total_thickness": a.silicone_above + a.piezo_thickness + a.silicone_below,
            "footprint": a.cols * a.taxel_width + (a.cols - 1) * a.gap + 2 * a.margin, "gap": a.gap,
            "pitch": a.taxel_width + a.gap}


def magnitude(v, unit=None, what=""):
    """(SI magnitude, unit) of a bound or start value; one-line OptimizeError otherwise."""
    try:
        return U.in_unit(v, unit or None)
    except U.UnitError as exc:
        raise OptimizeError(f"{what}: {exc}") from None


def load_optimization(path, out: Path | None = None) -> Optimization:
    spec, base, path = read_spec(path, BUILTIN, OptimizationSpec, OptimizeError, "optimization")
    lo, hi, x0, units = [], [], [], []
    for name, var in spec.variables.items():
        if var.path.split(".")[0] not in Scene.model_fields:
            raise OptimizeError(f"variables.{name}: unknown scene path '{var.path}'")
        problem = numeric_path(var.path)
        if problem:
            raise OptimizeError(f"variables.{name}: path = '{var.path}' {problem}; an optimization variable "
                                "varies a number (a length such as array.gap, a force); vary names in a study")
        a, unit = magnitude(var.min, what=f"variables.{name}.min")
        b, _ = magnitude(var.max, unit, f"variables.{name}.max")
        if not b > a:
            raise OptimizeError(f"variables.{name}: empty bounds (min {var.min} >= max {var.max}); use min < max")
        s = magnitude(var.start, unit, f"variables.{name}.start")[0] if var.start is not None else (a + b) / 2
        if not a <= s <= b:
            raise OptimizeError(f"variables.{name}: start {var.start} is outside [{var.min}, {var.max}]")
        lo.append(a), hi.append(b), x0.append(s), units.append(unit)
    cons = []
    for metric, text in spec.constraints.items():
        text = text.strip()
        op = text[:2]
        if op not in ("<=", ">="):
            raise OptimizeError(f"constraints.{metric}: write \"<= value\" or \">= value\", got {text!r}")
        unit = "" if METRIC_TABLE[metric].unit in PLAIN else METRIC_TABLE[metric].unit
        value = text[2:].strip()
        if unit:
            bound = magnitude(value, unit, f"constraints.{metric}")[0]
        else:
            try:
                bound = dimensionless_value(value, "ratio")
            except ValueError:
                raise OptimizeError(f"constraints.{metric}: {value!r} is not a number; write e.g. \"<= 0.05\" "
                                    "or \"<= 5 %\"") from None
        if not math.isfinite(bound):
            raise OptimizeError(f"constraints.{metric}: the bound {value!r} is not a finite number")
        cons.append((metric, op, bound))
    problem = Optimization(spec, base, np.array(lo), np.array(hi), np.array(x0), units, cons, out)
    if spec.press is not None:
        from taxel.optimize.probe import check as check_press
        check_press(spec.press, OptimizeError)
        other = problem.used - {*PROBE_METRICS, *LIMITS}
        if other:
            raise OptimizeError(f"[press]: {sorted(other)[0]} is not a press metric; under a probe press use "
                                "sensitivity, tangent_sensitivity, crosstalk, max_strain or the geometric metrics")
    from taxel.optimize.checks import check_robust
    check_robust(problem, OptimizeError)
    try:
        scene = parse({**problem.scene_data(problem.x0), "name": "start"})
    except SceneError as exc:
        raise OptimizeError(f"the starting design is not a valid scene: {exc}") from None
    asked = sorted(set(READOUT_METRICS) & (problem.used | set(problem.requirements)))
    if asked and scene.readout.circuit == "open":
        raise OptimizeError(f"{asked[0]} needs a readout in the base scene '{spec.base}': add [readout] circuit = "
                            "\"charge_amplifier\" (or \"resistor\") to it")
    if not magnitude(spec.noise, "V", "noise")[0] > 0:
        raise OptimizeError(f"noise: the rig's white noise must be positive, got {spec.noise!r}; e.g. noise = \"1 mV\"")
    if {"crosstalk", "localization_error"} & set(list(spec.objective.values()) + [c[0] for c in cons]) or spec.pareto:
        modelled = None if scene.array is None else \
            scene.array.rows * scene.array.cols if scene.model.type == "3d" else scene.array.cols
        if not modelled or modelled < 2:      # a 2D model holds the row through the pressed taxel
            raise OptimizeError("crosstalk and localization_error need at least two modelled taxels in the base "
                                "scene (array.cols >= 2, or rows x cols >= 2 in 3d)")
    if spec.pareto and spec.objective.get("maximize") != "sensitivity":
        raise OptimizeError("[pareto] needs objective maximize = \"sensitivity\" (the front is sensitivity "
                            "vs crosstalk)")
    _check_feasible(problem)
    return problem


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


def _check_feasible(problem: Optimization):
    """Geometric constraints that no design within the bounds can meet: say so now."""
    corners = [problem.lo + (problem.hi - problem.lo) * np.array(c)
               for c in np.ndindex(*(2,) * len(problem.lo))]
    for metric, op, bound in problem.constraints:
        if metric not in LIMITS:
            continue
        vals = [_geometry(parse({**problem.scene_data(x), "name": "c"}))[metric] for x in corners]
        best = min(vals) if op == "<=" else max(vals)
        if (op == "<=" and best > bound) or (op == ">=" and best < bound):
            raise OptimizeError(f"constraints.{metric} {op} {bound:g} cannot be met within the variable bounds "
                                f"(best possible {best:g}); widen the bounds or relax the constraint")


def optimize(problem: Optimization, constraints=None, max_evals=None) -> driver.Result:
    """One run: the spec's objective under its constraints (plus `constraints`)."""
    (sense, metric), = problem.spec.objective.items()
    alg = problem.spec.algorithm
    return driver.minimize(problem.evaluate, problem.x0, list(zip(problem.lo, problem.hi)), metric,
                           problem.constraints + list(constraints or []), maximize=sense == "maximize",
                           global_alg=None if alg.global_ == "none" else alg.global_, local_alg=alg.local,
                           max_evals=max_evals or alg.max_evaluations, xtol=alg.xtol)


def _front_run(problem_path, out, eps, max_evals):
    """One epsilon-constraint run (on a Dask worker): maximize sensitivity s.t. crosstalk <= eps."""
    p = load_optimization(problem_path, Path(out))
    cons = [("crosstalk", "<=", eps)] if eps is not None else []
    return FrontRun(eps, optimize(p, cons, max_evals))


def front(problem: Optimization, problem_path, workers=2) -> list[FrontRun]:
    """Sensitivity vs crosstalk front by epsilon-constraint: first the unconstrained
    maximum of sensitivity (its crosstalk c_max) and the minimum of crosstalk
    (c_min), then maximize sensitivity with crosstalk <= eps_k for eps_k evenly
    between; the runs are spread over Dask workers (each writes its evaluations
    to the shared store)."""
    n = problem.spec.pareto.points
    alg = problem.spec.algorithm
    best = optimize(problem)
    lowest = driver.minimize(problem.evaluate, problem.x0, list(zip(problem.lo, problem.hi)), "crosstalk",
                             problem.constraints, global_alg=None if alg.global_ == "none" else alg.global_,
                             local_alg=alg.local, max_evals=alg.max_evaluations, xtol=alg.xtol)
    c_hi, c_lo = best.metrics["crosstalk"], lowest.metrics["crosstalk"]
    eps = list(np.linspace(c_lo, c_hi, n)[1:-1])
    return [FrontRun(c_lo, lowest)] + _spread(problem_path, problem.out, eps, alg.max_evaluations, workers) + \
        [FrontRun(c_hi, best)]


def _spread(problem_path, out, eps, max_evals, workers):
    if workers <= 1:
        return [_front_run(problem_path, out, e, max_evals) for e in eps]
    from dask.distributed import Client
    cluster = local_cluster(workers)
    client = Client(cluster)
    try:
        futs = [client.submit(_front_run, str(problem_path), str(out), e, max_evals, pure=False) for e in eps]
        return client.gather(futs)
    finally:
        client.close()
        cluster.close()


def noise(problem: Optimization, variable: str, x=None, rel_steps=(1e-4, 3e-4, 1e-3, 3e-3)):
    """Discretisation noise of the metrics along one variable: the scatter of
    f(x + h e_i) about the straight line through the neighbours, relative."""
    x = problem.x0.copy() if x is None else np.asarray(x, float)
    i = problem.names.index(variable)
    span = problem.hi[i] - problem.lo[i]
    out = {}
    for h in rel_steps:
        xs = [x.copy() for _ in range(3)]
        for k, d in enumerate((-1, 0, 1)):
            xs[k][i] = x[i] + d * h * span
        vals = [problem.evaluate(v)["sensitivity"] for v in xs]
        out[h] = abs(vals[1] - 0.5 * (vals[0] + vals[2])) / abs(vals[1])
    return out


# The example under the optimization key reference (docs/reference/keys/optimization.md): a built-in one, whole.
KEY_EXAMPLES = {"the built-in optimization thesis-pzt-front (`taxel optimize thesis-pzt-front`)":
                (BUILTIN / "thesis-pzt-front.toml").read_text(),
                "the built-in probe front thesis-pzt-probe-front ([press])":
                (BUILTIN / "thesis-pzt-probe-front.toml").read_text(),
                "a robust optimum ([robust], [requirements], [resolution], noise)": """\
# the thesis PZT array's robust optimum: the 5th percentile of sensitivity under fabrication
# spread, at a yield of at least 90 % (docs/guide/noise-and-tolerances.md)
base = "thesis-pzt-3x3-2d"
noise = "1 mV"                     # localization_error: white noise on each taxel peak

[variables]
silicone_above = {path = "array.silicone_above", min = "0.2 mm", max = "1.8 mm", start = "1 mm"}
gap = {path = "array.gap", min = "1 mm", max = "5 mm", start = "3 mm"}

[objective]
maximize = "robust_sensitivity"

[constraints]
yield = ">= 0.9"

[requirements]                     # what a good part is (the yield's spec)
crosstalk = "<= 8 %"

[resolution]                       # the noise metrics' chain
rig = "thesis-bench"
band = ["1 Hz", "100 Hz"]
force = "10 mN"

[robust]
percentile = 5
samples = 16                       # parts per design
seed = 0

[[robust.parameters]]
path = "array.silicone_above"
tolerance = "0.1 mm"
distribution = "uniform"
"""}
