"""A scene becomes the finite-element model's Problem, once.

scene (taxel.scene) -> materials by name (`scene_materials`, checked with the mirror
planes by `check`) -> layered layout, refused when its solve cannot fit
(taxel.analyses.geometry) -> tagged mesh (meshing.build) -> kinematics, laws, load,
supports, electrodes, damping, the indenter (fem.assembly). Below this module nothing
reads the scene schema; above it nothing assembles. The readout chain
(`readout`) and the damping (`damping`) are translated here too.
"""

from __future__ import annotations

from dataclasses import replace

from taxel.fem import constitution
from taxel.fem.readout import Readout
from taxel.fem.assembly import Indenter
from taxel.fem.constitution import kinematics
from taxel.fem.assembly import Damping, Discretization, PatchLoad, Problem, Supports
from taxel.meshing.build import TaggedMesh, build
from taxel.scene import Scene, SceneError, electrode_state, scene_material_names
from taxel.analyses.geometry import checked_layout, mirror_planes


def check(scene: Scene) -> dict:
    """Everything about a scene that the schema alone cannot check: its materials
    (returned by name) and the mirror planes its model.symmetry asks for. Raises
    SceneError with one line."""
    mats = scene_materials(scene)
    sym = scene.model.symmetry
    if sym in ("half", "quarter"):
        if sym == "quarter" and scene.model.type != "3d":
            raise SceneError("model.symmetry = 'quarter' needs a 3d model (a 2D section has one mirror "
                             "plane); use 'half' or 'auto'")
        planes, why = mirror_planes(scene)
        if len(planes) < (2 if sym == "quarter" else 1):
            raise SceneError(f"model.symmetry = '{sym}': {why}; use 'auto' or 'full'")
    return mats


def scene_materials(scene: Scene) -> dict:
    """Every material the scene names (its own [materials] first, then the library),
    checked: raises SceneError (one line) for an unknown or unphysical material."""
    user = {}
    for name, rec in scene.materials.items():
        try:
            user[name] = constitution.from_record(name, rec)
        except ValueError as exc:
            raise SceneError(f"materials.{name}: {exc}") from None
    out = {}
    for name in scene_material_names(scene):
        try:
            out[name] = constitution.get(name, user)
        except KeyError as exc:
            raise SceneError(exc.args[0]) from None
    if scene.array is not None:
        for key, kind in (("piezo", constitution.Piezo), ("silicone", constitution.Solid)):
            name = getattr(scene.array, key)
            if not isinstance(out[name], kind):
                raise SceneError(f"array.{key} = '{name}' is not a "
                                 f"{'piezoelectric' if key == 'piezo' else 'passive solid'} material; pick one "
                                 f"that is (e.g. '{'PSI-5H4E' if key == 'piezo' else 'Ecoflex-00-30'}')")
    return out


def mesh(scene: Scene, msh_path=None) -> TaggedMesh:
    """The tagged mesh of a scene (also written to `msh_path`, gmsh's .msh, when given)."""
    return build(checked_layout(scene, check(scene)), msh_path=msh_path)


def problem(scene: Scene, tagged_mesh: TaggedMesh | None = None) -> Problem:
    """The finite-element Problem of a scene (meshing it unless `tagged_mesh` is given)."""
    mats = check(scene)
    tm = tagged_mesh or build(checked_layout(scene, mats))
    m, ld = scene.model, scene.load
    share = 2 ** len(tm.layout.planes)       # a half or quarter model carries its share of the force
    load = PatchLoad(pressure=ld.pressure) if ld.kind == "pressure" else \
        PatchLoad(force=ld.force / share, profile=ld.profile if ld.kind == "indenter" else "flat")
    return Problem(
        mesh=tm,
        kinematics=kinematics(m.type, tm.layout.depth),
        materials=mats,
        load=load,
        supports=Supports(scene.supports.bottom, scene.supports.edges),
        electrodes=electrode_states(scene, tm),
        discretization=Discretization(scene.mesh.order, scene.mesh.formulation == "mixed"),
        hyperelastic=m.silicone == "yeoh",
        damping=damping(scene),
        indenter=indenter(scene, tm),
    )


def indenter(scene: Scene, tm: TaggedMesh) -> Indenter | None:
    """The rigid indenter of a `[load] kind = "indenter"`, `contact = true` scene, centred
    on the layout's load patch."""
    ld = scene.load
    if ld.kind != "indenter" or not ld.contact:
        return None
    edge = ld.edge_radius if ld.edge_radius is not None else ld.radius / 20
    return Indenter(ld.shape, ld.radius, edge if ld.shape == "flat" else 0.0,
                    (tm.layout.load.x, tm.layout.load.y), ld.travel, None if ld.travel is not None else ld.force,
                    ld.friction or "sticking")


def with_silicone(p: Problem, silicone: str) -> Problem:
    """The same problem (same mesh) with a linear or a Yeoh silicone."""
    return replace(p, hyperelastic=silicone == "yeoh")


def electrode_states(scene: Scene, tm: TaggedMesh) -> dict:
    """Each electrode's state: "taxels" sets every taxel electrode, a name sets one;
    unset electrodes keep the FEM's default (common ground grounded, others open)."""
    names = [e.name for e in tm.layout.electrodes]
    every = [full for full, _, _ in tm.layout.images] or names    # a symmetric model: every taxel's name
    for key in scene.electrodes:
        if key not in every and key != "taxels":
            raise SceneError(f"electrodes.{key}: no such electrode; this scene has: {', '.join(every)}")
    states = {}
    for name in names:
        if name.startswith("taxel_") and "taxels" in scene.electrodes:
            states[name] = electrode_state(scene.electrodes["taxels"])
        if name in scene.electrodes:
            states[name] = electrode_state(scene.electrodes[name])
    return states


def damping(scene: Scene) -> Damping:
    d = scene.dynamics
    return Damping(d.silicone_loss, d.piezo_loss, d.dielectric_loss, d.rayleigh_alpha, d.rayleigh_beta,
                   d.reference_frequency)


def readout(scene: Scene) -> Readout:
    r = scene.readout
    return Readout(r.circuit, r.R, r.C_f, r.R_f, r.R_i, r.C_c, r.notch, r.notch_frequency, r.notch_bandwidth)
