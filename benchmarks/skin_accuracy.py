"""The skin runtime against the FEM transient, at and between taxels, and the influence's
interpolation error.

The thesis PZT 3 x 3 array (2D section, mesh 1 mm / 0.2 mm, 500 Mohm readout), a
taxel-wide flat probe of 1 N at the middle taxel's centre (x = pitch) and halfway to
its neighbour (x = 1.5 pitch), three histories of the scene's [analysis] (a step with a
5 ms rise, a 10 ms half-sine impulse, a 0-100 Hz chirp), the FEM transient
(taxel.solve, Newmark) and the runtime (first-order hold) at the same dt, 1 ms and
0.25 ms. Error: max over the row's taxels and time of |v_runtime - v_FEM| over the
FEM's peak |v|. Then the skin's influence error at 4 FEM presses halfway between knots.

    MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/skin_accuracy.py
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import taxel
from taxel.skin.build import build

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from skin_transient import COARSE, fem_and_runtime  # noqa: E402

HISTORIES = {"step": {"analysis.duration": 0.3, "analysis.rise": 0.005},
             "impulse": {"analysis.duration": 0.1, "analysis.width": 0.01},
             "chirp": {"analysis.duration": 1.0, "analysis.f0": 0.0, "analysis.f1": 100.0}}


def error(scene, sk, x, history) -> float:
    v, V = fem_and_runtime(scene, sk, x, history, HISTORIES)
    return float(np.abs(v - V).max() / np.abs(V).max())


def main():
    scene = taxel.load("thesis-pzt-3x3-2d").replace(**COARSE)
    print("| press | history | error at dt 1 ms | error at dt 0.25 ms |")
    print("|---|---|---|---|")
    skins = {dt: build(scene, dt=dt, checks=4 if dt == 1e-3 else 0) for dt in (1e-3, 2.5e-4)}
    for where, k in (("on the middle taxel", 1.0), ("halfway to its neighbour", 1.5)):
        for h in HISTORIES:
            e = [error(scene, sk, k * sk.pitch, h) for sk in skins.values()]
            print(f"| {where} | {h} | {100 * e[0]:.2f} % | {100 * e[1]:.2f} % |")
    sk = skins[1e-3]
    print(f"influence error at {len(sk.check_points)} FEM presses between knots: {sk.influence_error:.2e} of W's peak; "
          f"h: {sk.Ad.shape[0]} states, dynamics error {sk.dynamics_error:.1e} against the sweep (to {sk.band:.3g} Hz)")


if __name__ == "__main__":
    main()
