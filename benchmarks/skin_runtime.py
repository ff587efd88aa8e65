"""The skin runtime's cost per simulator step, as a real-time factor at 1 kHz.

Skins of the thesis PZT array (taxel.skin.build on the 2D section, mesh 1 mm / 0.2 mm,
500 Mohm readout) with 3 x 3 and 8 x 8 taxels (the same taxel, pitch and margin),
discretized at dt = 1 ms. Side by side in one process on one thread:

- "previous step": the runtime before the diagonal form (`Previous` below, its code
  kept here unchanged: about twenty numpy calls per step, the state update on the
  modal blocks of Ad);
- "step": SkinRuntime.step (checks on, the default) and with check=False;
- "step, E envs": one call of SkinRuntime(envs=E).step for E environments, per environment;
- "run": SkinRuntime.run over the whole history (contacts known ahead), per step.

Each case: 2000 steps with random contacts (the same for every case), noise off unless
said; 7 rounds, each round running every case once (so a change of the machine's load
hits all cases alike); the median over rounds of the process's CPU time per step
(time.process_time: on a machine shared by more processes than cores the wall time
counts the waits for a core, the CPU time does not) and of the wall time. Real-time
factor = dt / (CPU time per step). The previous and the new step's voltages are
compared (largest difference of the peak) so the speed-up is for the same output.

    MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python benchmarks/skin_runtime.py
"""

from __future__ import annotations

import os
import time

import numpy as np

import taxel
from taxel.skin.build import build
from taxel.skin.runtime import SkinRuntime

STEPS, ROUNDS = 2000, 7


class Previous:
    """The runtime's step before the diagonal form (commit 1dad508), noise off, no ADC."""

    def __init__(self, model):
        self.model = model
        self.Bd = model.Bd[:, 0][:, None]
        self.Cd, self.Dd = model.Cd[0], float(model.Dd[0, 0])
        self.g = model.gain.ravel()
        self.shape = (model.rows, model.cols)
        self.x = np.zeros((model.Ad.shape[0], model.taxels))
        A = model.Ad
        self.main = np.diag(A)[:, None].copy()
        self.up, self.low = np.diag(A, 1)[:, None].copy(), np.diag(A, -1)[:, None].copy()

    def loads(self, points, forces):
        forces = np.asarray(forces, float).reshape(-1)
        p = np.asarray(points, float).reshape(-1, 2)
        G = self.model.influence(np.concatenate([p[:, 0], p[:, 1]]))
        m = len(forces)
        gx, gy = G[:m, :self.model.cols], G[m:, :self.model.rows]
        return ((gy * forces[:, None]).T @ gx).ravel() * self.g

    def step(self, points, forces):
        u = self.loads(points, forces)
        x = self.x
        v = self.Cd @ x + self.Dd * u
        new = self.main * x + self.Bd * u
        new[:-1] += self.up * x[1:]
        new[1:] += self.low * x[:-1]
        self.x = new
        s = self.model.saturation
        return (np.clip(v, -s, s) if np.isfinite(s) else v).reshape(self.shape)


def skin(n: int):
    sc = taxel.load("thesis-pzt-3x3-2d").replace(**{"readout.circuit": "resistor", "mesh.size": "1 mm",
                                                     "mesh.piezo_size": "0.2 mm", "array.rows": n, "array.cols": n})
    return build(sc, dt=1e-3, checks=0)


def cases(sk):
    """name -> (contacts, a function running STEPS steps of it on (P, F), the environments it steps)."""
    def stepping(make, envs=1):
        def go(P, F):
            rt = make()
            if envs > 1:                                   # E environments, each its own contacts
                P, F = np.repeat(P[:, None], envs, axis=1), np.repeat(F[:, None], envs, axis=1)
            for k in range(STEPS):
                rt.step(P[k], F[k])
        return go

    def running(P, F):
        SkinRuntime(sk).run(P, F)

    return {
        "previous step": (1, stepping(lambda: Previous(sk)), 1),
        "step": (1, stepping(lambda: SkinRuntime(sk)), 1),
        "step, check=False": (1, stepping(lambda: SkinRuntime(sk, check=False)), 1),
        "previous step, 10 contacts": (10, stepping(lambda: Previous(sk)), 1),
        "step, 10 contacts": (10, stepping(lambda: SkinRuntime(sk)), 1),
        "step, noise on": (1, stepping(lambda: SkinRuntime(sk, noise=True, seed=1)), 1),
        "step, 4 envs": (1, stepping(lambda: SkinRuntime(sk, envs=4, check=False), 4), 4),
        "step, 16 envs": (1, stepping(lambda: SkinRuntime(sk, envs=16, check=False), 16), 16),
        "run": (1, running, 1),
        "run, 10 contacts": (10, running, 1),
    }


def same_output(sk) -> float:
    """Largest |previous - new| of the previous step's peak over STEPS steps with 3 contacts."""
    rng = np.random.default_rng(2)
    span = (sk.cols - 1) * sk.pitch
    P, F = rng.uniform(0, span, (STEPS, 3, 2)), rng.uniform(0, 1, (STEPS, 3))
    old, new = Previous(sk), SkinRuntime(sk)
    a = np.array([old.step(p, f) for p, f in zip(P, F)])
    b = np.array([new.step(p, f) for p, f in zip(P, F)])
    return float(np.abs(a - b).max() / np.abs(a).max())


def main():
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    print("| skin | modes (states) | case | CPU time per step | real-time factor at 1 kHz | "
          "wall time per step | speed-up on the previous step (CPU) |")
    print("|---|---|---|---|---|---|---|")
    for n in (3, 8):
        sk = skin(n)
        rng = np.random.default_rng(0)
        span = (sk.cols - 1) * sk.pitch
        data = {m: (rng.uniform(0, span, (STEPS, m, 2)), rng.uniform(0, 1, (STEPS, m))) for m in (1, 10)}
        table = cases(sk)
        cpu, wall = {k: [] for k in table}, {k: [] for k in table}
        for _ in range(ROUNDS):
            for name, (m, go, envs) in table.items():
                t0, c0 = time.perf_counter(), time.process_time()
                go(*data[m])
                cpu[name].append((time.process_time() - c0) / STEPS / envs)
                wall[name].append((time.perf_counter() - t0) / STEPS / envs)
        rt = SkinRuntime(sk)
        modes = f"{rt._lam.shape[0]} ({sk.Ad.shape[0]})" if rt.diagonal else f"dense ({sk.Ad.shape[0]})"
        med = {k: float(np.median(v)) for k, v in cpu.items()}
        for name in table:
            c, w = med[name], float(np.median(wall[name]))
            ref = med["previous step, 10 contacts" if "10 contacts" in name else "previous step"]
            print(f"| {n} x {n} | {modes} | {name} | {1e6 * c:.1f} us | {sk.dt / c:.0f} x | {1e6 * w:.1f} us | "
                  f"{ref / c:.1f} |")
        print(f"(the {n} x {n} skin: previous and new step differ by {same_output(sk):.1e} of the peak; "
              f"load average now {os.getloadavg()[0]:.2f})")


if __name__ == "__main__":
    main()
