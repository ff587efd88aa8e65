"""The 3D press's settled reference (docs/press_reference.json, benchmarks/press_directions.py)
and the answer's calibrated band around it: the band contains the reference and the converging
refinements of the press.

A converging refinement divides the whole size field: the nested family of benchmarks/press_3d.py
(docs/press_3d_reference.json, its levels in the asymptotic range, from / 1.41), and from the
default press mesh every size / k with the grading distance kept ("joint" runs of
docs/press_3d_directions.json), which is what `taxel.scene.refined` and a finer `[mesh]` of a punch
press now give (taxel.analyses.model.geometry.punch_grading)."""

import json
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"
DEFAULT = [1.4, 0.56, 0.28, 1, 2.8]        # the default press mesh in press_directions.py's numbers


def _band():
    from taxel.analyses.accuracy.error_estimate import PRESS_3D_ERROR
    from taxel.optimize.answer_press import ANSWER_PRESS_ERROR
    return {"single": PRESS_3D_ERROR, "3x3": ANSWER_PRESS_ERROR["PSI-5H4E"]["sensitivity"]}


def test_the_recorded_refinements_lie_in_the_answers_band():
    """Consistency test on the recorded runs (no press here): for the single taxel and the 3x3, the
    default press mesh's V/F with its band (PRESS_3D_ERROR; the PZT answer's ANSWER_PRESS_ERROR)
    contains the settled reference with its uncertainty and every converging level recorded: the
    nested family's fitted levels (the 3x3's: times rho, V(3x3) / V(single) on the same mesh) and the
    joint refinements of the default press mesh."""
    ref = json.loads((DOCS / "press_reference.json").read_text())
    runs = json.loads((DOCS / "press_3d_directions.json").read_text())["runs"]
    nested = json.loads((DOCS / "press_3d_reference.json").read_text())
    fitted = [abs(r["VF"]) for r in nested["levels"] if r["divide"] >= nested["fit_from"] - 1e-9]
    band = _band()
    for case in ("single", "3x3"):
        default = next(r for r in runs if r["case"] == case and r["k"] == 1.0 and r["mesh"] == DEFAULT)
        v0, e = default["VF"], band[case]
        r, u = ref[case]["VF"], ref[case]["uncertainty"]
        assert v0 * (1 - e) <= r * (1 - u) and r * (1 + u) <= v0 * (1 + e), (case, v0, r, u, e)
        rho = ref["3x3"]["rho"] if case == "3x3" else [1.0, 1.0]
        levels = [v * q for v in fitted for q in rho]
        levels += [x["VF"] for x in runs if x["case"] == case and x["direction"] == "joint" and x["k"] > 1]
        assert len(levels) >= 6
        for v in levels:
            assert abs(v / v0 - 1) <= e, (case, v, v0, e)


def _press(case: str, k: float):
    from taxel.analyses.model.problem import solve_model
    from taxel.scene import load, refined
    sc = load("thesis-pzt-probe-3d")
    if case == "3x3":
        sc = sc.replace(**{"array.rows": 3, "array.cols": 3, "load.taxel": [1, 1]})
    return abs(solve_model(sc if k == 1 else refined(sc, k)).outputs()["sensitivity"])


@pytest.mark.slow       # two single-taxel presses (8k and about 13k unknowns): about a minute on a quiet machine
def test_a_finer_single_taxel_press_stays_in_its_band():
    """The single taxel at the default press mesh and at every size / sqrt 2 (taxel.scene.refined, a
    converging refinement now): the finer press lies in the default's band, and both bands contain
    the settled reference with its uncertainty."""
    ref = json.loads((DOCS / "press_reference.json").read_text())["single"]
    e = _band()["single"]
    v1, v2 = _press("single", 1.0), _press("single", 2 ** 0.5)
    assert abs(v2 / v1 - 1) <= e, (v1, v2)
    for v in (v1, v2):
        assert abs(ref["VF"] / v - 1) + ref["uncertainty"] <= e, (v, ref)


@pytest.mark.slow       # two presses of the 3x3 quarter (18k and about 33k unknowns): several minutes
def test_a_finer_3x3_press_stays_in_the_answers_band():
    """The 3x3 pressed at its centre at the default press mesh and at every size / sqrt 2: the finer
    press lies in the answer's band around the default's, and the band contains the 3x3's settled
    reference with its uncertainty."""
    ref = json.loads((DOCS / "press_reference.json").read_text())["3x3"]
    e = _band()["3x3"]
    v1, v2 = _press("3x3", 1.0), _press("3x3", 2 ** 0.5)
    assert abs(v2 / v1 - 1) <= e, (v1, v2)
    assert abs(ref["VF"] / v1 - 1) + ref["uncertainty"] <= e, (v1, ref)
