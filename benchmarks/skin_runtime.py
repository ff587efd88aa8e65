"""The skin runtime's cost per simulator step, as a real-time factor at 1 kHz, and the
MuJoCo adapter's cost beside mj_step.

Skins of the thesis PZT array (taxel.skin.build on the 2D section, mesh 1 mm / 0.2 mm,
500 Mohm readout) with 3 x 3 and 8 x 8 taxels (the same taxel, pitch and margin),
discretized at dt = 1 ms. Side by side in one process on one thread:

- "step": SkinRuntime.step (checks on, the default), with check=False, with forces
  (m, 3) (shear: the three planes of W gathered), with 10 contacts, with the noise on;
- "step, E envs": one call of SkinRuntime(envs=E).step for E environments, per environment;
- "run": SkinRuntime.run over the whole history (contacts known ahead), per step;
- "step, idle": SkinRuntime.step with zero forces after 3000 idle steps (the modes decayed
  towards zero: without the runtime's flush of subnormal numbers this cost 110 us);
- "step, full order": SkinRuntime.step with order_tol = 0 (every mode of the file kept:
  the balanced cut off), to show what the cut buys;
- "numpy floor": the fewest numpy calls a step can be (the state update and the output
  product alone: the input row written, np.matmul, .real.copy, two in-place updates),
  what the interpreter costs whatever the loads are;
- MuJoCo (the 3 x 3 skin on taxel.skin.mujoco's fingertip, the flat probe pressed):
  mj_step alone, and mj_step + MujocoSkin.step (contacts, patches, the runtime).

Each case: 2000 steps with random contacts (the same for every case), noise off unless
said, timed without the runtime's construction (copying an 8 x 8 skin's influence table
and cutting its modes take about 20 ms: 10 us a step over 2000 steps, which this
benchmark counted before); 7 rounds, each round running every case once (so a change of the machine's load
hits all cases alike); the median over rounds of the process's CPU time per step
(time.process_time: on a machine shared by more processes than cores the wall time
counts the waits for a core, the CPU time does not). Real-time factor = dt / (CPU time
per step). Writes benchmarks/results/skin_runtime.json (docs/benchmarks.md's table is
printed from it).

    MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python benchmarks/skin_runtime.py
"""

from __future__ import annotations

import hashlib
import json
import os
import time
from pathlib import Path

import numpy as np

import taxel
from taxel.skin.build import build
from taxel.skin.model import SkinModel
from taxel.skin.runtime import SkinRuntime

STEPS, ROUNDS = 2000, 7


def skin(n: int) -> SkinModel:
    """The n x n skin, built once and kept in the user's cache (keyed by the scene and the code version)."""
    from taxel.analyses.solves.crosstalk import cache_dir
    from taxel.analyses.solves.version import code_version
    from taxel.schema import to_data
    sc = taxel.load("thesis-pzt-3x3-2d").replace(**{"readout.circuit": "resistor", "mesh.size": "1 mm",
                                                     "mesh.piezo_size": "0.2 mm", "array.rows": n, "array.cols": n})
    key = hashlib.sha256(json.dumps([to_data(sc), code_version(), "skin-bench"], sort_keys=True).encode()).hexdigest()
    path = cache_dir() / f"skin-bench-{key[:16]}.npz"
    try:
        return SkinModel.load(path)
    except ValueError:
        sk = build(sc, dt=1e-3, checks=0)
        path.parent.mkdir(parents=True, exist_ok=True)
        sk.save(path)
        return sk


def timed(loop) -> tuple[float, float]:
    """(CPU, wall) seconds of loop() (the runtime built before: its construction is not a step's cost)."""
    t0, c0 = time.perf_counter(), time.process_time()
    loop()
    return time.process_time() - c0, time.perf_counter() - t0


def cases(sk):
    """name -> (contacts, force shape, a function timing STEPS steps of it on (P, F): (CPU, wall) s,
    the environments it steps)."""
    def stepping(make, envs=1):
        def go(P, F):
            rt = make()
            if envs > 1:                                   # E environments, each its own contacts
                P, F = np.repeat(P[:, None], envs, axis=1), np.repeat(F[:, None], envs, axis=1)

            def loop():
                for k in range(STEPS):
                    rt.step(P[k], F[k])
            return timed(loop)
        return go

    def idle(P, F):
        rt = SkinRuntime(sk)
        for k in range(200):
            rt.step(P[k], F[k])
        z = np.zeros(F.shape[1:])
        for _ in range(3000):
            rt.step(P[0], z)

        def loop():
            for k in range(STEPS):
                rt.step(P[k], z)
        return timed(loop)

    def running(P, F):
        rt = SkinRuntime(sk)
        return timed(lambda: rt.run(P, F))

    def floor(P, F):
        rt = SkinRuntime(sk, check=False)
        u = np.ones(sk.taxels)

        def loop():
            for _ in range(STEPS):
                rt._ureal[...] = u
                np.matmul(rt._w, rt._Z, out=rt._out)
                rt._out.real.copy()
                rt._modes *= rt._lam
                rt._modes += rt._urep
        return timed(loop)

    return {
        "step": (1, "normal", stepping(lambda: SkinRuntime(sk)), 1),
        "step, check=False": (1, "normal", stepping(lambda: SkinRuntime(sk, check=False)), 1),
        "step, forces (m, 3)": (1, "vector", stepping(lambda: SkinRuntime(sk, check=False)), 1),
        "step, idle": (1, "normal", idle, 1),
        "step, full order": (1, "normal", stepping(lambda: SkinRuntime(sk, order_tol=0.0)), 1),
        "step, 10 contacts": (10, "normal", stepping(lambda: SkinRuntime(sk)), 1),
        "step, noise on": (1, "normal", stepping(lambda: SkinRuntime(sk, noise=True, seed=1)), 1),
        "step, 4 envs": (1, "normal", stepping(lambda: SkinRuntime(sk, envs=4, check=False), 4), 4),
        "step, 16 envs": (1, "normal", stepping(lambda: SkinRuntime(sk, envs=16, check=False), 16), 16),
        "run": (1, "normal", running, 1),
        "numpy floor (state update and output only)": (1, "normal", floor, 1),
    }


def mujoco_cost(sk) -> dict:
    """CPU time per step of mj_step alone and with MujocoSkin.step (median of ROUNDS rounds)."""
    import mujoco
    from taxel.skin.mujoco import MujocoSkin, fingertip_xml
    m = mujoco.MjModel.from_xml_path(fingertip_xml())
    res = {"mj_step": [], "mj_step + MujocoSkin.step": []}
    for _ in range(ROUNDS):
        for name in res:
            d = mujoco.MjData(m)
            skin = MujocoSkin(m, sk, body="pad")
            b0 = m.body("probe").pos
            d.ctrl[m.actuator("probe_x").id], d.ctrl[m.actuator("probe_y").id] = 0.007 - b0[0], 0.007 - b0[1]
            d.ctrl[m.actuator("sphere_z").id] = d.ctrl[m.actuator("edge_z").id] = 0.004
            d.ctrl[m.actuator("probe_z").id] = -0.01
            for _ in range(200):                           # pressed: the contacts exist
                mujoco.mj_step(m, d)
            c0 = time.process_time()
            for _ in range(STEPS):
                mujoco.mj_step(m, d)
                if name != "mj_step":
                    skin.step(d)
            res[name].append((time.process_time() - c0) / STEPS)
    return {k: float(np.median(v)) for k, v in res.items()}


def main():
    out = {"load_average_start": os.getloadavg()[0], "cores": os.cpu_count(), "steps": STEPS, "rounds": ROUNDS,
           "skins": {}}
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    print("| skin | modes (states) | case | CPU time per step | real-time factor at 1 kHz | wall time per step |")
    print("|---|---|---|---|---|---|")
    for n in (3, 8):
        sk = skin(n)
        rng = np.random.default_rng(0)
        span = (sk.cols - 1) * sk.pitch
        data = {(m, kind): (rng.uniform(0, span, (STEPS, m, 2)),
                            rng.uniform(0, 1, (STEPS, m)) if kind == "normal" else rng.uniform(-1, 1, (STEPS, m, 3)))
                for m in (1, 10) for kind in ("normal", "vector")}
        table = cases(sk)
        cpu, wall = {k: [] for k in table}, {k: [] for k in table}
        for _ in range(ROUNDS):
            for name, (m, kind, go, envs) in table.items():
                c, w = go(*data[m, kind])
                cpu[name].append(c / STEPS / envs)
                wall[name].append(w / STEPS / envs)
        rt = SkinRuntime(sk)
        c0 = time.process_time()
        full = SkinRuntime(sk, order_tol=0.0)
        c1 = time.process_time()
        SkinRuntime(sk)
        c2 = time.process_time()
        modes = (f"{rt._lam.shape[1]} of {full._lam.shape[1]} ({sk.Ad.shape[0]})" if rt.diagonal
                 else f"dense ({sk.Ad.shape[0]})")
        rec = {"modes": modes, "modes_kept": int(rt._lam.shape[1]), "modes_file": int(full._lam.shape[1]),
               "order_error": rt.order_error, "dt": sk.dt,
               "construct_ms": 1e3 * (c2 - c1), "construct_full_order_ms": 1e3 * (c1 - c0), "cases": {}}
        for name in table:
            c, w = float(np.median(cpu[name])), float(np.median(wall[name]))
            rec["cases"][name] = {"cpu_us": 1e6 * c, "wall_us": 1e6 * w, "real_time_factor": sk.dt / c}
            print(f"| {n} x {n} | {modes} | {name} | {1e6 * c:.1f} us | {sk.dt / c:.0f} x | {1e6 * w:.1f} us |")
        if n == 3:
            mj = mujoco_cost(sk)
            rec["mujoco"] = {k: 1e6 * v for k, v in mj.items()}
            over = mj["mj_step + MujocoSkin.step"] - mj["mj_step"]
            rec["mujoco"]["MujocoSkin.step overhead_us"] = 1e6 * over
            print(f"(MuJoCo fingertip, flat probe pressed: mj_step {1e6 * mj['mj_step']:.1f} us, with MujocoSkin.step "
                  f"{1e6 * mj['mj_step + MujocoSkin.step']:.1f} us: the skin adds {1e6 * over:.1f} us)")
        out["skins"][f"{n}x{n}"] = rec
    out["load_average_end"] = os.getloadavg()[0]
    path = Path(__file__).parent / "results" / "skin_runtime.json"
    path.parent.mkdir(exist_ok=True)
    path.write_text(json.dumps(out, indent=1))
    print(f"wrote {path} (load average now {os.getloadavg()[0]:.2f})")


if __name__ == "__main__":
    main()
