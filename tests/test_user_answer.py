"""A user's own optimization, as a new user runs it: a 4x4 PVDF array in their own silicone,
with their charge amplifier, their requirements, a front. Its report speaks of their design:
no "thesis", no "3x3", a requirements table, and an assumptions table that names the piezo's
loss factor (the values no input file gave)."""

from __future__ import annotations

import re

import pytest

SKIN = """description = "my fingertip skin: 4x4 PVDF in my silicone"
[model]
type = "plane_strain"
[mesh]
size = "0.8 mm"
piezo_size = "0.2 mm"
order = 2
[array]
rows = 4
cols = 4
taxel_width = "3 mm"
piezo = "PVDF"
piezo_thickness = "28 um"
gap = "2 mm"
margin = "2 mm"
silicone = "gel"
silicone_above = "0.8 mm"
silicone_below = "0.6 mm"
[materials.gel]
kind = "solid"
C10 = "20 kPa"
C20 = "0.3 kPa"
C30 = "0 Pa"
K = "40 MPa"
rho = "1050 kg/m^3"
[load]
kind = "taxel"
taxel = [1, 1]
force = "0.5 N"
[supports]
bottom = "bonded"
[readout]
circuit = "charge_amplifier"
C_f = "330 pF"
R_f = "100 Mohm"
"""

OPT = """name = "my-skin"
base = "skin.toml"
reference = {silicone_above = "0.8 mm", gap = "2 mm"}
[variables]
silicone_above = {path = "array.silicone_above", min = "0.3 mm", max = "1.5 mm", start = "0.8 mm"}
gap = {path = "array.gap", min = "1 mm", max = "4 mm", start = "2 mm"}
[objective]
maximize = "sensitivity"
[pareto]
points = 3
[requirements]
pitch = "<= 6 mm"
crosstalk = "<= 12 %"
[algorithm]
global = "none"
max_evaluations = 4
"""


def _text(page: str) -> str:
    import html
    page = re.sub(r"<(script|style)\b.*?</\1>", "", page, flags=re.S)
    page = re.sub(r'src="data:[^"]*"', "", page)
    return html.unescape(re.sub(r"<[^>]+>", " ", page))


@pytest.mark.slow        # about a minute on 2 cores: a 3-point front of a 4x4 2D row and its report
def test_a_users_optimization_report_speaks_of_their_design(tmp_path):
    from taxel import api
    (tmp_path / "skin.toml").write_text(SKIN)
    (tmp_path / "opt.toml").write_text(OPT)
    result = api.run_optimization(tmp_path / "opt.toml", tmp_path / "o", workers=1)
    assert any(line.startswith("requirements") for line in result.summary())
    index = api.report([tmp_path / "o"], tmp_path / "r", compare=False)
    pages = {p.name: _text(p.read_text(encoding="utf-8")) for p in index.parent.glob("*.html")}
    assert len(pages) >= 2
    for name, text in pages.items():
        for word in ("thesis", "3x3", "3 x 3"):
            hits = [m.start() for m in re.finditer(word, text, re.I)]
            assert not hits, (name, word, [" ".join(text[max(0, i - 80):i + 80].split()) for i in hits[:3]])
    page = pages["o.html"]
    assert "requirements" in page and "pitch ≤ 6 mm" in page
    assert "assumptions" in page and "PVDF mechanical loss factor" in page
    assert "converged" not in page or "evaluation budget used" in page
