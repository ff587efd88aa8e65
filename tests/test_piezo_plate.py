"""Piezo plates in uniform states against closed forms, to round-off, in every model.

The reference is computed independently of the solver's reductions: the 3D
strain-charge law (S = s T + d^T E, D = d T + eps^T E) is solved with the
conditions that define each case and model (which stresses vanish, which
strains are zero, open or short circuit). For the 3D free plate this is the
textbook V = g33 sigma t and Q = d33 F (docs/materials.md); plane strain, plane
stress and axisymmetric follow from the same conditions.

Uniform fields lie in the finite-element space, so the solver must reproduce
them to round-off (rtol 1e-9) with any mesh and any element order.
"""

import numpy as np
import pytest

from taxel.fem import constitution as M
from taxel.analyses import solve_static as solve
from taxel.scene import parse

P = 10e3          # Pa, downward pressure
T = 0.5e-3        # m, plate thickness
W = 6e-3          # m, width (and depth) of the plate; radius 3 mm when a disk

# Which strain/stress components each model fixes (3D Voigt indices 0..5, x-z plane: y = index 1).
MODEL_CONDITIONS = {
    "3d":           {"T_zero": [1, 3, 5], "S_zero": []},
    "axisymmetric": {"T_zero": [1, 3, 5], "S_zero": []},
    "plane_stress": {"T_zero": [1, 3, 5], "S_zero": []},
    "plane_strain": {"T_zero": [], "S_zero": [1, 3, 5]},
}


def reference_state(material, model, *, pressure=0.0, voltage=None, clamped=False):
    """Solve the 3D strain-charge law for a uniform plate state.

    Unknowns (18): S(6), T(6), E(3), D(3). Equations: the 9 constitutive ones plus
    9 conditions: T_zz = -pressure, T_xz = 0, E_x = E_y = 0, T_xx = 0 (free) or
    S_xx = 0 (laterally clamped), the model's out-of-plane conditions, and
    D_z = 0 (open) or E_z = -voltage / t (electrodes at a voltage; 0 = short).
    """
    s, d, epsT = material.strain_charge()
    rows, rhs = [], []
    I6, I3 = np.eye(6), np.eye(3)

    def eq(S=None, Tv=None, E=None, D=None, value=0.0):
        rows.append(np.concatenate([S if S is not None else np.zeros(6), Tv if Tv is not None else np.zeros(6),
                                    E if E is not None else np.zeros(3), D if D is not None else np.zeros(3)]))
        rhs.append(value)

    for i in range(6):   # S - s T - d^T E = 0
        eq(S=I6[i], Tv=-s[i], E=-d[:, i])
    for i in range(3):   # D - d T - eps E = 0
        eq(Tv=-d[i], E=-epsT[i], D=I3[i])
    eq(Tv=I6[2], value=-pressure)
    eq(Tv=I6[4])
    eq(E=I3[0])
    eq(E=I3[1])
    eq(S=I6[0]) if clamped else eq(Tv=I6[0])
    cond = MODEL_CONDITIONS[model]
    for i in cond["T_zero"]:
        eq(Tv=I6[i])
    for i in cond["S_zero"]:
        if clamped and i == 1 and model != "plane_strain":
            continue
        eq(S=I6[i])
    if clamped and model in ("3d", "axisymmetric"):
        rows.pop(-3), rhs.pop(-3)        # T_yy free again: S_yy = 0 instead (clamped in both directions)
        eq(S=I6[1])
    if voltage is None:
        eq(D=I3[2])
    else:
        eq(E=I3[2], value=-voltage / T)
    x = np.linalg.solve(np.array(rows), np.array(rhs))
    return {"S": x[:6], "T": x[6:12], "E": x[12:15], "D": x[15:]}


def plate_scene(model, material="PSI-5H4E", *, order=2, clamped=False, poling="up", pressure=P,
                electrodes=None):
    disk = model == "axisymmetric"
    plate = {"shape": "disk", "radius": f"{W / 2} m"} if disk else \
            {"shape": "rectangle", "width": f"{W} m", "length": f"{W} m"}
    plate["layers"] = [{"material": material, "thickness": f"{T} m", "poling": poling}]
    return parse({
        "model": {"type": model, "depth": f"{W} m"} if model.startswith("plane") else {"type": model},
        "mesh": {"size": "2 mm", "order": order},
        "plate": plate,
        "load": {"kind": "pressure", "pressure": f"{pressure} Pa"},
        "supports": {"bottom": "rollers", "edges": "rollers" if clamped else "free"},
        "electrodes": electrodes or {},
    })


def area(model):
    return np.pi * (W / 2) ** 2 if model == "axisymmetric" else W * W


MODELS = ["plane_strain", "plane_stress", "axisymmetric", "3d"]


@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("model", MODELS)
def test_free_plate_open_circuit_voltage_and_short_circuit_charge(model, order):
    mat = M.get("PSI-5H4E")
    sol = solve(plate_scene(model, order=order))
    ref_open = reference_state(mat, model, pressure=P)
    ref_short = reference_state(mat, model, pressure=P, voltage=0.0)
    top = sol.electrodes["top"]
    assert top.voltage == pytest.approx(-ref_open["E"][2] * T, rel=1e-9)
    assert top.short_circuit_charge == pytest.approx(-ref_short["D"][2] * area(model), rel=1e-9)
    assert sol.reaction[-1] == pytest.approx(P * area(model), rel=1e-9)
    if model in ("3d", "plane_stress", "axisymmetric"):      # the textbook forms
        assert top.voltage == pytest.approx(-mat.g33 * P * T, rel=1e-9)
        assert top.short_circuit_charge == pytest.approx(mat.d33 * P * area(model), rel=1e-9)


@pytest.mark.parametrize("model", ["plane_strain", "plane_stress", "3d"])
def test_pvdf_free_plate_gives_positive_voltage_under_compression(model):
    mat = M.get("PVDF")
    sol = solve(plate_scene(model, "PVDF"))
    ref = reference_state(mat, model, pressure=P)
    assert sol.electrodes["top"].voltage == pytest.approx(-ref["E"][2] * T, rel=1e-9)
    assert sol.electrodes["top"].voltage > 0


@pytest.mark.parametrize("model", MODELS)
def test_poling_down_flips_the_voltage(model):
    up = solve(plate_scene(model)).electrodes["top"].voltage
    down = solve(plate_scene(model, poling="down")).electrodes["top"].voltage
    assert down == pytest.approx(-up, rel=1e-9)


@pytest.mark.parametrize("model", ["plane_strain", "plane_stress", "3d"])
def test_laterally_clamped_plate(model):
    mat = M.get("PZT-5H")
    sol = solve(plate_scene(model, "PZT-5H", clamped=True))
    ref = reference_state(mat, model, pressure=P, clamped=True)
    assert sol.electrodes["top"].voltage == pytest.approx(-ref["E"][2] * T, rel=1e-9)
    if model == "3d":     # docs/materials.md: V = h33 sigma t / c33^D, 1D strain
        c33D = mat.c[2, 2] + mat.e[2, 2] ** 2 / mat.eps[2, 2]
        h33 = mat.e[2, 2] / mat.eps[2, 2]
        assert sol.electrodes["top"].voltage == pytest.approx(-h33 * P * T / c33D, rel=1e-9)


@pytest.mark.parametrize("model", MODELS)
def test_converse_effect_and_free_capacitance(model):
    mat = M.get("PSI-5H4E")
    V = 100.0
    sol = solve(plate_scene(model, pressure=0.0, electrodes={"top": f"{V} V"}))
    ref = reference_state(mat, model, voltage=V)
    u = sol.fields.u
    p = sol.mesh.mesh.p
    top = p[-1] > T * (1 - 1e-9)
    # thickness strain S3 (= d33 E3 in 3D), uniform: top displacement = S3 t
    np.testing.assert_allclose(u[top, -1], ref["S"][2] * T, rtol=1e-8)
    # lateral strain S1 (= d31 E3 in 3D), uniform in every element (the rollers' pins
    # leave a rigid motion that carries no strain)
    np.testing.assert_allclose(sol.fields.strain[:, 0], ref["S"][0], rtol=1e-8)
    # free capacitance: D3 A / V of the state with T = 0 (charge on the top electrode -D3 A)
    cap = -reference_state(mat, model, voltage=1.0)["D"][2] * area(model)
    assert sol.electrodes["top"].capacitance == pytest.approx(cap, rel=1e-9)
    assert sol.electrodes["top"].charge == pytest.approx(cap * V, rel=1e-8)
    if model == "3d":
        assert sol.electrodes["top"].capacitance == pytest.approx(mat.strain_charge()[2][2, 2] * W * W / T,
                                                                  rel=1e-9)


def test_bimorph_series_and_parallel():
    """Two PZT-5H layers, opposite poling, under pressure, middle electrode grounded:
    each layer gives the free-plate voltage and charge of its own poling."""
    mat = M.get("PZT-5H")
    scene = parse({
        "model": {"type": "3d"}, "mesh": {"size": "2 mm"},
        "plate": {"shape": "rectangle", "width": f"{W} m", "length": f"{W} m", "layers": [
            {"material": "PZT-5H", "thickness": f"{T} m", "poling": "up"},
            {"material": "PZT-5H", "thickness": f"{T} m", "poling": "down"}]},
        "load": {"kind": "pressure", "pressure": f"{P} Pa"},
        "supports": {"bottom": "rollers"},
        "electrodes": {"bottom": "open", "interface1": "ground"},
    })
    sol = solve(scene)
    v = mat.g33 * P * T
    assert sol.electrodes["top"].voltage == pytest.approx(+v, rel=1e-9)       # upper layer poled down
    assert sol.electrodes["bottom"].voltage == pytest.approx(+v, rel=1e-9)    # lower layer: 0 - (-v)
    # each outer electrode sits on the negative face of its layer: Q = -d33 F on both,
    # and the grounded middle electrode carries +2 d33 F
    F = P * W * W
    assert sol.electrodes["top"].short_circuit_charge == pytest.approx(-mat.d33 * F, rel=1e-9)
    assert sol.electrodes["bottom"].short_circuit_charge == pytest.approx(-mat.d33 * F, rel=1e-9)
    assert sol.electrodes["interface1"].short_circuit_charge == pytest.approx(2 * mat.d33 * F, rel=1e-9)
