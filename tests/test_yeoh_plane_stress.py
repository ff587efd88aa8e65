"""Yeoh silicone in plane stress (fem.hyperelastic): the condensed law against
its energy and finite differences, the FE sheet against the incompressible closed
forms to 1e-8 and against the 3D bar, the thin 3D slab, and the taxel."""

import numpy as np
import pytest
from scipy.optimize import brentq

from taxel.analyses import problem
from taxel.analyses import solve_static as solve
from taxel.fem import constitution as H
from taxel.fem import hyperelastic as S
from taxel.fem.assembly import assemble
from taxel.fem.static import component_dofs
from taxel.fem.hyperelastic import newton
from taxel.scene import load, parse

C_YEOH = (7.83e3, 0.103e3, -0.0008e3)       # the 300 % fit (docs/materials.md)
K_TOOL = 1e3 * 2 * C_YEOH[0]                 # the tool's bulk modulus, 1000 mu


def laws():
    return [H.Yeoh(*C_YEOH, K=K_TOOL), H.Yeoh(*C_YEOH, K=10 * 2 * C_YEOH[0]), H.Yeoh(*C_YEOH, K=None)]


def sheet_energy(F2, law):
    """W2(F2) = W(F2, lambda3(F2)) of the 3D law."""
    l3, _ = S.thickness_stretch(F2, law)
    I1 = np.einsum("nij,nij->n", F2, F2) + l3 ** 2
    if S.incompressible(law):
        return H.psi(I1, law.C)
    J = np.linalg.det(F2) * l3
    return H.psi(J ** (-2 / 3) * I1, law.C) + law.K / 2 * (J - 1) ** 2


@pytest.mark.parametrize("law", laws(), ids=["K=1000mu", "K=10mu", "incompressible"])
def test_condensed_stress_and_tangent_are_the_derivatives_of_the_sheet_energy(law):
    rng = np.random.default_rng(1)
    F2 = np.eye(2) + 0.3 * rng.standard_normal((6, 2, 2))
    P2, A2, J, l3 = S.stress_tangent(F2, law)
    if not S.incompressible(law):             # the faces are traction-free: P33 = 0 of the 3D law
        F = np.zeros((6, 3, 3))
        F[:, :2, :2], F[:, 2, 2] = F2, l3
        P, *_ = H.stress_tangent_batched(F, law.K * (np.linalg.det(F) - 1), law.C, False)
        assert np.abs(P[:, 2, 2]).max() < 1e-10 * np.abs(P).max()
        np.testing.assert_allclose(P[:, :2, :2], P2, rtol=0, atol=1e-9 * np.abs(P2).max())
    else:
        np.testing.assert_allclose(J, 1.0)
    h = 1e-6
    dW, dP = np.zeros((6, 4)), np.zeros((6, 4, 4))
    for k in range(4):
        d = np.zeros(4)
        d[k] = h
        d = d.reshape(2, 2)
        dW[:, k] = (sheet_energy(F2 + d, law) - sheet_energy(F2 - d, law)) / (2 * h)
        dP[:, :, k] = (S.stress_tangent(F2 + d, law)[0] - S.stress_tangent(F2 - d, law)[0]).reshape(6, 4) / (2 * h)
    assert np.abs(dW - P2.reshape(6, 4)).max() < 1e-8 * np.abs(P2).max()
    assert np.abs(dP - A2).max() < 1e-7 * np.abs(A2).max()
    assert np.abs(A2 - A2.transpose(0, 2, 1)).max() < 1e-12 * np.abs(A2).max()


def test_condensation_tends_to_the_incompressible_sheet_as_K_grows():
    F2 = np.array([[[1.4, 0.2], [-0.1, 0.8]]])
    P_inc = S.stress_tangent(F2, H.Yeoh(*C_YEOH))[0]
    errs = [np.abs(S.stress_tangent(F2, H.Yeoh(*C_YEOH, K=r * 2 * C_YEOH[0]))[0] - P_inc).max() / np.abs(P_inc).max()
            for r in (1e2, 1e3, 1e4)]
    assert errs[0] > 8 * errs[1] > 64 * errs[2]       # first order in mu / K


# ---------------------------------------------------------------- homogeneous sheets

def block(pressure, edges="free", K=K_TOOL):
    """A 2 x 2 mm Yeoh sheet (1 mm thick), rollers under it, a dead pressure on top."""
    return parse(block_data(pressure, edges, K))


def block_data(pressure, edges="free", K=K_TOOL):
    return ({
        "model": {"type": "plane_stress", "silicone": "yeoh", "depth": "1 mm"},
        "mesh": {"size": "1 mm", "piezo_layers": 2, "order": 2},
        "plate": {"shape": "rectangle", "width": "2 mm", "length": "2 mm",
                  "layers": [{"material": "gel", "thickness": "2 mm"}]},
        "materials": {"gel": {"kind": "solid", "C10": C_YEOH[0], "C20": C_YEOH[1], "C30": C_YEOH[2],
                              "K": K, "rho": 1070}},
        "load": {"kind": "pressure", "pressure": pressure},
        "supports": {"bottom": "rollers", "edges": edges},
    })


def incompressible_stretch(pressure_pa, edges):
    """The FE sheet with the exactly incompressible law (K None): the top's stretch lz."""
    sy = assemble(problem(block(f"{pressure_pa} Pa", edges)))
    sy.yeoh = {r: H.Yeoh(*C_YEOH) for r in sy.yeoh}
    x, res, *_ = newton(sy)
    assert res.converged
    u = x[sy.offsets["u"]]
    ub = next(iter(sy.ubases.values()))
    top = ub.nodal_dofs[1][sy.tm.mesh.p[1] > 2e-3 * (1 - 1e-9)]
    uz = u[top]
    assert np.ptp(uz) < 1e-12 * np.abs(uz).max()             # homogeneous
    return 1 + uz.mean() / 2e-3


@pytest.mark.parametrize("pressure", [5e3, -3e3])
def test_incompressible_sheet_uniaxial_closed_form(pressure):
    """Free edges: uniaxial, P = 2 (l - l^-2) W'(l^2 + 2/l) (fem.constitution.nominal_stress)."""
    lz = incompressible_stretch(pressure, "free")
    assert H.nominal_stress("uniaxial", lz, *C_YEOH) == pytest.approx(-pressure, rel=1e-8)
    ref = brentq(lambda l: H.nominal_stress("uniaxial", l, *C_YEOH) + pressure, 0.3, 3, xtol=1e-15)
    assert lz == pytest.approx(ref, rel=1e-8)


def test_incompressible_sheet_pure_shear_closed_form():
    """Edges on rollers (lx = 1), the thickness free: pure shear, P = 2 (l - l^-3) W'."""
    lz = incompressible_stretch(-3e3, "rollers")
    assert H.nominal_stress("pure shear", lz, *C_YEOH) == pytest.approx(3e3, rel=1e-8)


def test_incompressible_sheet_equibiaxial_closed_form():
    """Uniaxial compression of the incompressible sheet is, up to a hydrostatic pressure,
    equibiaxial tension in x and the thickness: le = lz^-1/2, P_eb = -Pz lz / le."""
    lz = incompressible_stretch(5e3, "free")
    le = lz ** -0.5
    assert H.nominal_stress("equibiaxial", le, *C_YEOH) == pytest.approx(5e3 * lz / le, rel=1e-8)


@pytest.mark.parametrize("pressure", ["5 kPa", "-3 kPa"])
def test_compressible_sheet_equals_the_3d_bar(pressure):
    """With the tool's K the uniaxial sheet is the uniaxial 3D bar of the same energy
    (both lateral directions free): stretches from the 3D stress, to 1e-8."""
    sol = solve(block(pressure))
    P_top = -float(pressure.split()[0]) * 1e3

    def eqs(l):
        F = np.diag([l[1], l[1], l[0]])[None]
        p = K_TOOL * (np.linalg.det(F) - 1)
        P, *_ = H.stress_tangent_batched(F, p, C_YEOH, False)
        return [P[0, 2, 2] - P_top, P[0, 0, 0]]
    from scipy.optimize import fsolve
    lz, lt = fsolve(eqs, [0.9, 1.05], xtol=1e-13)
    top = sol.mesh.mesh.p[1] > 2e-3 * (1 - 1e-9)
    np.testing.assert_allclose(sol.fields.u[top, 1], (lz - 1) * 2e-3, rtol=1e-8)
    np.testing.assert_allclose(sol.fields.strain[:, 0], lt - 1, rtol=1e-7)
    assert sol.newton.total_iterations <= 6                 # the consistent tangent: quadratic


# ---------------------------------------------------------------- thin 3D slab

def slab(model, thickness="0.05 mm"):
    """A 2 mm wide, 1 mm high Yeoh block (tool's K), bonded bottom, pulled by 2 kPa on
    top: an inhomogeneous state (the bonded corners). 3D: a slab `thickness` deep."""
    m = {"type": model, "silicone": "yeoh"}
    if model != "3d":
        m["depth"] = thickness
    return parse({"model": m, "mesh": {"size": "0.125 mm", "order": 2, "piezo_layers": 8},
                  "plate": {"shape": "rectangle", "width": "2 mm", "length": thickness,
                            "layers": [{"material": "gel", "thickness": "1 mm"}]},
                  "materials": {"gel": {"kind": "solid", "C10": C_YEOH[0], "C20": C_YEOH[1], "C30": C_YEOH[2],
                                        "K": K_TOOL, "rho": 1070}},
                  "load": {"kind": "pressure", "pressure": "-2 kPa"},
                  "supports": {"bottom": "bonded", "edges": "free"}})


@pytest.mark.slow
def test_plane_stress_sheet_equals_a_thin_3d_slab():
    """The 3D slab, 0.05 mm deep (1/40 of its width), its faces y = +-t/2 traction-free
    and its bottom holding u_x and u_z but not u_y (the sheet's thickness is free at
    its bonded edge too; u_y = 0 on the mid-plane y = 0 by symmetry): the top's mean
    lift within 0.05 % and the top corner's lateral pull within 0.5 % of the sheet's
    (measured 0.008 % and 0.25 %). With u_y held on the bottom as well, the slab is
    1.3 % stiffer: a boundary layer one element (0.125 mm) high, not of the sheet."""
    sheet = solve(slab("plane_stress"))
    p, u = sheet.mesh.mesh.p, sheet.fields.u
    top = p[1] > 1e-3 * (1 - 1e-9)
    lift_2d, pull_2d = u[top, 1].mean(), u[top, 0].max()

    sy = assemble(problem(slab("3d")))
    ub = next(iter(sy.ubases.values()))
    y = component_dofs(ub, 1)
    sy.fixed_u = np.setdiff1d(sy.fixed_u, y[np.abs(ub.doflocs[1, y]) > 1e-9 * 5e-5])
    x, res, *_ = newton(sy)
    u3 = x[sy.offsets["u"]]
    zt = ub.nodal_dofs[2][sy.tm.mesh.p[2] > 1e-3 * (1 - 1e-9)]
    xd = component_dofs(ub, 0)
    xt = xd[ub.doflocs[2, xd] > 1e-3 * (1 - 1e-9)]
    assert res.converged
    assert u3[zt].mean() == pytest.approx(lift_2d, rel=5e-4)
    assert u3[xt].max() == pytest.approx(pull_2d, rel=5e-3)


# ---------------------------------------------------------------- taxel

def test_thesis_taxel_in_plane_stress_small_load_limit_is_linear():
    """The condensed law's small-strain limit is the linear plane-stress silicone
    (mu = 2 C10, lambda* = 2 lambda mu / (lambda + 2 mu)) in the displacement formulation
    (the condensed form integrates lambda* div u fully; the mixed linear form projects it
    on the P1 pressure, 0.4 % apart on this mesh): the difference is first order in the
    force; at 0.4 N the nonlinearity shows (+1.2 % voltage per newton)."""
    base = load("thesis-pzt-single-2d").replace(**{"model.type": "plane_stress"})
    v_lin = solve(base.replace(**{"mesh.formulation": "displacement"})).voltages()["taxel_0_0"]
    rel = []
    for f in (1e-4, 1e-2):
        v = solve(base.replace(**{"model.silicone": "yeoh", "load.force": f})).voltages()["taxel_0_0"]
        rel.append(abs(v / (v_lin * f) - 1))
    assert rel[0] < 1e-4
    assert rel[1] == pytest.approx(100 * rel[0], rel=0.2)
    sol = solve(base.replace(**{"model.silicone": "yeoh", "load.force": 0.4}))
    assert sol.newton.converged
    assert 0.005 < abs(sol.voltages()["taxel_0_0"] / (0.4 * v_lin) - 1) < 0.1   # nonlinear, not far


# ---------------------------------------------------------------- studies: the last converged load

@pytest.mark.slow
def test_a_study_point_past_the_laws_limit_reports_the_last_converged_load(tmp_path):
    """A Yeoh set with C30 < 0 has a largest uniaxial nominal stress; pulled 20 % past
    it, Newton stops short, and the study point is the solve at the last converged
    pressure (requested load kept, stopped_at in the tidy row)."""
    from taxel.studies.evaluate import evaluate
    C = (7.83e3, 0.0, -60.0)
    lam = np.linspace(1, 6, 20001)
    P_max = H.nominal_stress("uniaxial", lam, *C).max()
    data = block_data(f"{-1.2 * P_max} Pa")
    data["materials"]["gel"].update(C10=C[0], C20=C[1], C30=C[2])
    res = evaluate(data, ("voltage",))
    reached = -res["force"] / (2e-3 * 1e-3)              # N (downward +) over the 2 mm x 1 mm top: Pa
    assert res["requested_load"] == pytest.approx(-1.2 * P_max)
    assert 0.9 * P_max < reached < P_max
    from taxel.studies.store import Store, tidy_rows
    store = Store(tmp_path)
    store.put("k", {"pressure": "pulled"}, "done", res, None, 1.0)
    store.close()
    assert tidy_rows(tmp_path)[0]["stopped_at"] == res["force"]


@pytest.mark.slow
@pytest.mark.parametrize("name,n", [("fig-2-5-thesis", 140), ("fig-2-8-thesis", 180)])
def test_the_thesis_model_studies_pair_every_linear_point_with_a_plane_stress_yeoh_point(name, n):
    from taxel.studies.spec import load_study
    st = load_study(name)
    data = [st.scene_data(p) for p in st.points()]
    laws = [d["model"]["silicone"] for d in data]
    assert len(data) == n and laws.count("yeoh") == laws.count("linear") == n // 2
    for d in (data[0], data[-1]):                      # linear and Yeoh: valid plane-stress scenes
        scene = parse({**d, "name": "p"})
        assert scene.model.type == "plane_stress" and scene.model.silicone in ("linear", "yeoh")
