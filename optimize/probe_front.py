"""The front under the rig's press: the linear pressure-patch front corrected by probe presses.

Levels (each a model of the same design, cheapest first):

  A  linear 2D, the base scene's pressure patch: the cheap front (problem.linear(),
     optimize.front) and every design its search visited (all cached);
  B  the probe press in 2D (optimize.probe: the [press] probe on Yeoh silicone,
     plane strain, the base scene's mesh): a few designs, through the correction
     loop of optimize.multifidelity (`correct`: log-linear + inverse-distance ratio
     B/A fitted at the pressed designs, every visited design re-scored, the
     corrected non-dominated set pressed next, until the prediction agrees);
  C  the probe press in 3D (the same probe on a 3D model, PRESS_3D unless given):
     estimated for every pressed design as B x (3D / 2D of the linear patch at the same
     design), the linear verification's ratio (optimize.multifidelity.verify,
     interpolated between its designs): the 3D/2D factor of the geometry from the
     linear model, the material law's and the probe's factor from the 2D press. Then
     `presses_3d` designs of that estimated front, spread along it by crosstalk, are
     pressed in 3D (`press_3d`) and their rows replaced by the 3D press's (the main
     job's count: RUN_3D_PRESSES, 0: a 3D press of a 3x3 front design with its error
     estimate took 101-112 s, benchmarks/probe_front.py, more than a third of the main job's
     whole time, docs/getting-started.md); with presses_3d None
     (`taxel demo --full`) the whole level-B front and the thesis design are pressed
     in 3D through the same correction loop (B corrected to C), and the front is the
     3D presses'. The estimate's largest miss against the 3D presses is the product's
     measured error, added to every row still estimated.

Every front design carries its estimated relative error, the sum of
  - discretisation: the 2D mesh's (DISCRETISATION_2D: the default mesh's voltage error
    against nested references, docs/benchmarks.md) at level B; for a 3D press, the project's
    error estimator on that press (taxel.analyses.accuracy.error_estimate.estimate: on a coarse
    mesh, the same press on a mesh twice as coarse, Richardson at the lowest order
    measured in 3D); for C estimated from B the linear ratio's own 3D mesh error
    (VERIFY_3D_ERROR, the verification mesh's worst measured voltage error, 3.8 %);
  - the correction: for a design predicted, not pressed, the loop's last measured
    disagreement of its prediction; for level C estimated from B, the product's
    error: the larger of PRODUCT_ERROR (the largest miss measured once, below) and the
    largest miss measured by this run's 3D presses;
  - the material law: 0 against the Yeoh law (the fit's own error is the law's, stated
    in docs/guide/silicone-and-contact.md).

`movements` compares, design by design, the linear verified front with the probe
front: how far sensitivity and crosstalk moved, whether the order of the designs by
sensitivity changed, and where the thesis design stands.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from taxel.analyses.accuracy.error_estimate import PRESS_3D_ERROR
from taxel.optimize.multifidelity import (VERIFY_3D, ScoredDesign, MultiFidelity, answer, correct, fine_data,
                                          interpolant, nondominated)
from taxel.scene import DEFAULT_PRESS_MESH
from taxel.optimize.probe import press_key, press_safely, press_scene, stored_press
from taxel.studies.execute import map_on_workers
from taxel.studies.store import Store

# The default 2D mesh's voltage error, the worst measured against nested references: 0.47 %
# (axisymmetric, two elements through the piezo; benchmarks/default_mesh.py, docs/benchmarks.md)
DISCRETISATION_2D = 0.0047
VERIFY_3D_ERROR = 0.038           # the verification mesh's voltage error, worst measured (optimize.multifidelity, 6.)
# The 3D model of the 3D presses (level C): the default press mesh (taxel.scene.DEFAULT_PRESS_MESH,
# the silicone meshed free, graded at the punch's rim), 0.84 % on the thesis taxel from the press's
# nested reference (Richardson fitted over six levels, order 1.35; benchmarks/press_3d.py; error
# floor: PRESS_3D_ERROR)
PRESS_3D = {"model.type": "3d", "mesh.size": f"{1e3 * DEFAULT_PRESS_MESH[0]:g} mm",
            "mesh.piezo_size": f"{1e3 * DEFAULT_PRESS_MESH[1]:g} mm", "mesh.piezo_layers": DEFAULT_PRESS_MESH[2],
            "mesh.extruded": False}
# level C from B x (3D/2D linear): its largest miss on sensitivity against 3D presses of front
# designs, measured by `taxel demo --presses-3d 1` (one run: PZT 5.4 %, PVDF 7.3 %)
PRODUCT_ERROR = 0.073
RUN_3D_PRESSES = 0                # front designs the main job presses in 3D (taxel demo --presses-3d N)
PROBE_FILE = "probe-front.json"   # the headline front, in the linear front's folder
KIND = "probe-front"


@dataclass
class ProbeFront:
    level: str                                  # "3D press" (full) or "2D press x linear 3D/2D"
    pool: list[ScoredDesign]                          # every visited design: cheap = linear 2D
    pressed_2d: list[ScoredDesign]                    # designs pressed in 2D (fine = 2D press)
    pressed_3d: list[ScoredDesign]                    # designs pressed in 3D (full only)
    front: list[dict]                           # the headline front's rows
    reference: dict                             # the thesis design's row
    rounds: dict = field(default_factory=dict)
    spent: dict = field(default_factory=dict)
    movements: list[dict] = field(default_factory=list)
    ranking: dict = field(default_factory=dict)
    fine_model: dict = field(default_factory=lambda: dict(PRESS_3D))

    def record(self, problem) -> dict:
        return {"kind": KIND, "name": problem.spec.name, "level": self.level,
                "press": problem.spec.press.model_dump(), "verify_3d": VERIFY_3D, "press_3d_model": self.fine_model,
                "front": self.front, "reference": self.reference, "movements": self.movements,
                "ranking": self.ranking, "rounds": self.rounds, "spent": self.spent,
                "requirements": dict(problem.spec.requirements),
                "definitions": DEFINITIONS, "sentence": sentence(self)}

    def summary(self, problem) -> list[str]:
        """The probe front, its errors, and each linear front design's move, for a person."""
        names = [f"{n} ({u})" for n, u in zip(problem.names, problem.units)]
        lines = [f"probe front ({self.level}): sensitivity V/N, crosstalk %, estimated error %, design"]
        for r in self.front + [dict(self.reference, how="thesis design")]:
            if r.get("sensitivity (V/N)") is None:
                continue
            lines.append(f"  {r['sensitivity (V/N)']:.4f}  {100 * r['crosstalk']:6.3g}  "
                             + f"{100 * r['estimated error']:4.2f}"
                         + f"{'' if r['within 2 %'] else ' (> 2 %)'}  "
                         + ", ".join(f"{r[n]:.3g}" for n in names) + f"  [{r['how']}]")
        lines.append("moves of the linear 3D-verified front's designs (linear -> probe): sensitivity V/N, crosstalk %")
        for m in self.movements:
            lines.append(f"  {'thesis ' if m.get('thesis design') else ''}"
                         f"{', '.join(f'{m[n]:.3g}' for n in names)}: {m['linear sensitivity (V/N)']:.4f} -> "
                         f"{m['probe sensitivity (V/N)']:.4f} ({100 * m['sensitivity moved']:+.1f} %), "
                         f"{100 * m['linear crosstalk']:.3g} -> {100 * m['probe crosstalk']:.3g} "
                         f"({100 * m['crosstalk moved']:+.1f} %)")
        return lines

    def to_folder(self, out, problem) -> dict:
        rec = self.record(problem)
        (Path(out) / PROBE_FILE).write_text(json.dumps(rec, indent=1))
        return rec


DEFINITIONS = {
    "sensitivity": "|V(F)| / F of the pressed taxel at the operating force F (secant, V/N)",
    "tangent_sensitivity": "|dV/dF| at F (small-signal slope, V/N)",
    "crosstalk": "largest neighbour |V| / pressed |V| of the same press at F",
    "estimated error": "discretisation + correction + material law, relative, on sensitivity; a 3D-pressed "
                       "design's is the error estimator's for its press (on a mesh twice as coarse)"}


def _solver(problem, model: dict | None, workers: int, results: dict | None = None):
    """xs -> [(sensitivity, crosstalk) or None]: the [press] of each design on the 2D base
    mesh (model None) or on `model` (3D, with the press's estimated error: probe.press_metrics),
    stored in the run's store; `results` collects each design's whole press record by x."""
    press = problem.spec.press
    estimate = model is not None

    def datas(xs):
        return [press_scene(problem.scene_data(x) if model is None else fine_data(problem, x, model), press)
                for x in xs]

    def solve(xs):
        ds = datas(xs)
        store = Store(problem.out)
        try:
            got = [stored_press(store, d, press, estimate=estimate) if _cached(store, d, press, estimate) else None
                   for d in ds]
            todo = [i for i, g in enumerate(got) if g is None]
            res = map_on_workers(press_safely, [(ds[i], press, estimate) for i in todo], workers)
            for i, r in zip(todo, res):
                _put(store, ds[i], press, estimate, r)
                got[i] = r
        finally:
            store.close()
        if results is not None:
            results.update({_key(x): g[1] for x, g in zip(xs, got) if g[0] == "done"})
        return [(g[1]["sensitivity"], g[1]["crosstalk"]) if g[0] == "done" else None for g in got]
    return solve


def _key(x) -> tuple:
    return tuple(np.round(np.asarray(x, float), 9))


def _cached(store, data, press, estimate) -> bool:
    row = store.get(press_key(data, press, estimate))
    return row is not None and row["status"] == "done"


def _put(store, data, press, estimate, r):
    status, result, error = r
    store.put(press_key(data, press, estimate), {"probe press": True}, status, result, error,
              (result or {}).get("seconds", 0.0))


def spread(items: list, n: int, key) -> list:
    """n of `items` evenly spread by `key` (both ends first; the middle one for n = 1)."""
    ds = sorted(items, key=key)
    if n >= len(ds):
        return ds
    if n == 1:
        return [ds[len(ds) // 2]]
    return [ds[i] for i in np.unique(np.linspace(0, len(ds) - 1, n).round().astype(int))]


def press_3d(problem, pool_c: list[ScoredDesign], candidates: list[ScoredDesign], cap: int, fine_model: dict = PRESS_3D,
             workers: int = 2, tolerance: float = 0.02, max_rounds: int = 1):
    """Level C: `candidates` of the level-B-scored pool `pool_c` pressed on the 3D model
    `fine_model` through the correction loop (multifidelity.correct, at most `cap` 3D
    presses a round); returns (designs pressed, rounds, each pressed design's press
    record by x, with its estimated error)."""
    records: dict = {}
    pressed, rounds = correct(problem.linear(), pool_c, candidates, cap,
                              _solver(problem, fine_model, workers, records), tolerance, max_rounds)
    return pressed, rounds, records


def _error_3d(rec: dict | None) -> tuple[float, float | None]:
    """A 3D press's estimated error on (sensitivity, crosstalk): the estimator's total
    (discretisation of this mesh + material law 0 on Yeoh)."""
    e = (rec or {}).get("error") or {}
    s, c = e.get("sensitivity", {}).get("total"), e.get("crosstalk", {}).get("total")
    return (PRESS_3D_ERROR if s is None else s), c


def probe_front(problem, linear_mf: MultiFidelity, runs, x_reference, presses_3d: int | None = 0, workers=2,
                tolerance=0.02, max_rounds=2, fine_model: dict = PRESS_3D, rounds_3d: int = 1) -> ProbeFront:
    """The probe front of `problem` (a spec with [press]) from its linear front `runs`
    (problem.linear()'s, optimize.front) and their 3D verification `linear_mf`.
    Level C: `presses_3d` designs of the estimated front (spread by crosstalk) pressed in
    3D on `fine_model`, their rows replaced by the 3D press's; None: the whole level-B
    front and the thesis design (`taxel demo --full`), corrected over `rounds_3d` rounds."""
    from taxel.optimize.multifidelity import visited_designs
    t0 = time.perf_counter()
    lin = problem.linear()
    pool = visited_designs(runs, lin)
    by_x = {_key(d.x): d for d in pool}
    front_a = [by_x[k] for k in (_key(d.x) for d in linear_mf.cheap_front) if k in by_x]
    ref = by_x.get(_key(x_reference))
    if ref is None:
        ref = ScoredDesign(list(map(float, x_reference)), linear_mf.reference.cheap)
        pool.append(ref)
    cap = max(len(front_a), 2)
    pressed_2d, rounds_b = correct(lin, pool, front_a + ([ref] if ref not in front_a else []), cap,
                                   _solver(problem, None, workers), tolerance, max_rounds)
    t1 = time.perf_counter()
    score_b = {id(d): d.fine or d.predicted for d in pool}
    ratio_lin = interpolant(lin, linear_mf.verified)
    rows, ref_row = [], None
    for d in pool:                      # level C estimated: the pressed designs x the linear 3D/2D ratio
        s = score_b[id(d)]
        if s is None or not d.fine:
            continue
        r = ratio_lin(d.x)
        row = _row(lin, d.x, (s[0] * r[0], s[1] * r[1]), "2D press x linear 3D/2D",
                   DISCRETISATION_2D + VERIFY_3D_ERROR + PRODUCT_ERROR)
        row["sensitivity 2D press (V/N)"], row["crosstalk 2D press"] = s
        rows.append(row)
        if d is ref:
            ref_row = row
    pressed_3d, rounds_c, product_miss = [], [], None
    if presses_3d is None or presses_3d > 0:
        pool_c = [ScoredDesign(d.x, score_b[id(d)]) for d in pool if score_b[id(d)] is not None]
        ref_c = next(d for d in pool_c if np.allclose(d.x, ref.x))
        if presses_3d is None:          # full: the pressed level-B front and the thesis design
            at_b = {_key(d.x) for d in pressed_2d}
            cand = nondominated([d for d in pool_c if _key(d.x) in at_b], lambda d: d.cheap)
            cand, cap_c, n_rounds = cand + ([ref_c] if ref_c not in cand else []), len(cand) + 1, rounds_3d
        else:                           # the main job: a few designs of the estimated front
            chosen = {_key(r["x"]) for r in spread([r for r in _nondominated_rows(rows) if r is not ref_row],
                                                    presses_3d, lambda r: r["crosstalk"])}
            cand = [d for d in pool_c if _key(d.x) in chosen]
            cap_c, n_rounds = len(cand), 1
        pressed_3d, rounds_c, recs = press_3d(problem, pool_c, cand, cap_c, fine_model, workers, tolerance, n_rounds)
        est = {_key(r["x"]): r for r in rows}
        miss = [(abs(est[_key(d.x)]["sensitivity (V/N)"] / d.fine[0] - 1),
                 abs(est[_key(d.x)]["crosstalk"] / d.fine[1] - 1)) for d in pressed_3d if d.fine and _key(d.x) in est]
        product_miss = [max(m[k] for m in miss) for k in (0, 1)] if miss else None
        for r in rows:                  # the estimated rows carry the product's measured miss
            if product_miss and product_miss[0] > PRODUCT_ERROR:     # this run measured a larger miss
                r["estimated error"] += product_miss[0] - PRODUCT_ERROR
                r["within 2 %"] = bool(r["estimated error"] <= 0.02)
        for d in pressed_3d:
            if not d.fine:
                continue
            es, ec = _error_3d(recs.get(_key(d.x)))
            row = _row(lin, d.x, d.fine, "3D press", es)
            row["estimated crosstalk error"] = ec
            if _key(d.x) in est:
                row["estimate before the 3D press (V/N, crosstalk)"] = (est[_key(d.x)]["sensitivity (V/N)"],
                                                                        est[_key(d.x)]["crosstalk"])
            rows = [r for r in rows if _key(r["x"]) != _key(d.x)] + [row]
            if _key(d.x) == _key(ref.x):
                ref_row = row
    front = _nondominated_rows(rows)
    if ref_row is None:
        ref_row = {"x": ref.x, "note": "the thesis design's press failed"}
    level = ("3D press" if presses_3d is None else
             f"2D press x linear 3D/2D, {len(pressed_3d)} verified by 3D presses" if pressed_3d else
             "2D press x linear 3D/2D")
    pf = ProbeFront(level, pool, pressed_2d, pressed_3d, front, ref_row,
                    {"2D press": rounds_b, "3D press": rounds_c},
                    {"2D presses": len(pressed_2d),
                     "3D presses": len(pressed_3d), "2D press seconds": t1 - t0,
                     "3D press seconds": time.perf_counter() - t1,
                     "3D solves if every candidate were pressed in 3D": len(pool),
                     "linear designs visited": len(pool),
                     "product error measured": product_miss is not None,
                     "product estimate's largest miss (sensitivity, crosstalk)": product_miss},
                    fine_model=dict(fine_model))
    pf.movements, pf.ranking = movements(lin, linear_mf, pf, ratio_lin, score_b, pool)
    return pf


def _row(problem, x, sc, how, err) -> dict:
    return {"x": list(map(float, x)), **{f"{n} ({u})": v for n, v, u in zip(problem.names, x, problem.units)},
            "sensitivity (V/N)": sc[0], "crosstalk": sc[1], "how": how, "estimated error": err,
            "within 2 %": bool(err <= 0.02)}


def _nondominated_rows(rows) -> list[dict]:
    from taxel.optimize.driver import pareto_front
    keep = set(pareto_front([(r["sensitivity (V/N)"], r["crosstalk"]) for r in rows]))
    return sorted([r for r in rows if (r["sensitivity (V/N)"], r["crosstalk"]) in keep], key=lambda r: r["crosstalk"])


def movements(lin, linear_mf: MultiFidelity, pf: ProbeFront, ratio_lin, score_b, pool):
    """Per design of the linear 3D-verified front: its linear 3D (s, c) and its probe
    estimate at the same design, the relative moves; the ranking by sensitivity under
    each; whether the thesis design is dominated under each."""
    by_x = {_key(d.x): d for d in pool}
    pressed = {_key(d.x): d.fine for d in pf.pressed_3d if d.fine}    # with full: the 3D press
    rows = []
    for d in linear_mf.front_3d:
        p = by_x.get(_key(d.x))
        if p is None or score_b.get(id(p)) is None:
            continue
        s = score_b[id(p)]
        r = ratio_lin(d.x)
        probe = pressed.get(_key(d.x)) or (s[0] * r[0], s[1] * r[1])
        rows.append({**{f"{n} ({u})": v for n, v, u in zip(lin.names, d.x, lin.units)},
                     "linear sensitivity (V/N)": d.fine[0], "probe sensitivity (V/N)": probe[0],
                     "sensitivity moved": probe[0] / d.fine[0] - 1,
                     "linear crosstalk": d.fine[1], "probe crosstalk": probe[1],
                     "crosstalk moved": probe[1] / d.fine[1] - 1})
    ref_lin, ref_row = linear_mf.reference, pf.reference
    thesis = None
    if ref_lin.fine and ref_row.get("sensitivity (V/N)") is not None:
        thesis = {**{f"{n} ({u})": v for n, v, u in zip(lin.names, ref_lin.x, lin.units)},
                  "linear sensitivity (V/N)": ref_lin.fine[0], "probe sensitivity (V/N)": ref_row["sensitivity (V/N)"],
                  "sensitivity moved": ref_row["sensitivity (V/N)"] / ref_lin.fine[0] - 1,
                  "linear crosstalk": ref_lin.fine[1], "probe crosstalk": ref_row["crosstalk"],
                  "crosstalk moved": ref_row["crosstalk"] / ref_lin.fine[1] - 1, "thesis design": True}
    order_lin = np.argsort([-r["linear sensitivity (V/N)"] for r in rows])
    order_probe = np.argsort([-r["probe sensitivity (V/N)"] for r in rows])
    ref = ref_row
    dominated = [r for r in pf.front if ref.get("sensitivity (V/N)") is not None and r["x"] != ref.get("x")
                 and dominates((r["sensitivity (V/N)"], r["crosstalk"]), (ref["sensitivity (V/N)"], ref["crosstalk"]))]
    ranking = {"same order by sensitivity": bool(np.array_equal(order_lin, order_probe)),
               "linear order": order_lin.tolist(), "probe order": order_probe.tolist(),
               "thesis dominated (linear 3D)": not answer(linear_mf)["thesis_on_3d_front"],
               "thesis dominated (probe)": bool(dominated),
               "designs dominating the thesis (probe)": len(dominated)}
    return rows + ([thesis] if thesis else []), ranking


def dominates(a, b, tol=1e-3) -> bool:
    """Does (sensitivity, crosstalk) a dominate b: as sensitive within `tol` with crosstalk
    lower by more than `tol`, or more sensitive by more than `tol` with crosstalk as low
    within `tol` (relative)?"""
    return (a[0] >= b[0] * (1 - tol) and a[1] <= b[1] * (1 - tol)) or \
        (a[0] >= b[0] * (1 + tol) and a[1] <= b[1] * (1 + tol))


def sentence(pf: ProbeFront) -> str:
    ref = pf.reference
    if ref.get("sensitivity (V/N)") is None:
        return "The thesis design could not be pressed."
    n = pf.ranking.get("designs dominating the thesis (probe)", 0)
    level = "3D presses" if pf.level == "3D press" else "a 2D press scaled by the linear 3D/2D ratio"
    head = (f"Under the probe ({level}) the thesis design gives {ref['sensitivity (V/N)']:.3g} V/N at "
            f"{100 * ref['crosstalk']:.3g} % crosstalk; "
            + (f"{n} front design{' is' if n == 1 else 's are'} at least as sensitive with less crosstalk."
               if pf.ranking.get("thesis dominated (probe)") else "it is on the probe front."))
    moved = [m for m in pf.movements if not m.get("thesis design")]
    if moved:
        ds = [100 * m["sensitivity moved"] for m in moved]
        dc = [100 * m["crosstalk moved"] for m in moved]
        head += (f" Against the linear 3D front, the front designs' sensitivity moved {min(ds):+.1f} to {max(ds):+.1f} %"
                 f" and crosstalk {min(dc):+.1f} to {max(dc):+.1f} %; the order by sensitivity "
                 f"{'did not change' if pf.ranking['same order by sensitivity'] else 'changed'}.")
    return head
