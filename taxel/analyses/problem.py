"""The adapter: a scene becomes the finite-element model's Problem, once.

scene (taxel.scene) -> materials by name -> layout (taxel.analyses.geometry)
-> tagged mesh (meshing.build) -> kinematics, laws, load, supports, electrodes
(fem.problem). Below this module nothing reads the scene schema; above it
nothing assembles. The readout chain and the damping are translated here too.
"""

from __future__ import annotations

import os
from dataclasses import replace

from taxel.fem import linalg, materials, records
from taxel.fem.circuits import Readout
from taxel.fem.contact import Indenter
from taxel.fem.kinematics import kinematics
from taxel.fem.problem import Damping, Discretization, PatchLoad, Problem, Supports
from taxel.meshing.build import TaggedMesh, build
from taxel.meshing.estimate import estimate
from taxel.scene import Scene, SceneError, electrode_state, scene_material_names
from taxel.analyses.geometry import layout


def scene_materials(scene: Scene) -> dict:
    """Every material the scene names (its own [materials] first, then the library),
    checked: raises SceneError (one line) for an unknown or unphysical material."""
    user = {}
    for name, rec in scene.materials.items():
        try:
            user[name] = records.from_record(name, rec)
        except ValueError as exc:
            raise SceneError(f"materials.{name}: {exc}") from None
    out = {}
    for name in scene_material_names(scene):
        try:
            out[name] = materials.get(name, user)
        except KeyError as exc:
            raise SceneError(exc.args[0]) from None
    if scene.array is not None:
        for key, kind in (("piezo", materials.Piezo), ("silicone", materials.Solid)):
            name = getattr(scene.array, key)
            if not isinstance(out[name], kind):
                raise SceneError(f"array.{key} = '{name}' is not a "
                                 f"{'piezoelectric' if key == 'piezo' else 'passive solid'} material; pick one "
                                 f"that is (e.g. '{'PSI-5H4E' if key == 'piezo' else 'Ecoflex-00-30'}')")
    return out


# Memory of a sparse direct solve per unknown, measured (benchmarks/taxel_2d.py; issue 12's 3D
# taxel: 6.7 GB at 182k unknowns); in 3D the fill grows about as n^(1/3) more.
BYTES_PER_UNKNOWN_2D = 3e3
BYTES_PER_UNKNOWN_3D = 37e3
REFERENCE_UNKNOWNS_3D = 182e3
BYTES_PER_UNKNOWN_KRYLOV = 20e3


def machine_memory() -> float:
    """Physical memory of this machine, bytes."""
    return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))


def cost(scene: Scene, lay) -> tuple[float, float]:
    """(estimated unknowns, estimated bytes of the solve) of a scene's mesh: a direct
    solve, or above linalg.AUTO_KRYLOV_ABOVE unknowns (static, linear) the Krylov
    solver, whose memory is about linear (1.37 GB at 70k unknowns, README)."""
    n = estimate(lay).unknowns(lay.dim, scene.mesh.order)
    if lay.dim == 2:
        per = BYTES_PER_UNKNOWN_2D
    elif n > linalg.AUTO_KRYLOV_ABOVE and scene.analysis.type == "static" and scene.model.silicone == "linear":
        per = BYTES_PER_UNKNOWN_KRYLOV
    else:
        per = BYTES_PER_UNKNOWN_3D * max(n / REFERENCE_UNKNOWNS_3D, 1e-3) ** (1 / 3)
    return n, n * per


def checked_layout(scene: Scene, mats: dict):
    """The scene's layout, refused (SceneError, with the estimate) when its mesh and
    solve cannot fit in this machine's memory."""
    lay = layout(scene, mats)
    n, need = cost(scene, lay)
    have = machine_memory()
    if need > 0.8 * have:
        raise SceneError(f"mesh: about {n:.3g} unknowns, needing about {need / 1e9:.3g} GB for the solve, "
                         f"more than this machine's {have / 1e9:.3g} GB; coarsen mesh.size / mesh.piezo_size "
                         "or model less (a 2D or axisymmetric model)")
    return lay


def mesh(scene: Scene) -> TaggedMesh:
    """The tagged mesh of a scene."""
    return build(checked_layout(scene, scene_materials(scene)))


def problem(scene: Scene, tagged_mesh: TaggedMesh | None = None) -> Problem:
    """The finite-element Problem of a scene (meshing it unless `tagged_mesh` is given)."""
    mats = scene_materials(scene)
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
