"""Declarative parameter studies: one TOML file, cached, resumable, parallel.

A study names a base scene, the parameters to vary and how (grid, explicit
list, Latin hypercube), fixed overrides ("fidelity"), and the outputs to keep:

    name = "fig-2-5"
    base = "thesis-pzt-single-2d"            # built-in example or a path (relative to this file)
    sampling = "grid"                        # grid (all combinations) | lhs
    outputs = ["voltage", "charge", "crosstalk", "max_strain"]

    [fidelity]                               # fixed overrides, by dotted scene path
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

Each design point is a pure function of its scene: its key is the SHA-256 of the
validated scene (canonical JSON) and of the code version (a hash of the fem,
meshing and studies sources). Results live in an SQLite database in the study
folder (`results.sqlite`): one row per key, written in one transaction when the
point finishes, so an interrupted run (Ctrl-C, kill -9, power loss) loses at
most the points in flight and never stores one twice; a rerun skips every
finished point. Failed points are stored with their error; `retry_failed`
reruns them.
"""

from __future__ import annotations

import hashlib
import json
import math
import sqlite3
import time
import tomllib
from dataclasses import dataclass
from functools import cache
from itertools import product
from pathlib import Path
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from studies.scene import EXAMPLES, SceneError, _one_line, _ureg, parse

OUTPUTS = ("voltage", "charge", "crosstalk", "max_strain", "frequency_response")
BUILTIN = Path(__file__).parent / "builtin"


class StudyError(SceneError):
    """A study file that cannot be run; one line with the fix."""


class Parameter(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)
    path: str | list[str]
    label: str | None = None          # display name (default: the last path key)
    values: list[Any] | None = None
    labels: list[str] | None = None
    start: Any = None
    stop: Any = None
    step: Any = None
    num: int | None = Field(None, ge=2)

    @property
    def paths(self) -> list[str]:
        return [self.path] if isinstance(self.path, str) else list(self.path)

    @property
    def name(self) -> str:
        if self.label:
            return self.label
        return self.paths[0].split(".")[-1] if len(self.paths) == 1 else \
            "+".join(p.split(".")[-1] for p in self.paths)


class StudySpec(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)
    name: str = "study"
    description: str = ""
    base: str
    sampling: Literal["grid", "lhs"] = "grid"
    samples: int | None = Field(None, ge=1)
    seed: int = 0
    fidelity: dict[str, Any] = {}
    parameters: list[Parameter] = Field(min_length=1)
    outputs: list[Literal[OUTPUTS]] = ["voltage", "charge", "crosstalk", "max_strain"]

    @model_validator(mode="after")
    def _check(self):
        if self.sampling == "lhs" and not self.samples:
            raise ValueError("sampling = 'lhs' needs samples = N")
        names = [p.name for p in self.parameters]
        for n in names:
            if names.count(n) > 1:
                raise ValueError(f"two parameters are named '{n}'; give one a label = \"...\"")
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
        axes = [_axis(p, self.spec) for p in self.spec.parameters]
        names = [p.name for p in self.spec.parameters]
        if self.spec.sampling == "grid":
            return [dict(zip(names, combo)) for combo in product(*axes)]
        from scipy.stats import qmc
        u = qmc.LatinHypercube(d=len(axes), seed=self.spec.seed).random(self.spec.samples)
        return [{n: ax(float(x)) for n, ax, x in zip(names, axes, row)} for row in u]

    def base_data(self) -> dict:
        """The base scene with the study's fixed overrides (no parameter applied)."""
        data = json.loads(json.dumps(self.base))
        for path, value in self.spec.fidelity.items():
            _set(data, path, value)
        return data

    def scene_data(self, point: dict) -> dict:
        data = self.base_data()
        for p in self.spec.parameters:
            for path in p.paths:
                _set(data, path, _value(point[p.name]))
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
        return [_fmt(a + i * s, unit) for i in range(n)]
    if p.num is None:
        raise StudyError(f"parameters '{p.name}': a range needs step = ... or num = N")
    if b < a:
        raise StudyError(f"parameters '{p.name}': empty range ({p.start} to {p.stop}); use stop >= start")
    return [_fmt(a + (b - a) * i / (p.num - 1), unit) for i in range(p.num)]


def _same_unit(name, *values, unit=None):
    """Magnitudes of quantities in one unit (that of the first, or `unit`)."""
    out = []
    for v in values:
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            if unit not in (None, ""):
                raise StudyError(f"parameters '{name}': {v!r} has no unit but the range is in {unit}; "
                                 f"write e.g. \"{v} {unit}\"")
            out.append(float(v))
            unit = ""
            continue
        try:
            q = _ureg().Quantity(str(v).replace("Ohm", "ohm"))
        except Exception:
            raise StudyError(f"parameters '{name}': cannot read {v!r} as a quantity") from None
        if unit is None:
            unit = f"{q.units:~}"
        try:
            out.append(float(q.to(unit).magnitude) if unit else float(q))
        except Exception:
            raise StudyError(f"parameters '{name}': unit mismatch: {v!r} is not in {unit or 'plain numbers'}") \
                from None
    return out, unit


def _fmt(x, unit):
    x = round(x, 12)
    return f"{x:g} {unit}" if unit else x


def _merge(node: dict, value: dict):
    for k, v in value.items():
        if isinstance(v, dict) and isinstance(node.get(k), dict):
            _merge(node[k], v)
        else:
            node[k] = v


def _set(data: dict, path: str, value):
    """Set `value` at a dotted path; a table is merged (deeply) into the table there.
    The path "" is the scene itself (a value such as {model = {...}, mesh = {...}})."""
    if path == "":
        if not isinstance(value, dict):
            raise StudyError("a parameter at the scene root (path = \"\") needs tables as values")
        _merge(data, value)
        return
    keys = path.split(".")
    node = data
    for k in keys[:-1]:
        node = node.setdefault(k, {})
        if not isinstance(node, dict):
            raise StudyError(f"'{path}': '{k}' is not a table in the base scene")
    if isinstance(value, dict) and isinstance(node.get(keys[-1]), dict):
        _merge(node[keys[-1]], value)
    else:
        node[keys[-1]] = value


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
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise error(f"{path}: not a valid UTF-8 TOML file: {exc}") from None
    data.setdefault("name", path.stem)
    try:
        spec = spec_class.model_validate(data)
    except ValidationError as err:
        raise error(_one_line(err)) from None
    base_path = Path(spec.base)
    if not base_path.is_absolute():
        base_path = path.parent / base_path
    if not base_path.is_file():
        base_path = EXAMPLES / f"{spec.base}.toml"
    if not base_path.is_file():
        raise error(f"base = '{spec.base}': no such scene file or built-in example")
    base = tomllib.loads(base_path.read_text(encoding="utf-8"))
    base.pop("name", None)
    return spec, base, path


def load_study(path) -> Study:
    spec, base, path = read_spec(path, BUILTIN, StudySpec, StudyError, "study")
    study = Study(spec, base, path.parent)
    known = _known_paths()
    for p in spec.parameters:
        for dotted in p.paths:
            if dotted and dotted.split(".")[0] not in known:
                raise StudyError(f"parameters: unknown scene path '{dotted}'; it must start with one of "
                                 f"{', '.join(sorted(known))}")
    points = study.points()
    try:                                  # validate the first point fully: unknown keys, units
        parse(study.scene_data(points[0]))
    except SceneError as exc:
        raise StudyError(f"the study's first point is not a valid scene: {exc}") from None
    return study


@cache
def _known_paths():
    from studies.scene import Scene
    return set(Scene.model_fields)


# --------------------------------------------------------------------------------------
# keys, code version, the store
# --------------------------------------------------------------------------------------

@cache
def code_version() -> str:
    """Hash of the sources a result depends on (fem, meshing, studies/scene.py)."""
    root = Path(__file__).parent.parent
    h = hashlib.sha256()
    for pkg in ("fem", "meshing"):
        for f in sorted((root / pkg).glob("*.py")):
            h.update(f.read_bytes())
    h.update((root / "studies" / "scene.py").read_bytes())
    return h.hexdigest()[:16]


def point_key(scene_data: dict) -> str:
    scene = parse({**scene_data, "name": "point"})
    canon = json.dumps(scene.model_dump(mode="json"), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256((canon + code_version()).encode()).hexdigest()


class Store:
    """The study's SQLite database: one row per design point key."""

    def __init__(self, folder: Path):
        folder.mkdir(parents=True, exist_ok=True)
        self.path = folder / "results.sqlite"
        self.db = sqlite3.connect(self.path, timeout=30)
        self.db.execute("PRAGMA journal_mode=WAL")
        self.db.execute("PRAGMA synchronous=FULL")
        self.db.execute("""CREATE TABLE IF NOT EXISTS points (
            key TEXT PRIMARY KEY, params TEXT NOT NULL, status TEXT NOT NULL,
            result TEXT, error TEXT, seconds REAL, finished REAL)""")
        self.db.commit()

    def status(self) -> dict[str, str]:
        return dict(self.db.execute("SELECT key, status FROM points"))

    def put(self, key, params, status, result=None, error=None, seconds=0.0):
        with self.db:                     # one transaction: a point is stored whole or not at all
            self.db.execute("INSERT OR REPLACE INTO points VALUES (?, ?, ?, ?, ?, ?, ?)",
                            (key, json.dumps(params), status, json.dumps(result) if result is not None else None,
                             error, seconds, time.time()))

    def rows(self, keys=None):
        cur = self.db.execute("SELECT key, params, status, result, error, seconds FROM points")
        out = []
        for key, params, status, result, error, seconds in cur:
            if keys is None or key in keys:
                out.append({"key": key, "params": json.loads(params), "status": status,
                            "result": json.loads(result) if result else None, "error": error,
                            "seconds": seconds})
        return out

    def close(self):
        self.db.close()


# --------------------------------------------------------------------------------------
# evaluating one point (a pure function of the scene: runs on any worker)
# --------------------------------------------------------------------------------------

def evaluate(scene_data: dict, outputs: tuple[str, ...]) -> dict:
    """Solve one design point and return its outputs (JSON-ready, SI units)."""
    import numpy as np

    from fem.solve import solve
    scene = parse({**scene_data, "name": "point"})
    t0 = time.perf_counter()
    sol = solve(scene)
    res: dict[str, Any] = {}
    taxels = {k: e for k, e in sol.electrodes.items() if e.state != "reference"}
    pressed = None
    if scene.array is not None and scene.load.kind in ("taxel", "indenter"):
        pressed = f"taxel_{scene.load.taxel[0]}_{scene.load.taxel[1]}"
    if "voltage" in outputs:
        res["voltage"] = {k: e.voltage for k, e in taxels.items()}
    if "charge" in outputs:
        res["charge"] = {k: e.short_circuit_charge for k, e in taxels.items()}
    if "crosstalk" in outputs and pressed in taxels and len(taxels) > 1:
        vp = abs(taxels[pressed].voltage)
        res["crosstalk"] = max(abs(e.voltage) for k, e in taxels.items() if k != pressed) / vp if vp else None
    if "max_strain" in outputs:
        res["max_strain"] = sol.max_silicone_strain
    if "frequency_response" in outputs:
        from fem import circuits, dynamics
        port = dynamics.sweep(dynamics.model(scene, tm=sol.mesh), dynamics.frequencies(scene.analysis))
        H = circuits.readout(port, scene.readout) / sol.applied_force
        res["frequency_response"] = {"freqs": port.freqs.tolist(),
                                     **{k: np.abs(H[:, i]).tolist() for i, k in enumerate(port.names)}}
    res["pressed"] = pressed
    res["model_note"] = sol.model_note
    res["seconds"] = time.perf_counter() - t0
    return res


def _evaluate_safely(scene_data, outputs):
    try:
        return "done", evaluate(scene_data, outputs), None
    except Exception as exc:            # recorded with the point; the study goes on
        return "failed", None, f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"


# --------------------------------------------------------------------------------------
# running
# --------------------------------------------------------------------------------------

@dataclass
class RunSummary:
    total: int
    cached: int
    done: int
    failed: int
    seconds: float


def run(study: Study, out: Path, workers: int = 2, scheduler: str | None = None,
        retry_failed: bool = False, progress: bool = True) -> RunSummary:
    """Run every point not already in the store (in-process for workers = 1, else on
    a local Dask cluster or the one at `scheduler`); the store stays with the caller."""
    t0 = time.perf_counter()
    store = Store(out)
    points = study.points()
    todo, params_of, cached = [], {}, 0
    known = store.status()
    seen = set()
    for pt in points:
        data = study.scene_data(pt)
        try:
            key = point_key(data)
        except SceneError as exc:
            key = hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest()
            if key not in known:
                store.put(key, pt, "failed", error=f"SceneError: {exc}")
            continue
        if key in seen:
            continue
        seen.add(key)
        params_of[key] = pt
        st = known.get(key)
        if st == "done" or (st == "failed" and not retry_failed):
            cached += 1
            continue
        todo.append((key, data))
    outputs = tuple(study.spec.outputs)
    done = failed = 0
    bar = _bar(len(seen), cached, progress)
    try:
        for key, (status, result, error) in _execute(todo, outputs, workers, scheduler):
            store.put(key, params_of[key], status, result, error, (result or {}).get("seconds", 0.0))
            done += status == "done"
            failed += status == "failed"
            bar.update(1)
            bar.set_postfix(done=done, failed=failed, cached=cached)
    finally:
        bar.close()
        store.close()
    return RunSummary(len(seen), cached, done, failed, time.perf_counter() - t0)


def _bar(total, cached, progress):
    from tqdm import tqdm
    bar = tqdm(total=total, initial=cached, disable=not progress, unit="point", dynamic_ncols=True)
    bar.set_postfix(done=0, failed=0, cached=cached)
    return bar


def _execute(todo, outputs, workers, scheduler):
    """Yield (key, (status, result, error)) as points finish."""
    if not todo:
        return
    if workers <= 1 and scheduler is None:
        for key, data in todo:
            yield key, _evaluate_safely(data, outputs)
        return
    from dask.distributed import Client, as_completed
    if scheduler is not None:
        client, cluster = Client(scheduler), None
        n_workers = max(len(client.scheduler_info()["workers"]), 1)
    else:
        cluster = local_cluster(workers)
        client = Client(cluster)
        n_workers = workers
    try:
        client.run(_single_threaded)
        # a few points per task: fewer round trips, results still stored as they come
        size = max(1, min(4, len(todo) // (8 * n_workers)))
        chunks = [todo[i:i + size] for i in range(0, len(todo), size)]
        futures = [client.submit(_evaluate_chunk, chunk, outputs, pure=False) for chunk in chunks]
        for fut in as_completed(futures):
            yield from fut.result()
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def local_cluster(workers: int):
    """A local Dask cluster for FEM work: one process per worker (gmsh is not
    thread-safe), one thread and one BLAS thread each, fork-started. Measured on
    the 70-point Fig. 2.5 study (2 cores): spawned workers start cold and their
    points took 35-43 % more CPU in total (speed-up 1.1x); forked ones inherit
    the loaded modules, 10 % more (speed-up 1.8-2.0x). The statistical profiler
    is off (no measurable effect either way)."""
    import dask
    from dask.distributed import LocalCluster
    one = {v: "1" for v in ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS")}
    with dask.config.set({"distributed.worker.profile.enabled": False,
                          "distributed.worker.multiprocessing-method": "fork"}):
        return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, env=one,
                            dashboard_address=None, silence_logs=40)


def _evaluate_chunk(chunk, outputs):
    return [(key, _evaluate_safely(data, outputs)) for key, data in chunk]


def _single_threaded():
    """One BLAS/MKL thread per worker (the workers are the parallelism)."""
    import os
    for var in ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS"):
        os.environ[var] = "1"
    try:
        from threadpoolctl import threadpool_limits
        threadpool_limits(1)
    except ImportError:
        pass


# --------------------------------------------------------------------------------------
# reading results: tidy rows, status, plots
# --------------------------------------------------------------------------------------

def tidy_rows(out: Path, study: Study | None = None) -> list[dict]:
    """One flat row per point: parameters, status, then outputs per taxel."""
    store = Store(out)
    rows = []
    for r in store.rows():
        row = {}
        for k, v in r["params"].items():
            if isinstance(v, dict) and "label" in v:
                v = v["label"]
            elif isinstance(v, dict):                 # an unlabelled table: "key=value; ..."
                v = "; ".join(f"{a}={b}" for a, b in v.items())
            row[k] = v
        row["status"] = r["status"]
        res = r["result"] or {}
        for name in ("voltage", "charge"):
            for taxel, val in (res.get(name) or {}).items():
                row[f"{name}_{taxel}"] = val
        if res.get("pressed") and res.get("voltage"):
            row["voltage_pressed"] = res["voltage"].get(res["pressed"])
        for name in ("crosstalk", "max_strain", "seconds"):
            if name in res:
                row[name] = res[name]
        row["error"] = r["error"] or ""
        rows.append(row)
    store.close()
    return rows


def magnitude(v):
    """The number in a value such as "0.5 mm" (SI), or the value itself."""
    if isinstance(v, (int, float)):
        return float(v)
    try:
        return float(_ureg().Quantity(str(v)).to_base_units().magnitude)
    except Exception:
        return v
