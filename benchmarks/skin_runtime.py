"""The skin runtime's cost per simulator step, as a real-time factor at 1 kHz.

Skins of the thesis PZT array (taxel.skin.build on the 2D section, mesh 1 mm / 0.2 mm,
500 Mohm readout) with 3 x 3 and 8 x 8 taxels (the same taxel, pitch and margin),
discretized at dt = 1 ms. Each case runs 2000 steps of SkinRuntime.step in one process
on one thread; median of 7 repeats of the wall time and of the process's CPU time
(time.process_time: on a machine shared by more processes than cores the wall time
counts the waits for a core, the CPU time does not); real-time factor = dt / (CPU
time per step), and the same from the wall time beside it.
Cases side by side: 1 and 10 contact points, noise off and on, and the state update
elementwise on the modal blocks (the runtime's) against a dense Ad @ x product.

    MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/skin_runtime.py
"""

from __future__ import annotations

import os
import time

import numpy as np

import taxel
from taxel.skin.build import build
from taxel.skin.runtime import SkinRuntime

STEPS, REPEATS = 2000, 7


def skin(n: int):
    sc = taxel.load("thesis-pzt-3x3-2d").replace(**{"readout.circuit": "resistor", "mesh.size": "1 mm",
                                                     "mesh.piezo_size": "0.2 mm", "array.rows": n, "array.cols": n})
    t0 = time.perf_counter()
    sk = build(sc, dt=1e-3, checks=0)
    return sk, time.perf_counter() - t0


def per_step(sk, contacts: int, noise: bool, dense: bool = False) -> tuple[float, float]:
    rng = np.random.default_rng(0)
    span = (sk.cols - 1) * sk.pitch
    P = rng.uniform(0, span, (STEPS, contacts, 2))
    F = rng.uniform(0, 1, (STEPS, contacts))
    wall, cpu = [], []
    for _ in range(REPEATS):
        rt = SkinRuntime(sk, noise=noise, seed=1)
        rt.tridiagonal = rt.tridiagonal and not dense
        t0, c0 = time.perf_counter(), time.process_time()
        for k in range(STEPS):
            rt.step(P[k], F[k])
        wall.append((time.perf_counter() - t0) / STEPS)
        cpu.append((time.process_time() - c0) / STEPS)
    return float(np.median(wall)), float(np.median(cpu))


def main():
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    print("| skin | states | contacts | noise | state update | CPU time per step | real-time factor at 1 kHz | "
          "wall time per step | (from the wall time) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for n in (3, 8):
        sk, built = skin(n)
        for contacts, noise, dense in ((1, False, False), (1, False, True), (10, False, False), (1, True, False),
                                       (10, True, False)):
            w, c = per_step(sk, contacts, noise, dense)
            print(f"| {n} x {n} | {sk.Ad.shape[0]} | {contacts} | {'on' if noise else 'off'} | "
                  f"{'dense' if dense else 'modal blocks'} | {1e6 * c:.1f} us | {sk.dt / c:.0f} x | "
                  f"{1e6 * w:.1f} us | {sk.dt / w:.0f} x |")
        print(f"(the {n} x {n} skin built in {built:.0f} s, cached FEM presses and reduced model reused if present)")


if __name__ == "__main__":
    main()
