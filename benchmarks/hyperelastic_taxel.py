"""Cost and accuracy of the Yeoh taxel (2D thesis PZT taxel, plane strain).

Prints, per force: Newton load steps and iterations, time per iteration, total
time, voltage, the linear model's voltage and its error, and the Yeoh voltage's
discretization error on the default mesh against a Richardson extrapolation over
nested refinements. 1 N is attempted too: the uniform pressure patch creases the
free surface before it (fem.hyperelastic), and the benchmark prints where it stopped.

Run: MKL_NUM_THREADS=1 python benchmarks/hyperelastic_taxel.py
"""

import numpy as np

from taxel.fem.hyperelastic import NewtonError
from taxel.analyses import solve_static as solve
from taxel.analyses import mesh
from taxel.scene import load
from taxel_2d import median_time     # benchmarks/ is on sys.path when run as a script


def with_(scene, silicone, force):
    return scene.replace(**{"model.silicone": silicone, "load.force": force})


def reference(scene):
    tm = mesh(scene)
    v = [solve(scene, tagged_mesh=tm.refined(k) if k else tm).voltages()["taxel_0_0"] for k in range(3)]
    p = np.log2(abs(v[1] - v[0]) / abs(v[2] - v[1]))
    return v[2] + (v[2] - v[1]) / (2 ** p - 1), p


def main():
    base = load("thesis-pzt-single-2d")
    solve(base)
    print(f"{'force N':>7} {'steps':>5} {'iters':>5} {'s/iter':>7} {'total s':>8} {'V Yeoh':>9} {'V linear':>9} "
          f"{'lin err %':>9} {'mesh err %':>10}")
    for F in (0.1, 0.2, 0.45, 1.0):
        scene = with_(base, "yeoh", F)
        try:
            t, sol = median_time(lambda: solve(scene), 3)
        except NewtonError as exc:
            print(f"{F:>7.2f}  Newton stopped: last converged load factor "
                  f"{exc.result.load_factors[-1] if exc.result.load_factors else 0:.3f} "
                  f"({exc.result.total_iterations} iterations, {len(exc.result.failed)} failed attempts)")
            continue
        v = sol.voltages()["taxel_0_0"]
        v_lin = solve(with_(base, "linear", F)).voltages()["taxel_0_0"]
        v_ref, p = reference(scene) if F <= 0.2 else (np.nan, np.nan)
        n_it = sol.newton.total_iterations
        print(f"{F:>7.2f} {len(sol.newton.load_factors):>5} {n_it:>5} {sol.times['solve'] / n_it:>7.3f} {t:>8.3f} "
              f"{v:>9.4f} {v_lin:>9.4f} {100 * abs(v_lin / v - 1):>9.2f} "
              f"{100 * abs(v / v_ref - 1) if np.isfinite(v_ref) else float('nan'):>10.3f}")


if __name__ == "__main__":
    main()
