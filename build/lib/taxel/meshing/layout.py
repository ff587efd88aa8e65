"""A layered layout: a plan (1D for 2D/axisymmetric models, 2D for 3D), patches in
it (taxel footprints, the load footprint), and a stack of layers.

Every scene this tool takes is a layered stack: bottom silicone, the piezo layer
(piezo inside the taxel footprints, silicone between them), top silicone; or,
for verification plates, full-width layers. Pure geometry, no gmsh.

Plan coordinates: x (and y in 3D), centred on the array or plate. A 2D model is
the x-z cross-section through the loaded taxel's row. taxel.analyses.geometry
makes the layout of a scene.
"""

from __future__ import annotations

from dataclasses import dataclass



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
