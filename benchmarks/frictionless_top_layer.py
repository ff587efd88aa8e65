"""What crushes the top layer under a frictionless punch in 3D: the trials of the guide's
"Frictionless presses" (docs/guide/silicone-and-contact.md), one run each.

The thesis taxel's 3D probe press (thesis-pzt-probe-3d), frictionless, one 1 N target, on the
default press mesh (8 031 unknowns), where it stops at 0.749 N (benchmarks/press_3d.py
--frictionless), its stop naming where (fem.contact): the top layer of elements under the
flat, J down to 0.05.

--ripple: the contact points under the flat (r < 1.5 mm) at 0.3 and 0.6 N, by kind (a P2
triangle's three vertices, three edge midpoints): how many press, their gaps and pressures.
A P2 triangle's consistent load of a uniform pressure puts nothing on its vertices, so under a
frictionless flat the vertices may leave the punch while the midpoints press.
--bilateral: a facet's vertices held in contact (pressure free to go negative) while its three
midpoints press (Surface.state patched for the run).
--tie: each top edge midpoint's vertical displacement tied to its edge's mean by a penalty of
TIE x mu h (the top facets flat in z: no ripple).
--extruded: the scene's own extruded mesh (1 mm / 0.4 mm) at sizes / 1 (x 2 reaches 1 N).

RESULT (2026-11-25, one run each, CPU s on the shared 2-core machine; --ripple, --bilateral and
--tie re-run from this script, --extruded by the same press_3d.run call in a scratch script):
--ripple: under r < 1.5 mm every midpoint presses (46 of 46 at 0.3 N, 32.6-42.3 kPa; 32 of 32
at 0.6 N, 73.3-115 kPa); of the vertices 19 of 39 are out of contact at 0.3 N, up to 7.4 um below
the punch, and 9 of 32 at 0.6 N, up to 23 um; the others at most 1.7 / 12 kPa.
--bilateral: stops at 0.438 N (0.307 mm), the step inverting J at 1.51 mm from the axis,
0.035 mm deep (94 s).
--tie (1e4 mu h): stops at 0.573 N (0.368 mm), J inverting at 1.53 mm, 0.013 mm deep (418 s).
--extruded: 34 143 unknowns, stops at 0.401 N (0.290 mm), the multipliers not settling (912 s).
Neither contact change passes the default's 0.749 N: the top layer crushes by itself.

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/frictionless_top_layer.py [--ripple] [--bilateral] [--tie] [--extruded]
"""

from __future__ import annotations

import sys
from contextlib import contextmanager

import numpy as np
import scipy.sparse as sp

from press_3d import layout, run, scene
from taxel.analyses import problem
from taxel.fem import contact
from taxel.fem.assembly import assemble
from taxel.fem.contact import Press
from taxel.meshing.build import build
from taxel.scene import load

TIE = 1e4            # the tie's penalty, x mu h
H_TOP = 0.3e-3       # m, about the top elements' size under the flat (the tie's length scale)
VERTICES, MIDPOINTS = slice(0, 3), slice(3, 6)      # a P2 triangle's nodal contact points (fem.contact.NODAL)


def user():
    return load("thesis-pzt-probe-3d").replace(**{"load.friction": "frictionless"})


def ripple():
    """The contact points under the flat at 0.3 and 0.6 N, vertices and midpoints apart."""
    sc = user()
    prob = problem(sc, tagged_mesh=build(layout(sc)))
    pr = Press(assemble(prob), prob.indenter)
    for F in (0.3, 0.6):
        pt = pr.force(F)
        st = pr.res.state
        under = np.hypot(st.x[0], st.x[1]) < 1.5e-3
        for name, q in (("vertices", VERTICES), ("midpoints", MIDPOINTS)):
            u, a = under[:, q], st.active[:, q]
            print(f"{pt.force:.3f} N, {name} under r < 1.5 mm: {u.sum()} points, {(a & u).sum()} pressing, "
                  f"gap up to {1e6 * st.g[:, q][u].max():.3g} um, pressure {1e-3 * st.tn[:, q][u].min():.3g}-"
                  f"{1e-3 * st.tn[:, q][u].max():.3g} kPa", flush=True)


@contextmanager
def bilateral_vertices():
    """Surface.state with a facet's vertices held (t_N = lambda - eps g, any sign) while its
    three midpoints press."""
    orig = contact.Surface.state

    def state(self, u, ind, travel, lam, eps, with_curvature=True, fixed=None, stick=None):
        st = orig(self, u, ind, travel, lam, eps, with_curvature, fixed, stick)
        if fixed is not None or stick is not None or st.tn.shape[-1] != 6:
            return st
        raw = lam - eps * st.g
        hold = np.zeros_like(raw, bool)
        hold[:, VERTICES] = (raw[:, MIDPOINTS] > 0).all(axis=1)[:, None]
        st.fixed = (raw > 0) | hold
        st.tn = np.where(st.fixed, raw, 0.0)
        return st
    contact.Surface.state = state
    try:
        yield
    finally:
        contact.Surface.state = orig


def tie(sy, ind):
    """Add to sy.A the penalty TIE mu h (w_m - (w_a + w_b) / 2)^2 on every top edge: its midpoint's
    vertical displacement w_m against its vertices'."""
    surf = Press(sy, ind).surf
    zi = np.argmax(surf.phi[:, :, :, 2], axis=2)                 # each nodal point's z dof (local)
    zd = np.take_along_axis(surf.dofs, zi, axis=1) + sy.offsets["u"].start
    mu = max(lw.mu for r, lw in sy.laws.items() if r in sy.soft)
    c = np.array([1.0, -0.5, -0.5])
    idx = np.concatenate([zd[:, [m, a, b]] for m, a, b in ((3, 0, 1), (4, 1, 2), (5, 2, 0))])
    rows, cols = np.repeat(idx, 3, axis=1).ravel(), np.tile(idx, (1, 3)).ravel()
    vals = np.tile((TIE * mu * H_TOP * np.outer(c, c)).ravel(), len(idx))
    sy.A = (sy.A + sp.csr_matrix((vals, (rows, cols)), shape=sy.A.shape)).tocsr()


def show(name, r):
    end = r.get("error") or f"reached 1 N at {1e3 * r['travel']:.4g} mm, V/F {r['VF']:.5f} V/N"
    print(f"{name} ({r['n']} unknowns, {r['cpu']:.0f} s CPU): {end}", flush=True)


def main():
    if "--ripple" in sys.argv:
        ripple()
    if "--bilateral" in sys.argv:
        with bilateral_vertices():
            show("vertices held while the midpoints press", run(user(), layout(user())))
    if "--tie" in sys.argv:
        show(f"midpoints tied to flat facets ({TIE:g} mu h)", run(user(), layout(user()), edit=tie))
    if "--extruded" in sys.argv:
        fr = scene("frictionless")
        show("the scene's own extruded mesh at sizes / 1", run(fr, layout(fr, 1.0)))


if __name__ == "__main__":
    main()
