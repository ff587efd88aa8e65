"""A scene becomes the finite-element model's Problem, once, and the Problem's
static solve (`solve_model`).

scene (taxel.scene) -> materials by name (`scene_materials`, checked with the mirror
planes by `check`) -> layered layout, refused when its solve cannot fit
(taxel.analyses.model.geometry) -> tagged mesh (meshing.build) -> kinematics, laws, load,
supports, electrodes, damping, the indenter (fem.assembly). Below this module nothing
reads the scene schema; above it nothing assembles. The readout chain
(`readout`) and the damping (`damping`) are translated here too.

The static solve is linear, Yeoh, or "auto" (the cheapest silicone law that is
accurate enough): model.silicone = "auto" solves the linear model, estimates its
voltage error as LINEAR_ERROR_PER_STRAIN x its largest silicone strain, keeps it when
the estimate is within model.tolerance and otherwise solves Yeoh on the same mesh;
the choice and the estimate are in `StaticResult.model_note`. A solve that stops short
of its load raises fem's NewtonError or PressError (taxel.analyses.solve returns it
as a result).
"""

from __future__ import annotations

import logging
import time
from dataclasses import replace

from taxel.fem import assembly
from taxel.fem import constitution
from taxel.fem import contact
from taxel.fem import hyperelastic
from taxel.fem import static
from taxel.fem.hyperelastic import NewtonError
from taxel.fem.readout import Readout
from taxel.fem.assembly import Indenter
from taxel.fem.constitution import kinematics
from taxel.fem.assembly import Damping, Discretization, PatchLoad, Problem, Supports
from taxel.meshing.build import TaggedMesh, build
from taxel.meshing.hexmesh import build_hex
from taxel.meshing.cost import MeshTooLarge
from taxel.scene import Scene, SceneError, electrode_state, scene_material_names
from taxel.analyses.model.geometry import layout, mirror_planes, solve_limit, too_large
from taxel.analyses.results import StaticResult
from taxel.analyses.results.static import linear_error


def check(scene: Scene) -> dict:
    """Everything about a scene that the schema alone cannot check: its materials
    (returned by name) and the mirror planes its model.symmetry asks for. Raises
    SceneError with one line. A scene is checked once: a second call returns the
    materials the first one checked (a changed scene, `scene.replace`, is a new scene)."""
    if scene._checked is not None:
        return scene._checked
    mats = scene_materials(scene)
    sym = scene.model.symmetry
    if sym in ("half", "quarter"):
        if sym == "quarter" and scene.model.type != "3d":
            raise SceneError("model.symmetry = 'quarter' needs a 3d model (a 2D section has one mirror "
                             "plane); use 'half' or 'auto'")
        planes, why = mirror_planes(scene)
        if len(planes) < (2 if sym == "quarter" else 1):
            raise SceneError(f"model.symmetry = '{sym}': {why}; use 'auto' or 'full'")
    scene._checked = mats
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
    return _mesh(scene, check(scene), msh_path)


def _mesh(scene: Scene, mats: dict, msh_path=None) -> TaggedMesh:
    """The scene's layout meshed, refused (SceneError) before gmsh runs when its solve
    cannot fit this machine."""
    lay = layout(scene, mats)
    try:
        if scene.mesh.element == "hex":       # a structured grid: refused in layout() if it cannot be built
            return build_hex(lay, limit=solve_limit(scene, lay))
        return build(lay, msh_path=msh_path, limit=solve_limit(scene, lay))
    except MeshTooLarge as exc:
        raise too_large(exc) from None


def problem(scene: Scene, tagged_mesh: TaggedMesh | None = None) -> Problem:
    """The finite-element Problem of a scene (meshing it unless `tagged_mesh` is given)."""
    mats = check(scene)
    tm = tagged_mesh or _mesh(scene, mats)
    m, ld = scene.model, scene.load
    share = 2 ** len(tm.layout.planes)       # a half or quarter model carries its share of the force
    load = PatchLoad(pressure=ld.pressure) if ld.kind == "pressure" else \
        PatchLoad(force=ld.force / share, profile=ld.profile if ld.kind == "probe" else "flat")
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
    """The rigid indenter of a `[load] kind = "probe"`, `contact = true` scene, centred
    on the layout's load patch."""
    ld = scene.load
    if ld.kind != "probe" or not ld.contact:
        return None
    edge = ld.edge_radius if ld.edge_radius is not None else ld.radius / 20
    return Indenter(ld.shape, ld.radius, edge if ld.shape == "flat" else 0.0,
                    (tm.layout.load.x, tm.layout.load.y), ld.travel, None if ld.travel is not None else ld.force,
                    "sticking" if ld.friction is None else ld.friction)


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


def solve_model(scene: Scene, solver: str = "auto", tagged_mesh: TaggedMesh | None = None,
                scale: bool = True, newton_options: dict | None = None) -> StaticResult:
    """Solve a scene's static load case on the model it gives (model.fidelity is not
    read here: taxel.analyses.solve_static resolves "auto" by the model choice), meshing it unless
    `tagged_mesh` is given. With a Yeoh silicone, `newton_options` go to
    fem.hyperelastic.newton (tol, max_iter, first_step, stepping, line_search)."""
    t0 = time.perf_counter()
    logging.getLogger(__name__).info("%s: meshing the %s model", scene.name, scene.model.type)
    prob = problem(scene, tagged_mesh)
    t1 = time.perf_counter()
    if scene.model.silicone != "auto":
        return _solve(scene, prob, solver, scale, newton_options, t0, t1)
    try:
        lin = _solve(scene, with_silicone(prob, "linear"), solver, scale, newton_options, t0, t1)
    except contact.PressError as exc:      # a linear silicone under a punch can fail where Yeoh does not
        hyper = _solve(scene, with_silicone(prob, "yeoh"), solver, scale, newton_options, t0, t1)
        hyper.model_note = f"auto: Yeoh silicone (the linear press failed: {exc})"
        return hyper
    est, tol = linear_error(lin.max_strain), scene.model.tolerance
    if est <= tol:
        lin.model_note = (f"auto: linear silicone (largest strain {100 * lin.max_strain:.1f} %, "
                          f"estimated voltage error {100 * est:.2g} % <= {100 * tol:g} %)")
        return lin
    t1 = time.perf_counter()
    try:
        hyper = _solve(scene, with_silicone(prob, "yeoh"), solver, scale, newton_options, t1, t1)
    except (NewtonError, contact.PressError) as exc:
        lin.model_note = (f"auto: Yeoh silicone needed (linear error about {100 * est:.2g} %) but {exc}; "
                          f"returning the LINEAR result")
        return lin
    hyper.model_note = f"auto: Yeoh silicone (the linear model would err by about {100 * est:.2g} %)"
    return hyper


def _solve(scene, prob, solver, scale, newton_options, t0, t1) -> StaticResult:
    sy = assembly.assemble(prob)
    t2 = time.perf_counter()
    logging.getLogger(__name__).info("%s: solving (%s)", scene.name, "press" if prob.indenter is not None else
                                     "Yeoh silicone, Newton" if prob.hyperelastic else "linear")
    if prob.indenter is not None:
        opts = {k: v for k, v in (newton_options or {}).items() if k in contact.Options.__dataclass_fields__}
        sol = contact.press(sy, prob.indenter, solver, contact.Options(**opts))
    elif prob.hyperelastic:
        sol = hyperelastic.solve_yeoh(sy, solver, **(newton_options or {}))
    else:
        sol = static.solve_linear(sy, solver, scale)
    t3 = time.perf_counter()
    return StaticResult(scene, sol, {"mesh": t1 - t0, "assemble": t2 - t1, "solve": t3 - t2, "total": t3 - t0},
                        yeoh=prob.hyperelastic)
