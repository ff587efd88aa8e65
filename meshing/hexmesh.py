"""Structured hexahedral meshes of layered 3D layouts (scikit-fem's MeshHex.init_tensor).

A tensor-product grid x_i, y_j, z_k whose planes sit on every layer interface (the piezo's
faces, the electrodes), every taxel edge and the symmetry planes: each hexahedron lies in
one layer and one material, so no element straddles an interface. Plan lines
(`axis_lines`): a target size h(s) along each axis, the smallest of
`size`; `piezo_size` at taxel edges growing by GROWTH per unit distance; and under a punch
`contact_size` over the whole footprint out to `rim` beyond its edge (a tensor grid cannot
follow the rim circle, so the footprint's square is fine throughout: the punch's rim crosses
it at every angle). The lines between two marks are spaced by the integral of 1/h
(equidistribution), so the marks are grid lines. Vertically the layers are divided as the
extruded tetrahedral meshes are (meshing.sizes.vertical_divisions): `piezo_layers` through
the piezo, silicone graded from `piezo_size` next to the piezo to `size`, under a punch the
top layer graded to `contact_size` at the top surface.

Tags are those of meshing.build: regions from the element centroids (a piezo body per taxel,
"piezo_0_0", else "silicone"); facets from their midpoints: "bottom", "top", "load" (a punch:
the whole top), "edges" (the outline), "mirror_x" / "mirror_y", one per electrode.

What it builds: 3D array layouts (square taxels, a rectangular outline) of any rows and
columns, whole, half or quarter, pressed by a punch or not. It refuses (HexMeshError, one line)
what a tensor grid cannot hold: a 2D or axisymmetric model, a disk outline or disk taxels,
a plate layout (no taxels).
"""

from __future__ import annotations

import numpy as np
import skfem

from taxel.meshing.build import TaggedMesh, region_name
from taxel.meshing.sizes import vertical_divisions
from taxel.meshing.cost import MeshTooLarge, SolveLimit, unknowns_cost
from taxel.meshing.layout import Layout

GROWTH = 0.5       # the size grows by this per unit distance from a mark (neighbouring cells x 1.5)


class HexMeshError(ValueError):
    """A layout the structured hexahedral mesher cannot build; one line with the fix."""


def supports(lay: Layout) -> str:
    """'' if the layout can be meshed with hexahedra, else why not (with the fix)."""
    if lay.dim != 3:
        return "mesh.element = 'hex' needs a 3d model (model.type = '3d'); use 'tet'"
    if lay.plan.shape == "disk" or any(p.shape == "disk" for p in lay.taxels):
        return "mesh.element = 'hex' needs a rectangular outline and square taxels; use 'tet'"
    if not lay.taxels:
        return "mesh.element = 'hex' meshes arrays (the [array] table), not plates; use 'tet'"
    return ""


def axis_lines(lo: float, hi: float, marks: list[tuple[float, float]], size: float,
               fine: list[tuple[float, float, float]] = ()) -> np.ndarray:
    """Grid lines on [lo, hi]: every mark (position, size there) a line; between them the
    spacing follows h(s) = min(size, min_m h_m + GROWTH |s - s_m|, h_f on the fine
    intervals (a, b, h_f)), by equidistribution of the integral of 1/h."""
    pos = sorted({lo, hi} | {float(np.clip(s, lo, hi)) for s, _ in marks}
                 | {float(np.clip(e, lo, hi)) for a, b, _ in fine for e in (a, b)})
    s = np.linspace(lo, hi, 4001)
    h = np.full_like(s, size)
    for m, hm in marks:
        h = np.minimum(h, hm + GROWTH * np.abs(s - m))
    for a, b, hf in fine:
        h = np.minimum(h, np.where((s >= a - 1e-12) & (s <= b + 1e-12), hf,
                                   hf + GROWTH * np.minimum(np.abs(s - a), np.abs(s - b))))
    cum = np.concatenate([[0.0], np.cumsum(np.diff(s) * 0.5 * (1 / h[1:] + 1 / h[:-1]))])
    lines = [lo]
    for a, b in zip(pos[:-1], pos[1:]):
        if b - a < 1e-12 * (hi - lo):
            continue
        ca, cb = np.interp([a, b], s, cum)
        n = max(1, int(np.ceil(cb - ca - 1e-6)))
        targets = ca + (cb - ca) * np.arange(1, n + 1) / n
        lines += list(np.interp(targets[:-1], cum, s)) + [b]
    return np.array(lines)


def z_lines(lay: Layout) -> np.ndarray:
    """Heights of the horizontal grid planes: every layer's faces, the divisions inside."""
    zs = [0.0]
    for layer in lay.layers:
        n, heights = vertical_divisions(lay, layer)     # ([k], [1.0]): k even; else one per fraction
        cum = np.arange(1, n[0] + 1) / n[0] if len(n) == 1 else np.asarray(heights)
        zs += list(layer.z0 + layer.thickness * cum)
    zs[-1] = lay.height
    return np.array(zs)


def plan_lines(lay: Layout) -> tuple[np.ndarray, np.ndarray]:
    """The x and y grid lines of the plan (the kept part of a cut layout)."""
    out = []
    for k, (lo, hi) in enumerate((lay.x_range, lay.y_range)):
        c = (lambda p: p.x) if k == 0 else (lambda p: p.y)
        marks = []
        for p in lay.taxels:
            h = min(lay.piezo_size * (1.0 if lay.near_load(p) else lay.far_taxel), lay.size)
            marks += [(c(p) - p.half, h), (c(p) + p.half, h)]
        fine = []
        if lay.load is not None and lay.contact_size is not None:
            reach = lay.load.half + max(lay.rim, lay.contact_size)
            fine.append((c(lay.load) - reach, c(lay.load) + reach, min(lay.contact_size, lay.piezo_size)))
        elif lay.load is not None:
            marks += [(c(lay.load) - lay.load.half, lay.piezo_size), (c(lay.load) + lay.load.half, lay.piezo_size)]
        out.append(axis_lines(lo, hi, marks, lay.size, fine))
    return out[0], out[1]


def unknowns(x, y, z, order: int) -> int:
    """The unknowns of the grid's displacement and pressure (Q2 / P1-disc or Q1 / P0), before supports."""
    nx, ny, nz = len(x) - 1, len(y) - 1, len(z) - 1
    nodes = (order * nx + 1) * (order * ny + 1) * (order * nz + 1)
    return 3 * nodes + (4 if order == 2 else 1) * nx * ny * nz


def build_hex(lay: Layout, limit: SolveLimit | None = None) -> TaggedMesh:
    """The structured hexahedral TaggedMesh of a 3D array layout (module docstring); `limit`:
    refuse first (MeshTooLarge, before the grid is made) a mesh whose solve cannot fit this
    machine (its unknowns counted from the grid lines, meshing.cost's memory model)."""
    why = supports(lay)
    if why:
        raise HexMeshError(why)
    x, y = plan_lines(lay)
    z = z_lines(lay)
    if limit is not None:
        cost = unknowns_cost(unknowns(x, y, z, limit.order), 3, limit.krylov)
        if not cost.fits:
            raise MeshTooLarge(cost)
    return tagged(lay, x, y, z)


def refined(tm: TaggedMesh, times: int = 1) -> TaggedMesh:
    """The uniform refinement of a hexahedral TaggedMesh (every box in 8: the midpoints added
    to its grid lines), tagged again (meshing.build.TaggedMesh.refined's nested meshes)."""
    lines = [np.unique(c) for c in tm.mesh.p]
    for _ in range(times):
        lines = [np.sort(np.r_[g, 0.5 * (g[1:] + g[:-1])]) for g in lines]
    return tagged(tm.layout, *lines)


def tagged(lay: Layout, x, y, z) -> TaggedMesh:
    """The tensor grid of lines x, y, z with the layout's regions and facet sets."""
    return tag(lay, skfem.MeshHex.init_tensor(x, y, z), refined)


def tag(lay: Layout, mesh: skfem.MeshHex, refiner=None) -> TaggedMesh:
    """A hexahedral mesh of the layout (each element in one layer and material) with the layout's
    regions (from the element centroids) and facet sets (from their midpoints)."""
    p = mesh.p
    c = p[:, mesh.t].mean(axis=1)
    H, tol = lay.height, 1e-9 * max(lay.height, lay.plan.half)
    regions: dict[str, list] = {}
    for e, (xc, yc, zc) in enumerate(c.T):
        layer = next(L for L in lay.layers if L.z0 - tol <= zc <= L.z1 + tol)
        patch = next((q for q in layer.patches if q.contains(xc, yc)), None)     # square: the centroid inside
        regions.setdefault(region_name(patch) if patch is not None else "silicone", []).append(e)
    regions = {k: np.array(v) for k, v in regions.items()}
    mid = p[:, mesh.facets].mean(axis=1)
    flat = np.ptp(p[2, mesh.facets], axis=0) < tol
    bnd = np.zeros(mesh.facets.shape[1], bool)
    bnd[mesh.boundary_facets()] = True
    (x0, x1), (y0, y1) = lay.x_range, lay.y_range
    facets = {"bottom": bnd & flat & (np.abs(mid[2]) < tol),
              "top": bnd & flat & (np.abs(mid[2] - H) < tol)}
    if lay.load is None or lay.contact_size is not None:
        facets["load"] = facets["top"]
    else:
        facets["load"] = facets["top"] & _inside(lay.load, mid)
    side = bnd & ~flat
    on_x = {0: np.abs(mid[0] - x0) < tol, 1: np.abs(mid[0] - x1) < tol}
    on_y = {0: np.abs(mid[1] - y0) < tol, 1: np.abs(mid[1] - y1) < tol}
    facets["edges"] = side & ((on_x[1] | on_y[1]) | (~np.isin(0, lay.planes) & on_x[0])
                              | (~np.isin(1, lay.planes) & on_y[0]))
    for k in lay.planes:
        facets["mirror_" + "xy"[k]] = side & (on_x[0] if k == 0 else on_y[0])
    for el in lay.electrodes:
        at = flat & (np.abs(mid[2] - el.z) < tol)
        if el.patches:
            at &= np.any([_inside(q, mid) for q in el.patches], axis=0)
        facets[el.name] = at
    facets = {k: np.flatnonzero(v) for k, v in facets.items() if np.any(v)}
    mesh = mesh.with_subdomains(regions).with_boundaries(facets)
    mats = {"silicone": None}
    for L in lay.layers:
        mats["silicone"] = mats["silicone"] or (L.material, L.poling)
        mats.update({region_name(q): (L.patch_material, L.poling) for q in L.patches})
    return TaggedMesh(mesh, lay, regions, facets, {k: v for k, v in mats.items() if k in regions}, refiner)


def _inside(patch, mid, tol=1e-12) -> np.ndarray:
    """Which points mid (2+, n) lie in the patch (square or disk), vectorised."""
    dx, dy = np.abs(mid[0] - patch.x), np.abs(mid[1] - patch.y)
    if patch.shape == "disk":
        return dx ** 2 + dy ** 2 <= (patch.half + tol) ** 2
    return (dx <= patch.half + tol) & (dy <= patch.half + tol)
