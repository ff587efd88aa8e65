"""Which physical scales can the bench's chirp identify on the FEM (the reduced model's
physics)? studies.measured.physical: the pressed taxel of thesis-pzt-3x3-2d through
the thesis bench's chain (charge amplifier, notch), the 0-100 Hz chirp's coherent
band as the calibration uses it (3-98 Hz every 1 Hz, 35-65 Hz around the notch left
out), a relative error of 1 % per frequency (the bench's H1 accuracy) and 0.1 %.

Printed: each scale's largest sensitivity |d log H / d log p|, its Cramer-Rao relative
standard deviation with all six free, and the correlation matrix; then the same with
the confounded scales fixed (gain and C_f), which is what a fit can report.

    MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/physical_identifiability.py
"""

from __future__ import annotations

import numpy as np

import taxel
from taxel.studies.bench.rig import load_rig
from taxel.studies.measured.physical import NAMES, Physical
from taxel.studies.measured.silicone import identifiability


def show(idf, sigma):
    for i, p in enumerate(idf.names):
        print(f"  {100 * sigma:5.1f} %  {p:8s} sensitivity {idf.sensitivity[i]:9.2e}  Cramer-Rao sd "
              f"{100 * idf.sd_rel[i]:10.3g} %")


def main():
    scene = taxel.load("thesis-pzt-3x3-2d")
    readout = load_rig("thesis-bench").chains()["taxel_1_1"].readout()
    freqs = np.arange(3.0, 99.0)
    freqs = freqs[np.abs(freqs - 50) >= 15]
    model = Physical(scene, readout)
    eta = next(e for k, (e, _) in model.dm.relax.losses.items() if k.startswith("shear:"))
    theta = {"piezo": 1.0, "gain": 1.0, "modulus": 1.0, "loss": eta, "R_f": 1.0, "C_f": 1.0}
    for sigma in (0.01, 0.001):
        idf = identifiability(model, theta, freqs, sigma)
        print(f"\nall six free ({', '.join(NAMES)}), sigma {100 * sigma:g} %:")
        show(idf, sigma)
        print("  correlation:\n" + "\n".join("    " + f"{n:8s}" + " ".join(f"{c:+.3f}" for c in row)
                                            for n, row in zip(idf.names, idf.correlation)))
        free = {k: v for k, v in theta.items() if k not in ("gain", "C_f")}
        fixed = identifiability(lambda f, **kw: model(f, **kw), free, freqs, sigma)
        print("  gain and C_f fixed (piezo then carries the gain, R_f the time constant):")
        show(fixed, sigma)
        print("  correlation:\n" + "\n".join("    " + f"{n:8s}" + " ".join(f"{c:+.3f}" for c in row)
                                            for n, row in zip(fixed.names, fixed.correlation)))


if __name__ == "__main__":
    main()
