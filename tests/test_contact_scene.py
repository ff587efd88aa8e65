"""A scene pressed by a rigid indenter ([load] kind = "probe", contact = true):
the thesis taxel pressed by a flat punch at a small force. Its bad input is in
test_bad_input.py (rows "scene-contact-*")."""

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from taxel.analyses import problem
from taxel.analyses import solve_static as solve
from taxel.fem.assembly import assemble
from taxel.fem.contact import Options, Press
from taxel.fem.static import solve_linear
from taxel.cli import main
from taxel.scene import load

FAST = '''
[model]
type = "{model}"

[mesh]
size = "1 mm"
piezo_size = "0.25 mm"

[array]

[load]
kind = "{kind}"
radius = "1 mm"
contact = true
{extra}
'''

def pressed(silicone, force, model="plane_strain"):
    return load("thesis-pzt-single-2d").replace(**{
        "model.type": model, "model.silicone": silicone, "load.kind": "probe", "load.contact": True,
        "load.radius": 2e-3, "load.edge_radius": 0.2e-3, "load.force": force})


@pytest.fixture(scope="module")
def taxel_small_press():
    return solve(pressed("linear", 0.1))


def test_force_control_reaches_the_force_and_the_supports_carry_it(taxel_small_press):
    sol = taxel_small_press.solution
    c = sol.contact
    assert sol.applied_force == pytest.approx(0.1, rel=1e-3)
    assert c.points[-1].penetration <= 1e-3 * c.points[-1].travel
    # the bonded bottom carries the punch force (vertical equilibrium)
    assert sol.reaction[-1] == pytest.approx(sol.applied_force, rel=1e-6)


def test_small_press_voltage_is_near_the_uniform_pressure_patch(taxel_small_press):
    """A 4 mm punch on the 4 mm taxel and a uniform 4 mm patch of the same force give
    voltages of the same sign and size (the punch concentrates pressure at its edge)."""
    v_punch = taxel_small_press.voltages()["taxel_0_0"]
    v_patch = solve(load("thesis-pzt-single-2d").replace(**{"load.force": 0.1})).voltages()["taxel_0_0"]
    assert v_punch < 0 and abs(v_punch / v_patch - 1) < 0.25


def test_small_press_equals_the_pressure_solution_with_the_punchs_pressure(taxel_small_press):
    """The small-load limit: the present linear pressure solve (fem.static), loaded by the
    punch's contact traction (its nodal forces on the top; sticking, the default, adds the
    tangential part), gives the press's voltage and
    displacement: the contact solution is that pressure solution, the pressure found by
    contact instead of prescribed."""
    res = taxel_small_press
    sol = res.solution
    sy = assemble(problem(res.scene, sol.mesh))
    pr = Press(sy, sy.problem.indenter)
    b = np.zeros_like(sy.b)
    S = pr.surf.dofs.ravel()                                         # the punch's traction as a load
    b[sy.offsets["u"]] = -np.bincount(S, pr.surf.element_residual(sol.contact.state).ravel(), minlength=len(b[sy.offsets["u"]]))
    lin = solve_linear(replace(sy, b=b))
    assert lin.voltages()["taxel_0_0"] == pytest.approx(res.voltages()["taxel_0_0"], rel=1e-6)
    np.testing.assert_allclose(lin.fields.u, sol.fields.u, atol=1e-6 * np.abs(sol.fields.u).max())


def test_cli_prints_and_records_the_press(tmp_path, capsys):
    """`taxel solve --json` records the press (force, travel, area, max pressure,
    penetration, iterations, load steps, the curve); the text print shows it; --out
    writes contact-curve.csv."""
    import json
    path = tmp_path / "press.toml"
    path.write_text(FAST.format(model="plane_strain", kind="probe", extra='force = "0.05 N"\nedge_radius = "0.2 mm"'))
    assert main(["solve", str(path), "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)["contact"]
    assert rec["force_N"] == pytest.approx(0.05, rel=2e-3)
    assert rec["travel_m"] > 0 and rec["contact_area_m2"] > 0 and rec["max_pressure_Pa"] > 0
    assert 0 <= rec["penetration_m"] <= 1e-3 * rec["travel_m"]
    # one state or more: a trial past the target is not a state (fem.contact.force; this press's first
    # trial goes past 0.05 N, its second ends at it: one state since 2026-11-29)
    assert rec["load_steps"] == len(rec["curve"]["force_N"]) >= 1 and rec["newton_iterations"] > 0
    assert np.all(np.diff(rec["curve"]["travel_m"]) > 0)
    assert len(rec["curve"]["voltages_V"]["taxel_0_0"]) == rec["load_steps"]
    assert main(["solve", str(path), "--out", str(tmp_path / "out")]) == 0
    out = capsys.readouterr().out
    assert "indenter (flat): force" in out and "Newton iterations" in out
    rows = (tmp_path / "out" / "contact-curve.csv").read_text().splitlines()
    assert rows[0].startswith("travel_m,force_N") and len(rows) == rec["load_steps"] + 1


@pytest.mark.slow
def test_cli_keeps_a_stopped_press_at_its_last_converged_state(tmp_path, capsys):
    """`taxel solve --out` of a press that stops (the 2D probe example, frictionless, asked
    for 3 N: Newton inverts silicone elements past 1.62 N) exits 1 with one line naming why,
    and writes the last converged state, saying so: result.json's stop (the force asked for,
    the cause, the message), the summary's first lines, a scene at the force reached; it
    reads back with its stop, and the report's banner says it, with a fix."""
    import json
    import taxel
    from taxel.cli import EXIT_FAILED
    text = (Path(taxel.__file__).parent / "examples" / "thesis-pzt-probe-2d.toml").read_text()
    path = tmp_path / "stops.toml"
    path.write_text(text.replace('friction = "sticking"', 'friction = "frictionless"').replace('force = "1 N"', 'force = "3 N"'))
    out = tmp_path / "out"
    assert main(["solve", str(path), "--out", str(out)]) == EXIT_FAILED == 1
    printed, err = capsys.readouterr()
    assert len(err.strip().splitlines()) == 1 and err.startswith(("taxel: failed: Newton ", "taxel: failed: force control: "))
    rec = json.loads((out / "result.json").read_text())
    F = rec["applied_force_N"]
    assert rec["stop"]["requested"] == 3.0 and rec["stop"]["load"] == "force"
    assert rec["stop"]["cause"] in ("inversion", "stagnation") and rec["stop"]["message"] in err
    assert 1.0 < F < 3.0 and rec["contact"]["force_N"] == F == rec["contact"]["curve"]["force_N"][-1]
    assert f"at load.force {F:.4g} N of 3 N" in err
    assert printed.splitlines()[1].startswith("STOPPED SHORT of load.force = 3 N")
    assert "STOPPED SHORT" in (out / "summary.txt").read_text()
    back = taxel.read(out)
    assert back.stop == taxel.analyses.results.Stop(**rec["stop"]) and back.scene.load.force == pytest.approx(F)
    from taxel.reports.findings import static_banners          # the report's page says so on top, with a fix
    said = [b.text for b in static_banners(back) if b.text.startswith("Stopped short of load.force = 3 N")]
    assert len(said) == 1 and 'friction = "sticking"' in said[0]


@pytest.mark.slow
def test_auto_reaches_yeoh_at_1_newton_through_contact():
    """silicone = "auto" under a sticking 4 mm punch at the thesis's 1 N: the linear
    press's largest strain puts its estimated error above the tolerance, and the Yeoh
    press converges at 1 N (issue 14)."""
    res = solve(pressed("auto", 1.0).replace(**{"load.friction": "sticking"}))
    assert res.model_note.startswith("auto: Yeoh silicone")
    assert res.applied_force == pytest.approx(1.0, rel=2e-3)
    assert res.solution.contact.points[-1].penetration <= 1e-3 * res.solution.contact.points[-1].travel
    assert res.voltages()["taxel_0_0"] < 0


def test_dynamics_about_the_pressed_state_tends_to_the_static_curves_slope():
    """The frequency response linearised about the pressed state (fem.dynamics, the
    indenter holding it and driving it) at a low frequency equals dV/dF of the static
    voltage-force curve, taken from two static presses (central difference). Losses set
    to zero: structural loss factors do not vanish at zero frequency."""
    from taxel.fem.dynamics import model
    from taxel.fem.dynamics import direct
    sc = pressed("linear", 0.3).replace(**{"load.friction": "sticking", "mesh.size": 1e-3, "dynamics.silicone_loss": 0.0,
                                           "dynamics.piezo_loss": 0.0, "dynamics.dielectric_loss": 0.0,
                                           "mesh.piezo_size": 2.5e-4, "model.symmetry": "full"})
    prob = problem(sc)
    d0 = 0.1e-3
    prob = replace(prob, indenter=replace(prob.indenter, force=None, travel=d0))
    V = {}
    for d in (0.995 * d0, 1.005 * d0):
        pr = Press(assemble(prob), prob.indenter, opts=Options(gap_tol=1e-7))
        pt = pr.travel(d)
        V[d] = (pt.voltages["taxel_0_0"], pt.force)
    (v1, f1), (v2, f2) = V.values()
    slope = (v2 - v1) / (f2 - f1)
    dm = model(prob)
    v_oc, _ = direct(dm, 1e-3)
    assert abs(v_oc[0].imag) < 1e-6 * abs(v_oc[0].real)
    assert v_oc[0].real == pytest.approx(slope, rel=5e-3)     # measured 0.2 % (the press's 1e-3 gap tolerance)


def test_solve_page_has_the_contact_curve(tmp_path, taxel_small_press):
    files, summary = taxel_small_press.to_folder(tmp_path), taxel_small_press.summary()
    png = [f for f in files if f.name.endswith("-contact.png")]
    assert len(png) == 1 and png[0].stat().st_size > 10_000
    assert any(line.startswith("indenter (flat)") for line in summary)
