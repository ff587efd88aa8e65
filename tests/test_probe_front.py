"""The rig's probe press as the optimizer's model (optimize.probe, optimize.probe_front):
the press objective against `taxel solve` of the same scene and its tangent against
independent presses; the objectives over a force range against presses at each force;
the multi-fidelity correction against pressing every candidate, in 2D and in 3D; an
optimization under the press that must find a known optimum. Coarse meshes."""

import json

import numpy as np
import pytest

from taxel.cli import main
from taxel.optimize.multifidelity import ScoredDesign, correct, nondominated
from taxel.optimize.probe import ProbePress, press_metrics, press_scene
from taxel.optimize.probe_front import _solver, press_3d, spread
from taxel.optimize.spec import load_optimization, optimize
from taxel.schema import to_data
from taxel.scene import load

COARSE = {"mesh.size": 1e-3, "mesh.piezo_size": 0.25e-3}

SCENE = """
description = "thesis pzt 3x3 row, pressed by the rig's 4 mm punch on Yeoh silicone"
[model]
type = "plane_strain"
silicone = "yeoh"
[mesh]
size = "1 mm"
piezo_size = "0.25 mm"
order = 2
[array]
rows = 3
cols = 3
taxel_width = "4 mm"
piezo = "PSI-5H4E"
piezo_thickness = "0.127 mm"
gap = "3 mm"
margin = "3 mm"
silicone = "Ecoflex-00-30"
silicone_above = "1 mm"
silicone_below = "1 mm"
[load]
kind = "probe"
contact = true
shape = "flat"
radius = "2 mm"
edge_radius = "0.2 mm"
friction = "sticking"
taxel = [1, 1]
force = "1 N"
[supports]
bottom = "bonded"
"""


@pytest.mark.slow
def test_press_objective_equals_taxel_solve_and_its_tangent_the_slope(tmp_path, capsys):
    """Secant sensitivity, crosstalk and largest strain equal `taxel solve --json` of the
    same scene (the same press to 1 N); the tangent matches within 1.5 % the central
    difference along one press through 0.9, 1 and 1.1 N (measured 0.85 % apart: under
    sticking contact the states depend on the load steps), and within 2 % the chord of
    two independent presses to 0.9 and 1.1 N (measured 1.1 %)."""
    path = tmp_path / "press.toml"
    path.write_text(SCENE)
    assert main(["solve", str(path), "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    data = to_data(load(path))
    m = press_metrics(data)
    assert m["sensitivity"] == pytest.approx(abs(rec["outputs"]["sensitivity"]), rel=1e-12)
    assert m["crosstalk"] == pytest.approx(rec["outputs"]["crosstalk"], rel=1e-12)
    assert m["max_strain"] == pytest.approx(rec["max_strain"], rel=1e-12)
    from taxel.analyses import problem
    from taxel.fem.assembly import assemble
    from taxel.fem.contact import Press
    prob = problem(load(path))
    pr = Press(assemble(prob), prob.indenter)
    v = {F: (p.force, p.voltages["taxel_1_1"]) for F, p in ((F, pr.force(F)) for F in (0.9, 1.0, 1.1))}
    slope = abs((v[1.1][1] - v[0.9][1]) / (v[1.1][0] - v[0.9][0]))      # central, along one press
    assert m["tangent_sensitivity"] == pytest.approx(slope, rel=1.5e-2)   # the load steps: ~1 % (sticking)
    # independent presses from zero to 0.9 and 1.1 N end on a curve 1.1 % less steep (the
    # sticking set depends on the load steps): the small-signal slope is the continued press's
    ends = []
    for F in (0.9, 1.1):
        d = json.loads(json.dumps(data))
        d["load"]["force"] = f"{F} N"
        ends.append(press_metrics(d))
    chord = abs((ends[1]["voltage"] - ends[0]["voltage"]) / (ends[1]["force"] - ends[0]["force"]))
    assert m["tangent_sensitivity"] == pytest.approx(chord, rel=2e-2)
    # Yeoh stiffens and the contact grows: the slope is below the secant
    assert m["tangent_sensitivity"] < m["sensitivity"]


def test_press_scene_puts_the_probe_on_the_pressed_taxel():
    data = to_data(load("thesis-pzt-3x3-2d"))
    d = press_scene(data, ProbePress(radius="1.5 mm", force="0.5 N"))
    assert d["load"] | {} == {**d["load"], "kind": "probe", "contact": True, "radius": "1.5 mm",
                             "force": "0.5 N", "shape": "flat", "edge_radius": "0.2 mm", "friction": "sticking"}
    assert d["model"]["silicone"] == "yeoh" and list(d["load"]["taxel"]) == [1, 1]


def _problem(tmp_path, objective="maximize = \"sensitivity\"", extra=""):
    text = f"""
base = "thesis-pzt-3x3-2d"
[variables]
silicone_above = {{path = "array.silicone_above", min = "0.4 mm", max = "1.8 mm", start = "0.7 mm"}}
gap = {{path = "array.gap", min = "1 mm", max = "5 mm", start = "3 mm"}}
[objective]
{objective}
[requirements]
total_thickness = "<= 2.127 mm"
{extra}
[algorithm]
global = "none"
local = "COBYLA"
max_evaluations = 10
xtol = 0.02
[press]
force = "1 N"
"""
    p = tmp_path / "opt.toml"
    p.write_text(text)
    prob = load_optimization(p, tmp_path / "out")
    prob.base = json.loads(json.dumps(prob.base))
    prob.base["mesh"].update(size="1 mm", piezo_size="0.25 mm")
    return prob


@pytest.mark.slow
def test_multifidelity_front_equals_pressing_every_candidate(tmp_path):
    """Six designs: the correction loop (linear 2D -> 2D press) presses some of them and
    predicts the rest; its front is the front of pressing all six, and each pressed value
    is the brute-force one."""
    prob = _problem(tmp_path)
    lin = prob.linear()
    xs = [np.array([a, g]) for a, g in ((0.5, 1.5), (0.8, 4.5), (1.0, 3.0), (0.9, 2.0), (0.6, 3.5),
                                          (1.0, 5.0))]             # mm
    pool = []
    for x in xs:
        m = lin.evaluate(x)
        pool.append(ScoredDesign(list(x), (m["sensitivity"], m["crosstalk"])))
    solve = _solver(prob, None, 1)
    front_lin = nondominated(pool, lambda d: d.cheap)
    verified, rounds = correct(lin, pool, front_lin, 2, solve, tolerance=0.01, max_rounds=6)
    brute = solve([d.x for d in pool])                       # from the store where the loop pressed
    mf_front = nondominated([d for d in pool if d.fine or d.predicted], lambda d: d.fine or d.predicted)
    bf_front = nondominated([ScoredDesign(d.x, b) for d, b in zip(pool, brute)], lambda d: d.cheap)
    assert {tuple(d.x) for d in mf_front} == {tuple(d.x) for d in bf_front}
    for d in verified:
        assert d.fine == brute[[tuple(p.x) for p in pool].index(tuple(d.x))]
    assert len(verified) < len(pool) or len(rounds) > 1


@pytest.mark.slow
def test_optimizer_under_the_press_finds_the_known_optimum(tmp_path):
    """Minimize crosstalk under the probe over the gap alone (silicone fixed): crosstalk
    falls with the distance to the neighbour, so the optimum is the largest gap, 5 mm;
    BOBYQA reaches it from 3 mm within 8 presses."""
    text = """
base = "thesis-pzt-3x3-2d"
[variables]
gap = {path = "array.gap", min = "1 mm", max = "5 mm", start = "3 mm"}
[objective]
minimize = "crosstalk"
[algorithm]
global = "none"
local = "BOBYQA"
max_evaluations = 8
xtol = 0.01
[press]
force = "1 N"
"""
    p = tmp_path / "gap.toml"
    p.write_text(text)
    prob = load_optimization(p, tmp_path / "out")
    prob.base["mesh"].update(size="1 mm", piezo_size="0.25 mm")
    r = optimize(prob)
    assert r.x[0] == pytest.approx(5.0, abs=0.05)                  # mm, the variable's unit
    assert r.metrics["tangent_sensitivity"] is not None


@pytest.mark.parametrize("line, words", [('radius = "2 kg"', "press.radius"), ('silicone = "rubber"', "press.silicone"),
                                         ('force = "-1 N"', "press.force must be positive"),
                                         ('force_range = ["2 N", "1 N"]', "press.force_range must be two forces"),
                                         ('force_range = ["1 kg", "2 N"]', "press.force_range")])
def test_a_bad_press_table_is_one_line_and_exit_2(tmp_path, capsys, line, words):
    p = tmp_path / "bad.toml"
    p.write_text('base = "thesis-pzt-3x3-2d"\n[variables]\ngap = {path = "array.gap", min = "1 mm", max = "5 mm"}\n'
                 f'[objective]\nminimize = "crosstalk"\n[press]\n{line}\n')
    assert main(["optimize", str(p), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and "\n" not in err and "Traceback" not in err


COARSE_3D = {"model.type": "3d", "mesh.size": "5 mm", "mesh.piezo_size": "2 mm", "mesh.piezo_layers": 1}


@pytest.mark.slow
def test_3d_level_equals_pressing_every_candidate_in_3d(tmp_path):
    """Level C on a small case: three designs scored by their 2D press (level B), two on
    the level-B front and one dominated (thick silicone, small gap). The 3D level
    presses the front in 3D (a coarse 5 mm mesh, Yeoh, 1 N), corrects the rest and
    presses whatever the correction puts on the front; its front is the front of
    pressing all three in 3D, each pressed value is the brute-force one, and it pressed
    fewer than all. Each 3D press carries the error estimator's record."""
    prob = _problem(tmp_path)
    xs = [[0.5, 1.5], [0.8, 4.5], [1.0, 1.2]]                        # mm: silicone above, gap
    b = _solver(prob, None, 1)(xs)
    pool = [ScoredDesign(x, m) for x, m in zip(xs, b)]
    assert all(m is not None for m in b)
    front_b = nondominated(pool, lambda d: d.cheap)
    assert len(front_b) < len(pool)                                  # the case has a dominated design
    pressed, rounds, recs = press_3d(prob, pool, front_b, len(pool), COARSE_3D, workers=1, tolerance=0.0,
                                     max_rounds=3)
    brute = _solver(prob, COARSE_3D, 1)(xs)                          # every candidate (pressed ones from the store)
    assert all(m is not None for m in brute)
    mf_front = nondominated([d for d in pool if d.fine or d.predicted], lambda d: d.fine or d.predicted)
    bf_front = nondominated([ScoredDesign(x, m) for x, m in zip(xs, brute)], lambda d: d.cheap)
    assert {tuple(d.x) for d in mf_front} == {tuple(d.x) for d in bf_front}
    assert all(d.fine is not None for d in mf_front)                # the answer's front is pressed, not predicted
    for d in pressed:
        assert d.fine == brute[xs.index(d.x)]
        e = recs[tuple(np.round(d.x, 9))]["error"]["sensitivity"]
        assert e["total"] > 0 and e["material"] == 0.0               # a coarse mesh errs; Yeoh is the law
    assert len(pressed) < len(pool)


def test_spread_takes_the_ends_then_the_middle():
    items = [5, 1, 4, 2, 3]
    assert spread(items, 1, float) == [3]
    assert spread(items, 2, float) == [1, 5]
    assert spread(items, 3, float) == [1, 3, 5]
    assert spread(items, 9, float) == [1, 2, 3, 4, 5]


@pytest.mark.slow
def test_press_over_a_force_range_is_the_worst_of_presses_at_each_force():
    """force_range = [0.5 N, 1 N], 3 forces: the range press's secant and crosstalk at
    each force equal a press to that force alone within the load-step dependence of
    sticking contact (measured 1.3e-4 at most; 2e-3 allowed), the objectives are the least sensitivity and the
    largest crosstalk of the range, and its top state is the press to 1 N's."""
    data = to_data(load("thesis-pzt-3x3-2d"))
    data["mesh"].update(size="1 mm", piezo_size="0.25 mm")
    press = ProbePress(force_range=["0.5 N", "1 N"], range_points=3)
    d = press_scene(data, press)
    assert d["load"]["force"] == "1 N"
    m = press_metrics(d, press)
    assert [r["force"] for r in m["range"]] == pytest.approx([0.5, 0.75, 1.0], rel=2e-3)   # force control to 0.1 %
    # each force pressed alone, independently of the range press (the top one with the range's
    # own scene: the same force along other load steps; measured 9e-5)
    singles = [press_metrics(press_scene(data, ProbePress(force=f"{r['force']} N"))) for r in m["range"][:-1]]
    singles.append(press_metrics(d))
    for r, one in zip(m["range"], singles):
        assert r["sensitivity"] == pytest.approx(one["sensitivity"], rel=2e-3)
        assert r["crosstalk"] == pytest.approx(one["crosstalk"], rel=2e-3)
    # the objectives are the worst of the separate presses: least sensitivity, largest crosstalk
    assert m["sensitivity"] == pytest.approx(min(one["sensitivity"] for one in singles), rel=2e-3)
    assert m["crosstalk"] == pytest.approx(max(one["crosstalk"] for one in singles), rel=2e-3)
    # Yeoh stiffens: the secant falls with force, so the worst sensitivity is the top force's
    assert m["range"][0]["sensitivity"] > m["range"][-1]["sensitivity"]
