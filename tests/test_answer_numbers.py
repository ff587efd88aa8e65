"""One number per quantity (issue 56): every page of the main job's report that shows a
quantity of an answer design (minimum detectable force, saturation, capacitance,
open-circuit sensitivity) shows the answer's value, or names its model and links the
ladder row that explains the difference (reports.answer_numbers)."""

from __future__ import annotations

import html
import re
import shutil
from pathlib import Path

import pytest

from taxel.reports.build import build


@pytest.mark.slow   # the fronts' records through the bench's readout, a noise budget, a 20-point sweep, a report (70 s beside other jobs)
def test_every_page_shows_the_answers_number_or_names_its_ladder_row(tmp_path):
    from taxel import api
    from taxel.jobs.answer_readout import answer_readout
    from taxel.jobs.main_job import noise_budget
    from taxel.reports.answer import headline_front
    from taxel.reports.answer_numbers import QUANTITIES, of_answers
    folders = []
    for src in sorted((Path(__file__).parent / "data" / "answer").iterdir()):   # the main job's front records
        shutil.copytree(src, tmp_path / src.name)
        answer_readout(tmp_path / src.name)              # the answer's readout numbers, as the main job makes them
        folders.append(tmp_path / src.name)
    folders.append(noise_budget(tmp_path / "noise-budget"))          # the thesis PZT design on the 2D FEM
    sweep = tmp_path / "thesis-pzt-frequency"
    api.solve(api.load("thesis-pzt-frequency").replace(**{"analysis.points": 20}), out=sweep)
    folders.append(sweep)
    answers = of_answers([headline_front(f) for f in folders[:2]])
    pzt = next(a for a in answers if a.folder == "thesis-pzt-front" and a.role == "thesis")
    assert {k for k, v in pzt.values.items() if v is not None} >= {"min_detectable_force", "capacitance",
                                                                     "force_range", "sensitivity"}
    index = build(folders, tmp_path / "report")
    pages = {p.name: p.read_text(encoding="utf-8") for p in index.parent.glob("*.html")}
    anchors = set(re.findall(r'id="([^"]+)"', pages["index.html"]))
    checked = differing = 0
    for name, page in pages.items():
        cards = re.findall(r'<span class="v">(.*?)</span><span class="l">(.*?)</span><span class="model">(.*?)'
                           r'</span></div>', page, re.S) + \
            [(v, lab, m) for lab, v, m in re.findall(r'<dt>(.*?)</dt><dd>(.*?)<span class="model">(.*?)</span></dd>',
                                                      page, re.S)]
        for value, label, model in cards:
            label, value = html.unescape(label), html.unescape(value)
            if label not in QUANTITIES or "thesis-pzt" not in model + name and "noise" not in name + model:
                continue
            key = QUANTITIES[label][0]
            want = pzt.shown(key)
            if value == want:
                checked += 1
                continue
            differing += 1
            row = re.search(r"ladder row (\d+); the answer's: ([^(]+) \(ladder row 7\)", html.unescape(model))
            assert row and row.group(2).strip() == want, (name, label, value, model)
            href = re.search(r'href="index\.html#([^"]+)"', model)
            assert href and href.group(1) in anchors and href.group(1).endswith(f"-{row.group(1)}"), (name, model)
        text = html.unescape(re.sub(r"<[^>]+>", " ", page))
        # a page of the design whose text gives another minimum detectable force or saturation says the answer's
        shown = re.findall(r"minimum detectable force ([\d.]+ [uµm]N)|saturates at ([\d.]+ N)", text)
        if name != "index.html" and any(m not in (pzt.shown("min_detectable_force"), pzt.shown("force_range"))
                                        for m in (a or b for a, b in shown)):
            assert "scene is the answer's thesis design of thesis-pzt-front" in text, name
            assert f"minimum detectable force {pzt.shown('min_detectable_force')}" in text
            assert f"saturation {pzt.shown('force_range')}" in text
            note = re.search(r'scene is the answer&#39;s thesis design.*?href="index\.html#([^"]+)"', page, re.S)
            assert note and note.group(1) in anchors, name
    assert differing >= 2 and "noise-budget.html" in pages      # the 2D noise budget's force, the sweep's capacitance
