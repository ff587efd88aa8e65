"""Where a linear silicone stops being enough: the linear model's voltage error
against the Yeoh model, for the thesis PZT and PVDF taxels (2D plane strain),
over force; and its relation to the linear solution's own largest silicone strain.

The fitted slope (error per unit strain) is what `model.silicone = "auto"` uses
(taxel.analyses.LINEAR_ERROR_PER_STRAIN): solve linear, estimate the error from the
strain, and switch to Yeoh when the estimate passes the scene's tolerance.
The uniform-pressure press on Ecoflex cannot be followed by Newton beyond
about 0.45 N in 2D (see fem.hyperelastic; the surface folds at the load edge), so the
study stops where Yeoh converges.

Run: MKL_NUM_THREADS=1 python benchmarks/silicone_model_error.py
"""

import numpy as np

from taxel.fem.hyperelastic import NewtonError
from taxel.analyses import solve_static as solve
from taxel.scene import load

FORCES = [0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45]


def with_(scene, silicone, force):
    return scene.replace(**{"model.silicone": silicone, "load.force": force})


def study(name):
    base = load(name)
    rows = []
    for F in FORCES:
        lin = solve(with_(base, "linear", F))
        try:
            yeoh = solve(with_(base, "yeoh", F))
        except NewtonError as exc:
            print(f"  {name} {F} N: Yeoh did not converge ({exc.args[0][:60]}...)")
            break
        vl, vy = lin.voltages()["taxel_0_0"], yeoh.voltages()["taxel_0_0"]
        rows.append((F, vl, vy, abs(vl / vy - 1), lin.max_strain))
    return rows


def main():
    all_rows = []
    for name in ("thesis-pzt-single-2d", "thesis-pvdf-single-2d"):
        rows = study(name)
        print(f"\n{name}\n{'force N':>8} {'V linear':>10} {'V Yeoh':>10} {'error %':>8} {'strain %':>9}")
        for F, vl, vy, err, strain in rows:
            print(f"{F:>8.2f} {vl:>10.4f} {vy:>10.4f} {100 * err:>8.2f} {100 * strain:>9.1f}")
        all_rows += rows
    err = np.array([r[3] for r in all_rows])
    strain = np.array([r[4] for r in all_rows])
    slope = float(strain @ err / (strain @ strain))          # least squares through 0
    worst = float(np.max(err / strain))
    print(f"\nlinear voltage error ~ {slope:.4f} x largest silicone strain (least squares), "
          f"worst ratio {worst:.4f}")
    for tol in (0.01, 0.02, 0.05):
        print(f"  tolerance {100 * tol:g} %: linear is enough below a largest strain of {100 * tol / worst:.1f} %")


if __name__ == "__main__":
    main()
