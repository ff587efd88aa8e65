"""Declarative parameter studies: one TOML file, cached, resumable, parallel.

A study names a base scene, the parameters to vary and how (grid, explicit
list, Latin hypercube), fixed overrides (`[overrides]`), and the outputs to keep:

    name = "fig-2-5"
    base = "thesis-pzt-single-2d"            # built-in example or a path (relative to this file)
    sampling = "grid"                        # grid (all combinations) | lhs
    outputs = ["voltage", "short_circuit_charge", "crosstalk", "max_strain"]

    [overrides]                              # fixed values, by dotted scene path
    "model.type" = "plane_stress"

    [[parameters]]
    path = ["array.silicone_above", "array.silicone_below"]   # one value for all the paths
    start = "0 mm"
    stop = "3 mm"
    step = "0.5 mm"

    [[parameters]]
    path = "array"                           # a table: merged into the scene at the path
    values = [{piezo = "PSI-5H4E", piezo_thickness = "0.127 mm"}, {piezo = "PVDF", piezo_thickness = "52 um"}]
    labels = ["PZT", "PVDF"]

Latin hypercube: sampling = "lhs", samples = N, seed = S, and each parameter a
range (start, stop); values drawn uniformly in each stratum (scipy.stats.qmc).

Results: studies.store (cache), studies.execute (running on Dask).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from itertools import product
from pathlib import Path
from typing import Any, Literal

from pydantic import Field, ValidationError, field_validator, model_validator

from taxel import units
from taxel.schema import Name, Strict, safe_name
from taxel.scene import EXAMPLES, Scene, SceneError, parse
from taxel.schema import one_line, read_toml, set_path

OUTPUTS = ("voltage", "short_circuit_charge", "crosstalk", "max_strain", "frequency_response")
BUILTIN = Path(__file__).parent / "builtin"


class StudyError(SceneError):
    """A study file that cannot be run; one line with the fix."""


class Parameter(Strict):
    path: str | list[str]
    label: str | None = None          # display name (default: the last path key)
    values: list[Any] | None = None
    labels: list[str] | None = None
    start: Any = None
    stop: Any = None
    step: Any = None
    num: int | None = Field(None, ge=2)
    tolerance: Any = None             # sampling = "tolerance": "0.1 mm" or "10 %" (studies.tolerance)
    distribution: Literal["normal", "uniform"] = "normal"
    nominal: Any = None               # default: the base scene's value at the (first) path

    @property
    def paths(self) -> list[str]:
        return [self.path] if isinstance(self.path, str) else list(self.path)

    @property
    def name(self) -> str:
        if self.label:
            return self.label
        return self.paths[0].split(".")[-1] if len(self.paths) == 1 else \
            "+".join(p.split(".")[-1] for p in self.paths)


class StudySpec(Strict):
    name: Name = "study"
    description: str = ""
    base: str
    sampling: Literal["grid", "lhs", "tolerance"] = "grid"
    samples: int | None = Field(None, ge=1)
    seed: int = 0                        # Latin hypercube: 0 to 2**32 - 1

    @field_validator("seed")
    @classmethod
    def _seed(cls, v):
        if not 0 <= v < 2 ** 32:
            raise ValueError(f"seed = {v}: use a whole number from 0 to {2 ** 32 - 1} (it seeds the Latin hypercube)")
        return v
    overrides: dict[str, Any] = {}       # fixed values, by dotted scene path
    parameters: list[Parameter] = Field(min_length=1)
    outputs: list[Literal[OUTPUTS]] = ["voltage", "short_circuit_charge", "crosstalk", "max_strain"]
    requirements: dict[str, str] = {}    # tolerance studies: output = ">= 0.7 V/N" (the yield)

    @model_validator(mode="after")
    def _check(self):
        if self.sampling in ("lhs", "tolerance") and not self.samples:
            raise ValueError(f"sampling = '{self.sampling}' needs samples = N")
        if self.requirements and self.sampling != "tolerance":
            raise ValueError("requirements: only a tolerance study (sampling = \"tolerance\") has a yield; "
                             "remove [requirements] or set sampling = \"tolerance\"")
        if self.requirements:
            from taxel.analyses.results.outputs import units_of
            from taxel.studies.requirements import parse_requirements
            parse_requirements(self.requirements, units_of("tolerance"))
        if self.sampling == "tolerance":
            for p in self.parameters:
                if p.tolerance is None:
                    raise ValueError(f"parameters '{p.name}': sampling = 'tolerance' needs tolerance = "
                                     "\"0.1 mm\" or \"10 %\"")
        names = [p.name for p in self.parameters]
        for n in names:
            if names.count(n) > 1:
                raise ValueError(f"two parameters are named '{n}'; give one a label = \"...\"")
        paths = [path for p in self.parameters for path in p.paths]
        for path in paths:
            if paths.count(path) > 1:
                raise ValueError(f"parameters: the path '{path}' is varied twice; vary each scene path in one "
                                 "parameter (list values, or link paths with path = [...])")
        return self


# --------------------------------------------------------------------------------------
# reading a study and expanding it into design points
# --------------------------------------------------------------------------------------

@dataclass
class Study:
    spec: StudySpec
    base: dict                      # the base scene as a TOML dict
    folder: Path                    # where the study file lives (for relative paths)

    def points(self) -> list[dict]:
        """Design points: {parameter name: value (as typed in the file or generated)}."""
        names = [p.name for p in self.spec.parameters]
        if self.spec.sampling == "tolerance":
            from taxel.studies.tolerance import sample
            spreads = self.spreads()
            x = sample(spreads, self.spec.samples, self.spec.seed)
            return [{n: s.text(v) for n, s, v in zip(names, spreads, row)} for row in x]
        axes = [_axis(p, self.spec) for p in self.spec.parameters]
        if self.spec.sampling == "grid":
            return [dict(zip(names, combo)) for combo in product(*axes)]
        from scipy.stats import qmc
        u = qmc.LatinHypercube(d=len(axes), seed=self.spec.seed).random(self.spec.samples)
        return [{n: ax(float(x)) for n, ax, x in zip(names, axes, row)} for row in u]

    def spreads(self) -> list:
        """The parameters' fabrication spreads (studies.tolerance.Spread) of a tolerance study."""
        from taxel.studies.tolerance import ToleranceError, spread
        base = self.base_data()
        out = []
        for p in self.spec.parameters:
            nominal = p.nominal if p.nominal is not None else get_value(base, p.paths[0])
            if nominal is None:                  # the scene's default
                from taxel.schema import to_data
                nominal = get_value(to_data(parse({**base, "name": "nominal"})), p.paths[0])
            try:
                out.append(spread(p.name, nominal, p.tolerance, p.distribution))
            except ToleranceError as exc:
                raise StudyError(str(exc)) from None
        return out

    def base_data(self) -> dict:
        """The base scene with the study's fixed overrides (no parameter applied)."""
        data = json.loads(json.dumps(self.base))
        for path, value in self.spec.overrides.items():
            set_value(data, path, value)
        return data

    def scene_data(self, point: dict) -> dict:
        data = self.base_data()
        for p in self.spec.parameters:
            for path in p.paths:
                set_value(data, path, _value(point[p.name]))
        return data


def _value(v):
    return v["value"] if isinstance(v, dict) and set(v) == {"label", "value"} else v


def _axis(p: Parameter, spec: StudySpec):
    """Values of one parameter (grid/list), or a map [0, 1) -> value (lhs)."""
    if p.values is not None:
        if not p.values:
            raise StudyError(f"parameters '{p.name}': values is empty; give at least one value")
        if p.labels is not None:
            if len(p.labels) != len(p.values):
                raise StudyError(f"parameters '{p.name}': {len(p.labels)} labels for {len(p.values)} values")
            vals = [{"label": lab, "value": v} for lab, v in zip(p.labels, p.values)]
        else:
            vals = list(p.values)
        if spec.sampling == "lhs":
            return lambda x: vals[min(int(x * len(vals)), len(vals) - 1)]
        return vals
    if p.start is None or p.stop is None:
        raise StudyError(f"parameters '{p.name}': give values = [...] or a range start/stop (and step or num)")
    (a, b), unit = _same_unit(p.name, p.start, p.stop)
    if spec.sampling == "lhs":
        return lambda x: _fmt(a + (b - a) * x, unit)
    if p.step is not None:
        (s,), _ = _same_unit(p.name, p.step, unit=unit)
        if s <= 0 or b < a:
            raise StudyError(f"parameters '{p.name}': empty range ({p.start} to {p.stop} by {p.step}); "
                             "use stop >= start and a positive step")
        n = int(math.floor((b - a) / s + 1e-9)) + 1
        _check_count(p, n)
        return [_fmt(a + i * s, unit) for i in range(n)]
    if p.num is None:
        raise StudyError(f"parameters '{p.name}': a range needs step = ... or num = N")
    if b < a:
        raise StudyError(f"parameters '{p.name}': empty range ({p.start} to {p.stop}); use stop >= start")
    _check_count(p, p.num)
    return [_fmt(a + (b - a) * i / (p.num - 1), unit) for i in range(p.num)]


MAX_POINTS = 100_000          # a study beyond this is refused before it starts
SECONDS_PER_POINT = 0.1      # the default 2D taxel (benchmarks/study_fig25.py): for the estimate


def _check_count(p: Parameter, n: float):
    if n > MAX_POINTS:
        raise StudyError(f"parameters '{p.name}': {n:.3g} values, more than the {MAX_POINTS} points a study "
                         f"may have (about {n * SECONDS_PER_POINT / 3600:.3g} h at {SECONDS_PER_POINT} s a point); "
                         "use a larger step or fewer values")


def _same_unit(name, *values, unit=None):
    """Magnitudes of quantities in one unit (that of the first, or `unit`)."""
    out = []
    for v in values:
        try:
            x, unit = units.in_unit(v, unit)
        except units.UnitError as exc:
            raise StudyError(f"parameters '{name}': {exc}") from None
        out.append(x)
    return out, unit


def _fmt(x, unit):
    x = round(x, 12)
    return f"{x:g} {unit}" if unit else x


def get_value(data: dict, path: str):
    """The value at a dotted path of a scene dict, or None."""
    node = data
    for key in path.split("."):
        if not isinstance(node, dict) or key not in node:
            return None
        node = node[key]
    return node


def set_value(data: dict, path: str, value):
    """taxel.scene.set_path, with a StudyError naming the path."""
    try:
        set_path(data, path, value)
    except KeyError:
        if path == "":
            raise StudyError("a parameter at the scene root (path = \"\") needs tables as values") from None
        raise StudyError(f"'{path}': a key on the way is not a table in the base scene") from None


def read_spec(path, builtin_dir: Path, spec_class, error, what: str):
    """(spec, base scene dict) of a study or optimization file, or a built-in one by
    name; every problem is one line through `error`."""
    path = Path(path)
    if not path.is_file():
        builtin = builtin_dir / f"{path}.toml"
        if not builtin.exists():
            names = ", ".join(sorted(p.stem for p in builtin_dir.glob("*.toml")))
            raise error(f"no {what} file '{path}' and no built-in one of that name; built-in: {names}")
        path = builtin
    data = read_toml(path, error)
    data.setdefault("name", safe_name(path.stem))
    try:
        spec = spec_class.model_validate(data)
    except ValidationError as err:
        raise error(one_line(err)) from None
    base_path = Path(spec.base)
    if not base_path.is_absolute():
        base_path = path.parent / base_path
    if not base_path.is_file():
        base_path = EXAMPLES / f"{spec.base}.toml"
    if not base_path.is_file():
        raise error(f"base = '{spec.base}': no such scene file or built-in example")
    base = read_toml(base_path, error)
    base.pop("name", None)
    return spec, base, path


def load_study(path) -> Study:
    spec, base, path = read_spec(path, BUILTIN, StudySpec, StudyError, "study")
    study = Study(spec, base, path.parent)
    known = set(Scene.model_fields)
    for p in spec.parameters:
        for dotted in p.paths:
            if dotted and dotted.split(".")[0] not in known:
                raise StudyError(f"parameters: unknown scene path '{dotted}'; it must start with one of "
                                 f"{', '.join(sorted(known))}")
    n = math.prod(len(_axis(p, spec)) for p in spec.parameters) if spec.sampling == "grid" else spec.samples
    if n > MAX_POINTS:
        raise StudyError(f"the study has {n:.3g} points, more than {MAX_POINTS} (about "
                         f"{n * SECONDS_PER_POINT / 3600:.3g} h at {SECONDS_PER_POINT} s a point); use fewer values")
    check_points(study)
    return study


CHECK_ALL = 2000      # points validated one by one before a run (a few ms each: pint reads every quantity)


def check_points(study: Study) -> None:
    """Validate the design points' scenes before anything runs, so that a run never
    starts on a study whose later points cannot be solved; the first invalid one is
    refused with one line naming the point and its values. Up to CHECK_ALL points
    every point is checked; beyond, every value of every parameter (with the other
    parameters at their first point's values), and the run stores any remaining
    invalid combination as failed (exit 1)."""
    points = study.points()
    if len(points) <= CHECK_ALL:
        candidates = list(enumerate(points))
    else:
        first, seen, candidates = points[0], set(), [(0, points[0])]
        for i, pt in enumerate(points):
            for name, v in pt.items():
                key = (name, json.dumps(v, sort_keys=True, default=str))
                if key not in seen:
                    seen.add(key)
                    candidates.append((i, {**first, name: v}))
    for i, pt in candidates:
        try:
            parse(study.scene_data(pt))
        except SceneError as exc:
            which = "first point" if i == 0 else f"point {i + 1} of {len(points)}"
            values = ", ".join(f"{k} = {_value(v)!r}" for k, v in pt.items())[:160]
            raise StudyError(f"the study's {which} ({values}) is not a valid scene: {exc}") from None


# The example under the study key reference (docs/reference/keys/study.md): a built-in study, whole.
KEY_EXAMPLES = {"the built-in study fig-2-5 (`taxel study run fig-2-5`)": (BUILTIN / "fig-2-5.toml").read_text(),
                "the built-in tolerance study thesis-pzt-tolerances (sampling, [requirements])":
                (BUILTIN / "thesis-pzt-tolerances.toml").read_text()}
