"""What a layout's mesh will cost, before gmsh is asked to make it.

The plan is meshed with the size field of meshing.build (piezo_size at taxel and
load edges, growing linearly to size over 2 size, at most 2 piezo_size inside
taxels) and extruded layer by layer (meshing.sizes.vertical_divisions, counted in closed form). The count
of plan elements is the integral of the element density over the plan,
1 / h(x) per length on a line, 4 / (sqrt(3) h^2) triangles per area on a face
(equilateral triangles of side h), sampled on a grid. Vertices follow from
Euler's relation (V ~ T / 2 for triangles). Good to a factor of about 1.5
(tests/test_hostile_input.py compares it with real meshes): enough to refuse a
request that cannot fit before it starts (`solve_cost`: the memory of the solve of
those unknowns, direct or Krylov as the caller's solver choice says). A free 3D layout (Layout.free: the silicone
meshed by the 3D mesher) is counted as if extruded, an overestimate (the 3D press's
default mesh: 1.95x its elements, 1.44x its vertices), which is the safe side for a refusal.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

from taxel.meshing.layout import Layout, is_graded

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
    """Elements through a layer (meshing.sizes.vertical_divisions, in closed form):
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


# Memory of a sparse direct solve per unknown, measured (benchmarks/taxel_2d.py; in 3D the
# 8x8 array of benchmarks/array_8x8.py: 3.7 GB peak at 202k unknowns, with fem.assembly's
# LazyBasis); in 3D the fill grows about as n^(1/3) more. Out of core (fem.linalg)
# the factors go to files: what stays is the assembled and reduced matrices and the mesh
# (1.5 GB at 202k unknowns) and the factors' share in memory.
BYTES_PER_UNKNOWN_2D = 3e3
BYTES_PER_UNKNOWN_3D = 18.3e3
REFERENCE_UNKNOWNS_3D = 202e3
BYTES_PER_UNKNOWN_OUT_OF_CORE = 7.5e3
BYTES_PER_UNKNOWN_KRYLOV = 20e3      # the Krylov solver's memory is about linear (benchmarks/array_8x8.py)
# mesh_cost's 3D unknowns against the meshes gmsh made: 1.29 (thesis-pzt-single-3d),
# 1.54 and 1.72 (the 3x3 array at its own and at array_8x8's mesh), 1.61 (the 8x8 array)
UNKNOWNS_3D_PER_ESTIMATE = 1.6


def machine_memory() -> float:
    """Physical memory of this machine, bytes."""
    return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))


@dataclass(frozen=True)
class SolveLimit:
    """What a mesh's solve is costed as: its element order and whether the caller's solver
    choice (fem.linalg.resolve) is the Krylov solver."""

    order: int
    krylov: bool = False


@dataclass(frozen=True)
class SolveCost:
    """What the solve of a layout's mesh is estimated to need, against this machine."""

    unknowns: float
    bytes: float
    memory: float            # this machine's physical memory, bytes

    @property
    def fits(self) -> bool:
        return self.bytes <= 0.8 * self.memory


def estimated_unknowns(lay: Layout, order: int) -> float:
    """The unknowns of the layout's mesh at element order `order` (3D: scaled to what
    gmsh makes, UNKNOWNS_3D_PER_ESTIMATE)."""
    n = mesh_cost(lay).unknowns(lay.dim, order)
    return n if lay.dim == 2 else n * UNKNOWNS_3D_PER_ESTIMATE


def solve_cost(lay: Layout, order: int, krylov: bool = False) -> SolveCost:
    """The estimated unknowns and bytes of the solve of a layout's mesh: a direct solve
    in memory, or out of core where that would not fit this machine (3D), or with
    `krylov` (the caller's solver choice, fem.linalg.resolve) the Krylov solver."""
    return unknowns_cost(estimated_unknowns(lay, order), lay.dim, krylov)


def unknowns_cost(n: float, dim: int, krylov: bool = False) -> SolveCost:
    """The bytes of the solve of n unknowns in a `dim` model (solve_cost's memory model)."""
    have = machine_memory()
    if dim == 2:
        return SolveCost(n, n * BYTES_PER_UNKNOWN_2D, have)
    if krylov:
        return SolveCost(n, n * BYTES_PER_UNKNOWN_KRYLOV, have)
    need = n * BYTES_PER_UNKNOWN_3D * max(n / REFERENCE_UNKNOWNS_3D, 1e-3) ** (1 / 3)
    if need > 0.8 * have:
        need = n * BYTES_PER_UNKNOWN_OUT_OF_CORE + 0.2 * have
    return SolveCost(n, need, have)


class MeshTooLarge(ValueError):
    """A mesh whose solve cannot fit this machine's memory (`cost`), refused before it is made."""

    def __init__(self, cost: SolveCost):
        self.cost = cost
        super().__init__(f"about {cost.unknowns:.3g} unknowns, needing about {cost.bytes / 1e9:.3g} GB for the "
                         f"solve, more than this machine's {cost.memory / 1e9:.3g} GB")


def check_fits(lay: Layout, limit: SolveLimit) -> SolveCost:
    """The solve cost of a layout's mesh, or MeshTooLarge where it cannot fit this machine."""
    cost = solve_cost(lay, limit.order, limit.krylov)
    if not cost.fits:
        raise MeshTooLarge(cost)
    return cost
