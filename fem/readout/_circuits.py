r"""Readout circuits on the electrodes, exact for a linear taxel.

Port relation of the finite-element model at angular frequency w (fem.dynamics):
charges and voltages of the active electrodes obey Q = Q_sc + C V, with
Q_sc = -C V_oc. A circuit fixes a second relation between Q and V; together
they give the electrode voltages and currents exactly (Norton equivalent):

* open circuit:  Q = 0,  V = V_oc.
* resistor R to ground on every electrode: the current leaving an electrode is
  V / R = -dQ/dt, so Q = -V / (i w R) and V = -(C + I / (i w R))^-1 Q_sc.
  One electrode: V / Q_sc = -i w R / (1 + i w R C)   (docs/materials.md, up to sign).
  A step of force decays with tau = R C.
* charge amplifier (TI SLOA033A): the input is a virtual ground through R_i, with
  cable capacitance C_c at the electrode:
      V_out = -(Q_sc / C_f) (i w R_f C_f / (1 + i w R_f C_f)) / (1 + i w R_i (C + C_c))
  lower cutoff 1 / (2 pi R_f C_f) = 19.4 Hz, upper 1 / (2 pi R_i (C_p + C_c)) (docs/materials.md
  errata: the cable capacitance belongs in it).
* 50 Hz notch: the second-order Butterworth band-stop (the order-1 prototype
  transformed): H = (s^2 + w0^2) / (s^2 + (w0 / Qn) s + w0^2), Qn = f0 / bandwidth.

The resistor is also coupled into the field equations (fem.dynamics.transient,
and fem.dynamics.coupled_resistor) where the load changes the mechanics; the tests
check that both routes agree.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np


@dataclass(frozen=True)
class Readout:
    """The conditioning chain on every active electrode (SI units)."""

    circuit: Literal["open", "resistor", "charge_amplifier"] = "open"
    R: float = 500e6            # resistor: the input resistance, ohm
    C_f: float = 820e-12        # charge amplifier feedback capacitor, F (TI SLOA033A)
    R_f: float = 10e6           # feedback resistor, ohm
    R_i: float = 10e3           # input resistor, ohm
    C_c: float = 100e-12        # cable capacitance, F
    notch: bool = False         # the thesis's 50 Hz second-order Butterworth band-stop
    notch_frequency: float = 50.0
    notch_bandwidth: float = 10.0

    @property
    def label(self) -> str:
        """What the chain outputs, in words."""
        what = {"open": "open-circuit voltage", "resistor": f"voltage across {self.R:.3g} ohm",
                "charge_amplifier": "charge-amplifier output"}[self.circuit]
        return what + (" + 50 Hz notch" if self.notch else "")


def resistor(V_oc, C, omega, R):
    """Electrode voltages (nf, na) with a resistor R on each electrode."""
    na = V_oc.shape[1]
    Q_sc = -np.einsum("fij,fj->fi", C, V_oc)
    Y = C + np.eye(na)[None] / (1j * omega[:, None, None] * R)
    return -np.linalg.solve(Y, Q_sc[..., None])[..., 0]


def charge_amplifier(V_oc, C, omega, C_f, R_f, R_i, C_c):
    """Amplifier output voltages (nf, na): one amplifier per electrode."""
    Q_sc = -np.einsum("fij,fj->fi", C, V_oc)
    Cp = np.einsum("fii->fi", C)
    s = 1j * omega[:, None]
    return -(Q_sc / C_f) * (s * R_f * C_f / (1 + s * R_f * C_f)) / (1 + s * R_i * (Cp + C_c))


def notch(omega, f0=50.0, bandwidth=10.0):
    """Second-order Butterworth band-stop around f0 (transfer function values)."""
    w0 = 2 * np.pi * f0
    s = 1j * omega
    return (s ** 2 + w0 ** 2) / (s ** 2 + (w0 * bandwidth / f0) * s + w0 ** 2)


def readout(port, r: Readout) -> np.ndarray:
    """What the readout chain outputs (nf, na), for a PortResponse `port` (per newton)."""
    omega = 2 * np.pi * port.freqs
    if r.circuit == "open":
        out = port.V_oc
    elif r.circuit == "resistor":
        out = resistor(port.V_oc, port.C, omega, r.R)
    else:
        out = charge_amplifier(port.V_oc, port.C, omega, r.C_f, r.R_f, r.R_i, r.C_c)
    if r.notch:
        out = out * notch(omega, r.notch_frequency, r.notch_bandwidth)[:, None]
    return out


def amplifier_in_time(t, Q_sc, C_p, r):
    """Charge-amplifier output over time for short-circuit charges Q_sc (nt, na):
    the same transfer function, simulated (scipy.signal.lsim)."""
    from scipy import signal         # imported where used: scipy.signal costs 0.5 s at start-up
    out = np.zeros_like(Q_sc)
    for k in range(Q_sc.shape[1]):
        Ct = C_p[k] + r.C_c
        num = [-r.R_f, 0.0]
        den = np.polymul([r.R_f * r.C_f, 1.0], [r.R_i * Ct, 1.0])
        out[:, k] = signal.lsim((num, den), Q_sc[:, k] - Q_sc[0, k], t)[1]
    return out


def in_time(t, Q_sc, C_p, r):
    """What the chain outputs over time (nt, na) for short-circuit charges Q_sc (nt, na) of
    quasi-static charge sources of capacitances C_p (na,), from rest at Q_sc[0]: the open
    circuit V = -Q / C_p, the resistor's V / Q_sc = -s R / (1 + s R C_p) (scipy.signal.lsim),
    the charge amplifier (`amplifier_in_time`); then the notch, if the chain has one."""
    from scipy import signal
    t, Q = np.asarray(t, float), np.asarray(Q_sc, float)
    C_p = np.broadcast_to(np.asarray(C_p, float), Q.shape[1:])
    dQ = Q - Q[0]
    if r.circuit == "open":
        out = -dQ / C_p
    elif r.circuit == "resistor":
        out = np.column_stack([signal.lsim(([-r.R, 0.0], [r.R * C_p[k], 1.0]), dQ[:, k], t)[1]
                               for k in range(Q.shape[1])])
    else:
        out = amplifier_in_time(t, Q, C_p, r)
    return notch_in_time(t, out, r) if r.notch else out


def notch_in_time(t, x, r):
    """The band-stop applied to sampled signals (nt, na), as a digital filter."""
    from scipy import signal
    fs = 1.0 / (t[1] - t[0])
    lo, hi = r.notch_frequency - r.notch_bandwidth / 2, r.notch_frequency + r.notch_bandwidth / 2
    if hi >= fs / 2:
        raise ValueError(f"the notch needs a time step below {1 / (2 * hi):.3g} s; set analysis.dt smaller")
    sos = signal.iirfilter(1, [lo, hi], btype="bandstop", ftype="butter", fs=fs, output="sos")
    return signal.sosfilt(sos, x, axis=0)
