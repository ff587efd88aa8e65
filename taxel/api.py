"""The Python API: what a design engineer calls from a script or a notebook.

    import taxel
    scene = taxel.load("thesis-pzt-single-2d")             # a file, a built-in name, or a dict
    thicker = scene.replace(**{"array.silicone_above": "2 mm", "load.force": 0.5})   # SI numbers or strings
    result = taxel.solve(thicker)                           # StaticResult | FrequencyResult | TransientResult
    result.voltages(), result.record(), result.to_folder("out/thicker")
    taxel.run_study("fig-2-5", "out/fig-2-5", workers=2)
    front = taxel.run_optimization("thesis-pzt-front", "out/front")  # OptimizationResult: front.summary(), .runs
    taxel.report(["out/fig-2-5", "out/front"], "out/report")

The command line is a thin shell over these functions.
"""

from __future__ import annotations

import shutil
from dataclasses import dataclass, field, replace
from pathlib import Path

from taxel import analyses
from taxel.analyses.results import write_scene
from taxel.scene import Scene, parse
from taxel.scene import load as _load_scene


def load(source: str | Path | dict) -> Scene:
    """A validated scene from a TOML file, a built-in example name, or a dict
    (Python numbers in SI); its materials are checked too. Raises SceneError
    with a one-line message."""
    scene = source if isinstance(source, Scene) else _load_scene(source)
    analyses.check(scene)
    return scene


solve = analyses.solve          # the analyses' own: the API adds nothing to a solve
friction_band = analyses.friction_band   # a press at frictionless, its coefficient and sticking (FrictionBand)
lumped = analyses.lumped


def mesh(scene: Scene | str | Path | dict, path: str | Path):
    """Mesh a scene and write it to `path` (.msh: gmsh, with physical groups; .vtu, .xdmf,
    ...: meshio); returns the TaggedMesh."""
    from taxel.meshing.build import export
    scene = scene if isinstance(scene, Scene) else _load_scene(scene)
    path = Path(path)
    if path.suffix == ".msh":
        return analyses.mesh(scene, msh_path=path)
    tm = analyses.mesh(scene)
    export(tm, path)
    return tm


def read(folder: str | Path):
    """The result a folder holds (its result.json and scene.json, written by
    `result.to_folder` or `taxel solve --out`), as the type that wrote it: its
    numbers, `record()`, `outputs()` and `summary()`, but no mesh or fields.
    An optimization folder reads back as its OptimizationResult. Raises
    ResultError (a ValueError, one line) for a folder without a result."""
    from taxel.analyses.results import result_kind
    from taxel.optimize.result import KINDS as OPTIMIZATION_KINDS, OptimizationResult
    kind = result_kind(folder)
    if kind in OPTIMIZATION_KINDS:
        return OptimizationResult.from_folder(folder)
    if kind == "reduced":                  # its matrices are in the folder's model.npz
        from taxel.analyses.solves.reduced import read_folder
        return read_folder(folder)
    return analyses.read(folder)


@dataclass
class StudyRun:
    name: str
    folder: Path
    total: int
    cached: int
    done: int
    failed: int
    seconds: float
    rows: list[dict] = field(repr=False, default_factory=list)     # one tidy row per point
    plots: list[Path] = field(default_factory=list)


def run_study(spec, out: str | Path | None = None, workers: int = 2, scheduler: str | None = None,
              retry_failed: bool = False, progress: bool = True,
              plots=("pressed_voltage", "crosstalk", "max_strain")) -> StudyRun:
    """Run a parameter study (a TOML file, a built-in name, or a studies.spec.Study)
    into `out` (default out/NAME): every point not already stored is solved
    (on `workers` local Dask workers, or the cluster at `scheduler`), then
    results.csv and the plots of the outputs `plots` are written."""
    from taxel.reports.figures import study_plots
    from taxel.studies.execute import run
    from taxel.studies.spec import Study, StudyError, load_study
    from taxel.studies.store import Store, tidy_rows, write_rows
    st = spec if isinstance(spec, Study) else load_study(spec)
    if workers < 1:
        raise StudyError(f"--workers {workers}: use 1 (in-process) or more")
    out = Path(out) if out is not None else Path("out") / st.spec.name
    if out.exists() and not out.is_dir():
        raise StudyError(f"{out}: exists and is not a folder; choose another --out")
    created = not out.exists()
    try:
        out.mkdir(parents=True, exist_ok=True)
        Store(out).close()                    # a corrupt store is refused before anything is written
        (out / "study.json").write_text(st.spec.model_dump_json(indent=1))
        write_scene(out, parse({**st.base_data(), "name": st.spec.name}))
        s = run(st, out, workers=workers, scheduler=scheduler, retry_failed=retry_failed, progress=progress)
    except BaseException:
        if created and not tidy_rows_or_none(out):        # nothing computed: leave nothing behind
            shutil.rmtree(out, ignore_errors=True)
        raise
    rows = tidy_rows(out)
    write_rows(rows, out / "results.csv")
    reached = [r for r in rows if not r.get("stopped_at")]     # a point stopped short is in the table, not the plots
    files = study_plots(reached, [p.name for p in st.spec.parameters], list(plots), out / "plots", st.spec.name)
    return StudyRun(st.spec.name, out, s.total, s.cached, s.done, s.failed, s.seconds, rows, files)


def tidy_rows_or_none(out: Path) -> list[dict]:
    """The stored rows of a study folder, or [] when it has no readable store."""
    from taxel.studies.store import StoreError, tidy_rows
    if not (out / "results.sqlite").exists():
        return []
    try:
        return tidy_rows(out)
    except StoreError:
        return []


def run_optimization(problem, out: str | Path | None = None, workers: int = 2, influence: str = "answer"):
    """Optimize a design (an optimization TOML file, a built-in name, or a loaded
    optimize.spec.Optimization) into `out` (default out/NAME): an OptimizationResult
    holding the optimum, or with [pareto] the sensitivity-crosstalk front, and the
    reference design's evaluation; its files (result.json, optimum.json or
    front.json, the history CSV) and plots are written to `out`; every design is
    cached in out's store. `influence`: whose coverage and localization error only
    [requirements] names are judged, the answer's designs' or the reference's only
    (optimize.run.run)."""
    from taxel.optimize import spec as O
    from taxel.optimize.run import run
    from taxel.reports.optimization import draw
    loaded = problem if isinstance(problem, O.Optimization) else O.load_optimization(problem)
    name = loaded.spec.name
    out = Path(out) if out is not None else Path("out") / name
    out.mkdir(parents=True, exist_ok=True)
    if isinstance(problem, O.Optimization):
        prob, path = replace(problem, out=out), None
    else:
        prob = O.load_optimization(problem, out)
        path = problem if Path(problem).is_file() else O.BUILTIN / f"{problem}.toml"
    write_scene(out, parse({**prob.scene_data(prob.x0), "name": name}))
    result = run(prob, path, workers=workers, influence=influence)
    result.to_folder(out)
    draw(result, out)
    return result


def report(folders, out: str | Path, pdf: bool = False, compare: bool = True, run: dict | None = None) -> Path:
    """Self-contained HTML pages of result folders and an index; returns the index.
    `run` adds to the index's run summary: "what" was run, "started", "seconds"."""
    from taxel.reports.build import build
    return build([Path(f) for f in folders], Path(out), pdf=pdf, compare=compare, run=run)


def work_precision(scenes, out: str | Path, forces=(0.2, 1.0), store: str | Path | None = None, progress=None):
    """The work-precision chart of scenes (names, files or Scenes) at each force (N)
    into `out` (reports/work_precision.py); every solve is cached in the store (default
    out/store), so a rerun only draws. Returns the WorkPrecision list."""
    from taxel.reports.work_precision import write
    from taxel.studies.work_precision import work_precision
    out = Path(out)
    scenes = [load(s) for s in ([scenes] if isinstance(scenes, (str, Path, Scene)) else scenes)]
    wps = [work_precision(sc, f, Path(store) if store else out / "store", progress) for sc in scenes for f in forces]
    write(wps, out)
    return wps


def serve_explorer(scene: Scene | str | Path | dict = "thesis-pzt-single-2d", folder: str | Path | None = None,
            host: str = "127.0.0.1", port: int = 8080, token: str | bool = True) -> None:
    """Serve the design explorer (taxel.explore) for a scene, or for a result,
    study or optimization folder (its scene.json; its results.sqlite is the
    cache), at http://host:port/ until interrupted. Answers are cached in the
    study store under `folder` (default out/explore/NAME); saved scenes go to
    `folder`/exports. An optimization folder's stored front is shown with the current
    design on it; a front design loads into the controls, and the current design can
    start a new optimization. Binds to this machine only unless `host` says otherwise.
    `token`: True, a new random token required in the printed address (as Jupyter's);
    a string, that token; False, none (only with a loopback `host`). Every request's Host
    and Origin are checked (taxel.explore.guard)."""
    import json
    from taxel.explore.app import Explorer
    source = scene
    if isinstance(source, (str, Path)) and Path(source).is_dir():
        if not (Path(source) / "scene.json").is_file():
            from taxel.scene import SceneError
            raise SceneError(f"{source}: a folder without scene.json; give a scene file, a built-in name, "
                             "or a result, study or optimization folder")
        scene = load(parse(json.loads((Path(source) / "scene.json").read_text())))
        store = Path(source)
        from taxel.explore.front import Front
        front = Front.of(source)
    else:
        scene = load(scene)
        store, front = None, None
    from taxel.explore.guard import check_bind, new_token
    token = new_token() if token is True else (token or None)
    check_bind(host, token)
    from taxel.explore.confine import confine
    folder = confine(Path(folder) if folder is not None else Path("out") / "explore" / scene.name)
    Explorer(scene, folder, store=store, front=front).serve(host, port, token)


def reduce(scene: Scene | str | Path | dict, inputs: str | None = None, output: str = "readout",
           f_max: float | None = None):
    """The scene's reduced-order model (taxel.analyses.solves.reduced.ReducedModel): inputs a
    force on each taxel ("taxels", array scenes) or the scene's load ("probe"), outputs
    the readout chain ("readout") or the short-circuit charges ("charge") at every
    taxel; `.frf(f)`, `.simulate(t, force)`, `.to_control()`, `.to_scipy()`,
    `.save_mat(path)`, `.save(path.npz)`, `.to_folder(dir)`."""
    from taxel.analyses.solves.reduced import reduce as _reduce
    return _reduce(scene if isinstance(scene, Scene) else load(scene), inputs, output, f_max)


def build_skin(scene: Scene | str | Path | dict, out: str | Path | None = None, dt: float = 1e-3, per_pitch: int = 8,
         checks: int = 4, rig: str | Path | None = None):
    """The scene's skin (taxel.skin.model.SkinModel): the sensor model a simulator runs
    with taxel.skin.runtime.SkinRuntime (layout, the influence W of normal and shear forces
    with its measured interpolation error: from the 3D surface map for a 3D scene, the 2D
    section's separable normal influence otherwise; the readout dynamics discretized at
    `dt` with its error against the solver's sweep; noise, saturation, provenance);
    written to `out` (.npz) when given. `rig`: a bench rig (name or file) whose
    conditioning and ADC the skin's noise and quantization take."""
    from taxel.skin.build import build
    sc = scene if isinstance(scene, Scene) else load(scene)
    r = None
    if rig is not None:
        from taxel.studies.bench.rig import load_rig
        r = load_rig(rig)
    model = build(sc, dt, per_pitch, checks, r)
    if out is not None:
        model.save(out)
    return model
