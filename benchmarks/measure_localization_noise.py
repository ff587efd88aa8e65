"""Localization against the ADC's white noise, on the simulated rig.

    python benchmarks/measure_localization_noise.py [--seconds 60]

The thesis bench (charge amplifiers, notch), the 3x3 PZT scene with its FEM
crosstalk, presses of 0.3-1.5 N on random taxels (the simulator's defaults but
the white noise): the largest-taxel correct rate and the model-based estimator's
position error (mm, rms and max) and force error (%, rms), the estimator's
sensitivities calibrated on the even presses and scored on the odd ones
(studies.measure.localize). The pressed taxel's peak is about 0.2-0.7 V.
"""

from __future__ import annotations

import argparse

import numpy as np

import taxel
from taxel.studies.measure import events
from taxel.studies.measure.influence import influence
from taxel.studies.measure.localize import largest_taxel, model_based
from taxel.studies.measure.rig import load_rig
from taxel.studies.measure.simulate import Settings, simulate


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=60.0)
    args = ap.parse_args()
    scene, rig = taxel.load("thesis-pzt-3x3-2d"), load_rig("thesis-bench")
    infl = influence(scene)
    print("noise_mV  presses  largest_taxel_%  position_rms_mm  position_max_mm  force_rms_%")
    for noise in (1e-3, 10e-3, 30e-3, 100e-3, 300e-3):
        tr = simulate(rig, scene, Settings(input="presses", seconds=args.seconds, noise_V=noise, seed=11))
        v = rig.counts_to_volts(tr.frames.counts.astype(float)) / rig.volts_per_si()[None]
        rec = events.Record(tr.t, v[:, 9], v[:, :9], rig.names[:9], [c.taxel for c in rig.ordered()[:9]],
                            rig.sampling.rate)
        presses = [(p["t"], tuple(tr.params["positions"][p["position"]])) for p in tr.params["presses"]]
        loc = largest_taxel(rec, presses)
        mb = model_based(rec, presses, infl).record()
        print(f"{1e3 * noise:8.0f}  {loc.matched:7d}  {100 * loc.correct_rate:15.1f}  "
              f"{mb['position_error_mm']['rms']:15.3f}  {mb['position_error_mm']['max']:15.3f}  "
              f"{mb['force_error_pct']['rms']:11.2f}")


if __name__ == "__main__":
    main()
