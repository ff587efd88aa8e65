"""Optimization: the driver on problems with known optima and a known front; a
coarse FEM optimization that converges and reruns from the cache; bad files."""

import json

import numpy as np
import pytest

from taxel.optimize import driver
from taxel.optimize.spec import load_optimization, optimize
from taxel.cli import main
from taxel.studies.store import Store


def test_bound_constrained_rosenbrock():
    ev = lambda x: {"f": (1 - x[0]) ** 2 + 100 * (x[1] - x[0] ** 2) ** 2}      # noqa: E731
    r = driver.minimize(ev, [-1, 2], [(-2, 2), (-1, 3)], "f", local_alg="BOBYQA", max_evals=400, xtol=1e-8)
    np.testing.assert_allclose(r.x, [1, 1], atol=1e-4)
    assert r.success


def test_constrained_problem_and_active_constraint():
    """min x^2 + y^2 subject to x + y >= 1: the optimum (0.5, 0.5) on the constraint."""
    ev = lambda x: {"f": x[0] ** 2 + x[1] ** 2, "s": x[0] + x[1]}             # noqa: E731
    r = driver.minimize(ev, [1, 1], [(-2, 2), (-2, 2)], "f", [("s", ">=", 1.0)], max_evals=200, xtol=1e-8)
    np.testing.assert_allclose(r.x, [0.5, 0.5], atol=1e-4)
    assert r.success and abs(r.constraints["s >= 1"]) < 1e-6



def test_the_constrained_global_pass_keeps_its_evaluation_budget():
    """nlopt's constrained DIRECT (GN_ORIG_DIRECT_L) does not count calls at infeasible
    points against maxeval (637 calls on a budget of 20 where the feasible set is small);
    the driver holds the budget itself: at most max_evals distinct evaluations in all, and
    the best feasible point found is still returned."""
    calls = []

    def ev(x):
        calls.append(x)
        return {"f": float(((x - 0.3) ** 2).sum()), "a": abs(x[0] - 0.9), "b": x[1] + x[2]}
    r = driver.minimize(ev, [0.5, 0.5, 0.5], [(0, 1)] * 3, "f", [("a", "<=", 0.05), ("b", "<=", 0.1)],
                        max_evals=40, xtol=0.02)
    assert len(calls) <= 40 and r.nfev == len(calls)
    assert "DIRECT: evaluation budget used" in r.message

def test_maximize_with_isres_global_pass():
    ev = lambda x: {"g": np.exp(-((x[0] - 0.3) ** 2 + (x[1] + 0.2) ** 2))}   # noqa: E731
    r = driver.minimize(ev, [1.5, 1.5], [(-2, 2), (-2, 2)], "g", maximize=True, global_alg="ISRES",
                        local_alg="SBPLX", max_evals=600, xtol=1e-8)
    np.testing.assert_allclose(r.x, [0.3, -0.2], atol=1e-3)


def test_epsilon_constraint_recovers_a_known_front():
    """Maximize S = 1 - x^2 subject to C = (1 - x)^2 <= eps, x in [0, 1]: the front
    is S(eps) = 1 - (1 - sqrt(eps))^2."""
    ev = lambda x: {"S": 1 - x[0] ** 2, "C": (1 - x[0]) ** 2}                  # noqa: E731
    pts = []
    for eps in (0.05, 0.2, 0.4, 0.6, 0.8):
        r = driver.minimize(ev, [0.9], [(0.0, 1.0)], "S", [("C", "<=", eps)], maximize=True,
                            max_evals=150, xtol=1e-9)
        assert r.metrics["S"] == pytest.approx(1 - (1 - np.sqrt(eps)) ** 2, abs=1e-4)
        pts.append((r.metrics["S"], r.metrics["C"]))
    assert len(driver.pareto_front(pts)) == len(pts)


# a coarse optimization: 15 COBYLA evaluations of the 2D single taxel (tests/test_bad_input.py breaks it)
COARSE_OPT = """base = "thesis-pzt-single-2d"
[variables]
silicone_above = {path = "array.silicone_above", min = "0.2 mm", max = "1.8 mm", start = "1 mm"}
[objective]
maximize = "sensitivity"
[requirements]
total_thickness = "<= 2.127 mm"
max_strain = "<= 5"
[algorithm]
global = "none"
local = "COBYLA"
max_evaluations = 15
xtol = 0.01
"""


def coarse_problem(tmp_path):
    text = COARSE_OPT
    p = tmp_path / "opt.toml"
    p.write_text(text)
    return p


def test_coarse_fem_optimization_converges_and_reruns_from_the_cache(tmp_path):
    """One variable (silicone above, below fixed at 1 mm): the sensitivity rises
    with the top silicone (Fig. 2.5), so the optimum is the thickness limit
    (1 mm on top); COBYLA finds it within 15 evaluations, and a rerun solves
    nothing new."""
    path = coarse_problem(tmp_path)
    out = tmp_path / "out"
    r = optimize(load_optimization(path, out))
    assert r.success and r.nfev <= 15
    assert r.x[0] == pytest.approx(1.0, abs=0.02)
    n_solved = len(Store(out).rows())
    again = optimize(load_optimization(path, out))
    assert len(Store(out).rows()) == n_solved                      # every design from the store
    np.testing.assert_allclose(again.x, r.x)


def test_cli_writes_optimum_history_and_plots(tmp_path, capsys):
    path = coarse_problem(tmp_path)
    assert main(["optimize", str(path), "--out", str(tmp_path / "o")]) == 0
    rec = json.loads((tmp_path / "o" / "optimum.json").read_text())
    assert rec["success"] and rec["x"]["silicone_above"] == pytest.approx(1.0, abs=0.02)
    assert (tmp_path / "o" / "optimum-convergence.png").stat().st_size > 1000
    assert len((tmp_path / "o" / "optimum-history.csv").read_text().splitlines()) == rec["evaluations"] + 1


def test_api_optimize_returns_one_result_type_for_an_optimum(tmp_path):
    """An optimum: the result holds it, writes result.json beside optimum.json and
    the history, reads back equal, and its summary names the optimum."""
    from taxel import api
    from taxel.optimize.result import OptimizationResult
    out = tmp_path / "o"
    r = api.run_optimization(coarse_problem(tmp_path), out, workers=1)
    assert isinstance(r, OptimizationResult) and r.kind == "optimum" and r.runs == []
    assert r.optimum.success and r.optimum.x[0] == pytest.approx(1.0, abs=0.02)
    assert r.reference is None and r.reference_dominated is None
    assert 0 < r.fem_solves <= r.optimum.nfev + sum(x.evaluations for x in r.prices)
    assert r.summary()[0].startswith("optimum: silicone_above = ")
    for name in ("result.json", "optimum.json", "optimum-history.csv", "optimum-convergence.png"):
        assert (out / name).stat().st_size > 0
    back = OptimizationResult.from_folder(out)
    assert back.record() == json.loads(json.dumps(r.record()))


def test_a_binding_requirement_is_priced_by_searching_again_with_its_bound_relaxed(tmp_path):
    """The coarse problem's optimum sits at total thickness <= 2.127 mm (the sensitivity rises
    with the top silicone, Fig. 2.5; below 1 mm and the piezo 0.127 mm fixed). Relaxed by the
    stated 10 %, the bound is 2.3397 mm, so the new optimum is at silicone above
    2.3397 - 1.127 = 1.2127 mm (closed form), more sensitive; max_strain <= 5, far from its
    bound at the optimum, is not tried. The price reaches the summary and result.json."""
    from taxel import api
    from taxel.optimize import relax
    from taxel.optimize.result import OptimizationResult
    r = api.run_optimization(coarse_problem(tmp_path), tmp_path / "o", workers=1)
    assert [x.metric for x in r.prices] == ["total_thickness"]
    p = r.prices[0]
    assert p.relaxed == pytest.approx(2.127e-3 * (1 + relax.STEP))
    assert p.x[0] == pytest.approx(2.127 * (1 + relax.STEP) - 1.127, abs=0.02)
    assert p.metrics["total_thickness"] <= p.relaxed * (1 + 1e-6)
    assert p.metrics["sensitivity"] > r.optimum.metrics["sensitivity"] * 1.01
    line = next(ln for ln in r.summary() if "binds" in ln)
    assert "total thickness ≤ 2.13 mm binds: at ≤ 2.34 mm (+10 %), sensitivity" in line
    assert OptimizationResult.from_folder(tmp_path / "o").prices == r.prices


def test_api_optimize_returns_one_result_type_for_a_front(tmp_path):
    """A two-point front on the 2D 3x3 array (3 evaluations a run): the same type,
    its runs and bounds, the reference design evaluated and placed against it."""
    from taxel import api
    from taxel.optimize.result import FrontRun, OptimizationResult
    text = """
base = "thesis-pzt-3x3-2d"
reference = {gap = "3 mm"}
[variables]
gap = {path = "array.gap", min = "1 mm", max = "5 mm", start = "3 mm"}
[objective]
maximize = "sensitivity"
[pareto]
points = 2
[algorithm]
global = "none"
local = "COBYLA"
max_evaluations = 3
"""
    path = tmp_path / "front.toml"
    path.write_text(text)
    out = tmp_path / "f"
    r = api.run_optimization(path, out, workers=1)
    assert isinstance(r, OptimizationResult) and r.kind == "front" and r.optimum is None
    assert len(r.runs) == 2 and all(isinstance(run, FrontRun) for run in r.runs)
    assert r.runs[0].bound <= r.runs[1].bound
    assert r.reference["x"] == {"gap": pytest.approx(3.0)} and r.reference["sensitivity"] > 0
    assert r.reference_dominated in (True, False) and r.nondominated
    s0, c0 = r.reference["sensitivity"], r.reference["crosstalk"]          # dominated: by any row of the front
    assert r.reference_dominated == any(row["sensitivity_V_per_N"] >= s0 * (1 + 1e-3)
                                        and row["crosstalk"] <= c0 * (1 - 1e-3) for row in r.front_rows)
    assert r.evaluations == sum(run.result.nfev for run in r.runs) and r.fem_solves > 0
    assert r.summary()[-1].startswith(f"front: {len(r.front_rows)} of {len(r.runs)} runs on the front")
    front = json.loads((out / "front.json").read_text())
    assert len(front["front"]) == len(r.front_rows) and front["reference"]["sensitivity"] == r.reference["sensitivity"]
    assert (out / "pareto.png").stat().st_size > 1000
    back = OptimizationResult.from_folder(out)
    assert back.kind == "front" and back.reference_dominated == r.reference_dominated
    assert [run.bound for run in back.runs] == [run.bound for run in r.runs]
