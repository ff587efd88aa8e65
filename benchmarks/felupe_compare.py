"""Independent-code check: our Yeoh u-p solve against FELupe on the same problem.

Problem: a plane-strain silicone block 10 mm wide, 5 mm high (depth 1 mm), bottom
bonded, edges free, Yeoh 300 % Ecoflex set (C10, C20, C30) = (7.83e3, 0.103e3,
-0.8) Pa, K = 1000 * 2 C10, under a dead (nominal) pressure of 12 kPa on the top.
That compresses the top by 10 % at the centre, 14 % on average and 25 % at the
free corners; beyond about 14.5 kPa the free top corners fold (a limit point:
both codes stop converging, and at 14 kPa a refined mesh lands on another branch),
so a 20-30 % *uniform* compression is out of reach with a bonded base and free
edges under a dead load.

FELupe side (FELupe 11.3, tensortrax for the automatic-differentiation Yeoh):

* mesh: our gmsh vertices and triangles; P2 midside nodes at the edge midpoints,
  numbered like skfem's facets (cell = [t0, t1, t2, nv + t2f]); clockwise cells
  reordered (skfem integrates with |det|, FELupe warns about negative volumes);
* `RegionQuadraticTriangle` with skfem's own intorder-4 rule (6 points) passed as a
  `felupe.quadrature.Scheme` (FELupe's TriangleQuadrature offers orders 1, 2, 3, 5
  only), and the P2 gradient corrected (see below);
* `FieldsMixed(region, n=3, planestrain=True)`: P2 u, continuous P1 p and P1 Jbar;
* `NearlyIncompressible(Hyperelastic(yeoh, C10, C20, C30), bulk=K)`:
  W = psi(F) + K/2 (Jbar - 1)^2 + p (J - Jbar), which with p and Jbar in the same
  P1 space is our two-field form (p = K (Jbar - 1) nodewise, Jbar the L2 projection
  of J); FELupe's yeoh uses I1b = det(C)^(-1/3) tr C, as we do;
* the dead load as a `PointLoad` of consistent nodal forces (straight P2 edge of
  length L under uniform p: p L / 6 at the ends, 2 p L / 3 at the midpoint), per
  unit depth; `SolidBodyPressure` is a follower load and FELupe has no boundary
  region for quadratic triangles;
* bottom points (vertices and midpoints) fixed with `Boundary(field[0], fy=0)`;
  Newton: `Step(...).generate(tol=...)` in equal load substeps.

FELupe 11.3's `QuadraticTriangle.gradient` is wrong: the s-derivative of the
midside function h5 = 4 s (1 - r - s) is coded as 4 (t1 - t2) = 4 (1 - 2r - s)
instead of 4 (t1 - t3) = 4 (1 - r - 2s) (right only where r = s). With the stock
element the two codes differ by 2.6 % in displacement at 1 kPa and FELupe's Newton
diverges at 12 kPa; with the corrected gradient (`QuadraticTriangleFixed`) they
agree to round-off (about 1e-14). `--diagnose` prints both effects and the
quadrature one (FELupe's order-5 rule vs skfem's order-4 rule).

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/felupe_compare.py
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from taxel.analyses import mesh, problem
from taxel.analyses import solve_static as solve
from taxel.fem.assembly import assemble
from taxel.fem.hyperelastic import yeoh_terms
from taxel.scene import parse

C_YEOH = (7.83e3, 0.103e3, -0.8)
K = 1000 * 2 * C_YEOH[0]
WIDTH, HEIGHT, DEPTH = 10e-3, 5e-3, 1e-3
PRESSURE = 12e3          # Pa
REPEAT = 3


# ----------------------------------------------------------------------------- ours

def scene(pressure=PRESSURE, size="0.625 mm", through=8):
    """The block: one silicone layer, `through` elements through its thickness."""
    return parse({
        "model": {"type": "plane_strain", "silicone": "yeoh", "depth": f"{DEPTH * 1e3} mm"},
        "mesh": {"size": size, "order": 2, "piezo_layers": through},
        "plate": {"shape": "rectangle", "width": f"{WIDTH * 1e3} mm", "length": f"{WIDTH * 1e3} mm",
                  "layers": [{"material": "gel", "thickness": f"{HEIGHT * 1e3} mm"}]},
        "materials": {"gel": {"kind": "solid", "C10": C_YEOH[0], "C20": C_YEOH[1], "C30": C_YEOH[2],
                              "K": K, "rho": 1070}},
        "load": {"kind": "pressure", "pressure": f"{pressure} Pa"},
        "supports": {"bottom": "bonded", "edges": "free"},
    })


def tagged_mesh(sc, refine=0):
    tm = mesh(sc)
    return tm.refined(refine) if refine else tm


def ours(sc, tm, tol=1e-12):
    """Our solve (assembly + Newton + results) on a prebuilt mesh."""
    return solve(sc, tagged_mesh=tm, newton_options={"tol": tol})


def our_point_values(sc, sol):
    """Full P2 displacement and support reactions per unit depth, in FELupe's point
    order (vertices, then edge midpoints in skfem's facet order)."""
    sy = assemble(problem(sc, sol.mesh))
    x = sol.fields.x
    ub = next(iter(sy.ubases.values()))
    r_y, _ = yeoh_terms(sy, x, with_tangent=False)
    r = (sy.A @ x + r_y - sy.b)[sy.offsets["u"]]
    u = x[sy.offsets["u"]]
    fixed = np.zeros(ub.N, bool)
    fixed[sy.fixed_u] = True
    r = np.where(fixed, r, 0.0) / DEPTH

    def points(v):
        return np.vstack([v[ub.nodal_dofs.T], v[ub.facet_dofs.T]])
    return points(u), points(r)


# -------------------------------------------------------------------------- FELupe

def quadratic_triangle_fixed():
    """FELupe's QuadraticTriangle with the derivative of h5 = 4 s (1 - r - s) corrected."""
    import felupe as fe

    class QuadraticTriangleFixed(fe.QuadraticTriangle):
        def gradient(self, rs):
            r, s = rs
            t = 1 - r - s
            d = np.array([[-1, -1], [1, 0], [0, 1],
                          [4 * (t - r), -4 * r], [4 * s, 4 * r], [-4 * s, 4 * (t - s)]], dtype=float)
            d[0] -= (d[3] + d[5]) / 2
            d[1] -= (d[3] + d[4]) / 2
            d[2] -= (d[4] + d[5]) / 2
            return d
    return QuadraticTriangleFixed()


def quadratic_mesh(m):
    """(points, cells) of FELupe triangle6 cells from a skfem MeshTri, skfem P2 order."""
    nv = m.p.shape[1]
    points = np.vstack([m.p.T, m.p[:, m.facets].mean(axis=1).T])
    cells = np.vstack([m.t, nv + m.t2f]).T          # t2f: edges (0,1), (1,2), (0,2)
    a, b, c = (m.p[:, m.t[i]] for i in range(3))
    clockwise = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) < 0
    cells[clockwise] = cells[clockwise][:, [0, 2, 1, 5, 4, 3]]
    return points, cells


def dead_pressure_loads(m, points, pressure):
    """Consistent nodal forces (per unit depth) of a downward dead pressure on the top."""
    nv = m.p.shape[1]
    top = np.flatnonzero(np.all(np.isclose(m.p[1, m.facets], HEIGHT), axis=0))
    f = np.zeros_like(points)
    for e in top:
        a, b = m.facets[:, e]
        L = np.linalg.norm(m.p[:, b] - m.p[:, a])
        f[[a, b], 1] -= pressure * L / 6
        f[nv + e, 1] -= 2 * pressure * L / 3
    return f


def felupe_solve(m, pressure=PRESSURE, *, substeps=2, tol=1e-12, quadrature="skfem4", fixed_gradient=True,
                 solver=None):
    """Solve the block in FELupe on the mesh `m`; returns (u, reactions, iterations)
    with u and reactions per point (reactions per unit depth)."""
    import felupe as fe
    import felupe.constitution.tensortrax as mat
    from skfem.quadrature import get_quadrature
    from skfem.refdom import RefTri

    points, cells = quadratic_mesh(m)
    mesh = fe.Mesh(points, cells, "triangle6")
    if quadrature == "skfem4":
        X, W = get_quadrature(RefTri, 4)
        q = fe.quadrature.Scheme(X.T, W)
    else:
        q = fe.TriangleQuadrature(order=quadrature)
    region = fe.RegionQuadraticTriangle(mesh, quadrature=q)
    if fixed_gradient:
        region.reload(element=quadratic_triangle_fixed())   # keeps the region type (dual: P1 triangle)
    field = fe.FieldsMixed(region, n=3, planestrain=True)
    yeoh = mat.Hyperelastic(mat.models.hyperelastic.yeoh, C10=C_YEOH[0], C20=C_YEOH[1], C30=C_YEOH[2])
    solid = fe.SolidBody(fe.NearlyIncompressible(yeoh, bulk=K), field)
    boundaries = {"bottom": fe.Boundary(field[0], fy=0.0)}
    f = dead_pressure_loads(m, points, pressure)
    loaded = np.flatnonzero(np.any(f != 0, axis=1))
    load = fe.PointLoad(field, loaded, f[loaded])
    ramp = np.linspace(0, 1, substeps + 1)[1:, None, None] * f[loaded]
    step = fe.Step(items=[solid, load], ramp={load: ramp}, boundaries=boundaries)
    kw = {"solver": solver} if solver is not None else {}
    iterations = [res.iterations for res in step.generate(x0=field, tol=tol, verbose=0, **kw)]
    r = solid.assemble.vector(field).toarray().ravel()[: points.size].reshape(-1, 2)
    r[~np.isclose(points[:, 1], 0.0)] = 0.0
    return field[0].values.copy(), r, iterations


# ----------------------------------------------------------------------- comparison

def compare(sc, tm, **kw):
    """Solve with both codes; the relative differences of vertex displacements (max
    over vertices / max |u|), of nodal support reactions, and of the total reaction."""
    sol = ours(sc, tm)
    nv = sol.mesh.mesh.p.shape[1]
    u_ours, r_ours = our_point_values(sc, sol)
    u_fe, r_fe, iters = felupe_solve(sol.mesh.mesh, sc.load.pressure, **kw)
    du = np.abs(u_fe[:nv] - sol.fields.u).max() / np.abs(sol.fields.u).max()
    du_all = np.abs(u_fe - u_ours).max() / np.abs(u_ours).max()
    dr = np.abs(r_fe - r_ours).max() / np.abs(r_ours).max()
    R_fe = r_fe.sum(axis=0) * DEPTH
    dR = abs(R_fe[1] - sol.reaction[1]) / abs(sol.reaction[1])
    return dict(sol=sol, du=du, du_all=du_all, dr=dr, dR=dR, R_fe=R_fe, R_ours=sol.reaction,
                felupe_iterations=iters, u_fe=u_fe)


def median_time(fn, repeat=REPEAT):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def diagnose(sc, tm):
    """What breaks the agreement: FELupe's stock P2 gradient and its own quadrature."""
    import felupe as fe
    el = fe.QuadraticTriangle()
    rs, h = np.array([0.2, 0.3]), 1e-6
    fd = np.array([(el.function(rs + h * e) - el.function(rs - h * e)) / (2 * h) for e in np.eye(2)]).T
    print(f"stock QuadraticTriangle gradient vs finite differences at (0.2, 0.3): "
          f"max error {np.abs(el.gradient(rs) - fd).max():.2f} (row h5: {el.gradient(rs)[5]} vs {fd[5]})")
    print(f"corrected gradient vs finite differences: {np.abs(quadratic_triangle_fixed().gradient(rs) - fd).max():.1e}")
    small = sc.replace(**{"load.pressure": 1e3})
    c = compare(small, tm, fixed_gradient=False, substeps=1)
    print(f"1 kPa, stock FELupe gradient:            max |du| / max |u| = {c['du']:.2e}")
    try:
        c = compare(sc, tm, fixed_gradient=False)
        print(f"{sc.load.pressure / 1e3:g} kPa, stock FELupe gradient: du = {c['du']:.2e}")
    except Exception as exc:                     # noqa: BLE001 - report what FELupe raised
        print(f"{sc.load.pressure / 1e3:g} kPa, stock FELupe gradient: {type(exc).__name__}: {str(exc).strip()}")
    c = compare(sc, tm, quadrature=5)
    print(f"{sc.load.pressure / 1e3:g} kPa, FELupe order-5 (7-point) rule vs our order 4: "
          f"du = {c['du']:.2e}, nodal reactions {c['dr']:.2e} (a quadrature-error-sized difference)")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--refine", type=int, nargs="*", default=[0, 1, 2],
                    help="nested refinements of the 16 x 8 (x2 triangles) base mesh")
    ap.add_argument("--pardiso", action="store_true", help="also time FELupe with pypardiso.spsolve")
    ap.add_argument("--diagnose", action="store_true", help="stock-FELupe gradient bug and quadrature effect")
    args = ap.parse_args()
    import felupe
    sc = scene()
    print(f"FELupe {felupe.__version__}; block {WIDTH * 1e3:g} x {HEIGHT * 1e3:g} mm plane strain, "
          f"{PRESSURE / 1e3:g} kPa dead load, Newton tol 1e-12 both; times: median of {REPEAT}")
    print(f"{'tri':>6} {'dofs':>7} {'ours s':>8} {'FELupe s':>9} {'FE/ours':>8} {'max du rel':>11} "
          f"{'du m':>9} {'reac rel':>9} {'R_z ours N':>11} {'R_z FE N':>11} {'top mid/corner':>15} {'FE its':>8}"
          + ("  FELupe+pardiso s" if args.pardiso else ""))
    for k in args.refine:
        tm = tagged_mesh(sc, k)
        c = compare(sc, tm)
        m = c["sol"].mesh.mesh
        t_ours = median_time(lambda: ours(sc, tm))
        t_fe = median_time(lambda: felupe_solve(m))
        top = np.isclose(m.p[1], HEIGHT)
        uz = c["sol"].fields.u[top, 1] / HEIGHT
        x = m.p[0, top]
        du_abs = np.abs(c["u_fe"][: m.p.shape[1]] - c["sol"].fields.u).max()
        line = (f"{m.t.shape[1]:>6} {c['sol'].unknowns:>7} {t_ours:>8.3f} {t_fe:>9.3f} {t_fe / t_ours:>8.2f} "
                f"{c['du']:>11.2e} {du_abs:>9.1e} {c['dr']:>9.1e} {c['R_ours'][1]:>11.6f} {c['R_fe'][1]:>11.6f} "
                f"{uz[np.argmin(np.abs(x))]:>7.3f}/{uz[np.argmax(x)]:.3f} {str(c['felupe_iterations']):>8}")
        if args.pardiso:
            import pypardiso
            line += f"  {median_time(lambda: felupe_solve(m, solver=pypardiso.spsolve)):.3f}"
        print(line, flush=True)
    if args.diagnose:
        diagnose(sc, tagged_mesh(sc))


if __name__ == "__main__":
    main()
