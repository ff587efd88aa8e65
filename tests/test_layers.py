"""Reports only read folders and draw: no module of reports/ imports a solver,
a solve function of the analyses, or an optimization flow (a figure helper may
import a type or a constant)."""

from __future__ import annotations

import ast
import importlib
import inspect
from pathlib import Path

REPORTS = Path(__file__).resolve().parents[1] / "reports"

# modules whose functions run a model (a FEM solve, a sweep, a transient, an optimization)
SOLVER_MODULES = {"taxel.fem.dynamics", "taxel.fem.dynamics", "taxel.fem.static", "taxel.fem.contact",
                  "taxel.fem.hyperelastic", "taxel.fem.dynamics", "taxel.analyses", "taxel.analyses.solves.analysis", "taxel.analyses.model.problem",
                  "taxel.analyses.accuracy.model_choice", "taxel.analyses.solves.dynamic",
                  "taxel.optimize.spec", "taxel.optimize.front", "taxel.optimize.coverage", "taxel.optimize.answer_press",
                  "taxel.optimize.run", "taxel.optimize.driver", "taxel.studies.execute"}
# functions of those modules that run no model: formulas and closed forms
NOT_A_SOLVE = {"taxel.analyses.results.static.linear_error": "a formula of the largest strain",
               "taxel.analyses.model.problem.scene_materials": "the scene's materials, looked up and checked",
               "taxel.analyses.solves.analysis.output_folder": "a folder made whole or not at all",
               "taxel.analyses.solves.dynamic.lumped_model": "the closed-form 3-DoF model, no FEM",
               "taxel.optimize.driver.pareto_front": "the nondominated subset of given points",
               "taxel.optimize.driver.violation": "a constraint's violation at given metrics",
               "taxel.optimize.spec.load_optimization": "reads a problem's spec file (its bounds, its reference)",
               "taxel.optimize.coverage.of": "reads a design's influence metrics from OUT/coverage.json",
               "taxel.optimize.answer_press.read": "reads the answer's 3D presses from a probe-front record"}
# known, owned elsewhere: the model-comparison section of a scene page still solves
KNOWN = {("scene_sections.py", "taxel.analyses.solves.analysis.solve_static")}


def imports(path: Path) -> list[str]:
    """Every module or module.name a file imports (nested imports included)."""
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            out += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module:
            out += [f"{node.module}.{a.name}" for a in node.names]
    return out


def runs_a_model(dotted: str) -> str | None:
    """The solver module.function behind an import, or None for a module, type or constant
    that runs nothing."""
    if dotted in SOLVER_MODULES:
        return dotted
    module, _, name = dotted.rpartition(".")
    if not module.startswith("taxel"):
        return None
    try:
        obj = getattr(importlib.import_module(module), name)
    except (ImportError, AttributeError):
        return None                                   # a submodule: checked as a module above
    if inspect.ismodule(obj):
        return obj.__name__ if obj.__name__ in SOLVER_MODULES else None
    if not inspect.isfunction(obj) or obj.__module__ not in SOLVER_MODULES:
        return None                                   # a type or a constant
    where = f"{obj.__module__}.{obj.__name__}"
    return None if where in NOT_A_SOLVE else where


def test_the_check_sees_a_solver_import():
    assert runs_a_model("taxel.fem.dynamics") == "taxel.fem.dynamics"
    assert runs_a_model("taxel.fem.dynamics") == "taxel.fem.dynamics"
    assert runs_a_model("taxel.analyses.solve_static") == "taxel.analyses.solves.analysis.solve_static"
    assert runs_a_model("taxel.analyses.frequency") == "taxel.analyses.solves.dynamic.frequency"
    assert runs_a_model("taxel.optimize.front.front") == "taxel.optimize.front.front"
    assert runs_a_model("taxel.analyses.results.FrequencyResult") is None
    assert runs_a_model("taxel.analyses.LINEAR_ERROR_PER_STRAIN") is None


def test_no_report_module_imports_a_solver():
    files = sorted(REPORTS.glob("*.py"))
    assert len(files) >= 10
    bad = [(f.name, hit) for f in files for dotted in imports(f) if (hit := runs_a_model(dotted))
           and (f.name, hit) not in KNOWN]
    assert not bad, bad


def test_reports_build_and_validation_do_not_import_each_other():
    assert not [d for d in imports(REPORTS / "validation.py") if d.startswith("taxel.reports.build")]
