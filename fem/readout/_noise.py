r"""Noise of the readout chain: each source's power spectral density at the readout output.

All densities are one-sided (V^2/Hz, integrated over 0..infinity gives the
variance), referred to the readout output (the amplifier output, or the electrode
voltage for the open and resistor circuits), through the same circuits as
fem.readout. The electrode is the taxel's capacitance C_p(f), complex when the
piezo has a dielectric loss tan(delta): C_p = C' (1 - i tan(delta)), so its
admittance is Y_p = i w C_p = i w C' + G with G = w C' tan(delta) (fem.dynamics
builds eps (1 - i tan(delta))). By the fluctuation-dissipation theorem every
conductance G at temperature T is a current-noise source of density 4 k T G
(Nyquist); a resistor R one of 4 k T / R (or a voltage source 4 k T R in series).

Charge amplifier (fem.readout.charge_amplifier; the input node of the source
Z_s = 1 / (s (C_p + C_c)) [the cable C_c lossless] joined to the virtual ground
through R_i; feedback Z_f = R_f / (1 + s R_f C_f); Z_in = R_i + Z_s):

    e_n  (op-amp voltage noise, at + input)   |1 + Z_f / Z_in|^2 e_n^2      the noise gain
    i_n  (op-amp current noise, at - input)   |Z_f|^2 i_n^2
    R_f  (4 k T / R_f across R_f)              |Z_f|^2 4 k T / R_f
    R_i  (4 k T R_i in series)                 |Z_f / Z_in|^2 4 k T R_i
    dielectric loss (4 k T G across C_p)       |Z_f Z_s / Z_in|^2 4 k T G

At mid band (R_i -> 0, w R_f C_f >> 1) the noise gain is 1 + (C_p + C_c) / C_f.
The signal takes the path of the dielectric noise: a current s Q_sc into the node.

Resistor R across the electrode (and open circuit: R -> infinity), read by a
buffer of noise e_n, i_n: the node admittance is Y = 1 / R + s C_p, and

    R    4 k T / (R |Y|^2)      (integrates to k T / C_p for a lossless C_p: kT/C)
    dielectric loss   4 k T G / |Y|^2;   i_n  i_n^2 / |Y|^2;   e_n   e_n^2

The amplifier's voltage noise has an optional 1/f corner f_c: e_n^2 (1 + f_c / f).
The notch (when on) multiplies every analog source by |H_notch|^2.

ADC quantisation: a uniform error of one LSB Delta = span / 2^bits has variance
Delta^2 / 12, spread evenly over 0..fs/2 (white; valid when the signal spans many
codes): density Delta^2 / (6 fs) at the ADC, / gain^2 at the readout output. An ADC
of effective number of bits `enob` (below bits: its own noise and distortion) is
taken as the quantisation of span / 2^enob.
Mains hum: lines at the mains frequency and its odd harmonics, of peak amplitude
A_k at the readout output before the notch; after it A_k |H_notch(f_k)|, power
(A_k |H_notch|)^2 / 2 each.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.constants import k as K_B

from ._circuits import Readout, notch


@dataclass(frozen=True)
class Amplifier:
    """The op-amp (or the buffer) and the temperature of the chain, SI units."""

    e_n: float = 18e-9            # V/sqrt(Hz), white voltage noise (TL072 datasheet: 18 nV/sqrt(Hz) at 1 kHz)
    i_n: float = 10e-15           # A/sqrt(Hz), current noise (TL072: 0.01 pA/sqrt(Hz))
    e_n_corner: float = 0.0       # Hz, 1/f corner of e_n (0: white)
    swing: float = 12.0           # V, the largest linear output (+-)
    temperature: float = 296.15   # K


@dataclass(frozen=True)
class Converter:
    """The ADC behind the readout: bits over [lo, hi] at `rate`, `gain` V at the ADC per V out."""

    bits: int = 16
    lo: float = -10.0
    hi: float = 10.0
    rate: float = 2000.0
    gain: float = 1.0
    offset: float = 0.0
    enob: float | None = None     # effective number of bits (None: bits, an ideal quantiser)

    @property
    def lsb(self) -> float:
        return (self.hi - self.lo) / 2 ** self.bits

    def psd(self) -> float:
        """Quantisation noise density at the readout output, V^2/Hz (white to rate / 2):
        (span / 2^enob)^2 / 12 over rate / 2, enob = bits for an ideal ADC."""
        step = (self.hi - self.lo) / 2 ** (self.enob if self.enob is not None else self.bits)
        return step ** 2 / 12 / (self.rate / 2) / self.gain ** 2

    @property
    def full_scale(self) -> float:
        """The largest |readout output| the ADC codes without clipping, V."""
        return min(self.hi - self.offset, self.offset - self.lo) / self.gain


@dataclass(frozen=True)
class Hum:
    """Mains pickup at the readout output before the notch: peak amplitudes (V) of the
    mains frequency and its odd harmonics (1, 3, 5, ...)."""

    amplitudes: tuple[float, ...] = ()
    frequency: float = 50.0

    def lines(self, r: Readout) -> list[tuple[float, float]]:
        """(frequency Hz, power V^2) of each line after the notch."""
        out = []
        for k, a in enumerate(self.amplitudes):
            f = (2 * k + 1) * self.frequency
            h = abs(notch(np.array([2 * np.pi * f]), r.notch_frequency, r.notch_bandwidth)[0]) if r.notch else 1.0
            out.append((f, (a * h) ** 2 / 2))
        return out


@dataclass(frozen=True)
class Chain:
    """Everything that makes noise at one readout output."""

    readout: Readout
    amplifier: Amplifier = Amplifier()
    adc: Converter | None = None
    hum: Hum = field(default_factory=Hum)

    def psd(self, f, C_p) -> dict[str, np.ndarray]:
        """Each source's one-sided PSD at the readout output (V^2/Hz) at frequencies f (Hz),
        for an electrode of complex capacitance C_p (F; scalar or one per frequency)."""
        f = np.asarray(f, float)
        C_p = np.broadcast_to(np.asarray(C_p, complex), f.shape)
        r, a = self.readout, self.amplifier
        s = 2j * np.pi * f
        kT4 = 4 * K_B * a.temperature
        G = (s * C_p).real                          # the dielectric loss conductance w C' tan(delta)
        en2 = a.e_n ** 2 * (1 + a.e_n_corner / f)
        out: dict[str, np.ndarray] = {}
        if r.circuit == "charge_amplifier":
            Zs = 1 / (s * (C_p + r.C_c))
            Zf = r.R_f / (1 + s * r.R_f * r.C_f)
            Zin = r.R_i + Zs
            out["amplifier e_n"] = np.abs(1 + Zf / Zin) ** 2 * en2
            out["amplifier i_n"] = np.abs(Zf) ** 2 * a.i_n ** 2
            out["R_f"] = np.abs(Zf) ** 2 * kT4 / r.R_f
            out["R_i"] = np.abs(Zf / Zin) ** 2 * kT4 * r.R_i
            out["dielectric loss"] = np.abs(Zf * Zs / Zin) ** 2 * kT4 * G
        else:
            Y = s * C_p + (1 / r.R if r.circuit == "resistor" else 0.0)
            out["amplifier e_n"] = en2 + 0 * f
            out["amplifier i_n"] = a.i_n ** 2 / np.abs(Y) ** 2
            if r.circuit == "resistor":
                out["R"] = kT4 / r.R / np.abs(Y) ** 2
            out["dielectric loss"] = kT4 * G / np.abs(Y) ** 2
        if r.notch:
            h2 = np.abs(notch(2 * np.pi * f, r.notch_frequency, r.notch_bandwidth)) ** 2
            out = {k: v * h2 for k, v in out.items()}
        if self.adc is not None:
            out["ADC quantisation"] = np.where(f <= self.adc.rate / 2, self.adc.psd(), 0.0)
        return out

    def saturation(self) -> tuple[float, str]:
        """(the largest |readout output| before clipping, V; what clips: amplifier or ADC)."""
        amp = self.amplifier.swing if self.readout.circuit == "charge_amplifier" else np.inf
        adc = self.adc.full_scale if self.adc is not None else np.inf
        return (float(adc), "ADC") if adc <= amp else (float(amp), "amplifier")


def band_power(f, psd, band) -> float:
    """The integral of a PSD sampled at f over band = (f1, f2), V^2 (trapezoid on the
    samples inside, the ends interpolated in log f)."""
    f = np.asarray(f, float)
    lo, hi = band
    inside = (f > lo) & (f < hi)
    x = np.concatenate([[lo], f[inside], [hi]])
    y = np.concatenate([[np.interp(np.log(lo), np.log(f), psd)], psd[inside], [np.interp(np.log(hi), np.log(f), psd)]])
    return float(np.trapezoid(y, x))


def grid(band, points: int = 2000) -> np.ndarray:
    """Log-spaced frequencies over a band (Hz); the hum lines are added as lines, not sampled here."""
    return np.geomspace(band[0], band[1], points)
