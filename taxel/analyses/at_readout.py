"""A static solve's numbers at the readout: what the scene's [readout] chain outputs per
newton, the crosstalk there, the minimum detectable force and the force range to
saturation, beside the open-circuit values (a scene that names a readout is never
answered with open-circuit numbers alone).

A static solve gives, per newton, each taxel's open-circuit voltage V_oc and
short-circuit charge Q_sc. Below the first mechanical resonance a taxel is a charge
source of capacitance C_p = |Q_sc / V_oc| (taxel.analyses.noise.quasi_static_noise,
checked there against the FEM sweep), so the readout's output per newton is the
circuit's |H(f)| on that source (fem.readout):

  readout sensitivity   S_r = max over the band of |H(f)| of the pressed taxel, V/N (a
                        charge amplifier: |Q_sc| / C_f between its corners; a resistor:
                        V_oc above its RC corner; the notch cuts its band);
  crosstalk at the readout: the largest neighbour's |H| over the pressed taxel's, at
                        the frequency of S_r (each taxel on its own channel);
  charge sensitivity    |Q_sc| / F of the pressed taxel, C/N;
  minimum detectable force: the band's rms noise of every source of the chain (amplifier,
                        resistors, dielectric loss, hum; the ADC with a rig) over the band
                        sensitivity (taxel.analyses.noise: NoiseResult);
  force range           the amplifier's swing (or the ADC's full scale) over S_r, N.

The band is the scene's [analysis] f_min..f_max. Assumptions: linear taxel (a press is
linearised at its operating force: secant V/N); the quasi-static source (the band well
below the first resonance); uncorrelated noise sources.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from taxel.scene import SceneError
from taxel.units import engineering

# the named outputs a static result adds when its scene names a readout (SI)
READOUT_OUTPUTS = {"readout_sensitivity": "V/N", "readout_crosstalk": "", "min_detectable_force": "N",
                   "force_range": "N"}


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


def at_readout(scene, voltages: dict[str, float], charges: dict[str, float], pressed: str | None,
               force: float, rig=None) -> AtReadout | None:
    """The readout's numbers of a static solve (per-taxel open-circuit voltages and
    short-circuit charges at `force`, N), None when the scene's readout is the open
    circuit, or there is no pressed taxel with a voltage and a charge."""
    from taxel.analyses.noise import quasi_static_noise
    if scene.readout.circuit == "open" or scene.array is None:
        return None
    force = abs(force) or 1.0
    p = pressed if pressed in voltages else next(iter(voltages), None)
    if p is None or not voltages[p] or not charges.get(p):
        return None
    try:
        nr = quasi_static_noise(scene, voltages[p] / force, charges[p] / force, rig)
        k = int(np.argmax(nr.gain))
        crosstalk = None
        others = [n for n in voltages if n != p and voltages[n] and charges.get(n)]
        if others:
            crosstalk = max(float(quasi_static_noise(scene, voltages[n] / force, charges[n] / force, rig).gain[k])
                            for n in others) / float(nr.gain[k])
    except SceneError:
        return None
    return AtReadout(nr.label, tuple(nr.band), float(nr.freqs[k]), float(nr.gain[k]), abs(charges[p]) / force,
                     crosstalk, nr.min_detectable_force, nr.saturation_force, nr.saturation_by)
