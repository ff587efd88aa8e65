"""Requirements in, one recommendation out (optimize.requirements, reports.answer).

The front records under tests/data/answer are the main job's own (`taxel demo`,
probe-front.json and front-3d.json of the thesis PZT and PVDF fronts, written by
optimize.probe_front and optimize.multifidelity); the tests state requirements on
them and check the design the answer recommends."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from taxel.optimize.requirements import Requirement, RequirementError, choose, implied, judge, read
from taxel.reports.answer import block, headline_front, requirement_rows

DATA = Path(__file__).parent / "data" / "answer"
THESIS_REQUIREMENTS = {"pitch": "<= 7 mm", "total_thickness": "<= 2.127 mm", "gap": ">= 1 mm"}


def _front(tmp_path: Path, material: str, requirements: dict) -> Path:
    """A copy of the main job's front folder with `requirements` in its records."""
    folder = tmp_path / f"thesis-{material}-front"
    shutil.copytree(DATA / folder.name, folder, dirs_exist_ok=True)
    for name in ("probe-front.json", "front-3d.json"):
        rec = json.loads((folder / name).read_text())
        rec["requirements"] = requirements
        (folder / name).write_text(json.dumps(rec))
    return folder


def test_read_uses_the_tolerance_grammar_and_si():
    reqs = read({"pitch": "<= 7 mm", "crosstalk": "<= 2 %", "sensitivity": ">= 0.5 V/N"})
    assert [(r.metric, r.op) for r in reqs] == [("pitch", "<="), ("crosstalk", "<="), ("sensitivity", ">=")]
    assert reqs[0].bound == pytest.approx(7e-3) and reqs[1].bound == pytest.approx(0.02)
    assert reqs[0].text() == "pitch ≤ 7 mm" and reqs[1].text() == "crosstalk ≤ 2 %"


@pytest.mark.parametrize("table, key", [({"pitch": "7 mm"}, "requirements.pitch"),
                                        ({"pitch": "<= seven"}, "requirements.pitch"),
                                        ({"colour": "<= 1"}, "requirements.colour")])
def test_bad_requirement_is_one_line_naming_the_key(table, key):
    with pytest.raises(RequirementError) as exc:
        read(table)
    assert key in str(exc.value) and "\n" not in str(exc.value)


def test_margin_is_relative_and_signed():
    r = Requirement("pitch", "<=", 7e-3)
    assert r.margin(6.3e-3) == pytest.approx(0.1) and r.margin(7.7e-3) == pytest.approx(-0.1)
    assert Requirement("sensitivity", ">=", 0.5).margin(0.6) == pytest.approx(0.2)
    assert r.margin(None) is None and r.margin(float("nan")) is None


def test_choose_limits_exclude_then_the_objective_then_leximin_then_binding():
    reqs = read({"pitch": "<= 7 mm", "crosstalk": "<= 2 %", "sensitivity": ">= 0.5 V/N"})
    a = {"pitch": 6e-3, "crosstalk": 0.019, "sensitivity": 0.9}      # the most sensitive that meets all: recommended
    b = {"pitch": 7e-3, "crosstalk": 0.01, "sensitivity": 0.6}       # larger smallest margin (20 % against 5 %)
    c = {"pitch": 8e-3, "crosstalk": 0.001, "sensitivity": 1.0}      # breaks the pitch limit
    ch = choose([a, b, c], reqs)
    assert ch.recommended == 0 and not ch.verdicts[2].meets and ch.binding is None
    # the objective is the run's: minimizing crosstalk takes b
    assert choose([a, b, c], reqs, ("minimize", "crosstalk")).recommended == 1
    # equal by the objective (within TIE): the larger smallest margin decides (leximin)
    assert choose([a, dict(b, sensitivity=0.9 * (1 + 1e-4))], reqs).recommended == 1
    # a thinner design is not a better one: the limits' margins are not weighed
    assert choose([b, dict(b, pitch=5e-3)], reqs).recommended == 0
    none = choose([c, {"pitch": 6e-3, "crosstalk": 0.03, "sensitivity": 0.9}], reqs)
    assert none.recommended is None
    # the closest design misses pitch by 1/7 (the other misses crosstalk by 1/2): pitch binds
    assert none.binding[0] == "pitch" and none.binding[1] == pytest.approx(-1 / 7)


def test_a_crosstalk_requirement_alone_does_not_buy_crosstalk_with_sensitivity():
    """A user's PVDF front (thickness <= 1.5 mm, crosstalk <= 3 %, maximize sensitivity): the
    design at 2.99 % and 9.40 V/N is recommended, not the one at 0.27 % and 5.41 V/N that the
    largest crosstalk margin would take (the objective decides among designs meeting them all)."""
    reqs = read({"total_thickness": "<= 1.5 mm", "crosstalk": "<= 3 %"})
    low = {"total_thickness": 0.668e-3, "crosstalk": 0.0027, "sensitivity": 5.41}
    high = {"total_thickness": 1.48e-3, "crosstalk": 0.0299, "sensitivity": 9.40}
    assert choose([low, high], reqs).recommended == 1


def test_implied_bar_is_the_reference_design():
    ref = {"sensitivity": 0.7, "crosstalk": 0.02, "pitch": 7e-3}
    reqs = implied(read({"pitch": "<= 8 mm"}), ref)
    assert {r.metric for r in reqs if not r.stated} == {"sensitivity", "crosstalk"}
    assert judge(ref, reqs).meets
    assert implied(read({"crosstalk": "<= 1 %"}), ref) == read({"crosstalk": "<= 1 %"})


def test_a_pitch_requirement_of_7_mm_changes_the_answer(tmp_path):
    """The main job's PZT front: without requirements the answer widens the gap (pitch
    7.44 mm) to cut crosstalk; with the seed's pitch <= 7 mm it keeps the thesis design."""
    free = headline_front(_front(tmp_path / "free", "pzt", {}))
    assert free.recommended is not None and free.recommended.pitch_mm > 7.0 + 1e-6
    assert free.recommended.crosstalk < free.thesis.crosstalk
    held = headline_front(_front(tmp_path / "held", "pzt", {"pitch": "<= 7 mm"}))
    assert held.recommended is None or held.recommended.pitch_mm <= 7.0 + 1e-9
    assert (held.recommended and (held.recommended.gap_mm, held.recommended.silicone_above_mm)) != \
        (free.recommended.gap_mm, free.recommended.silicone_above_mm)


def test_unmeetable_requirements_name_the_binding_one(tmp_path):
    a = headline_front(_front(tmp_path, "pvdf", {"pitch": "<= 7 mm", "crosstalk": "<= 1 %"}))
    assert a.recommended is None and a.binding[1] < 0
    assert "binds" in a.trade and "by the closest design" in a.trade


def test_block_shows_requirement_prediction_margin_per_material(tmp_path):
    answers = [headline_front(_front(tmp_path, m, THESIS_REQUIREMENTS)) for m in ("pzt", "pvdf")]
    blk = block(answers)
    assert len(blk["lines"]) == 2
    for line, a in zip(blk["lines"], answers):
        rows = line["requirements"]
        assert [r[0] for r in rows[:3]] == ["pitch ≤ 7 mm", "total thickness ≤ 2.13 mm", "gap ≥ 1 mm"]
        assert rows == requirement_rows(a) and all(len(r) == len(line["requirement_cols"]) for r in rows)
        assert rows[0][-2] == "7 mm" and rows[0][-1] == "at the bound"     # the thesis design's pitch
        assert line["requirement_cols"][-2] == ("thesis design (kept): prediction" if a.recommended is None
                                                 else "thesis design: prediction")
    assert blk["title"].count(";") == 1                                    # one recommendation per material


def test_a_front_that_drops_a_run_says_so_in_its_summary():
    """A front asked for 3 points whose middle run found no feasible design: the summary
    counts 2 of 3 runs and names the dropped one with the driver's message."""
    import numpy as np
    from taxel.optimize.driver import Result
    from taxel.optimize.result import FrontRun, OptimizationResult

    def run(ok, s, c):
        return Result(np.array([1.0, 3.0]), -s, {"sensitivity": s if ok else None, "crosstalk": c}, {}, 5, ok,
                      "ok" if ok else "evaluation budget used; no feasible design found")
    res = OptimizationResult("f", ["silicone_above", "gap"], ["mm", "mm"], "maximize", "sensitivity",
                             runs=[FrontRun(0.01, run(True, 0.6, 0.01)), FrontRun(0.02, run(False, 0.7, 0.03)),
                                   FrontRun(0.03, run(True, 0.8, 0.03))])
    last = res.summary()[-1]
    assert last.startswith("front: 2 of 3 runs on the front (1 dropped: crosstalk <= 2 %: evaluation budget used")


def test_the_answer_block_reads_in_plain_language(tmp_path):
    """Every word of the answer block (title, table, requirements, trade, notes, model,
    definitions) holds no code identifier and no number of more than 4 significant
    figures (reports.plain, the check every page gets)."""
    from taxel.reports.plain import problems
    answers = [headline_front(_front(tmp_path, m, THESIS_REQUIREMENTS)) for m in ("pzt", "pvdf")]
    blk = block(answers)
    blk.pop("records")                       # answer.csv's numeric rows, not prose
    blk.pop("links")                         # page anchors, not prose
    blk["title_parts"] = [t for t, _ in blk["title_parts"]]
    for line in blk["lines"]:
        line.pop("requirement_ids")
        for g in line["ladders"]:
            g.pop("ids"), g.pop("answer")

    def words(x):
        if isinstance(x, dict):
            return " ".join(words(v) for v in x.values())
        if isinstance(x, (list, tuple)):
            return " ".join(words(v) for v in x)
        return str(x) if x is not None else ""
    assert problems(f"<p>{words(blk)}</p>") == []


@pytest.mark.parametrize("html, found", [
    ("<p>see optimize.probe_front.PRODUCT_ERROR</p>", 1), ("<p>commit 31482dd, PRODUCT_ERROR</p>", 1), ("<p>tangent_sensitivity: 1</p>", 1),
    ("<p>0.7386685841 V/N</p>", 1), ("<p>1.8000000000000002e-08 V</p>", 1), ("<p>{'x': 1}</p>", 1),
    ("<p>738 mV/N at 1.25 %, 4.24 nF, 14567 unknowns, 2026-11-28 04:10:00, fig-2-5.csv, taxel_1_1</p>", 0),
    ("<pre>min_detectable_force = 0.000282</pre><p>results (s)</p>", 0)])
def test_plain_language_check_finds_what_it_should(html, found):
    from taxel.reports.plain import problems
    assert len(problems(html)) == found, problems(html)


def test_each_answer_design_has_its_model_ladder(tmp_path):
    """The thesis PZT design's sensitivity appears in six models in the main job's records
    (the last the answer's 3D press under the probe, ladder row 7);
    its ladder holds each once with its model, error and why, and the row marked as the
    answer is the number the answer table shows."""
    from taxel.reports.tables import eng, percent
    a = headline_front(_front(tmp_path, "pzt", {}))
    ladders = {g["design"]: g["rows"] for g in a.ladders()}
    thesis = ladders["the thesis design"]
    assert [r[1] for r in thesis] == ["812 mV/N", "860 mV/N", "824 mV/N", "697 mV/N", "739 mV/N", "776 mV/N"]
    answer_rows = [r for r in thesis if r[0].endswith("(the answer)")]
    assert len(answer_rows) == 1
    assert answer_rows[0][1] == eng(a.thesis.sensitivity_V_per_N, "V/N", 3)
    assert answer_rows[0][2] == percent(a.thesis.crosstalk)
    assert all(r[-1] for r in thesis) and "recommended design" in ladders
    rec = ladders["recommended design"]
    assert [r for r in rec if r[0].endswith("(the answer)")][0][1] == eng(a.recommended.sensitivity_V_per_N, "V/N", 3)
    blk = block([a])
    assert blk["lines"][0]["ladders"] and blk["ladder_cols"][0] == "model"


@pytest.fixture(scope="module")
def through_readout(tmp_path_factory):
    """Both materials' answers of the main job's records through the bench's readout
    (taxel.jobs.answer_readout: one 2D solve per design)."""
    from taxel.jobs.answer_readout import answer_readout
    root = tmp_path_factory.mktemp("readout")
    folders = [_front(root, m, {}) for m in ("pzt", "pvdf")]
    for f in folders:
        answer_readout(f)
    return [headline_front(f) for f in folders]


def test_every_answer_row_has_its_readout_numbers_and_csv_is_numeric(through_readout, tmp_path):
    """Each answer design gets charge per newton, V/N at the readout (the charge amplifier's
    |Q| / C_f in its passband), a minimum detectable force dominated by the rig's hum, and
    a force range; answer.csv holds numbers with their error and unit."""
    import csv
    from taxel import api
    from taxel.reports.tables import eng
    c_f = api.load("thesis-pzt-frequency").readout.C_f
    for a in through_readout:
        for d in (a.recommended, a.thesis):
            v = d.values
            # the passband gain |Q| / C_f, less the piezo's dispersion from the static charge up to the
            # passband (the causal laws of tan(delta) = 0.02 and of Qm: PZT's Qm 32 about 14 % lower,
            # PVDF's Qm 10 about 37 %); the lossless case is exact in tests/test_at_readout.py
            assert 0.5 < v["readout_sensitivity"] / (v["charge_sensitivity"] / c_f) < 1.0
            assert d.min_detectable_force_N == v["min_detectable_force"] > 0 and v["force_range"] > 0
    blk = block(through_readout)
    assert "PZT (PSI-5H4E) is preferred" in blk["preference"] and "charge amplifier reads charge" in blk["preference"]
    assert all(r[blk["cols"].index("min. detectable force")] not in ("not computed", "—") for r in blk["rows"])
    # page one's bandwidth: each design's charge amplifier corners, the lower one 1 / (2 pi R_f C_f)
    r = api.load("thesis-pzt-frequency").readout
    low = eng(1 / (2 * 3.141592653589793 * r.R_f * r.C_f), "Hz", 3)
    assert blk["dynamics"].count(f"design {low} to ") == 4 and "not computed (no frequency sweep" in blk["dynamics"]
    path = tmp_path / "answer.csv"
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(blk["records"][0]))
        w.writeheader()
        w.writerows(blk["records"])
    rows = list(csv.DictReader(open(path)))
    assert {r["quantity"] for r in rows} >= {"open-circuit sensitivity", "charge per newton", "minimum detectable force"}
    for r in rows:
        float(r["value"])
        assert r["unit"] and (r["relative error"] == "" or 0 < float(r["relative error"]) < 1)


def test_charge_voltage_and_the_ladders_capacitance_agree(through_readout):
    """V = Q / C for every answer design: its charge per newton over the capacitance of its
    ladder's answer row is its open-circuit sensitivity, on the page too (3 significant
    figures each). That capacitance is the free plate's, the seed's 4.24 nF for a 4 x 4 x
    0.127 mm PSI-5H4E taxel and 33-35 pF for the 52 um PVDF one (eps_r 12-13); the 2D
    section's (row 1) is lower for PZT, whose depth it holds unstrained, and the note says why."""
    from taxel.reports.ladder import ladder
    from taxel.units import magnitude
    blk = block(through_readout)
    for a in through_readout:
        for d in (a.recommended, a.thesis):
            rungs = ladder(a.path, d.design.in_units(), d is a.thesis)
            c = next(r for r in rungs if r.answer).capacitance
            assert d.values["charge_sensitivity"] / c == pytest.approx(d.sensitivity_V_per_N, rel=1e-12)
            two = next((r.capacitance for r in rungs if r.number == 1), None)    # a 2D-pressure-patch row, if solved
            assert two is not None or d is not a.thesis
            if d.material == "PSI-5H4E":
                assert c == pytest.approx(4.24e-9, rel=0.005) and (two is None or 0.75 < two / c < 0.9)
            else:
                assert 32e-12 < c < 35.5e-12 and (two is None or two == pytest.approx(c, rel=0.01))
    for line in blk["lines"]:
        for g in line["ladders"]:
            assert "parallel plate" in g["note"] and "2D section" in g["note"]
    for row in blk["rows"]:
        cells = dict(zip(blk["cols"], row))
        words = cells["charge per newton"].split()                 # "3.3 ± 0.21 nC/N (band ...)"
        q = magnitude(f"{words[0]} {next(w for w in words if w.endswith('C/N'))[:-2]}")
        words = cells["open-circuit sensitivity"].split()          # "738 ± 85 mV/N"
        v = magnitude(f"{words[0]} {next(w for w in words if w.endswith('V/N'))}")
        material = "PZT" if cells["material"].startswith("PZT") else "PVDF"
        ladder_rows = [g["rows"] for ln in blk["lines"] if ln["material"].startswith(material)
                       for g in ln["ladders"] if g["role"] == cells["design"]][0]
        c = magnitude([r for r in ladder_rows if r[0].endswith("(the answer)")][0][3])
        assert q / c == pytest.approx(v, rel=0.01)            # 3 significant figures on each


def test_an_optimization_whose_every_evaluation_fails_says_so():
    """The driver returns an unsuccessful result naming the failure (a front then drops the
    run and its summary says so) instead of crashing on a missing objective."""
    import numpy as np
    from taxel.optimize.driver import minimize

    def evaluate(x):
        return {"sensitivity": None, "crosstalk": None}
    r = minimize(evaluate, np.array([0.5]), [(0.0, 1.0)], "sensitivity", [("crosstalk", "<=", 0.1)],
                 maximize=True, global_alg=None, local_alg="COBYLA", max_evals=4, xtol=0.02)
    assert not r.success and "every evaluation failed" in r.message


def test_no_reference_sensitivity_implies_no_bar():
    """A run whose only requirement is coverage and whose reference was not evaluated: no bar
    (was a KeyError on 'sensitivity')."""
    reqs = read({"coverage": ">= 100 %"})
    assert implied(reqs, {}) == reqs and implied(reqs, {"x": {}}) == reqs
    # a requirement on localization alone still leaves the reference's sensitivity and crosstalk as the bar
    bar = implied(read({"localization_error": "<= 1 mm"}), {"sensitivity": 0.7, "crosstalk": 0.02})
    assert {r.metric for r in bar if not r.stated} == {"sensitivity", "crosstalk"}


@pytest.mark.parametrize("table, words", [({"coverage": ">= 200 %"}, "never above 100 %"),
                                          ({"localization_error": "<= -0.5 mm"}, "never below 0 m"),
                                          ({"yield": ">= 1.5"}, "never above 100 %")])
def test_a_bound_no_design_can_reach_is_refused(table, words):
    with pytest.raises(RequirementError, match=words) as exc:
        read(table)
    assert f"requirements.{next(iter(table))}" in str(exc.value) and "\n" not in str(exc.value)


def _result(requirements, designs, reference=None):
    import numpy as np
    from taxel.optimize.driver import Result
    from taxel.optimize.result import FrontRun, OptimizationResult
    runs = [FrontRun(m["crosstalk"], Result(np.array([g]), 0.0, m, {}, 3, True, "ok", [])) for g, m in designs]
    return OptimizationResult("t", ["gap"], ["mm"], "maximize", "sensitivity", runs=runs,
                              reference=reference, requirements=requirements)


def test_the_verdict_names_the_missed_requirement_by_how_much_and_the_closest_design():
    from taxel.optimize.answer import Answer
    res = _result({"pitch": "<= 6 mm", "crosstalk": "<= 2 %"},
                  [(3.0, {"sensitivity": 0.8, "crosstalk": 0.05, "pitch": 7e-3}),
                   (2.0, {"sensitivity": 0.7, "crosstalk": 0.03, "pitch": 6e-3})])
    ans = Answer.of(res)
    assert ans.chosen is None and ans.closest.x["gap"] == pytest.approx(2e-3)
    req, margin = ans.binding
    assert req.metric == "crosstalk" and margin == pytest.approx(-0.5)
    text = "\n".join(res.summary())
    assert "NOT met" in text and "crosstalk ≤ 2 %: 3 %, MISSED (short by 50 %)" in text and "gap 2 mm" in text
    met = Answer.of(_result({"pitch": "<= 8 mm"}, [(3.0, {"sensitivity": 0.8, "crosstalk": 0.05, "pitch": 7e-3})]))
    assert met.chosen is not None and met.binding[0].metric == "pitch" and met.binding[1] == pytest.approx(1 / 8)


def test_requirements_are_the_searchs_constraints(tmp_path):
    """[requirements] is the one table the optimizer obeys (but coverage and localization_error,
    judged after the search); a file with the retired [constraints] is refused, naming the move."""
    from taxel.optimize.spec import OptimizeError, load_optimization
    head = ('base = "thesis-pzt-3x3-2d"\n[variables]\ngap = {path = "array.gap", min = "1 mm", max = "5 mm"}\n'
            '[objective]\nmaximize = "sensitivity"\n')
    f = tmp_path / "o.toml"
    f.write_text(head + '[requirements]\npitch = "<= 7 mm"\ncrosstalk = "<= 2 %"\ncoverage = ">= 100 %"\n')
    p = load_optimization(f)
    assert p.constraints == [("pitch", "<=", pytest.approx(7e-3)), ("crosstalk", "<=", pytest.approx(0.02))]
    f.write_text(head + '[constraints]\npitch = "<= 7 mm"\n')
    with pytest.raises(OptimizeError, match=r'\[constraints\].*move pitch = "<= 7 mm" under \[requirements\]'):
        load_optimization(f)


def test_front_targets_are_spaced_in_log_between_the_ends():
    from taxel.optimize.front import targets
    t = targets(0.002, 0.06, 5)
    assert len(t) == 3 and t[0] / 0.002 == pytest.approx(0.06 / t[-1]) and t[1] == pytest.approx((0.002 * 0.06) ** 0.5)
    assert targets(None, 0.06, 5) == [] and targets(0.05, 0.05, 5) == []
