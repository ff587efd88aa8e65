"""The Coulomb press of a rigid cylinder on a Yeoh block in two codes, FELupe 11.3's
ContactRigidCylinder and fem.contact (tests/test_contact_felupe.py,
benchmarks/friction_felupe.py: the problem and the penalty extrapolation are described there)."""

import numpy as np

from contact_meshes import block, problem, quarter_block
from taxel.fem.assembly import Indenter, assemble
from taxel.fem.constitution import Solid
from taxel.fem.contact import OPEN, SLIP, STICK, Press

C10, C20, C30, K = 7.83e3, 0.103e3, -0.0008e3, 5e6
W, H, R = 2e-3, 2e-3, 2e-3            # half-width, height, cylinder radius
TRAVEL, STEPS = 0.28e-3, 14


def travels(steps=STEPS, travel=TRAVEL):
    return np.linspace(0, travel, steps + 1)[1:]


def felupe_cylinder(mu, mult, n=(81, 41), steps=STEPS, travel=TRAVEL, maxiter=60):
    """FELupe's press: (force per metre at each travel, x of the top nodes, in contact, slipping,
    the friction force per metre on the half x > 0: the sum of |f_x| of its nodes)."""
    import felupe as fe
    mesh = fe.Rectangle(a=(-W, 0), b=(W, H), n=n)
    mesh.update(points=np.vstack([mesh.points, [0.0, H + R]]))
    field = fe.FieldsMixed(fe.RegionQuad(mesh), n=3, planestrain=True)
    u = field[0]
    umat = fe.NearlyIncompressible(fe.Hyperelastic(fe.yeoh, C10=C10, C20=C20, C30=C30), bulk=K)
    cp = len(mesh.points) - 1
    top = np.flatnonzero(np.isclose(mesh.points[:, 1], H))
    eps = mult * 2 * C10            # N/m per node and metre of depth: m x 2 C10 / h times the node's length h
    cyl = fe.ContactRigidCylinder(field, points=top, centerpoint=cp, radius=R, friction=mu,
                                  multiplier=eps, multiplier_tangential=eps)
    at_cp = np.arange(len(mesh.points)) == cp
    move = fe.Boundary(u, mask=at_cp, skip=(1, 0))
    bounds = {"bottom": fe.Boundary(u, fy=0), "cpx": fe.Boundary(u, mask=at_cp, skip=(0, 1)), "move": move}
    step = fe.Step(items=[fe.SolidBody(umat, field), cyl], ramp={move: -np.concatenate([[0.0], travels(steps, travel)])},
                   boundaries=bounds)
    job = fe.CharacteristicCurve(steps=[step], boundary=move)
    job.evaluate(tol=1e-8, verbose=0, maxiter=maxiter)
    F = -np.array([f[1] for f in job.y[1:]])
    x = mesh.points[top, 0] + u.values[top, 0]
    f = cyl.results.force                      # the contact's nodal forces (a sparse column)
    f = (f.toarray() if hasattr(f, "toarray") else np.asarray(f)).reshape(-1, 2)[top]
    return F, x, np.asarray(cyl.results.active), np.asarray(cyl.results.slip), float(np.abs(f[x > 0, 0]).sum())


def felupe_extrapolated(mu, mults=(10.0, 20.0), **kw):
    """FELupe at two penalties and the force (and the friction force on a half) extrapolated
    to an infinite one; the slip zone of the stiffer penalty. (At 30 x 2 C10 FELupe's Newton
    does not converge with mu = 0.1 or 0.3 in 60 iterations: stick and slip alternate.)"""
    (F1, *_, Ft1), (F2, x, act, slip, Ft2) = (felupe_cylinder(mu, m, **kw) for m in mults)
    m1, m2 = mults
    F = F2 + (F2 - F1) * m1 / (m2 - m1)
    return dict(F=F, F_penalties=[F1, F2], Ft=Ft2 + (Ft2 - Ft1) * m1 / (m2 - m1), a=float(np.abs(x[act]).max()),
                c=float(np.abs(x[act & ~slip]).max(initial=0.0)), x=x, zone=np.where(act, np.where(slip, 2, 1), 0))


def ours(mu, h=1e-4, steps=STEPS, travel=TRAVEL):
    """Our press: force per metre at each travel and the final slip zone."""
    mat = Solid("block", 2 * C10, K, 1000.0, yeoh=(C10, C20, C30))
    tm = block(W, H, H, h, model="plane_strain", growth=1.0)
    ind = Indenter("cylinder", R, travel=travel, friction=mu)
    pr = Press(assemble(problem(tm, mat, ind, hyperelastic=True)), ind)
    F = np.array([pr.travel(d, first=1.0).force for d in travels(steps, travel)])
    st = pr.res.state
    x, z = st.x[0].ravel(), st.zone.ravel()
    Ft = 0.0 if st.tang is None else float((np.abs(st.tang.t[0]) * st.dA)[st.x[0] > 0].sum())
    return dict(F=F, Ft=Ft, a=float(np.abs(x[z > 0]).max()), c=float(np.abs(x[z == STICK]).max(initial=0.0)), x=x, zone=z)


# --- 3D: a rigid plate with Coulomb friction compressing a Yeoh block (a quarter) -------------
# The block 4 x 4 mm, 2 mm high (a quarter, x, y in [0, 2 mm], two symmetry planes), bonded at
# the bottom; a rigid plate wider than the block (ours: a flat punch of radius 20 mm) pressed
# TRAVEL_3D in STEPS_3D equal steps. The same grid of nodes in both codes: FELupe Q1/P0/P0
# mixed hexahedra on an N3D^3 grid; ours P2/P1 tetrahedra, six per hexahedron of the same
# grid (skfem MeshTet.init_tensor), the contact at the P2 nodes of the top (fem.contact's 3D rule).
W3, H3 = 2e-3, 2e-3
TRAVEL_3D, STEPS_3D, N3D = 0.2e-3, 10, 8


def box3d(n=N3D, width=W3, height=H3):
    """The quarter block's tetrahedral mesh for fem.contact (TaggedMesh, planes x = 0 and y = 0)."""
    import skfem
    xs = np.linspace(0, width, n + 1)
    return quarter_block(skfem.MeshTet.init_tensor(xs, xs, np.linspace(0, height, n + 1)), width, height)


def travels_3d(steps=STEPS_3D, travel=TRAVEL_3D):
    return np.linspace(0, travel, steps + 1)[1:]


def _stick_radius(xy, active, slip):
    """The outermost sticking point's distance from the axis (0 without one)."""
    r = np.hypot(xy[:, 0], xy[:, 1])
    return float(r[active & ~slip].max(initial=0.0))


def felupe_plate_3d(mu, mult, n=N3D, steps=STEPS_3D, travel=TRAVEL_3D, maxiter=60):
    """FELupe's plate on the quarter: (force at each travel, the full block's, N; the top
    nodes' deformed x, y; in contact; slipping)."""
    import felupe as fe
    xs = np.linspace(0, W3, n + 1)
    mesh = fe.Cube(a=(0, 0, 0), b=(W3, W3, H3), n=n + 1)
    mesh.update(points=np.vstack([mesh.points, [0.0, 0.0, H3]]))
    field = fe.FieldsMixed(fe.RegionHexahedron(mesh), n=3)
    u = field[0]
    umat = fe.NearlyIncompressible(fe.Hyperelastic(fe.yeoh, C10=C10, C20=C20, C30=C30), bulk=K)
    cp = len(mesh.points) - 1
    top = np.flatnonzero(np.isclose(mesh.points[:, 2], H3))
    top = top[top != cp]
    eps = mult * 2 * C10 * (xs[1] - xs[0])        # N/m per node: m x 2 C10 / h times the node's area h^2
    plate = fe.ContactRigidPlane(field, points=top, centerpoint=cp, normal=[0, 0, -1], friction=mu,
                                 multiplier=eps, multiplier_tangential=eps)
    at_cp = np.arange(len(mesh.points)) == cp
    X = mesh.points
    move = fe.Boundary(u, mask=at_cp, skip=(1, 1, 0))
    bounds = {"bottom": fe.Boundary(u, mask=np.isclose(X[:, 2], 0) & ~at_cp),
              "sym_x": fe.Boundary(u, mask=np.isclose(X[:, 0], 0) & ~at_cp, skip=(0, 1, 1)),
              "sym_y": fe.Boundary(u, mask=np.isclose(X[:, 1], 0) & ~at_cp, skip=(1, 0, 1)),
              "cpxy": fe.Boundary(u, mask=at_cp, skip=(0, 0, 1)), "move": move}
    step = fe.Step(items=[fe.SolidBody(umat, field), plate],
                   ramp={move: -np.concatenate([[0.0], travels_3d(steps, travel)])}, boundaries=bounds)
    job = fe.CharacteristicCurve(steps=[step], boundary=move)
    job.evaluate(tol=1e-8, verbose=0, maxiter=maxiter)
    F = -4 * np.array([f[2] for f in job.y[1:]])
    xy = X[top, :2] + u.values[top, :2]
    return F, xy, np.asarray(plate.results.active), np.asarray(plate.results.slip), X[top, :2]


def felupe_extrapolated_3d(mu, mults=(10.0, 20.0), **kw):
    """FELupe's plate at two penalties, the force extrapolated to an infinite one (error ~ 1/m);
    the stick radius of the stiffer penalty."""
    (F1, *_), (F2, xy, act, slip, X) = (felupe_plate_3d(mu, m, **kw) for m in mults)
    m1, m2 = mults
    return dict(F=F2 + (F2 - F1) * m1 / (m2 - m1), F_penalties=[F1, F2], c=_stick_radius(xy, act, slip),
                xy=xy, X=X, zone=np.where(act, np.where(slip, SLIP, STICK), OPEN))


def ours_3d(mu, n=N3D, steps=STEPS_3D, travel=TRAVEL_3D, opts=None):
    """Our plate (a flat punch of radius 20 mm, no edge radius) on the same grid: the full
    block's force at each travel and the stick radius (`opts`: the press's Options)."""
    mat = Solid("block", 2 * C10, K, 1000.0, yeoh=(C10, C20, C30))
    ind = Indenter("flat", 20e-3, 0.0, travel=travel, friction=mu)
    pr = Press(assemble(problem(box3d(n), mat, ind, hyperelastic=True)), ind, opts=opts)
    assert pr.G == 4
    F = np.array([pr.travel(d, first=1.0).force for d in travels_3d(steps, travel)])
    st = pr.res.state
    xy, z = st.x[:2].reshape(2, -1).T, st.zone.ravel()
    return dict(F=F, c=_stick_radius(xy, z > 0, z != STICK), xy=xy, X=pr.surf.X[:2].reshape(2, -1).T, zone=z,
                dA=st.dA.ravel())


def same_nodes(o, f):
    """Our state at FELupe's top nodes (the grid's vertices are P2 nodes of ours too), against
    FELupe's: (ours, FELupe's). Our contact points are each facet's nodes, so a node has a copy
    (its own multiplier and state) in every top facet around it: its state is the one its
    copies carry the most weight (dA) of."""
    def key(x):
        return tuple(np.round(x / 1e-9).astype(int))
    copies: dict = {}
    for k, x in enumerate(o["X"]):
        copies.setdefault(key(x), []).append(k)
    ours, theirs = [], []
    for x, z in zip(f["X"], f["zone"]):
        ks = copies.get(key(x))
        if ks:
            w = np.bincount(o["zone"][ks], o["dA"][ks], minlength=3)
            ours.append(int(np.argmax(w)))
            theirs.append(z)
    return np.array(ours), np.array(theirs)
