"""How baseline drift biases the fitted time constant of a step response.

    python benchmarks/measure_step_drift.py [--seeds 8]

The thesis bench with a resistor across the taxel (tau = 1.7 s and 3.1 s with the
lumped model's C_p), the simulator's default white noise and hum, a 1 N or 2 N
step, 12 s records, tau_spread 0; the drift (a low-passed random walk, rms over the
record) at 0, 0.5, 2 and 20 mV (20 mV is the simulator's default). Printed: the
largest and the rms relative error of tau over the seeds, and the mean half-width
of the Jacobian's 95 % interval (studies.measure.analyze.fit_step), which assumes
white residuals: where the error exceeds it, the interval under-covers.
"""

from __future__ import annotations

import argparse

import numpy as np

import taxel
from taxel.analyses import lumped_model
from taxel.studies.measure import analyze, events
from taxel.studies.measure.rig import load_rig, parse_rig
from taxel.studies.measure.simulate import Settings, simulate


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=8)
    args = ap.parse_args()
    scene = taxel.load("thesis-pzt-3x3-2d")
    C_p = lumped_model(scene).C_p
    bench = load_rig("thesis-bench").model_dump()
    print("tau_s  step_N  drift_mV  max_err_%  rms_err_%  ci95_halfwidth_%")
    for tau in (1.7, 3.1):
        rig = parse_rig({**bench, "conditioning": {"circuit": "resistor", "R": f"{float(tau / C_p)!r} ohm",
                                                   "notch": True}}, si_numbers=True)
        ch = rig.chains()["taxel_1_1"]
        for amp in (1.0, 2.0):
            for drift in (0.0, 0.5e-3, 2e-3, 20e-3):
                err, ci = [], []
                for seed in range(args.seeds):
                    tr = simulate(rig, scene, Settings(input="step", seconds=12, amplitude=amp, tau_spread=0.0,
                                                       drift_V=drift, crosstalk=False, seed=seed))
                    v = rig.counts_to_volts(tr.frames.counts.astype(float)) / rig.volts_per_si()[None]
                    rec = events.Record(tr.t, v[:, 9], v[:, :9], rig.names[:9],
                                        [c.taxel for c in rig.ordered()[:9]], rig.sampling.rate)
                    f = analyze.fit_step(rec, 4, ch, C_p)
                    err.append(f.tau_s / tau - 1)
                    ci.append((f.tau_ci95_s[1] - f.tau_ci95_s[0]) / 2 / tau)
                err = np.array(err)
                print(f"{tau:5.1f}  {amp:6.1f}  {1e3 * drift:8.1f}  {100 * np.abs(err).max():9.2f}  "
                      f"{100 * np.sqrt(np.mean(err ** 2)):9.2f}  {100 * np.mean(ci):16.2f}")


if __name__ == "__main__":
    main()
