"""Layered hexahedral meshes of 3D array layouts: a plan mesh graded where the stresses are
(the taxel edges, the punch's rim), extruded through the stack (issue 57).

The plan (the kept quadrant or half of the outline, fragmented at every taxel edge; meshing.build's
`plan_faces`) is meshed by gmsh's quadrilateral mesher (Frontal-Delaunay for quads, Blossom full-quad
recombination) under the plan size field of meshing.sizes (`piezo_size` at the taxel edges,
`contact_size` within `rim` of the punch's rim circle, growing to `size` over growth x size, at
most taxel_cap x piezo_size inside the taxels), then extruded layer by layer with recombination,
with each layer's own elements through it (meshing.build.vertical_divisions: `piezo_layers`
through each piezo layer, the silicone graded from `piezo_size` next to the piezo, the top layer
under a punch to `contact_size` at the top surface). Every element is a hexahedron (a quadrilateral
prism: bilinear in plan, linear through), lying in one layer and one material, conformal at every
interface; the thin film is resolved through its thickness by `piezo_layers` without refining the
plan. The mesh is scikit-fem's MeshHex (gmsh's vertex order to scikit-fem's), tagged as
meshing.hexmesh's (meshing.hexmesh.tag), so the assembly gives it the hexahedral elements
(Q2 / P1-disc, fem.assembly) and the press its quadrilateral contact faces.

Unlike meshing.hexmesh's tensor grid, the plan's fine elements stay at the rim circle and the
taxel edges (they do not run across the whole model); unlike the free tetrahedra (Layout.free),
they run through every height (the price of a layered mesh). benchmarks/press_hex.py --layered
measures it against the press's reference.
"""

from __future__ import annotations

import numpy as np
import skfem

from taxel.meshing.build import TaggedMesh, gmsh_model, plan_faces
from taxel.meshing.sizes import size_field, vertical_divisions
from taxel.meshing.hexmesh import HexMeshError, supports, tag
from taxel.meshing.layout import Layout

GMSH_TO_SKFEM = [0, 4, 3, 1, 7, 5, 2, 6]      # gmsh's (VTK's) hexahedron vertices in scikit-fem's order
MIRROR = [0, 1, 3, 2, 5, 4, 6, 7]             # scikit-fem's vertices with x and y swapped (reverses orientation)


def build_layered(lay: Layout) -> TaggedMesh:
    """The layered hexahedral TaggedMesh of a 3D array layout (module docstring)."""
    why = supports(lay)
    if why:
        raise HexMeshError(why.replace("'hex'", "'layered'"))
    flat = _replace(lay, free=False)
    with gmsh_model("layered") as gmsh:
        occ = gmsh.model.occ
        plan = plan_faces(occ, flat)
        occ.synchronize()
        opt = gmsh.option.setNumber
        opt("Mesh.RecombineAll", 1)
        opt("Mesh.Algorithm", 8)                 # Frontal-Delaunay for quads
        opt("Mesh.RecombinationAlgorithm", 3)    # Blossom full-quad: no triangle left in the plan
        for layer in flat.layers:
            n, heights = vertical_divisions(flat, layer)
            out = occ.extrude(plan, 0, 0, layer.thickness, numElements=n, heights=heights, recombine=True)
            plan = [out[i - 1] for i, e in enumerate(out) if e[0] == 3]
        occ.synchronize()
        size_field(gmsh, flat)
        gmsh.model.mesh.generate(3)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
        index[tags.astype(np.int64)] = np.arange(len(tags))
        types, _, nodes = gmsh.model.mesh.getElements(3)
        if any(t != 5 for t in types):
            raise HexMeshError("layered mesh: the plan's recombination left triangles (prisms in the stack); "
                               "use mesh.element = 'tet'")
        t = index[np.asarray(nodes[0], dtype=np.int64)].reshape(-1, 8)
    p = coords.reshape(-1, 3).T
    used = np.unique(t)
    renum = np.full(p.shape[1], -1, dtype=np.int64)
    renum[used] = np.arange(len(used))
    t = renum[t][:, GMSH_TO_SKFEM].T
    p = np.ascontiguousarray(p[:, used])
    # a plan quadrilateral numbered clockwise seen from above makes a left-handed hexahedron: its
    # reference x and y swapped (MIRROR), so every J > 0
    left = skfem.MeshHex(p, t).mapping().detDF(np.full((3, 1), 0.5))[:, 0] < 0
    t[:, left] = t[MIRROR][:, left]
    return tag(lay, skfem.MeshHex(p, np.ascontiguousarray(t)))


def _replace(lay: Layout, **kw) -> Layout:
    from dataclasses import replace
    return replace(lay, **kw)
