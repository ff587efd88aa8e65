"""The answer's friction band (taxel.jobs.friction_band, reports.friction_band) and the
rig's probe coefficient (`[probe] friction` of the rig file, studies.bench.rig)."""

import json
import shutil
from pathlib import Path

import pytest

from taxel.studies.bench.rig import RigError, load_rig, parse_rig

DATA = Path(__file__).parent / "data" / "answer"


def _rig(tmp_path, friction) -> Path:
    text = (Path(load_rig.__code__.co_filename).parent / "builtin" / "thesis-bench.toml").read_text()
    text = text.replace('friction = "unknown"', f"friction = {friction}")
    path = tmp_path / "rig.toml"
    path.write_text(text)
    return path


def test_the_rig_file_gives_the_probes_coefficient_or_says_it_is_unknown(tmp_path):
    """The built-in rig has no sourced coefficient (the thesis names neither the probe's material
    nor a measured friction): "unknown". A number >= 0 or a limit is taken; anything else is one
    line naming probe.friction and what it takes."""
    assert load_rig("thesis-bench").probe.friction == "unknown"
    assert load_rig("thesis-bench").probe.coefficient is None
    rig = load_rig(_rig(tmp_path, "0.6"))
    assert rig.probe.friction == 0.6 and rig.probe.coefficient == 0.6
    assert load_rig(_rig(tmp_path, '"sticking"')).probe.coefficient is None
    for bad in ("-0.2", '"tacky"', "true", "nan"):
        with pytest.raises(RigError) as err:
            load_rig(_rig(tmp_path, bad))
        msg = str(err.value)
        assert "\n" not in msg and "probe.friction" in msg and "Coulomb coefficient >= 0" in msg, msg
    data = load_rig("thesis-bench").model_dump()
    assert parse_rig(data, si_numbers=True).probe.friction == "unknown"       # rig.json round trip


@pytest.mark.slow      # four 2D probe presses of the thesis design (two frictionless)
@pytest.mark.parametrize("coefficient", ["unknown", 0.4])
def test_the_answers_friction_band_is_written_and_shown(tmp_path, coefficient):
    """taxel.jobs.friction_band on the main job's PZT front records (tests/data/answer): the
    thesis design's 2D probe press at each law. Its own law (sticking) reproduces the
    probe front's stored 2D press (probe-front.json, the same model: ladder row 5) to 1e-3 (its load path);
    the frictionless press is more sensitive (the silicone squeezed out under the punch
    strains the piezo more; measured +9.8 %), a coefficient from the rig lies between the
    limits, and the report's answer carries the band's table."""
    from taxel.jobs.friction_band import friction_band
    from taxel.reports.build import build
    folder = tmp_path / "thesis-pzt-front"
    shutil.copytree(DATA / "thesis-pzt-front", folder)
    rig = "thesis-bench" if coefficient == "unknown" else _rig(tmp_path, coefficient)
    out = friction_band(folder, workers=1, rig=rig)
    rec = json.loads(out.read_text())
    laws = ["frictionless"] + ([] if coefficient == "unknown" else [coefficient]) + ["sticking"]
    assert rec["laws"] == laws and rec["coefficient"] == coefficient and rec["reference"] == "sticking"
    ref = json.loads((folder / "probe-front.json").read_text())["reference"]
    thesis = next(d for d in rec["designs"] if d["role"] == "thesis")
    s = {leg["friction"]: leg["sensitivity_V_per_N"] for leg in thesis["legs"]}
    x = {leg["friction"]: leg["crosstalk"] for leg in thesis["legs"]}
    assert all(leg["success"] and leg["force_N"] == pytest.approx(1.0, rel=2e-3) for leg in thesis["legs"])
    # the same model; a sticking press depends on its load path, and the stored front's was made
    # before a force step stopped at its target (fem.contact, 2026-11-29): 4.3e-4 apart since
    assert s["sticking"] == pytest.approx(ref["sensitivity 2D press (V/N)"], rel=1e-3)
    assert x["sticking"] == pytest.approx(ref["crosstalk 2D press"], rel=1e-3)
    assert s["frictionless"] > 1.05 * s["sticking"]
    if coefficient != "unknown":
        assert s["frictionless"] > s[coefficient] > 0.999 * s["sticking"]
    assert thesis["sensitivity_spread"] == pytest.approx((max(s.values()) - min(s.values())) / s["sticking"])
    import html
    page = html.unescape(build([folder], tmp_path / "report").read_text(encoding="utf-8"))
    assert "friction band: the probe's unknown friction on the silicone" in page
    assert "ladder row 5" in page and ("mu = 0.4" in page) == (coefficient != "unknown")
