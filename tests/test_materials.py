"""Material library: sourced values, form conversions, rotations and 2D reductions; a
user material (a [materials] table) as the silicone of a scene, solved."""

import json

import numpy as np
import pytest

from taxel.fem import constitution as M
from taxel.cli import main
from taxel.fem import constitution

EPS0 = M.EPS0


def test_pzt5h_stress_charge_matches_reference_table():
    # docs/materials.md: converted from Erturk & Inman Table E.1
    m = M.get("PZT-5H")
    c = m.c / 1e9
    assert c[0, 0] == pytest.approx(127.205, rel=2e-4)
    assert c[0, 1] == pytest.approx(80.212, rel=2e-4)
    assert c[0, 2] == pytest.approx(84.670, rel=2e-4)
    assert c[2, 2] == pytest.approx(117.436, rel=2e-4)
    assert c[3, 3] == pytest.approx(22.989, rel=2e-4)
    assert c[5, 5] == pytest.approx(23.474, rel=2e-4)
    assert m.e[2, 0] == pytest.approx(-6.623, rel=2e-4)
    assert m.e[2, 2] == pytest.approx(23.240, rel=2e-4)
    assert m.e[0, 4] == pytest.approx(17.034, rel=2e-4)
    assert m.eps[0, 0] / EPS0 == pytest.approx(1704.4, rel=2e-4)
    assert m.eps[2, 2] / EPS0 == pytest.approx(1433.6, rel=2e-4)


def test_psi5h4e_reproduces_its_datasheet():
    m = M.get("PSI-5H4E")
    s, d, epsT = m.strain_charge()
    assert d[2, 2] == pytest.approx(650e-12, rel=1e-12)
    assert d[2, 0] == pytest.approx(-320e-12, rel=1e-12)
    assert epsT[2, 2] / EPS0 == pytest.approx(3800, rel=1e-12)
    assert 1 / s[0, 0] == pytest.approx(6.2e10, rel=1e-12)
    assert 1 / s[2, 2] == pytest.approx(5.0e10, rel=1e-12)
    assert m.g33 == pytest.approx(19.0e-3, rel=0.02)          # sheet: 19.0e-3 Vm/N
    k31 = abs(d[2, 0]) / np.sqrt(s[0, 0] * epsT[2, 2])
    k33 = d[2, 2] / np.sqrt(s[2, 2] * epsT[2, 2])
    assert k31 == pytest.approx(0.44, abs=0.02)                # sheet: 0.44
    assert k33 == pytest.approx(0.75, abs=0.05)                # sheet: 0.75
    # free capacitance of a 4 x 4 x 0.127 mm taxel: about 4.24 nF (docs/materials.md)
    assert epsT[2, 2] * 16e-6 / 0.127e-3 == pytest.approx(4.24e-9, rel=0.01)


def test_pvdf_manual_values_and_signs():
    m = M.get("PVDF")
    s, d, epsT = m.strain_charge()
    assert d[2, 0] == pytest.approx(23e-12) and d[2, 2] == pytest.approx(-33e-12)
    assert d[2, 0] / epsT[2, 2] == pytest.approx(216e-3, rel=0.01)     # g31, manual 216e-3
    assert d[2, 2] / epsT[2, 2] == pytest.approx(-330e-3, rel=0.07)    # g33, manual -330e-3 (eps_r 12 vs 13)
    assert epsT[2, 2] * 16e-6 / 52e-6 == pytest.approx(33.5e-12, rel=0.03)   # 33 to 35 pF


@pytest.mark.parametrize("name", ["PZT-5H", "PSI-5H4E", "PVDF"])
def test_electromechanical_matrix_is_positive_definite(name):
    s, d, epsT = M.get(name).strain_charge()
    full = np.block([[s, d.T], [d, epsT]])
    assert np.linalg.eigvalsh(full).min() > 0


@pytest.mark.parametrize("name", ["PZT-5H", "PVDF"])
def test_form_conversion_round_trip(name):
    m = M.get(name)
    c, e, eps = M.strain_to_stress_charge(*m.strain_charge())
    np.testing.assert_allclose(c, m.c, rtol=1e-10)
    np.testing.assert_allclose(e, m.e, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(eps, m.eps, rtol=1e-10)


def test_poling_down_flips_the_piezo_tensor_and_keeps_stiffness():
    m = M.get("PZT-5H")
    down = m.poled([0, 0, -1])
    np.testing.assert_allclose(down.c, m.c, rtol=1e-12, atol=1e-3)
    assert down.e[2, 2] == pytest.approx(-m.e[2, 2])
    assert down.e[2, 0] == pytest.approx(-m.e[2, 0])
    np.testing.assert_allclose(down.eps, m.eps, rtol=1e-12)


def test_poling_along_x_moves_d33_to_d11():
    m = M.get("PZT-5H").poled([1, 0, 0])
    s, d, _ = m.strain_charge()
    assert d[0, 0] == pytest.approx(593e-12, rel=1e-10)
    assert d[0, 1] == pytest.approx(-274e-12, rel=1e-10)
    assert s[0, 0] == pytest.approx(20.7e-12, rel=1e-10)      # s33 now along x


def test_rotation_round_trip_for_an_arbitrary_direction():
    m = M.get("PVDF")
    R = M.poling_rotation([0.3, -0.5, 0.8])
    c, e, eps = M.rotate(*M.rotate(m.c, m.e, m.eps, R), R.T)
    np.testing.assert_allclose(c, m.c, rtol=1e-10, atol=1e-3)
    np.testing.assert_allclose(e, m.e, atol=1e-12)


def _condensed(c, e, eps, keep_S, zero_T, keep_E, rng):
    """Independent check of a 2D reduction: pick kept strains and fields at random,
    solve the 3D stress-charge law for the strains whose stresses must vanish
    (zero_T), with the other strains zero and E_y = 0, and return kept T and D."""
    S = np.zeros(6)
    E = np.zeros(3)
    S[keep_S] = rng.normal(size=len(keep_S)) * 1e-4
    E[keep_E] = rng.normal(size=len(keep_E)) * 1e4
    if zero_T:
        # T_z = c[z,:] S - e[:,z]^T E = 0 for the unknown strains in zero_T
        A = c[np.ix_(zero_T, zero_T)]
        rhs = -(c[zero_T] @ S - e[:, zero_T].T @ E)
        S[zero_T] = np.linalg.solve(A, rhs)
    T = c @ S - e.T @ E
    D = e @ S + eps @ E
    return S[keep_S], E[keep_E], T[keep_S], D[keep_E]


@pytest.mark.parametrize("model,zero_T", [("plane_strain", []), ("plane_stress", [1, 3, 5])])
def test_plane_reductions_against_3d_condensation(model, zero_T):
    m = M.get("PSI-5H4E").poled([0.0, 0.0, 1.0])
    cr, er, epsr = M.model_tensors(m, model)
    rng = np.random.default_rng(1)
    for _ in range(3):
        S, E, T, D = _condensed(m.c, m.e, m.eps, [0, 2, 4], zero_T, [0, 2], rng)
        np.testing.assert_allclose(cr @ S - er.T @ E, T, rtol=1e-9, atol=1e-6)
        np.testing.assert_allclose(er @ S + epsr @ E, D, rtol=1e-9, atol=1e-16)


def test_axisymmetric_reduction_needs_transverse_isotropy():
    c, e, eps = M.model_tensors(M.get("PZT-5H"), "axisymmetric")
    assert c.shape == (4, 4) and e.shape == (2, 4)
    with pytest.raises(ValueError, match="transversely isotropic"):
        M.model_tensors(M.get("PVDF"), "axisymmetric")


def test_unknown_material_names_the_known_ones():
    with pytest.raises(KeyError, match="PSI-5H4E"):
        M.get("unobtainium")


def test_user_material_from_record_is_checked():
    steel = constitution.from_record("steel", {"kind": "solid", "E": 2e11, "nu": 0.3, "rho": 7800})
    assert steel.E == pytest.approx(2e11) and steel.nu == pytest.approx(0.3)
    bad = {"kind": "piezo", "c": (-np.eye(6)).tolist(), "e": np.zeros((3, 6)).tolist(),
           "eps_S": np.eye(3).tolist(), "rho": 1000}
    with pytest.raises(ValueError, match="positive definite"):
        constitution.from_record("bad", bad)


USER_SILICONE = '''[model]
type = "plane_strain"
[mesh]
size = "1 mm"
piezo_size = "0.25 mm"
[array]
silicone = "soft-gel"

[materials.soft-gel]
kind = "solid"
E = 60000.0
nu = 0.49
rho = 1050.0
'''


def test_user_material_as_silicone(tmp_path, capsys):
    path = tmp_path / "user.toml"
    path.write_text(USER_SILICONE)
    assert main(["solve", str(path), "--json"]) == 0
    out, err = capsys.readouterr()
    assert err == ""
    user = json.loads(out)

    # the same scene with the library silicone: the user material must change the answer
    ref_path = tmp_path / "ref.toml"
    ref_path.write_text(USER_SILICONE.split('silicone = ')[0] + 'silicone = "Ecoflex-00-30"\n')
    assert main(["solve", str(ref_path), "--json"]) == 0
    ref = json.loads(capsys.readouterr().out)

    v_user = user["electrodes"]["taxel_0_0"]["voltage_V"]
    v_ref = ref["electrodes"]["taxel_0_0"]["voltage_V"]
    assert v_user < 0 and v_ref < 0             # PZT pressed: negative open-circuit voltage
    assert abs(v_user - v_ref) > 1e-3 * abs(v_ref)
    assert user["applied_force_N"] == pytest.approx(1.0)
    # a silicone given as E and nu has its strain reported too (it decides linear vs Yeoh)
    assert user["max_strain"] > 0.01
    assert user["max_strain"] == pytest.approx(ref["max_strain"], rel=0.8)


def test_user_material_as_silicone_plain_output(tmp_path, capsys):
    path = tmp_path / "user.toml"
    path.write_text(USER_SILICONE)
    assert main(["solve", str(path)]) == 0
    out, err = capsys.readouterr()
    assert err == ""
    assert "taxel_0_0" in out and "applied force" in out


SILICONE_IN_UNITS = {"kind": '"solid"', "C10": '"27.5 kPa"', "C20": '"0.4 kPa"', "C30": '"0 Pa"',
                     "K": '"55 MPa"', "rho": '"1070 kg/m^3"'}
SILICONE_IN_SI = {"kind": '"solid"', "C10": "27500.0", "C20": "400.0", "C30": "0.0", "K": "55e6", "rho": "1070.0"}


@pytest.mark.parametrize("silicone", ["linear", "yeoh"])
def test_a_user_silicone_in_unit_strings_solves_as_in_si_numbers(tmp_path, capsys, silicone):
    """[materials.NAME] takes unit strings as every other table of a scene does: the scene
    converts them (taxel.scene.material_in_si), so the same silicone in SI numbers gives the
    same solve, to the last digit; it differs from the library's Ecoflex."""
    fast = '[model]\ntype = "plane_strain"\n[mesh]\nsize = "1 mm"\npiezo_size = "0.25 mm"\n'
    answers = []
    for name, table in (("units", SILICONE_IN_UNITS), ("si", SILICONE_IN_SI)):
        path = tmp_path / f"{name}.toml"
        force = '[load]\nforce = "0.1 N"\n' if silicone == "yeoh" else ""
        path.write_text(fast.replace('type = "plane_strain"', f'type = "plane_strain"\nsilicone = "{silicone}"')
                        + '\n[array]\nsilicone = "my-silicone"\n' + force + "\n[materials.my-silicone]\n"
                        + "".join(f"{k} = {v}\n" for k, v in table.items()))
        assert main(["solve", str(path), "--json"]) == 0
        out, err = capsys.readouterr()
        assert err == ""
        answers.append(json.loads(out)["electrodes"]["taxel_0_0"]["voltage_V"])
    assert answers[0] == answers[1] and answers[0] < 0
