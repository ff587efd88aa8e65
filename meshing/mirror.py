"""The full mesh of a cut (half or quarter) layout, made by mirroring its mesh.

Each mirror image of the cut mesh (across x = 0 and/or y = 0) is added and the
nodes on the planes are merged, so the full mesh is exactly mirror symmetric:
solved whole, it must give what the symmetric model (fem.static) gives, to
round-off. Regions and facet sets are carried over under their mirrored names
(piezo_0_0 mirrored across x = 0 in a 1 x 3 array is piezo_0_2); the planes'
facets ("mirror_x", "mirror_y") are inside the full mesh and dropped. Used to
test the symmetric model, and to show a symmetric model's mesh whole.
"""

from __future__ import annotations

import numpy as np
import skfem

from taxel.meshing.build import TaggedMesh, facet_keys
from taxel.meshing.layout import Layout, group


def _image(lay: Layout, name: str, g) -> str:
    """The full electrode (or piezo region) that `name` of the cut layout becomes under g."""
    prefix = "piezo_" if name.startswith("piezo_") else ""
    model = "taxel_" + name[len(prefix):] if prefix else name
    entries = [(full, h) for full, m, h in lay.images if m == model]
    if not entries:                             # silicone, or a facet set that is its own image
        return name
    hs = [h for _, h in entries]
    planes = lay.planes
    cutting = {i for i in range(len(planes))
               if tuple(-1 if j == i else 1 for j in range(len(planes))) not in hs}
    g2 = tuple(1 if i in cutting else s for i, s in enumerate(g))
    full = next(f for f, h in entries if h == g2)
    return full.replace("taxel_", "piezo_", 1) if prefix else full


def unfold_mesh(tm: TaggedMesh, full: Layout) -> TaggedMesh:
    """The full, mirror-symmetric mesh of the cut mesh `tm`, tagged for the `full` layout."""
    lay, m = tm.layout, tm.mesh
    D, n = m.dim(), m.p.shape[1]
    pts, tets, copies = [], [], group(lay.planes)
    for c, g in enumerate(copies):
        p = m.p.copy()
        for k, s in zip(lay.planes, g):
            p[k] *= s
        t = m.t.copy() + c * n
        if np.prod(g) < 0:                      # keep the orientation positive
            t[[0, 1]] = t[[1, 0]]
        pts.append(p)
        tets.append(t)
    P, T = np.hstack(pts), np.hstack(tets)
    scale = 1e-9 * np.abs(P).max()
    _, first, merge = np.unique(np.round(P / scale).astype(np.int64), axis=1, return_index=True,
                                return_inverse=True)
    merge = merge.ravel()
    mesh = (skfem.MeshTri if D == 2 else skfem.MeshTet)(np.ascontiguousarray(P[:, first]),
                                                        np.ascontiguousarray(merge[T]))
    N = mesh.p.shape[1]
    fkeys = facet_keys(mesh.facets, N)
    order = np.argsort(fkeys)
    regions, facets = {}, {}
    for c, g in enumerate(copies):
        for name, ix in tm.regions.items():
            key = _image(lay, name, g)
            regions[key] = np.concatenate([regions.get(key, np.zeros(0, np.int64)), ix + c * m.nelements])
        for name, ix in tm.facets.items():
            if name.startswith("mirror_"):
                continue
            keys = facet_keys(np.sort(merge[m.facets[:, ix] + c * n], axis=0), N)
            pos = order[np.searchsorted(fkeys, keys, sorter=order)]
            if not np.array_equal(fkeys[pos], keys):
                raise RuntimeError(f"mirror: facets of '{name}' not found in the full mesh")
            key = _image(lay, name, g)
            facets[key] = np.unique(np.concatenate([facets.get(key, np.zeros(0, np.int64)), pos]))
    mesh = mesh.with_subdomains(regions).with_boundaries(facets)
    mats = {_image(lay, r, g): v for r, v in tm.materials.items() for g in copies}
    return TaggedMesh(mesh, full, regions, facets, mats)
