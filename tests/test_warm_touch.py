"""A warm finger on a scene (taxel.analyses.solves.warm_touch): its numbers, and the readout's
output against the charge amplifier's slow-signal closed form.

Below its lower corner (1 / (2 pi R_f C_f) = 19.4 Hz) the bench's charge amplifier
outputs -R_f dQ/dt; a thin film's pyroelectric charge is -p3 A dT_film (fem.thermal),
so the touch's peak is R_f |p3| A max|dT_film/dt|, with the film's mean temperature from
the same conduction. The press of F held (ramped over `rise`) peaks at
(|Q_sc| F / C_f) (tau / rise) (1 - exp(-rise / tau)), tau = R_f C_f. These are closed
forms of the circuit, checked against the time-domain readout (a consistency test of
the chain; the conduction itself is checked against closed forms in test_thermal.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import taxel
from taxel.analyses.solves.warm_touch import warm_touch
from taxel.fem import constitution
from taxel.scene import SceneError


@pytest.fixture(scope="module")
def solved():
    """A scene with a [warm_touch] table, solved: the static result carries the warm touch."""
    scene = taxel.load("thesis-pvdf-single-2d").replace(**{"readout.circuit": "charge_amplifier",
                                                           "warm_touch.finger": "34 degC"})
    return taxel.solve(scene)


@pytest.fixture(scope="module")
def pvdf(solved):
    return solved.warm_touch


def test_a_scene_with_a_warm_touch_solves_it_beside_the_press(solved):
    """`taxel.solve` of a scene with [warm_touch]: its outputs and summary carry the false
    force, and its record (result.json) reads back with them."""
    import json
    from taxel.analyses import StaticResult
    assert solved.outputs()["warm_touch_force"] == pytest.approx(solved.warm_touch.false_force)
    assert any("false force" in line for line in solved.summary())
    back = StaticResult.from_record(solved.scene, json.loads(json.dumps(solved.record())))
    assert back.outputs()["warm_touch_force"] == pytest.approx(solved.warm_touch.false_force)
    assert back.outputs()["warm_touch_ratio"] == pytest.approx(solved.warm_touch.ratio)


def test_thesis_pvdf_warm_touch_numbers(pvdf):
    """The thesis PVDF taxel (2D, 1 mm silicone above), a 34 C finger held 1 s on a 23 C skin
    through 1000 W/(m^2 K): the film warms 1.28 K in 3 s, at most 0.98 K/s; the bench's
    charge amplifier makes it a false press of 10.9 mN (mesh and step converged within
    0.1 %, benchmarks/warm_touch.py), 1256 times the chain's minimum detectable force."""
    s = pvdf.summary()
    assert s["film_rise_K"] == pytest.approx(1.276, rel=0.02)
    assert s["film_max_rate_K_per_s"] == pytest.approx(0.978, rel=0.02)
    assert s["false_force_N"] == pytest.approx(10.9e-3, rel=0.03)
    assert s["ratio"] > 100


def test_touch_and_press_peaks_against_the_amplifier_closed_form(pvdf):
    r, sc = pvdf, pvdf.scene
    p, ro, a = r.pressed, sc.readout, sc.array
    area = a.taxel_width * a.taxel_width          # the 2D model's depth is the taxel's width
    rate = np.abs(np.gradient(r.film_temperature[p], r.t)).max()
    touch = ro.R_f * abs(constitution.get("PVDF").pyro) * area * rate
    assert np.abs(r.touch[p]).max() == pytest.approx(touch, rel=0.02)
    tau, rise = ro.R_f * ro.C_f, sc.analysis.rise
    q = abs(np.interp(0.5, r.t, r.press[p]))      # the held press's output has decayed: ~0
    assert q < 1e-6 * np.abs(r.press[p]).max()
    from taxel.analyses import solve_static
    st = solve_static(sc)
    qn = abs(st.electrodes[p].short_circuit_charge / st.applied_force)
    press = qn * r.force / ro.C_f * (tau / rise) * (1 - math.exp(-rise / tau))
    assert np.abs(r.press[p]).max() == pytest.approx(press, rel=0.01)
    # heating PVDF (p3 < 0) charges its top electrode like a release (d33 < 0): opposite to the press's onset
    k_on = int(np.argmax(np.abs(r.press[p][r.t < 0.5])))
    k_touch = int(np.argmax(np.abs(r.touch[p])))
    assert np.sign(r.press[p][k_on]) == -np.sign(r.touch[p][k_touch])


def test_a_user_silicone_needs_its_heat():
    """A user silicone without conductivity and specific heat: one line naming them; with
    them (in units) the warm touch runs on them."""
    base = taxel.load("thesis-pvdf-single-2d")
    soft = {"kind": "solid", "E": "30 kPa", "nu": 0.45, "rho": "1070 kg/m^3"}
    bare = base.replace(**{"array.silicone": "soft", "materials.soft": soft})
    with pytest.raises(SceneError, match="materials.soft: no thermal properties.*conductivity"):
        warm_touch(bare)
    from taxel.analyses.solves.warm_touch import thermal_model
    warm = bare.replace(**{"materials.soft.conductivity": "0.3 W/(m*K)", "materials.soft.specific_heat": "1.2 kJ/(kg*K)"})
    model, tm = thermal_model(warm)
    sil = tm.regions["silicone"]
    assert model.volume_load(sil).sum() > 0
    assert constitution.from_record("soft", {**soft, "E": 3e4, "rho": 1070, "conductivity": 0.3}).conductivity == 0.3


def test_the_requirement_reads_and_judges_the_warm_touch(pvdf):
    """warm_touch_force and warm_touch_ratio are optimizer metrics: a [requirements] table
    names them in its grammar, and the design's metrics (optimize.warm) are the analysis's."""
    from taxel.optimize import requirements
    from taxel.optimize.warm import warm_metrics
    reqs = requirements.read({"warm_touch_ratio": "<= 100 %", "warm_touch_force": "<= 5 mN"})
    assert [(r.metric, r.op, r.bound) for r in reqs] == [("warm_touch_ratio", "<=", 1.0), ("warm_touch_force", "<=", 5e-3)]
    with pytest.raises(requirements.RequirementError):
        requirements.read({"warm_touch_force": "<= 5 K"})
    m = warm_metrics(pvdf.scene)
    assert m["warm_touch_force"] == pytest.approx(pvdf.false_force, rel=1e-9)
    assert m["warm_touch_ratio"] == pytest.approx(pvdf.ratio, rel=1e-9)


def test_the_report_section_reads_the_record(pvdf, tmp_path):
    """The record a warm touch writes is the report section's: its table and its figure."""
    from taxel.reports import warm_touch as section
    pvdf.write(tmp_path)
    b = section.block(tmp_path)
    assert dict(b["rows"])["false force"].endswith("N") and len(b["png"]) > 10_000
    assert section.block(tmp_path / "none") is None and list(tmp_path.iterdir()) == [tmp_path / "warm-touch.json"]



def test_the_warm_pages_read_in_plain_language(pvdf, tmp_path):
    """The warm touch's page section and its answer row show no code identifier and no number
    past 4 significant figures (reports.plain, the report tests' rule): the model by its name."""
    from taxel.reports import warm_touch as section
    from taxel.reports.page import templates
    from taxel.reports.plain import problems
    pvdf.write(tmp_path)
    row = section.answer_row(tmp_path)
    assert row["rows"][0][3].endswith("mN") and "fakes a press" in row["note"]
    html = templates().get_template("page.html").render(title="warm", kind="analysis", folder="warm",
                                                         banners=[], headline=[], sections=[section.section(tmp_path)])
    text = html + "<p>" + " ".join(row["cols"] + row["rows"][0] + [row["caption"], row["note"]]) + "</p>"
    assert "2D plane strain model" in html and not problems(text), problems(text)


@pytest.mark.slow      # a static solve and a conduction on a busy machine: 3-12 s
def test_the_main_jobs_warm_touch_on_the_bench(tmp_path):
    """The main job's warm touch of an optimization folder (taxel.jobs.warm_touch): the thesis
    PVDF design through the bench's charge amplifier and notch, the minimum detectable force
    on the bench's converter with the rig's hum (as the answer's): 11.2 mN false against 4.17 mN
    detectable (docs/benchmarks.md)."""
    from taxel.jobs.warm_touch import warm_touch as job
    from taxel.reports import warm_touch as section
    folder = tmp_path / "thesis-pvdf-front"
    folder.mkdir()
    job(folder)
    rec = section.record(folder)
    assert rec["false_force_N"] == pytest.approx(11.2e-3, rel=0.03)
    assert rec["min_detectable_force_N"] == pytest.approx(4.17e-3, rel=0.05)
    assert rec["ratio"] == pytest.approx(2.69, rel=0.05)
    assert rec["scene"] == "thesis-pvdf-single-2d" and "notch" in rec["readout"]


def test_the_sensitivity_drift_is_the_datasheets_or_says_it_has_none():
    """PSI-5H4E's permittivity coefficient (PI Ceramic's PIC153, 5e-3/K) moves the capacitance
    by 5e-3 x (0 - 23) = -11.5 % at 0 C and +13.5 % at 50 C about a 23 C skin; no sheet gives
    a d coefficient (PZT) nor any (PVDF): "no drift data", never a zero. A user piezo's
    coefficients (in units) give the charge's and the open-circuit volts' drift."""
    from taxel.analyses.solves.warm_touch import drift, drift_words
    pzt = drift(constitution.get("PSI-5H4E"), 296.15)
    assert pzt["capacitance"] == pytest.approx([-0.115, 0.135]) and pzt["charge_sensitivity"] is None
    assert "PIC153" in pzt["source"]
    words = drift_words(pzt, "charge-amplifier output")
    assert words.startswith("no drift data") and "-11.5 % at 0 °C, +13.5 % at 50 °C" in words
    pvdf = drift(constitution.get("PVDF"), 296.15)
    assert pvdf["capacitance"] is None and drift_words(pvdf, "open-circuit voltage") == \
        "no drift data (no temperature coefficient of the d constants found)"
    base = taxel.load("thesis-pvdf-single-2d")
    s, d, eps_T = constitution.get("PVDF").strain_charge()
    user = {"kind": "piezo", "s": s.tolist(), "d": d.tolist(), "eps_T": (eps_T / constitution.EPS0).tolist(),
            "rho": 1780, "permittivity_tc": "0.2 %/K", "d_tc": "-0.1 %/K"}
    from taxel.analyses.model.problem import check
    mat = check(base.replace(**{"array.piezo": "film", "materials.film": user}))["film"]
    r = drift(mat, 296.15)
    assert r["charge_sensitivity"] == pytest.approx([0.023, -0.027])
    assert r["open_circuit_sensitivity"][1] == pytest.approx(0.973 / 1.054 - 1)
