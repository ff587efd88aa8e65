"""Cost and accuracy of the dynamic analyses (2D thesis PZT taxel).

Prints in one run: one static solve; a 200-point frequency sweep, direct and
reduced, with the reduced one's error against the direct one; a 1 s transient
(step through a 500 MOhm resistor); the lumped model's frequency points per
second; and the explicit central-difference critical time step of a 0.127 mm
PZT layer (why the implicit integrator is the default).

Run: MKL_NUM_THREADS=1 python benchmarks/dynamics.py
"""

import numpy as np

from taxel.analyses import lumped_model, problem
from taxel.analyses import solve_static as solve
from taxel.fem import dynamics
from taxel.fem import readout
from taxel.scene import load, parse
from taxel_2d import median_time     # benchmarks/ is on sys.path when run as a script


def critical_step():
    """A laterally clamped 0.127 mm PSI-5H4E column, one P2 element through it (as in the taxel mesh)."""
    return dynamics.critical_time_step(dynamics.model(problem(PZT_COLUMN)))


PZT_COLUMN = parse({"model": {"type": "plane_strain", "depth": "0.1 mm"}, "mesh": {"size": "0.1 mm"},
                    "plate": {"shape": "rectangle", "width": "0.1 mm",
                              "layers": [{"material": "PSI-5H4E", "thickness": "0.127 mm"}]},
                    "load": {"kind": "pressure", "pressure": "1 kPa"},
                    "supports": {"bottom": "rollers", "edges": "rollers"}})


def main():
    scene = load("thesis-pzt-single-2d")
    solve(scene)
    t_static, _ = median_time(lambda: solve(scene))
    dm = dynamics.model(problem(scene))
    freqs = np.geomspace(1, 1000, 200)
    t_direct, direct = median_time(lambda: dynamics.sweep(dm, freqs, method="direct"), 1)
    t_red, red = median_time(lambda: dynamics.sweep(dm, freqs), 3)
    err = np.abs(red.V_oc - direct.V_oc).max() / np.abs(direct.V_oc).max()
    t = np.arange(0, 1.0 + 2.5e-4, 5e-4)
    f = np.clip(t / 5e-3, 0, 1)
    t_tr, tr = median_time(lambda: dynamics.transient(dm, t, f, R=5e8), 3)
    lm = lumped_model(scene)
    pps = np.median([readout.points_per_second(lm) for _ in range(5)])
    dt_crit = critical_step()
    print(f"{'what':<52} {'seconds':>9} {'x static':>9}  note")
    print(f"{'static solve (mesh + assemble + solve)':<52} {t_static:>9.3f} {1:>9.1f}")
    print(f"{'200-point sweep, direct (complex LU per point)':<52} {t_direct:>9.3f} {t_direct / t_static:>9.1f}")
    print(f"{'200-point sweep, reduced (Krylov, checked)':<52} {t_red:>9.3f} {t_red / t_static:>9.1f}  "
          f"{red.basis_size} vectors, error vs direct {err:.1e} (self-reported {red.error:.1e})")
    print(f"{'1 s transient, 2000 steps, 500 MOhm readout':<52} {t_tr:>9.3f} {t_tr / t_static:>9.1f}  "
          f"{tr.basis_size} vectors")
    print(f"lumped 3-DoF model: {pps:.3g} frequency points per second")
    print(f"explicit central difference, 0.127 mm PZT layer: dt_crit = {dt_crit:.3g} s, "
          f"{1 / dt_crit:.3g} steps for 1 s; the implicit Newmark default runs 1 s in 2000 steps")


if __name__ == "__main__":
    main()
