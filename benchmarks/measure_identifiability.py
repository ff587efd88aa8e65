"""Can the bench identify the silicone's modulus scale and loss factor? The bench's
0-100 Hz chirp (taxel voltage per newton) against a chirp with the actuator's travel
recorded (force per metre of travel).

    python benchmarks/measure_identifiability.py

1. The lumped model of the thesis taxel (thesis-pzt-3x3-2d): the relative change of
   |Q_sc / F| at 1, 10, 50 and 100 Hz when the silicone's moduli are scaled by 1.2,
   and when its loss factor goes from the scene's 0.1 to 0.12 (+20 %).
2. Fisher information (studies.measured.silicone.identifiability) at the truth of the
   tests (modulus scale 1.2, loss factor 0.12, gain 0.85, chain tau scale 1.1), over
   10-96 Hz every 1 Hz with independent relative errors of 1 % per frequency (the
   bench's H1 accuracy, tests/test_measure_analyze.py) and of 0.1 % (the travel
   record's random error at its coherence 0.99998 over 14 Welch segments):
     bench chirp  V/F through the charge amplifier and notch (35-65 Hz left out):
                  parameters modulus scale, loss factor, gain, tau scale;
     travel chirp F/delta: modulus scale, loss factor.
   Printed: each parameter's largest sensitivity |d log H / d log p| over the band,
   its Cramer-Rao relative standard deviation, and the modulus-loss correlation.
"""

from __future__ import annotations


import numpy as np

import taxel
from taxel.analyses.solves.dynamic import damping
from taxel.studies.measured.calibrate import scaled_chain
from taxel.studies.measured.frf import lumped_frf
from taxel.studies.bench.rig import load_rig
from taxel.studies.measured.silicone import compliance, identifiability, scaled_model


def main():
    sc = taxel.load("thesis-pzt-3x3-2d")
    f = np.array([1.0, 10.0, 50.0, 100.0])

    def q(scale=1.0, loss=None):
        lm = scaled_model(sc, scale, loss)
        return np.abs(lm.Q_sc(f) / lm.force)
    q0 = q()
    eta = damping(sc).silicone_loss
    print("1. |Q_sc / F| of the lumped taxel")
    print("f_Hz   modulus_x1.2_%   loss_+20%_%")
    for fi, dm, dl in zip(f, 100 * (q(1.2) / q0 - 1), 100 * (q(loss=1.2 * eta) / q0 - 1)):
        print(f"{fi:5.0f}  {dm:15.2e}  {dl:13.2e}")
    readout = load_rig("thesis-bench").chains()["taxel_1_1"].readout()
    freqs = np.arange(10.0, 97.0)
    bench = freqs[np.abs(freqs - 50) >= 15]

    def chirp(fr, modulus_scale, loss_factor, gain, tau_scale):
        r, _ = scaled_chain(readout, tau_scale)
        return gain * lumped_frf(scaled_model(sc, modulus_scale, loss_factor), r, fr)

    def travel(fr, modulus_scale, loss_factor):
        return 1.0 / compliance(scaled_model(sc, modulus_scale, loss_factor), fr)
    truth = {"modulus_scale": 1.2, "loss_factor": 0.12}
    print("\n2. Fisher information, 10-96 Hz")
    print("input         sigma_%  parameter       max_sensitivity  cramer_rao_sd_%   corr(modulus, loss)")
    for name, model, th, fr in (("bench chirp", chirp, {**truth, "gain": 0.85, "tau_scale": 1.1}, bench),
                                ("travel chirp", travel, truth, freqs)):
        for sigma in (0.01, 0.001):
            idf = identifiability(model, th, fr, sigma)
            for i, p in enumerate(idf.names):
                c = f"{idf.correlation[0, 1]:+.3f}" if i == 0 else ""
                print(f"{name:12s}  {100 * sigma:7.1f}  {p:14s}  {idf.sensitivity[i]:15.2e}  "
                      f"{100 * idf.sd_rel[i]:15.3g}   {c}")


if __name__ == "__main__":
    main()
