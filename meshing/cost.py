"""What a layout's mesh will cost, before gmsh is asked to make it.

The plan is meshed with the size field of meshing.build (piezo_size at taxel and
load edges, growing linearly to size over 2 size, at most 2 piezo_size inside
taxels) and extruded layer by layer (meshing.build.vertical_divisions, counted in closed form). The count
of plan elements is the integral of the element density over the plan,
1 / h(x) per length on a line, 4 / (sqrt(3) h^2) triangles per area on a face
(equilateral triangles of side h), sampled on a grid. Vertices follow from
Euler's relation (V ~ T / 2 for triangles). Good to a factor of about 1.5
(tests/test_hostile_input.py compares it with real meshes): enough to refuse a
request that cannot fit before it starts. A free 3D layout (Layout.free: the silicone
meshed by the 3D mesher) is counted as if extruded, an overestimate (the 3D press's
default mesh: 1.95x its elements, 1.44x its vertices), which is the safe side for a refusal.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from taxel.meshing.build import is_graded
from taxel.meshing.layout import Layout

SAMPLES = 2000           # grid points per plan direction (1D: per line)


@dataclass(frozen=True)
class MeshCost:
    vertices: float          # mesh vertices
    elements: float          # triangles (2D) or tetrahedra (3D)

    def unknowns(self, dim: int, order: int) -> float:
        """Displacement (P2: vertices + edges), pressure (P1) and potential unknowns."""
        edges = (3.0 if dim == 2 else 7.0) * self.vertices
        nodes = self.vertices + edges if order == 2 else self.vertices + self.elements   # P2, or P1 + bubble
        return dim * nodes + self.vertices


def _size(lay: Layout, x, y):
    """The element size at plan points (x, y), as meshing.build's size field."""
    h = np.full(np.shape(x), lay.size, dtype=float)
    edges = list(lay.taxels) + ([lay.load] if lay.load else [])
    for p in edges:
        if lay.dim == 2:
            d = np.abs(np.abs(x - p.x) - p.half)
        else:
            dx, dy = np.abs(x - p.x), np.abs(y - p.y)
            outside = np.hypot(np.maximum(dx - p.half, 0), np.maximum(dy - p.half, 0))
            d = np.where((dx <= p.half) & (dy <= p.half), np.minimum(p.half - dx, p.half - dy), outside)
        h = np.minimum(h, lay.piezo_size + (lay.size - lay.piezo_size) * np.clip(d / (lay.growth * lay.size), 0, 1))
    if lay.contact_size is not None and lay.load is not None:     # the band under a punch's rounded edge
        p, hc = lay.load, min(lay.contact_size, lay.piezo_size)
        d = np.abs(np.hypot(x - p.x, y - p.y) - p.half) if lay.dim == 3 else np.abs(np.abs(x - p.x) - p.half)
        h = np.minimum(h, hc + (lay.size - hc) * np.clip((d - lay.rim) / (lay.growth * lay.size), 0, 1))
    for p in lay.taxels:
        inside = np.abs(x - p.x) <= p.half
        if lay.dim == 3:
            inside &= np.abs(y - p.y) <= p.half
        h = np.where(inside, np.minimum(h, lay.taxel_cap * lay.piezo_size), h)
    return h


def _divisions(lay: Layout, layer) -> float:
    """Elements through a layer (meshing.build.vertical_divisions, in closed form):
    sizes piezo_size * 1.5^k up to size, then size."""
    if not is_graded(lay, layer):
        return lay.piezo_layers
    if lay.contact_size is not None and layer is lay.layers[-1] and layer.name != "silicone_below":
        h = max(min(lay.contact_size, lay.size), 1e-9 * layer.thickness)   # graded from the top as well
        extra = max(np.ceil(np.log(lay.size / h) / np.log(1.5)), 0)
        return _one_sided(lay, layer) + extra
    return _one_sided(lay, layer)


def _one_sided(lay: Layout, layer) -> float:
    k = max(np.ceil(np.log(lay.size / lay.piezo_size) / np.log(1.5)), 0)
    graded = lay.piezo_size * (1.5 ** k - 1) / 0.5
    if graded >= layer.thickness:
        return max(np.log(1 + 0.5 * layer.thickness / lay.piezo_size) / np.log(1.5), 1.0)
    return k + (layer.thickness - graded) / lay.size


def mesh_cost(lay: Layout) -> MeshCost:
    """Estimated vertices and elements of the layout's mesh."""
    layers = sum(_divisions(lay, layer) for layer in lay.layers)
    x0, x1 = lay.x_range
    if lay.dim == 2:
        x = np.linspace(x0, x1, SAMPLES)
        segments = float(np.trapezoid(1.0 / _size(lay, x, 0.0), x))
        return MeshCost((segments + 1) * (layers + 1), 2 * segments * layers)
    y0, y1 = lay.y_range
    x, y = np.meshgrid(np.linspace(x0, x1, SAMPLES // 4), np.linspace(y0, y1, SAMPLES // 4), indexing="ij")
    density = 4.0 / (np.sqrt(3.0) * _size(lay, x, y) ** 2)
    area_factor = np.pi / 4 if lay.plan.shape == "disk" else 1.0       # (symmetry cuts: rectangles only)
    triangles = float(density.mean() * (x1 - x0) * (y1 - y0) * area_factor)
    return MeshCost(triangles / 2 * (layers + 1), 3 * triangles * layers)
