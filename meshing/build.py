"""gmsh (OCC) meshes of layered layouts, tagged, and their scikit-fem form.

The plan (a line for 2D and axisymmetric models, a face set for 3D) is built and
fragmented at every patch edge (taxels, load footprint), then extruded layer by
layer with a fixed number of elements through each layer. The result is
conformal at every interface, keeps thin layers (a 52 um PVDF film) at a
controlled element count through the thickness, and has nodes on every patch
edge. In-plane size: `piezo_size` at taxel and load edges (where stresses are
singular), growing to `size` over a distance of `growth` x `size` (2), and at most
`taxel_cap` x `piezo_size` (2) inside taxels; the taxels the load does not touch at
`far_taxel` x those sizes (a punch on one taxel strains its neighbours little;
benchmarks/press_speed.py measures what it costs the pressed taxel). Plan curves are found from points
on them, not from their bounding boxes (gmsh pads OCC boxes by 1e-7 m). The plan
mesh is extruded, so its grading holds at every height: at the piezo's bottom and
top faces as at z = 0. Under a punch (`contact_size`, contact-aware): the in-plane
size is `contact_size` within `rim` of the load edge (the band under the punch's
rounded edge), growing to `size` beyond as above; in 3D the rim is that size field
only, not a plan curve (the punch's footprint is where contact puts it, and a rim circle
touching a taxel square's side left slivers along the tangency). Vertically: `piezo_layers` elements per piezo
(or plate) layer; silicone layers graded from `piezo_size` next to the piezo to
`size`, ratio 1.5; under a punch the top layer is graded from both ends, to
`contact_size` at the top surface. A free 3D layout (`Layout.free`): only the piezo
layers are extruded; the silicone layers are meshed by gmsh's 3D mesher with a 3D size
field, `piezo_size` at the taxel edges on the piezo's faces and `contact_size` within
`rim` of the punch's rim on the top surface, so neither runs through the whole height.

Physical groups (names), classified by the first element of each entity:
regions "silicone" and one piezo body per taxel ("piezo_0_0", ...) in arrays, one
per layer ("layer0", ...) in plates;
facets "bottom", "top", "load" (a 3D punch: the whole top), "edges" (the outline), "axis" (r = 0), the
symmetry planes "mirror_x" (x = 0) and "mirror_y" (y = 0) of a cut layout
(meshing.layout.cut: the plan is fragmented by the kept quadrant or half and the
rest removed before extrusion), and one per electrode ("taxel_0_0", "ground"; "bottom", "interface1", "top" on plates).
"""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import skfem
from taxel.meshing.cost import SolveLimit, check_fits
from taxel.meshing.layout import Layout
from taxel.meshing.sizes import rim_field, size_field, is_free, vertical_divisions


@dataclass
class TaggedMesh:
    """A scikit-fem mesh with named regions (element indices) and facet sets."""

    mesh: skfem.Mesh
    layout: Layout
    regions: dict[str, np.ndarray]
    facets: dict[str, np.ndarray]
    materials: dict[str, tuple[str, int]]       # region -> (material name, poling +-1)
    # the uniform refinement where the mesher makes its own (meshing.hexmesh), else the simplices'
    refiner: Callable[[TaggedMesh, int], TaggedMesh] | None = field(default=None, repr=False)

    def refined(self, times: int = 1) -> TaggedMesh:
        """Uniformly refined (each triangle in 4, tetrahedron in 8), names kept: nested
        meshes for convergence studies. scikit-fem keeps the regions; the facet sets of
        a tetrahedral mesh are carried here (each facet's 4 children, from the new
        edge-midpoint nodes: node n + e for edge e, as scikit-fem numbers them)."""
        if self.refiner is not None:            # its mesher's own (meshing.hexmesh: grid lines halved)
            return self.refiner(self, times)
        tm = self
        for _ in range(times):
            m0 = tm.mesh
            m = m0.refined()
            facets = dict(m.boundaries) if m0.dim() == 2 else _refined_facets(m0, m, tm.facets)
            tm = TaggedMesh(m, tm.layout, dict(m.subdomains), facets, tm.materials)
        return tm


# gmsh keeps one global model: two threads of one process meshing at once (the explorer's
# lanes) corrupt each other's model; one mesh at a time per process
_GMSH = threading.Lock()


@contextlib.contextmanager
def _reading_files_only():
    """gmsh's option defaults start its FLTK toolkit, and FLTK then rewrites its preference
    files at every `gmsh.initialize` ($HOME/.fltk/fltk.org/fltk.prefs and, where it may,
    /etc/fltk/fltk.org/fltk.prefs); neither readConfigFiles=False nor -noenv stops it.
    A root process initializes gmsh with the file-system identity of `nobody` (setfsuid:
    this thread only, restored after), so FLTK reads its files but writes none; another
    user's process writes only its own home (the explorer gives it a private one)."""
    import ctypes
    import os
    if not hasattr(os, "geteuid") or os.geteuid() != 0:
        yield
        return
    libc = ctypes.CDLL(None, use_errno=True)
    libc.setfsuid(65534)
    try:
        yield
    finally:
        libc.setfsuid(0)


@contextlib.contextmanager
def gmsh_model(name="taxel"):
    import gmsh
    with _GMSH:
        fresh = not gmsh.isInitialized()
        if fresh:
            with _reading_files_only():
                gmsh.initialize(readConfigFiles=False, interruptible=False)   # no signal handler: off the main thread
        else:
            # options are gmsh's process state: one model's (the layered mesh's RecombineAll and
            # quad algorithm) carried into the next tetrahedral mesh of the same process
            gmsh.option.restoreDefaults()
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add(name)
        try:
            yield gmsh
        finally:
            gmsh.model.remove()


def build(lay: Layout, msh_path: str | Path | None = None, limit: SolveLimit | None = None) -> TaggedMesh:
    """Mesh a layout with gmsh and return the tagged scikit-fem mesh.

    `msh_path`: also write the gmsh mesh (with physical groups) there. `limit`: refuse
    first (MeshTooLarge, before gmsh runs) a mesh whose solve cannot fit this machine
    (meshing.cost.check_fits).
    """
    if limit is not None:
        check_fits(lay, limit)
    with gmsh_model() as gmsh:
        occ = gmsh.model.occ
        plan = plan_faces(occ, lay)
        occ.synchronize()
        for layer in lay.layers:
            step = (0, layer.thickness, 0) if lay.dim == 2 else (0, 0, layer.thickness)
            if is_free(lay, layer):          # geometry only: meshed by the 3D mesher
                out = occ.extrude(plan, *step)
            else:
                n, heights = vertical_divisions(lay, layer)
                out = occ.extrude(plan, *step, numElements=n, heights=heights, recombine=False)
            plan = [out[i - 1] for i, e in enumerate(out) if e[0] == lay.dim]
        occ.synchronize()
        size_field(gmsh, lay)
        gmsh.model.mesh.generate(lay.dim)
        groups = _classify(gmsh, lay)
        for (dim, name), tags in groups.items():
            gmsh.model.setPhysicalName(dim, gmsh.model.addPhysicalGroup(dim, sorted(tags)), name)
        if msh_path is not None:
            gmsh.write(str(msh_path))
        return _to_skfem(gmsh, lay, groups)


def plan_faces(occ, lay: Layout):
    """Plan entities at z = 0, fragmented at every patch edge."""
    patches = list(lay.taxels) + ([lay.load] if lay.load and not rim_field(lay) else [])
    if lay.dim == 2:
        xs = lay.breakpoints()
        pts = [occ.addPoint(x, 0, 0) for x in xs]
        return [(1, occ.addLine(a, b)) for a, b in zip(pts[:-1], pts[1:])]

    def face(p, half_y=None):
        if p.shape == "disk":
            return (2, occ.addDisk(p.x, p.y, 0, p.half, p.half))
        hy = p.half if half_y is None else half_y
        return (2, occ.addRectangle(p.x - p.half, p.y - hy, 0, 2 * p.half, 2 * hy))

    outline = face(lay.plan, lay.plan_half_y if lay.plan.shape != "disk" else None)
    tools = [face(p) for p in patches]
    if lay.planes:                       # the kept half or quadrant, as one more fragment tool
        (x0, x1), (y0, y1) = lay.x_range, lay.y_range
        tools.append((2, occ.addRectangle(x0, y0, 0, x1 - x0, y1 - y0)))
    if not tools:
        return [outline]
    out, _ = occ.fragment([outline], tools)
    occ.synchronize()
    faces = [e for e in out if e[0] == 2]
    if lay.planes:
        tol = 1e-9 * max(lay.plan.half, lay.plan_half_y)
        drop = [e for e in faces if any(occ.getCenterOfMass(*e)[k] < -tol for k in lay.planes)]
        occ.remove(drop, recursive=True)
        occ.synchronize()
        faces = [e for e in faces if e not in drop]
    return faces


def region_name(patch):
    """The region of a taxel's piezo body ("piezo_0_1"); its top electrode is "taxel_0_1"."""
    return patch.name.replace("taxel", "piezo", 1)


def _classify(gmsh, lay: Layout):
    """Physical groups {(dim, name): [entity tags]} from each entity's first element."""
    D = lay.dim
    groups: dict[tuple[int, str], list[int]] = {}

    def add(dim, name, tag):
        groups.setdefault((dim, name), []).append(tag)

    def first_element_nodes(dim, tag):
        _, _, nodes = gmsh.model.mesh.getElements(dim, tag)
        n = {2: 3, 3: 4, 1: 2}[dim]
        enodes = np.asarray(nodes[0][:n], dtype=np.int64)
        return np.array([gmsh.model.mesh.getNode(int(k))[0] for k in enodes])

    def plan_xyz(X):           # (plan x, plan y, height z) of gmsh points
        return (X[:, 0], np.zeros(len(X)), X[:, 1]) if D == 2 else (X[:, 0], X[:, 1], X[:, 2])

    H, tol = lay.height, 1e-9 * max(lay.height, lay.plan.half)
    for _, tag in gmsh.model.getEntities(D):
        x, y, z = (c.mean() for c in plan_xyz(first_element_nodes(D, tag)))
        layer = next(L for L in lay.layers if L.z0 - tol <= z <= L.z1 + tol)
        patch = next((p for p in layer.patches if p.contains(x, y)), None)
        if patch is not None:
            add(D, region_name(patch), tag)
        elif lay.taxels:
            add(D, "silicone", tag)
        else:                                   # plates: one region per layer
            add(D, layer.name, tag)
    for _, tag in gmsh.model.getEntities(D - 1):
        x, y, z = plan_xyz(first_element_nodes(D - 1, tag))
        xc, yc, zc = x.mean(), y.mean(), z.mean()
        if np.ptp(z) < tol:                                  # horizontal
            if abs(zc) < tol:
                add(D - 1, "bottom", tag)
            if abs(zc - H) < tol:
                add(D - 1, "top", tag)
                if lay.load is None or rim_field(lay) or lay.load.contains(xc, yc):
                    add(D - 1, "load", tag)         # a punch (rim_field): the contact finds where
            for el in lay.electrodes:
                if abs(zc - el.z) < tol and (not el.patches or any(p.contains(xc, yc) for p in el.patches)):
                    add(D - 1, el.name, tag)
        else:                                                # vertical
            if _on_outline(lay, x, y).all():
                add(D - 1, "edges", tag)
            elif lay.model == "axisymmetric" and (np.abs(x) < tol).all():
                add(D - 1, "axis", tag)
            else:
                for k in lay.planes:
                    if (np.abs((x, y)[k]) < tol).all():
                        add(D - 1, "mirror_" + "xy"[k], tag)
    return groups


def _on_outline(lay: Layout, x, y):
    tol = 1e-9 * lay.plan.half
    if lay.model == "axisymmetric" or lay.plan.shape == "disk":
        r = np.hypot(x, y) if lay.dim == 3 else np.abs(x)
        return np.abs(r - lay.plan.half) < tol
    if lay.dim == 2:
        return np.abs(np.abs(x) - lay.plan.half) < tol
    return (np.abs(np.abs(x) - lay.plan.half) < tol) | (np.abs(np.abs(y) - lay.plan_half_y) < tol)


def _to_skfem(gmsh, lay: Layout, groups) -> TaggedMesh:
    D = lay.dim
    tags, coords, _ = gmsh.model.mesh.getNodes()
    index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    p = coords.reshape(-1, 3)[:, :D].T
    etype, nper = (2, 3) if D == 2 else (4, 4)
    ftype, fper = (1, 2) if D == 2 else (2, 3)

    blocks, regions, start = [], {}, 0
    for (dim, name), ents in groups.items():
        if dim != D:
            continue
        ix = []
        for ent in ents:
            _, nodes = gmsh.model.mesh.getElementsByType(etype, ent)
            t = index[nodes.astype(np.int64)].reshape(-1, nper)
            blocks.append(t)
            ix.append(np.arange(start, start + len(t)))
            start += len(t)
        regions[name] = np.concatenate(ix)
    t = np.vstack(blocks).T
    used = np.unique(t)
    renum = np.full(p.shape[1], -1, dtype=np.int64)
    renum[used] = np.arange(len(used))
    MeshType = skfem.MeshTri if D == 2 else skfem.MeshTet
    mesh = MeshType(np.ascontiguousarray(p[:, used]), np.ascontiguousarray(renum[t]))

    n = mesh.p.shape[1]
    fkeys = facet_keys(mesh.facets, n)
    order = np.argsort(fkeys)
    facets = {}
    for (dim, name), ents in groups.items():
        if dim != D - 1:
            continue
        fs = [renum[index[gmsh.model.mesh.getElementsByType(ftype, ent)[1].astype(np.int64)]]
              .reshape(-1, fper).T for ent in ents]
        keys = facet_keys(np.sort(np.hstack(fs), axis=0), n)
        pos = order[np.searchsorted(fkeys, keys, sorter=order)]
        if not np.array_equal(fkeys[pos], keys):
            raise RuntimeError(f"mesh conversion: facets of group '{name}' not found in the mesh")
        facets[name] = np.unique(pos)
    mesh = mesh.with_subdomains(regions).with_boundaries(facets)
    mats = {}
    for L in lay.layers:
        mats[L.name if not lay.taxels else "silicone"] = (L.material, L.poling)
        mats.update({region_name(patch): (L.patch_material, L.poling) for patch in L.patches})
    return TaggedMesh(mesh, lay, regions, facets, {k: v for k, v in mats.items() if k in regions})


def _refined_facets(m0, m, named):
    """The facet sets of a once uniformly refined tetrahedral mesh."""
    n0, n = m0.p.shape[1], m.p.shape[1]
    ekeys = facet_keys(m0.edges, n0)
    eorder = np.argsort(ekeys)

    def mid(a, b):            # the new node at the midpoint of edge (a, b)
        k = facet_keys(np.vstack([a, b]), n0)
        return n0 + eorder[np.searchsorted(ekeys, k, sorter=eorder)]

    fkeys = facet_keys(m.facets, n)
    forder = np.argsort(fkeys)
    out = {}
    for name, ix in named.items():
        a, b, c = m0.facets[:, ix]
        ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
        kids = np.hstack([np.vstack(v) for v in ((a, ab, ca), (b, ab, bc), (c, bc, ca), (ab, bc, ca))])
        keys = facet_keys(np.sort(kids, axis=0), n)
        pos = forder[np.searchsorted(fkeys, keys, sorter=forder)]
        if not np.array_equal(fkeys[pos], keys):
            raise RuntimeError(f"refinement: children of facet set '{name}' not found")
        out[name] = np.unique(pos)
    return out


def facet_keys(f, n):
    """One integer key per facet (its sorted vertex indices, n the number of vertices)."""
    f = np.sort(f, axis=0).astype(np.int64)
    k = f[0]
    for row in f[1:]:
        k = k * n + row
    return k


def export(tm: TaggedMesh, path: str | Path, point_data=None, cell_data=None):
    """Write the mesh (and optional fields) with meshio (.vtu, .xdmf, ...); for a
    gmsh .msh with physical groups use `build(..., msh_path=...)`."""
    import meshio
    m = tm.mesh
    cell_type = "triangle" if m.dim() == 2 else "hexahedron" if m.t.shape[0] == 8 else "tetra"
    region_id = np.zeros(m.t.shape[1], dtype=np.int32)
    for i, name in enumerate(tm.regions, start=1):
        region_id[tm.regions[name]] = i
    cd = {"region": [region_id]}
    for k, v in (cell_data or {}).items():
        cd[k] = [v]
    pts = m.p.T if m.dim() == 3 else np.column_stack([m.p.T, np.zeros(m.p.shape[1])])
    t = m.t[[0, 3, 6, 2, 1, 5, 7, 4]] if cell_type == "hexahedron" else m.t     # skfem's to VTK's order
    out = meshio.Mesh(pts, [(cell_type, t.T)], point_data=point_data or {}, cell_data=cd,
                      cell_sets={k: [v] for k, v in tm.regions.items()})
    meshio.write(path, out)
