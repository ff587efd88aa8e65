"""Localization against the ADC's white noise, on the simulated rig, on and between taxels.

    python benchmarks/measure_localization_noise.py [--seconds 60]

The thesis bench (charge amplifiers, notch), the 3x3 PZT scene, presses of
0.3-1.5 N, half on the taxels in turn and half at random points of the array
(Settings.between = 0.5; the taxels' weights from the FEM influence functions of
position), the simulator's defaults but the white noise. Printed per noise level:
the largest-taxel correct rate (on-taxel presses), and for both estimators
(studies.measured.localize) the position error (mm rms) and force error (% rms) on
the taxels, between them (inside the outer taxels' centres) and beyond the outer
taxels, each taxel's sensitivity calibrated on its 1st, 3rd, ... on-taxel press and
the rest scored; position errors are rms, then medians (mm). The pressed taxel's
peak is about 0.2-0.7 V.
"""

from __future__ import annotations

import argparse

import taxel
from taxel.studies.measured import events
from taxel.analyses.surface.influence import influence
from taxel.studies.measured.localize import PressEvent, largest_taxel, model_based
from taxel.studies.bench.rig import load_rig
from taxel.studies.bench.signals import Settings, simulate


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=60.0)
    args = ap.parse_args()
    scene, rig = taxel.load("thesis-pzt-3x3-2d"), load_rig("thesis-bench")
    infl = influence(scene)
    print("noise_mV  largest_%  method         on_mm  on_F_%  between_mm  between_F_%  beyond_mm  beyond_F_%  "
          "on_median  between_median  beyond_median")
    for noise in (1e-3, 3e-3, 10e-3, 30e-3, 100e-3):
        tr = simulate(rig, scene, Settings(input="presses", seconds=args.seconds, noise_V=noise, seed=12, between=0.5))
        v = rig.counts_to_volts(tr.frames.counts.astype(float)) / rig.volts_per_si()[None]
        rec = events.Record(tr.t, v[:, 9], v[:, :9], rig.names[:9], [c.taxel for c in rig.ordered()[:9]],
                            rig.sampling.rate)
        pos = tr.params["positions"]
        presses = [PressEvent(p["t"], tuple(pos[p["position"]]), tuple(p["xy_mm"])) for p in tr.params["presses"]]
        loc = model_based(rec, presses, infl, loc=largest_taxel(rec, presses, pitch_mm=1e3 * infl.pitch))
        for name, sc in (("largest taxel", loc.largest), ("model-based", loc.model)):
            cells, med = [], []
            for c in ("on", "between", "edge"):
                r = sc[c].record() if c in sc else {"presses": 0}
                cells += [r["position_error_mm"]["rms"], r["force_error_pct"]["rms"]] if r["presses"] else [float("nan")] * 2
                med.append(r["position_error_mm"]["median"] if r["presses"] else float("nan"))
            print(f"{1e3 * noise:8.0f}  {100 * loc.correct_rate:9.1f}  {name:13s}  {cells[0]:5.3f}  {cells[1]:6.2f}  "
                  f"{cells[2]:10.3f}  {cells[3]:11.2f}  {cells[4]:9.3f}  {cells[5]:10.2f}  "
                  f"{med[0]:9.3f}  {med[1]:14.3f}  {med[2]:13.3f}", flush=True)


if __name__ == "__main__":
    main()
