"""The answer's 3D presses (optimize.answer_press): the calibrated error estimate checked on
a second design of the press family, and a press's numbers equal to `taxel.solve`'s."""

import pytest


@pytest.mark.slow       # four 3D presses (the 3x3 and the single taxel, two meshes each): a few minutes
def test_the_calibrated_press_error_holds_on_a_third_design():
    """ANSWER_PRESS_ERROR for PZT is the worst of the rule on two PZT designs
    (benchmarks/answer_press_error.py: gaps 3 and 3.44 mm, on the converging refinement path);
    the same rule measured on a third design of the family, the PZT probe front's 1 / 1 mm,
    gap 4.78 mm, comes out within the stored constants."""
    from taxel.optimize import answer_press as AP
    from taxel.optimize import spec as O
    prob = O.load_optimization("thesis-pzt-probe-front")
    m = AP.rule(prob, [1.0, 1.0, 4.777777777777778])
    cal = AP.ANSWER_PRESS_ERROR["PSI-5H4E"]
    # the calibration holds on the third design; re-calibrated on the converging refinement (issue 57,
    # benchmarks/answer_press_error.py, 2026-11-29) the PZT constants are 2.6 % / 3.7 % (crosstalk: 1.5 % from
    # the two designs did not bound this one's 1.98 %), the sensitivity's
    # above the 2 % bound (AP.WITHIN): flagged on the page
    assert 0 < m["sensitivity"] <= cal["sensitivity"], m
    assert 0 < m["crosstalk"] <= cal["crosstalk"], m


def _answer_folders(tmp_path, edit=None):
    """The main job's front records (tests/data/answer, the two of the seed's requirements
    the report tests state), with the answer's 3D presses of a real run (answer_3d: the
    recommended and the thesis design of each material pressed by taxel.jobs.answer_3d);
    `edit(rec)` changes each probe-front record first."""
    import json
    import shutil
    from pathlib import Path
    folders = []
    for src in sorted((Path(__file__).parent / "data" / "answer").iterdir()):
        shutil.copytree(src, tmp_path / src.name)
        for name in ("probe-front.json", "front-3d.json"):
            rec = json.loads((tmp_path / src.name / name).read_text())
            rec["requirements"] = {"gap": ">= 1 mm", "total_thickness": "<= 2.127 mm"}
            if edit and name == "probe-front.json":
                edit(rec)
            (tmp_path / src.name / name).write_text(json.dumps(rec))
        folders.append(tmp_path / src.name)
    return folders


def test_the_answer_is_the_3d_presses_with_their_own_bands(tmp_path):
    """With every answer design pressed in 3D within 2 % (PZT), the answer's numbers are the
    presses' (not the candidate selection's), each quantity with its own band, the model
    says so, and the ladder's answer row is 7 (3D under the probe) with the selection
    model's row 6 below it. (PVDF's presses are estimated at 2.7 %: the next test.)"""
    import json
    from taxel.optimize.answer_press import read
    from taxel.reports.answer import headline_front
    for folder in _answer_folders(tmp_path)[1:]:                   # thesis-pzt-front
        rec = json.loads((folder / "probe-front.json").read_text())
        presses = {p.role: p for p in read(rec)}
        a = headline_front(folder)
        assert set(presses) == {"thesis"} | ({"recommended"} if a.recommended else set())
        for d in (a.recommended, a.thesis):
            if d is None:
                continue
            p = presses[d.role]
            assert p.within and (d.sensitivity_V_per_N, d.crosstalk) == (p.sensitivity, p.crosstalk)
        assert a.row == 7 and "3D presses by the rig's probe" in a.model
        assert a.error["sensitivity"] != a.error["crosstalk"]          # crosstalk carries its own band
        for g in a.ladders():
            rows = [r[0] for r in g["rows"]]
            assert rows[-1].startswith("7. ") and rows[-1].endswith("(the answer)"), rows
            assert any(r.startswith("6. ") for r in rows) and g["answer"].endswith("-7")


def test_a_press_estimated_above_2_percent_is_the_answer_with_its_band_flagged(tmp_path):
    """A 3D press whose error estimate is above 2 % is still the answer (the better model than
    the selection's estimate): its own band, flagged on the page (PVDF's 2.7 %, and the PZT
    presses' estimates set to 2.5 %); a press without an estimate is not the answer: the
    selection model's numbers stay (ladder row 6) and a note says why."""
    from taxel.reports.answer import headline_front
    from taxel.reports.answer_design import _band

    def worse(rec):
        for p in rec["answer_3d"]["designs"]:
            p["error"] = max(p["error"], 0.025)
    for folder in _answer_folders(tmp_path, worse):
        a = headline_front(folder)
        assert a.row == 7 and "3D presses by the rig's probe" in a.model
        assert a.error["sensitivity"] >= 0.025 and "> 2 %" in _band(1.0, a.error["sensitivity"], "V/N")
        for g in a.ladders():
            assert g["answer"].endswith("-7")

    def unestimated(rec):
        for p in rec["answer_3d"]["designs"]:
            p["error"] = None
    for folder in _answer_folders(tmp_path / "none", unestimated):
        a = headline_front(folder)
        assert a.row == 6 and "an estimate, not a 3D press" in a.model
        assert any("has no error estimate" in n for n in a.notes)
        for g in a.ladders():
            rows = [r[0] for r in g["rows"]]
            assert rows[-1].startswith("7. ") and "(the answer)" not in rows[-1]
            assert g["answer"].endswith("-6")


def test_the_strain_limit_is_judged_on_the_answers_3d_presses(tmp_path):
    """The silicone's strain limit (max_strain, Ecoflex 00-30's elongation at break in the built-in
    requirements) is judged on each answer design's own 3D press (its largest silicone strain),
    not left "not evaluated": margin 1 - strain / bound, and a bound below it is missed."""
    from taxel.optimize.answer_folder import FolderAnswer
    strain = {"thesis": 1.378, "recommended": 1.775}         # the demo's presses, 2026-11-29

    def edit(limit):
        def f(rec):
            rec["requirements"] = {**rec["requirements"], "max_strain": limit}
            for d in rec["answer_3d"]["designs"]:
                d["max_strain"] = strain.get(d["role"], 1.4)
        return f
    folder = _answer_folders(tmp_path / "a", edit("<= 900 %"))[1]          # thesis-pzt-front
    a = FolderAnswer.read(folder)
    ref = a.reference
    assert ref.metrics["max_strain"] == strain["thesis"]
    assert ref.margins["max_strain"] == pytest.approx(1 - strain["thesis"] / 9.0)
    tight = FolderAnswer.read(_answer_folders(tmp_path / "b", edit("<= 100 %"))[1])
    assert tight.reference.margins["max_strain"] == pytest.approx(1 - strain["thesis"] / 1.0)


def test_a_price_the_3d_presses_reverse_buys_nothing(tmp_path):
    """pitch <= 7 mm keeps the thesis PZT design; relaxing it takes the 3.44 mm gap design on the
    candidate selection's numbers. Its own 3D press (0.7786 V/N, above the thesis design's
    0.7758) makes that a price ("binds: at <= 7.44 mm the choice is 779 mV/N"); pressed at
    0.770 V/N, below the chosen design's press, the relaxation buys nothing, and the page
    says so instead of offering a worse design as what the requirement costs."""
    from taxel.reports.answer import headline_front

    def edit(sensitivity):
        def f(rec):
            rec["requirements"] = {"pitch": "<= 7 mm"}
            for d in rec["answer_3d"]["designs"]:
                if d["role"] == "recommended":
                    d["role"] = "relaxed-pitch"
                    d["sensitivity"] = sensitivity or d["sensitivity"]
        return f
    bought = headline_front(_answer_folders(tmp_path / "a", edit(None))[1])
    assert bought.recommended is None and not bought.reversed
    assert "pitch ≤ 7 mm binds: at ≤ 7.44 mm the choice is 779 mV/N" in bought.trade
    none = headline_front(_answer_folders(tmp_path / "b", edit(0.770))[1])
    assert none.reversed == {"relaxed-pitch"}
    assert "pitch ≤ 7 mm binds on the candidate selection's numbers, but relaxing it buys nothing" in none.trade
    assert "presses at 770 mV/N" in none.trade and "no better than the chosen design's 776 mV/N" in none.trade
