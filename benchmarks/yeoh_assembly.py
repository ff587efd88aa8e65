"""The Yeoh residual and consistent tangent: vectorised (fem.hyperelastic, through
fem.hyperelastic.yeoh_terms) against scikit-fem's forms (fem.hyperelastic.yeoh_terms_skfem),
side by side in one run, at the same deformed state, median CPU time of 3 repeats
(1 in 3D).

Scenes: the thesis taxel in 2D plane strain and axisymmetric (default meshes) and
in 3D (thesis-pzt-single-3d), Yeoh silicone, at the state of a small uniform
load (one Newton solve, 0.05 N, so the state is deformed but converged quickly;
3D: a linear solve's displacement scaled to the same size).

Run: MKL_NUM_THREADS=1 python benchmarks/yeoh_assembly.py [--no-3d]
"""

import sys
import time

import numpy as np

from taxel.analyses import problem
from taxel.fem.assembly import assemble
from taxel.fem.hyperelastic import newton, yeoh_terms, yeoh_terms_skfem
from taxel.scene import load


def cpu(fn, repeats=3):
    t = []
    for _ in range(repeats):
        c0 = time.process_time()
        fn()
        t.append(time.process_time() - c0)
    return float(np.median(t))


def main():
    cases = [("thesis-pzt-single-2d", {}), ("thesis-pzt-single-2d", {"model.type": "axisymmetric"})]
    if "--no-3d" not in sys.argv:
        cases.append(("thesis-pzt-single-3d", {}))
    print(f"{'scene':<24} {'model':<13} {'unknowns':>8} {'elements':>8} {'skfem s':>8} {'vectorised s':>12} "
          f"{'ratio':>6} {'max rel diff':>12}")
    for name, up in cases:
        sc = load(name).replace(**{"model.silicone": "yeoh", "load.force": 0.05, **up})
        sy = assemble(problem(sc))
        if sc.model.type == "3d":
            x = np.zeros(sy.A.shape[0])
            u = sy.offsets["u"]
            x[u] = 1e-6 * np.sin(np.arange(u.stop))       # a small smooth-enough state
        else:
            x = newton(sy)[0]
        ne = sum(b.nelems for r, b in sy.ubases.items() if r in sy.yeoh)
        reps = 1 if sc.model.type == "3d" else 3
        t_sk = cpu(lambda: yeoh_terms_skfem(sy, x), reps)
        t_v = cpu(lambda: yeoh_terms(sy, x), reps)
        r1, K1 = yeoh_terms(sy, x)
        r2, K2 = yeoh_terms_skfem(sy, x)
        diff = max(np.abs(r1 - r2).max() / np.abs(r2).max(), abs(K1 - K2).max() / abs(K2).max())
        print(f"{name:<24} {sc.model.type:<13} {sy.A.shape[0]:8d} {ne:8d} {t_sk:8.3f} {t_v:12.3f} "
              f"{t_sk / t_v:6.1f} {diff:12.1e}")


if __name__ == "__main__":
    main()
