"""How baseline drift biases the fitted time constant of a step response, and
whether the fit's 95 % interval covers the truth: the white-residual fit against
the drift-robust one (studies.measured.step, noise "white" and "drift").

    python benchmarks/measure_step_drift.py [--seeds 40] [--quick]

The thesis bench with a resistor across the taxel (tau = 1.7 s and 3.1 s with the
lumped model's C_p), the simulator's default white noise and hum, a 2 N step
(0.3 V), 12 s records, tau_spread 0; the drift (a low-passed random walk, rms over
the record) at 0, 0.5, 2, 5 and 20 mV (20 mV is the simulator's default). Printed
per fit: the rms relative error of tau over the seeds, the median half-width of
the 95 % interval, the fraction of seeds whose interval contains the truth
(coverage; 95 % if honest), and the Cramer-Rao floor 2 q sqrt(tau) / a of one
step (studies.measured.step), q the random walk's intensity estimated from the
simulator's own drift path (its rms increment over 1 s, of 20 ms means).
"""

from __future__ import annotations

import argparse

import numpy as np

import taxel
from taxel.analyses import lumped_model
from taxel.studies.measured import events
from taxel.studies.bench.rig import load_rig, parse_rig
from taxel.studies.bench.signals import Settings, simulate
from taxel.studies.measured.step import fit_step


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=40)
    ap.add_argument("--quick", action="store_true", help="tau 1.7 s only, drift 0.5 and 20 mV")
    args = ap.parse_args()
    scene = taxel.load("thesis-pzt-3x3-2d")
    C_p = lumped_model(scene).C_p
    bench = load_rig("thesis-bench").model_dump()
    print("tau_s  drift_mV  fit    rms_err_%  ci95_halfwidth_%  coverage_%  floor_%")
    for tau in (1.7,) if args.quick else (1.7, 3.1):
        rig = parse_rig({**bench, "conditioning": {"circuit": "resistor", "R": f"{float(tau / C_p)!r} ohm",
                                                   "notch": True}}, si_numbers=True)
        ch = rig.chains()["taxel_1_1"]
        for drift in (0.5e-3, 20e-3) if args.quick else (0.0, 0.5e-3, 2e-3, 5e-3, 20e-3):
            res = {"white": ([], [], []), "drift": ([], [], [])}
            floor = []
            for seed in range(args.seeds):
                s = Settings(input="step", seconds=12, amplitude=2.0, tau_spread=0.0, drift_V=drift,
                             crosstalk=False, seed=seed)
                tr = simulate(rig, scene, s)
                v = rig.counts_to_volts(tr.frames.counts.astype(float)) / rig.volts_per_si()[None]
                rec = events.Record(tr.t, v[:, 9], v[:, :9], rig.names[:9],
                                    [c.taxel for c in rig.ordered()[:9]], rig.sampling.rate)
                for kind, (err, ci, cov) in res.items():
                    f = fit_step(rec, 4, ch, C_p, noise=kind)
                    err.append(f.tau_s / tau - 1)
                    ci.append((f.tau_ci95_s[1] - f.tau_ci95_s[0]) / 2 / tau)
                    cov.append(f.tau_ci95_s[0] <= tau <= f.tau_ci95_s[1])
                if drift:
                    m = int(rig.sampling.rate) // 50                      # 20 ms means: no hum, little noise
                    d = v[:, 4] - tr.clean_volts[:, 4]
                    d = d[:len(d) // m * m].reshape(-1, m).mean(axis=1)
                    q = np.std(d[50:] - d[:-50])                          # V over 1 s
                    a = abs(tr.clean_volts[:, 4]).max()
                    floor.append(2 * q * np.sqrt(tau) / a)
            for kind, (err, ci, cov) in res.items():
                err = np.array(err)
                fl = f"{100 * np.median(floor):7.2f}" if floor else "      -"
                print(f"{tau:5.1f}  {1e3 * drift:8.1f}  {kind:5s}  {100 * np.sqrt(np.mean(err ** 2)):9.2f}  "
                      f"{100 * np.median(ci):16.2f}  {100 * np.mean(cov):10.0f}  {fl}", flush=True)


if __name__ == "__main__":
    main()
