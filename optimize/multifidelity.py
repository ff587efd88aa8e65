"""A multi-fidelity front: search on the cheap model, verify in 3D, correct, repeat.

1. The epsilon-constraint front is found on the cheap model (the problem's own:
   2D plane strain, problem.front).
2. Every front point and the reference (thesis) design are re-solved in 3D
   (VERIFY_3D, a coarse 3D mesh whose error is measured by the work-precision
   chart, studies.work_precision), on the Dask workers, cached in the run's store.
3. Correction, multiplicative: at each verified design the ratios
   r_s = s_3D / s_2D and r_c = c_3D / c_2D of sensitivity and crosstalk;
   between them log r is fitted linear in the normalised design variables plus
   an inverse-distance interpolation of the residuals (exact at the verified
   designs). Multiplicative, not additive, because the 2D error is a factor
   (2D crosstalk is 2-9x the 3D one here) that varies with the geometry about
   exponentially (crosstalk decays faster with the gap in 3D than in a 2D
   section): log-linear captures that trend with four coefficients, keeps a
   corrected crosstalk positive, and needs no more points than the first
   round verifies. (Inverse-distance weighting alone was tried first: its
   corrected predictions missed 3D by 625 % and then 116 % on the PZT front.)
4. Every design the cheap search evaluated (its history, all cached) is
   re-scored with the corrected model; the non-dominated set of the corrected
   scores is the next candidate front; its designs not yet verified are solved
   in 3D, at most as many a round as the cheap front has points (spread along
   it). The loop stops when every candidate is verified, when the corrected
   prediction of each newly verified design agreed with 3D within `tolerance`,
   or after `max_rounds`.
5. The 3D-verified front is the non-dominated set of all designs solved in 3D
   (3D values only).
6. Confirmation (`confirm`): VERIFY_3D is cheap but coarse (0.2-3.8 % off in
   voltage, measured; 3-6 % on the thesis 3x3 array against its 3D reference),
   which is as large as the differences the front shows. So the two designs the
   answer compares, the reference (thesis) design and the most sensitive 3D-front
   design at or below its crosstalk, are solved again on CONFIRM_3D, the
   estimator's cheapest 3D model (taxel.analyses.accuracy.error_estimate.CHEAP_3D: at most
   0.42 % off in voltage and 3.5 % in crosstalk over the estimator's 22 scenes). The corrected search is restricted to the designs the cheap
   search visited: no new 2D solves, so the loop costs only 3D solves.

The plan (solves per fidelity, estimated wall time from measured per-solve
times) is stated before the start and what was spent at the end.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from taxel.analyses.accuracy.error_estimate import CHEAP_3D
from taxel.optimize.driver import pareto_front, violation
from taxel.optimize.result import FrontRun
from taxel.studies.evaluate import evaluate_safely
from taxel.studies.execute import map_on_workers
from taxel.studies.store import Store, point_key

# The 3D model the front is verified on: 3 mm elements, 1.2 mm at the taxels, two through
# the piezo (3x3 array: 2e4 unknowns, about 6 s, 0.8 GB). Its error against the finest 3D
# is measured by the work-precision chart (taxel work-precision thesis-pzt-3x3-2d).
VERIFY_3D = {"model.type": "3d", "mesh.size": "3 mm", "mesh.piezo_size": "1.2 mm", "mesh.piezo_layers": 2}
SECONDS_PER_SOLVE = {"cheap": 0.5, "3d": 1.4}      # measured: 2D 3x3 plane strain; 3D 3x3 quarter at VERIFY_3D (1.4 s, benchmarks/work_precision.py)
# The 3D model the answer's two designs are confirmed on (see 6. above).
CONFIRM_3D = {"model.type": "3d", "mesh.size": f"{1e3 * CHEAP_3D['mesh.size']:g} mm",
              "mesh.piezo_size": f"{1e3 * CHEAP_3D['mesh.piezo_size']:g} mm",
              "mesh.piezo_layers": CHEAP_3D["mesh.piezo_layers"]}


@dataclass
class ScoredDesign:
    x: list[float]
    cheap: tuple[float, float]                 # (sensitivity V/N, crosstalk) on the cheap model
    fine: tuple[float, float] | None = None    # the same in 3D
    predicted: tuple[float, float] | None = None   # the corrected prediction before it was verified


@dataclass
class MultiFidelity:
    cheap_front: list[ScoredDesign]
    verified: list[ScoredDesign]
    front_3d: list[ScoredDesign]
    reference: ScoredDesign
    rounds: list[dict] = field(default_factory=list)
    plan: dict = field(default_factory=dict)
    spent: dict = field(default_factory=dict)
    confirmed: dict = field(default_factory=dict)    # "reference", "best": (sensitivity, crosstalk) on CONFIRM_3D

    def record(self, problem) -> dict:
        """front-3d.json: the cheap front, every 3D-verified design, the 3D front, the
        reference (thesis) design in 2D and 3D, the rounds, the plan and what was
        spent, and the answer to the thesis's question (`answer`, `sentence`)."""
        def row(d):
            return {**{f"{n} ({u})": v for n, v, u in zip(problem.names, d.x, problem.units)},
                    "sensitivity 2D (V/N)": d.cheap[0], "crosstalk 2D": d.cheap[1],
                    "sensitivity 3D (V/N)": d.fine[0] if d.fine else None,
                    "crosstalk 3D": d.fine[1] if d.fine else None,
                    "predicted sensitivity": d.predicted[0] if d.predicted else None,
                    "predicted crosstalk": d.predicted[1] if d.predicted else None}
        a = answer(self)
        return {"verify_3d": VERIFY_3D, "confirm_3d": {k: str(v) for k, v in CONFIRM_3D.items()},
                "cheap_front": [row(d) for d in self.cheap_front], "verified": [row(d) for d in self.verified],
                "front_3d": [row(d) for d in self.front_3d], "reference": row(self.reference),
                "rounds": self.rounds, "plan": self.plan, "spent": self.spent, "answer": a,
                "requirements": dict(problem.spec.requirements),
                "sentence": sentence(problem, a)}

    def summary(self) -> list[str]:
        """What the verification spent, for a person."""
        s = self.spent
        return [f"3D verification {s['3D solves']} solves in {len(self.rounds)} rounds, {s['seconds']:.0f} s; "
                f"confirmation on the finer 3D mesh {s.get('confirmation solves', 0)} solves, "
                f"{s.get('confirmation seconds', 0):.0f} s"]

    def to_folder(self, out, problem) -> dict:
        """Write front-3d.json into `out` (the plot: taxel.reports.multifidelity); returns the record."""
        rec = self.record(problem)
        (Path(out) / "front-3d.json").write_text(json.dumps(rec, indent=1))
        return rec


def fine_data(problem, x, model: dict = VERIFY_3D) -> dict:
    """The design's scene on a 3D model (VERIFY_3D unless given)."""
    data = problem.scene_data(x)
    for path, value in model.items():
        sec, key = path.split(".")
        data.setdefault(sec, {})[key] = value
    data.get("model", {}).pop("depth", None)
    return data


def _metrics(result) -> tuple[float, float] | None:
    if result is None:
        return None
    v = result["voltage"].get(result["pressed"])
    return abs(v) / result["force"], result.get("crosstalk")


def solve_3d(problem, xs, workers=2, model: dict = VERIFY_3D) -> list[tuple[float, float] | None]:
    """3D (sensitivity, crosstalk) of designs, from the run's store or solved on workers."""
    outputs = ("voltage", "crosstalk", "max_strain")
    store = Store(problem.out)
    try:
        datas = [fine_data(problem, x, model) for x in xs]
        keys = [point_key(d) for d in datas]
        got = {k: (store.get(k) or {}) for k in keys}
        todo = [(k, d, x) for k, d, x in zip(keys, datas, xs) if got[k].get("status") != "done"]
        if todo:
            res = map_on_workers(evaluate_safely, [(d, outputs) for _, d, _ in todo], workers)
            for (k, _, x), (status, result, error) in zip(todo, res):
                store.put(k, {"x": list(map(float, x)), "fidelity": "3d"}, status, result, error,
                          (result or {}).get("seconds", 0.0))
                got[k] = {"status": status, "result": result}
        return [_metrics(got[k].get("result")) if got[k].get("status") == "done" else None for k in keys]
    finally:
        store.close()


def interpolant(problem, designs: list[ScoredDesign]):
    """The correction (r_s, r_c) at x: log r fitted linear in the normalised design
    variables (least squares; the 2D/3D crosstalk ratio falls about exponentially
    with the gap) plus an inverse-distance interpolation of the fit's residuals,
    so it is exact at every verified design. Fewer points than variables + 2:
    the residual interpolation alone."""
    pts = [d for d in designs if d.fine and d.cheap[1] and d.fine[1]]
    span = np.asarray(problem.hi) - np.asarray(problem.lo)
    X = np.array([(np.asarray(d.x) - problem.lo) / span for d in pts])
    L = np.array([[np.log(d.fine[0] / d.cheap[0]), np.log(d.fine[1] / d.cheap[1])] for d in pts])
    A = np.hstack([np.ones((len(X), 1)), X])
    coef = np.linalg.lstsq(A, L, rcond=None)[0] if len(X) >= X.shape[1] + 2 else \
        np.vstack([L.mean(axis=0), np.zeros((X.shape[1], 2))])
    R = L - A @ coef

    def ratio(x) -> np.ndarray:
        u = (np.asarray(x) - problem.lo) / span
        trend = np.concatenate([[1.0], u]) @ coef
        dist = np.linalg.norm(X - u, axis=1)
        if dist.min() < 1e-9:
            return np.exp(trend + R[dist.argmin()])
        w = 1 / dist ** 2
        return np.exp(trend + w @ R / w.sum())
    return ratio


def visited_designs(runs, problem) -> list[ScoredDesign]:
    """Every design the optimizer runs visited, once each, with its cheap metrics."""
    seen, out = set(), []
    for run in runs:
        for h in run.result.history:
            m = h["metrics"]
            key = tuple(np.round(h["x"], 12))
            if key in seen or m.get("sensitivity") is None or m.get("crosstalk") is None:
                continue
            if all(violation(m, c) <= 1e-9 for c in problem.constraints):
                seen.add(key)
                out.append(ScoredDesign(list(map(float, h["x"])), (m["sensitivity"], m["crosstalk"])))
    return out


def nondominated(designs: list[ScoredDesign], score) -> list[ScoredDesign]:
    """The non-dominated designs (sensitivity up, crosstalk down), one per score."""
    keep = {(round(s, 12), round(c, 12)) for s, c in pareto_front([score(d) for d in designs])}
    out = []
    for d in designs:
        key = (round(score(d)[0], 12), round(score(d)[1], 12))
        if key in keep:
            keep.discard(key)
            out.append(d)
    return sorted(out, key=lambda d: score(d)[1])


def plan(problem) -> dict:
    """Solves planned per fidelity and the estimated wall time, before the start."""
    alg, n = problem.spec.algorithm, problem.spec.pareto.points
    cheap = n * alg.max_evaluations
    fine = n + 1
    return {"cheap solves (at most)": cheap, "3D solves (first round)": fine,
            "estimated seconds": cheap * SECONDS_PER_SOLVE["cheap"] + fine * SECONDS_PER_SOLVE["3d"]}


def verify(problem, runs: list[FrontRun], x_reference, tolerance=0.05, max_rounds=3, workers=2) -> MultiFidelity:
    """The multi-fidelity loop over a cheap front `runs` (problem.front's output,
    OptimizationResult.runs)."""
    t0 = time.perf_counter()
    pool = visited_designs(runs, problem)
    by_x = {tuple(np.round(d.x, 9)): d for d in pool}
    cheap_front = [by_x.setdefault(tuple(np.round(r.x, 9)), ScoredDesign(list(map(float, r.x)),
                                                                     (r.metrics["sensitivity"], r.metrics["crosstalk"])))
                   for r in (run.result for run in runs) if r.success and r.metrics.get("sensitivity") is not None]
    cheap_front = nondominated(cheap_front, lambda d: d.cheap)
    cap = max(len(cheap_front), 2)
    ref_cheap = problem.evaluate(np.asarray(x_reference))
    reference = ScoredDesign(list(map(float, x_reference)), (ref_cheap["sensitivity"], ref_cheap["crosstalk"]))
    verified, rounds = correct(problem, pool, cheap_front + [reference], cap,
                               lambda xs: solve_3d(problem, xs, workers), tolerance, max_rounds)
    n3d = sum(r["verified"] for r in rounds)
    front_3d = nondominated([d for d in verified if d.fine], lambda d: d.fine)
    spent = {"cheap designs (feasible, distinct)": len(pool), "3D solves": n3d, "seconds": time.perf_counter() - t0}
    return MultiFidelity(cheap_front, verified, front_3d, reference, rounds, plan(problem), spent)


def correct(problem, pool: list[ScoredDesign], candidates: list[ScoredDesign], cap: int, solve, tolerance=0.05,
            max_rounds=3) -> tuple[list[ScoredDesign], list[dict]]:
    """The correction loop (3.-4. above) over the cheap designs `pool`: solve the
    `candidates` on the expensive level (`solve(xs)` -> [(sensitivity, crosstalk) or
    None], at most `cap` a round), fit the correction (`interpolant`) to every design
    solved so far, predict the rest of the pool, and take its corrected non-dominated
    set as the next candidates. Sets each design's `fine` or `predicted`; returns the
    designs solved and one record per round."""
    rounds: list[dict] = []
    verified: list[ScoredDesign] = []
    for k in range(max_rounds):
        new = [d for d in candidates if d.fine is None]
        if not new:
            break
        if len(new) > cap:              # at most as many expensive solves a round as the front has points
            new = sorted(new, key=lambda d: (d.predicted or d.cheap)[1])
            new = [new[i] for i in np.unique(np.linspace(0, len(new) - 1, cap).round().astype(int))]
        for d, m in zip(new, solve([d.x for d in new])):
            d.fine = m
        verified += [d for d in new if d.fine]
        miss = [max(abs(d.predicted[0] / d.fine[0] - 1), abs(d.predicted[1] / d.fine[1] - 1))
                for d in new if d.predicted and d.fine]
        solved = [d for d in new if d.fine]
        rounds.append({"round": k, "verified": len(new), "largest disagreement of the corrected prediction":
                       max(miss) if miss else None,
                       "largest cheap/expensive disagreement": max((max(abs(d.cheap[0] / d.fine[0] - 1),
                                                                        abs(d.cheap[1] / d.fine[1] - 1))
                                                                    for d in solved), default=None)})
        if (miss and max(miss) <= tolerance) or not verified:
            break
        ratio = interpolant(problem, verified)
        for d in pool:
            if d.fine is None:
                r = ratio(d.x)
                d.predicted = (d.cheap[0] * r[0], d.cheap[1] * r[1])
        candidates = nondominated(pool, lambda d: d.fine or d.predicted)
    return verified, rounds


def best_below(mf: MultiFidelity) -> ScoredDesign | None:
    """The most sensitive 3D-front design at or below the reference's 3D crosstalk."""
    c0 = mf.reference.fine[1]
    below = [d for d in mf.front_3d if d.fine[1] <= c0 and d is not mf.reference]
    return max(below, key=lambda d: d.fine[0]) if below else None


def confirm(problem, mf: MultiFidelity, workers=2) -> MultiFidelity:
    """Solve the reference and `best_below` again on CONFIRM_3D (see 6. above)."""
    if mf.reference.fine is None:
        return mf
    best = best_below(mf)
    designs = {"reference": mf.reference, **({"best": best} if best else {})}
    t = time.perf_counter()
    got = solve_3d(problem, [d.x for d in designs.values()], workers, CONFIRM_3D)
    mf.confirmed = {k: m for k, m in zip(designs, got) if m is not None}
    mf.spent["confirmation solves"] = len(designs)
    mf.spent["confirmation seconds"] = time.perf_counter() - t
    return mf


def answer(mf: MultiFidelity) -> dict:
    """Is the reference design on the 3D front, and what does the 3D front offer?"""
    s0, c0 = mf.reference.fine
    better = [d for d in mf.front_3d if d is not mf.reference and d.fine[0] >= s0 and d.fine[1] <= c0]
    out = {"thesis_3d": {"sensitivity_V_per_N": s0, "crosstalk": c0},
           "thesis_on_3d_front": not better and any(d is mf.reference for d in mf.front_3d)}
    best = b = best_below(mf)
    if b is not None:
        out["best_at_or_below_thesis_crosstalk"] = {"x": b.x, "sensitivity_V_per_N": b.fine[0], "crosstalk": b.fine[1],
                                                   "sensitivity_gain": b.fine[0] / s0 - 1}
    conf = mf.confirmed
    if "reference" in conf:
        out["confirmed"] = {"model": {k: str(v) for k, v in CONFIRM_3D.items()},
                            "thesis": {"sensitivity_V_per_N": conf["reference"][0], "crosstalk": conf["reference"][1]}}
        if "best" in conf:
            b = best
            out["confirmed"]["best"] = {"x": b.x, "sensitivity_V_per_N": conf["best"][0], "crosstalk": conf["best"][1],
                                        "sensitivity_gain": conf["best"][0] / conf["reference"][0] - 1}
    same = [d for d in mf.front_3d if d.fine[0] >= s0]
    if same:
        b = min(same, key=lambda d: d.fine[1])
        out["least_crosstalk_at_thesis_sensitivity"] = {"x": b.x, "sensitivity_V_per_N": b.fine[0],
                                                        "crosstalk": b.fine[1]}
    return out


def sentence(problem, a: dict) -> str:
    """The answer in words; each number names its model's row of the report's model
    ladder (reports.ladder.ROW: 3 the verification mesh, 4 the finer mesh). `problem`:
    anything with the variables' `names` and `units`."""
    t = a["thesis_3d"]
    head = (f"In 3D (ladder row 3) the thesis design gives {t['sensitivity_V_per_N']:.3g} V/N at "
            f"{100 * t['crosstalk']:.3g} % crosstalk; it is {'on' if a['thesis_on_3d_front'] else 'not on'} the "
            "3D-verified front.")
    b = a.get("best_at_or_below_thesis_crosstalk")
    if b and not a["thesis_on_3d_front"]:
        x = ", ".join(f"{n.replace('_', ' ')} {v:.2f} {u}" for n, v, u in zip(problem.names, b["x"], problem.units))
        head += (f" The 3D front offers {b['sensitivity_V_per_N']:.3g} V/N ({100 * b['sensitivity_gain']:+.1f} %) "
                 f"at {100 * b['crosstalk']:.3g} % crosstalk ({x}).")
    c = a.get("confirmed")
    if c:
        t = c["thesis"]
        head += (f" On the finer 3D mesh ({CONFIRM_3D['mesh.size']}, {CONFIRM_3D['mesh.piezo_size']} at the taxels; "
                 "ladder row 4): the thesis design "
                 f"{t['sensitivity_V_per_N']:.3g} V/N at {100 * t['crosstalk']:.3g} %")
        if "best" in c:
            b = c["best"]
            head += (f", the front's design {b['sensitivity_V_per_N']:.3g} V/N ({100 * b['sensitivity_gain']:+.1f} %) "
                     f"at {100 * b['crosstalk']:.3g} %")
        head += "."
    return head
