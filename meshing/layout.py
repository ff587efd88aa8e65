"""From a scene to a layered layout: a plan (1D for 2D/axisymmetric models, 2D for 3D),
patches in it (taxel footprints, the load footprint), and a stack of layers.

Every scene this tool takes is a layered stack: bottom silicone, the piezo layer
(piezo inside the taxel footprints, silicone between them), top silicone; or,
for verification plates, full-width layers. Pure geometry, no gmsh.

Plan coordinates: x (and y in 3D), centred on the array or plate. A 2D model is
the x-z cross-section through the loaded taxel's row. An axisymmetric model
turns a square taxel of width w into a disk of equal area (radius w / sqrt(pi))
and the domain into a disk of radius (that radius + margin).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from fem import materials
from studies.scene import Scene, SceneError, user_materials


@dataclass(frozen=True)
class Patch:
    """A region of the plan: a square (half-width `half`) or a disk (radius `half`)
    centred at (x, y). In a 1D plan both are the segment [x - half, x + half]."""

    name: str
    x: float
    y: float
    half: float
    shape: str = "square"

    def contains(self, x, y=0.0, tol=1e-12):
        if self.shape == "disk":
            return (x - self.x) ** 2 + (y - self.y) ** 2 <= (self.half + tol) ** 2
        return abs(x - self.x) <= self.half + tol and abs(y - self.y) <= self.half + tol

    @property
    def area_2d(self):
        return math.pi * self.half ** 2 if self.shape == "disk" else 4 * self.half ** 2


@dataclass(frozen=True)
class Layer:
    """One layer of the stack. Inside `patches` the material is `patch_material`
    (a piezo body per patch); elsewhere it is `material`."""

    name: str
    z0: float
    thickness: float
    material: str
    poling: int = 1                     # +1 up, -1 down (piezo only)
    patch_material: str | None = None
    patches: tuple[Patch, ...] = ()

    @property
    def z1(self):
        return self.z0 + self.thickness


@dataclass(frozen=True)
class Electrode:
    """An electrode at height z covering `patches` (all of the plan if empty)."""

    name: str
    z: float
    patches: tuple[Patch, ...] = ()


@dataclass(frozen=True)
class Layout:
    model: str                          # plane_strain | plane_stress | axisymmetric | 3d
    plan: Patch                         # the outline (a square/rectangle or a disk)
    plan_half_y: float                  # y half-extent of a rectangle (3D)
    layers: tuple[Layer, ...]
    electrodes: tuple[Electrode, ...]
    load: Patch | None                  # None: the whole top
    load_profile: str = "flat"
    taxels: tuple[Patch, ...] = ()
    depth: float = 1.0                  # 2D out-of-plane depth (m)
    size: float = 5e-4
    piezo_size: float = 1.25e-4
    piezo_layers: int = 1
    midplane: float | None = None       # z of a simply supported mid-plane line

    @property
    def dim(self):
        return 3 if self.model == "3d" else 2

    @property
    def height(self):
        return self.layers[-1].z1

    @property
    def x_range(self):
        if self.model == "axisymmetric":
            return 0.0, self.plan.half
        return self.plan.x - self.plan.half, self.plan.x + self.plan.half

    def breakpoints(self) -> list[float]:
        """x of every patch edge in a 1D plan, sorted, inside the outline."""
        x0, x1 = self.x_range
        xs = {x0, x1}
        for p in self.taxels + ((self.load,) if self.load else ()):
            xs.update((p.x - p.half, p.x + p.half))
        return sorted(x for x in xs if x0 - 1e-12 <= x <= x1 + 1e-12)


def layout(scene: Scene) -> Layout:
    """The layered layout of a scene (raises SceneError for geometry that cannot be built)."""
    m, mesh = scene.model, scene.mesh
    common = dict(model=m.type, size=mesh.size, piezo_layers=mesh.piezo_layers)
    if scene.array is not None:
        return _array_layout(scene, common)
    return _plate_layout(scene, common)


def _array_layout(scene: Scene, common) -> Layout:
    a, ld, model = scene.array, scene.load, scene.model.type
    w, pitch = a.taxel_width, a.taxel_width + a.gap
    axisym = model == "axisymmetric"
    half = w / math.sqrt(math.pi) if axisym else w / 2
    shape = "disk" if axisym else "square"

    def centre(r, c):
        return (c - (a.cols - 1) / 2) * pitch, ((a.rows - 1) / 2 - r) * pitch

    cells = [(r, c) for r in range(a.rows) for c in range(a.cols)]
    if model != "3d":                       # 2D: the row through the loaded taxel
        cells = [(r, c) for r, c in cells if r == ld.taxel[0]]
    taxels = tuple(Patch(f"taxel_{r}_{c}", *(centre(r, c) if model == "3d" else (centre(r, c)[0], 0.0)),
                         half, shape) for r, c in cells)
    if axisym:
        plan = Patch("plan", 0.0, 0.0, half + a.margin, "disk")
        half_y = plan.half
    else:
        plan = Patch("plan", 0.0, 0.0, (a.cols * w + (a.cols - 1) * a.gap) / 2 + a.margin)
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
    if a.silicone_above > 0:
        layers.append(Layer("silicone_above", piezo.z1, a.silicone_above, a.silicone))
    electrodes = tuple(Electrode(t.name, piezo.z1, (t,)) for t in taxels) + (
        Electrode("ground", piezo.z0, taxels),)
    depth = scene.model.depth or w
    return Layout(plan=plan, plan_half_y=half_y, layers=tuple(layers), electrodes=electrodes,
                  load=load, load_profile=ld.profile if ld.kind == "indenter" else "flat",
                  taxels=taxels, depth=depth,
                  piezo_size=scene.mesh.piezo_size or scene.mesh.size / 4, **common)


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
    if ld.kind == "indenter":
        return Patch("load", x + ld.offset[0], y + (ld.offset[1] if model == "3d" else 0.0),
                     ld.radius, "disk" if model in ("3d", "axisymmetric") else "square")
    return Patch("load", x, y, half, shape)


def _plate_layout(scene: Scene, common) -> Layout:
    p, model = scene.plate, scene.model.type
    if p.shape == "disk":
        plan = Patch("plan", 0.0, 0.0, p.radius, "disk")
        half_y = p.radius
    else:
        plan = Patch("plan", 0.0, 0.0, p.width / 2)
        half_y = (p.length or p.width) / 2
    layers, z = [], 0.0
    for i, L in enumerate(p.layers):
        layers.append(Layer(f"layer{i}", z, L.thickness, L.material, 1 if L.poling == "up" else -1))
        z += L.thickness
    midplane = None
    if scene.supports.edges == "simply_supported":
        midplane = z / 2
        layers = _split_at(layers, midplane)
    load = None
    if scene.load.kind == "indenter":
        ld = scene.load
        load = Patch("load", ld.offset[0], ld.offset[1] if model == "3d" else 0.0, ld.radius,
                     "disk" if model in ("3d", "axisymmetric") else "square")
    # electrodes on every interface that touches a piezo layer (named bottom, interface<k>, top)
    user = user_materials(scene)
    levels = sorted({round(L.z0, 15) for L in layers} | {round(z, 15)})
    piezo_levels = set()
    for L in layers:
        if isinstance(materials.get(L.material, user), materials.Piezo):
            piezo_levels.update((round(L.z0, 15), round(L.z1, 15)))
    interfaces = sorted({round(L.z0, 15) for L in _unsplit(p)} | {round(z, 15)})
    names = {lv: ("bottom" if k == 0 else "top" if k == len(interfaces) - 1 else f"interface{k}")
             for k, lv in enumerate(interfaces)}
    electrodes = tuple(Electrode(names[lv], lv) for lv in levels if lv in piezo_levels and lv in names)
    depth = scene.model.depth or 1.0
    return Layout(plan=plan, plan_half_y=half_y, layers=tuple(layers), electrodes=electrodes,
                  load=load, load_profile=scene.load.profile, depth=depth,
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
            out.append(Layer(L.name, L.z0, zc - L.z0, L.material, L.poling))
            out.append(Layer(L.name, zc, L.z1 - zc, L.material, L.poling))
        else:
            out.append(L)
    return out
