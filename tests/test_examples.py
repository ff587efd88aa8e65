"""Every built-in example scene loads and solves with physically sensible results,
and the `taxel` CLI writes what it promises (JSON record, .msh, .vtu).

Examples that take more than 8 s to solve (measured on the development machine,
MKL_NUM_THREADS=OMP_NUM_THREADS=1) are marked slow:

    thesis-pvdf-3x3-2d   0.8 s        thesis-pzt-3x3-2d    0.3 s
    thesis-pvdf-3x3-3d  22   s slow   thesis-pzt-3x3-3d   25   s slow
    thesis-pvdf-single-2d 0.3 s       thesis-pzt-single-2d 0.5 s
    thesis-pvdf-single-3d 3.6 s       thesis-pzt-single-3d 3.5 s

The rig's probe presses (a sticking 4 mm flat punch, Yeoh silicone, to 1 N) are
nonlinear solves: thesis-pzt-probe-2d and -axisymmetric take seconds,
thesis-pzt-probe-3d about 6 s on a quiet machine (benchmarks/press_3d.py), marked slow
for its wall time on a busy one.
"""

from __future__ import annotations

import json
import time
import warnings
from functools import cache

import meshio
import pytest

from taxel.analyses import solve_static as solve
from taxel.cli import main
from taxel.scene import examples, load

SLOW = {"thesis-pvdf-3x3-3d", "thesis-pzt-3x3-3d", "thesis-pzt-probe-3d"}
SLOW_SECONDS = 8.0
# sign of the pressed taxel's open-circuit voltage under a downward load, poling up
VOLTAGE_SIGN = {"PSI-5H4E": -1, "PZT-5H": -1, "PVDF": +1}

EXAMPLES = [pytest.param(name, id=name, marks=[pytest.mark.slow] if name in SLOW else [])
            for name in examples()]


@cache
def solved(name):
    t0 = time.perf_counter()
    scene = load(name)
    sol = solve(scene)
    return scene, sol, time.perf_counter() - t0


def pressed(scene):
    r, c = scene.load.taxel
    return f"taxel_{r}_{c}"


def test_examples_exist():
    names = examples()
    assert len(names) >= 8
    assert set(SLOW) <= set(names), "a slow-marked example no longer exists"
    assert any("pzt" in n for n in names) and any("pvdf" in n for n in names)


@pytest.mark.parametrize("name", EXAMPLES)
def test_example_solves(name):
    scene, sol, seconds = solved(name)
    assert scene.name == name
    if name not in SLOW and seconds > SLOW_SECONDS:
        warnings.warn(f"{name} took {seconds:.1f} s (> {SLOW_SECONDS} s): "
                      "add it to SLOW in tests/test_examples.py")
    assert sol.unknowns > 0
    assert sol.applied_force > 0


@pytest.mark.parametrize("name", EXAMPLES)
def test_pressed_taxel_has_largest_voltage(name):
    scene, sol, _ = solved(name)
    taxels = {k: e.voltage for k, e in sol.electrodes.items() if k.startswith("taxel_")}
    key = pressed(scene)
    assert key in taxels, f"no electrode {key}; have {sorted(sol.electrodes)}"
    others = [abs(v) for k, v in taxels.items() if k != key]
    assert all(abs(taxels[key]) > v for v in others), taxels


@pytest.mark.parametrize("name", EXAMPLES)
def test_vertical_reaction_balances_applied_force(name):
    _, sol, _ = solved(name)
    # a press balances to its Newton tolerance (the contact traction against the reaction: 1e-6)
    tol = 1e-8 if sol.contact is None else 1e-6
    assert abs(sol.reaction[-1] - sol.applied_force) <= tol * abs(sol.applied_force), \
        (sol.reaction, sol.applied_force)


@pytest.mark.parametrize("name", EXAMPLES)
def test_backward_error_is_tiny(name):
    scene, sol, _ = solved(name)
    if sol.contact is not None:         # a press: the requested force, no penetration beyond tolerance
        pt = sol.contact.points[-1]
        assert pt.force == pytest.approx(scene.load.force, rel=1e-3)
        assert pt.penetration <= 1e-3 * pt.travel
        return
    assert sol.residual < 1e-10         # relative residual of the scaled system (measured ~1e-12)


@pytest.mark.parametrize("name", EXAMPLES)
def test_pressed_voltage_sign(name):
    scene, sol, _ = solved(name)
    piezo = scene.array.piezo
    assert piezo in VOLTAGE_SIGN, f"no expected sign for piezo {piezo!r}"
    assert scene.array.poling == "up"
    v = sol.electrodes[pressed(scene)].voltage
    assert v * VOLTAGE_SIGN[piezo] > 0, f"{piezo}: pressed-taxel voltage {v}"


# --------------------------------------------------------------------------------------
# CLI
# --------------------------------------------------------------------------------------

def test_cli_solve_json(capsys):
    assert main(["solve", "thesis-pzt-single-2d", "--json"]) == 0
    out, err = capsys.readouterr()
    lines = out.splitlines()
    assert len(lines) == 1, out
    rec = json.loads(lines[0])
    assert {"electrodes", "applied_force_N"} <= rec.keys()
    assert rec["applied_force_N"] == pytest.approx(1.0)
    assert {"taxel_0_0", "ground"} <= rec["electrodes"].keys()
    assert rec["electrodes"]["taxel_0_0"]["voltage_V"] < 0


def test_cli_mesh_msh(tmp_path, capsys):
    path = tmp_path / "m.msh"
    assert main(["mesh", "thesis-pzt-single-2d", "-o", str(path)]) == 0
    assert path.is_file()
    m = meshio.read(path)
    names = set(m.field_data)
    assert {"silicone", "taxel_0_0", "ground", "load"} <= names, names
    assert len(m.points) > 0
    assert str(path) in capsys.readouterr().out


def test_cli_solve_vtu(tmp_path, capsys):
    path = tmp_path / "f.vtu"
    assert main(["solve", "thesis-pzt-single-2d", "--vtu", str(path)]) == 0
    assert path.is_file()
    m = meshio.read(path)
    assert "phi" in m.point_data
    assert len(m.point_data["phi"]) == len(m.points)
    assert f"fields written to {path}" in capsys.readouterr().out
