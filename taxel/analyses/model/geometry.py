"""From a scene to its layered layout (meshing.layout), refused when its solve cannot
fit this machine: the geometry half of the translation from the scene schema to the
finite-element model (taxel.analyses.model.problem makes the other half).

A 2D model is the x-z cross-section through the loaded taxel's row. An
axisymmetric model turns a square taxel of width w into a disk of equal area
(radius w / sqrt(pi)) and the square outline (w + 2 margin) into the disk of
equal area, radius (w + 2 margin) / sqrt(pi). Measured against the 3D taxel
(benchmarks/axisymmetric_radius.py, 297k unknowns): the pressed-taxel voltage is
+0.91 % off with this outline, +1.74 % with the radius w / sqrt(pi) + margin; the
capacitance is the same to 1e-5 with either.

Symmetry. A half or quarter model (fem.static) answers for the full one when
the array, its outline and supports are symmetric about the planes, the press
is centred on them and the electrode states are mirror images (`mirror_planes`).

Cost. `solve_limit` says what the layout's solve is costed as (its order, and the
solver fem.linalg.resolve picks for it); meshing refuses a mesh that cannot fit
(meshing.cost.check_fits, also at meshing.build.build), and `too_large` says so in
the scene's keys.
"""

from __future__ import annotations

import math

from taxel.fem import linalg
from taxel.fem import constitution
from taxel.meshing.cost import MeshTooLarge, SolveLimit, check_fits, estimated_unknowns
from taxel.meshing import hexmesh
from taxel.meshing.layout import Electrode, Layer, Layout, Patch, cut
from taxel.scene import DEFAULT_PRESS_MESH, Scene, SceneError, electrode_state
from taxel.schema import electrode_name


def mirror_planes(scene: Scene) -> tuple[tuple[int, ...], str]:
    """The mirror planes (0: x = 0, 1: y = 0) of a scene's static press, and
    why it has no other: the array, its outline and supports are symmetric about
    both; the press must be centred on the plane and the electrode states mirrored."""
    m, a, ld = scene.model, scene.array, scene.load
    if a is None or m.type == "axisymmetric":
        return (), "symmetric models are built for arrays in plane or 3d models"
    if scene.analysis.type != "static" or (m.silicone != "linear" and not ld.contact):
        return (), ("symmetric models solve the static press: linear silicone, or any silicone "
                    "under a rigid indenter (load.contact)")
    states = scene.electrodes
    if electrode_state(states.get("ground", "ground")) != "ground":
        return (), "the common ground is not grounded (electrodes.ground), so the reference is off the planes"

    def state(r, c):
        s = states.get(electrode_name(r, c), states.get("taxels", "open"))
        return electrode_state(s)

    planes, why = [], ""
    for k in ((0, 1) if m.type == "3d" else (0,)):
        n, i = (a.cols, 1) if k == 0 else (a.rows, 0)      # x runs along columns, y along rows
        pos = ld.taxel[i] + (ld.neighbour[i] if ld.kind == "between" else ld.taxel[i])
        centre = (pos - (n - 1)) / 2 * a.pitch * (1 if k == 0 else -1) + (
            ld.offset[k] if ld.kind == "probe" else 0)              # the press's x or y
        rows = range(a.rows) if m.type == "3d" else (ld.taxel[0],)
        mirrored = all(state(r, c) == (state(r, a.cols - 1 - c) if k == 0 else state(a.rows - 1 - r, c))
                       for r in rows for c in range(a.cols))
        if ld.kind != "pressure" and abs(centre) > 1e-9 * a.taxel_width:
            why = f"the press is not centred on {'xy'[k]} = 0 (load.taxel, load.offset)"
        elif not mirrored:
            why = f"the electrode states are not mirror images across {'xy'[k]} = 0 ([electrodes])"
        else:
            planes.append(k)
    return tuple(planes), why


def symmetry_planes(scene: Scene) -> tuple[int, ...]:
    """The planes the model is cut at (fem.static): model.symmetry = "full" none;
    "half" x = 0 (or y = 0); "quarter" both; "auto" all the scene allows in 3d and
    under a rigid indenter, none for other 2D presses (a linear 2D solve takes a
    second, and plots show the whole section; a press takes a few: half is 3x faster)."""
    planes, _ = mirror_planes(scene)
    sym = scene.model.symmetry
    if sym == "full" or (sym == "auto" and scene.model.type != "3d" and not scene.load.contact):
        return ()
    return planes[:1] if sym == "half" else planes


def layout(scene: Scene, mats: dict) -> Layout:
    """The layered layout of a scene; `mats` maps material names to materials
    (raises SceneError for geometry that cannot be built)."""
    m, mesh = scene.model, scene.mesh
    common = dict(model=m.type, size=mesh.size, piezo_layers=mesh.piezo_layers)
    if scene.array is not None:            # a half or quarter of a symmetric array (model.symmetry)
        planes = symmetry_planes(scene)
        whole = _array_layout(scene, common)
        lay = cut(whole, planes) if planes else whole
    else:
        lay = _plate_layout(scene, common, mats)
    why = hexmesh.supports(lay) if mesh.element == "hex" else ""
    if why:
        raise SceneError(why)
    return lay


def _array_layout(scene: Scene, common) -> Layout:
    a, ld, model = scene.array, scene.load, scene.model.type
    w, pitch = a.taxel_width, a.pitch
    axisym = model == "axisymmetric"
    half = w / math.sqrt(math.pi) if axisym else w / 2
    shape = "disk" if axisym else "square"

    def centre(r, c):
        return (c - (a.cols - 1) / 2) * pitch, ((a.rows - 1) / 2 - r) * pitch

    cells = [(r, c) for r in range(a.rows) for c in range(a.cols)]
    if model != "3d":                       # 2D: the row through the loaded taxel
        cells = [(r, c) for r, c in cells if r == ld.taxel[0]]
    taxels = tuple(Patch(electrode_name(r, c), *(centre(r, c) if model == "3d" else (centre(r, c)[0], 0.0)),
                         half, shape) for r, c in cells)
    if axisym:                              # the outline's equal-area disk (closer to 3D, see the docstring)
        plan = Patch("plan", 0.0, 0.0, (w + 2 * a.margin) / math.sqrt(math.pi), "disk")
        half_y = plan.half
    else:
        plan = Patch("plan", 0.0, 0.0, a.footprint / 2)
        half_y = (a.rows * w + (a.rows - 1) * a.gap) / 2 + a.margin

    load = _load_patch(scene, centre, half, model)
    if load is not None:
        inside = (abs(load.x) + load.half <= plan.half * (1 + 1e-9)
                  and (model != "3d" or abs(load.y) + load.half <= half_y * (1 + 1e-9)))
        if not inside:
            raise SceneError("load: the load footprint lies (partly) outside the sensor; "
                             "move it (load.offset) or make it smaller")

    z, layers = 0.0, []
    if a.silicone_below > 0:
        layers.append(Layer("silicone_below", 0.0, a.silicone_below, a.silicone))
        z = a.silicone_below
    piezo = Layer("piezo", z, a.piezo_thickness, a.silicone, 1 if a.poling == "up" else -1,
                  a.piezo, taxels)
    layers.append(piezo)
    top = z + a.piezo_thickness             # the taxel electrodes' height
    if a.silicone_above > 0:
        layers.append(Layer("silicone_above", top, a.silicone_above, a.silicone))
    electrodes = tuple(Electrode(t.name, top, (t,)) for t in taxels) + (
        Electrode("ground", piezo.z0, taxels),)
    depth = scene.model.depth or w
    return Layout(plan=plan, plan_half_y=half_y, layers=tuple(layers), electrodes=electrodes,
                  load=load, taxels=taxels, depth=depth,
                  piezo_size=scene.mesh.piezo_size or scene.mesh.size / 4, **common, **punch_grading(scene))


def punch_grading(scene: Scene) -> dict:
    """The contact-aware grading of a 3D scene pressed by a flat punch (meshing.build):
    elements of the punch's edge radius under its rounded edge and at the top surface,
    but not below half the taxel edges' size (a coarse `[mesh]` stays coarse). With the
    default mesh (taxel.scene.DEFAULT_PRESS_MESH), or mesh.extruded = false, the silicone is meshed free
    (meshing.layout.Layout.free: graded at the rim on the top surface and at the taxel
    edges on the piezo's faces only; benchmarks/press_3d_mesh.py), and the taxels the punch does not
    touch coarser (FAR_TAXEL).

    A `[mesh]` finer or coarser than the default press mesh is the same size field divided: the rim's
    size is divided as the taxel edges' size is (from its default, max(edge radius, half the default
    edge size)), and the distance over which the sizes grow is the default's, PRESS_GROWTH (not
    growth x size: that distance shrank with the sizes, so the graded zone was not refined and the
    press did not converge; benchmarks/press_directions.py --sizes, docs/benchmarks.md)."""
    ld = scene.load
    if not scene.pressed_by_punch:
        return {}
    edge = ld.edge_radius if ld.edge_radius is not None else ld.radius / 20
    piezo = scene.mesh.piezo_size or scene.mesh.size / 4
    scale = piezo / DEFAULT_PRESS_MESH[1]            # 1 at the default press mesh
    free = dict(free=True, far_taxel=FAR_TAXEL) if scene.mesh.extruded is False else {}
    grading = dict(contact_size=scale * max(edge, DEFAULT_PRESS_MESH[1] / 2), rim=edge,
                   growth=PRESS_GROWTH / scene.mesh.size)
    return dict(grading, **free) if edge > 0 else free


# m: the distance over which a press mesh's sizes grow from the taxel edges' and the rim's to the far
# size: the default press mesh's (growth 2 x its 1.4 mm), kept when a [mesh] divides the sizes
PRESS_GROWTH = 2 * DEFAULT_PRESS_MESH[0]


# A free press mesh's taxels the punch does not touch: their edges at this x the taxel edges' size
# (meshing.layout.Layout.far_taxel). On the 3x3 thesis array pressed at its centre (the default press
# mesh, benchmarks/press_speed.py --levers 3x3, one run at load 5-6): 1 (every taxel alike) 34 482
# unknowns, 79 s of CPU; 2: 20 292, 35 s, V/F -0.26 %, crosstalk +1.7 % (relative); 3: 17 935, 28 s,
# V/F -0.29 %, crosstalk -0.6 %; at sizes / 1.41 the V/F difference is 0.09 % (a mesh effect that
# converges), and the 3x3 / single-taxel ratio moves less under refinement with 3 than with 1
# (0.09 % against 0.30 %; docs/benchmarks.md, "The 3D press in seconds"). A single taxel is unchanged.
FAR_TAXEL = 3.0


def _load_patch(scene: Scene, centre, half, model) -> Patch | None:
    ld = scene.load
    if ld.kind == "pressure":
        return None
    shape = "disk" if model == "axisymmetric" else "square"
    x, y = centre(*ld.taxel)
    if ld.kind == "between":
        if model != "3d" and ld.neighbour[0] != ld.taxel[0]:
            raise SceneError("load.neighbour: a 2D model is the cross-section of one row; "
                             "press between taxels of the same row or use a 3d model")
        x2, y2 = centre(*ld.neighbour)
        x, y = (x + x2) / 2, (y + y2) / 2
    if model != "3d":
        y = 0.0
    if ld.kind == "probe":
        return Patch("load", x + ld.offset[0], y + (ld.offset[1] if model == "3d" else 0.0),
                     ld.radius, "disk" if model in ("3d", "axisymmetric") else "square")
    return Patch("load", x, y, half, shape)


def _plate_layout(scene: Scene, common, mats) -> Layout:
    p, model = scene.plate, scene.model.type
    if p.shape == "disk":
        plan = Patch("plan", 0.0, 0.0, p.radius, "disk")
        half_y = p.radius
    else:
        plan = Patch("plan", 0.0, 0.0, p.width / 2)
        half_y = (p.length or p.width) / 2
    layers, z = [], 0.0
    for i, L in enumerate(p.layers):
        layers.append(Layer(f"layer{i}", z, L.thickness, L.material, 1 if L.poling == "up" else -1,
                            piezo=isinstance(mats[L.material], constitution.Piezo)))
        z += L.thickness
    midplane = None
    if scene.supports.edges == "simply_supported":
        midplane = z / 2
        layers = _split_at(layers, midplane)
    load = None
    if scene.load.kind == "probe":
        ld = scene.load
        load = Patch("load", ld.offset[0], ld.offset[1] if model == "3d" else 0.0, ld.radius,
                     "disk" if model in ("3d", "axisymmetric") else "square")
    # electrodes on every interface that touches a piezo layer (named bottom, interface<k>, top)
    levels = sorted({round(L.z0, 15) for L in layers} | {round(z, 15)})
    piezo_levels = set()
    for L in layers:
        if L.piezo:
            piezo_levels.update((round(L.z0, 15), round(L.z1, 15)))
    interfaces = sorted({round(L.z0, 15) for L in _unsplit(p)} | {round(z, 15)})
    names = {lv: ("bottom" if k == 0 else "top" if k == len(interfaces) - 1 else f"interface{k}")
             for k, lv in enumerate(interfaces)}
    electrodes = tuple(Electrode(names[lv], lv) for lv in levels if lv in piezo_levels and lv in names)
    depth = scene.model.depth or (p.width if p.width is not None else 2 * p.radius)
    return Layout(plan=plan, plan_half_y=half_y, layers=tuple(layers), electrodes=electrodes,
                  load=load, depth=depth,
                  piezo_size=scene.mesh.piezo_size or scene.mesh.size, midplane=midplane, **common)


def _unsplit(plate):
    z, out = 0.0, []
    for i, L in enumerate(plate.layers):
        out.append(Layer(f"layer{i}", z, L.thickness, L.material))
        z += L.thickness
    return out


def _split_at(layers, zc):
    """Split the layer that contains height zc in two (same material), so that a
    node line exists at zc."""
    out = []
    for L in layers:
        if L.z0 + 1e-12 < zc < L.z1 - 1e-12:
            out.append(Layer(L.name, L.z0, zc - L.z0, L.material, L.poling, piezo=L.piezo))
            out.append(Layer(L.name, zc, L.z1 - zc, L.material, L.poling, piezo=L.piezo))
        else:
            out.append(L)
    return out


def solve_limit(scene: Scene, lay: Layout) -> SolveLimit:
    """What the solve of the layout's mesh is costed as (meshing.cost): its order, and the
    Krylov solver where fem.linalg.resolve picks it (a static linear 3D solve that large)."""
    order = scene.mesh.order
    krylov = (scene.model.type == "3d" and scene.analysis.type == "static" and scene.model.silicone == "linear"
              and linalg.resolve("auto", estimated_unknowns(lay, order), iterative=True, dim=3) == "krylov")
    return SolveLimit(order, krylov)


def too_large(exc: MeshTooLarge) -> SceneError:
    """The scene's error for a mesh whose solve cannot fit this machine, with the fix."""
    return SceneError(f"mesh: {exc}; coarsen mesh.size / mesh.piezo_size or model less (a 2D or "
                      "axisymmetric model)")


def checked_layout(scene: Scene, mats: dict) -> Layout:
    """The scene's layout, refused (SceneError, with the estimate) when its mesh and
    solve cannot fit in this machine's memory (meshing.build refuses the same when
    given the `solve_limit`)."""
    lay = layout(scene, mats)
    try:
        check_fits(lay, solve_limit(scene, lay))
    except MeshTooLarge as exc:
        raise too_large(exc) from None
    return lay
