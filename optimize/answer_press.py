"""The answer's designs pressed in 3D by the rig's probe: the numbers a run's answer gives.

Cheap models choose the candidates (the probe front's selection model: a 2D press by the
rig's probe on Yeoh silicone times the linear model's 3D/2D ratio, optimize.probe_front);
the answer's numbers, for the recommended and the thesis (reference) design, are a 3D press
of each by the same probe on Yeoh silicone: the 3x3 array in 3D, its centre taxel pressed
to the operating force, a quarter model by symmetry, on the default press mesh
(optimize.probe_front.PRESS_3D, the free silicone graded at the punch's rim, the taxels the
punch does not touch coarser). One press per design, through `taxel.solve` on the design's
pressed scene (`scene`), so a faster press element drops in without a change here; its
result folder is the design's 3D view (fields and contact curve), the same solve as its
numbers.

Sensitivity is |V(F)| / F of the pressed taxel at F (secant, open circuit), crosstalk the
largest neighbour's |V| over the pressed taxel's, both of that one press at F.

The error estimate (`ANSWER_PRESS_ERROR`) is calibrated on the press family, not computed
per design (a per-design nested reference, or the press's own estimate at 2 x the press's
cost, does not fit the main job's time). The rule (benchmarks/answer_press_error.py):

    sensitivity  e_s = SAFETY x (E_SINGLE + R |rho(sqrt 2) / rho(1) - 1|)
    crosstalk    e_c = SAFETY x R |c(sqrt 2) / c(1) - 1|

E_SINGLE: the single thesis taxel's error at the default press mesh against its nested
reference (0.84 %, eight levels, benchmarks/press_3d.py) plus the reference's own uncertainty (0.30 %,
docs/press_reference.json): 1.14 %; rho = V_3x3 / V_single of the same
design at the same mesh, whose move between the default mesh and every size / sqrt 2 is
extrapolated at the single taxel's measured order P = 1.35 (R = r^P / (r^P - 1) = 2.67,
r = sqrt 2); c the 3x3's crosstalk at the two meshes; SAFETY = 1.25, the estimator's
three-mesh factor. Measured on two designs of each material, stored as the worst by piezo,
rounded up to 0.1 % (each second design's came out above its thesis design's, by 1.25-1.4 x
on sensitivity and 2.7-1.5 x on crosstalk: a constant from one design does not bound the
next, so each material's constant is its worst measured; tests/test_answer_press.py, slow,
checks a third PZT design, gap 4.78 mm). It holds for this mesh model and these piezos only:
a press on another model (`model` not PRESS_3D) or of another piezo gets no estimate (None:
not presented as within 2 %). The 2 % bound (WITHIN) is the page's flag: since the calibration
on the converging refinement path (2026-11-29) neither PZT's 2.6 % nor PVDF's 3.4 % is within it;
each answer is still its 3D press (the better model), its band flagged (optimize.band). Crosstalk
carries its own band (3.7 % PZT, 9.5 % PVDF), flagged too.
"""

from __future__ import annotations

import json
import time
from dataclasses import asdict, dataclass
from pathlib import Path

from taxel.optimize.multifidelity import fine_data
from taxel.optimize.probe import press_scene
from taxel.optimize.probe_front import PRESS_3D, PROBE_FILE

# the rule's constants (module docstring)
P_ORDER = 1.35            # the single taxel's nested family's fitted order (benchmarks/press_3d.py)
# the default press mesh against the single taxel's nested reference (0.84 %, same) plus that
# reference's uncertainty (0.30 %, docs/press_reference.json, benchmarks/press_directions.py; 2026-11-29)
E_SINGLE = 0.0114
SAFETY = 1.25             # taxel.analyses.accuracy.error_estimate.SAFETY_THREE_MESH
REFINE = 2 ** 0.5         # the second mesh: every size / sqrt 2 (taxel.scene.refined)
R = REFINE ** P_ORDER / (REFINE ** P_ORDER - 1)
# benchmarks/answer_press_error.py, 2026-11-28 (docs/answer_press_error.json): the rule on each
# material's thesis design and on a second design of each (1 / 1 mm, gap 3.44 mm PZT, 4.78 mm PVDF), stored
# by the array's piezo as the largest over the designs measured, rounded up to 0.1 % (a piezo not
# calibrated here: no estimate). PZT thesis: 3x3 V/F 0.77581 / 0.77732 V/N (17 941 / 33 501
# unknowns), single taxel 0.78635 / 0.78779 V/N, rho moved 0.012 %, crosstalk 1.1336 / 1.1290 %
# (moved 0.41 %): e_s 1.09 %, e_c 1.36 %. PZT gap 3.44 mm: 3x3 0.77862 / 0.77931 V/N, rho moved
# 0.094 %, crosstalk 0.8692 / 0.8597 % (moved 1.09 %): e_s 1.37 %, e_c 3.66 % -- above the thesis
# design's, so a constant from one design does not bound the next: the stored one is the largest.
# PVDF thesis: 3x3 9.66919 / 9.69160 V/N (17 957 / 33 263), single 9.76461 / 9.81164 V/N, rho moved
# 0.25 %: e_s 1.88 %; crosstalk 2.1389 / 2.1001 % (moved 1.81 %): e_c 6.07 %. PVDF gap 4.78 mm:
# 3x3 9.72672 / 9.72765 V/N (20 274 / 37 444), rho moved 0.47 %: e_s 2.62 %; crosstalk 0.9143 /
# 0.8888 % (moved 2.80 %): e_c 9.35 % -- so a PVDF press is not within 2 % on this mesh. The check,
# a third PZT design (gap 4.78 mm; tests/test_answer_press.py, slow): 3x3 0.77929 / 0.78020 V/N
# (20 246 / 37 610 unknowns), rho moved 0.066 %, crosstalk 0.4734 / 0.4690 % (moved 0.93 %):
# e_s 1.27 %, e_c 3.10 %, within the PZT constants.
# 2026-11-29: the sensitivity constants re-computed from the same recorded moves of rho with E_SINGLE
# including the reference's uncertainty (issue 57): PZT 1.47 / 1.74 / 1.65 % (thesis, gap 3.44, the
# check at gap 4.78), PVDF 2.26 / 3.00 %; stored as the worst, rounded up: PZT 1.8 %, PVDF 3.0 %.
# 2026-11-29, after a press's [mesh] became the converging refinement (the rule's second mesh is now
# every size / sqrt 2 with the grading distance kept): the check design (PZT gap 4.78 mm) gives
# e_s 2.04 % (tests/test_answer_press.py, slow), above 1.8 %: PZT stored as 2.1 % until the
# calibration was re-run on the new path.
# 2026-11-29, the calibration re-run on the converging refinement path (benchmarks/answer_press_error.py
# --write, docs/answer_press_error.json; the rule unchanged): PZT thesis rho moved 0.036 %, crosstalk
# 0.435 %: e_s 1.55 %, e_c 1.46 %; PZT gap 3.44 mm rho moved 0.341 % (its 3x3 falls 0.31 % under
# refinement, the single taxel rises 0.04 %), crosstalk 0.242 %: e_s 2.57 %, e_c 0.81 %; PVDF thesis
# rho 0.193 %, crosstalk 1.96 %: e_s 2.07 %, e_c 6.57 %; PVDF gap 4.78 mm rho 0.567 %, crosstalk
# 2.83 %: e_s 3.32 %, e_c 9.48 %. Stored as the worst by piezo, rounded up to 0.1 %: neither
# material's sensitivity is within the 2 % bound (WITHIN) on this mesh now. The check (PZT gap 4.78 mm,
# a second run): rho moved 0.204 %, crosstalk 0.591 %: e_s 2.11 % (within 2.6 %), e_c 1.98 %, above the
# two designs' 1.46 %: PZT's crosstalk constant stays 3.7 % (the worst on the earlier path, which bounds
# all three designs on both paths), not 1.5 %.
ANSWER_PRESS_ERROR = {"PSI-5H4E": {"sensitivity": 0.026, "crosstalk": 0.037},
                      "PVDF": {"sensitivity": 0.034, "crosstalk": 0.095}}
CALIBRATION = "benchmarks/answer_press_error.py, 2026-11-29, on the converging refinement path"
WITHIN = 0.02                     # the answer's bound on a press's estimate (issue 45): above it, not the answer
KEY = "answer_3d"                 # the record's key in probe-front.json


@dataclass
class AnswerPress:
    """One answer design pressed in 3D: its numbers and their estimated relative errors."""
    role: str                                   # "recommended" or "thesis" ("reference" for a user's)
    x: list[float]                              # the design variables, the problem's units
    sensitivity: float | None = None            # V/N, |V(F)| / F of the pressed taxel
    crosstalk: float | None = None              # ratio
    error: float | None = None                  # relative, on sensitivity (ANSWER_PRESS_ERROR)
    crosstalk_error: float | None = None        # relative, on crosstalk
    max_strain: float | None = None             # the press's largest silicone strain (the strain limit's value)
    unknowns: int | None = None
    seconds: float | None = None
    folder: str | None = None                   # the press's result folder (its 3D view)
    failed: str | None = None                   # why there is no number

    @property
    def within(self) -> bool:
        """The press's estimate (on sensitivity, the design's number) known and within WITHIN;
        crosstalk carries its own band beside it, whatever its size."""
        return self.failed is None and self.error is not None and self.error <= WITHIN


def scene_data(problem, x, model: dict = PRESS_3D) -> dict:
    """The design `x` of `problem` (a spec with [press]) on the 3D `model`, pressed by its probe."""
    return press_scene(fine_data(problem, x, model), problem.spec.press)


def press(data: dict, out: str | None, model: dict = PRESS_3D) -> dict:
    """One press of the scene `data` through taxel.solve (its result folder written to `out`
    when given); a dict of AnswerPress's numbers (JSON-ready: it crosses a worker)."""
    from taxel.analyses import solve
    from taxel.scene import parse
    t0 = time.perf_counter()
    try:
        res = solve(parse(data), out=out)
    except Exception as exc:               # recorded: the answer then says it has no 3D number
        return {"failed": f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"}
    if not res.success:
        return {"failed": f"the press stopped short: {res.stop.message}"}
    o = res.outputs()
    cal = ANSWER_PRESS_ERROR.get((data.get("array") or {}).get("piezo"), {}) if model == PRESS_3D else {}
    return {"sensitivity": abs(o["sensitivity"]), "crosstalk": o.get("crosstalk"), "max_strain": o.get("max_strain"),
            "unknowns": res.unknowns,
            "error": cal.get("sensitivity"), "crosstalk_error": cal.get("crosstalk"),
            "seconds": time.perf_counter() - t0, "folder": str(out) if out else None}


def press_all(jobs: list[tuple[str, dict, str | None]], workers: int = 2, model: dict = PRESS_3D) -> list[dict]:
    """`press` of each (name, scene data, out folder) job, on `workers` Dask processes."""
    from taxel.studies.execute import map_on_workers
    return map_on_workers(press, [(d, out, model) for _, d, out in jobs], workers)


def rule(problem, x, model: dict = PRESS_3D, log=print) -> dict:
    """The estimator's rule (module docstring) measured on the design `x` of `problem`: the 3x3
    and the single taxel of the design, each on `model` and on every size / REFINE (four
    presses); e_s, e_c and every press's numbers (V/F, crosstalk, unknowns, CPU s)."""
    from taxel.analyses import solve
    from taxel.scene import parse, refined
    data = scene_data(problem, x, model)
    single = json.loads(json.dumps(data))
    single["array"].update(rows=1, cols=1)
    single["load"]["taxel"] = [0, 0]
    levels = {}
    for name, d in (("3x3", data), ("single", single)):
        sc = parse({**d, "name": f"{problem.spec.name}-{name}"})
        for k in (1.0, REFINE):
            c = time.process_time()
            res = solve(sc if k == 1.0 else refined(sc, k))
            o = res.outputs()
            r = {"VF": abs(o["sensitivity"]), "crosstalk": o.get("crosstalk"), "unknowns": res.unknowns,
                 "cpu": time.process_time() - c}
            levels[f"{name} / {k:.3g}"] = r
            log(f"  {problem.spec.name} {name} sizes / {k:.3g}: {r['unknowns']} unknowns, V/F {r['VF']:.5f} V/N"
                + (f", crosstalk {100 * r['crosstalk']:.4f} %" if r["crosstalk"] else "") + f", {r['cpu']:.1f} s CPU")
    k2 = f"{REFINE:.3g}"
    rho = [levels["3x3 / 1"]["VF"] / levels["single / 1"]["VF"], levels[f"3x3 / {k2}"]["VF"] / levels[f"single / {k2}"]["VF"]]
    ratio_move = abs(rho[1] / rho[0] - 1)
    xt_move = abs(levels[f"3x3 / {k2}"]["crosstalk"] / levels["3x3 / 1"]["crosstalk"] - 1)
    return {"levels": levels, "rho": rho, "ratio moved": ratio_move, "crosstalk moved": xt_move,
            "sensitivity": SAFETY * (E_SINGLE + R * ratio_move), "crosstalk": SAFETY * R * xt_move}


def write(front_dir: Path, presses: list[AnswerPress], model: dict = PRESS_3D) -> None:
    """The presses into the folder's probe-front.json (KEY), where the answer reads them (through its
    owner: optimize.answer_folder.FolderAnswer.write_presses)."""
    path = Path(front_dir) / PROBE_FILE
    rec = json.loads(path.read_text())
    rec[KEY] = {"model": dict(model), "calibration": CALIBRATION if model == PRESS_3D else None,
                "within": WITHIN, "designs": [asdict(p) for p in presses]}
    path.write_text(json.dumps(rec, indent=1))


def read(rec: dict) -> list[AnswerPress]:
    """The presses of a probe-front record (none when the run made none)."""
    return [AnswerPress(**d) for d in (rec.get(KEY) or {}).get("designs", [])]
