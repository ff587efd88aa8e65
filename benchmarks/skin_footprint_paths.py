"""Does a path per footprint close the skin's between-taxel error? (issue 48, second goal: measured, not built)

The skin (taxel.skin.build) runs every taxel through the middle taxel's path h times the
static influence. A candidate refinement keeps the reduced model's own path P(c <- m)
from each taxel footprint m's force to each readout c (`taxel reduce` with the load on
footprint m, all 185 states, no cut) and interpolates them between footprints with
linear hats phi_m(x) (1 at footprint m's centre, 0 at its neighbours'):

    v_c = [the skin runtime's v_c] + sum_m phi_m(x) [P(c <- m) - g G_c(x_m) h] * F

(exact at the footprints' centres, the runtime's static influence kept). And, as the
best any skin built on the reduced model can do there, the press's own path: the
reduced model with the load at the press itself (all states, no cut, no interpolation). Thesis PZT
3 x 3 2D section, mesh 1 mm / 0.2 mm, 500 Mohm readout, a taxel-wide flat probe of 1 N on
the middle taxel (x = pitch) and halfway to its neighbour (1.5 pitch), the step and the
impulse of benchmarks/skin_accuracy.py, the FEM transient (taxel.solve) at the same dt;
error max over the row's taxels and time of |v - v_FEM| / max |v_FEM|. Then, for the
halfway press at 0.25 ms, each taxel's error, when it happens and what is left after the
best constant scale of that taxel's runtime voltage (a static error would vanish).

    MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/skin_footprint_paths.py
"""

from __future__ import annotations

import numpy as np
from scipy import signal

import taxel
from taxel.analyses.solves import reduced
from taxel.schema import electrode_name
from taxel.skin.build import build
from taxel.skin.runtime import SkinRuntime

COARSE = {"readout.circuit": "resistor", "mesh.size": "1 mm", "mesh.piezo_size": "0.2 mm"}
HISTORIES = {"step": {"analysis.duration": 0.3, "analysis.rise": 0.005},
             "impulse": {"analysis.duration": 0.1, "analysis.width": 0.01}}    # as benchmarks/skin_accuracy.py


def footprint_paths(scene) -> dict:
    """m -> (A, B, C, D): footprint m's force to the row's three readouts."""
    out = {}
    for m in range(3):
        rm = reduced.cached(scene.replace(**{"load.kind": "taxel", "load.taxel": [1, m], "load.force": 1.0}),
                            inputs="probe", output="readout")
        ss = rm.state_space()
        _, j = rm.pressed()
        rows = [rm.output_names.index(f"voltage:{electrode_name(1, c)}") for c in range(3)]
        out[m] = (ss.A, ss.B[:, [j]], ss.C[rows, :], ss.D[rows][:, [j]])
    return out


def own_path(scene, sk, x):
    """(A, B, C, D): the flat probe's force at x to the row's three readouts (the reduced model of that press)."""
    c = int(round(x / sk.pitch))
    rm = reduced.cached(scene.replace(**{"load.kind": "probe", "load.taxel": [1, c], "load.radius": sk.taxel_width / 2,
                                         "load.offset": [x - c * sk.pitch, 0.0], "load.profile": "flat",
                                         "load.force": 1.0}), inputs="probe", output="readout")
    ss = rm.state_space()
    _, j = rm.pressed()
    rows = [rm.output_names.index(f"voltage:{electrode_name(1, k)}") for k in range(3)]
    return ss.A, ss.B[:, [j]], ss.C[rows, :], ss.D[rows][:, [j]]


def simulate(sys_, F, dt) -> np.ndarray:
    Ad, Bd, Cd, Dd, _ = signal.cont2discrete(sys_, dt, method="foh")
    return signal.dlsim((Ad, Bd, Cd, Dd, dt), F)[1]


def fem(scene, sk, x, history, dt):
    p = sk.pitch
    c = int(round(x / p))
    tr = taxel.solve(scene.replace(**{"load.kind": "probe", "load.taxel": [1, c], "load.radius": sk.taxel_width / 2,
                                      "load.offset": [x - c * p, 0.0], "load.profile": "flat", "load.force": 1.0,
                                      "analysis.type": "transient", "analysis.input": history, "analysis.dt": dt,
                                      **HISTORIES[history]}))
    V = np.array(tr.output)[:, [tr.names.index(electrode_name(1, k)) for k in range(3)]]
    return np.asarray(tr.t), np.asarray(tr.force, float), V


def main():
    scene = taxel.load("thesis-pzt-3x3-2d").replace(**COARSE)
    paths = footprint_paths(scene)
    print("| dt | press | history | skin runtime | with a path per footprint | the press's own reduced path |")
    print("|---|---|---|---|---|---|")
    detail = []
    for dt in (1e-3, 2.5e-4):
        sk = build(scene, dt=dt, checks=0)
        p = sk.pitch
        for x_rel in (1.0, 1.5):
            x = x_rel * p
            for history in HISTORIES:
                t, F, V = fem(scene, sk, x, history, dt)
                v = SkinRuntime(sk).run(np.tile([[x, p]], (len(F), 1, 1)), F[:, None])[:, 1, :]
                hF = simulate((sk.A, sk.B, sk.C, sk.D), F, dt)[:, 0]
                corr = np.zeros_like(v)
                for m in range(3):
                    phi = max(0.0, 1 - abs(x_rel - m))
                    if phi:
                        share = SkinRuntime(sk).loads([[m * p, p]], [1.0])[1]      # g_c G_c(x_m), row 1
                        corr += phi * (simulate(paths[m], F, dt) - share[None, :] * hF[:, None])
                own = simulate(own_path(scene, sk, x), F, dt)
                peak = np.abs(V).max()
                e0, e1, e2 = (np.abs(a - V).max() / peak for a in (v, v + corr, own))
                print(f"| {dt * 1e3:g} ms | {x_rel:g} pitch | {history} | {100 * e0:.2f} % | {100 * e1:.2f} % | "
                      f"{100 * e2:.2f} % |")
                if dt == 2.5e-4 and x_rel == 1.5:
                    for k in range(3):
                        a = np.dot(v[:, k], V[:, k]) / np.dot(v[:, k], v[:, k])
                        i = int(np.argmax(np.abs(v[:, k] - V[:, k])))
                        detail.append(f"| {history} | taxel {k} | {np.abs(V[:, k]).max() / peak:.2f} | "
                                      f"{100 * abs(v[i, k] - V[i, k]) / peak:.2f} % at {1e3 * t[i]:.1f} ms | "
                                      f"{a:.4f}: {100 * np.abs(a * v[:, k] - V[:, k]).max() / peak:.2f} % |")
    print("\nhalfway, dt 0.25 ms, the skin runtime per taxel:\n")
    print("| history | taxel | its peak (of the row's) | its largest error, when | best scale: error left |")
    print("|---|---|---|---|---|")
    print("\n".join(detail))


if __name__ == "__main__":
    main()
