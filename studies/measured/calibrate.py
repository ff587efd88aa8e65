"""Calibration of the lumped model and the readout chain against a measured FRF.

Parameters (per taxel, the pressed one of a chirp record), as the thesis says
is needed:
  g   the charge gain: the measured short-circuit charge per newton over the
      lumped model's (the piezo coefficient and the taxel's gain spread together);
  s   the chain's time-constant scale: tau = s R_f C_f (charge amplifier) or
      s R C_p (resistor), from the rig's nominal components.
Model: H(f; g, s) = g H_lumped(f; chain with R_f -> s R_f (or R -> s R)), through
the rig's own readout (fem.readout.readout, notch included).
Fit: scipy.optimize.least_squares of the relative magnitude residuals
|H(f)| / |H1(f)| - 1 over the calibration frequencies (log g, log s as
unknowns); 95 % intervals exp(p +- 1.96 sigma) with sigma^2 from s^2 (J^T J)^-1,
s^2 = sum(r^2) / (n - 2) (white residuals assumed).
Frequencies used: where the coherence exceeds 0.9, except where Welch's H1 on
an 8 s chirp is biased by the chain's memory rather than by noise (measured in
tests/test_measure_analyze.py): within 1.5 notch bandwidths of the notch (3-13 %)
and below 10 resolution bins (the chirp's mean force leaking through the window:
18 % at 5 Hz).
Cross-validation: those frequencies are split at their median; the fit uses the lower half, and the RMS error (studies.measured.frf)
is reported on the other half before and after calibration (and on all of it).
With a step record, the step's first-order fit tau (studies.measured.peaks)
is reported beside s R_f C_f as an independent check.

Not identifiable from this chirp: the silicone's modulus scale and loss factor.
In the lumped model the force passes through the silicone and the piezo in
series, so the quasi-static charge does not depend on the silicone, and its
resonances are above 10 kHz: a 1.2 x modulus changes |Q_sc / F| by 0.0015 % at
10 Hz and 0.15 % at 100 Hz, a loss factor 0.1 -> 0.12 by 0.004 % at 100 Hz; the
Cramer-Rao bound over 10-96 Hz at H1's 1 % is 62 % (modulus scale) and 400 %
(loss factor) (benchmarks/measure_identifiability.py). A chirp with the
actuator's travel recorded identifies both (studies.measured.silicone: 0.1 % and
1.5 % at the same 1 %): `taxel measure calibrate --travel DIR` fits them there
and writes them into the overlay, with the charge gain g as the piezo
coefficient scale (d scaled by g).

Written: DIR/calibration.json, and DIR/calibrated-scene.toml: the scene with the
calibrated readout ([readout] from the rig's chain, R_f or R scaled by s), which
`taxel solve` reads; with --travel also the silicone (a user material
"<name>-calibrated", moduli scaled, and [dynamics] silicone_loss) and the piezo
(a user material with d scaled by g, the taxel's gain spread included).
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path

import numpy as np
from scipy import optimize

from taxel.studies.measured.frf import FRF, lumped_frf, rms_error
from taxel.studies.bench.folder import MeasurementError, write_json
from taxel.studies.measured.silicone import SiliconeFit

JSON, SCENE_TOML = "calibration.json", "calibrated-scene.toml"


@dataclass
class Calibration:
    taxel: str
    gain: float
    gain_ci95: tuple[float, float]
    tau_scale: float
    tau_scale_ci95: tuple[float, float]
    tau_s: float                         # the calibrated chain time constant
    fit_band_Hz: tuple[float, float]
    validation_band_Hz: tuple[float, float]
    rms_before_pct: float                # on the validation half
    rms_after_pct: float
    rms_before_all_pct: float            # on every coherent frequency
    rms_after_all_pct: float
    step_tau_s: float | None = None

    def record(self) -> dict:
        return asdict(self)


def scaled_chain(readout, s: float):
    if readout.circuit == "charge_amplifier":
        return replace(readout, R_f=readout.R_f * s), readout.R_f * readout.C_f * s
    if readout.circuit == "resistor":
        return replace(readout, R=readout.R * s), None
    raise MeasurementError("calibration needs a resistor or charge-amplifier chain in the rig's conditioning")


def calibrate(frf: FRF, lm, readout, min_coherence: float = 0.9) -> Calibration:
    """Fit g and s on the lower half of the coherent band; validate on the upper half."""
    ok = (frf.coherence > min_coherence) & (np.abs(frf.H1) > 0) & (frf.freqs >= 10 * frf.freqs[1])
    if readout.notch:
        ok &= np.abs(frf.freqs - readout.notch_frequency) > 1.5 * readout.notch_bandwidth
    f = frf.freqs[ok]
    if len(f) < 6:
        raise MeasurementError(f"only {len(f)} frequencies with coherence > {min_coherence}; "
                               "record a longer or stronger chirp")
    split = np.median(f)
    fit, val = f <= split, f > split
    H1 = np.abs(frf.H1[ok])

    def model(p, sel):
        r, _ = scaled_chain(readout, float(np.exp(p[1])))
        return np.exp(p[0]) * np.abs(lumped_frf(lm, r, f[sel]))

    def resid(p):
        return model(p, fit) / H1[fit] - 1

    res = optimize.least_squares(resid, np.zeros(2), method="lm")
    s2 = 2 * res.cost / max(len(res.fun) - 2, 1)
    try:
        sig = np.sqrt(np.clip(np.diag(s2 * np.linalg.inv(res.jac.T @ res.jac)), 0, None))
    except np.linalg.LinAlgError:
        sig = np.full(2, np.inf)
    g, s = np.exp(res.x)
    ci = [(float(np.exp(res.x[i] - 1.96 * sig[i])), float(np.exp(res.x[i] + 1.96 * sig[i]))) for i in range(2)]
    r_cal, tau = scaled_chain(readout, float(s))
    if tau is None:
        tau = r_cal.R * lm.C_p

    def rms(p, sel):
        e = model(p, sel) / H1[sel] - 1
        return float(100 * np.sqrt(np.mean(e ** 2)))
    every = np.ones(len(f), bool)
    return Calibration(frf.taxel, float(g), ci[0], float(s), ci[1], float(tau),
                       (float(f[fit].min()), float(f[fit].max())), (float(f[val].min()), float(f[val].max())),
                       rms(np.zeros(2), val), rms(res.x, val), rms(np.zeros(2), every), rms(res.x, every))


def toml_text(data: dict) -> str:
    """A minimal TOML writer for scene dicts: scalars, lists of scalars, nested tables."""
    def val(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, (int, float)):
            return repr(v)
        if isinstance(v, str):
            return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
        if isinstance(v, (list, tuple)):
            return "[" + ", ".join(val(x) for x in v) + "]"
        raise TypeError(f"cannot write {type(v).__name__} to TOML")

    lines: list[str] = []

    def table(prefix: str, d: dict):
        scalars = {k: v for k, v in d.items() if not isinstance(v, dict) and v is not None}
        if prefix and scalars:
            lines.append(f"\n[{prefix}]")
        lines.extend(f"{k} = {val(v)}" for k, v in scalars.items())
        for k, v in d.items():
            if isinstance(v, dict):
                table(f"{prefix}.{k}" if prefix else k, v)
    table("", data)
    return "\n".join(lines).lstrip("\n") + "\n"


def calibrated_scene(scene_source: str, readout, s: float, silicone=None, piezo_scale: float | None = None) -> str:
    """The scene's TOML with [readout] replaced by the rig's chain, R_f (or R) scaled by s; with a
    studies.measured.silicone.SiliconeFit, the silicone as a user material with its moduli scaled and
    [dynamics] silicone_loss; with piezo_scale, the piezo as a user material with d scaled."""
    from taxel.scene import EXAMPLES, SceneError, load
    from taxel.schema import read_toml
    path = Path(scene_source)
    if not path.is_file():
        path = EXAMPLES / f"{scene_source}.toml"
    data = read_toml(path, SceneError)
    r, _ = scaled_chain(readout, s)
    ro = {"circuit": r.circuit, "R": f"{r.R!r} ohm", "C_f": f"{r.C_f!r} F", "R_f": f"{r.R_f!r} ohm",
          "R_i": f"{r.R_i!r} ohm", "C_c": f"{r.C_c!r} F", "notch": bool(r.notch),
          "notch_frequency": f"{r.notch_frequency!r} Hz", "notch_bandwidth": f"{r.notch_bandwidth!r} Hz"}
    data["readout"] = ro
    what = ["readout"]
    if silicone is not None or piezo_scale is not None:
        from taxel.analyses import scene_materials
        scene = load(str(path))
        mats, arr = scene_materials(scene), scene.array
        user = data.setdefault("materials", {})
        if silicone is not None:
            sil, k = mats[arr.silicone], silicone.modulus_scale
            rec = {"kind": "solid", "mu": sil.mu * k, "K": sil.K * k, "rho": sil.rho, "eps_r": sil.eps_r}
            if sil.yeoh is not None:
                rec.update(C10=sil.yeoh[0] * k, C20=sil.yeoh[1] * k, C30=sil.yeoh[2] * k)
            user[f"{arr.silicone}-calibrated"] = rec
            data["array"]["silicone"] = f"{arr.silicone}-calibrated"
            data.setdefault("dynamics", {})["silicone_loss"] = float(silicone.loss_factor)
            what += ["silicone modulus scale and loss factor"]
        if piezo_scale is not None:
            from taxel.fem.constitution import EPS0
            pz = mats[arr.piezo]
            sE, d, eps_T = pz.strain_charge()
            rec = {"kind": "piezo", "s": sE.tolist(), "d": (d * piezo_scale).tolist(), "eps_T": (eps_T / EPS0).tolist(),
                   "rho": pz.rho}
            rec.update({k: v for k, v in (("Qm", pz.Qm), ("tan_delta", pz.tan_delta)) if v is not None})
            user[f"{arr.piezo}-calibrated"] = rec
            data["array"]["piezo"] = f"{arr.piezo}-calibrated"
            what += ["piezo coefficient scale"]
    data["description"] = (data.get("description", "") + f" Calibrated {', '.join(what)} (taxel measure calibrate).").strip()
    return toml_text(data)


def write(folder: Path, cal: Calibration, scene_text: str, extra: dict | None = None) -> list[Path]:
    folder = Path(folder)
    tmp = folder / (SCENE_TOML + ".tmp")
    tmp.write_text(scene_text)
    tmp.replace(folder / SCENE_TOML)
    write_json(folder / JSON, {**cal.record(), **(extra or {}), "scene": SCENE_TOML})
    return [folder / JSON, folder / SCENE_TOML]


@dataclass
class FolderCalibration:
    """The calibration of a chirp's measurement folder (`calibrate_folder`): the chain's fit, with a travel
    record the silicone's, the calibrated scene's TOML, and what calibration.json adds (`extra`)."""

    folder: Path
    calibration: Calibration
    scene_text: str
    silicone: SiliconeFit | None = None
    extra: dict = field(default_factory=dict)

    def record(self) -> dict:
        """JSON-ready: calibration.json."""
        return {**self.calibration.record(), **self.extra, "scene": SCENE_TOML}

    def summary(self) -> list[str]:
        """For a person: the gain and time constant with their intervals, the silicone's, the RMS errors."""
        cal, sil = self.calibration, self.silicone
        lines = [f"{cal.taxel}: gain {cal.gain:.4g} (95 % {cal.gain_ci95[0]:.4g}-{cal.gain_ci95[1]:.4g}), tau "
                 f"{cal.tau_s:.4g} s (scale {cal.tau_scale:.4g}, 95 % {cal.tau_scale_ci95[0]:.4g}-"
                 f"{cal.tau_scale_ci95[1]:.4g})" + (f", step tau {cal.step_tau_s:.4g} s" if cal.step_tau_s else "")]
        if sil is not None:
            lines.append(f"silicone: modulus scale {sil.modulus_scale:.4g} (95 % {sil.modulus_scale_ci95[0]:.4g}-"
                         f"{sil.modulus_scale_ci95[1]:.4g}), loss factor {sil.loss_factor:.4g} (95 % "
                         f"{sil.loss_factor_ci95[0]:.4g}-{sil.loss_factor_ci95[1]:.4g}); piezo coefficient scale "
                         f"{cal.gain:.4g}")
        lines.append(f"RMS error on {cal.validation_band_Hz[0]:g}-{cal.validation_band_Hz[1]:g} Hz (not fitted): "
                     f"{cal.rms_before_pct:.2f} % before, {cal.rms_after_pct:.2f} % after")
        return lines

    def to_folder(self, folder: str | Path | None = None) -> list[Path]:
        """calibration.json and calibrated-scene.toml in `folder` (default: the chirp's folder)."""
        return write(Path(folder) if folder is not None else self.folder, self.calibration, self.scene_text, self.extra)

    @classmethod
    def read(cls, folder: str | Path) -> FolderCalibration:
        """The calibration written in `folder`; one-line MeasurementError if there is none."""
        folder = Path(folder)
        try:
            rec = json.loads((folder / JSON).read_text())
            text = (folder / SCENE_TOML).read_text()
        except (OSError, ValueError):
            raise MeasurementError(f"{folder}: no readable {JSON} and {SCENE_TOML}; run 'taxel measure calibrate "
                                   f"{folder} --scene SCENE' first") from None
        names = {f.name for f in fields(Calibration)}
        cal = Calibration(**{k: tuple(v) if isinstance(v, list) else v for k, v in rec.items() if k in names})
        extra = {k: v for k, v in rec.items() if k not in names and k != "scene"}
        sil = extra.get("silicone")
        sil = None if sil is None else SiliconeFit(**{k: tuple(v) if isinstance(v, list) else v for k, v in sil.items()})
        return cls(folder, cal, text, sil, extra)


def calibrate_folder(folder, scene, scene_source: str, step=None, travel=None,
                     resolution: float = 1.0, model: str = "lumped") -> FolderCalibration:
    """Calibrate the chain (and with a travel record the silicone) on the chirp in `folder`.

    Parameters
    ----------
    folder : path
        A chirp's measurement folder.
    scene : taxel.scene.Scene
        The measured array's scene.
    scene_source : str
        The scene's file or built-in name (the calibrated scene is its TOML, overlaid).
    step : path, optional
        A step's measurement folder of the same taxel: its fitted tau, for comparison.
    travel : path, optional
        A chirp with the actuator's travel recorded: the silicone's modulus scale and loss factor,
        and the piezo coefficient scale, into the calibrated scene.
    resolution : float
        H1's frequency resolution, Hz.
    model : {"lumped", "reduced"}
        The taxel model the chain is fitted on: the seed's lumped model, or the pressed
        path of the scene's reduced model (taxel.analyses.solves.reduced.one_port: the FEM's
        V_oc(f) and static capacitance; fast enough for the least-squares loop).

    Returns
    -------
    FolderCalibration
        Not yet written: `to_folder()` writes calibration.json and calibrated-scene.toml.
    """
    from taxel.analyses import lumped_model
    from taxel.studies.bench.folder import read, read_rig
    from taxel.studies.measured import events, silicone as SI
    from taxel.studies.measured.analysis import analyze_folder
    a = analyze_folder(folder, scene, scene_source, "chirp", resolution, fem=False)
    rig = read_rig(folder)
    chain = rig.chains()[a.frf.taxel].readout()
    if model == "reduced":
        from taxel.analyses.solves.reduced import cached, one_port
        taxel = next(tuple(c.taxel) for c in rig.ordered() if c.name == a.frf.taxel)
        cal = calibrate(a.frf, one_port(cached(scene, None, "charge"), taxel), chain)
    elif model == "lumped":
        cal = calibrate(a.frf, lumped_model(scene), chain)
    else:
        raise ValueError(f"--model {model}: use lumped or reduced")
    if step:
        fits = {f.taxel: f for f in analyze_folder(step, scene, scene_source, "step").steps}
        if cal.taxel not in fits:
            raise ValueError(f"--step {step}: no step fit of {cal.taxel}; give a step of the same taxel")
        cal.step_tau_s = fits[cal.taxel].tau_s
    sil, extra = None, {}
    if travel:
        sil = SI.fit(events.record(read(travel)), scene)
        extra = {"silicone": sil.record(), "piezo_coefficient_scale": cal.gain,
                 "piezo_coefficient_scale_ci95": list(cal.gain_ci95), "travel": str(travel)}
    text = calibrated_scene(scene_source, chain, cal.tau_scale, sil, cal.gain if sil is not None else None)
    return FolderCalibration(Path(folder), cal, text, sil, {**extra, "model": model})


__all__ = ["Calibration", "FolderCalibration", "calibrate", "calibrate_folder", "calibrated_scene", "rms_error",
           "scaled_chain", "write"]
