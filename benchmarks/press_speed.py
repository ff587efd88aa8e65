"""The 3D probe press in seconds (issue 46): where its time goes, and what each lever buys.

Two presses, both the rig's probe (a sticking 4 mm flat punch, 0.2 mm edge radius) pressing
Yeoh Ecoflex 00-30 to 1 N, quarter models (model.symmetry = "auto"):

- single: thesis-pzt-probe-3d, the thesis PZT taxel alone;
- 3x3: the same scene with a 3 x 3 array (array.rows = cols = 3), the punch on the centre taxel:
  the case that gives sensitivity and crosstalk together.

Each at its default press mesh (taxel.scene.DEFAULT_PRESS_MESH) and at refinements of it
(taxel.scene.refined, every size / k; --levels), through the whole pipeline a user runs
(taxel.analyses.model.problem.solve_model: mesh, assembly, press, the solution with the unfolded
capacitance), printing wall and CPU time, the unknowns, Newton iterations, load states,
factorizations (fem.contact.PressResult.stats), V/F and crosstalk, and the error against the
reference: the single taxel's eight-level Richardson fit (docs/press_3d_reference.json,
benchmarks/press_3d.py), and for the 3x3 Richardson over the levels run here (three levels,
any size ratios) where they are monotone.

--levers CASE: the levers side by side in one run on that case's default mesh (each a whole
solve_model; --repeat N for medians): the default; the PARDISO analysis redone at every Newton
step (Options.reuse_analysis False); no chord steps; no tangent predictor (each travel from the
last state, not from the linear rate dx/dd); the first force-control trial from the unpressed
(linear) stiffness at half the target (Options.first_force 0.5: fewer load states); and the
taxels the punch does not touch meshed as finely as the pressed one (meshing Layout.far_taxel 1,
the default before) and at 2 x (the default is taxel.analyses.model.geometry.FAR_TAXEL, 3: fewer
unknowns where the silicone stays nearly linear).

--designs N: N designs pressed in one process (the single taxel, silicone above 1, 0.75, 1.25, 0.5
mm ...: what an optimization or the main job presses), each design's wall and CPU time, against
a cold start (a new process, `taxel solve thesis-pzt-probe-3d --json`: imports, MKL, mesh, press).
What carries over between designs of one process: the imports, MKL's and pypardiso's set-up and
gmsh's initialisation; not the mesh or the PARDISO analysis (a new design is a new mesh, a new
pattern; fem.linalg.Refactorizer reuses its analysis within one press).

--estimate CASE: the error estimate of the default press (taxel.analyses.accuracy.error_estimate.estimate:
for a 3D press the through-the-piezo and in-plane parts, widened) against the true error (the
single taxel's reference), and its cost against the press's.

--linear-estimate: the linear 3D estimate of thesis-pzt-single-3d and thesis-pzt-3x3-3d (their
own meshes) against docs/reference_3d.json: its mean, and the largest error against any chain.

--profile CASE: cProfile of one default solve, the 25 most costly functions.

Run with MKL_NUM_THREADS=1 (the machine is shared). Measured numbers and what they mean are in
docs/benchmarks.md ("The 3D press in seconds").

RESULT (2026-11-28, one run each unless said, CPU s, the 2-core machine at load 4-10):
- --case single: sizes / 1, 1.41, 2 (taxel.scene.refined): 8 031, 13 223, 21 866 unknowns, V/F
  -0.78635, -0.78850, -0.79327 V/N, +0.84, +1.11, +1.73 % from the reference -0.77981; 8.1, 24.7,
  42.0 s (refined kept the rim's size and shrank the grading distance with the sizes: not a converging
  family of the press then; since 2026-11-29 a press's finer [mesh] divides the same size field,
  taxel.analyses.model.geometry.punch_grading, and benchmarks/press_directions.py measures both paths).
- --levers 3x3 (before FAR_TAXEL was the default: far taxels 1 then): far taxels 1, 2, 3 x:
  34 482, 20 292, 17 935 unknowns, V/F -0.77836, -0.77632, -0.77609 V/N, crosstalk 1.140, 1.159,
  1.133 %, 79.1, 35.3, 28.3 s (182, 61, 56 s wall).
- --case 3x3 --levels 1,1.41421 (FAR_TAXEL 3): 17 935, 33 591 unknowns, -0.77609, -0.77750 V/N,
  crosstalk 1.133, 1.130 %, 29.3, 65.5 s; against the single taxel's -0.78635, -0.78850: ratios
  0.98695, 0.98605.
- --case 3x3 --levels 1.41421 --far-taxel 1 (load 12): 52 596 unknowns, -0.77818 V/N, crosstalk
  1.140 %, 155.4 s (334.5 s wall): the far taxels' effect 0.09 % at / 1.41 against 0.29 % at / 1.
- --levers single --repeat 3 (medians): default 9.7 s, analysis at every step 12.1 s (1.24 x),
  no chord steps 9.0 s (0.92 x), no predictor 15.3 s (1.57 x, 13 states), first trial at half
  the target 9.0 s (0.92 x); V/F within 0.08 %.
- --estimate single (load 10.6): V/F -0.78635, estimate 1.91 % (through the piezo 1.7 %, in plane
  0.15 %), true 0.84 %: 2.27 x; the press 8.3 s of CPU, the estimate 17.0 s (2.0 x the press).
- --linear-estimate (load 11): single 0.618 % at -0.85451 V/N, against the mean 0.062 % (9.9 x), the
  largest against a chain 0.369 % (1.7 x); 3x3 0.500 % at -0.82431 V/N, 0.239 % (2.1 x), 0.710 % (0.7 x).
- --profile 3x3 (FAR_TAXEL 3, load 10): 27.2 s of CPU: factorizations 9.8 s (38), assembly 11.1 s
  (the Yeoh terms over all the silicone, 57 Newton iterations), solves 2.3 s, the rest (mesh,
  scaling, the final state's unfolded capacitance) 3.9 s.
- --designs 4: a cold process 10.1 s of CPU (two runs); in one process, silicone above 1, 0.75,
  1.25, 0.5 mm: 9.2, 10.2, 13.7, 8.5 s (-0.78635, -0.73878, -0.80931, -0.66599 V/N).
"""

from __future__ import annotations

import argparse
import cProfile
import dataclasses
import json
import os
import pstats
import statistics
import time
from pathlib import Path


from taxel.analyses import checked_layout, check
from taxel.analyses.model.problem import solve_model
from taxel.meshing.build import build
from taxel.scene import load, refined

DOCS = Path(__file__).resolve().parents[1] / "docs"
LEVELS = (1.0, 2 ** 0.5, 2.0)


def scene(case: str):
    """The single taxel or the 3x3 array pressed at its centre taxel by the rig's probe."""
    sc = load("thesis-pzt-probe-3d")
    if case == "3x3":
        sc = sc.replace(**{"array.rows": 3, "array.cols": 3, "load.taxel": [1, 1]})
    return sc


def reference(case: str) -> float | None:
    """V/N: the single taxel's Richardson fit (benchmarks/press_3d.py --reference)."""
    if case != "single":
        return None
    ref = json.loads((DOCS / "press_3d_reference.json").read_text())
    return float(ref["VF"])


def run(sc, options: dict | None = None, far_taxel: float | None = None) -> dict:
    """One whole solve (mesh, assembly, press, solution); its numbers. `far_taxel`: the layout's
    (meshing Layout.far_taxel) instead of the scene's default (taxel.analyses.model.geometry.FAR_TAXEL)."""
    w, c = time.perf_counter(), time.process_time()
    tm = None
    if far_taxel is not None:
        lay = checked_layout(sc, check(sc))
        tm = build(dataclasses.replace(lay, far_taxel=far_taxel))
    res = solve_model(sc, tagged_mesh=tm, newton_options=options)
    wall, cpu = time.perf_counter() - w, time.process_time() - c
    out = res.outputs()
    cr = res.contact
    st = cr.stats
    return dict(n=res.unknowns, VF=out["sensitivity"], crosstalk=out.get("crosstalk"), wall=wall, cpu=cpu,
                states=len(cr.points), iterations=cr.total_iterations, factorizations=st["factorizations"],
                chord=st["chord_steps"], factorize_s=st["factorize_s"], assemble_s=st["assemble_s"],
                solve_s=st["solve_s"], continuation=st.get("continuation_steps", 0), times=res.times)


def richardson(h, v):
    """(order, extrapolated value) of three levels h0 > h1 > h2 (v_i = v + C h_i^p), or (None, None)
    where the steps change sign or no order in (0, 12] fits."""
    from scipy.optimize import brentq
    (h0, h1, h2), (v0, v1, v2) = h, v
    d1, d2 = v0 - v1, v1 - v2
    if d1 * d2 <= 0:
        return None, None
    g = lambda p: (h0 ** p - h1 ** p) / (h1 ** p - h2 ** p) - d1 / d2
    try:
        p = brentq(g, 1e-3, 12.0)
    except ValueError:
        return None, None
    C = d2 / (h1 ** p - h2 ** p)
    return p, v2 - C * h2 ** p


HEAD = ("| run | unknowns | V/F V/N | error | crosstalk % | states | Newton iterations | factorizations | chord "
        "steps | factorize CPU s | assembly CPU s | solve CPU s | CPU s | wall s |")


def row(name, r, ref):
    err = f"{100 * (r['VF'] / ref - 1):+.2f} %" if ref else ""
    xt = f"{100 * r['crosstalk']:.3f}" if r.get("crosstalk") is not None else ""
    return (f"| {name} | {r['n']} | {r['VF']:.5f} | {err} | {xt} | {r['states']} | {r['iterations']} | "
            f"{r['factorizations']} | {r['chord']} | {r['factorize_s']:.1f} | {r['assemble_s']:.1f} | "
            f"{r['solve_s']:.1f} | {r['cpu']:.1f} | {r['wall']:.1f} |")


def levels(case: str, ks, far_taxel: float | None = None):
    sc0 = scene(case)
    ref = reference(case)
    print(f"\n{case}: default press mesh and refinements (sizes / k); reference "
          f"{'%.5f V/N (docs/press_3d_reference.json)' % ref if ref else 'Richardson over these levels'}"
          f"; load {os.getloadavg()[0]:.1f}")
    print(HEAD)
    print("|" + "---|" * 14)
    rows = []
    for k in ks:
        r = run(sc0 if k == 1.0 else refined(sc0, k), far_taxel=far_taxel)
        rows.append((k, r))
        print(row(f"sizes / {k:.3g}", r, ref), flush=True)
    if len(rows) >= 3:
        h = [1 / k for k, _ in rows[-3:]]
        p, v = richardson(h, [r["VF"] for _, r in rows[-3:]])
        if v is not None:
            print(f"Richardson over the last three levels: order {p:.2f}, V/F {v:.5f} V/N; errors "
                  + ", ".join(f"/ {k:.3g} {100 * (r['VF'] / v - 1):+.2f} %" for k, r in rows))
            pc, vc = richardson(h, [r["crosstalk"] for _, r in rows[-3:]]) if rows[0][1]["crosstalk"] else (0, None)
            if vc is not None:
                print(f"crosstalk: order {pc:.2f}, {100 * vc:.4f} %")
        else:
            print("the levels are not monotone: no Richardson value")


LEVERS = {
    "default": dict(),
    "PARDISO analysis at every Newton step": dict(options=dict(reuse_analysis=False)),
    "no chord steps": dict(options=dict(chord=False)),
    "no tangent predictor": dict(options=dict(predictor=False)),
    "first trial from the unpressed stiffness, half the target": dict(options=dict(first_force=0.5)),
    "far taxels as fine as the pressed one (Layout.far_taxel 1, the default before)": dict(far_taxel=1.0),
    "far taxels' edges 2 x piezo_size": dict(far_taxel=2.0),
}


def levers(case: str, repeat: int, only: list[str] | None):
    sc = scene(case)
    ref = reference(case)
    print(f"\n{case}: levers on the default press mesh ({repeat} run(s) each, medians of the times); "
          f"load {os.getloadavg()[0]:.1f}")
    print(HEAD)
    print("|" + "---|" * 14)
    base = None
    for name, kw in LEVERS.items():
        if only and name != "default" and not any(o in name for o in only):
            continue
        runs = [run(sc, **kw) for _ in range(repeat)]
        r = dict(runs[0])
        for key in ("wall", "cpu", "factorize_s", "assemble_s", "solve_s"):
            r[key] = statistics.median(x[key] for x in runs)
        base = base or r
        print(row(name, r, ref) + f" {r['cpu'] / base['cpu']:.2f} x CPU", flush=True)
        if not ref and name != "default":
            print(f"|   against the default | | {100 * (r['VF'] / base['VF'] - 1):+.2f} % | "
                  + (f"{100 * (r['crosstalk'] / base['crosstalk'] - 1):+.1f} % (relative)" if r["crosstalk"] else "")
                  + " |")


def designs(n: int):
    import resource
    import subprocess
    import sys
    import tempfile
    print(f"\ndesigns pressed in one process against a cold start (single taxel); load {os.getloadavg()[0]:.1f}")
    cold = []
    for _ in range(2):
        w = time.perf_counter()
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        with tempfile.TemporaryDirectory() as tmp:
            subprocess.run([str(Path(sys.executable).parent / "taxel"), "solve", "thesis-pzt-probe-3d", "--json"],
                           cwd=tmp, check=True, capture_output=True)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cold.append((time.perf_counter() - w, after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime))
    print(f"cold start (a new process, taxel solve, two runs): wall {', '.join(f'{c[0]:.1f}' for c in cold)} s, "
          f"CPU {', '.join(f'{c[1]:.1f}' for c in cold)} s")
    print("| design (silicone above) | unknowns | V/F V/N | CPU s | wall s |")
    print("|---|---|---|---|---|")
    sc = scene("single")
    for i in range(n):
        t = 1e-3 * (1.0 + 0.25 * ((i + 1) // 2) * (-1) ** i)
        r = run(sc.replace(**{"array.silicone_above": t}))
        print(f"| {1e3 * t:g} mm | {r['n']} | {r['VF']:.5f} | {r['cpu']:.1f} | {r['wall']:.1f} |", flush=True)


def estimate(case: str):
    from taxel.analyses.accuracy import error_estimate as est
    sc, ref = scene(case), reference(case)
    w, c = time.perf_counter(), time.process_time()
    r = solve_model(sc)
    w1, c1 = time.perf_counter(), time.process_time()
    e = est.estimate(sc, r)
    w2, c2 = time.perf_counter(), time.process_time()
    oe = e.outputs["sensitivity"]
    true = f"true {100 * abs(oe.value / ref - 1):.2f} %, ratio {oe.total / abs(oe.value / ref - 1):.2f}" if ref else ""
    print(f"{case}: V/F {oe.value:.5f} V/N, estimate {100 * oe.total:.2f} % ({e.method}); {true}; press {c1 - c:.1f} s "
          f"of CPU ({w1 - w:.1f} wall), estimate {c2 - c1:.1f} s of CPU ({w2 - w1:.1f} wall); load {os.getloadavg()[0]:.1f}")
    for h in e.how:
        print("  ", h)


def linear_estimate():
    from taxel.analyses.accuracy import error_estimate as est
    refs = json.loads((DOCS / "reference_3d.json").read_text())
    for key, rec in refs.items():
        sc = load(rec["scene"])
        c = time.process_time()
        r = solve_model(sc)
        e = est.estimate(sc, r)
        oe = e.outputs["sensitivity"]
        mean = abs(oe.value / rec["reference"] - 1)
        worst = max(abs(oe.value / f["reference"] - 1) for f in rec["fits"])
        print(f"{key}: V/F {oe.value:.5f} V/N, discretisation estimate {100 * oe.discretisation:.3f} % ({e.method}); "
              f"error against the chains' mean {100 * mean:.3f} % (ratio {oe.discretisation / mean:.1f}), the largest "
              f"against a chain {100 * worst:.3f} % (ratio {oe.discretisation / worst:.1f}); {time.process_time() - c:.1f} s "
              f"of CPU")


def profile(case: str):
    pr = cProfile.Profile()
    pr.enable()
    r = run(scene(case))
    pr.disable()
    print(row(f"{case}, profiled", r, reference(case)))
    pstats.Stats(pr).sort_stats("tottime").print_stats(25)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--case", choices=("single", "3x3", "both"), default="both")
    ap.add_argument("--levels", default=",".join(f"{k:.6g}" for k in LEVELS),
                    help="size divisors k of the refinements (1: the default press mesh)")
    ap.add_argument("--far-taxel", type=float, help="the levels with this Layout.far_taxel (default FAR_TAXEL)")
    ap.add_argument("--levers", choices=("single", "3x3"))
    ap.add_argument("--only", default="", help="comma-separated parts of lever names to run (with the default)")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--profile", choices=("single", "3x3"))
    ap.add_argument("--designs", type=int, default=0)
    ap.add_argument("--estimate", choices=("single", "3x3"))
    ap.add_argument("--linear-estimate", action="store_true")
    a = ap.parse_args()
    if a.profile:
        profile(a.profile)
        return
    if a.linear_estimate:
        linear_estimate()
        return
    if a.estimate:
        estimate(a.estimate)
        return
    if a.designs:
        designs(a.designs)
        return
    if a.levers:
        levers(a.levers, a.repeat, [s for s in a.only.split(",") if s])
        return
    ks = [float(k) for k in a.levels.split(",")]
    for case in (("single", "3x3") if a.case == "both" else (a.case,)):
        levels(case, ks, a.far_taxel)


if __name__ == "__main__":
    main()
