"""The reduced-order model of a scene (taxel.reduce): order, build time against one
direct FEM sweep, simulation speed of a 60 s record at 2 kHz, and the FRF error
against the direct sweep over 1 Hz-2 kHz with the readout (500 Mohm input).

Cases: the 3x3 thesis array in 2D (the section through the pressed row: inputs a
force on each of the row's three taxels, outputs the voltage of each: 3 x 3 of the
array's 9 x 9 paths) and the single 3D taxel on a coarse mesh (1 x 1).

Errors: per path, max over frequency of |H - H_direct| relative to the path's
largest |H_direct|; the worst path is printed, over 1 Hz-2 kHz (60 log-spaced
points) and, separately, at the 7 points of a 400-point grid around the pressed
path's resonance peak. "frf" is the reduced second-order model with the FEM's
causal loss law (fem.constitution); "state space" its exact real realization with
the law's internal variables, modally truncated (fem.dynamics), which the exports
(python-control, scipy.signal, .mat) carry.

    MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/reduced_model.py
"""

from __future__ import annotations

import os
import statistics
import time

import numpy as np

import taxel
from taxel.analyses.solves import reduced as R
from taxel.analyses import problem
from taxel.fem import dynamics
from taxel.fem import dynamics as fr

FREQS = np.geomspace(1.0, 2000.0, 60)


def worst_path(H, Hd):
    err = np.abs(H - Hd).max(axis=0) / np.abs(Hd).max(axis=0)
    i, j = np.unravel_index(np.argmax(err), err.shape)
    return float(err.max()), (int(i), int(j))


def case(label, scene):
    t = time.perf_counter()
    model = R.reduce(scene)
    build = time.perf_counter() - t
    dm = dynamics.model(problem(scene))
    loads = R.taxel_loads(dm)[0]
    t = time.perf_counter()
    pairs = [fr.direct_ports(dm, loads, f) for f in FREQS]
    direct = time.perf_counter() - t
    t = time.perf_counter()
    dynamics.sweep(dm, FREQS, "reduced")
    existing = time.perf_counter() - t
    V, Ci = np.array([p[0] for p in pairs]), np.array([p[1] for p in pairs])
    Hd = R.port_readout(FREQS, V, Ci, model.red.names, model.readout)
    e_rom, p_rom = worst_path(model.frf(FREQS), Hd)
    t = time.perf_counter()
    ss = model.state_space()
    realize = time.perf_counter() - t
    e_ss, p_ss = worst_path(ss.frf(FREQS), Hd)
    fine = np.geomspace(1.0, 2000.0, 400)
    i, j = model.pressed()
    k = int(np.argmax(np.abs(model.frf(fine)[:, i, j])))
    near = fine[max(k - 3, 0):k + 4]
    pairs = [fr.direct_ports(dm, loads, f) for f in near]
    Hn = R.port_readout(near, np.array([p[0] for p in pairs]), np.array([p[1] for p in pairs]), model.red.names,
                        model.readout)
    e_near, p_near = worst_path(ss.frf(near), Hn)
    tt = np.arange(0.0, 60.0, 1 / 2000)
    rng = np.random.default_rng(0)
    u = np.column_stack([np.interp(tt, np.arange(0, 61, 0.5), rng.uniform(0, 1, 122)) for _ in model.input_names])
    model.simulate(tt[:100], u[:100])                     # warm-up (imports)
    sims, cpus = [], []
    for _ in range(3):
        t, c = time.perf_counter(), time.process_time()
        model.simulate(tt, u)
        sims.append(time.perf_counter() - t)
        cpus.append(time.process_time() - c)
    n_in, n_out = len(model.input_names), len(model.output_names)
    print(f"\n{label}: {dm.M.shape[0]} unknowns, {n_in} inputs x {n_out} outputs ({model.readout_label})")
    print(f"  order: {model.order} states ({model.red.order} basis vectors; measured reduction error "
          f"{model.red.error:.1e}; {model.red.relax.n} relaxation times; modal truncation error "
          f"{ss.truncation_error:.1e}, realized in {realize:.1f} s)")
    print(f"  build {build:.1f} s + state space {realize:.1f} s | one direct sweep ({len(FREQS)} points, all inputs) "
          f"{direct:.1f} s (ratio {direct / (build + realize):.2f}) | the frequency analysis' reduced sweep (pressed taxel only) {existing:.1f} s")
    print(f"  60 s record at 2 kHz ({len(tt)} samples x {n_in} inputs): median {statistics.median(sims):.2f} s "
          f"(of {', '.join(f'{s:.2f}' for s in sims)}); CPU time {statistics.median(cpus):.2f} s (the wall time "
          f"on a shared machine includes waiting: load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)")
    print(f"  FRF error vs direct, 1 Hz-2 kHz, {len(FREQS)} points: frf {e_rom:.1e} (worst path {p_rom}); "
          f"state space {e_ss:.1e} (worst path {p_ss}); state space at the resonance "
          f"({near[0]:.0f}-{near[-1]:.0f} Hz) {e_near:.1e} (worst path {p_near})")
    return model


def lumped_rows(label, scene):
    """The seed's and the FEM-informed 3-DoF models against the FEM (the scene's reduced
    model, charge output, pressed path): |FRF| and complex errors below half the first
    resonance and within +-50 % of it."""
    from taxel.analyses.solves.dynamic import lumped_model
    from taxel.analyses.solves.lumped_fem import informed, targets
    t = time.perf_counter()
    fem = targets(scene)
    idf = informed(scene, fem)
    seconds = time.perf_counter() - t
    rm = R.cached(scene, None, "charge")
    i, j = rm.pressed()
    f1 = fem.first_resonance
    f = np.geomspace(1.0, 1.5 * f1, 300)
    H = rm.frf(f)[:, i, j]
    below, around = f < 0.5 * f1, f >= 0.5 * f1
    print(f"\n{label}: FEM first resonance {f1:.0f} Hz, static charge {fem.charge_per_newton:.4g} C/N, compliance "
          f"{fem.compliance:.4g} m/N; informed model identified in {seconds:.1f} s (scales {idf.scales})")
    for name, lm in (("lumped (seed's)", lumped_model(scene)), ("lumped (FEM-informed)", idf.model)):
        Hl = lm.Q_sc(f) / lm.force
        Hl = Hl * np.sign((Hl[0] / H[0]).real)                  # the FEM's sign convention
        mag = np.abs(np.abs(Hl) - np.abs(H)) / np.abs(H)
        cpx = np.abs(Hl - H) / np.abs(H)
        print(f"  {name:22s} static charge {abs(Hl[0]):.4g} C/N ({100 * (abs(Hl[0]) / abs(H[0]) - 1):+.1f} %); "
              f"|FRF| error below 0.5 f1 {100 * mag[below].max():.1f} %, 0.5-1.5 f1 {100 * mag[around].max():.0f} %; "
              f"complex below {100 * cpx[below].max():.1f} %")


def main():
    resistor = {"readout.circuit": "resistor", "readout.R": "500 Mohm"}
    case("thesis-pzt-3x3-2d (the row through the pressed taxel: paths taxel_1_c -> taxel_1_c')",
         taxel.load("thesis-pzt-3x3-2d").replace(**resistor))
    case("thesis-pzt-single-3d, coarse mesh (size 2 mm, piezo 1 mm)",
         taxel.load("thesis-pzt-single-3d").replace(**{"mesh.size": "2 mm", "mesh.piezo_size": "1 mm",
                                                      "model.symmetry": "full", **resistor}))
    lumped_rows("thesis-pzt-single-2d, the 3-DoF models against the FEM", taxel.load("thesis-pzt-single-2d"))


if __name__ == "__main__":
    main()
