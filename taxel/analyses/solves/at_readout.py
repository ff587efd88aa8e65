"""A static solve's numbers at the readout: what the scene's [readout] chain outputs per
newton, the crosstalk there, the minimum detectable force and the force range to
saturation, beside the open-circuit values (a scene that names a readout is never
answered with open-circuit numbers alone).

A static solve gives, per newton, each taxel's open-circuit voltage V_oc and
short-circuit charge Q_sc. Below the first mechanical resonance a taxel is a charge
source of capacitance C_p = |Q_sc / V_oc| (taxel.analyses.solves.noise.quasi_static_noise,
checked there against the FEM sweep), so the readout's output per newton is the
circuit's |H(f)| on that source (fem.readout):

  readout sensitivity   S_r = max over the band of |H(f)| of the pressed taxel, V/N (a
                        charge amplifier: |Q_sc| / C_f between its corners; a resistor:
                        V_oc above its RC corner; the notch cuts its band);
  crosstalk at the readout: the largest neighbour's |H| over the pressed taxel's, at
                        the frequency of S_r (each taxel on its own channel);
  charge sensitivity    |Q_sc| / F of the pressed taxel, C/N;
  minimum detectable force: the band's rms noise of every source of the chain (amplifier,
                        resistors, dielectric loss, hum; the ADC's quantisation: [readout.adc] or a rig's) over the band
                        sensitivity (taxel.analyses.solves.noise: NoiseResult);
  force range           the smaller of the amplifier's swing and the ADC's half range over S_r, N.

The band is the scene's readout.band (default 1-300 Hz, taxel.scene.NOISE_BAND). Assumptions: linear taxel (a press is
linearised at its operating force: secant V/N); the quasi-static source (the band well
below the first resonance); uncorrelated noise sources.
"""

from __future__ import annotations

import numpy as np

from taxel.analyses.results.readout import AtReadout
from taxel.scene import SceneError

__all__ = ["AtReadout", "at_readout"]


def at_readout(result, rig=None) -> AtReadout | None:
    """The readout's numbers of a static solve (a StaticResult: per-taxel open-circuit
    voltages and short-circuit charges at its applied force), None when the scene's
    readout is the open circuit, or there is no pressed taxel with a voltage and a charge."""
    from taxel.analyses.solves.noise import quasi_static_noise
    scene = result.scene
    if scene.readout.circuit == "open" or scene.array is None:
        return None
    taxels = {k: e for k, e in result.electrodes.items() if e.state != "reference"}
    voltages = {k: e.voltage for k, e in taxels.items()}
    charges = {k: e.short_circuit_charge for k, e in taxels.items()}
    force = abs(result.applied_force) or 1.0
    p = result.pressed if result.pressed in voltages else next(iter(voltages), None)
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
