"""The noise floor as design outputs: min_detectable_force, snr and dynamic_range of a
design, from its static solve (no extra FEM solve).

An optimization (or a tolerance study) asks for them in an optional table:

    [resolution]
    rig = "thesis-bench"              # the rig's conditioning, channel gain and ADC (default: none,
                                      # the scene's [readout] alone)
    band = ["1 Hz", "100 Hz"]          # the force's band (default: the scene's readout.band, 1-300 Hz)
    force = "10 mN"                    # the force of the snr (rms; default: the scene's load force)

How: taxel.analyses.solves.noise.quasi_static_noise. The static solve gives the pressed
taxel's open-circuit sensitivity S = V_oc / F (V/N) and charge sensitivity
Q_sc / F (C/N); their ratio is its capacitance C_p. Below the first mechanical
resonance the readout output per newton is the circuit's transfer H(f) of that
charge source, and each noise source's PSD depends only on the circuit and C_p
(fem.readout). Then (taxel.analyses.results.noise):

    min_detectable_force = noise_rms / S_B        (N rms, SNR 1; S_B = rms of |H| over the band)
    snr = 20 log10(force / min_detectable_force)   (dB)
    dynamic_range = 20 log10(F_sat / sqrt 2 / min_detectable_force)   (dB; F_sat = swing / max|H|)

The default band is the scene's readout.band (taxel.scene.NOISE_BAND, 1-300 Hz: what human
mechanoreceptors sense, as `taxel solve`'s); it stays below the silicone layer's first
resonance (about 400 Hz for the thesis PZT taxel, where the FEM's |H| starts to rise); a band
through it needs the FEM sweep (taxel.analyses.solves.noise.noise), which costs a frequency
analysis per design. tests/test_robust.py checks the quasi-static numbers against that sweep.
"""

from __future__ import annotations

from typing import Any

from taxel.analyses.results.outputs import table
from taxel.schema import Strict
from taxel.scene import Scene
from taxel import units as U

NOISE_METRICS = tuple(table("design_noise"))      # min_detectable_force, snr, dynamic_range


class Resolution(Strict):
    """The [resolution] table of an optimization: where the noise floor is taken."""
    rig: str | None = None
    band: tuple[Any, Any] | None = None      # None: the scene's readout.band
    force: Any = None


def band_hz(res: Resolution) -> tuple[float, float] | None:
    """The band in Hz (None: the scene's readout.band); a ValueError naming the key otherwise."""
    if res.band is None:
        return None
    try:
        lo, hi = (U.in_unit(v, "Hz")[0] for v in res.band)
    except U.UnitError as exc:
        raise ValueError(f"resolution.band: {exc}; write e.g. band = [\"1 Hz\", \"100 Hz\"]") from None
    if not 0 < lo < hi:
        raise ValueError(f"resolution.band: {res.band} is empty; give 0 < low < high")
    return lo, hi


def force_n(res: Resolution, scene: Scene) -> float:
    """The snr's force (N): the table's, else the scene's load force."""
    if res.force is None:
        return float(scene.load.force or 1.0)
    try:
        f = U.in_unit(res.force, "N")[0]
    except U.UnitError as exc:
        raise ValueError(f"resolution.force: {exc}; write e.g. force = \"10 mN\"") from None
    if not f > 0:
        raise ValueError(f"resolution.force must be positive, got {res.force!r}")
    return f


def load_rig_of(res: Resolution):
    """The rig of the table (None without one)."""
    if res.rig is None:
        return None
    from taxel.studies.bench.rig import load_rig
    try:
        return load_rig(res.rig)
    except (OSError, ValueError) as exc:
        raise ValueError(f"resolution.rig: {str(exc).splitlines()[0]}") from None


def noise_metrics(scene: Scene, outputs: dict, res: Resolution, rig=None) -> dict:
    """{min_detectable_force (N), snr (dB), dynamic_range (dB)} of a design from its static
    solve's named outputs (sensitivity, charge_sensitivity); None values when it has none."""
    from taxel.analyses.solves.noise import design_noise
    return design_noise(scene, outputs, rig, band_hz(res), force_n(res, scene))
