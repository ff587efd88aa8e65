"""The semi-smooth Newton on the Alart-Curnier contact and friction conditions
(fem.contact._alart_curnier, Options.solver "semismooth"): its generalized Jacobian against
central differences on every branch, its converged states against the Uzawa path's (an
independent iteration on the same equations: a consistency test) and Coulomb's conditions,
and the rig's probe pressed to 1 N in 2D frictionless, where the Uzawa path stops."""

import warnings

import numpy as np
import pytest

from contact_meshes import block, problem
from taxel.fem.assembly import Indenter, assemble
from taxel.fem.constitution import Solid
from taxel.fem.contact import SLIP, STICK, Options, Press
from taxel.fem.contact._alart_curnier import conditions

MU, NU = 10e3, 0.3
MAT = Solid("block", MU, 2 * MU * (1 + NU) / (3 * (1 - 2 * NU)), 1000.0)


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("frictionless", [False, True])
def test_the_alart_curnier_jacobian_is_a_derivative(dim, frictionless):
    """C's derivatives in x and lambda against central differences at random points on a
    flat punch with a rounded edge (open, sticking and slipping points, the curvature terms)."""
    rng = np.random.default_rng(0)
    m, z_top, d, eps, mu = 400, 2e-3, 5e-5, 1e9, 0.3
    ind = Indenter("flat", 1e-3, 3e-4, travel=d, friction=mu)
    X = np.vstack([rng.uniform(0, 1.6e-3, (dim - 1, m)), np.full((1, m), z_top)])
    x = X + 3e-5 * rng.normal(size=X.shape)
    a = x + 1e-6 * rng.normal(size=X.shape)
    lam = 3e3 * rng.normal(size=X.shape)
    lam[-1] = -3 * np.abs(lam[-1])
    cd = conditions(ind, x, lam, a, z_top, d, mu, eps, frictionless)
    slip = cd.closed & ~cd.stick
    assert (~cd.closed).any() and slip.any() and (cd.stick.any() != frictionless)
    for j in range(dim):
        for h, field, jac in ((1e-11, "x", cd.Cx), (1e-3, "lam", cd.Cl)):
            e = np.zeros_like(x)
            e[j] = h
            args = {"x": x, "lam": lam}
            plus = conditions(ind, **{**args, field: args[field] + e}, a=a, z_top=z_top, travel=d, mu=mu, eps=eps,
                              frictionless=frictionless).C
            minus = conditions(ind, **{**args, field: args[field] - e}, a=a, z_top=z_top, travel=d, mu=mu, eps=eps,
                               frictionless=frictionless).C
            np.testing.assert_allclose((plus - minus) / (2 * h), jac[:, j], atol=1e-6 * np.abs(jac).max())


@pytest.fixture(scope="module")
def flat_pair():
    """A flat punch on a bonded compressible layer (plane strain), each law by both solvers."""
    a, d = 1e-3, 2e-5
    tm = block(8 * a, 8 * a, 1.2 * a, a / 6, model="plane_strain", growth=1.4)
    out = {}
    for friction in ("frictionless", 0.3):
        ind = Indenter("flat", a, 0.0, travel=d, friction=friction)
        sy = assemble(problem(tm, MAT, ind))
        for solver in ("semismooth", "uzawa"):
            pr = Press(sy, ind, opts=Options(solver=solver))
            out[friction, solver] = pr, pr.travel(d, first=0.5)
    return out


def test_semismooth_and_uzawa_reach_the_same_state(flat_pair):
    """Two iterations on one set of equations: the same force (to the Uzawa path's penetration
    tolerance, 1e-3 of the travel), the semi-smooth state without penetration and without an
    Uzawa pass, Coulomb's conditions exact at its points (consistency test)."""
    for friction in ("frictionless", 0.3):
        (_, pt), (_, pu) = flat_pair[friction, "semismooth"], flat_pair[friction, "uzawa"]
        assert pt.force == pytest.approx(pu.force, rel=2e-3)
        assert pt.penetration <= 1e-9 * 2e-5 and pt.uzawa == 0
    st = flat_pair[0.3, "semismooth"][0].res.state
    tt = np.sqrt((st.tang.t ** 2).sum(axis=0))
    assert (tt <= 0.3 * st.tn * (1 + 1e-9) + 1e-9).all()
    slip = st.zone == SLIP
    assert slip.any() and (st.zone == STICK).any()
    np.testing.assert_allclose(tt[slip], 0.3 * st.tn[slip], rtol=1e-6)


def test_a_huge_coefficient_sticks_without_a_warning():
    """load.friction = 1e9: no overflow in the return mapping or in the Alart-Curnier
    function (every point sticks), the force that of mu = 3 (both stick) within 0.2 %."""
    a, d = 1e-3, 2e-5
    tm = block(10 * a, 10 * a, 1.2 * a, a / 4, model="plane_strain", growth=1.4)
    F = {}
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        for mu in (3.0, 1e9):
            for solver in ("semismooth", "uzawa"):
                ind = Indenter("flat", a, 0.0, travel=d, friction=mu)
                pr = Press(assemble(problem(tm, MAT, ind)), ind, opts=Options(solver=solver))
                F[mu, solver] = pr.travel(d, first=1.0).force
    assert F[1e9, "semismooth"] == pytest.approx(F[3.0, "semismooth"], rel=2e-3)
    assert F[1e9, "uzawa"] == pytest.approx(F[1e9, "semismooth"], rel=2e-3)


@pytest.mark.slow      # four presses of the 2D probe (about 5 s)
def test_the_probe_reaches_one_newton_in_2d_under_every_law():
    """The rig's probe (thesis-pzt-probe-2d, Yeoh) to 1 N frictionless and at mu = 0.1, 0.3, 1:
    the semi-smooth Newton ("auto") reaches it under every law and agrees with the Uzawa path
    where both reach 1 N (0.1 %)."""
    from taxel.analyses import check, checked_layout, problem as scene_problem
    from taxel.meshing.build import build
    from taxel.scene import load
    sc = load("thesis-pzt-probe-2d").replace(**{"load.force": 1.0, "load.friction": "frictionless"})
    tm = build(checked_layout(sc, check(sc)))
    VF = {}
    for friction in ("frictionless", 0.1, 0.3, 1.0):
        prob = scene_problem(sc.replace(**{"load.friction": friction}), tagged_mesh=tm)
        sy = assemble(prob)
        pt = Press(sy, prob.indenter, opts=Options(solver="auto")).force(1.0)
        VF[friction] = next(iter(pt.voltages.values())) / pt.force
        if friction == 0.3:
            pu = Press(sy, prob.indenter, opts=Options(solver="uzawa")).force(1.0)
            assert VF[friction] == pytest.approx(next(iter(pu.voltages.values())) / pu.force, rel=1e-3)
    # frictionless squeezes the silicone out under the punch: the most sensitive
    assert abs(VF["frictionless"]) > abs(VF[0.1]) > abs(VF[0.3]) > abs(VF[1.0])


@pytest.mark.slow      # the semi-smooth Newton alone on a 3D Coulomb press: about 60 s of CPU
def test_the_semismooth_newton_stays_on_the_branch_in_3d():
    """The quarter Yeoh block under a rigid plate at mu = 0.3 (tests/felupe_contact.py, 4 per
    edge), the semi-smooth Newton alone: the Uzawa path's force and slip zone (FELupe's
    Q1/P0 gives 0.128665 N on the same grid; ours by Uzawa 0.128662 N). Without the trust
    region (a contact point moves at most half the travel per Newton step) it left the branch
    after failed trials: 0.13067 N with the centre open (measured)."""
    from felupe_contact import ours_3d
    o, s = (ours_3d(0.3, n=4, opts=Options(solver=solver)) for solver in ("uzawa", "semismooth"))
    np.testing.assert_allclose(s["F"], o["F"], rtol=5e-4)
    assert (s["zone"] == o["zone"]).mean() >= 0.95
