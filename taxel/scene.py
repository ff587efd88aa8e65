"""The scene: one validated TOML description of a design and its load case.

A scene is either a taxel array (`[array]`: piezo squares in silicone, one top
electrode per taxel and a common bottom ground) or a verification plate
(`[plate]`: a stack of full-width layers), plus `[load]`, `[supports]`, `[model]`
and `[mesh]`. Lengths, forces and pressures are strings with units ("1 mm",
"0.5 N", "10 kPa"); inside the code everything is SI.

Every validation error is one line: `scene error: <key>: <problem>; <fix>`. The tables a
scene is made of are taxel.scene_tables (re-exported here).
"""

from __future__ import annotations

import json
from pathlib import Path

from pydantic import BaseModel, PrivateAttr, ValidationError, model_validator

from taxel import units
from taxel.schema import GEOMETRY, Name, Strict, one_line, read_toml, safe_name, set_path, to_data
from taxel.scene_tables import (DEFAULT_MESH, DEFAULT_PRESS_MESH, MATERIAL_UNITS, NOISE_BAND, AdcTable,  # noqa: F401
                                AnalysisTable, ArrayTable, DynamicsTable, FrictionLaw, LayerTable, LoadTable, MeshTable, ModelTable, PlateTable,
                                ReadoutTable, SupportsTable, UserMaterial, WarmTouchTable, material_in_si)

EXAMPLES = Path(__file__).parent / "examples"

# One example per table of a scene, shown under the key reference (`taxel schema`'s page in
# the docs, docs/reference/keys/scene.md); each loads as a scene (tests/test_docs.py). Each is
# a file of taxel/examples/keys/, its first line the title ("# materials (a user silicone)").
KEY_EXAMPLES = {title.removeprefix("# "): text.rstrip("\n") for title, _, text in
                (f.read_text().partition("\n") for f in sorted((EXAMPLES / "keys").glob("*.toml")))}


class SceneError(ValueError):
    """A scene that cannot be solved; the message is one line with the fix."""


MAX_TIME_STEPS = 1_000_000     # a transient beyond this is refused before it starts


class Scene(Strict):
    name: Name = "scene"
    """The scene's name (default: its file's name); result folders and reports use it."""
    description: str = ""
    """A line about the design, for the reports."""
    model: ModelTable = ModelTable()
    """The model: type, silicone law, symmetry, fidelity."""
    mesh: MeshTable = MeshTable()
    """The mesh: sizes, elements through the piezo, order, element kind."""
    array: ArrayTable | None = None
    """A taxel array: piezo squares in silicone (or a [plate])."""
    plate: PlateTable | None = None
    """A verification plate: a stack of full-width layers (or an [array])."""
    load: LoadTable = LoadTable()
    """The load case: a pressure patch, a probe (as a patch or a rigid indenter), or a pressure."""
    supports: SupportsTable = SupportsTable()
    """The boundary conditions at the bottom and the edges."""
    electrodes: dict[str, str] = {}
    """Electrode states by name (or "taxels"): "open", "ground" or a voltage such as "10 V"."""
    dynamics: DynamicsTable = DynamicsTable()
    """Damping: loss factors and Rayleigh factors."""
    analysis: AnalysisTable = AnalysisTable()
    """The analysis: static, a frequency sweep or a transient, and its settings."""
    readout: ReadoutTable = ReadoutTable()
    """The readout chain: circuit, notch and noise."""
    warm_touch: WarmTouchTable | None = None
    """A warm finger on the skin: its temperature, the contact, the air (taxel.analyses.solves.warm_touch)."""
    materials: dict[str, UserMaterial] = {}
    """User materials by name, each a piezo or a solid; a value is a string with its unit ("27.5 kPa") or an SI number."""
    _default_mesh: tuple[str, ...] = PrivateAttr(())    # the mesh keys filled from DEFAULT_MESH
    _checked: dict | None = PrivateAttr(None)            # its materials once checked (taxel.analyses.check)

    def replace(self, **changes) -> Scene:
        """A new validated scene with values changed by dotted path (see `replace`)."""
        return replace(self, **changes)

    @property
    def pressed_by_punch(self) -> bool:
        """A 3D array scene pressed by a flat punch in contact (the rig's probe)."""
        ld = self.load
        return (self.array is not None and self.model.type == "3d" and ld.kind == "probe" and ld.contact
                and ld.shape == "flat")

    def _fill_default_mesh(self) -> None:
        """mesh.size (and piezo_size) not given: DEFAULT_MESH for this model type, or
        DEFAULT_PRESS_MESH (with its piezo_layers, unless given) for a 3D punch press."""
        m = self.mesh
        if m.size is not None:
            return
        press = self.pressed_by_punch
        size, piezo = (DEFAULT_PRESS_MESH[:2] if press else DEFAULT_MESH[self.model.type] if self.array is not None
                       else (0.5e-3, None))
        filled = {"size": size}
        if press and "piezo_layers" not in m.model_fields_set:
            filled["piezo_layers"] = DEFAULT_PRESS_MESH[2]
        if press and m.extruded is None:
            filled["extruded"] = False
        if m.piezo_size is None and piezo is not None:
            filled["piezo_size"] = piezo
        elif m.piezo_size is not None and m.piezo_size > size:
            filled["size"] = m.piezo_size * 4 if piezo is None else max(size, m.piezo_size)
        object.__setattr__(self, "mesh", m.model_copy(update=filled))
        self._default_mesh = tuple(filled)

    @model_validator(mode="after")
    def _consistent(self):
        if (self.array is None) == (self.plate is None):
            raise ValueError("give exactly one of [array] or [plate]")
        self._fill_default_mesh()
        m = self.mesh
        if m.piezo_size is not None and m.piezo_size > m.size:
            raise ValueError(f"mesh.piezo_size ({m.piezo_size * 1e3:g} mm) is larger than mesh.size "
                             f"({m.size * 1e3:g} mm); the piezo size is the fine one: make it smaller")
        if self.array is not None:
            a = self.array
            if a.gap < 0:
                raise ValueError(f"array.gap = {a.gap * 1e3:g} mm: a negative edge-to-edge gap makes the taxels "
                                 "overlap; give a gap >= 0, e.g. \"1 mm\"")
            if a.gap < GEOMETRY[0] and a.rows * a.cols > 1:
                raise ValueError(f"array.gap = {a.gap * 1e3:g} mm makes the taxels overlap or touch; "
                                 "use an edge-to-edge gap of at least 1 um")
            if self.model.type == "axisymmetric" and a.rows * a.cols > 1:
                raise ValueError("model.type = 'axisymmetric' holds one taxel; set rows = cols = 1 "
                                 "or use a plane or 3d model")
            for key in ("taxel", "neighbour"):
                rc = getattr(self.load, key)
                if rc is not None and not (0 <= rc[0] < a.rows and 0 <= rc[1] < a.cols):
                    raise ValueError(f"load.{key} = {list(rc)} is outside the {a.rows}x{a.cols} array; "
                                     f"use rows 0..{a.rows - 1}, cols 0..{a.cols - 1}")
        if self.plate is not None:
            p = self.plate
            if self.load.kind not in ("pressure", "probe"):
                raise ValueError(f"load.kind = '{self.load.kind}' needs taxels; a plate takes "
                                 "'pressure' or 'probe'")
            if p.shape == "rectangle" and p.width is None:
                raise ValueError("plate.width is missing; give the rectangle's width, e.g. \"20 mm\"")
            if p.shape == "rectangle" and self.model.type == "3d" and p.length is None:
                raise ValueError("plate.length is missing; a 3d rectangle needs it, e.g. \"20 mm\"")
            if p.shape == "disk" and p.radius is None:
                raise ValueError("plate.radius is missing; give the disk's radius, e.g. \"10 mm\"")
            if self.model.type == "axisymmetric" and p.shape != "disk":
                raise ValueError("model.type = 'axisymmetric' needs plate.shape = 'disk'")
            if self.load.kind == "probe" and self.load.radius is not None:
                _probe_on_plate(self.load, p)
        ld = self.load
        if ld.kind == "pressure" and ld.pressure is None:
            raise ValueError("load.pressure is missing for kind = 'pressure'; e.g. \"10 kPa\"")
        if ld.force is not None and ld.force < 0:
            raise ValueError(f"load.force = {ld.force:g} N: a press pushes, the force is its size (>= 0); "
                             "a pull is not modelled, e.g. \"1 N\"")
        if ld.kind != "pressure" and ld.force is None:
            raise ValueError(f"load.force is missing for kind = '{ld.kind}'; e.g. \"0.5 N\"")
        driven = any(not isinstance(electrode_state(v, f"electrodes.{k}"), str) for k, v in self.electrodes.items())
        if not driven and ld.kind != "pressure" and ld.force == 0:
            raise ValueError("load.force = 0 N and no electrode at a voltage: nothing drives the model; "
                             "give the press's force, e.g. \"1 N\"")
        if not driven and ld.kind == "pressure" and ld.pressure == 0:
            raise ValueError("load.pressure = 0 Pa and no electrode at a voltage: nothing drives the model; "
                             "give a pressure, e.g. \"10 kPa\"")
        if ld.kind == "between":
            if ld.neighbour is None:
                raise ValueError("load.neighbour is missing for kind = 'between'; e.g. [0, 1]")
            dr, dc = ld.neighbour[0] - ld.taxel[0], ld.neighbour[1] - ld.taxel[1]
            if abs(dr) + abs(dc) != 1:
                raise ValueError("load.neighbour must be next to load.taxel (one row or column apart)")
        if ld.kind == "probe" and ld.radius is None:
            raise ValueError("load.radius is missing for kind = 'probe'; e.g. \"1 mm\"")
        if ld.friction is not None and not ld.contact:
            raise ValueError("load.friction needs load.contact = true (a rigid indenter)")
        if ld.contact:
            if ld.kind != "probe":
                raise ValueError("load.contact = true needs load.kind = 'probe'")
            two_d = self.model.type in ("plane_strain", "plane_stress")
            if (ld.shape == "cylinder") != two_d and ld.shape != "flat":
                raise ValueError(f"load.shape = '{ld.shape}' does not fit model.type = '{self.model.type}'; "
                                 "use 'cylinder' in 2D and 'sphere' axisymmetric or in 3d")
            if ld.edge_radius is not None and not 0 <= ld.edge_radius <= ld.radius:
                raise ValueError("load.edge_radius must be between 0 and load.radius")
            if self.analysis.type != "static":
                raise ValueError("load.contact = true is static only for now; set analysis.type = 'static'")
        if self.model.type == "axisymmetric" and (ld.offset != (0.0, 0.0) or ld.kind == "between"):
            raise ValueError("an axisymmetric model needs a load centred on the axis; "
                             "drop load.offset or use a 3d model")
        if self.warm_touch is not None:
            _check_warm_touch(self.warm_touch, self.analysis.rise)
        if self.analysis.f_min >= self.analysis.f_max:
            raise ValueError("analysis.f_min must be below analysis.f_max")
        if self.analysis.type == "transient" and self.analysis.dt >= self.analysis.duration:
            raise ValueError("analysis.dt must be below analysis.duration")
        steps = self.analysis.duration / self.analysis.dt
        if self.analysis.type == "transient" and steps > MAX_TIME_STEPS:
            raise ValueError(f"analysis: {steps:.3g} time steps (duration / dt) is more than {MAX_TIME_STEPS:.0e}; "
                             "shorten analysis.duration or raise analysis.dt")
        if self.analysis.input == "csv" and self.analysis.type == "transient" and not self.analysis.file:
            raise ValueError("analysis.file is missing for input = 'csv'; give a CSV of time (s), force (N)")
        if self.model.fidelity == "auto" and (self.analysis.type != "static" or self.array is None):
            raise ValueError("model.fidelity = 'auto' needs a static analysis of an [array]; "
                             "set model.fidelity = 'fixed'")
        if "crosstalk" in self.model.outputs and self.array is not None and self.array.rows * self.array.cols < 2:
            raise ValueError("model.outputs: 'crosstalk' needs at least two taxels; add array.rows or "
                             "array.cols, or drop it")
        if self.analysis.type != "static" and self.model.silicone == "auto":
            raise ValueError("dynamic analyses need model.silicone = 'linear' or 'yeoh' (not 'auto')")
        if self.analysis.type == "transient" and self.model.silicone == "yeoh" and self.readout.circuit != "open":
            raise ValueError("a hyperelastic transient reads open-circuit voltages; set readout.circuit = "
                             "'open' (or use the linear silicone for circuits)")
        if (self.supports.bottom == "free" and self.supports.edges == "free"):
            raise ValueError("supports: bottom and edges are both free, so the body can move freely; "
                             "set supports.bottom = 'bonded' or 'rollers', or fix the edges")
        for name, state in self.electrodes.items():
            electrode_state(state, f"electrodes.{name}")
        if self.model.silicone == "yeoh":
            for name in _user_solids_without_yeoh(self):
                raise ValueError(f"model.silicone = 'yeoh' needs the Yeoh constants of '{name}': add C10 (and C20, "
                                 f"C30) to [materials.{name}] (taxel material fit-yeoh fits them to a tension "
                                 "test), or use model.silicone = 'linear'")
        if self.mesh.element == "hex" and self.model.type != "3d":
            raise ValueError("mesh.element = 'hex' needs model.type = '3d'; use mesh.element = 'tet'")
        if self.mesh.element == "hex" and self.mesh.formulation != "mixed":
            raise ValueError("mesh.element = 'hex' is mixed u-p only (Q2/P0, Q1/P0); set mesh.formulation = 'mixed'")
        if self.model.silicone != "linear":
            if self.mesh.formulation != "mixed":
                raise ValueError("model.silicone = 'yeoh' needs mesh.formulation = 'mixed'")
            if any(not isinstance(electrode_state(v), str) for v in self.electrodes.values()):
                raise ValueError("electrodes at a set voltage are linear-model only; use 'open' or 'ground'")
        return self


def _check_warm_touch(w: WarmTouchTable, rise: float):
    """The warm touch's times: the touch within the simulated time, steps that resolve it, a
    readout grid (the press's rise / 4) that fits; temperatures and conductances in range."""
    for key in ("finger", "ambient"):
        if not 1.0 <= getattr(w, key) <= 1000.0:
            raise ValueError(f"warm_touch.{key} = {getattr(w, key):g} K is outside 1 K to 1000 K; give a "
                             "temperature such as \"34 degC\"")
    for key in ("contact_conductance", "convection"):
        if getattr(w, key) > 1e9:
            raise ValueError(f"warm_touch.{key} = {getattr(w, key):g} W/(m^2 K) is above 1e9 W/(m^2 K), "
                             "beyond any contact; give e.g. \"1000 W/(m^2*K)\"")
    if w.duration > w.time:
        raise ValueError(f"warm_touch.duration = {w.duration:g} s is longer than warm_touch.time = {w.time:g} s, "
                         "the simulated time; make the time at least the touch's duration")
    if w.dt > w.duration / 2:
        raise ValueError(f"warm_touch.dt = {w.dt:g} s does not resolve a touch of {w.duration:g} s; "
                         "make dt at most half the duration")
    samples = w.time / min(w.dt, rise / 4)
    if samples > MAX_TIME_STEPS:
        raise ValueError(f"warm_touch: {samples:.3g} readout samples (time / min(dt, analysis.rise / 4)) is more than "
                         f"{MAX_TIME_STEPS:.0e}; shorten warm_touch.time or raise analysis.rise")


def _user_solids_without_yeoh(scene: Scene) -> list[str]:
    """The scene's user solid materials (its [materials] of kind "solid") that it
    uses and that have no Yeoh constant C10 (a linear law only)."""
    used = scene_material_names(scene)
    return [n for n in used if isinstance(scene.materials.get(n), dict)
            and scene.materials[n].get("kind") == "solid" and "C10" not in scene.materials[n]]


def _probe_on_plate(load: LoadTable, plate: PlateTable):
    """A probe's footprint (radius about its offset centre) must lie on the plate."""
    half = [plate.radius] * 2 if plate.shape == "disk" else [plate.width / 2, (plate.length or plate.width) / 2]
    reach = [abs(load.offset[0]) + load.radius, abs(load.offset[1]) + load.radius]
    if plate.shape == "disk":
        far = (load.offset[0] ** 2 + load.offset[1] ** 2) ** 0.5 + load.radius
        if far > half[0] * (1 + 1e-9):
            raise ValueError(f"load.radius = {load.radius * 1e3:g} mm (offset included) reaches "
                             f"{far * 1e3:g} mm from the centre of a disk of radius {plate.radius * 1e3:g} mm; "
                             "make the probe smaller than the plate (or the offset smaller)")
        return
    for axis, r, h, key in ((0, reach[0], half[0], "width"), (1, reach[1], half[1], "length")):
        if r > h * (1 + 1e-9):
            raise ValueError(f"load.radius = {load.radius * 1e3:g} mm (offset included) reaches {r * 1e3:g} mm "
                             f"from the centre, beyond the plate's half-{key} {h * 1e3:g} mm; make the "
                             "probe smaller than the plate (or the offset smaller)")


def electrode_state(state: str, key="electrode"):
    """'open' | 'ground' | volts (float) from a scene's electrode string."""
    s = state.strip().lower()
    if s in ("open", "ground"):
        return s
    if s == "short":
        return "ground"
    try:
        return units.to_si(state, "V", "voltage")
    except units.UnitError:
        raise ValueError(f"{key} = {state!r}: use 'open', 'ground' or a voltage such as \"10 V\"") from None


def parse(data: dict, *, si_numbers: bool = False) -> Scene:
    """A validated Scene from a dict (TOML-like: quantities as strings with units;
    with `si_numbers`, plain numbers are SI). Raises SceneError with one line.
    Material names are checked where materials are known (taxel.analyses)."""
    try:
        return Scene.model_validate(data, context={"si_numbers": si_numbers})
    except ValidationError as err:
        raise SceneError(one_line(err)) from None


def load(source: str | Path | dict) -> Scene:
    """A scene from a TOML file, a built-in example by name (see `examples()`), or a
    dict (Python numbers in SI). A file's relative `analysis.file` is resolved
    against the file's folder."""
    if isinstance(source, dict):
        return parse({"name": "scene", **source}, si_numbers=True)
    path = Path(source)
    if not path.is_file():
        builtin = EXAMPLES / f"{source}.toml"
        if not builtin.exists():
            raise SceneError(f"no scene file '{source}' and no built-in example of that name; "
                             f"built-in: {', '.join(examples())}")
        path = builtin
    data = read_toml(path, SceneError)
    data.setdefault("name", safe_name(path.stem))
    analysis = data.get("analysis")
    if isinstance(analysis, dict) and isinstance(analysis.get("file"), str):
        f = Path(analysis["file"])
        if not f.is_absolute():
            analysis["file"] = str(path.parent / f)
    return parse(data)


def examples() -> list[str]:
    return sorted(p.stem for p in EXAMPLES.glob("*.toml"))


def scene_material_names(scene: Scene) -> list[str]:
    if scene.array is not None:
        return [scene.array.piezo, scene.array.silicone]
    return [layer.material for layer in scene.plate.layers]


def replace(scene: Scene, **changes) -> Scene:
    """A new, validated scene with values changed by dotted path:
    replace(scene, **{"array.silicone_above": "0.5 mm", "load.force": 0.2}).
    Values are strings with units or SI numbers; a table merges into the table there.
    Mesh sizes the scene took from DEFAULT_MESH are defaults again (a changed model
    type gets its own)."""
    data = to_data(scene)
    for key in scene._default_mesh:
        data.get("mesh", {}).pop(key, None)
    for path, value in changes.items():
        if isinstance(value, BaseModel):
            value = to_data(value)
        try:
            set_path(data, path, value)
        except KeyError:
            raise SceneError(f"'{path}': not a scene path; a key on the way is not a table") from None
    return parse(data, si_numbers=True)


def refined(scene: Scene, factor: float, in_plane: bool = True, through: bool = True) -> Scene:
    """The scene with every element size divided by `factor`, for convergence studies:
    factor 2 halves h everywhere; `in_plane` False keeps the in-plane sizes (only the
    elements through the piezo change), `through` False keeps those. The mesh family
    (`mesh.extruded`, free silicone for a default 3D press) is kept."""
    m = scene.mesh
    changes = {"mesh.extruded": m.extruded} if m.extruded is not None else {}
    if in_plane:
        changes.update({"mesh.size": m.size / factor, "mesh.piezo_size": (m.piezo_size or m.size / 4) / factor})
    else:               # the sizes as they are (defaults included: replace re-fills only what is not given)
        changes.update({"mesh.size": m.size, "mesh.piezo_size": m.piezo_size or m.size / 4})
    changes["mesh.piezo_layers"] = max(1, round(m.piezo_layers * factor)) if through else m.piezo_layers
    return replace(scene, **changes)


def canonical(scene: Scene) -> str:
    """The scene as canonical JSON (sorted keys, SI numbers): what a result depends on."""
    return json.dumps(scene.model_dump(mode="json"), sort_keys=True, separators=(",", ":"))
