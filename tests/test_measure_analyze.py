"""`taxel measure analyze` and `localize` on the simulated rig, against its known truth.

Noise: the simulator's defaults (1 mV white at the ADC, 5 / 1.5 / 0.5 mV hum at
50 / 150 / 250 Hz, 5 mN load-cell noise, 16-bit ADC over +-10 V, 10 % gain and
30 % time-constant spread, 20 mV rms baseline drift) unless a test says otherwise.
The drift is a low-passed random walk whose power sits at the time scales of a
seconds-long time constant: at 20 mV one 2 N step (0.3 V) pins a 1.7-3.1 s tau to
about 7-12 % at best (studies.measured.step gives the bound), so the step tests check
the drift-robust fit's interval there, and the 2 % target on a quiet bench (0.5 mV)."""

import json

import numpy as np
import pytest
from scipy import signal

import taxel
from taxel.cli import main
from taxel.studies.measured import events, frf, peaks
from taxel.studies.measured.analysis import analyze_folder
from taxel.studies.bench.importers import import_file
from taxel.studies.measured.localize import largest_taxel
from taxel.studies.bench.protocol import encode_frames
from taxel.studies.bench.rig import load_rig, parse_rig
from taxel.studies.bench.signals import Settings, conditioning_tf, save_truth, simulate

SCENE = "thesis-pzt-3x3-2d"


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    """One crosstalk cache for the module (three static FEM solves, once)."""
    import os
    d = tmp_path_factory.mktemp("cache")
    old = os.environ.get("XDG_CACHE_HOME")
    os.environ["XDG_CACHE_HOME"] = str(d)
    yield d
    if old is None:
        os.environ.pop("XDG_CACHE_HOME")
    else:
        os.environ["XDG_CACHE_HOME"] = old


def measure(tmp_path, rig, settings, name="m", scene=SCENE):
    """Simulate, encode as the serial stream, import into a measurement folder; (folder, truth)."""
    truth = simulate(rig, taxel.load(scene), settings)
    stream = tmp_path / f"{name}.bin"
    stream.write_bytes(b"".join(encode_frames(truth.frames, rig.port.protocol)))
    save_truth(truth, tmp_path / f"{name}.truth")
    import_file(stream, rig, tmp_path / name)
    return tmp_path / name, truth


def resistor_rig(tau: float):
    """The thesis bench with a resistor across each taxel giving time constant tau with the lumped C_p."""
    from taxel.analyses import lumped_model
    C_p = lumped_model(taxel.load(SCENE)).C_p
    d = load_rig("thesis-bench").model_dump()
    d["conditioning"] = {"circuit": "resistor", "R": f"{float(tau / C_p)!r} ohm", "notch": True}
    return parse_rig(d, si_numbers=True), tau / C_p


@pytest.mark.parametrize("tau", [1.7, 3.1])
def test_step_time_constant_within_its_interval_at_the_default_drift(tmp_path, tau):
    rig, R = resistor_rig(tau)
    folder, truth = measure(tmp_path, rig, Settings(input="step", seconds=12, amplitude=2.0, tau_spread=0.0,
                                                    crosstalk=False, seed=int(tau * 10)))
    assert truth.params["taxels"]["taxel_1_1"]["tau_s"] == pytest.approx(tau)
    assert truth.params["settings"]["drift_V"] == 20e-3
    assert main(["measure", "analyze", str(folder), "--scene", SCENE]) == 0
    rec = json.loads((folder / "analysis.json").read_text())
    assert rec["kind"] == "step"
    fit = {s["taxel"]: s for s in rec["step"]}["taxel_1_1"]
    lo, hi = fit["tau_ci95_s"]
    assert lo < tau < hi and 0.05 < (hi - lo) / 2 / tau < 0.4      # honest: several % wide at 20 mV
    assert fit["tau_s"] == pytest.approx(tau, rel=0.2)
    assert fit["R_eff_ohm"] == pytest.approx(fit["tau_s"] / truth.params["C_p_F"], rel=1e-9)
    assert fit["noise_model"] == "drift" and fit["drift_V_per_sqrt_s"] > 1e-3


@pytest.mark.parametrize("tau", [1.7, 3.1])
def test_step_recovers_the_time_constant_within_2_percent_on_a_quiet_bench(tmp_path, tau):
    rig, R = resistor_rig(tau)
    folder, truth = measure(tmp_path, rig, Settings(input="step", seconds=12, amplitude=2.0, tau_spread=0.0,
                                                    drift_V=0.5e-3, crosstalk=False, seed=int(tau * 10)))
    a = analyze_folder(folder, taxel.load(SCENE), SCENE)
    fit = {s.taxel: s for s in a.steps}["taxel_1_1"]
    assert fit.tau_s == pytest.approx(tau, rel=0.02)
    assert fit.tau_ci95_s[0] < tau < fit.tau_ci95_s[1] and (fit.tau_ci95_s[1] - fit.tau_ci95_s[0]) / tau < 0.05
    assert fit.R_eff_ohm == pytest.approx(R, rel=0.02)


@pytest.mark.slow      # 12 s of CPU: fits over many seeds
def test_step_interval_covers_the_truth_over_seeds_where_the_white_fit_does_not():
    """16 seeded steps at the default 20 mV drift: the drift-robust 95 % interval contains
    the drawn tau in at least 13 (the white-residual fit's in at most 4)."""
    rig, _ = resistor_rig(1.7)
    scene = taxel.load(SCENE)
    hits = {"drift": 0, "white": 0}
    for seed in range(16):
        tr = simulate(rig, scene, Settings(input="step", seconds=12, amplitude=2.0, tau_spread=0.0,
                                           crosstalk=False, seed=100 + seed))
        v = rig.counts_to_volts(tr.frames.counts.astype(float)) / rig.volts_per_si()[None]
        rec = events.Record(tr.t, v[:, 9], v[:, :9], rig.names[:9], [c.taxel for c in rig.ordered()[:9]],
                            rig.sampling.rate)
        for kind in hits:
            f = peaks.fit_step(rec, 4, rig.chains()["taxel_1_1"], truth_C_p(), noise=kind)
            hits[kind] += f.tau_ci95_s[0] <= 1.7 <= f.tau_ci95_s[1]
    assert hits["drift"] >= 13 and hits["white"] <= 4, hits


def truth_C_p():
    from taxel.analyses import lumped_model
    return lumped_model(taxel.load(SCENE)).C_p


def test_linearity_sensitivity_within_1_percent(tmp_path, cache):
    rig = load_rig("thesis-bench")
    folder, truth = measure(tmp_path, rig, Settings(input="presses", seconds=60, seed=5))
    a = analyze_folder(folder)
    assert a.kind == "presses" and len(a.linearity) >= 6
    # the truth: the same peaks on the simulator's clean signals (no noise, hum, drift, quantisation)
    clean = events.Record(truth.t, truth.force, truth.clean_volts[:, :9], rig.names[:9],
                          [c.taxel for c in rig.ordered()[:9]], rig.sampling.rate)
    exact = {x.taxel: x for x in peaks.linearity(clean, events.segments(clean))}
    for x in a.linearity:
        assert x.sensitivity_V_per_N == pytest.approx(exact[x.taxel].sensitivity_V_per_N, rel=0.01)
        assert abs(exact[x.taxel].r) > 0.99999 and 0.999 < abs(x.r) <= 1.0
        assert len(x.residuals_V) == x.n >= 3
    assert sum(x.n for x in a.linearity) >= 80


def test_repeatability_both_definitions_on_a_known_spread(tmp_path):
    rig = load_rig("thesis-bench")
    folder, truth = measure(tmp_path, rig, Settings(input="impulse", seconds=20, amplitude_spread=0.03,
                                                    crosstalk=False, seed=2))
    a = analyze_folder(folder)
    assert a.kind == "impulse"
    (r,) = a.repeatability
    assert r.taxel == "taxel_1_1" and r.n == 10
    clean = events.Record(truth.t, truth.force, truth.clean_volts[:, :9], rig.names[:9],
                          [c.taxel for c in rig.ordered()[:9]], rig.sampling.rate)
    (e,) = peaks.repeatability(clean, events.segments(clean))
    # the known spread: 3 % rms on the impulse forces, so about 97 % by the spread definition
    forces = np.array([p["force_N"] for p in truth.params["presses"]])
    assert 100 * (1 - forces.std(ddof=1) / forces.mean()) == pytest.approx(e.by_spread_pct, abs=0.3)
    assert r.by_spread_pct == pytest.approx(e.by_spread_pct, abs=0.3)
    assert r.by_range_pct == pytest.approx(e.by_range_pct, abs=1.0)
    assert r.by_range_pct < r.by_spread_pct < 100


def _exact_frf(truth, rig, C_p, name, freqs):
    """The simulator's own discrete chain (bilinear) and notch for one taxel, per newton."""
    p = truth.params["taxels"][name]
    cond = rig.chains()[name]
    num, den, _ = conditioning_tf(cond, C_p, p["tau_factor"])
    b, a = signal.bilinear(num, den, fs=rig.sampling.rate)
    _, Hc = signal.freqz(b, a, worN=freqs, fs=rig.sampling.rate)
    lo, hi = cond.notch_frequency - cond.notch_bandwidth / 2, cond.notch_frequency + cond.notch_bandwidth / 2
    sos = signal.iirfilter(1, [lo, hi], btype="bandstop", ftype="butter", fs=rig.sampling.rate, output="sos")
    _, Hn = signal.sosfreqz(sos, worN=freqs, fs=rig.sampling.rate)
    return truth.params["q_per_N_C"] * p["gain_factor"] * Hc * Hn


def test_h1_matches_the_exact_frf_within_1_percent(tmp_path):
    rig = load_rig("thesis-bench")
    folder, truth = measure(tmp_path, rig, Settings(input="chirp", seconds=10, crosstalk=False, seed=1))
    a = analyze_folder(folder, taxel.load(SCENE), SCENE)
    F = a.frf
    assert a.kind == "chirp" and F.taxel == "taxel_1_1"
    H = _exact_frf(truth, rig, truth.params["C_p_F"], "taxel_1_1", F.freqs)
    good = F.coherence > 0.95
    # Welch on an 8 s sweep (12.5 Hz/s, so 12.5 Hz per 1 s segment) is biased where the chain's
    # memory is long against a segment: within 15 Hz of the notch (ringing 30 ms; 3-13 % per bin),
    # below 10 Hz (the chirp's large mean force leaks through the window's side lobes into bins
    # where the charge amplifier passes nothing: to 18 % at 5 Hz), and by 1-3 % in single bins
    # elsewhere (measured on this record: RMS 0.5-0.8 %, worst bin 3.2 %). Checked over 10-90 Hz
    # outside 35-65 Hz: the RMS relative error below 1 %, every bin below 3.5 %.
    band = good & (F.freqs >= 10) & (F.freqs <= 90) & (np.abs(F.freqs - 50) >= 15)
    assert band.sum() >= 45
    e = np.abs(F.H1[band] / H[band] - 1)
    assert np.sqrt(np.mean(e ** 2)) < 0.01 and e.max() < 0.035
    # the thesis's amplitude-spectrum ratio, on the same band, for comparison
    r = np.abs(F.ratio[band] / np.abs(H[band]) - 1)
    assert np.median(r) < 0.02
    # the lumped model misses only the taxel's gain spread (and the bilinear discretisation)
    err = frf.rms_error(F, "lumped")
    g = truth.params["taxels"]["taxel_1_1"]["gain_factor"]
    assert err["rms_error_pct"] == pytest.approx(100 * abs(1 / g - 1), abs=1.5)
    a.write()
    rec = json.loads((folder / "analysis.json").read_text())
    assert rec["frf"]["models"]["lumped"]["rms_error_pct"] == pytest.approx(err["rms_error_pct"])
    assert (folder / "analysis-frf.csv").read_text().startswith("f_Hz,H1_abs_V_per_N")


def _record(folder):
    from taxel.studies.bench.folder import read
    return events.record(read(folder))


@pytest.mark.slow      # 3.3 s of CPU; localization stays in the fast tier (test_measure_api)
def test_largest_taxel_localization_degrades_with_noise(tmp_path, cache):
    rig = load_rig("thesis-bench")
    rates = []
    for noise in (1e-3, 0.1, 0.3):
        folder, truth = measure(tmp_path, rig, Settings(input="presses", seconds=30, noise_V=noise, seed=7),
                                name=f"n{noise}")
        presses = [(p["t"], tuple(truth.params["positions"][p["position"]])) for p in truth.params["presses"]]
        loc = largest_taxel(_record(folder), presses)
        assert loc.missed == 0 and loc.matched == len(presses) >= 40
        rates.append(loc.correct_rate)
    assert rates[0] == 1.0
    assert rates[0] >= rates[1] >= rates[2] and rates[2] < 0.95
    # the CLI on the simulator's truth.json
    assert main(["measure", "localize", str(tmp_path / "n0.001"), "--presses",
                 str(tmp_path / "n0.001.truth" / "truth.json")]) == 0
    rec = json.loads((tmp_path / "n0.001" / "localization.json").read_text())
    assert rec["correct_rate"] == 1.0 and np.trace(rec["confusion"]) == rec["matched"]


def _no_force_rig():
    d = load_rig("thesis-bench").model_dump()
    d["channels"] = [c for c in d["channels"] if c["name"] != "force"]
    return parse_rig(d, si_numbers=True)


def test_bad_input_one_line_exit_2_nothing_written(tmp_path, capsys):
    rig = load_rig("thesis-bench")
    folder, truth = measure(tmp_path, rig, Settings(input="chirp", seconds=4, crosstalk=False))
    # a chirp too short for the requested resolution
    assert main(["measure", "analyze", str(folder), "--input", "chirp", "--resolution", "0.5"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "too short for 0.5 Hz resolution" in err and "--resolution" in err
    # a scene whose array does not match the rig's channels
    assert main(["measure", "analyze", str(folder), "--scene", "thesis-pzt-single-2d"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "taxel_0_1" in err and "array.rows x array.cols" in err
    # a folder with no force channel
    nf = _no_force_rig()
    t = simulate(nf, taxel.load(SCENE), Settings(input="step", seconds=1, crosstalk=False))
    (tmp_path / "nf.bin").write_bytes(b"".join(encode_frames(t.frames, nf.port.protocol)))
    import_file(tmp_path / "nf.bin", nf, tmp_path / "nf")
    assert main(["measure", "analyze", str(tmp_path / "nf")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "no force channel" in err
    for f in (folder, tmp_path / "nf"):
        assert not list(f.glob("analysis*"))


def test_calibration_recovers_gain_and_time_constant_cross_validated(tmp_path):
    rig = load_rig("thesis-bench")
    folder, truth = measure(tmp_path, rig, Settings(input="chirp", seconds=10, crosstalk=False, seed=4))
    step, _ = measure(tmp_path, rig, Settings(input="step", seconds=2, crosstalk=False, seed=4), name="step")
    assert main(["measure", "calibrate", str(folder), "--scene", SCENE, "--step", str(step)]) == 0
    cal = json.loads((folder / "calibration.json").read_text())
    p = truth.params["taxels"]["taxel_1_1"]
    assert cal["taxel"] == "taxel_1_1"
    assert cal["gain"] == pytest.approx(p["gain_factor"], rel=0.01)
    assert cal["tau_scale"] == pytest.approx(p["tau_factor"], rel=0.05)
    assert cal["tau_s"] == pytest.approx(p["tau_s"], rel=0.05)
    # the same seed gives the same taxel factors; this step keeps the default 20 mV drift (5 % off here)
    assert cal["step_tau_s"] == pytest.approx(p["tau_s"], rel=0.10)
    assert cal["validation_band_Hz"][0] > cal["fit_band_Hz"][1]
    # the validation half (about 70-97 Hz) holds the chirp's end, where H1 is biased by 1-3 %
    assert cal["rms_after_pct"] < 5.0 and cal["rms_after_pct"] < cal["rms_before_pct"] / 2
    scene = taxel.load(str(folder / "calibrated-scene.toml"))
    assert scene.readout.circuit == "charge_amplifier" and scene.readout.notch
    assert scene.readout.R_f == pytest.approx(10e6 * cal["tau_scale"], rel=1e-9)
    assert scene.array.rows == 3 and scene.model.type == taxel.load(SCENE).model.type
    assert main(["solve", str(folder / "calibrated-scene.toml"), "--json"]) == 0        # taxel solve reads it


@pytest.mark.slow      # 6.5 s of CPU: model-based localization over many presses
def test_model_based_position_error_below_half_a_millimetre(tmp_path, cache):
    """At the simulator's default noise (the level assumed for the thesis bench: 1 mV white,
    5 mV hum, 20 mV drift, 5 mN on the load cell), presses on the taxels."""
    rig = load_rig("thesis-bench")
    folder, truth = measure(tmp_path, rig, Settings(input="presses", seconds=60, seed=11))
    assert main(["measure", "localize", str(folder), "--presses", str(tmp_path / "m.truth" / "truth.json"),
                 "--scene", SCENE]) == 0
    rec = json.loads((folder / "localization.json").read_text())
    mb = rec["model_based"]
    assert mb["presses"] >= 35
    assert mb["position_error_mm"]["rms"] < 0.5
    assert mb["force_error_pct"]["rms"] < 5.0
    assert rec["correct_rate"] == 1.0
    # the design-time prediction (Cramer-Rao, white noise only) at the taxel centres, for the median
    # sensitivity and press force of this record, against the estimator's measured error
    from taxel.analyses.surface.influence import influence
    from taxel.analyses.surface.localization import accuracy_map
    infl = influence(taxel.load(SCENE))
    S = float(np.median(np.abs(list(mb["sensitivity_V_per_N"].values()))))
    F = float(np.median([p["force_N"] for p in truth.params["presses"]]))
    from taxel.studies.measured.localize import reading_noise
    amap = accuracy_map(infl, 3, 3, S, reading_noise(1e-3, 2000.0), F)      # 1 mV per sample, 9 samples read
    predicted = float(np.sqrt(np.mean(amap.at_taxels(1e3 * infl.pitch) ** 2)))
    assert 0.7 < mb["position_error_mm"]["rms"] / predicted < 3.0           # hum and drift residuals add
    assert np.nanmax(amap.position_error_mm) > 1.5 * predicted       # the map is not flat (worst: on a
    # taxel centre line inside a gap, where one direction has no slope of G)


@pytest.mark.slow      # 18 s wall: a simulated press session; test_measure_api localizes in the fast tier
def test_presses_between_taxels_both_estimators_scored_apart(tmp_path, cache):
    """Half the presses at random points of the array (between taxels and over the margins), at the
    simulator's default noise: the model-based estimator places presses in the gaps about as well as
    on the taxels, the largest-taxel method only to the nearest taxel centre."""
    rig = load_rig("thesis-bench")
    folder, truth = measure(tmp_path, rig, Settings(input="presses", seconds=60, seed=12, between=0.5))
    ps = truth.params["presses"]
    assert sum("column" in p for p in ps) >= 30 and all("xy_mm" in p for p in ps)
    assert main(["measure", "localize", str(folder), "--presses", str(tmp_path / "m.truth" / "truth.json"),
                 "--scene", SCENE]) == 0
    rec = json.loads((folder / "localization.json").read_text())
    mb, lt = rec["model_based"], rec["largest_taxel"]
    assert rec["correct_rate"] == 1.0 and rec["matched"] >= 40          # on-taxel presses only
    assert mb["presses"] >= 15 and mb["between"]["presses"] >= 15 and mb["edge"]["presses"] >= 5
    assert mb["position_error_mm"]["rms"] < 0.5 and mb["force_error_pct"]["rms"] < 5
    # a corner press can land at its mirror image (studies.measured.localize): the median and 90th percentile
    assert mb["between"]["position_error_mm"]["median"] < 0.3 and mb["between"]["position_error_mm"]["p90"] < 1.0
    assert mb["between"]["force_error_pct"]["rms"] < 10
    # the largest taxel names a centre: a press in a gap is pitch / 2 (3.5 mm) or more away
    assert lt["between"]["position_error_mm"]["rms"] > 3.0
    assert lt["between"]["position_error_mm"]["median"] > 10 * mb["between"]["position_error_mm"]["median"]
    # beyond the outer taxels the estimate stays at the edge: the error is about the distance beyond
    beyond = [max(-x, x - 14, -y, y - 14, 0) for x, y in mb["edge"]["per_press"]["truth_mm"]]
    assert np.all(np.array(mb["edge"]["per_press"]["error_mm"]) < np.hypot(beyond, beyond) + 0.5)


def test_a_press_beyond_an_edge_taxel_looks_like_a_weaker_press_on_it(cache):
    """Why the estimator keeps to the taxels' span: 0.5-1.7 mm beyond taxel_0_0, with the force that
    gives the same peak on it, every one of the nine peaks is within 6 mV (of 0.4 V) of a press on it;
    the neighbours' 7 % crosstalk (28 mV) is what carries the position."""
    from taxel.analyses.surface.influence import influence
    infl = influence(taxel.load(SCENE))
    taxels = [(r, c) for r in range(3) for c in range(3)]
    on = 0.4 * infl.weights((0.0, 0.0), taxels)
    for x in (-0.5e-3, -1e-3, -1.7e-3):
        w = infl.weights((x, 0.0), taxels)
        assert np.abs(0.4 * w / w[0] - on).max() < 6e-3
    assert abs(on[1]) > 0.02
