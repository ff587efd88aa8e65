"""The noise budget of a scene's taxel through its readout chain (and a rig's ADC).

The transfer function H(f) (readout output per newton of the pressed taxel) and
each electrode's capacitance C_p(f) (complex: its imaginary part is the piezo's
dielectric loss, -Im C_p = C' tan(delta)) come from the frequency analysis: the FEM
sweep (taxel.analyses.solves.dynamic.frequency, model = "fem") or the 3-DoF lumped model
(model = "lumped", tan(delta) of the material or [dynamics] dielectric_loss). The
noise sources, their transfer to the readout output and the ADC are fem.readout; the
numbers of the chain are the scene's [readout] (e_n, i_n, e_n_corner, swing,
temperature, hum, mains_frequency, and its ADC [readout.adc]: bits, range, offset,
enob, rate), with a rig the conditioning of the pressed taxel's channel, the channel
gain and the ADC (bits, range, rate) of the rig, which replace the scene's.

Assumptions: the sources are uncorrelated (their PSDs add); the chain is linear up
to saturation; the ADC's quantisation is white (the noise spans several codes);
the band is the scene's readout.band (default taxel.scene.NOISE_BAND, 1-300 Hz: what human
mechanoreceptors sense), cut at the rig's (or the scene's ADC's) Nyquist frequency; a scene's
ADC without a rate samples at twice the band's top.
"""

from __future__ import annotations

import numpy as np

from taxel.fem import readout as N
from taxel.fem.readout import Readout
from taxel.scene import Scene, SceneError
from taxel.analyses.model.problem import readout as scene_readout
from taxel.analyses.model.problem import scene_materials
from taxel.analyses.results.noise import NoiseResult
from taxel.analyses.results.outputs import table
from taxel.analyses.results.base import pressed_name


def chain(scene: Scene, rig=None, channel: str | None = None, band=None) -> N.Chain:
    """The noise chain of a scene (and rig: the conditioning of `channel`, its gain and the ADC;
    without one the scene's [readout.adc], sampling at twice the top of `band` when it names no rate)."""
    r = scene.readout
    amp = N.Amplifier(r.e_n, r.i_n, r.e_n_corner or 0.0, r.swing, r.temperature)
    hum = N.Hum(tuple(r.hum), r.mains_frequency)
    if rig is None:
        return N.Chain(scene_readout(scene), amp, scene_adc(scene, band), hum)
    chains = rig.chains()
    name = channel if channel in chains else next(iter(chains))
    gain = next((c.volts_per_si for c in rig.ordered() if c.name == name), 1.0)
    adc = N.Converter(rig.adc.bits, rig.adc.range[0], rig.adc.range[1], rig.sampling.rate, gain, rig.adc.offset)
    return N.Chain(chains[name].readout(), amp, adc, hum)


def scene_adc(scene: Scene, band=None) -> N.Converter | None:
    """The scene's ADC ([readout.adc]) as fem.readout's Converter; None without one. Its rate:
    the table's, else twice the top of `band` (else of the scene's readout.band)."""
    a = scene.readout.adc
    if a is None:
        return None
    lo, hi = a.range
    rate = a.rate or 2 * (band[1] if band is not None else scene.readout.band[1])
    return N.Converter(a.bits, lo, hi, rate, 1.0, (lo + hi) / 2 if a.offset is None else a.offset, a.enob)


def with_readout(scene: Scene, r: Readout) -> Scene:
    """The scene with the readout chain `r` (a rig's conditioning)."""
    return scene.replace(**{f"readout.{k}": v for k, v in
                            dict(circuit=r.circuit, R=r.R, C_f=r.C_f, R_f=r.R_f, R_i=r.R_i, C_c=r.C_c, notch=r.notch,
                                 notch_frequency=r.notch_frequency, notch_bandwidth=r.notch_bandwidth).items()})


def band_of(scene: Scene, rig=None, band=None) -> tuple[float, float]:
    """The band (Hz): given, else the scene's readout.band, cut at the rig's (or readout.adc's) Nyquist."""
    lo, hi = band if band is not None else scene.readout.band
    if rig is not None:
        hi = min(hi, rig.sampling.rate / 2)
    elif scene.readout.adc is not None and scene.readout.adc.rate:
        hi = min(hi, scene.readout.adc.rate / 2)
    if not 0 < lo < hi:
        raise SceneError(f"noise band {lo:g}-{hi:g} Hz is empty; set readout.band = [low, high] "
                         "(below the rig's or readout.adc's Nyquist frequency)")
    return float(lo), float(hi)


def transfer(scene: Scene, band, model: str = "fem", points: int = 60):
    """(freqs, H (nf, na) V/N of the readout, C_p (nf, na) complex F, electrode names, label) over the band."""
    s = scene.replace(**{"analysis.type": "frequency", "analysis.f_min": band[0], "analysis.f_max": band[1],
                         "analysis.points": points, "analysis.spacing": "log"})
    if model == "lumped":
        from taxel.analyses.solves.dynamic import lumped_response
        lr = lumped_response(s)
        C = np.full((len(lr.freqs), 1), lr.model.C_p * (1 - 1j * loss_tangent(s)))
        return lr.freqs, lr.output[:, None], C, ["lumped"], lr.label
    if model != "fem":
        raise SceneError(f"noise model '{model}': use fem or lumped")
    from taxel.analyses.solves.dynamic import frequency
    fr = frequency(s.replace(**{"analysis.method": "reduced"}))
    C = np.einsum("fii->fi", fr.port.C)
    return fr.freqs, fr.output, C, list(fr.names), fr.label


def noise(scene: Scene, rig=None, band=None, model: str = "fem", points: int = 2000) -> NoiseResult:
    """The noise budget of the scene's pressed taxel (see the module docstring): each
    source's PSD over the band on `points` log-spaced frequencies, the rms noise at
    every electrode, and the minimum detectable force, SNR and dynamic range."""
    band = band_of(scene, rig, band)
    ch = chain(scene, rig, _pressed_hint(scene), band)
    f_sw, H, C, names, label = transfer(with_readout(scene, ch.readout), band, model)
    return _budget(scene, rig, ch, band, f_sw, H, C, names, label, points)


def _pressed_hint(scene: Scene) -> str | None:
    if scene.array is None:
        return None
    from taxel.schema import electrode_name
    return electrode_name(*scene.load.taxel)


def _budget(scene, rig, ch, band, f_sw, H, C, names, label, points) -> NoiseResult:
    """The NoiseResult from the transfer H (nf, na) V/N and the capacitances C (nf, na) on f_sw."""
    k = names.index(pressed_name(scene, names)) if pressed_name(scene, names) else 0
    f = N.grid(band, points)
    lf, lsw = np.log(f), np.log(f_sw)
    gain = np.interp(lf, lsw, np.abs(H[:, k]))

    def cap(j):
        return np.interp(lf, lsw, C[:, j].real) + 1j * np.interp(lf, lsw, C[:, j].imag)
    psd = ch.psd(f, cap(k))
    lines = [(fl, p) for fl, p in ch.hum.lines(ch.readout) if band[0] <= fl <= band[1]]
    hum = sum(p for _, p in lines)
    per = {n: float(np.sqrt(sum(N.band_power(f, v, band) for v in ch.psd(f, cap(j)).values()) + hum))
           for j, n in enumerate(names)}
    sat, by = ch.saturation()
    return NoiseResult(scene, band, f, psd, lines, gain, names[k], per, float(scene.load.force or 1.0), sat,
                       by if np.isfinite(sat) else "none", label, getattr(rig, "name", None))


DESIGN_NOISE = tuple(table("design_noise"))       # min_detectable_force, snr, dynamic_range


def design_noise(scene: Scene, outputs: dict, rig=None, band=None, force: float | None = None) -> dict:
    """{min_detectable_force (N), snr (dB at `force`, default the scene's load force),
    dynamic_range (dB)} of a design from its static solve's named outputs (sensitivity,
    charge_sensitivity) through the quasi-static budget; None values when the design has
    no pressed taxel's voltage and charge, or its chain cannot be built."""
    s, q = outputs.get("sensitivity"), outputs.get("charge_sensitivity")
    if not s or not q:
        return dict.fromkeys(DESIGN_NOISE)
    try:
        nr = quasi_static_noise(scene, s, q, rig, band)
    except SceneError:
        return dict.fromkeys(DESIGN_NOISE)
    o = nr.outputs()
    return {"min_detectable_force": o["min_detectable_force"],
            "snr": nr.snr_at(force) if force is not None else o["snr"], "dynamic_range": o["dynamic_range"]}


def loss_tangent(scene: Scene) -> float:
    """The piezo's dielectric loss tangent: [dynamics] dielectric_loss, else the material's (0 without one)."""
    if scene.dynamics.dielectric_loss is not None:
        return float(scene.dynamics.dielectric_loss)
    return float(scene_materials(scene)[scene.array.piezo].tan_delta or 0.0)


def quasi_static_noise(scene: Scene, sensitivity: float, charge_sensitivity: float, rig=None, band=None,
                       points: int = 400) -> NoiseResult:
    """The noise budget from one static solve: the cheap route for design outputs.

    Below the first mechanical resonance the taxel is a charge source: per newton its
    short-circuit charge is the static Q_sc = `charge_sensitivity` (C/N) and its
    open-circuit voltage the static V_oc = `sensitivity` (V/N), so its capacitance is
    C_p = |Q_sc / V_oc| (with the other electrodes as in the static solve) and the
    readout output per newton is the circuit's H(f) for that source (fem.readout.readout
    on a one-port PortResponse of C = C_p kappa(f) and Q_sc / kappa_c(f)); kappa and
    kappa_c are the permittivity's and the piezo stiffness's causal laws (fem.constitution,
    the FEM's own): the capacitance falls with frequency and carries the dielectric loss,
    and a stiffer piezo gives less charge per newton. The noise sources, the ADC and the hum are those of
    `noise` (fem.readout). Valid where the band sits well below the resonance (a few kHz
    and up for a silicone-covered taxel; tests/test_robust.py checks it against the FEM
    sweep of `noise` on the thesis PZT taxel). Cost: no solve beyond the static one.
    """
    from taxel.fem import readout
    from taxel.fem.dynamics import PortResponse
    if not sensitivity or not charge_sensitivity:
        raise SceneError("quasi-static noise: the pressed taxel has no voltage or no charge; press a taxel")
    band = band_of(scene, rig, band)
    ch = chain(scene, rig, _pressed_hint(scene), band)
    from taxel.fem import constitution
    C_p = abs(charge_sensitivity / sensitivity)
    f = np.geomspace(band[0], band[1], 200)
    # the permittivity's causal law, as the FEM's (fem.dynamics): C_p is the relaxed
    # (static) capacitance, C(f) = C_p kappa(f), which falls with frequency and carries the loss
    mat = scene_materials(scene)[scene.array.piezo]
    qm_loss = scene.dynamics.piezo_loss if scene.dynamics.piezo_loss is not None else (1 / mat.Qm if mat.Qm else 0.0)
    law = constitution.relaxation_law({"dielectric": (loss_tangent(scene), True), "elastic": (qm_loss, False)})
    k = [law.kappa(2 * np.pi * fi) for fi in f]
    kappa = np.array([x.get("dielectric", 1.0) for x in k])
    stiff = np.array([x.get("elastic", 1.0) for x in k])      # the piezo stiffens: less charge per newton
    C = (C_p * kappa)[:, None]
    port = PortResponse(f, (abs(sensitivity) / (stiff * kappa))[:, None], (1 / C)[:, :, None], ["taxel"],
                        "quasi-static", 0.0)
    H = readout.readout(port, ch.readout)
    name = _pressed_hint(scene) or "taxel"
    return _budget(scene, rig, ch, band, f, H, C, [name], ch.readout.label + " (quasi-static)", points)
