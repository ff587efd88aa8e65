"""A layered layout: a plan (1D for 2D/axisymmetric models, 2D for 3D), patches in
it (taxel footprints, the load footprint), and a stack of layers.

Every scene this tool takes is a layered stack: bottom silicone, the piezo layer
(piezo inside the taxel footprints, silicone between them), top silicone; or,
for verification plates, full-width layers. Pure geometry, no gmsh.

Plan coordinates: x (and y in 3D), centred on the array or plate. A 2D model is
the x-z cross-section through the loaded taxel's row. taxel.analyses.model.geometry
makes the layout of a scene.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, replace



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
    piezo: bool = False                 # `material` is piezoelectric (a plate layer)

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
    taxels: tuple[Patch, ...] = ()
    depth: float = 1.0                  # 2D out-of-plane depth (m)
    size: float = 5e-4
    piezo_size: float = 1.25e-4
    piezo_layers: int = 1
    growth: float = 2.0                 # in-plane size grows from piezo_size at patch edges to size over growth x size
    taxel_cap: float = 2.0              # largest in-plane size inside a taxel, in piezo_size
    # the edges of taxels the load does not touch at far_taxel x piezo_size (at most size): a punch
    # on one taxel of an array strains its neighbours little, so they need fewer elements (1: no grading)
    far_taxel: float = 1.0
    # contact-aware grading under a punch (None: none): the in-plane size within `rim` of the
    # load edge (the punch's rounded edge, its radius) and the size at the top surface
    contact_size: float | None = None
    rim: float = 0.0                    # m, the width of the band under the punch's rounded edge
    # 3D: silicone layers meshed free (3D size field: taxel edges on the piezo's faces, the punch's
    # rim on the top surface) instead of extruded from the plan mesh (its grading at every height)
    free: bool = False
    midplane: float | None = None       # z of a simply supported mid-plane line
    planes: tuple[int, ...] = ()        # symmetry: cut at x = 0 (0) and/or y = 0 (1), keeping x, y >= 0
    # symmetry: every electrode of the full layout as (its name, the modelled electrode it
    # mirrors, the group element, one sign per plane, that maps the modelled one onto it)
    images: tuple[tuple[str, str, tuple[int, ...]], ...] = ()

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
        x0 = 0.0 if 0 in self.planes else self.plan.x - self.plan.half
        return x0, self.plan.x + self.plan.half

    @property
    def y_range(self):
        """Plan y extent (3D)."""
        y0 = 0.0 if 1 in self.planes else self.plan.y - self.plan_half_y
        return y0, self.plan.y + self.plan_half_y

    def near_load(self, p: Patch) -> bool:
        """The patch overlaps the load's footprint (every patch does with no load patch)."""
        if self.load is None:
            return True
        gap = max(abs(p.x - self.load.x), abs(p.y - self.load.y) if self.dim == 3 else 0.0)
        return gap < p.half + self.load.half

    def breakpoints(self) -> list[float]:
        """x of every patch edge in a 1D plan, sorted, inside the outline."""
        x0, x1 = self.x_range
        xs = {x0, x1}
        for p in self.taxels + ((self.load,) if self.load else ()):
            xs.update((p.x - p.half, p.x + p.half))
        return sorted(x for x in xs if x0 - 1e-12 <= x <= x1 + 1e-12)


def is_graded(lay: Layout, layer) -> bool:
    """Silicone layers of an array are graded from piezo_size (next to the piezo)
    to size; piezo and plate layers get piezo_layers elements through."""
    return not (layer.patch_material is not None or layer.piezo or not lay.taxels)


def group(planes: tuple[int, ...]) -> list[tuple[int, ...]]:
    """The mirror group of symmetry planes: one sign per plane (-1: mirrored across
    it), the identity first. Also its characters (a class's sign per plane)."""
    return list(itertools.product((1, -1), repeat=len(planes)))


def cut(lay: Layout, planes: tuple[int, ...]) -> Layout:
    """The part x >= 0 (plane 0) and/or y >= 0 (plane 1) of a layout that is mirror
    symmetric about those planes (the caller checks it is): the taxels with a part
    there, their electrodes, and `images`: which modelled electrode each electrode
    of the full layout mirrors (taxel names are the patch names)."""
    if not planes:
        return lay
    tol = 1e-9 * max(lay.plan.half, lay.plan_half_y)

    def kept(p):
        return all((p.x, p.y)[k] > -tol for k in planes)

    def image(p, g):
        x, y = p.x, p.y
        for k, s in zip(planes, g):
            if k == 0:
                x *= s
            else:
                y *= s
        return next(q for q in lay.taxels if abs(q.x - x) < tol and abs(q.y - y) < tol)

    taxels = tuple(p for p in lay.taxels if kept(p))
    identity = group(planes)[0]
    electrodes, images = [], []
    for el in lay.electrodes:
        if el.name == "ground" or not el.patches:      # the common ground: its own image
            electrodes.append(replace(el, patches=tuple(p for p in el.patches if kept(p))))
            images.append((el.name, el.name, identity))
            continue
        if kept(el.patches[0]):
            electrodes.append(el)
        g = next(g for g in group(planes) if kept(image(el.patches[0], g)))
        images.append((el.name, image(el.patches[0], g).name, g))
    layers = tuple(replace(L, patches=tuple(p for p in L.patches if kept(p))) for L in lay.layers)
    return replace(lay, taxels=taxels, electrodes=tuple(electrodes), layers=layers, planes=tuple(planes),
                   images=tuple(images))
