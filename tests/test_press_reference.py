"""The 3D press's settled reference (docs/press_reference.json, benchmarks/press_directions.py)
and the answer's calibrated band (optimize.answer_press.ANSWER_PRESS_ERROR) around it: the band
contains the reference and every converging refinement of the answer's own press.

A converging refinement: the default press mesh's size field divided by k (far size, taxel edges'
size and the rim's size / k, the grading distance kept, the piezo's elements through x k rounded),
which is what `taxel.scene.refined` and a finer `[mesh]` of a punch press now give
(taxel.analyses.geometry.punch_grading)."""

import json
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"


def _band():
    from taxel.analyses.error_estimate import PRESS_3D_ERROR
    from taxel.optimize.answer_press import ANSWER_PRESS_ERROR
    return {"single": PRESS_3D_ERROR, "3x3": ANSWER_PRESS_ERROR["PSI-5H4E"]["sensitivity"]}


def test_the_recorded_refinements_lie_in_the_answers_band():
    """Consistency test on the recorded runs (no press here): for the single taxel and the 3x3, the
    default press mesh's V/F with its band (PRESS_3D_ERROR; the PZT answer's ANSWER_PRESS_ERROR)
    contains the settled reference with its uncertainty, and every recorded level of the converging
    refinement ("joint" in docs/press_3d_directions.json) of the same press."""
    ref = json.loads((DOCS / "press_reference.json").read_text())
    runs = json.loads((DOCS / "press_3d_directions.json").read_text())["runs"]
    band = _band()
    for case in ("single", "3x3"):
        default = next(r for r in runs if r["case"] == case and r["k"] == 1.0 and r["mesh"] == [1.4, 0.56, 0.28, 1, 2.8])
        v0, e = default["VF"], band[case]
        r, u = ref[case]["VF"], ref[case]["uncertainty"]
        assert v0 * (1 - e) <= r * (1 - u) and r * (1 + u) <= v0 * (1 + e), (case, v0, r, u, e)
        joint = [x for x in runs if x["case"] == case and x["direction"] == "joint" and x["k"] > 1]
        assert joint, case
        for x in joint:
            assert abs(x["VF"] / v0 - 1) <= e, (case, x["k"], x["VF"], v0, e)


def _press(case: str, k: float):
    from taxel.analyses.problem import solve_model
    from taxel.scene import load, refined
    sc = load("thesis-pzt-probe-3d")
    if case == "3x3":
        sc = sc.replace(**{"array.rows": 3, "array.cols": 3, "load.taxel": [1, 1]})
    return abs(solve_model(sc if k == 1 else refined(sc, k)).outputs()["sensitivity"])


@pytest.mark.slow       # two single-taxel presses (8k and 15k unknowns): about a minute on a quiet machine
def test_a_finer_single_taxel_press_stays_in_its_band():
    """The single taxel at the default press mesh and at every size / sqrt 2 (taxel.scene.refined, a
    converging refinement): the finer press lies in the default's band, and both bands contain the
    settled reference."""
    ref = json.loads((DOCS / "press_reference.json").read_text())["single"]
    e = _band()["single"]
    v1, v2 = _press("single", 1.0), _press("single", 2 ** 0.5)
    assert abs(v2 / v1 - 1) <= e, (v1, v2)
    for v in (v1, v2):
        assert abs(ref["VF"] / v - 1) + ref["uncertainty"] <= e, (v, ref)


@pytest.mark.slow       # two presses of the 3x3 quarter (18k and 35k unknowns): several minutes
def test_a_finer_3x3_press_stays_in_the_answers_band():
    """The 3x3 pressed at its centre at the default press mesh and at every size / sqrt 2: the finer
    press lies in the answer's band around the default's, and the band contains the 3x3's settled
    reference with its uncertainty."""
    ref = json.loads((DOCS / "press_reference.json").read_text())["3x3"]
    e = _band()["3x3"]
    v1, v2 = _press("3x3", 1.0), _press("3x3", 2 ** 0.5)
    assert abs(v2 / v1 - 1) <= e, (v1, v2)
    assert abs(ref["VF"] / v1 - 1) + ref["uncertainty"] <= e, (v1, ref)
