"""The Coulomb press of a rigid cylinder on a Yeoh block in two codes, FELupe 11.3's
ContactRigidCylinder and fem.contact (tests/test_contact_felupe.py,
benchmarks/friction_felupe.py: the problem and the penalty extrapolation are described there)."""

import numpy as np

from contact_meshes import block, problem
from taxel.fem.assembly import Indenter, assemble
from taxel.fem.constitution import Solid
from taxel.fem.contact import STICK, Press

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
