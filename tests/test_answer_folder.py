"""The answer's owner (optimize.answer_folder.FolderAnswer): a design is the optimization's own
variables, so a variable other than the silicone and the gap -- here the taxel width, at path
array.taxel_width under the name "width" -- flows through it: the design's mapping holds it, its
pitch (ArrayTable.pitch of the scene with the variables set) follows it and agrees with the pitch
the optimizer computed from its own scene of the design, the requirements judge that pitch, and
the report's view draws it. A consistency test of the owner's bookkeeping against the
optimizer's, on a coarse 2D row of the thesis PZT array (three static solves)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

EXAMPLE = Path(__file__).resolve().parents[1] / "taxel" / "examples" / "thesis-pzt-3x3-2d.toml"
PROBLEM = """
base = "coarse.toml"
reference = {width = "4 mm", gap = "3 mm"}
[variables]
width = {path = "array.taxel_width", min = "3 mm", max = "6 mm", start = "4 mm"}
gap = {path = "array.gap", min = "2 mm", max = "4 mm", start = "3 mm"}
[objective]
maximize = "sensitivity"
[requirements]
pitch = "<= 8 mm"
"""


@pytest.fixture(scope="module")
def width_front(tmp_path_factory):
    """A front folder of three designs (the reference 4 + 3 mm, 3 + 3.5 mm and 6 + 3 mm), each
    evaluated by the optimizer, written as `taxel optimize` writes it."""
    from taxel.api import write_scene
    from taxel.optimize.driver import Result
    from taxel.optimize.result import FrontRun, OptimizationResult
    from taxel.optimize.run import reference_evaluation
    from taxel.optimize.spec import load_optimization
    from taxel.scene import parse
    tmp = tmp_path_factory.mktemp("width")
    (tmp / "coarse.toml").write_text(EXAMPLE.read_text().replace('size = "0.5 mm"', 'size = "2 mm"')
                                     .replace('piezo_size = "0.1 mm"', 'piezo_size = "0.5 mm"'))
    (tmp / "width-front.toml").write_text(PROBLEM)
    out = tmp / "width-front"
    prob = load_optimization(tmp / "width-front.toml", out)
    runs = [FrontRun(None, Result(np.array(x), 0.0, prob.evaluate(x), {}, 1, True, "ok"))
            for x in ([3.0, 3.5], [6.0, 3.0])]
    res = OptimizationResult("width-front", prob.names, prob.units, "maximize", "sensitivity", runs=runs,
                             reference=reference_evaluation(prob), requirements=dict(prob.spec.requirements),
                             paths={n: v.path for n, v in prob.spec.variables.items()})
    res.to_folder(out)
    write_scene(out, parse({**prob.scene_data(prob.x0), "name": "width-front"}))
    return out, res


def test_a_taxel_width_variable_flows_through_the_answers_owner(width_front):
    from taxel.optimize.answer_folder import FolderAnswer
    out, res = width_front
    a = FolderAnswer.read(out)
    assert a.kind == "front" and [(v.name, v.path, v.unit) for v in a.variables] == \
        [("width", "array.taxel_width", "mm"), ("gap", "array.gap", "mm")]
    assert a.reference.x == pytest.approx({"width": 4e-3, "gap": 3e-3}) and a.reference.label == "reference"
    assert [d.in_units() for d in a.candidates] == [{"width": 3.0, "gap": 3.5}, {"width": 6.0, "gap": 3.0}]
    evaluated = [res.reference] + [r.result.metrics for r in res.runs]
    for d, m in zip([a.reference, *a.candidates], evaluated):
        assert d.metrics["pitch"] == pytest.approx(d.x["width"] + d.x["gap"], rel=1e-12)
        assert d.metrics["pitch"] == pytest.approx(m["pitch"], rel=1e-12)      # the optimizer's own scene's
        assert a.array(d).taxel_width == pytest.approx(d.x["width"], rel=1e-12)
    narrow, wide = a.candidates                     # pitch 6.5 mm; pitch 9 mm: misses pitch <= 8 mm by 1/8
    assert wide.margins["pitch"] == pytest.approx(-1 / 8) and a.recommended is not wide
    assert narrow.margins["pitch"] == pytest.approx(1.5 / 8)
    # the narrower taxel is more sensitive with less crosstalk than the reference: the answer
    assert narrow.metrics["sensitivity"] > a.reference.metrics["sensitivity"]
    assert narrow.metrics["crosstalk"] < a.reference.metrics["crosstalk"] and a.recommended is narrow


def test_the_reports_view_draws_the_owners_width(width_front):
    from taxel.reports.answer import headline_front
    out, _ = width_front
    view = headline_front(out)
    assert view.thesis.pitch_mm == pytest.approx(7.0) and view.thesis.mm("taxel_width") == 4.0
    r = view.recommended
    assert (r.mm("width"), r.gap_mm, r.pitch_mm) == (3.0, 3.5, pytest.approx(6.5))
    assert next(row for row in r.records(view.error, view.model) if row["quantity"] == "pitch")["value"] == \
        pytest.approx(6.5e-3)
    assert "a narrower pitch 7.00 → 6.50 mm" in view.trade
