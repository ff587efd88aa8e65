"""Yeoh silicone: constitutive consistency, tangents, Newton, closed forms, and the
places where methods fail (locking, Newton without load stepping)."""

import numpy as np
import pytest
from scipy.optimize import fsolve

from taxel.analyses import mesh, problem
from taxel.analyses import solve_static as solve
from taxel.fem import constitution as H
from taxel.fem.assembly import assemble
from taxel.fem.hyperelastic import NewtonError, newton, yeoh_terms
from taxel.scene import load, parse, refined

C_YEOH = (7.83e3, 0.103e3, -0.0008e3)       # the 300 % fit (docs/materials.md)


def with_(scene, silicone=None, force=None, **mesh):
    up = {f"mesh.{k}": v for k, v in mesh.items()}
    if silicone:
        up["model.silicone"] = silicone
    if force is not None:
        up["load.force"] = force
    return scene.replace(**up)


# ---------------------------------------------------------------- constitutive level

def test_stress_is_the_derivative_of_the_energy_and_tangent_of_the_stress():
    rng = np.random.default_rng(3)
    F = (np.eye(3) + 0.3 * rng.normal(size=(3, 3)))[..., None, None]
    p = np.array([[2.5e3]])

    def W(F):
        J = np.linalg.det(F[..., 0, 0])
        return H.psi(J ** (-2 / 3) * (F ** 2).sum(), C_YEOH) + p[0, 0] * (J - 1)
    P = H.stress(F, p, C_YEOH)[0][..., 0, 0]
    A = H.tangent(F, p, C_YEOH)[..., 0, 0]
    h = 1e-6
    for i in range(3):
        for j in range(3):
            E = np.zeros_like(F)
            E[i, j] = h
            assert (W(F + E) - W(F - E)) / (2 * h) == pytest.approx(P[i, j], rel=1e-6, abs=1e-6 * np.abs(P).max())
            dP = (H.stress(F + E, p, C_YEOH)[0] - H.stress(F - E, p, C_YEOH)[0])[..., 0, 0] / (2 * h)
            np.testing.assert_allclose(dP, A[:, :, i, j], rtol=1e-6, atol=1e-7 * np.abs(A).max())


@pytest.fixture(scope="module")
def taxel_state():
    """The 2D thesis taxel at 0.2 N with Yeoh silicone: system and converged state."""
    scene = with_(load("thesis-pzt-single-2d"), "yeoh", 0.2, size=1e-3, piezo_size=2e-4)
    sy = assemble(problem(scene))
    x, res, red, _ = newton(sy)
    return sy, x, res


def test_assembled_tangent_matches_finite_differences(taxel_state):
    sy, x, _ = taxel_state
    rng = np.random.default_rng(0)
    d = np.zeros_like(x)
    d[sy.offsets["u"]] = rng.normal(size=sy.offsets["u"].stop) * 1e-6
    for region in sy.yeoh:
        d[sy.offsets[("p", region)]] = rng.normal(size=sy.offsets[("p", region)].stop
                                                  - sy.offsets[("p", region)].start) * 1e2
    _, K = yeoh_terms(sy, x)
    h = 1e-3
    fd = (yeoh_terms(sy, x + h * d, False)[0] - yeoh_terms(sy, x - h * d, False)[0]) / (2 * h)
    Kd = K @ d
    assert np.linalg.norm(fd - Kd) < 1e-6 * np.linalg.norm(Kd)


def test_newton_converges_quadratically(taxel_state):
    _, _, res = taxel_state
    r = [v for v in res.residuals[-1] if v > 1e-13]
    assert res.converged and len(r) >= 3
    # quadratic: log r_{k+1} / log r_k -> 2 (r relative, < 1); the last ratios show it
    orders = [np.log(r[k + 1]) / np.log(r[k]) for k in range(1, len(r) - 1)]
    assert max(orders) > 1.8, (r, orders)


def test_small_load_limit_yeoh_equals_linear():
    base = load("thesis-pzt-single-2d")
    v_lin = solve(base).voltages()["taxel_0_0"]
    rel = []
    for F in (1e-4, 1e-2):
        v = solve(with_(base, "yeoh", F)).voltages()["taxel_0_0"]
        rel.append(abs(v / (v_lin * F) - 1))
    assert rel[0] < 1e-4                       # same discretization of the small-strain limit
    assert rel[1] == pytest.approx(100 * rel[0], rel=0.2)    # and the difference is first order in F


# ---------------------------------------------------------------- homogeneous states

def block(model, sil="yeoh", pressure="5 kPa", K_ratio=1e3, size="2 mm", layers=1):
    plate = ({"shape": "disk", "radius": "2 mm"} if model == "axisymmetric"
             else {"shape": "rectangle", "width": "2 mm", "length": "2 mm"})
    plate["layers"] = [{"material": "gel", "thickness": "2 mm"}]
    return parse({
        "model": {"type": model, "silicone": sil, "depth": "1 mm"} if model.startswith("plane")
        else {"type": model, "silicone": sil},
        "mesh": {"size": size, "piezo_layers": layers, "order": 2},
        "plate": plate, "materials": {"gel": {"kind": "solid", "C10": C_YEOH[0], "C20": C_YEOH[1],
                                              "C30": C_YEOH[2], "K": K_ratio * 2 * C_YEOH[0], "rho": 1070}},
        "load": {"kind": "pressure", "pressure": pressure},
        "supports": {"bottom": "rollers", "edges": "free"},
    })


def homogeneous_reference(P_top, K, lateral_free_dims):
    """Stretches of the two-field Yeoh model in a homogeneous state with nominal
    stress P_top on z and zero stress on the free lateral directions (2: uniaxial,
    1: plane strain = pure shear), solved from the closed-form stress."""
    def F_of(l):
        lz, lt = l
        return np.diag([lt, lt if lateral_free_dims == 2 else 1.0, lz])[..., None, None]

    def eqs(l):
        F = F_of(l)
        J = np.linalg.det(F[..., 0, 0])
        P, _, _ = H.stress(F, np.array([[K * (J - 1)]]), C_YEOH)
        return [P[2, 2, 0, 0] - P_top, P[0, 0, 0, 0]]
    return fsolve(eqs, [0.9, 1.05], xtol=1e-14)


@pytest.mark.parametrize("model,free", [("3d", 2), ("axisymmetric", 2), ("plane_strain", 1)])
@pytest.mark.parametrize("pressure", ["5 kPa", "-3 kPa"])
def test_homogeneous_compression_and_tension_to_round_off(model, free, pressure):
    """One element per direction; the FE state is homogeneous and must equal the
    closed-form stretches of the same energy to round-off."""
    sol = solve(block(model, pressure=pressure))
    P = -float(pressure.split()[0]) * 1e3
    lz, lt = homogeneous_reference(P, 1e3 * 2 * C_YEOH[0], free)
    p, u = sol.mesh.mesh.p, sol.fields.u
    top = p[-1] > 2e-3 * (1 - 1e-9)
    np.testing.assert_allclose(u[top, -1], (lz - 1) * 2e-3, rtol=1e-8)
    np.testing.assert_allclose(sol.fields.strain[:, 0], lt - 1, rtol=1e-7)


def test_distorted_mesh_still_exact():
    scene = block("plane_strain", size="0.5 mm", layers=4)
    tm = mesh(scene)
    m = tm.mesh
    inner = (np.abs(m.p[0]) < 1e-3 - 1e-9) & (m.p[1] > 1e-9) & (m.p[1] < 2e-3 - 1e-9)
    rng = np.random.default_rng(5)
    p = m.p.copy()
    p[:, inner] += rng.uniform(-0.1e-3, 0.1e-3, size=(2, inner.sum()))
    tm.mesh = type(m)(p, m.t).with_subdomains(tm.regions).with_boundaries(tm.facets)
    sol = solve(scene, tagged_mesh=tm)
    lz, lt = homogeneous_reference(-5e3, 1e3 * 2 * C_YEOH[0], 1)
    top = sol.mesh.mesh.p[1] > 2e-3 * (1 - 1e-9)
    np.testing.assert_allclose(sol.fields.u[top, 1], (lz - 1) * 2e-3, rtol=1e-8)


@pytest.mark.parametrize("mode", ["uniaxial", "equibiaxial", "pure_shear"])
def test_incompressible_closed_forms(mode):
    """docs/materials.md's incompressible formulas, reached as K/C10 grows (K = 1e5 mu):
    uniaxial P = 2 (l - l^-2) W'; equibiaxial P = 2 (l - l^-5) W' (the uniaxial
    compression state plus a hydrostatic pressure); pure shear P = 2 (l - l^-3) W'."""
    model = "plane_strain" if mode == "pure_shear" else "3d"
    sol = solve(block(model, pressure="5 kPa", K_ratio=1e5))
    p, u = sol.mesh.mesh.p, sol.fields.u
    lz = 1 + u[p[-1] > 2e-3 * (1 - 1e-9), -1].mean() / 2e-3
    Pz = -5e3

    def dW(I1):
        return H.dpsi(I1, C_YEOH)[0]
    if mode == "uniaxial":
        ref = 2 * (lz - lz ** -2) * dW(lz ** 2 + 2 / lz)
        assert Pz == pytest.approx(ref, rel=1e-4)
    elif mode == "equibiaxial":
        le = lz ** -0.5                       # lateral stretch; sigma_eb = -sigma_zz of the uniaxial state
        P_eb = -Pz * lz / le
        assert P_eb == pytest.approx(2 * (le - le ** -5) * dW(2 * le ** 2 + le ** -4), rel=1e-4)
    else:
        ref = 2 * (lz - lz ** -3) * dW(lz ** 2 + 1 + lz ** -2)
        assert Pz == pytest.approx(ref, rel=1e-4)


# ---------------------------------------------------------------- where methods fail

@pytest.mark.parametrize("ratio", [1e1, 1e3, 1e5])
def test_displacement_p1_locks_mixed_does_not(ratio):
    """Linear silicone, K/mu growing: P1 displacement-only elements lock (the taxel
    voltage error against the converged mixed P2/P1 answer grows with K/mu), the
    mixed formulations (MINI and Taylor-Hood) stay within their discretization error.
    One element through the piezo (the mesh these thresholds were measured on)."""
    base = load("thesis-pzt-single-2d").replace(**{"mesh.piezo_layers": 1})
    gel = {"kind": "solid", "mu": 2 * C_YEOH[0], "K": ratio * 2 * C_YEOH[0], "rho": 1070}

    def v(order, formulation, f=1.0):
        s = base.replace(**{"array.silicone": "gel", "materials": {"gel": gel}, "mesh.order": order,
                            "mesh.formulation": formulation})
        return solve(refined(s, f)).voltages()["taxel_0_0"]
    ref = v(2, "mixed", 2.0)
    err_p1 = abs(v(1, "displacement") / ref - 1)
    err_mini = abs(v(1, "mixed") / ref - 1)
    err_th = abs(v(2, "mixed") / ref - 1)
    assert err_th < 0.01 and err_mini < 0.05
    if ratio >= 1e3:
        assert err_p1 > 5 * err_mini            # locking
    if ratio == 1e5:
        assert err_p1 > 0.3


def test_newton_without_stepping_or_line_search_fails_where_the_default_converges():
    scene = with_(load("thesis-pzt-single-2d"), "yeoh", 0.5)
    with pytest.raises(NewtonError, match="last converged"):
        solve(scene, newton_options={"stepping": False, "line_search": False})
    sol = solve(scene)
    assert sol.newton.converged
    assert sol.reaction[-1] == pytest.approx(0.5, rel=1e-8)


def test_pvdf_52um_under_silicone_converges():
    """Aspect ratio: a 52 um film under 1 mm of silicone, nested refinement; the
    voltage steps shrink and the Yeoh solve converges."""
    scene = with_(load("thesis-pvdf-single-2d"), None, 0.2)
    tm = mesh(scene)
    v = [solve(scene, tagged_mesh=tm.refined(k) if k else tm).voltages()["taxel_0_0"] for k in range(3)]
    assert abs(v[2] - v[1]) < abs(v[1] - v[0])
    assert abs(v[2] - v[1]) < 0.01 * abs(v[2])
    sol = solve(with_(scene, "yeoh"))
    assert sol.newton.converged and sol.voltages()["taxel_0_0"] > 0


@pytest.mark.parametrize("force,expect", [(0.01, "linear"), (0.3, "Yeoh")])
def test_auto_picks_the_cheapest_model_that_is_accurate_enough(force, expect):
    base = load("thesis-pzt-single-2d")
    scene = with_(base, "auto", force)
    sol = solve(scene)
    assert sol.model_note.startswith(f"auto: {expect}")
    v_yeoh = solve(with_(base, "yeoh", force)).voltages()["taxel_0_0"]
    # the answer returned is within the scene's tolerance of the Yeoh answer
    assert abs(sol.voltages()["taxel_0_0"] / v_yeoh - 1) <= scene.model.tolerance


# ---------------------------------------------------------------- vectorised assembly (fem.hyperelastic)

def test_batched_law_equals_the_pointwise_law():
    rng = np.random.default_rng(5)
    F = np.eye(3) + 0.2 * rng.normal(size=(7, 3, 3))
    p = rng.normal(size=7) * 1e3
    P, A, J, JFiT = H.stress_tangent_batched(F, p, C_YEOH)
    Fq = np.moveaxis(F, 0, -1)[..., None]                 # (3, 3, 7, 1): trailing point axes
    P0, J0, FiT0 = H.stress(Fq, p[:, None], C_YEOH)
    A0 = H.tangent(Fq, p[:, None], C_YEOH)
    np.testing.assert_allclose(P, np.moveaxis(P0[..., 0], -1, 0), rtol=1e-12, atol=1e-12 * np.abs(P).max())
    np.testing.assert_allclose(A, np.moveaxis(A0[..., 0], -1, 0).reshape(7, 9, 9), rtol=1e-12,
                               atol=1e-12 * np.abs(A).max())
    np.testing.assert_allclose(J, J0[:, 0], rtol=1e-13)


@pytest.mark.parametrize("model", ["plane_strain", "axisymmetric",
                                   pytest.param("3d", marks=pytest.mark.slow)])     # 3D: 5.6 s of CPU
def test_vectorised_residual_and_tangent_equal_scikit_fem_forms(model):
    """fem.hyperelastic (batched over elements; through the scalar gradients in plane
    strain and 3D, through the vector B with its hoop term in axisymmetric) against
    its test oracle, the scikit-fem forms of fem/hyperelastic/_reference_forms.py
    (`yeoh_terms_skfem`: the same Yeoh energy written as scikit-fem forms), at a
    deformed state, to 1e-12 relative."""
    from taxel.fem.hyperelastic import yeoh_terms_skfem
    size = (3e-3, 1.2e-3) if model == "3d" else (1e-3, 2e-4)
    scene = with_(load("thesis-pzt-single-2d").replace(**{"model.type": model, "model.depth": None}), "yeoh", 0.2,
                  size=size[0], piezo_size=size[1])
    sy = assemble(problem(scene))
    x, _, _, _ = newton(sy)
    u = sy.offsets["u"]
    x[u] += 0.002 * np.abs(x[u]).max() * np.random.default_rng(2).normal(size=x[u].shape)
    r1, K1 = yeoh_terms(sy, x)
    r2, K2 = yeoh_terms_skfem(sy, x)
    assert np.abs(r1 - r2).max() < 1e-12 * np.abs(r2).max()
    assert abs(K1 - K2).max() < 1e-12 * abs(K2).max()


def test_smallest_jacobian_finds_where_the_silicone_is_most_compressed():
    """u = (-c x^2, 0, 0) on a P2 tetrahedral box, represented exactly: J = 1 - 2 c x, smallest
    where x is largest. fem.hyperelastic.smallest_jacobian returns that J and its point (the
    press's stop names where its elements crush, fem.contact)."""
    import skfem
    from taxel.fem.hyperelastic import min_jacobian, smallest_jacobian
    from taxel.fem.constitution import Solid3D
    m = skfem.MeshTet.init_tensor(*(np.linspace(0, 1e-3, 4),) * 3)
    ub = skfem.Basis(m, skfem.ElementVector(skfem.ElementTetP2()))
    c = 400.0                                            # 1/m: J from 1 down to 0.2 over the box
    u = ub.project(lambda x: np.stack([-c * x[0] ** 2, 0 * x[0], 0 * x[0]]))
    J, X = smallest_jacobian(ub, u, Solid3D())
    xq = np.asarray(ub.global_coordinates())[0]
    assert J == pytest.approx(1 - 2 * c * X[0], abs=1e-9)
    assert X[0] == pytest.approx(xq.max())
    assert J == min_jacobian(ub, u, Solid3D()) == pytest.approx(1 - 2 * c * xq.max(), abs=1e-9)
