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

    [requirements]                                # metric = "<= value" or ">= value": the search obeys them
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
taxel.analyses.solves.at_readout; with it min_detectable_force is the chain's own, unless
[resolution] asks for a rig's),
tangent_sensitivity (the small-signal slope |dV/dF| there: equal to sensitivity on the
linear model; under a [press], optimize.probe), crosstalk (largest
neighbour-to-pressed voltage ratio), max_strain (largest
silicone strain), localization_error (the predicted rms position error of a press
over the array, m: the Cramer-Rao bound of taxel.analyses.surface.localization from the FEM
influence functions at the rig's white noise `noise`, default 1 mV on each taxel
peak; 9 more static solves per design for a 3-taxel row, kept in OUT/influence/),
coverage (the fraction of the surface where a press at `smallest_force` gives a taxel a
peak above 3 times the noise floor; the same solves: optimize.coverage),
and geometric ones without FEM: total_thickness (silicone above + piezo + below,
m), footprint (array width along x, m), gap (m), pitch (taxel width + gap, m).

[requirements] states what the sensor must meet (optimize.requirements): the
search's constraints (`searched`), the yield's spec and the answer's (the report
recommends the design meeting every requirement that is best by the objective). The
retired [constraints] table is refused with the lines to move.

Discretisation noise: the mesh is rebuilt for every design, so the objective
jitters at the level of the discretisation error's variation with geometry.
`optimize.front.noise` measures it (benchmarks/optimize_front.py: about 1e-4 relative on the
default 2D mesh for steps of 1e-3 of the range); the tolerance xtol = 0.02 of
the range and the local initial step (0.1) sit well above it.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Literal

import numpy as np
from pydantic import ConfigDict, Field, model_validator

from taxel.optimize import driver
from taxel.optimize.coverage import INFLUENCE_METRICS, influence_metrics
from taxel.optimize.metrics import METRICS, geometry
from taxel.optimize.probe import PROBE_METRICS, ProbePress, press_scene, stored_press
from taxel.optimize.requirements import LIMITS

READOUT_METRICS = ("readout_sensitivity", "readout_crosstalk")   # with a [readout] in the base scene
from taxel.optimize.resolution import NOISE_METRICS, Resolution
from taxel.optimize.warm import WARM_METRICS, warm_metrics
from taxel.optimize.robust import ROBUST_METRICS, Robust
from taxel import units as U
from taxel.schema import Fraction, Name, Strict
from taxel.scene import Scene, SceneError, parse
from taxel.studies.evaluate import evaluate_safely
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
    pareto: Pareto | None = None
    algorithm: Algorithm = Algorithm()
    noise: Any = "1 mV"                       # coverage, localization_error: white noise on each taxel peak
    smallest_force: Any = None    # coverage, localization_error are judged at it, e.g. "0.2 N" (default: the load's)
    resolution: Resolution = Resolution()     # the noise metrics' rig, band and force (optimize.resolution)
    robust: Robust | None = None              # the robust metrics' tolerances (optimize.robust)
    requirements: dict[Literal[METRICS], str] = {}   # the answer's and the yield's spec, e.g. coverage = ">= 100 %"
    press: ProbePress | None = None                # the rig's probe press as the model (optimize.probe)

    @model_validator(mode="before")
    @classmethod
    def _retired(cls, data):
        if isinstance(data, dict) and "constraints" in data:
            table = data["constraints"] if isinstance(data["constraints"], dict) else {}
            lines = "; ".join(f"{k} = \"{v}\"" for k, v in table.items()) or "its lines"
            raise ValueError(f"[constraints]: the search obeys [requirements] alone (one table); move {lines} "
                             "under [requirements]")
        return data

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
        if set(INFLUENCE_METRICS) & self.used and metrics["sensitivity"] is not None:
            got = self.influence_metrics(x, metrics)
            metrics.update({k: got[k] for k in INFLUENCE_METRICS})
        if set(ROBUST_METRICS) & self.used:
            from taxel.optimize.robust import robust_metrics
            metrics.update(robust_metrics(self.spec.robust, self.requirements, data, self.point))
        return metrics

    def point(self, data: dict, params: dict) -> dict:
        """The metrics of one scene (a design or one of its parts): geometry, FEM (stored), noise."""
        scene = parse({**data, "name": "design"})
        metrics = {**geometry(scene), **dict.fromkeys(("sensitivity", "tangent_sensitivity", "crosstalk", "max_strain",
                                                       *INFLUENCE_METRICS, *NOISE_METRICS, *READOUT_METRICS,
                                                       *WARM_METRICS))}
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
        named = result.get("outputs") or {}          # a scene naming a readout: its numbers (analyses.solves.at_readout)
        metrics.update({k: named.get(k) for k in (*READOUT_METRICS, "min_detectable_force") if named.get(k) is not None})
        if set(NOISE_METRICS) & (self.used | set(self.requirements)):
            from taxel.optimize.resolution import noise_metrics
            metrics.update(noise_metrics(scene, result.get("outputs") or {}, self.spec.resolution, self.rig))
        if set(WARM_METRICS) & (self.used | set(self.requirements)):     # solved with the scene's [warm_touch], or now
            metrics.update({k: named[k] for k in WARM_METRICS if k in named} or warm_metrics(scene, self.rig))
        return metrics

    def influence_metrics(self, x, metrics: dict | None = None) -> dict:
        """coverage and localization_error of design x and how they were made (optimize.coverage),
        at smallest_force against the design's readout's noise floor (its min_detectable_force in
        `metrics`), else `noise`."""
        scene = parse({**self.scene_data(x), "name": "design"})
        mdf = (metrics or {}).get("min_detectable_force")
        return influence_metrics(scene, self.smallest_force_N, self.noise_V, mdf, self.out)

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

    @property
    def smallest_force_N(self) -> float:
        """The force coverage and localization_error are judged at (N): smallest_force, else the base load's."""
        if self.spec.smallest_force is not None:
            return magnitude(self.spec.smallest_force, "N", "smallest_force")[0]
        return float(parse({**self.scene_data(self.x0), "name": "start"}).load.force or 1.0)


def magnitude(v, unit=None, what=""):
    """(SI magnitude, unit) of a bound or start value; one-line OptimizeError otherwise."""
    try:
        return U.in_unit(v, unit or None)
    except U.UnitError as exc:
        raise OptimizeError(f"{what}: {exc}") from None


def load_optimization(path, out: Path | None = None) -> Optimization:
    from taxel.optimize.checks import check_feasible, check_robust, numeric_path
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
    cons = searched(spec.requirements, OptimizeError)
    problem = Optimization(spec, base, np.array(lo), np.array(hi), np.array(x0), units, cons, out)
    if spec.press is not None:
        from taxel.optimize.probe import check as check_press
        check_press(spec.press, OptimizeError)
        other = problem.used - {*PROBE_METRICS, *LIMITS}
        if other:
            raise OptimizeError(f"[press]: {sorted(other)[0]} is not a press metric; under a probe press use "
                                "sensitivity, tangent_sensitivity, crosstalk, max_strain or the geometric metrics")
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
    if spec.smallest_force is not None and not magnitude(spec.smallest_force, "N", "smallest_force")[0] > 0:
        raise OptimizeError(f"smallest_force: must be a positive force, got {spec.smallest_force!r}; "
                            "e.g. smallest_force = \"0.2 N\"")
    if {"crosstalk", *INFLUENCE_METRICS} & (set(spec.objective.values()) | {c[0] for c in cons} |
                                            set(spec.requirements)) or spec.pareto:
        modelled = None if scene.array is None else \
            scene.array.rows * scene.array.cols if scene.model.type == "3d" else scene.array.cols
        if not modelled or modelled < 2:      # a 2D model holds the row through the pressed taxel
            raise OptimizeError("crosstalk, coverage and localization_error need at least two modelled taxels in "
                                "the base scene (array.cols >= 2, or rows x cols >= 2 in 3d)")
    if spec.pareto and spec.objective.get("maximize") != "sensitivity":
        raise OptimizeError("[pareto] needs objective maximize = \"sensitivity\" (the front is sensitivity "
                            "vs crosstalk)")
    check_feasible(problem, OptimizeError)
    return problem


def searched(requirements: dict, error=OptimizeError) -> list[tuple[str, str, float]]:
    """The optimizer's constraints: every [requirements] line (optimize.requirements.read, its
    bound checked against what the metric can reach), but coverage and localization_error,
    which take 9 more solves per design and are judged after the search on the designs the
    answer reaches (optimize.coverage.judge_lazily)."""
    from taxel.optimize.requirements import RequirementError, read
    try:
        reqs = read(requirements)
    except RequirementError as exc:
        raise error(str(exc)) from None
    return [(r.metric, r.op, r.bound) for r in reqs if r.metric not in INFLUENCE_METRICS]


def optimize(problem: Optimization, constraints=None, max_evals=None) -> driver.Result:
    """One run: the spec's objective under its constraints (plus `constraints`)."""
    (sense, metric), = problem.spec.objective.items()
    alg = problem.spec.algorithm
    return driver.minimize(problem.evaluate, problem.x0, list(zip(problem.lo, problem.hi)), metric,
                           problem.constraints + list(constraints or []), maximize=sense == "maximize",
                           global_alg=None if alg.global_ == "none" else alg.global_, local_alg=alg.local,
                           max_evals=max_evals or alg.max_evaluations, xtol=alg.xtol)


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

[requirements]                     # the search obeys them all; a good part meets all but the yield
yield = ">= 0.9"
crosstalk = "<= 8 %"

[resolution]                       # the noise metrics' chain
rig = "thesis-bench"
band = ["1 Hz", "100 Hz"]          # default: the scene's readout.band (1-300 Hz)
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
