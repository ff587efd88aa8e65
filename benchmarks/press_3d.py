"""The 3D press at the rig's probe against its nested-mesh reference, and what each
speed and accuracy measure buys.

The thesis PZT taxel (thesis-pzt-single-3d), a quarter model, pressed to 1 N by the
rig's probe (a sticking 4 mm flat punch, 0.2 mm edge radius), Yeoh silicone. The
quantity is the pressed taxel's open-circuit voltage per newton, V/F.

Reference (--reference): a family of meshes whose every size (size, piezo_size,
and the contact-aware size under the punch's rounded edge, meshing.build) is
divided by RATIO from one to the next; the observed order p from the last three
and the Richardson value (last three levels) V_ref = V_2 + (V_2 - V_1) / (RATIO^p - 1) where p is at
least MIN_ORDER, else the finest level (not extrapolated, with its last step), written to
docs/press_3d_reference.json with every level's numbers. The default run reads it. Measured
2026-11-25 (the rim a size field, every P2 node of the top a contact point; CPU s, shared
machine): sizes / 0.5, 0.71, 1, 1.41, 2: 11 472, 19 850, 34 143, 69 879, 137 853 unknowns,
V/F -0.80351, -0.79860, -0.79485, -0.79151, -0.78836 V/N, 11, 27, 91, 246, 1 398 s: observed
order 0.17 over the last three, not extrapolated; the reference is -0.78836 V/N, its last
step 0.40 %. (Before, with the rim a plan curve and the edge midpoints as contact points:
three levels, order 2.24, Richardson -0.78992 V/N, which the two finest levels now pass.)
The tables below were measured before 2026-11-25, against that value, except where dated.

Default run: the press at the default settings (the scene's own mesh and Options),
its error against the reference and its wall and CPU time, then the variants
tried, side by side in the same run: the solver's tolerances before (Newton to 1e-9 in
every Uzawa pass, no chord steps); no chord steps; no inexact Uzawa; a penetration
tolerance of 1 % of the travel; the frictionless punch (how far it gets, or why it
stops); a first trial at half the target; force control through 0.25, 0.5, 0.75 N
instead of one target; the PARDISO analysis redone at every Newton step
(Options.reuse_analysis = False); the contact-aware grading off; the contact size at
twice the edge radius; 6 Gauss points per facet instead of the edge midpoints.

The solver's levers (fem.press, fem.contact_newton, fem.linalg), rows of the --divide 0.5 run:
the tangent is symmetric (Yeoh, piezo, contact and stick terms), so PARDISO factorizes its upper
triangle in the symmetric-indefinite mode (the pattern made structurally symmetric, fem.sparsity);
a Newton step's solve refines to 1e-10, not 1e-13; Newton stops at 1e-6 (V/F moves by 3e-5
relative against 1e-9) and, while the contact multipliers still move, at 1e-3 (inexact Uzawa);
a converged iterate gets no tangent (the line search's residual is reused); a chord step tries
the last factorization while the active set, stick set and penalty hold (kept when it cuts the
residual 4x); Newton stagnating on one active set is stopped and named, so force control
bisects at once (at sizes / 0.707 a trial sat at residual 0.027 for 20 iterations before).
Krylov solves preconditioned by an old factorization were not built: one PARDISO solve costs
about a fifth of a numeric factorization at 11 634 unknowns (the solve and factorize columns),
so a Krylov solve of more than a few iterations would cost more than the chord step's refactorization.

Measured (one run each; CPU time, MKL_NUM_THREADS=1, on a machine shared at load 15-25, so wall
times were 10-15x the CPU times). Before this work (the landed code, the same script): the
default mesh 295 s of CPU, 62 Newton iterations, 71 factorizations (152 s), assembly 119 s;
sizes / 0.5 30.4 s of CPU, 38 iterations, 38 factorizations (docs/press_3d_reference.json).

| run | unknowns | V/F V/N | error | states | Newton iterations | factorizations | chord steps | factorize CPU s | solve CPU s | assembly CPU s | CPU s | wall s |
|---|---|---|---|---|---|---|---|---|---|---|---|---|
| **default, 2026-11-25** (--quick; against the finest level, -0.78836 V/N; load 0.9) | 8031 | -0.78635 | -0.25 % | 6 | 53 | 29 | 26 | 1.9 | 0.5 | 3.4 | 6.5 | 6.8 |
| **default** (thesis-pzt-probe-3d, no [mesh]; quiet machine, load 0.8) | 8928 | -0.79594 | +0.76 % | 5 | 39 | 20 | 20 | 1.8 | 0.5 | 2.9 | 5.8 | 6.0 |
| the reference family's mesh (extruded, sizes / 1; same quiet run) | 36687 | -0.79380 | +0.49 % | 8 | 62 | 38 | 32 | 48.0 | 8.5 | 20.9 | 81.1 | 81.1 |
| the reference family's mesh, sizes / 1 (loaded machine) | 36687 | -0.79380 | +0.49 % | 8 | 62 | 38 | 32 | 60.6 | 9.8 | 27.1 | 102.2 | 1111.5 |
| **the default's settings, sizes / 0.5** | 11634 | -0.80804 | +2.29 % | 5 | 33 | 15 | 19 | 3.2 | 1.2 | 3.7 | 9.1 | 110.1 |
| Newton to 1e-9 in every Uzawa pass, no chord steps (the tolerances before) | 11634 | -0.80802 | +2.29 % | 5 | 34 | 35 | 0 | 7.1 | 0.9 | 5.0 | 14.0 | 153.4 |
| no chord steps (a factorization at every Newton step) | 11634 | -0.80802 | +2.29 % | 5 | 24 | 25 | 0 | 5.3 | 0.7 | 3.9 | 10.9 | 156.1 |
| Newton to 1e-6 in every Uzawa pass (no inexact Uzawa) | 11634 | -0.80804 | +2.29 % | 5 | 40 | 15 | 26 | 3.3 | 1.4 | 3.7 | 9.3 | 112.6 |
| penetration tolerance 1 % of the travel (gap_tol 1e-2) | 11634 | -0.80816 | +2.31 % | 6 | 30 | 15 | 16 | 3.3 | 1.1 | 3.3 | 8.9 | 81.4 |
| frictionless punch | 11634 | stopped: 0.608 N reached; Newton stagnates at travel 0.0004022 m: 5 steps on one active set cut the residual from 5.76e-04 only to 2.34e-03 | | | | | | | | | 136.4 | |
| first trial at half the target from the unpressed stiffness | 11634 | -0.81152 | +2.73 % | 4 | 30 | 18 | 15 | 3.6 | 1.2 | 3.9 | 9.5 | 59.6 |
| load path 0.25, 0.5, 0.75, 1 N | 11634 | -0.80802 | +2.29 % | 10 | 54 | 13 | 42 | 2.5 | 1.5 | 4.4 | 9.7 | 34.6 |
| PARDISO analysis at every Newton step | 11634 | -0.80804 | +2.29 % | 5 | 33 | 15 | 19 | 4.9 | 1.0 | 3.1 | 9.8 | 30.9 |
| no contact-aware grading (edges at piezo_size only) | 5528 | -0.82406 | +4.32 % | 6 | 34 | 11 | 24 | 0.6 | 0.3 | 1.6 | 2.7 | 8.3 |
| contact size 2 x edge radius | 5528 | -0.82552 | +4.51 % | 6 | 34 | 11 | 24 | 0.5 | 0.3 | 1.6 | 2.7 | 8.7 |
| 6 Gauss points per facet (intorder 3) | 11634 | stopped: 0.00489 N reached; Newton inverts silicone elements at travel 2.825e-06 m | | | | | | | | | 34.2 | |

(The default is the press's default mesh, taxel.scene.DEFAULT_PRESS_MESH: free silicone, one
element through the piezo, graded at the punch's rim; benchmarks/press_3d_mesh.py chose it. The
first two rows from --quick on a quiet machine, the third from --quick under load, the others from --divide 0.5; the machine's load fell during the
second run, so its later rows' wall times are 3x their CPU times, the first rows' 10-15x.)

The press (mesh + assemble + press to 1 N) is 2.9x cheaper at the default mesh (102 s against
295 s of CPU, the same V/F to 5e-5) and 1.5x at sizes / 0.5 against the tolerances before in the
same run (9.1 s against 14.0 s; 30.4 s in the reference run of the landed code); the 10 s
target within 1 % is not met on these meshes: the default mesh is within 1 % but takes 102 s,
sizes / 0.5 takes 9.1 s but is +2.3 % off. At 36 687 unknowns one numeric factorization costs
1.6 s of CPU, so the 38 left are 60 % of the time; the cheaper mesh within 1 % (meshing) decides.
A looser penetration tolerance (1 % of the travel) moves V/F by 0.015 % and saves little once
Uzawa is inexact, so gap_tol stays 1e-3 (tests check the penetration against it). A larger first
step (from the unpressed state's stiffness, half the target: 4 states) moves V/F by +0.43 % and
saves nothing: the rounded edge's points slide through the step before they stick, so sticking
keeps the small first steps. The frictionless punch at sizes / 0.5 got to 0.608 N (before continuation; now 0.797 N, below) and stopped,
named: Newton stagnates on one active set at 0.402 mm of travel (the line search's steps down to
1/64; 136 s of CPU with the bisections); it does not reach 1 N.

Frictionless (--frictionless: the default press mesh, then the reference family's at sizes x 2;
one run, load 2, 2026-11-25, with every P2 node of the top a contact point and the rim a size
field (fem.contact, meshing.build); the error column is against the sticking reference, not
comparable, left out; the stop's message names what the stalled Newton iterate measured,
fem.contact_newton):

| variant | unknowns | V/F V/N | error | states | Newton iterations | factorizations | chord steps | factorize CPU s | solve CPU s | assembly CPU s | CPU s | wall s |
|---|---|---|---|---|---|---|---|---|---|---|---|---|
| frictionless punch, the default press mesh | 8031 | stopped: 0.749 N reached at 0.5013 mm, V/F -0.88150 V/N; Newton inverts silicone elements at travel 0.0005014 m ||||||||| 322.8 | 325.1 |
| frictionless punch, the reference family's mesh at sizes x 2 | 11472 | -0.84074 | | 27 | 408 | 1286 | 72 | 176.9 | 14.2 | 93.2 | 305.4 | 308.4 |

The reference family's mesh at sizes x 2 reaches 1 N frictionless, through continuation (1 286
factorizations); the default press mesh stops at 0.749 N. Before the two fixes (edge midpoints
as contact points, the rim a plan curve): 0.687 N at 0.4814 mm on the default mesh (8 928
unknowns) and 0.797 N at 0.5076 mm at sizes x 2 (11 634), elements inverting; with continuation's
active set fixed and 20 steps of patience 0.397 and 0.607 N; before continuation 0.306 and
0.607 N. What stops the default mesh: docs/guide/silicone-and-contact.md, "Frictionless presses".

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/press_3d.py [--reference [--resume]] [--quick] [--divide K] [--frictionless]
(--quick: the default row only; --divide K: the rows on the default mesh with every size divided
by K, e.g. 0.5 for a mesh twice as coarse, to compare the variants at a quarter of the cost;
--frictionless: the frictionless punch on the default press mesh and at sizes x 2 only)
"""

from __future__ import annotations

import dataclasses
import json
import sys
import time
from pathlib import Path

import numpy as np

from taxel.analyses import problem
from taxel.analyses.adapter import checked_layout, check
from taxel.fem.assembly import assemble
from taxel.fem.press import ContactError, Options, Press
from taxel.meshing.build import build
from taxel.scene import load

OUT = Path(__file__).resolve().parents[1] / "docs" / "press_3d_reference.json"
RATIO = 2 ** 0.5
LEVELS = (0.5, 0.5 * RATIO, 1.0, RATIO, 2.0)   # the reference family: every size divided by these
MIN_ORDER = 1.0   # an observed order below it is not extrapolated (P2 outputs converge at 1-4; 0.17 measured here)


def scene(friction="sticking", **edit):
    """The thesis taxel in 3D pressed to 1 N by the rig's probe (Yeoh, sticking)."""
    return load("thesis-pzt-single-3d").replace(**{
        "model.silicone": "yeoh", "load.kind": "indenter", "load.contact": True, "load.radius": 2e-3,
        "load.edge_radius": 0.2e-3, "load.force": 1.0, "load.friction": friction, **edit})


def layout(sc, divide=1.0, contact_factor=1.0, grading=True):
    """The scene's layout with every size divided by `divide`; the contact size
    `contact_factor` x the edge radius (grading False: none)."""
    lay = checked_layout(sc, check(sc))
    if not grading:
        return dataclasses.replace(lay, contact_size=None, rim=0.0, size=lay.size / divide,
                                   piezo_size=lay.piezo_size / divide)
    return dataclasses.replace(lay, size=lay.size / divide, piezo_size=lay.piezo_size / divide,
                               contact_size=contact_factor * lay.contact_size / divide)


def run(sc, lay, opts: Options | None = None, path=()):
    """Mesh, assemble and press to 1 N; the numbers of the run."""
    w, c = time.perf_counter(), time.process_time()
    tm = build(lay)
    prob = problem(sc, tagged_mesh=tm)
    pr = Press(assemble(prob), prob.indenter, opts=opts)
    try:
        for F in (*path, 1.0):
            pt = pr.force(F)
    except ContactError as exc:
        p = pr.res.points[-1] if pr.res.points else None
        last = (f"{p.force:.3g} N reached at {1e3 * p.travel:.4g} mm, V/F {p.voltages['taxel_0_0'] / p.force:.5f} V/N"
                if p else "no state reached")
        return dict(n=pr.red.n, error=f"{last}; {exc}", force=p.force if p else 0.0, travel=p.travel if p else 0.0,
                    VF=p.voltages["taxel_0_0"] / p.force if p else None,
                    cause=str(exc), cpu=time.process_time() - c, wall=time.perf_counter() - w)
    return dict(n=pr.red.n, VF=pt.voltages["taxel_0_0"] / pt.force, travel=pt.travel, states=len(pr.res.points),
                iterations=pr.res.total_iterations, factorizations=pr.stats["factorizations"],
                factorize_s=pr.stats["factorize_s"], assemble_s=pr.stats["assemble_s"],
                solve_s=pr.stats["solve_s"], chord=pr.stats["chord_steps"], wall=time.perf_counter() - w, cpu=time.process_time() - c)


def stop(r) -> tuple[float, float, float | None, str]:
    """(force reached, travel, V/F at the last state, cause) of a run: 1 N and "reached 1 N",
    or where it stopped and the stop's first clause (its cause, without the measurements)."""
    if "error" not in r:
        return 1.0, r["travel"], r["VF"], "reached 1 N"
    text = r["cause"]
    return r["force"], r["travel"], r["VF"], text.split(":")[0] if text.startswith("Newton") else text.split(" (")[0]


def reference():
    """Every level of the family in turn; after each from the third on, the reference
    (Richardson over the last three, where their observed order is at least MIN_ORDER;
    else the finest level, not extrapolated, with its last step) is written, so a stopped
    run keeps what it had."""
    sc = scene()
    rows = []
    done = {r["divide"]: r for r in json.loads(OUT.read_text()).get("levels", [])} if "--resume" in sys.argv else {}
    for k in LEVELS:
        r = done[k] if k in done else run(sc, layout(sc, k))   # --resume: the levels OUT has
        r.pop("divide", None)
        print(f"sizes / {k:.3g}: {r}", flush=True)
        rows.append(dict(divide=k, **r))
        if len(rows) < 3:
            continue
        v = [r["VF"] for r in rows[-3:]]
        out = dict(quantity="V/F, pressed taxel, 1 N, Yeoh, sticking 4 mm punch (0.2 mm edge), 3D quarter",
                   ratio=RATIO, levels=rows)
        p = (float(np.log(abs(v[1] - v[0]) / abs(v[2] - v[1])) / np.log(RATIO))
             if (v[1] - v[0]) * (v[2] - v[1]) > 0 else None)
        if p is not None and p >= MIN_ORDER:
            out.update(order=p, extrapolated=True, VF=v[2] + (v[2] - v[1]) / (RATIO ** p - 1))
            print(f"observed order {p:.2f}; Richardson V/F {out['VF']:.5f} V/N", flush=True)
        else:           # not monotone, or too slow to be the asymptotic range: no extrapolation
            out.update(order=p, extrapolated=False, VF=v[2], last_step=abs(v[2] - v[1]))
            print(f"observed order {p if p is None else round(p, 2)}: not in the asymptotic range; the finest "
                  f"value is the reference (no extrapolation), its last step {abs(v[2] - v[1]):.5f} V/N", flush=True)
        OUT.write_text(json.dumps(out, indent=1) + "\n")


VARIANTS = {
    "Newton to 1e-9 in every Uzawa pass, no chord steps (the tolerances before)":
        dict(opts=Options(tol=1e-9, uzawa_tol=None, chord=False)),
    "no chord steps (a factorization at every Newton step)": dict(opts=Options(chord=False)),
    "Newton to 1e-6 in every Uzawa pass (no inexact Uzawa)": dict(opts=Options(uzawa_tol=None)),
    "penetration tolerance 1 % of the travel (gap_tol 1e-2)": dict(opts=Options(gap_tol=1e-2)),
    "frictionless punch": dict(friction="frictionless"),
    "first trial at half the target from the unpressed stiffness": dict(opts=Options(first_force=0.5)),
    "load path 0.25, 0.5, 0.75, 1 N": dict(path=(0.25, 0.5, 0.75)),
    "PARDISO analysis at every Newton step": dict(opts=Options(reuse_analysis=False)),
    "no contact-aware grading (edges at piezo_size only)": dict(grading=False),
    "contact size 2 x edge radius": dict(contact_factor=2.0),
    "6 Gauss points per facet (intorder 3)": dict(opts=Options(rule="gauss", intorder=3)),
}


def main():
    if "--reference" in sys.argv:
        reference()
        return
    ref = json.loads(OUT.read_text()) if OUT.exists() else None
    sc = scene()

    def line(name, r, sticking=True):
        """A table row; the error column only for a sticking press (the reference is sticking's)."""
        ref = json.loads(OUT.read_text()) if OUT.exists() else None     # (a reference run may be writing it)
        if "error" in r:
            return f"| {name} | {r['n']} | stopped: {r['error']} ||||||||| {r['cpu']:.1f} | {r['wall']:.1f} |"
        err = f"{100 * (r['VF'] / ref['VF'] - 1):+.2f} %" if ref and sticking else ""
        return (f"| {name} | {r['n']} | {r['VF']:.5f} | {err} | {r['states']} | {r['iterations']} | "
                f"{r['factorizations']} | {r['chord']} | {r['factorize_s']:.1f} | {r['solve_s']:.1f} | {r['assemble_s']:.1f} | "
                f"{r['cpu']:.1f} | {r['wall']:.1f} |")

    if ref:
        print(f"reference: V/F {ref['VF']:.5f} V/N, observed order "
              f"{ref['order'] if ref['order'] is None else round(ref['order'], 2)} over sizes / "
              + ", ".join(f"{lv['divide']:.3g}" for lv in ref["levels"]) + f" ({OUT.name})")
    print("| variant | unknowns | V/F V/N | error | states | Newton iterations | factorizations | chord steps | "
          "factorize CPU s | solve CPU s | assembly CPU s | CPU s | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    k = float(sys.argv[sys.argv.index("--divide") + 1]) if "--divide" in sys.argv else 1.0
    if "--frictionless" in sys.argv:      # the frictionless punch on the default mesh and at sizes x 2
        user = load("thesis-pzt-probe-3d").replace(**{"load.friction": "frictionless"})
        print(line("frictionless punch, the default press mesh", run(user, layout(user)), False), flush=True)
        fr = scene("frictionless")
        print(line("frictionless punch, the reference family's mesh at sizes x 2", run(fr, layout(fr, 0.5)), False),
              flush=True)
        return
    if k == 1.0:    # a user's scene without [mesh]: the default press mesh (taxel.scene.DEFAULT_PRESS_MESH)
        user = load("thesis-pzt-probe-3d")
        print(line("**default** (thesis-pzt-probe-3d, no [mesh])", run(user, layout(user))), flush=True)
    print(line("the reference family's mesh (extruded, sizes / 1)" if k == 1.0
               else f"the reference family's mesh, sizes / {k:g}", run(sc, layout(sc, k))), flush=True)
    if "--quick" in sys.argv:
        return
    for name, v in VARIANTS.items():
        s = scene(v["friction"]) if "friction" in v else sc
        lay = layout(s, k, contact_factor=v.get("contact_factor", 1.0), grading=v.get("grading", True))
        print(line(name, run(s, lay, v.get("opts"), v.get("path", ())), "friction" not in v), flush=True)


if __name__ == "__main__":
    main()
