"""The influence metrics of a design, coverage and localization_error: both from one set
of influence functions (taxel.analyses.surface.influence: the 2D section's line scan of a press
as wide as a taxel, 9 static solves for a 3-taxel row, each press position a point of
the optimization's OUT/influence store), at the smallest force of interest, against
one noise floor.

    smallest_force = "0.2 N"     # both are judged at it (default: the base scene's load force)
    noise = "1 mV"               # white noise on each taxel's open-circuit peak

coverage (ratio): the fraction of the surface between the outer taxels' centres where a
press at the smallest force gives at least one taxel a peak above k = 3 times the
noise floor (taxel.analyses.surface.coverage). localization_error (m): the rms over that
surface of the predicted position error at the same force (the Cramer-Rao bound of
taxel.analyses.surface.localization; it scales as noise / force).

The noise floor sigma (V rms, referred to a taxel's open-circuit peak) is the design's
readout's when it has one, sigma = F_min,det S (its minimum detectable force, from the
base scene's [readout] or the [resolution] rig, times the influence scan's open-circuit
sensitivity: the chain's noise referred back to the taxel), else `noise`.

When they are computed: during the search when the objective or a constraint names
them (each evaluation: about 9 2D solves); when only a [requirements] line names them,
after the search, for the designs the answer's choice reaches (`judge_lazily`: the
reference design, then the recommended one until it has them; every candidate for a
localization_error requirement, whose margin is weighed; optimize.run for a
front or an optimum, taxel.jobs.answer_coverage for the main job's answer). Their values
go to OUT/coverage.json (RECORD), which the report's answer reads beside each design's
record.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

INFLUENCE_METRICS = ("coverage", "localization_error")
RECORD = "coverage.json"


def influence_metrics(scene, force: float, noise_V: float, min_detectable_force: float | None = None,
                      out: Path | None = None, per_pitch: int = 8) -> dict:
    """{coverage, localization_error, and how: noise_V, noise_source, force_N, dead_m,
    solves, seconds} of a design (a taxel-array scene); every press position a point of
    the store OUT/influence. None values when a solve fails."""
    from taxel.analyses.surface.coverage import coverage
    from taxel.analyses.surface.influence import influence
    from taxel.analyses.surface.localization import localization_error_of
    from taxel.schema import to_data
    from taxel.studies.evaluate import evaluate_safely
    from taxel.studies.store import Store
    t0 = time.perf_counter()
    store = Store(out / "influence") if out is not None else None

    def solve(s):
        data = to_data(s)
        status, result, error = store.get_or_compute(data, ("voltage",)) if store is not None else \
            evaluate_safely(data, ("voltage",))
        if status != "done":
            raise RuntimeError(error)
        return result["voltage"]
    try:
        infl = influence(scene, per_pitch=per_pitch, edges=False, solve=solve)
    except (RuntimeError, ValueError):
        return dict.fromkeys(INFLUENCE_METRICS)
    finally:
        if store is not None:
            store.close()
    if min_detectable_force is not None and min_detectable_force > 0:
        s_mid = abs(float(infl.sensitivity[len(infl.sensitivity) // 2]))
        sigma, source = min_detectable_force * s_mid, "the readout's minimum detectable force"
    else:
        sigma, source = noise_V, "noise on each open-circuit peak"
    cov = coverage(infl, force, sigma)
    try:
        loc = localization_error_of(infl, scene, sigma, force).rms_m
    except ValueError:
        loc = None
    return {"coverage": cov.fraction, "localization_error": loc, "line_coverage": cov.line_fraction,
            "force_N": force, "noise_V": sigma, "noise_source": source, "sigmas": cov.sigmas,
            "dead_mm": [[1e3 * a, 1e3 * b] for a, b in cov.dead_m], "solves": infl.solves,
            "seconds": time.perf_counter() - t0}


def record(folder: Path) -> list[dict]:
    """The rows of OUT/coverage.json: {"x_mm": {variable: mm}, "coverage", "localization_error", ...}."""
    path = Path(folder) / RECORD
    return json.loads(path.read_text())["designs"] if path.exists() else []


def add(folder: Path, x_mm: dict, values: dict) -> None:
    """Add (or replace) one design's row of OUT/coverage.json."""
    rows = [r for r in record(folder) if not same(r["x_mm"], x_mm)] + [{"x_mm": x_mm, **values}]
    (Path(folder) / RECORD).write_text(json.dumps({"what": __doc__.splitlines()[0], "designs": rows}, indent=1))


def same(a: dict, b: dict, tol_mm: float = 1e-6) -> bool:
    """The same design: every variable of `a` within tol_mm of `b`'s."""
    return all(k in b and abs(a[k] - b[k]) <= tol_mm for k in a)


def of(folder: Path, x_mm: dict) -> dict:
    """The influence metrics OUT/coverage.json holds for design `x_mm` ({} when none)."""
    row = next((r for r in record(folder) if same(r["x_mm"], x_mm)), None)
    return {k: row[k] for k in INFLUENCE_METRICS if row.get(k) is not None} if row else {}


def judge_lazily(candidates: list[dict], reqs: list, compute, always=()) -> None:
    """Fill in the influence metrics `reqs` name, in place, for the candidates `always` lists
    (the reference design, shown beside the answer) and for the one the answer's choice
    (optimize.requirements.choose) recommends, again until the recommended one has them: a
    candidate the choice never reaches is not solved (its margin "not evaluated"), and
    one that fails a requirement loses to the next. That is exact for a requirement met
    or not (coverage: the choice never weighs its margin); a performance requirement
    (localization_error: its margin is weighed, and an unsolved design cannot win on it)
    is computed for every candidate. `compute(i)` -> {metric: value}."""
    from taxel.optimize.requirements import choose
    named = [r for r in reqs if r.metric in INFLUENCE_METRICS]
    if not named:
        return
    done = set()
    for i in (range(len(candidates)) if any(not r.limit for r in named) else always):
        candidates[i].update(compute(i))
        done.add(i)
    while True:
        i = choose(candidates, reqs).recommended
        if i is None or i in done:
            return
        candidates[i].update(compute(i))
        done.add(i)
