"""The validation loop on the simulated rig: simulate -> capture over a pty ->
analyze -> calibrate -> localize, into one folder, with a summary beside the
thesis's figures.

    ROOT/step-1.7s, step-3.1s   a 2 N step through a resistor giving tau = 1.7 s / 3.1 s
                                with the lumped C_p (the thesis's two PZT taxels), at the default
                                20 mV drift: the fit's 95 % interval says how well one step pins tau
    ROOT/impulse                10 impulses, 3 % force spread, thesis bench (charge amplifier, notch)
    ROOT/chirp                  0-100 Hz over 8 s, thesis bench; analysed and calibrated
    ROOT/chirp-travel           a chirp on the rig with the actuator's travel recorded (one more channel),
                                the silicone drawn 1.2 x stiffer with loss factor 0.12: the modulus
                                scale and loss factor fitted (studies.measured.silicone) into chirp/'s
                                calibrated scene, with the piezo coefficient scale; the Cramer-Rao
                                figures of both chirps for them
    ROOT/chirp-fem              the same chirp with the taxel simulated by the FEM transient
                                (--model fem): both models against an FEM "reality"
    ROOT/chirp-reduced          the same chirp with the taxel simulated by the scene's reduced model
                                (the FEM's dynamics and crosstalk, --model reduced): the seed's lumped
                                model, the FEM-informed lumped model and the FEM against an FEM truth
    ROOT/presses                60 s of presses on random taxels; linearity
    ROOT/presses-between        60 s of presses, half on the taxels in turn and half at random points of the
                                array (between taxels, over the margins); localization by both methods,
                                on and between taxels, and the predicted accuracy map
                                (taxel.analyses.surface.localization) at the white noise of one reading
                                (1 mV per sample over the 9 samples it averages)
    ROOT/validation.json        the summary table (measured here) beside the thesis's figures
Each measurement folder is captured from a pseudo-terminal fed by the simulator
(taxel-cobs, streamed as fast as the pty takes it), holds the simulator's truth in
truth/ and the analysis files. The settings are the simulator's defaults but where
stated above.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from taxel.scene import Scene
from taxel.studies.measured import calibrate as C
from taxel.studies.measured.analysis import analyze_folder
from taxel.studies.bench.capture import capture, open_port
from taxel.studies.bench.folder import write_json
from taxel.studies.measured.localize import localize_folder
from taxel.studies.bench.protocol import encode_frames
from taxel.studies.bench.rig import Rig, load_rig, parse_rig
from taxel.studies.bench.signals import Settings, save_truth, simulate
from taxel.studies.bench.wire import Player, assemble

THESIS = {"tau_s": [1.7, 3.1], "linearity_R": {"PZT": 0.9942, "PVDF": 0.9933},
          "repeatability_pct": [95.65, 96.63], "rms_error_pct": {"lumped": 9.75, "FEM": 11.58}}


@dataclass
class Validation:
    """The loop's summary (ROOT/validation.json): measured here, the simulator's truth, the thesis's figures."""

    folder: Path
    data: dict

    def record(self) -> dict:
        """JSON-ready: validation.json."""
        return self.data

    def summary(self) -> list[str]:
        """For a person: each measured figure beside the thesis's."""
        m, th = self.data["measured"], self.data["thesis"]
        r = [abs(x) for x in m["linearity_R"].values()]
        loc = m["localization"]
        return [f"{self.folder}: {self.data['scene']} on {self.data['rig']}",
                "  time constants " + ", ".join(f"{t['tau_s']:.4g} s (set {t['truth_s']:g})" for t in m["tau"])
                + f"; thesis {', '.join(f'{x:g}' for x in th['tau_s'])} s",
                f"  linearity R {min(r):.5f}-{max(r):.5f}; thesis {th['linearity_R']['PZT']} (PZT)",
                f"  repeatability {m['repeatability_pct']['by_spread']:.2f} % by spread, "
                f"{m['repeatability_pct']['by_range']:.2f} % by range; thesis {th['repeatability_pct']}",
                f"  FRF RMS error: lumped {m['rms_error_pct']['lumped']:.2f} %, FEM {m['rms_error_pct']['fem']:.1f} %; "
                f"lumped after calibration {m['rms_error_pct']['lumped_validation_after']:.2f} %",
                f"  localization: largest taxel {100 * loc['correct_rate']:.0f} % correct, model-based "
                f"{loc['model_position_error_mm_rms']:.3g} mm rms on the taxels"]

    def to_folder(self, folder: str | Path | None = None) -> Path:
        """validation.json in `folder` (default: the loop's root); returns its path."""
        path = Path(folder if folder is not None else self.folder) / "validation.json"
        write_json(path, self.data)
        return path

    @classmethod
    def read(cls, folder: str | Path) -> Validation:
        """The loop's summary in `folder`; one-line MeasurementError if there is none."""
        from taxel.studies.bench.folder import MeasurementError
        try:
            return cls(Path(folder), json.loads((Path(folder) / "validation.json").read_text()))
        except (OSError, ValueError):
            raise MeasurementError(f"{folder}: no readable validation.json; run the loop into it first") from None


def captured(rig: Rig, scene: Scene, settings: Settings, out: Path) -> Path:
    """Simulate, serve the stream on a pty, capture it into `out`; the truth goes to out/truth."""
    truth = simulate(rig, scene, settings)
    wire = assemble(encode_frames(truth.frames, rig.port.protocol))
    with Player.pty(wire, None, linger=1.0, start=False) as player:
        r = parse_rig({**rig.model_dump(), "port": {**rig.port.model_dump(), "url": player.url}}, si_numbers=True)
        port = open_port(r)
        player.start()
        # ends when the port vanishes or, at the latest, when the player is done (all bytes written, then
        # 1 s for the capture to drain the pty's few kB); the frame count is checked below
        res = capture(r, out, seconds=len(truth.t) / rig.sampling.rate + 10, stop=player.done, port=port)
    save_truth(truth, out / "truth")
    if res.stats["frames"] != len(truth.t):
        raise RuntimeError(f"{out}: captured {res.stats['frames']} of {len(truth.t)} frames")
    return out


def resistor_rig(rig: Rig, R: float) -> Rig:
    return parse_rig({**rig.model_dump(), "conditioning": {"circuit": "resistor", "R": f"{float(R)!r} ohm",
                                                           "notch": True}}, si_numbers=True)


def travel_rig(rig: Rig) -> Rig:
    """The rig with the actuator's travel recorded on one more channel (an LVDT, 1 V/mm)."""
    d = rig.model_dump()
    d["channels"] = d["channels"] + [{"index": rig.n, "name": "travel", "sensitivity": 1000.0}]
    return parse_rig(d, si_numbers=True)


def identifiability_pair(scene, chain, sil, cal, sigma: float = 0.01) -> dict:
    """Cramer-Rao figures of the silicone from the bench chirp and from the travel chirp, at the
    fitted values, over 10-96 Hz (the bench's without 35-65 Hz, the notch), sigma relative per frequency."""
    from taxel.studies.measured.frf import lumped_frf
    from taxel.studies.measured.silicone import compliance, identifiability, scaled_model
    f = np.arange(10.0, 97.0)
    th = {"modulus_scale": sil.modulus_scale, "loss_factor": sil.loss_factor}

    def chirp(fr, modulus_scale, loss_factor, gain, tau_scale):
        return gain * lumped_frf(scaled_model(scene, modulus_scale, loss_factor), C.scaled_chain(chain, tau_scale)[0], fr)

    def travel(fr, modulus_scale, loss_factor):
        return 1.0 / compliance(scaled_model(scene, modulus_scale, loss_factor), fr)
    return {"sigma_pct": 100 * sigma,
            "bench_chirp": identifiability(chirp, {**th, "gain": cal.gain, "tau_scale": cal.tau_scale},
                                           f[np.abs(f - 50) >= 15], sigma).record(),
            "travel_chirp": identifiability(travel, th, f, sigma).record()}


def run(root: Path, scene_name: str = "thesis-pzt-3x3-2d", rig_name: str = "thesis-bench",
        progress=print) -> dict:
    """The loop (module docstring); returns the summary written to ROOT/validation.json."""
    from taxel.analyses import lumped_model
    from taxel.scene import load
    root = Path(root)
    root.mkdir(parents=True, exist_ok=True)
    scene, rig = load(scene_name), load_rig(rig_name)
    C_p = lumped_model(scene).C_p
    summary: dict = {"scene": scene_name, "rig": rig_name, "thesis": THESIS, "measured": {}, "truth": {}}
    meas, tru = summary["measured"], summary["truth"]
    taus = []
    for tau in THESIS["tau_s"]:
        out = captured(resistor_rig(rig, tau / C_p), scene,
                       Settings(input="step", seconds=12, amplitude=2.0, tau_spread=0.0,
                                crosstalk=False, seed=int(10 * tau)), root / f"step-{tau:g}s")
        a = analyze_folder(out, scene, scene_name)
        a.write()
        fit = {s.taxel: s for s in a.steps}["taxel_1_1"]
        taus.append({"tau_s": fit.tau_s, "ci95_s": list(fit.tau_ci95_s), "R_eff_ohm": fit.R_eff_ohm, "truth_s": tau})
        progress(f"      step: tau {fit.tau_s:.4g} s, 95 % {fit.tau_ci95_s[0]:.3g}-{fit.tau_ci95_s[1]:.3g} s "
                 f"(truth {tau:g} s, 20 mV drift)")
    meas["tau"] = taus
    out = captured(rig, scene, Settings(input="impulse", seconds=20, amplitude_spread=0.03, crosstalk=False, seed=2),
                   root / "impulse")
    a = analyze_folder(out, scene, scene_name)
    a.write()
    (rep,) = a.repeatability
    meas["repeatability_pct"] = {"by_spread": rep.by_spread_pct, "by_range": rep.by_range_pct, "impulses": rep.n}
    tru["impulse_force_by_spread_pct"] = rep.force_by_spread_pct
    progress(f"      impulses: repeatability {rep.by_spread_pct:.2f} % (spread), {rep.by_range_pct:.2f} % (range)")
    out = captured(rig, scene, Settings(input="chirp", seconds=10, crosstalk=False, seed=4), root / "chirp")
    a = analyze_folder(out, scene, scene_name)
    a.write()
    chain = rig.chains()[a.frf.taxel].readout()
    cal = C.calibrate(a.frf, lumped_model(scene), chain)
    sil_truth = {"modulus_scale": 1.2, "silicone_loss": 0.12}
    tout = captured(travel_rig(rig), scene, Settings(input="chirp", seconds=10, crosstalk=False, seed=5, **sil_truth),
                    root / "chirp-travel")
    from taxel.studies.measured import events, silicone as SI
    from taxel.studies.bench.folder import read
    sil = SI.fit(events.record(read(tout)), scene)
    ident = identifiability_pair(scene, chain, sil, cal)
    C.write(out, cal, C.calibrated_scene(scene_name, chain, cal.tau_scale, sil, cal.gain),
            {"silicone": sil.record(), "piezo_coefficient_scale": cal.gain,
             "piezo_coefficient_scale_ci95": list(cal.gain_ci95), "travel": "../chirp-travel", "identifiability": ident})
    meas["silicone"] = {**sil.record(), "identifiability": ident}
    tru["silicone"] = json.loads((tout / "truth" / "truth.json").read_text())["silicone"]
    progress(f"      chirp with the travel: silicone modulus scale {sil.modulus_scale:.4g} (truth 1.2), loss factor "
             f"{sil.loss_factor:.3g} (truth 0.12); from the bench chirp alone the Cramer-Rao bound is "
             f"{ident['bench_chirp']['cramer_rao_sd_pct'][0]:.0f} % / {ident['bench_chirp']['cramer_rao_sd_pct'][1]:.0f} %")
    truth = json.loads((out / "truth" / "truth.json").read_text())["taxels"][a.frf.taxel]
    meas["rms_error_pct"] = {"lumped": C.rms_error(a.frf, "lumped")["rms_error_pct"],
                             "fem": C.rms_error(a.frf, "fem")["rms_error_pct"],
                             "lumped_validation_before": cal.rms_before_pct,
                             "lumped_validation_after": cal.rms_after_pct}
    meas["calibration"] = cal.record()
    tru["gain_factor"], tru["tau_factor"] = truth["gain_factor"], truth["tau_factor"]
    progress(f"      chirp: RMS error lumped {meas['rms_error_pct']['lumped']:.2f} %, FEM "
             f"{meas['rms_error_pct']['fem']:.1f} %; calibrated gain "
             f"{cal.gain:.4g} (truth {truth['gain_factor']:.4g}), validation RMS {cal.rms_before_pct:.2f} -> "
             f"{cal.rms_after_pct:.2f} %")
    out = captured(rig, scene, Settings(input="chirp", seconds=10, crosstalk=False, seed=4, model="fem"),
                   root / "chirp-fem")
    a = analyze_folder(out, scene, scene_name)
    a.write()
    meas["rms_error_pct_fem_rig"] = {k: C.rms_error(a.frf, k)["rms_error_pct"] for k in ("lumped", "fem")}
    progress(f"      chirp, FEM-simulated taxel: RMS error lumped {meas['rms_error_pct_fem_rig']['lumped']:.1f} %, "
             f"FEM {meas['rms_error_pct_fem_rig']['fem']:.2f} %")
    out = captured(rig, scene, Settings(input="chirp", seconds=10, seed=4, model="reduced"), root / "chirp-reduced")
    a = analyze_folder(out, scene, scene_name)
    from taxel.analyses.solves.lumped_fem import informed
    from taxel.studies.measured.frf import lumped_frf
    chain = rig.chains()[a.frf.taxel]
    a.frf.models["lumped_fem"] = lumped_frf(informed(scene).model, chain.readout(), a.frf.freqs)
    a.write()
    meas["rms_error_pct_reduced_rig"] = {k: C.rms_error(a.frf, k)["rms_error_pct"] for k in ("lumped", "lumped_fem", "fem")}
    from taxel.analyses.solves.reduced import cached, one_port
    truth = json.loads((out / "truth" / "truth.json").read_text())["taxels"][a.frf.taxel]
    port = one_port(cached(scene, None, "charge"), tuple(truth["taxel"]))
    cal = C.calibrate(a.frf, port, chain.readout())              # the chain fit on the FEM's reduced model
    meas["calibration_reduced"] = cal.record()
    tru["reduced_rig"] = {"gain_factor": truth["gain_factor"], "tau_factor": truth["tau_factor"]}
    progress("      chirp, the taxel simulated by the scene's reduced model (FEM truth, drawn gain and tau): RMS error "
             + ", ".join(f"{k} {v:.1f} %" for k, v in meas["rms_error_pct_reduced_rig"].items())
             + " (lumped: the seed's; lumped_fem: identified from the FEM); calibrated on the reduced model: gain "
             f"{cal.gain:.4g} [{cal.gain_ci95[0]:.4g}, {cal.gain_ci95[1]:.4g}] (truth {truth['gain_factor']:.4g}), tau "
             f"scale {cal.tau_scale:.4g} [{cal.tau_scale_ci95[0]:.4g}, {cal.tau_scale_ci95[1]:.4g}] (truth "
             f"{truth['tau_factor']:.4g}), validation RMS {cal.rms_before_pct:.2f} -> {cal.rms_after_pct:.2f} %")
    out = captured(rig, scene, Settings(input="presses", seconds=60, seed=11), root / "presses")
    a = analyze_folder(out, scene, scene_name)
    a.write()
    meas["linearity_R"] = {x.taxel: x.r for x in a.linearity}
    meas["sensitivity_V_per_N"] = {x.taxel: x.sensitivity_V_per_N for x in a.linearity}
    out = captured(rig, scene, Settings(input="presses", seconds=60, seed=12, between=0.5), root / "presses-between")
    loc = localize_folder(out, out / "truth" / "truth.json", scene)
    loc.write(out)

    def brief(scores):
        r = scores.record()
        return {"presses": r["presses"], "position_error_mm_rms": r["position_error_mm"]["rms"],
                "position_error_mm_median": r["position_error_mm"]["median"],
                "position_error_mm_max": r["position_error_mm"]["max"],
                "force_error_pct_rms": r["force_error_pct"]["rms"]} if r["presses"] else {"presses": 0}
    meas["localization"] = {"correct_rate": loc.correct_rate, "presses": loc.matched,
                            "largest_taxel": {c: brief(v) for c, v in loc.largest.items()},
                            "model_based": {c: brief(v) for c, v in loc.model.items()}}
    meas["localization"]["model_position_error_mm_rms"] = meas["localization"]["model_based"]["on"]["position_error_mm_rms"]
    meas["localization"]["model_force_error_pct_rms"] = meas["localization"]["model_based"]["on"]["force_error_pct_rms"]
    from taxel.analyses.surface.influence import influence
    from taxel.analyses.surface.localization import accuracy_map
    infl = influence(scene)
    S = float(np.median(np.abs(list(loc.sensitivity_V_per_N.values()))))
    F = float(np.median([p["force_N"] for p in json.loads((out / "truth" / "truth.json").read_text())["presses"]]))
    from taxel.studies.measured.localize import reading_noise
    amap = accuracy_map(infl, scene.array.rows, scene.array.cols, S, reading_noise(1e-3, rig.sampling.rate), F)
    write_json(out / "accuracy-map.json", amap.record())
    meas["localization"]["predicted_position_error_mm_at_taxels"] = float(
        np.sqrt(np.mean(amap.at_taxels(1e3 * infl.pitch) ** 2)))
    meas["localization"]["predicted_position_error_mm_max"] = float(np.nanmax(amap.position_error_mm))
    r = np.array(list(meas["linearity_R"].values()))
    btw = meas["localization"]["model_based"].get("between", {})
    progress(f"      presses: R {np.abs(r).min():.5f}-{np.abs(r).max():.5f}, largest taxel "
             f"{100 * loc.correct_rate:.0f} % correct, model-based {meas['localization']['model_position_error_mm_rms']:.3g}"
             f" mm rms on the taxels, between them {btw.get('position_error_mm_rms', float('nan')):.3g} mm rms, "
             f"median {btw.get('position_error_mm_median', float('nan')):.3g} mm")
    write_json(root / "validation.json", summary)
    return summary
