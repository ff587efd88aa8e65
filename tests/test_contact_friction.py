"""Coulomb friction (fem.contact's return mapping, Indenter(friction=mu)): the
consistent tangent and travel derivatives against central differences, Coulomb's
inequality at the converged state, and the limits: mu = 0 is frictionless, a large
mu is sticking (fem.contact.Stick), in plane strain and axisymmetric presses."""

import numpy as np
import pytest

from contact_meshes import block, problem
from taxel.fem.assembly import assemble
from taxel.fem.assembly import Indenter
from taxel.fem.constitution import Solid
from taxel.fem.contact import OPEN, SLIP, STICK, Coulomb, Press, Surface

MU, NU = 10e3, 0.3
MAT = Solid("block", MU, 2 * MU * (1 + NU) / (3 * (1 - 2 * NU)), 1000.0)


def _coulomb_state(ind, model, seed, mu=0.3):
    """A small block with random u, normal and tangential multipliers and anchors:
    some points open, some sticking, some slipping."""
    tm = block(4e-3, 2e-3, 1e-3, 2.5e-4, model=model, growth=1.5)
    sy = assemble(problem(tm, MAT, ind))
    ub = next(iter(sy.ubases.values()))
    surf = Surface(tm.mesh, ub.elem, tm.facets["top"], sy.kin, 2e-3)
    rng = np.random.default_rng(seed)
    u = 1e-5 * rng.normal(size=ub.N)
    lam = np.abs(rng.normal(size=surf.shape)) * 1e3
    a0 = surf.X + 2e-7 * rng.normal(size=surf.X.shape)
    c = Coulomb(mu, a0, 3e2 * rng.normal(size=surf.X.shape), np.zeros(surf.shape))
    return surf, ub, u, lam, 1e9, c


@pytest.mark.parametrize("shape,model", [("sphere", "plane_strain"), ("sphere", "axisymmetric"),
                                         ("flat", "plane_strain")])
def test_coulomb_tangent_and_travel_derivatives_are_derivatives(shape, model):
    ind = Indenter(shape, 3e-3 if shape == "sphere" else 1e-3, 3e-4 if shape == "flat" else 0.0,
                   travel=5e-5, friction=0.3)
    surf, ub, u, lam, eps, c = _coulomb_state(ind, model, 2)
    d = 5e-5
    st = surf.state(u, ind, d, lam, eps, stick=c)
    zone = st.zone
    assert (zone == STICK).any() and (zone == SLIP).any() and (zone == OPEN).any()
    S = surf.dofs
    from taxel.fem.hyperelastic import scatter
    K = scatter(S, S, surf.element_tangent(st, eps), ub.N).toarray()

    def res(uu, dd=d):
        return np.bincount(S.ravel(), surf.element_residual(surf.state(uu, ind, dd, lam, eps, stick=c)).ravel(),
                           minlength=ub.N)
    h = 1e-12
    rng = np.random.default_rng(3)
    for k in rng.choice(np.flatnonzero(np.abs(K).sum(axis=0) > 0), 10, replace=False):
        e = np.zeros(ub.N)
        e[k] = h
        np.testing.assert_allclose((res(u + e) - res(u - e)) / (2 * h), K[:, k], rtol=1e-4,
                                   atol=1e-5 * np.abs(K).max())
    dr, dF_dd, dF_du = surf.travel_derivatives(st, eps)
    fd = (res(u, d + h) - res(u, d - h)) / (2 * h)
    np.testing.assert_allclose(np.bincount(S.ravel(), dr.ravel(), minlength=ub.N), fd, rtol=1e-4,
                               atol=1e-5 * np.abs(fd).max())
    Fp, Fm = (surf.state(u, ind, dd, lam, eps, stick=c).force for dd in (d + h, d - h))
    assert dF_dd == pytest.approx((Fp - Fm) / (2 * h), rel=1e-4)


def _flat_press(friction, model="plane_strain", d=2e-5):
    a = 1e-3
    tm = block(20 * a, 20 * a, 1.2 * a, a / 8, model=model, growth=1.3)
    ind = Indenter("flat", a, 0.0, travel=d, friction=friction)
    pr = Press(assemble(problem(tm, MAT, ind)), ind)
    pt = pr.travel(d, first=0.5)
    return pr, pt


@pytest.fixture(scope="module", params=["plane_strain", pytest.param("axisymmetric", marks=pytest.mark.slow)])
def flat_presses(request):
    return {f: _flat_press(f, request.param) for f in ("frictionless", 0.0, 0.1, 0.3, 3.0, "sticking")}


def test_coulomb_lies_between_frictionless_and_sticking(flat_presses):
    """A bonded compressible (nu = 0.3) layer under a flat punch: mu = 0 gives the
    frictionless force, the force grows with mu, and a large mu gives sticking's."""
    F = {f: pt.force for f, (_, pt) in flat_presses.items()}
    assert F[0.0] == pytest.approx(F["frictionless"], rel=1e-6)
    assert F["frictionless"] < F[0.1] < F[0.3] <= F[3.0]
    assert F[3.0] == pytest.approx(F["sticking"], rel=2e-3)
    assert F["sticking"] > 1.01 * F["frictionless"]


def test_converged_tractions_obey_coulomb(flat_presses):
    """|t_T| <= mu t_N everywhere, = at the slipping points, and the slip zone lies at the
    punch's edge (outside the stick zone) with a positive slip distance there."""
    for mu in (0.1, 0.3):
        pr, pt = flat_presses[mu]
        st = pr.res.state
        tt = np.sqrt((st.tang.t ** 2).sum(axis=0))
        assert (tt <= mu * st.tn * (1 + 1e-9) + 1e-12).all()
        slip = st.zone == SLIP
        assert slip.any() and (st.zone == STICK).any()
        np.testing.assert_allclose(tt[slip], mu * st.tn[slip], rtol=1e-9)
        r = np.abs(st.x[0])
        far = slip & (st.slip > 1e-3 * 2e-5)      # slipped by more than the gap tolerance
        assert far.any() and r[far].min() > r[st.zone == STICK].min()
        assert (st.slip[slip] > 0).all()
        assert pt.penetration <= 1e-3 * 2e-5


@pytest.mark.parametrize("shape", ["flat", pytest.param("sphere", marks=pytest.mark.slow)])
def test_incompressible_half_space_closed_forms_hold_with_friction(shape):
    """On an incompressible half-space a normal load moves the surface only normally
    (Johnson, Contact Mechanics, 1985, eq. 3.19b: the tangential displacement of a point
    load carries 1 - 2 nu), so friction carries no traction and Coulomb contact gives the
    frictionless closed forms (E* = E / (1 - nu^2) = 4 mu_s at nu = 1/2):
      Boussinesq, flat punch radius a:  F = 2 a E* d
      Hertz, sphere radius R:           F = 4/3 E* R^1/2 d^3/2,  contact radius sqrt(R d)
    within 2 % (axisymmetric, a bonded block of radius and height 300 a: the layer's
    correction is about 1 %, tests/test_contact.py). The contact is finite-strain in its
    geometry (the sphere's normal tilts by r / R), so the friction carries a little traction."""
    nu = 0.4999
    mat = Solid("block", MU, 2 * MU * (1 + nu) / (3 * (1 - 2 * nu)), 1000.0)
    e_star = 2 * MU * (1 + nu) / (1 - nu ** 2)
    if shape == "flat":
        a = 1e-3
        d = 1e-3 * a
        tm = block(300 * a, 300 * a, 1.2 * a, a / 16, growth=1.3)
        ind = Indenter("flat", a, 0.0, travel=d, friction=0.3)
        closed = 2 * a * e_star * d
    else:
        R = 10e-3
        d = 0.004 * R
        a = np.sqrt(R * d)
        tm = block(300 * a, 300 * a, 1.5 * a, a / 8, growth=1.3)
        ind = Indenter("sphere", R, travel=d, friction=0.3)
        closed = 4 / 3 * e_star * np.sqrt(R) * d ** 1.5
    pr = Press(assemble(problem(tm, mat, ind)), ind)
    pt = pr.travel(d, first=1.0)
    assert pt.force == pytest.approx(closed, rel=0.02)
    assert pr.res.state.half_width() == pytest.approx(a, rel=0.02)
    print(f"{shape}: F / closed form - 1 = {pt.force / closed - 1:+.2%}, "
          f"a / closed form - 1 = {pr.res.state.half_width() / a - 1:+.2%}")


@pytest.mark.slow      # three 3D presses
def test_coulomb_flat_punch_in_3d_on_the_quarter_model():
    """3D (the quarter model, two symmetry planes; the 3D contact points, P2 nodes lumped):
    a flat punch on a compressible (nu = 0.3) bonded block: mu = 0.3 lies between the
    frictionless and the sticking force, Coulomb's inequality holds at every point, and
    the stick zone is inside the slip zone. (Not at nu = 0.4999: there the Coulomb press
    stagnates in its first step, the stick/slip split of the nearly traction-free surface
    changing from iterate to iterate; frictionless and sticking converge. Measured: the
    normal active set moves between 415 and 433 of 455 points, line-search steps of 1/64.)"""
    from contact_meshes import block3d
    a = 1e-3
    d = 1e-3 * a
    tm = block3d(30 * a, 30 * a, a, a / 8, a / 4)
    F = {}
    for friction in ("frictionless", 0.3, "sticking"):
        ind = Indenter("flat", a, 0.0, travel=d, friction=friction)
        pr = Press(assemble(problem(tm, MAT, ind)), ind)
        assert pr.G == 4
        F[friction] = pr.travel(d, first=1.0).force
        if friction == 0.3:
            st = pr.res.state
    assert F["frictionless"] * 1.005 < F[0.3] < F["sticking"] * 1.001
    tt = np.sqrt((st.tang.t ** 2).sum(axis=0))
    assert (tt <= 0.3 * st.tn * (1 + 1e-9) + 1e-12).all()
    r = np.sqrt(st.x[0] ** 2 + st.x[1] ** 2)
    far = (st.zone == SLIP) & (st.slip > 1e-3 * d)
    assert far.any() and (st.zone == STICK).any() and r[far].min() > r[st.zone == STICK].min()


def test_the_slip_zone_is_a_result_field(flat_presses):
    """PressResult.slip_zone: per contact point its state and slip distance, and its
    summary (the result's JSON record, contact.slip_zone)."""
    pr, _ = flat_presses[0.3]
    z = pr.res.slip_zone
    assert z.state.shape == z.slip.shape == (z.x.shape[1],)
    rec = z.record()
    assert rec["stick_points"] + rec["slip_points"] + rec["open_points"] == z.state.size
    assert 0 < rec["stick_half_width_m"] < rec["slip_half_width_m"] <= 1.1e-3
    assert rec["largest_slip_m"] == pytest.approx(float(pr.res.state.slip.max()))
    stuck = _flat_press("sticking")[0].res.slip_zone
    assert stuck.slip is None and stuck.record()["stick_points"] > 0


def test_load_friction_takes_a_coefficient_and_refuses_a_negative_one():
    from taxel.scene import SceneError, load
    sc = load("thesis-pzt-probe-2d").replace(**{"load.friction": 0.4})
    assert sc.load.friction == 0.4
    from taxel.analyses import indenter, mesh
    assert indenter(sc, mesh(sc)).coulomb == 0.4
    for bad in (-0.3, "lots", True):
        with pytest.raises(SceneError, match="load.friction: expected .* Coulomb coefficient >= 0"):
            load("thesis-pzt-probe-2d").replace(**{"load.friction": bad})


@pytest.mark.slow      # three 2D presses of the probe example
def test_the_friction_band_of_the_probe_example():
    """taxel.analyses.solves.friction_band: the 2D probe example at 0.3 N with mu = 0.4, solved at
    frictionless, 0.4 and sticking: the frictionless press is the most sensitive (material
    squeezed out under the punch strains the piezo more), mu = 0.4 lies between, and the
    record carries every leg (the JSON key friction_band of `taxel solve --friction-band`)."""
    import json
    from taxel.analyses import FrictionBand, friction_band
    from taxel.scene import load
    sc = load("thesis-pzt-probe-2d").replace(**{"load.friction": 0.4, "load.force": 0.3})
    band = friction_band(sc)
    assert isinstance(band, FrictionBand) and all(leg.success for leg in band.legs)
    s = {str(leg.friction): abs(leg.sensitivity) for leg in band.legs}
    assert s["frictionless"] > s["0.4"] > 0.99 * s["sticking"]
    assert band.sensitivity_spread == pytest.approx((max(s.values()) - min(s.values())) / s["sticking"])
    rec = json.loads(json.dumps(band.record()))
    assert rec["coulomb"]["friction"] == 0.4 and rec["frictionless"]["force_N"] == pytest.approx(0.3, rel=2e-3)
