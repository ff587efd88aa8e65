"""The noise budget of a taxel's readout (taxel.analyses.solves.noise): each source's PSD at
the readout output, its share of the band's variance, and what they imply for the
smallest force the chain can feel.

Definitions (SI; the band B = [f1, f2]):
- noise_rms: sqrt of the integral of the total PSD over B plus the hum lines in B, V;
- band sensitivity S_B = sqrt(mean over B of |H(f)|^2), V/N, with H the readout
  output per newton of the pressed taxel (a force of flat spectrum over B and rms F
  gives an output of rms F S_B);
- min_detectable_force: noise_rms / S_B, N (rms; the force at SNR 1);
- snr: 20 log10(F / min_detectable_force) dB at the scene's load force F (as rms);
- saturation force: the swing of what clips first (amplifier output or ADC full scale)
  over max |H| in B, N (peak); dynamic_range: 20 log10((F_sat / sqrt 2) / min_detectable_force) dB
  (a full-scale sine against the noise floor).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from taxel.scene import Scene
from taxel.analyses.results.base import ErrorEstimate, error_record
from taxel.analyses.results.base import FORMAT, write_csv, write_result, write_summary
from taxel import units


@dataclass
class NoiseResult:
    """A noise budget: PSDs per source at the pressed taxel's readout output."""

    scene: Scene
    band: tuple[float, float]             # Hz
    freqs: np.ndarray                     # Hz, the integration grid
    psd: dict[str, np.ndarray]            # source -> V^2/Hz at the readout output (pressed taxel)
    lines: list[tuple[float, float]]      # hum lines in the band: (Hz, V^2)
    gain: np.ndarray                      # |H(f)|, V/N of the pressed taxel on the grid
    electrode: str                        # the pressed taxel's electrode
    noise_per_electrode: dict[str, float]  # V rms in the band at each electrode's readout
    force: float                          # N, the scene's load force (for the SNR)
    saturation_output: float              # V: what clips first
    saturation_by: str                    # "amplifier" | "ADC" | "none"
    label: str                            # the readout chain in words
    rig: str | None = None
    error: ErrorEstimate | None = None    # no error estimate for a noise budget: None
    kind = "noise"
    success = True             # no load to stop short of
    stop = None

    # ---------------------------------------------------------------- derived numbers
    def variance(self) -> dict[str, float]:
        """Each source's variance in the band (V^2); the hum lines under "hum residual"."""
        from taxel.fem.readout import band_power
        out = {k: band_power(self.freqs, v, self.band) for k, v in self.psd.items()}
        out["hum residual"] = float(sum(p for _, p in self.lines))
        return out

    def shares(self) -> dict[str, float]:
        """Each source's fraction of the band's variance."""
        v = self.variance()
        tot = sum(v.values())
        return {k: x / tot for k, x in v.items()}

    @property
    def noise_rms(self) -> float:
        return float(np.sqrt(sum(self.variance().values())))

    @property
    def band_sensitivity(self) -> float:
        """S_B = sqrt(mean |H|^2 over the band), V/N."""
        from taxel.fem.readout import band_power
        return float(np.sqrt(band_power(self.freqs, self.gain ** 2, self.band) / (self.band[1] - self.band[0])))

    @property
    def min_detectable_force(self) -> float:
        return self.noise_rms / self.band_sensitivity

    @property
    def saturation_force(self) -> float:
        return float(self.saturation_output / self.gain.max()) if np.isfinite(self.saturation_output) else np.inf

    def snr_at(self, force: float) -> float:
        """SNR (dB) of a band-limited force of rms `force` (N)."""
        return float(20 * np.log10(force / self.min_detectable_force))

    def outputs(self) -> dict[str, float]:
        """min_detectable_force (N), noise_rms (V), snr (dB at the scene's load force),
        dynamic_range (dB; inf without a clipping stage)."""
        fs = self.saturation_force
        return {"min_detectable_force": self.min_detectable_force, "noise_rms": self.noise_rms,
                "snr": self.snr_at(self.force),
                "dynamic_range": float(20 * np.log10(fs / np.sqrt(2) / self.min_detectable_force))
                if np.isfinite(fs) else float("inf")}

    # ---------------------------------------------------------------- the protocol
    def record(self) -> dict:
        return {"kind": self.kind, "format": FORMAT, "scene": self.scene.name, "output": self.label,
                "rig": self.rig, "band_Hz": list(self.band), "electrode": self.electrode, "force_N": self.force,
                "frequency_Hz": self.freqs.tolist(), "gain_V_per_N": self.gain.tolist(),
                "psd_V2_per_Hz": {k: v.tolist() for k, v in self.psd.items()},
                "hum_lines": [[f, p] for f, p in self.lines],
                "variance_V2": self.variance(), "share": self.shares(),
                "noise_per_electrode_V": self.noise_per_electrode,
                "band_sensitivity_V_per_N": self.band_sensitivity, "saturation_output_V": self.saturation_output,
                "saturation_by": self.saturation_by, "saturation_force_N": self.saturation_force,
                "outputs": self.outputs(), **error_record(self.error, self.kind)}

    @classmethod
    def from_record(cls, scene: Scene, rec: dict) -> NoiseResult:
        return cls(scene, tuple(rec["band_Hz"]), np.asarray(rec["frequency_Hz"], float),
                   {k: np.asarray(v, float) for k, v in rec["psd_V2_per_Hz"].items()},
                   [tuple(x) for x in rec["hum_lines"]], np.asarray(rec["gain_V_per_N"], float), rec["electrode"],
                   dict(rec["noise_per_electrode_V"]), float(rec["force_N"]), float(rec["saturation_output_V"]),
                   rec["saturation_by"], rec["output"], rec.get("rig"))

    def summary(self) -> list[str]:
        o, E = self.outputs(), units.engineering
        lines = [f"noise at the {self.label} of {self.electrode}, {self.band[0]:g}-{self.band[1]:g} Hz"
                 + (f" on {self.rig}" if self.rig else "") + f": {E(o['noise_rms'], 'V')} rms",
                 f"band sensitivity {E(self.band_sensitivity, 'V/N')}; minimum detectable force "
                 f"{E(o['min_detectable_force'], 'N')} rms; SNR {o['snr']:.1f} dB at {self.force:g} N",
                 f"saturates at {E(self.saturation_force, 'N')} ({self.saturation_by}); dynamic range "
                 f"{o['dynamic_range']:.1f} dB"]
        for k, s in sorted(self.shares().items(), key=lambda kv: -kv[1]):
            lines.append(f"  {k}: {100 * s:.1f} % of the variance")
        return lines

    def __str__(self) -> str:
        return "\n".join(self.summary())

    def to_folder(self, out) -> list[Path]:
        """result.json, scene.json, <scene>-noise.csv (the PSD per source) and summary.txt."""
        out = Path(out)
        paths = write_result(out, self.record(), self.scene)
        header = ["frequency_Hz", "gain_V_per_N"] + [f"{k.replace(' ', '_')}_V2_per_Hz" for k in self.psd]
        cols = [self.freqs, self.gain] + list(self.psd.values())
        return paths + [write_csv(out / f"{self.scene.name}-noise.csv", header, cols), write_summary(out, self.summary())]
