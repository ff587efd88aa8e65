"""Dimensionless quantities (fractions, loss factors, gains) read the same in all
four schemas: "1 %", "0.01", 0.01 and "1 percent" are one value; anything with a
dimension, out of range, or not finite is refused naming the key."""

from __future__ import annotations

import tomllib

import pytest

from taxel.optimize.spec import OptimizeError, load_optimization
from taxel.scene import SceneError, parse
from taxel.studies.bench.rig import RigError, load_rig, parse_rig
from taxel.studies.spec import StudyError, load_study

SPELLINGS = [("1 %", 0.01), ("0.01", 0.01), (0.01, 0.01), ("1 percent", 0.01), ("10000 ppm", 0.01),
             ("1e-2", 0.01), ("10 mm/m", 0.01)]


@pytest.mark.parametrize("text, value", SPELLINGS)
@pytest.mark.parametrize("key", ["model.tolerance", "analysis.tolerance", "dynamics.silicone_loss",
                                 "dynamics.piezo_loss", "dynamics.dielectric_loss"])
def test_every_scene_fraction_reads_percent_and_plain_numbers(key, text, value):
    table, leaf = key.split(".")
    scene = parse({"array": {}, table: {leaf: text}})
    assert getattr(getattr(scene, table), leaf) == pytest.approx(value, rel=1e-12)


@pytest.mark.parametrize("bad, words", [("1 mm", "fraction"), ("150 %", "below"), ("-1 %", "above"),
                                        ("inf", "finite"), (True, "fraction"), ([1], "fraction")])
def test_a_bad_fraction_is_refused_naming_the_key(bad, words):
    with pytest.raises(SceneError) as err:
        parse({"array": {}, "model": {"tolerance": bad}})
    assert "model.tolerance" in str(err.value) and words in str(err.value)


def test_a_scene_round_trips_its_fractions():
    scene = parse({"array": {}, "model": {"tolerance": "3 %"}, "dynamics": {"piezo_loss": "0.5 %"}})
    again = scene.replace(**{"load.force": "2 N"})
    assert again.model.tolerance == pytest.approx(0.03) and again.dynamics.piezo_loss == pytest.approx(0.005)


def test_a_study_override_reads_a_percent(tmp_path):
    f = tmp_path / "st.toml"
    f.write_text('base = "thesis-pzt-single-2d"\n[overrides]\n"model.tolerance" = "1 %"\n'
                 '[[parameters]]\npath = "dynamics.silicone_loss"\nvalues = ["5 %", 0.1, "0.2"]\n')
    st = load_study(f)
    losses = [parse(st.scene_data(p)).dynamics.silicone_loss for p in st.points()]
    assert losses == pytest.approx([0.05, 0.1, 0.2])
    assert parse(st.scene_data(st.points()[0])).model.tolerance == pytest.approx(0.01)
    f.write_text(f.read_text().replace('"1 %"', '"1 N"'))
    with pytest.raises(StudyError, match="model.tolerance"):
        load_study(f)


OPT = ('base = "thesis-pzt-3x3-2d"\n[variables]\ngap = {path = "array.gap", min = "1 mm", max = "5 mm"}\n'
       '[objective]\nmaximize = "sensitivity"\n[requirements]\ncrosstalk = "<= CON"\n'
       '[algorithm]\nmax_evaluations = 4\nglobal = "none"\nxtol = XTOL\n')


@pytest.mark.parametrize("xtol, con", [('"2 %"', "5 %"), ('"0.02"', "0.05"), ("0.02", "0.05")])
def test_an_optimization_reads_xtol_and_ratio_bounds_as_percent_or_number(tmp_path, xtol, con):
    f = tmp_path / "op.toml"
    f.write_text(OPT.replace("XTOL", xtol).replace("CON", con))
    p = load_optimization(f)
    assert p.spec.algorithm.xtol == pytest.approx(0.02)
    assert p.constraints == [("crosstalk", "<=", pytest.approx(0.05))]
    f.write_text(OPT.replace("XTOL", '"2 Hz"').replace("CON", con))
    with pytest.raises(OptimizeError, match="xtol"):
        load_optimization(f)


@pytest.mark.parametrize("gain, value", [("10", 10.0), (10, 10.0), ("1000 %", 10.0), ("10 V/V", 10.0)])
def test_a_rig_gain_reads_as_a_ratio(gain, value):
    from taxel.studies.bench.rig import BUILTIN
    data = tomllib.loads((BUILTIN / "thesis-bench.toml").read_text())
    data["channels"][0]["gain"] = gain
    assert parse_rig(data).channels[0].gain == pytest.approx(value)
    data["channels"][0]["gain"] = "10 mV"
    with pytest.raises(RigError, match="gain"):
        parse_rig(data)
    assert load_rig(BUILTIN / "thesis-bench.toml").channels
