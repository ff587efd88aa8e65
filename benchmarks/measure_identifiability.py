"""Can the bench's 0-100 Hz chirp identify the silicone's modulus scale and loss factor?

    python benchmarks/measure_identifiability.py

The lumped model of the thesis taxel (thesis-pzt-3x3-2d): the relative change of
its short-circuit charge per newton |Q_sc / F| at 1, 10, 50 and 100 Hz when the
silicone's shear and bulk moduli are scaled by 1.2, and when its loss factor goes
from the scene's 0.1 to 0.12 (+20 %). Measured H1 is good to about 1 % on this
bench (tests/test_measure_analyze.py): a parameter whose effect is far below that
cannot be fitted from it, which is why studies.measure.calibrate does not fit them.
"""

from __future__ import annotations

import dataclasses

import numpy as np

import taxel
from taxel.analyses.dynamic import damping
from taxel.analyses.problem import scene_materials
from taxel.fem import lumped


def main():
    sc = taxel.load("thesis-pzt-3x3-2d")
    a, mats = sc.array, scene_materials(sc)
    sil, f = mats[a.silicone], np.array([1.0, 10.0, 50.0, 100.0])

    def q(scale=1.0, loss=None):
        s2 = dataclasses.replace(sil, mu=sil.mu * scale, K=sil.K * scale)
        d = damping(sc) if loss is None else dataclasses.replace(damping(sc), silicone_loss=loss)
        lm = lumped.taxel_model(mats[a.piezo], s2, a.taxel_width, a.silicone_above, a.piezo_thickness,
                                a.silicone_below, sc.load.force, d)
        return np.abs(lm.Q_sc(f) / lm.force)
    q0 = q()
    print("f_Hz   modulus_x1.2_%   loss_0.1_to_0.12_%")
    for fi, dm, dl in zip(f, 100 * (q(1.2) / q0 - 1), 100 * (q(loss=0.12) / q0 - 1)):
        print(f"{fi:5.0f}  {dm:15.2e}  {dl:18.2e}")


if __name__ == "__main__":
    main()
