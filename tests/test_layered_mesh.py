"""meshing.layered: the layered hexahedral press mesh (a graded quadrilateral plan extruded
through each layer with its own divisions)."""

import dataclasses

import numpy as np


def _layout(**edit):
    from taxel.analyses import check, checked_layout
    from taxel.scene import load
    sc = load("thesis-pzt-probe-3d")
    return dataclasses.replace(checked_layout(sc, check(sc)), **edit)


def test_the_layered_mesh_is_right_handed_hexahedra_in_their_layers():
    """Every element a hexahedron with J > 0 at its centre, each piezo element inside the piezo
    layer with `piezo_layers` of them through it, the electrodes' facets the piezo's faces, and the
    plan finer at the punch's rim than far from it."""
    from taxel.meshing.layered import build_layered
    lay = _layout(piezo_layers=3)
    tm = build_layered(lay)
    m = tm.mesh
    assert m.t.shape[0] == 8
    assert (m.mapping().detDF(np.full((3, 1), 0.5))[:, 0] > 0).all()
    piezo = next(L for L in lay.layers if L.patches)
    zc = m.p[2, m.t[:, tm.regions["piezo_0_0"]]].mean(axis=0)
    assert ((zc > piezo.z0) & (zc < piezo.z1)).all()
    assert len(np.unique(np.round(zc, 9))) == 3                     # three elements through the piezo
    top = m.p[:, m.facets[:, tm.facets["taxel_0_0"]]]
    assert np.allclose(top[2], piezo.z1) and len(tm.facets["taxel_0_0"]) * 3 == len(tm.regions["piezo_0_0"])
    # plan sizes at the top: the facets' areas within 0.2 mm of the rim circle against those beyond 2 mm
    f = m.facets[:, tm.facets["top"]]
    c = m.p[:, f].mean(axis=1)
    a = np.linalg.norm(np.cross(m.p[:, f[2]] - m.p[:, f[0]], m.p[:, f[1]] - m.p[:, f[3]], axis=0), axis=0) / 2
    d = np.abs(np.hypot(c[0] - lay.load.x, c[1] - lay.load.y) - lay.load.half)
    assert np.median(a[d < 0.2e-3]) < 0.25 * np.median(a[d > 2e-3])
