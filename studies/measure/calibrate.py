"""Calibration of the lumped model and the readout chain against a measured FRF.

Parameters (per taxel, the pressed one of a chirp record), as the thesis says
is needed:
  g   the charge gain: the measured short-circuit charge per newton over the
      lumped model's (the piezo coefficient and the taxel's gain spread together);
  s   the chain's time-constant scale: tau = s R_f C_f (charge amplifier) or
      s R C_p (resistor), from the rig's nominal components.
Model: H(f; g, s) = g H_lumped(f; chain with R_f -> s R_f (or R -> s R)), through
the rig's own readout (fem.circuits.readout, notch included).
Fit: scipy.optimize.least_squares of the relative magnitude residuals
|H(f)| / |H1(f)| - 1 over the calibration frequencies (log g, log s as
unknowns); 95 % intervals exp(p +- 1.96 sigma) with sigma^2 from s^2 (J^T J)^-1,
s^2 = sum(r^2) / (n - 2) (white residuals assumed).
Frequencies used: where the coherence exceeds 0.9, except where Welch's H1 on
an 8 s chirp is biased by the chain's memory rather than by noise (measured in
tests/test_measure_analyze.py): within 1.5 notch bandwidths of the notch (3-13 %)
and below 10 resolution bins (the chirp's mean force leaking through the window:
18 % at 5 Hz).
Cross-validation: those frequencies are split at their median; the fit uses the lower half, and the RMS error (studies.measure.frf)
is reported on the other half before and after calibration (and on all of it).
With a step record, the step's first-order fit tau (studies.measure.analyze)
is reported beside s R_f C_f as an independent check.

Not identifiable from this chirp: the silicone's modulus scale and loss factor.
In the lumped model the force passes through the silicone and the piezo in
series, so the quasi-static charge does not depend on the silicone, and its
resonances are above 10 kHz: a 1.2 x modulus changes |Q_sc / F| by 0.0015 % at
10 Hz and 0.15 % at 100 Hz, a loss factor 0.1 -> 0.12 by 0.004 % at 100 Hz; the
Cramer-Rao bound over 10-96 Hz at H1's 1 % is 62 % (modulus scale) and 400 %
(loss factor) (benchmarks/measure_identifiability.py). A chirp with the
actuator's travel recorded identifies both (studies.measure.silicone: 0.1 % and
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

from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np
from scipy import optimize

from taxel.studies.measure.frf import FRF, lumped_frf, rms_error
from taxel.studies.measure.folder import MeasurementError, write_json

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


def _chain(readout, s: float):
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
        r, _ = _chain(readout, float(np.exp(p[1])))
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
    r_cal, tau = _chain(readout, float(s))
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
    studies.measure.silicone.SiliconeFit, the silicone as a user material with its moduli scaled and
    [dynamics] silicone_loss; with piezo_scale, the piezo as a user material with d scaled."""
    from taxel.scene import EXAMPLES, load, read_toml
    path = Path(scene_source)
    if not path.is_file():
        path = EXAMPLES / f"{scene_source}.toml"
    data = read_toml(path)
    r, _ = _chain(readout, s)
    ro = {"circuit": r.circuit, "R": f"{r.R!r} ohm", "C_f": f"{r.C_f!r} F", "R_f": f"{r.R_f!r} ohm",
          "R_i": f"{r.R_i!r} ohm", "C_c": f"{r.C_c!r} F", "notch": bool(r.notch),
          "notch_frequency": f"{r.notch_frequency!r} Hz", "notch_bandwidth": f"{r.notch_bandwidth!r} Hz"}
    data["readout"] = ro
    what = ["readout"]
    if silicone is not None or piezo_scale is not None:
        from taxel.analyses.adapter import scene_materials
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
            from taxel.fem.materials import EPS0
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


__all__ = ["Calibration", "calibrate", "calibrated_scene", "rms_error", "write"]
