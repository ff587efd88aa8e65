"""The thesis PZT taxel pressed by a rigid flat punch (fem.contact, fem.contact).

2D plane strain (a half section: model.symmetry auto), axisymmetric with --axisym,
3D with --3d (the 3D taxel's default mesh, a quarter model), each model's default
mesh, a 4 mm flat punch with a 0.2 mm edge radius centred on the taxel, sticking
(the scene default) or frictionless (--frictionless), augmented Lagrangian. Force control along
0.1, 0.25, 0.5, 0.75, 1, 1.5, 2 N, linear and Yeoh silicone, each warm-started from the last. Prints per target: travel,
voltage, contact half-width, Newton iterations, multiplier updates, time;
where a press stops, the reason (fem.contact.PressError). Writes
out/contact-taxel/curve-<model>-<friction>-<silicone>.csv (every converged state) and
the voltage-force figure docs/contact-voltage-force-<model>-<friction>.png. The
nonlinearity printed is V_Yeoh(F) / V_linear(F) - 1 at each force, and
the voltage's own departure from a straight line through the origin fitted at the
smallest force, V(F) / (F V(F0)/F0) - 1, for each silicone.

Run: MKL_NUM_THREADS=1 python benchmarks/contact_taxel.py [--axisym | --3d] [--frictionless] [--full]
(--full: the whole 2D section instead of the half; the figure is then not rewritten)
"""

import sys
import time
from pathlib import Path

import numpy as np

from taxel.analyses import problem
from taxel.fem.assembly import assemble
from taxel.fem.contact import PressError, Press
from taxel.scene import load

TARGETS = (0.1, 0.25, 0.5, 0.75, 1.0, 1.5, 2.0)


def scene(silicone, model, friction="sticking", symmetry="auto"):
    up = {"model.type": model, "model.silicone": silicone, "load.kind": "probe", "load.contact": True,
          "load.radius": 2e-3, "load.edge_radius": 0.2e-3, "load.force": 1.0, "load.friction": friction,
          "model.symmetry": symmetry}
    # 3D: the 3D taxel's default mesh (thesis-pzt-single-3d), a quarter model (model.symmetry auto)
    return load("thesis-pzt-single-3d" if model == "3d" else "thesis-pzt-single-2d").replace(**up)


def run(silicone, model, friction="sticking", symmetry="auto"):
    prob = problem(scene(silicone, model, friction, symmetry))
    t0 = time.perf_counter()
    pr = Press(assemble(prob), prob.indenter)
    rows, stop = [], ""
    for F in TARGETS:
        n0 = len(pr.res.points)
        try:
            pt = pr.force(F)
        except PressError as exc:
            stop = f"stopped before {F} N: {exc}"
            break
        its = sum(p.iterations for p in pr.res.points[n0:])
        rows.append((F, pt.travel, pt.voltages["taxel_0_0"], pt.half_width, its,
                     sum(p.uzawa for p in pr.res.points[n0:]), len(pr.res.points) - n0, time.perf_counter() - t0))
    return rows, pr.res, stop


def main():
    model = "axisymmetric" if "--axisym" in sys.argv else "3d" if "--3d" in sys.argv else "plane_strain"
    friction = "frictionless" if "--frictionless" in sys.argv else "sticking"
    symmetry = "full" if "--full" in sys.argv else "auto"     # --full: the whole section, not the half
    out = Path("out/contact-taxel")
    out.mkdir(parents=True, exist_ok=True)
    curves = {}
    for silicone in ("linear", "yeoh"):
        rows, res, stop = run(silicone, model, friction, symmetry)
        print(f"\n{model}, {friction}, {silicone} silicone, penalty {res.penalty:.3g} Pa/m")
        print(f"{'F N':>5} {'travel mm':>9} {'V':>8} {'a mm':>6} {'iters':>5} {'uzawa':>5} {'states':>6} {'cum s':>6}")
        for F, d, V, a, its, uz, n, t in rows:
            print(f"{F:5.2f} {1e3 * d:9.4f} {V:8.4f} {1e3 * a:6.3f} {its:5d} {uz:5d} {n:6d} {t:6.1f}")
        if stop:
            print(stop)
        pts = sorted(res.points, key=lambda p: p.travel)
        arr = np.array([(p.travel, p.force, p.voltages["taxel_0_0"], p.area, p.half_width, p.penetration)
                        for p in pts])
        np.savetxt(out / f"curve-{model}-{friction}-{silicone}.csv", arr, delimiter=",",
                   header="travel_m,force_N,voltage_V,contact_area_reference_m2,contact_half_width_m,penetration_m")
        curves[silicone] = (arr, rows)
    lin, yeo = curves["linear"][1], curves["yeoh"][1]
    common = min(len(lin), len(yeo))
    print("\nforce N, V linear, V Yeoh, Yeoh/linear - 1, linear and Yeoh off their small-force line")
    for k in range(common):
        off_l = lin[k][2] / (lin[k][0] * lin[0][2] / lin[0][0]) - 1
        off_y = yeo[k][2] / (yeo[k][0] * yeo[0][2] / yeo[0][0]) - 1
        print(f"{lin[k][0]:5.2f} {lin[k][2]:8.4f} {yeo[k][2]:8.4f} {yeo[k][2] / lin[k][2] - 1:+.3f} "
              f"{off_l:+.3f} {off_y:+.3f}")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5, 3.5))
    for silicone, (arr, _) in curves.items():
        ax.plot(arr[:, 1], -arr[:, 2], "o-", ms=3, label=f"{silicone} silicone")
    ax.set_xlabel("punch force (N)")
    ax.set_ylabel("-V open circuit (V)")
    ax.set_title(f"thesis PZT taxel, 4 mm punch, {model.replace('_', ' ')}, {friction}", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    if symmetry == "full":
        return
    fig.savefig(f"docs/contact-voltage-force-{model}-{friction}.png", dpi=120)


if __name__ == "__main__":
    main()
