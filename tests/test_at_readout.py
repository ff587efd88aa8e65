"""A scene that names a readout is answered at the readout too (taxel.analyses.solves.at_readout):
`taxel solve`'s outputs and summary carry the readout's V/N, crosstalk, minimum
detectable force and force range beside the open-circuit values, checked against the
circuit's closed form."""

from __future__ import annotations

import numpy as np
import pytest

from taxel import api

C_F, R_F, R_I, C_C = 820e-12, 10e6, 10e3, 100e-12


@pytest.fixture(scope="module")
def solved():
    """The thesis PZT 3x3 row (2D, 1 N on the middle taxel), lossless so that the
    quasi-static source is exactly Q_sc and C_p (no relaxation law)."""
    scene = api.load("thesis-pzt-3x3-2d").replace(**{"dynamics.dielectric_loss": 0.0, "dynamics.piezo_loss": 0.0})
    return scene, api.solve(scene)


def _with(scene, result, **readout):
    from taxel.analyses.solves.at_readout import at_readout
    from taxel.analyses.results import StaticResult
    r = StaticResult(scene.replace(**{f"readout.{k}": v for k, v in readout.items()}), result.solution,
                     {}, result.model_note)
    r.readout = at_readout(r)
    return r


def test_open_circuit_has_no_readout_numbers(solved):
    scene, res = solved
    assert res.at_readout() is None and "readout_sensitivity" not in res.outputs()


def test_taxel_solve_of_a_readout_scene_gives_its_numbers():
    """taxel.analyses.solve attaches the readout's numbers to a scene naming one."""
    scene = api.load("thesis-pzt-3x3-2d").replace(**{"readout.circuit": "charge_amplifier", "mesh.size": "1 mm"})
    res = api.solve(scene)
    assert res.at_readout() is not None and res.outputs()["readout_sensitivity"] > 0


def test_charge_amplifier_matches_its_closed_form(solved):
    scene, res = solved
    r = _with(scene, res, circuit="charge_amplifier")
    a = r.at_readout()
    e = res.electrodes[res.pressed]
    q = abs(e.short_circuit_charge) / abs(res.applied_force)
    cp = abs(e.short_circuit_charge / e.voltage)
    s = 2j * np.pi * a.frequency
    closed = q / C_F * abs(s * R_F * C_F / (1 + s * R_F * C_F)) / abs(1 + s * R_I * (cp + C_C))
    assert a.sensitivity == pytest.approx(closed, rel=1e-6)
    assert a.sensitivity == pytest.approx(q / C_F, rel=0.03)           # the passband gain |Q_sc| / C_f
    assert a.charge_sensitivity == pytest.approx(q, rel=1e-12)
    # identical taxels on identical channels: the readout's crosstalk is the charge ratio
    qs = {k: abs(v.short_circuit_charge) for k, v in res.electrodes.items() if v.state != "reference"}
    assert a.crosstalk == pytest.approx(max(v for k, v in qs.items() if k != res.pressed) / qs[res.pressed], rel=1e-6)
    assert a.force_range == pytest.approx(12.0 / a.sensitivity, rel=1e-9)       # the amplifier's 12 V swing
    out = r.outputs()
    assert out["readout_sensitivity"] == a.sensitivity and out["min_detectable_force"] > 0
    assert abs(out["sensitivity"]) != pytest.approx(a.sensitivity, rel=0.1)      # not the open-circuit V/N
    lines = "\n".join(r.summary())
    assert "at the readout (charge-amplifier output" in lines and "open circuit" in lines
    # written and read back: the same numbers
    from taxel.analyses.results import StaticResult
    back = StaticResult.from_record(r.scene, r.record())
    assert back.at_readout() == a and back.outputs()["readout_sensitivity"] == a.sensitivity


def test_hum_raises_the_minimum_detectable_force(solved):
    scene, res = solved
    quiet = _with(scene, res, circuit="charge_amplifier").at_readout()
    hum = _with(scene, res, circuit="charge_amplifier", hum=["5 mV"]).at_readout()
    # one 50 Hz line of 5 mV peak adds (5 mV)^2 / 2 to the band's variance, through the same gain
    expected = np.sqrt((quiet.min_detectable_force * quiet.sensitivity) ** 2 + 0.005 ** 2 / 2)
    assert hum.min_detectable_force > 10 * quiet.min_detectable_force
    assert hum.min_detectable_force * quiet.sensitivity == pytest.approx(expected, rel=0.05)


def test_a_resistor_above_its_corner_reads_the_open_circuit_voltage(solved):
    scene, res = solved
    a = _with(scene, res, circuit="resistor", R="500 Mohm").at_readout()
    assert a.sensitivity == pytest.approx(abs(res.outputs()["sensitivity"]), rel=1e-3)


@pytest.mark.slow      # two 2D study points through the store (about 8 s)
def test_a_study_of_a_readout_scene_gives_the_readout_columns(tmp_path):
    """A study whose scene names a charge amplifier: results.csv holds the readout's V/N,
    its crosstalk, the minimum detectable force and the force range beside the
    open-circuit sensitivity and crosstalk (two 2D points)."""
    import csv
    (tmp_path / "ca.toml").write_text('''
base = "thesis-pzt-3x3-2d"
outputs = ["voltage", "short_circuit_charge", "crosstalk"]
[overrides]
"readout.circuit" = "charge_amplifier"
[[parameters]]
path = "array.gap"
values = ["2 mm", "4 mm"]
''')
    from taxel.studies.spec import load_study
    summ = api.run_study(load_study(tmp_path / "ca.toml"), tmp_path / "out", workers=1, progress=False)
    rows = list(csv.DictReader(open(summ.folder / "results.csv")))
    assert len(rows) == 2
    for r in rows:
        for col in ("sensitivity", "crosstalk", "readout_sensitivity", "readout_crosstalk", "min_detectable_force",
                    "force_range", "charge_sensitivity"):
            assert float(r[col]) == float(r[col]) and r[col] != "", col
        assert float(r["readout_sensitivity"]) > 2 * abs(float(r["sensitivity"]))    # 820 pF << C_p: a gain
    assert float(rows[1]["readout_crosstalk"]) < float(rows[0]["readout_crosstalk"])  # a wider gap, less


def _readout_scene(tmp_path, circuit='"charge_amplifier"'):
    from taxel.examples import __path__ as ex
    from pathlib import Path
    text = (Path(list(ex)[0]) / "thesis-pzt-3x3-2d.toml").read_text()
    (tmp_path / "ca.toml").write_text(text + f"\n[readout]\ncircuit = {circuit}\n")
    return tmp_path / "ca.toml"


@pytest.mark.slow      # a two-evaluation optimization (about 5 s)
def test_an_optimization_on_a_readout_scene_reports_the_readout(tmp_path):
    """The optimizer's metrics of a base scene naming a charge amplifier hold the
    readout's V/N and crosstalk; a requirement on them is met or missed by those numbers;
    its summary says the readout's numbers beside the open-circuit ones."""
    from taxel.optimize.spec import load_optimization
    _readout_scene(tmp_path)
    (tmp_path / "opt.toml").write_text('''
base = "ca.toml"
reference = {gap = "3 mm"}
[variables]
gap = {path = "array.gap", min = "2 mm", max = "4 mm", start = "3 mm"}
[objective]
maximize = "readout_sensitivity"
[requirements]
readout_crosstalk = "<= 10 %"
[algorithm]
global = "none"
max_evaluations = 2
''')
    prob = load_optimization(tmp_path / "opt.toml")
    m = prob.evaluate(prob.x0)
    assert m["readout_sensitivity"] > 2 * m["sensitivity"] and m["readout_crosstalk"] == pytest.approx(
        m["crosstalk"], rel=1e-3) and m["min_detectable_force"] > 0
    res = api.run_optimization(tmp_path / "opt.toml", tmp_path / "out", workers=1)
    assert any("at the readout" in line for line in res.summary())


def test_a_readout_metric_without_a_readout_is_refused(tmp_path):
    from taxel.optimize.spec import OptimizeError, load_optimization
    (tmp_path / "opt.toml").write_text('''
base = "thesis-pzt-3x3-2d"
[variables]
gap = {path = "array.gap", min = "2 mm", max = "4 mm", start = "3 mm"}
[objective]
maximize = "readout_sensitivity"
''')
    with pytest.raises(OptimizeError, match="needs a readout in the base scene"):
        load_optimization(tmp_path / "opt.toml")


def test_a_scene_adc_clips_and_quantises_by_its_closed_forms(solved):
    """[readout.adc]: a 10-bit ADC on 0-3.3 V (its output biased to the middle) clips at its half
    range, 1.65 V < the amplifier's 12 V, so the force range is 1.65 V / S_r; its quantisation
    adds LSB^2 / 12 (LSB = 3.3 V / 2^10), spread to rate / 2 = the band's top, to the band's
    variance, through the band sensitivity; an enob of 8 adds (3.3 V / 2^8)^2 / 12 instead."""
    from taxel.analyses.solves.noise import quasi_static_noise
    scene, res = solved
    e = res.electrodes[res.pressed]
    force = abs(res.applied_force)
    v, q = e.voltage / force, e.short_circuit_charge / force
    ca = scene.replace(**{"readout.circuit": "charge_amplifier"})
    quiet = quasi_static_noise(ca, v, q)
    for enob, bits in ((None, 10), (8.0, 8)):
        adc = {"bits": 10, "range": ["0 V", "3.3 V"]} | ({} if enob is None else {"enob": enob})
        nr = quasi_static_noise(ca.replace(**{"readout.adc": adc}), v, q)
        f1, f2 = nr.band
        quantisation = (3.3 / 2 ** bits) ** 2 / 12 * (f2 - f1) / f2
        assert nr.variance()["ADC quantisation"] == pytest.approx(quantisation, rel=1e-9)
        assert nr.min_detectable_force == pytest.approx(
            np.sqrt(quiet.min_detectable_force ** 2 + quantisation / nr.band_sensitivity ** 2), rel=1e-9)
        assert nr.saturation_by == "ADC" and nr.saturation_force == pytest.approx(1.65 / nr.gain.max(), rel=1e-12)
    a = _with(scene, res, circuit="charge_amplifier", adc={"bits": 10, "range": ["0 V", "3.3 V"]}).at_readout()
    assert a.force_range == pytest.approx(1.65 / a.sensitivity, rel=1e-9) and a.saturation_by == "ADC"
    # a range wider than the swing: the amplifier clips first
    wide = _with(scene, res, circuit="charge_amplifier", adc={"bits": 16, "range": ["-30 V", "30 V"]}).at_readout()
    assert wide.saturation_by == "amplifier" and wide.force_range == pytest.approx(12.0 / wide.sensitivity, rel=1e-9)


def test_the_assumptions_table_names_a_missing_adc():
    """A readout without [readout.adc] shows "ADC: none" among the assumptions; one naming it does not."""
    from taxel.reports.answer_assumptions import assumptions
    from taxel.schema import to_data
    scene = api.load("thesis-pzt-3x3-2d").replace(**{"readout.circuit": "charge_amplifier"})
    rows = assumptions(to_data(scene))
    assert [r["value"] for r in rows if r["assumed"] == "ADC"] == ["none (an ideal converter)"]
    named = to_data(scene.replace(**{"readout.adc": {"bits": 12, "range": ["0 V", "3.3 V"]}}))
    assert not [r for r in assumptions(named) if r["assumed"] == "ADC"]
    assert [r["value"] for r in assumptions(named) if r["assumed"] == "ADC noise"] == [
        "enob = bits (an ideal quantiser), rate = twice the band's top"]
    full = to_data(scene.replace(**{"readout.adc": {"bits": 12, "range": ["0 V", "3.3 V"], "enob": 11, "rate": "1 kHz"}}))
    assert not [r for r in assumptions(full) if r["assumed"].startswith("ADC")]
