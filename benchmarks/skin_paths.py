"""The skin's factoring measured on the reduced model's own paths (issue 48, the
between-taxel error's source).

The skin (taxel.skin.build) runs every taxel through the reference taxel's path h (its
footprint's force to its own readout) times a static influence: it assumes the path
from that footprint to a neighbour's readout is a constant times h. The reduced model
the skin is built from (taxel.analyses.solves.reduced, input the middle taxel's footprint, the
thesis PZT 3 x 3 2D section, mesh 1 mm / 0.2 mm, 500 Mohm readout) has those
neighbour paths as its other outputs, with the same poles (one state space: only the
output rows differ). For each neighbour path H_k: the least-squares constant a with
H_k ~ a h over the band 0.01 Hz .. f_max, and max |H_k - a h| / max |H_k| there (how far
H_k is from a scaled h), and the same times |a| (the same error on h's scale, what a
press on the middle taxel would see on its neighbour, of the middle taxel's peak).

    MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/skin_paths.py
"""

from __future__ import annotations

import numpy as np

import taxel
from taxel.analyses.solves import reduced
from taxel.skin.build import reference

COARSE = {"readout.circuit": "resistor", "mesh.size": "1 mm", "mesh.piezo_size": "0.2 mm"}


def response(ss, out: int, inp: int, f) -> np.ndarray:
    A, B, C, D = ss.A, ss.B[:, [inp]], ss.C[[out], :], ss.D[out, inp]
    eye = np.eye(len(A))
    return np.array([(C @ np.linalg.solve(2j * np.pi * fi * eye - A, B))[0, 0] + D for fi in f])


def main():
    ref = reference(taxel.load("thesis-pzt-3x3-2d").replace(**COARSE))
    rm = reduced.cached(ref, inputs="probe", output="readout")
    ss = rm.state_space()
    i, j = rm.pressed()
    print(f"reduced model: {ss.A.shape[0]} states, outputs {rm.output_names}, pressed output {i}")
    print("| path | band | a (H_k ~ a h) | max abs(H_k - a h) / max abs(H_k) | the same, of h's peak |")
    print("|---|---|---|---|---|")
    for f_max in (500.0, 2000.0):                  # Nyquist of dt = 1 ms and 0.25 ms
        f = np.geomspace(0.01, f_max, 400)
        h = response(ss, i, j, f)
        for k in range(ss.C.shape[0]):
            if k == i:
                continue
            H = response(ss, k, j, f)
            a = np.vdot(h, H) / np.vdot(h, h)
            e = np.abs(H - a * h).max()
            print(f"| {rm.output_names[k]} | 0.01-{f_max:g} Hz | {a.real:.3f}{a.imag:+.3f}j | "
                  f"{e / np.abs(H).max():.2f} | {100 * e / np.abs(h).max():.1f} % |")


if __name__ == "__main__":
    main()
