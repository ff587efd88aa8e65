"""The 3D press at the rig's probe against its nested-mesh reference, and what each
speed and accuracy measure buys.

The thesis PZT taxel (thesis-pzt-single-3d), a quarter model, pressed to 1 N by the
rig's probe (a sticking 4 mm flat punch, 0.2 mm edge radius), Yeoh silicone. The
quantity is the pressed taxel's open-circuit voltage per newton, V/F.

Reference (--reference): a family of meshes (Family: the silicone meshed free, sizes 1 mm far,
0.2 mm at the piezo's edges and under the punch's rim, divided by k from level to level with the
distances the sizes grow over fixed, so every element shrinks; 4 elements through the piezo),
each pressed along one load path (16 travel steps of 25 um, then force control to 1 N: a sticking
press's answer depends on its steps, --path). The reference is Richardson's V_ref from V_k = V_ref +
C h_k^p fitted by least squares to the levels at sizes / FIT_FROM and finer (fit: four or more, so
the residual shows the mesh noise three levels cannot), beside it V_ref at orders 1 and 2 (the
bracket) and the three-level Richardson over the sqrt 2 levels (1.41, 2, 2.83); with fewer levels
Richardson over the last three (any size ratios). It is extrapolated where p is at least MIN_ORDER,
else the finest level is the reference (with its last step); written to docs/press_3d_reference.json
with every level's numbers. The default run reads it. --through: the family with 2k elements
through the piezo (docs/press_3d_reference_through.json). --levels K,...: those levels only (runs of
different levels side by side); --resume: not the levels the files have (with every level there:
the file re-written). --layers, --path: the piezo's elements through its thickness and the load
path on the family's two coarsest levels; --axisymmetric: the axisymmetric probe press's family,
where the piezo's edge can be refined far enough to converge. Measured 2026-11-25: RESULT below.
The tables below were measured before 2026-11-25, against the superseded references, except where dated.

RESULT (2026-11-25, one run each, CPU s on the shared 2-core machine). --reference: sizes / 0.71,
1, 1.41, 1.68, 2, 2.38, 2.83, 3.36: 18 114, 31 062, 59 940, 86 494, 123 598, 183 372, 281 493,
423 664 unknowns, V/F -0.79738, -0.79071, -0.78799, -0.78656, -0.78485, -0.78388, -0.78299,
-0.78243 V/N (travel 0.407 ... 0.420 mm; 32, 69, 204, 425, 883, 1 756, 3 943, 8 248 s; 3.5, 8.8
and 14.3 GB at / 2, / 2.83 and / 3.36, the last on two threads, 82 min wall). The fit over the six
levels from / 1.41: order 1.35, V_ref -0.77981 V/N (the reference), largest residual 2.2e-4 V/N;
at order 1 / 2: -0.77812 / -0.78136; the sqrt 2 levels' Richardson: order 1.50, -0.78027 V/N.
Before / 3.36 was run the fit over five levels gave order 1.14, -0.77871 V/N; / 3.36 read
-0.78243 V/N where that fit predicted -0.78222 (2e-4 off: the mesh noise). Fits over four or
more levels from / 0.71, 1.41, 1.68 and 2 give orders 1.11, 1.35, 2.03, 1.43 and V_ref -0.77933,
-0.77981, -0.78112, -0.78018; three-level Richardson over the close levels scatters (orders
0.3-3.3; --fits prints them): their steps (1.4-1.7e-3 between / 1.41, 1.68 and 2) are within a
few times the noise. The default press mesh: +0.84 % from the reference (+1.06 / +0.64 % at
orders 1 / 2, +0.78 % from the sqrt 2 Richardson, +0.50 % from the finest level; --quick's V/F;
taxel.analyses.accuracy.error_estimate.PRESS_3D_ERROR). --through: / 0.5, 1, 1.5, 2 with 1, 2, 3, 4
through: -0.79092, -0.78969, -0.78652, -0.78485 V/N (order 0.86, not extrapolated). --layers:
1, 2, 4, 8 through at / 0.71: -0.78753, -0.79548, -0.79738, -0.79867; at / 1: -0.78666, -0.78969,
-0.79071, -0.79146 V/N. --path (4 through): force control alone, 4, 8, 16, 32 steps at / 0.71:
-0.79794, -0.79859, -0.79770, -0.79738, -0.79721; at / 1 force control -0.79113, 16 steps
-0.79071 V/N. --axisymmetric: k 0.5, 1, 2, 4, 8 (the piezo's edge 0.2 ... 0.0125 mm): -0.797186,
-0.792362, -0.790471, -0.790623, -0.790484 V/N: converged to 2e-4 once the edge is 0.05 mm or
finer. The families before this one divided the distances the sizes grow over with the sizes
(Family's docstring) and refined neither the piezo's thickness nor the load path: their
Richardson value -0.78992 V/N (order 2.24) and then their finest level -0.78836 V/N (order 0.17)
are superseded. (One-off, not scripted: a ball at the piezo's corner refined to 0.1 / 0.05 mm on the
/ 1 mesh moves V/F to -0.78963 / -0.78973 V/N; on the default press mesh, one through the piezo,
a ball of 0.2 / 0.14 / 0.1 mm at the corners moves it the other way, -0.78853 / -0.78924 / -0.78734 V/N.)

Default run: the press at the default settings (the scene's own mesh and Options),
its error against the reference and its wall and CPU time, then the variants
tried, side by side in the same run: the solver's tolerances before (Newton to 1e-9 in
every Uzawa pass, no chord steps); no chord steps; no inexact Uzawa; a penetration
tolerance of 1 % of the travel; the frictionless punch (how far it gets, or why it
stops); a first trial at half the target; force control through 0.25, 0.5, 0.75 N
instead of one target; the PARDISO analysis redone at every Newton step
(Options.reuse_analysis = False); the contact-aware grading off; the contact size at
twice the edge radius; 6 Gauss points per facet instead of the edge midpoints.

The solver's levers (fem.contact, fem.contact, fem.linalg), rows of the --divide 0.5 run:
the tangent is symmetric (Yeoh, piezo, contact and stick terms), so PARDISO factorizes its upper
triangle in the symmetric-indefinite mode (the pattern made structurally symmetric, fem.assembly);
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
| **default, 2026-11-25, third stop** (--quick, against the six-level fit -0.77981) | 8031 | -0.78635 | +0.84 % | 6 | 53 | 29 | 26 | 1.8 | 0.5 | 3.1 | 6.0 | 6.2 |
| the cheapest 3D model's mesh (same run) | 17214 | -0.79956 | +2.53 % | 6 | 56 | 40 | 18 | 11.5 | 1.9 | 7.4 | 21.9 | 21.9 |
| the scene's own mesh (extruded, 1 mm / 0.4 mm, 2 through; same run) | 34143 | -0.79485 | +1.93 % | 8 | 78 | 56 | 28 | 59.6 | 7.7 | 20.0 | 91.9 | 91.9 |
| default, 2026-11-25, second stop (--quick, against the five-level fit -0.77871; +0.78 % from the sqrt 2 levels' Richardson -0.78027) | 8031 | -0.78635 | +0.98 % | 6 | 53 | 29 | 26 | 1.8 | 0.5 | 2.9 | 5.7 | 5.8 |
| the cheapest 3D model's mesh (same run) | 17214 | -0.79956 | +2.68 % | 6 | 56 | 40 | 18 | 11.6 | 2.1 | 8.0 | 23.0 | 23.0 |
| the scene's own mesh (extruded, 1 mm / 0.4 mm, 2 through; same run) | 34143 | -0.79485 | +2.07 % | 8 | 78 | 56 | 28 | 65.5 | 8.4 | 22.9 | 101.4 | 102.2 |
| **default, 2026-11-25** (--quick, against the finest level then, -0.78485; +0.78 % against the Richardson value -0.78027 since) | 8031 | -0.78635 | +0.19 % | 6 | 53 | 29 | 26 | 1.8 | 0.6 | 3.5 | 6.5 | 9.7 |
| the cheapest 3D model's mesh (error_estimate.CHEAP_3D; same run; +2.47 % against -0.78027) | 17214 | -0.79956 | +1.87 % | 6 | 56 | 40 | 18 | 11.8 | 2.3 | 8.4 | 23.9 | 36.4 |
| the scene's own mesh (extruded, 1 mm / 0.4 mm, 2 through; same run) | 34143 | -0.79485 | +1.27 % | 8 | 78 | 56 | 28 | 65.2 | 8.3 | 23.9 | 102.1 | 153.7 |
| **default, 2026-11-25** (--quick; against the finest level then, -0.78836 V/N; load 0.9) | 8031 | -0.78635 | -0.25 % | 6 | 53 | 29 | 26 | 1.9 | 0.5 | 3.4 | 6.5 | 6.8 |
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
fem.contact):

| variant | unknowns | V/F V/N | error | states | Newton iterations | factorizations | chord steps | factorize CPU s | solve CPU s | assembly CPU s | CPU s | wall s |
|---|---|---|---|---|---|---|---|---|---|---|---|---|
| frictionless punch, the default press mesh | 8031 | stopped: 0.749 N reached at 0.5013 mm, V/F -0.88150 V/N; Newton inverts silicone elements at travel 0.0005014 m ||||||||| 322.8 | 325.1 |
| frictionless punch, the reference family's mesh at sizes x 2 | 11472 | -0.84074 | | 27 | 408 | 1286 | 72 | 176.9 | 14.2 | 93.2 | 305.4 | 308.4 |
| frictionless punch, the default press mesh, 24 travel steps of 25 um (2026-11-25, second stop) | 8031 | stopped: 0.749 N reached at 0.5016 mm, V/F -0.88150 V/N; Newton inverts silicone elements at travel 0.0005023 m ||||||||| 216.7 | |
| frictionless punch, the default press mesh, force steps of 0.1 N (same) | 8031 | stopped: 0.748 N reached at 0.5010 mm, V/F -0.88152 V/N; Newton inverts silicone elements at travel 0.0005011 m ||||||||| 204.3 | |
| frictionless punch, the default press mesh, one target (2026-11-25, third stop: the stop names where; run at low priority beside --reference) | 8031 | stopped: 0.749 N reached at 0.5013 mm, V/F -0.88150 V/N; Newton inverts silicone elements at travel 0.0005014 m: its last line-search step leaves J -0.052 at 1.19 mm from the indenter's axis, 0.024 mm below the top surface; the last converged state, at travel 0.0005013 m, has J down to 0.05 ||||||||| 331.7 | |

The reference family's mesh at sizes x 2 reaches 1 N frictionless, through continuation (1 286
factorizations); the default press mesh stops at 0.749 N. Before the two fixes (edge midpoints
as contact points, the rim a plan curve): 0.687 N at 0.4814 mm on the default mesh (8 928
unknowns) and 0.797 N at 0.5076 mm at sizes x 2 (11 634), elements inverting; with continuation's
active set fixed and 20 steps of patience 0.397 and 0.607 N; before continuation 0.306 and
0.607 N. Along 24 travel steps or nine force steps the default mesh stops where one target does
(0.748-0.749 N, 0.501-0.502 mm): the stop is a travel, not a load path. What stops the default
mesh: docs/guide/silicone-and-contact.md, "Frictionless presses".

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/press_3d.py [--reference [--resume]] [--quick] [--divide K] [--frictionless] [--fits]
(--quick: the default press mesh's, the cheapest 3D model's and the scene's own mesh's rows only; --divide K: the rows on the default mesh with every size divided
by K, e.g. 0.5 for a mesh twice as coarse, to compare the variants at a quarter of the cost;
--frictionless: the frictionless punch on the default press mesh (one target, travel steps, force
steps) and at sizes x 2 only; --fits: the
reference file's fits from each level and Richardson over each triple, no press run)
"""

from __future__ import annotations

import dataclasses
import itertools
import json
import sys
import time
from pathlib import Path

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from taxel.analyses import problem
from taxel.analyses import checked_layout, check
from taxel.analyses.accuracy.error_estimate import CHEAP_3D
from taxel.fem.assembly import assemble
from taxel.fem.contact import PressError, Options, Press
from taxel.meshing.build import build
from taxel.scene import load

DOCS = Path(__file__).resolve().parents[1] / "docs"
BASE = (1e-3, 0.2e-3, 0.2e-3)     # m: size, at the piezo's edges (piezo_size; inside the taxel 2x), under the rim
STEPS = 16          # the reference's load path: travel steps of TRAVEL / STEPS, then force control to 1 N
TRAVEL = 0.4e-3     # m, about the travel of 1 N (0.402-0.421 mm on the families measured)
MIN_ORDER = 1.0     # an observed order below it is not extrapolated (P2 outputs converge at 1-4)
FIT_FROM = 2 ** 0.5  # the levels fitted (sizes / FIT_FROM and finer): a fit from / 1 has order 0.60 (the coarse
#                      levels' steps, 6.7 then 2.7e-3 V/N, are not the asymptotic range); from / 1.41, 1.35 (--fits)
PATH = f"{STEPS} travel steps of {1e3 * TRAVEL / STEPS:g} mm, then force control to 1 N"


@dataclasses.dataclass(frozen=True)
class Family:
    """A family of meshes: the silicone meshed free (Layout.free), the piezo's edges at BASE's
    edge size, the band under the punch's rounded edge at its contact size, far from both at
    its size; every size divided by k from level to level and the distances over which the
    sizes grow fixed (Layout.growth x k), so the size field itself is divided by k and every
    element shrinks. (With the growth distances divided too, a size at a distance d from an edge,
    e/k + (1 - e/S) d / 2, shrinks only in its first part: such a family drifted by
    2.3-2.9e-3 V/N per level, observed order 0.3.) Elements through the piezo: `layers`,
    or 2k (None: the piezo's edge refined through its thickness with the plan)."""

    levels: tuple[float, ...]
    layers: int | None
    out: Path

    def through(self, k):
        """Elements through the piezo at level k."""
        return self.layers or round(2 * k)

    def layout(self, sc, k):
        lay = checked_layout(sc, check(sc))
        size, edge, rim = (v / k for v in BASE)
        return dataclasses.replace(lay, size=size, piezo_size=edge, contact_size=rim, taxel_cap=2.0,
                                   piezo_layers=self.through(k), free=True, growth=lay.growth * k)

    @property
    def text(self):
        through = f"{self.layers} elements" if self.layers else "2k elements"
        return (f"free silicone; sizes {', '.join(f'{1e3 * v:g}' for v in BASE)} mm (far, the piezo's edges, the "
                f"rim) / k, the distances they grow over fixed; {through} through the piezo")


# the reference: the plan refined, 4 elements through the piezo at every level (their own error, a
# fraction of a step, by --layers: 4 -> 8 through at the family's coarsest levels)
# (sizes / 2^0.75 and 2^1.25 between the sqrt 2 levels: four levels for a fit, and the mesh noise; / 2^1.75
# beyond them: a sixth level for the fit)
REFERENCE = Family((0.5 ** 0.5, 1.0, 2 ** 0.5, 2 ** 0.75, 2.0, 2 ** 1.25, 2 ** 1.5, 2 ** 1.75), 4,
                   DOCS / "press_3d_reference.json")
# --through: the piezo's elements through its thickness refined with the plan (2k), a check
THROUGH = Family((0.5, 1.0, 1.5, 2.0), None, DOCS / "press_3d_reference_through.json")
OUT = REFERENCE.out


def scene(friction="sticking", **edit):
    """The thesis taxel in 3D pressed to 1 N by the rig's probe (Yeoh, sticking)."""
    return load("thesis-pzt-single-3d").replace(**{
        "model.silicone": "yeoh", "load.kind": "probe", "load.contact": True, "load.radius": 2e-3,
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


def run(sc, lay, opts: Options | None = None, path=(), travels=(), edit=None):
    """Mesh, assemble and press to 1 N (through the travels, m, then the forces of the
    path, N); the numbers of the run. `edit(system, indenter)`: a change to the assembled
    system before the press (a one-off trial's, benchmarks/frictionless_top_layer.py)."""
    w, c = time.perf_counter(), time.process_time()
    tm = build(lay)
    prob = problem(sc, tagged_mesh=tm)
    sy = assemble(prob)
    if edit is not None:
        edit(sy, prob.indenter)
    pr = Press(sy, prob.indenter, opts=opts)
    try:
        for d in travels:
            pr.travel(d, first=1.0)
        for F in (*path, 1.0):
            pt = pr.force(F)
    except PressError as exc:
        p = pr.res.points[-1] if pr.res.points else None
        last = (f"{p.force:.3g} N reached at {1e3 * p.travel:.4g} mm, V/F {p.voltages['taxel_0_0'] / p.force:.5f} V/N"
                if p else "no state reached")
        return dict(n=pr.red.n, error=f"{last}; {exc}", force=p.force if p else 0.0, travel=p.travel if p else 0.0,
                    VF=p.voltages["taxel_0_0"] / p.force if p else None,
                    cause=exc.cause, summary=exc.summary, cpu=time.process_time() - c, wall=time.perf_counter() - w)
    return dict(n=pr.red.n, layers=lay.piezo_layers, VF=pt.voltages["taxel_0_0"] / pt.force, travel=pt.travel,
                states=len(pr.res.points),
                iterations=pr.res.total_iterations, factorizations=pr.stats["factorizations"],
                factorize_s=pr.stats["factorize_s"], assemble_s=pr.stats["assemble_s"],
                solve_s=pr.stats["solve_s"], chord=pr.stats["chord_steps"], wall=time.perf_counter() - w, cpu=time.process_time() - c)


def stop(r) -> tuple[float, float, float | None, str]:
    """(force reached, travel, V/F at the last state, stop) of a run: 1 N and "reached 1 N", or
    where it stopped and why: the stop's cause and summary (fem.contact.PressError, without
    the measurements)."""
    if "error" not in r:
        return 1.0, r["travel"], r["VF"], "reached 1 N"
    return r["force"], r["travel"], r["VF"], f"{r['cause']}: {r['summary']}"


def steps(n=STEPS):
    """The travels of a load path of n equal steps up to about 1 N (then force control)."""
    return tuple(TRAVEL * i / n for i in range(1, n))


def richardson(h, v):
    """(order p, extrapolated value) of three levels at sizes h0 > h1 > h2 (any ratios) with
    values v, from v_i = v_inf + C h_i^p; (None, None) where the steps change sign or no p
    in (0, 12] fits."""
    (h0, h1, h2), (v0, v1, v2) = h, v
    ratio = lambda p: (h0 ** p - h1 ** p) / (h1 ** p - h2 ** p)    # increasing in p
    q = (v1 - v0) / (v2 - v1) if v2 != v1 else np.inf
    if not ratio(1e-6) < q < ratio(12.0):
        return None, None
    p = brentq(lambda p: ratio(p) - q, 1e-6, 12.0)
    return p, v2 - (v1 - v2) * h2 ** p / (h1 ** p - h2 ** p)


def fit(h, v, p=None):
    """(order p, extrapolated value, largest residual) of v_i = v_inf + C h_i^p fitted to four or more
    levels by least squares (Richardson over more than three levels: the residual measures the mesh
    noise that three levels cannot show); p given: v_inf and C only, at that order."""
    h, v = np.asarray(h), np.asarray(v)

    def solve(p):
        A = np.c_[np.ones_like(h), h ** p]
        c = np.linalg.lstsq(A, v, rcond=None)[0]
        return c[0], v - A @ c
    if p is None:
        p = minimize_scalar(lambda p: float(np.sum(solve(p)[1] ** 2)), bounds=(0.1, 8.0), method="bounded").x
    vx, res = solve(p)
    return p, vx, float(np.abs(res).max())


def levels(fam: Family) -> dict:
    """{k: level} of the family: the levels in either family's file on the same path and sizes whose
    elements through the piezo are this family's at k (REFERENCE's level 2, 4 through, is THROUGH's too)."""
    rows = {}
    for f in (REFERENCE, THROUGH):
        ref = json.loads(f.out.read_text()) if f.out.exists() else {}
        if ref.get("path") == PATH and ref.get("family", "").split(";")[0] == fam.text.split(";")[0]:
            rows.update({r["divide"]: r for r in ref.get("levels", []) if r.get("layers") == fam.through(r["divide"])})
    return rows


def hv(rows):
    """(sizes h = 1 / k, values V/F) of levels."""
    return [1 / r["divide"] for r in rows], [r["VF"] for r in rows]


def fits():
    """--fits: from the reference's file, no press run: the fit from each level on (four or more
    levels) and three-level Richardson over every triple from FIT_FROM on: how far the order and
    the extrapolated value move with the levels chosen (the mesh noise)."""
    rows = json.loads(OUT.read_text())["levels"]
    for i in range(len(rows) - 3):
        p, vx, worst = fit(*hv(rows[i:]))
        print(f"fit from / {rows[i]['divide']:.3g} ({len(rows) - i} levels): order {p:.2f}, V_ref {vx:.5f} V/N, "
              f"largest residual {worst:.1e}")
    for tri in itertools.combinations([r for r in rows if r["divide"] >= FIT_FROM - 1e-9], 3):
        p, vx = richardson(*hv(tri))
        sizes = ", ".join(f"{r['divide']:.3g}" for r in tri)
        print(f"Richardson over / {sizes}: "
              + (f"order {p:.2f}, V_ref {vx:.5f} V/N" if p is not None else "no order (steps grow or change sign)"))


def write(fam: Family, new: dict | None = None):
    """The family's file: its levels (with `new`, a level just run) and the reference: with four or
    more levels at sizes / FIT_FROM and finer, the least-squares fit over them (fit; with V_inf at
    orders 1 and 2 beside it, the bracket); else Richardson over the last three; extrapolated where
    the observed order is at least MIN_ORDER, else the finest level, not extrapolated, with its last step."""
    done = levels(fam) | ({new["divide"]: new} if new else {})
    rows = [r for _, r in sorted(done.items())]
    out = dict(quantity="V/F, pressed taxel, 1 N, Yeoh, sticking 4 mm punch (0.2 mm edge), 3D quarter",
               family=fam.text, path=PATH, levels=rows)
    fitted = [r for r in rows if r["divide"] >= FIT_FROM - 1e-9]
    sqrt2 = [r for r in rows if any(abs(r["divide"] - 2 ** e) < 1e-9 for e in (0.5, 1.0, 1.5))]
    if len(sqrt2) == 3:             # the sqrt 2 levels' three-level Richardson, beside the reference
        out["richardson_sqrt2"] = dict(zip(("order", "VF"), richardson(*hv(sqrt2))))
    if len(rows) >= 3:
        v = [r["VF"] for r in rows[-3:]]
        if len(fitted) >= 4:
            hf, vf = hv(fitted)
            p, vx, worst = fit(hf, vf)
            out.update(fit_from=FIT_FROM, fit_levels=len(fitted), residual=worst,
                       bracket={f"order {q:g}": fit(hf, vf, q)[1] for q in (1.0, 2.0)})
        else:
            p, vx = richardson(*hv(rows[-3:]))
        if p is not None and p >= MIN_ORDER:
            out.update(order=p, extrapolated=True, VF=vx, last_step=abs(v[2] - v[1]))
            print(f"observed order {p:.2f}; Richardson V/F {vx:.5f} V/N" + (
                f" (fit over {len(fitted)} levels, largest residual {out['residual']:.1e} V/N)"
                if "residual" in out else ""), flush=True)
        else:           # not monotone, or too slow to be the asymptotic range: no extrapolation
            out.update(order=p, extrapolated=False, VF=v[2], last_step=abs(v[2] - v[1]))
            print(f"observed order {p if p is None else round(p, 2)}: not in the asymptotic range; the finest "
                  f"value is the reference (no extrapolation), its last step {abs(v[2] - v[1]):.5f} V/N", flush=True)
    fam.out.write_text(json.dumps(out, indent=1) + "\n")


def reference(fam: Family):
    """Every level of the family (--levels K,...: those only), each pressed along steps(); the
    family's file written after each (write), so a stopped run keeps what it had and runs of
    different levels can go side by side (--resume: the levels it has are not run again)."""
    sc = scene()
    only = ([float(k) for k in sys.argv[sys.argv.index("--levels") + 1].split(",")]
            if "--levels" in sys.argv else fam.levels)
    for k in only:
        if "--resume" in sys.argv and k in levels(fam):
            continue
        r = run(sc, fam.layout(sc, k), travels=steps())
        print(f"sizes / {k:.3g}, {r.get('layers')} piezo layers: {r}", flush=True)
        write(fam, dict(divide=k, **r))     # levels re-read: a run of other levels may have written meanwhile
    if "--levels" not in sys.argv:
        write(fam)


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


def studies():
    """--path: the sticking history, V/F along force control alone (the default) and along n equal
    travel steps; --layers: the piezo's elements through its thickness (the reference's path);
    on the family's two coarsest levels."""
    sc = scene()
    print("| level | piezo layers | load path | unknowns | states | V/F V/N | CPU s |\n|---|---|---|---|---|---|---|")
    for k in REFERENCE.levels[:2]:
        if "--path" in sys.argv:
            m = REFERENCE.layers
            cases = [(m, "force control (the default)", ())] + [(m, f"{n} steps", steps(n)) for n in (4, 8, 16, 32)]
        else:
            cases = [(m, f"{STEPS} steps", steps()) for m in (1, 2, 4, 8)]
        for m, name, travels in cases:
            r = run(sc, dataclasses.replace(REFERENCE.layout(sc, k), piezo_layers=m), travels=travels)
            print(f"| sizes / {k:.3g} | {m} | {name} | {r['n']} | {r.get('states', '')} | "
                  f"{r['VF']:.5f} | {r['cpu']:.1f} |", flush=True)


def axisymmetric():
    """--axisymmetric: the rig's probe on the axisymmetric taxel (thesis-pzt-probe-axisymmetric,
    a disk of the taxel's width: not the 3D square's value), the size field / k (as Family) and the
    piezo's elements through its thickness x k (its own 0.5 mm / 0.1 mm mesh, 2 through, at k = 1),
    the reference's path: how fine the piezo's edges must be, at a cost 3D cannot pay."""
    sc = load("thesis-pzt-probe-axisymmetric")
    lay = checked_layout(sc, check(sc))
    print("| k | piezo's edges mm | piezo layers | unknowns | V/F V/N | travel mm | CPU s |\n|---|---|---|---|---|---|---|")
    for k in (0.5, 1, 2, 4, 8):
        lk = dataclasses.replace(lay, size=lay.size / k, piezo_size=lay.piezo_size / k, growth=lay.growth * k,
                                 piezo_layers=max(1, round(lay.piezo_layers * k)))
        r = run(sc, lk, travels=steps())
        print(f"| {k:g} | {1e3 * lk.piezo_size:.4g} | {lk.piezo_layers} | {r['n']} | {r['VF']:.6f} | "
              f"{1e3 * r['travel']:.4f} | {r['cpu']:.1f} |", flush=True)


def main():
    if "--axisymmetric" in sys.argv:
        axisymmetric()
        return
    if "--fits" in sys.argv:
        fits()
        return
    if "--reference" in sys.argv:
        reference(THROUGH if "--through" in sys.argv else REFERENCE)
        return
    if "--path" in sys.argv or "--layers" in sys.argv:
        studies()
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
        fitted = ref["levels"][-ref.get("fit_levels", 3):]
        print(f"reference: V/F {ref['VF']:.5f} V/N, observed order "
              f"{ref['order'] if ref['order'] is None else round(ref['order'], 2)} over sizes / "
              + ", ".join(f"{lv['divide']:.3g}" for lv in fitted) + f" ({OUT.name})")
    print("| variant | unknowns | V/F V/N | error | states | Newton iterations | factorizations | chord steps | "
          "factorize CPU s | solve CPU s | assembly CPU s | CPU s | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    k = float(sys.argv[sys.argv.index("--divide") + 1]) if "--divide" in sys.argv else 1.0
    if "--frictionless" in sys.argv:      # the frictionless punch on the default mesh and at sizes x 2
        user = load("thesis-pzt-probe-3d").replace(**{"load.friction": "frictionless"})
        print(line("frictionless punch, the default press mesh", run(user, layout(user)), False), flush=True)
        # the same mesh along load paths: the stop is a travel (about 0.502 mm), not a path
        print(line("frictionless punch, the default press mesh, 24 travel steps of 25 um",
                   run(user, layout(user), travels=tuple(25e-6 * i for i in range(1, 25))), False), flush=True)
        print(line("frictionless punch, the default press mesh, force steps of 0.1 N",
                   run(user, layout(user), path=tuple(0.1 * i for i in range(1, 10))), False), flush=True)
        fr = scene("frictionless")
        print(line("frictionless punch, the reference family's mesh at sizes x 2", run(fr, layout(fr, 0.5)), False),
              flush=True)
        return
    if k == 1.0:    # a user's scene without [mesh]: the default press mesh (taxel.scene.DEFAULT_PRESS_MESH)
        user = load("thesis-pzt-probe-3d")
        print(line("**default** (thesis-pzt-probe-3d, no [mesh])", run(user, layout(user))), flush=True)
        # the cheapest 3D model's mesh under the punch (taxel.analyses.accuracy.error_estimate.CHEAP_3D_PRESS_ERROR)
        cheap = sc.replace(**CHEAP_3D)
        print(line("the cheapest 3D model's mesh (error_estimate.CHEAP_3D)", run(cheap, layout(cheap))), flush=True)
    print(line("the scene's own mesh (extruded, 1 mm / 0.4 mm, 2 through)" if k == 1.0
               else f"the scene's own mesh, sizes / {k:g}", run(sc, layout(sc, k))), flush=True)
    if "--quick" in sys.argv:
        return
    for name, v in VARIANTS.items():
        s = scene(v["friction"]) if "friction" in v else sc
        lay = layout(s, k, contact_factor=v.get("contact_factor", 1.0), grading=v.get("grading", True))
        print(line(name, run(s, lay, v.get("opts"), v.get("path", ())), "friction" not in v), flush=True)


if __name__ == "__main__":
    main()
