"""The readout's numbers of a static solve (the data; computed by
taxel.analyses.solves.at_readout): the readout's V/N, crosstalk, minimum detectable force and
force range, beside the open-circuit values."""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from taxel.units import engineering


@dataclass(frozen=True)
class AtReadout:
    """The pressed taxel's numbers through the readout chain (SI)."""
    label: str                      # what the chain outputs, in words
    band: tuple[float, float]       # Hz
    frequency: float                # where the readout sensitivity peaks, Hz
    sensitivity: float              # V/N at the readout output
    charge_sensitivity: float       # C/N (short-circuit)
    crosstalk: float | None         # at the readout
    min_detectable_force: float     # N rms in the band
    force_range: float              # N to saturation (inf without a clipping stage)
    saturation_by: str              # "amplifier", "ADC" or "none"

    def outputs(self) -> dict[str, float | None]:
        return {"readout_sensitivity": self.sensitivity, "readout_crosstalk": self.crosstalk,
                "min_detectable_force": self.min_detectable_force,
                "force_range": self.force_range if np.isfinite(self.force_range) else None}

    def lines(self, open_circuit: dict) -> list[str]:
        """For a person: the readout's numbers beside the open-circuit ones."""
        xt = "" if self.crosstalk is None else (
            f", crosstalk {100 * self.crosstalk:.3g} %" + (f" (open circuit {100 * open_circuit['crosstalk']:.3g} %)"
                                                           if open_circuit.get("crosstalk") is not None else ""))
        rng = (f"saturates at {engineering(self.force_range, 'N', 3)} ({self.saturation_by})"
               if np.isfinite(self.force_range) else "no clipping stage")
        return [f"at the readout ({self.label}, {self.band[0]:g}-{self.band[1]:g} Hz): "
                f"{engineering(self.sensitivity, 'V/N', 3)} at {self.frequency:.3g} Hz (open circuit "
                f"{engineering(abs(open_circuit['sensitivity']), 'V/N', 3)}), "
                f"{engineering(self.charge_sensitivity, 'C/N', 3)}{xt}",
                f"  minimum detectable force {engineering(self.min_detectable_force, 'N', 3)} rms in the band; {rng}"]

    def record(self) -> dict:
        rec = asdict(self)
        rec["band"] = list(self.band)
        rec["force_range"] = self.force_range if np.isfinite(self.force_range) else None
        return rec

    @classmethod
    def from_record(cls, rec: dict | None) -> "AtReadout | None":
        if not rec:
            return None
        return cls(**{**rec, "band": tuple(rec["band"]),
                      "force_range": rec["force_range"] if rec["force_range"] is not None else float("inf")})
