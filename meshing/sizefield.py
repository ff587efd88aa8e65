"""gmsh size fields of a layered layout (meshing.build): in-plane `piezo_size` at the taxel edges
(the taxels the load does not touch at `far_taxel` x it), growing linearly to `size` over `growth` x
`size`; at most `taxel_cap` x `piezo_size` inside the taxels; under a punch `contact_size` within
`rim` of the punch's rim circle (a MathEval distance, not a plan curve). Where they hold: the plan
(z = 0, extruded to every height), or in a free layout (Layout.free) the taxel edges on the piezo's
faces and the rim on the top surface. Plan curves are found from points on them, not from their
bounding boxes (gmsh pads OCC boxes by 1e-7 m).
"""

from __future__ import annotations

import math

import numpy as np

from taxel.meshing.layout import Layout, is_graded


def size_field(gmsh, lay: Layout):
    opt = gmsh.option
    opt.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    opt.setNumber("Mesh.MeshSizeFromPoints", 0)
    opt.setNumber("Mesh.MeshSizeFromCurvature", 0)
    opt.setNumber("Mesh.MeshSizeMax", lay.size)
    f = gmsh.model.mesh.field
    free = lay.free and lay.dim == 3
    piezo = [L for L in lay.layers if not is_graded(lay, L)]
    # where the edges' sizes hold: the plan (extruded to every height), or in a free layout
    # the taxel edges on the piezo's faces and the punch's rim on the top surface
    at_piezo = sorted({z for L in piezo for z in (L.z0, L.z1)}) if free else [0.0]
    at_top = [lay.height] if free else [0.0]
    edges = list(lay.taxels) + ([lay.load] if lay.load and not free and not rim_field(lay) else [])
    if not edges and lay.load is None:
        return
    far = [p for p in lay.taxels if lay.far_taxel != 1.0 and not lay.near_load(p)]
    near = [p for p in edges if p not in far]
    fields = [_threshold(gmsh, lay, near, lay.piezo_size, 0.0, at_piezo)] if near else []
    if far:                                       # taxels the load does not touch: coarser edges
        fields.append(_threshold(gmsh, lay, far, min(lay.far_taxel * lay.piezo_size, lay.size), 0.0, at_piezo))
    if free and lay.load is not None and lay.contact_size is None:
        fields.append(_threshold(gmsh, lay, [lay.load], lay.piezo_size, 0.0, at_top))
    if rim_field(lay):                                  # the band under the punch's rounded edge
        fields.append(_rim_threshold(gmsh, lay, min(lay.contact_size, lay.piezo_size), at_top[0] if free else None))
    elif lay.contact_size is not None and lay.load is not None:
        fields.append(_threshold(gmsh, lay, [lay.load], min(lay.contact_size, lay.piezo_size), lay.rim, at_top))
    zs = (min(L.z0 for L in piezo), max(L.z1 for L in piezo)) if free and piezo else (-1.0, 1.0)
    for p in lay.taxels:                          # cap inside taxels (free: inside the piezo)
        box = f.add("Box")
        f.setNumber(box, "VIn", min(lay.taxel_cap * lay.piezo_size * (1.0 if p not in far else lay.far_taxel),
                                    lay.size))
        f.setNumber(box, "VOut", lay.size)
        f.setNumber(box, "XMin", p.x - p.half)
        f.setNumber(box, "XMax", p.x + p.half)
        f.setNumber(box, "YMin", -1.0 if lay.dim == 2 else p.y - p.half)
        f.setNumber(box, "YMax", 1.0 if lay.dim == 2 else p.y + p.half)
        f.setNumber(box, "ZMin", zs[0])
        f.setNumber(box, "ZMax", zs[1])
        fields.append(box)
    mn = f.add("Min")
    f.setNumbers(mn, "FieldsList", fields)
    f.setAsBackgroundMesh(mn)


def _threshold(gmsh, lay: Layout, patches, size_min, dist_min, heights=(0.0,)):
    """A size field: `size_min` within `dist_min` of the patches' edges at the given
    heights (the plan, z = 0, where it is extruded: the in-plane size at every height),
    growing linearly to `size` over `growth` x `size` beyond."""
    f = gmsh.model.mesh.field
    if lay.dim == 2:
        xs = {round(p.x + s * p.half, 12) for p in patches for s in (-1, 1)}
        ents = [t for _, t in gmsh.model.getEntities(0)
                if abs(gmsh.model.getValue(0, t, [])[1]) < 1e-12
                and round(gmsh.model.getValue(0, t, [])[0], 12) in xs]
        kind = "PointsList"
    else:
        ents, tol = [], 1e-9 * lay.height
        for _, t in gmsh.model.getEntities(1):
            # points on the curve, not its bounding box: gmsh pads OCC boxes by 1e-7
            a, b = gmsh.model.getParametrizationBounds(1, t)
            xyz = np.reshape(gmsh.model.getValue(1, t, [a[0], 0.5 * (a[0] + b[0]), b[0]]), (3, 3))
            if (any(np.all(np.abs(xyz[:, 2] - z) < tol) for z in heights)
                    and any(_on_edge(p, xyz[1, 0], xyz[1, 1]) for p in patches)):
                ents.append(t)
        kind = "CurvesList"
    dist = f.add("Distance")
    f.setNumbers(dist, kind, ents)
    f.setNumber(dist, "Sampling", 50 if dist_min == 0 else 200)
    thr = f.add("Threshold")
    f.setNumber(thr, "InField", dist)
    f.setNumber(thr, "SizeMin", size_min)
    f.setNumber(thr, "SizeMax", lay.size)
    f.setNumber(thr, "DistMin", dist_min)
    f.setNumber(thr, "DistMax", dist_min + lay.growth * lay.size)
    return thr


def rim_field(lay: Layout) -> bool:
    """A 3D punch with a rounded edge: its rim is a size field (_rim_threshold), not a
    plan curve. Where the punch touches is the contact's outcome, not a boundary of the
    geometry; and a rim circle fragmented with a taxel square it touches (the thesis
    probe: both 2 mm from the centre) leaves slivers along the tangency through every
    height (2.8 degree dihedral angles on the default press mesh, 0.86 on the reference
    family's; tests/test_meshing.py)."""
    return lay.dim == 3 and lay.contact_size is not None and lay.load is not None


def _rim_threshold(gmsh, lay: Layout, size_min, z_top):
    """`size_min` within `rim` of the punch's rim circle (at the top surface, z_top; None:
    in the plan, extruded to every height), growing linearly to `size` over growth x size:
    the distance to the circle in closed form (a MathEval field)."""
    f = gmsh.model.mesh.field
    p = lay.load
    radial = f"(Sqrt((x - ({p.x!r}))^2 + (y - ({p.y!r}))^2) - {p.half!r})"
    dist = f.add("MathEval")
    f.setString(dist, "F", f"Sqrt({radial}^2 + (z - ({z_top!r}))^2)" if z_top is not None else f"Abs{radial}")
    thr = f.add("Threshold")
    f.setNumber(thr, "InField", dist)
    f.setNumber(thr, "SizeMin", size_min)
    f.setNumber(thr, "SizeMax", lay.size)
    f.setNumber(thr, "DistMin", lay.rim)
    f.setNumber(thr, "DistMax", lay.rim + lay.growth * lay.size)
    return thr


def _on_edge(p, x, y, tol=1e-9):
    if p.shape == "disk":
        return abs(math.hypot(x - p.x, y - p.y) - p.half) < tol
    dx, dy = abs(x - p.x), abs(y - p.y)
    return (abs(dx - p.half) < tol and dy <= p.half + tol) or (abs(dy - p.half) < tol and dx <= p.half + tol)
