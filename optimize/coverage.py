"""The influence metrics of a design, coverage and localization_error: both from its 3D
surface map (taxel.analyses.surface.surface_map: every taxel's response to a force anywhere on
the top surface, by reciprocity from one linear 3D solve per mirror class), at the
smallest force of interest, against one noise floor, for the probe's footprint.

    smallest_force = "0.2 N"     # both are judged at it (default: the base scene's load force)
    noise = "1 mV"               # white noise on each taxel's open-circuit peak

coverage (ratio): the fraction of the surface between the outer taxels' centres where a
press of the probe's footprint at the smallest force gives at least one taxel an
open-circuit voltage above k = 3 times the noise floor; with it the 3D minimum (the
smallest best-taxel margin over that surface, searched, and where: taxel.analyses.
map_metrics). localization_error (m): the rms over that surface of the Cramer-Rao
position error at the same force (with its 95th percentile and worst case).

The footprint: the optimization's [press] probe (a flat punch's radius, a sphere's
contact taken as its radius, Hertzian), else a flat disc as wide as a taxel (the
thesis rig's 4 mm punch on its 4 mm taxels). The map: the design's 3D model (a 2D
design is made 3D on MAP_MESH, the array mesh measured at +0.067 % on the 3x3 array's
pressed taxel, docs/benchmarks.md), linear silicone (the small-force limit); one map
per design, kept in OUT/maps (keyed by the map scene's SHA-256) for the report's figure.

The noise floor sigma (V rms, referred to a taxel's open-circuit peak) is the design's
readout's when it has one, sigma = F_min,det S (its minimum detectable force, from the
base scene's [readout] or the [resolution] rig, times the middle taxel's open-circuit
sensitivity to the footprint at its centre: the chain's noise referred back to the
taxel), else `noise`.

When they are computed: during the search when the objective or a constraint names
them; when only a [requirements] line names them, after the search, for the designs the
answer's choice reaches (`judge_lazily`: the reference design, then the recommended one
and each priced relaxation's design until they have them, exactly: both are limits;
optimize.run for a front or an optimum, taxel.jobs.answer_coverage for the
main job's answer). Their values go to OUT/coverage.json (RECORD), which the report's
answer reads beside each design's record.

A check that fails (the design's mesh or solve) is not hidden: its row carries `error`
(one line), and a design whose requirement could not be checked is never recommended
(judge_lazily marks it, optimize.requirements.judge excludes it).
"""

from __future__ import annotations

import hashlib
import json
import logging
import time
from pathlib import Path

INFLUENCE_METRICS = ("coverage", "localization_error")
RECORD = "coverage.json"
MAPS = "maps"
MAP_MESH = ("2 mm", "0.8 mm")     # mesh.size, mesh.piezo_size of a 2D design's 3D map
CHECK_ERRORS = "check_errors"     # a candidate's {metric: why it could not be checked}
WEAKEST = ("coverage_minimum", "coverage_minimum_at_mm")   # the 3D map's weakest point, which a 100 % coverage is judged on


def design_map_scene(scene):
    """The 3D scene whose map judges a design: the scene itself when 3D, else made 3D on MAP_MESH."""
    if scene.model.type == "3d":
        return scene
    return scene.replace(**{"model.type": "3d", "model.depth": None, "model.symmetry": "auto",
                            "mesh.size": MAP_MESH[0], "mesh.piezo_size": MAP_MESH[1]})


def default_footprint(scene, probe=None):
    """The probe's footprint (module docstring): `probe` an optimize.probe.ProbePress or None."""
    from taxel.analyses.surface.surface_map import Footprint
    from taxel import units as U
    if probe is not None and getattr(probe, "radius", None) is not None:
        r = U.in_unit(probe.radius, "m")[0] if not isinstance(probe.radius, (int, float)) else float(probe.radius)
        return Footprint(float(r), "round" if getattr(probe, "shape", "flat") == "sphere" else "flat")
    return Footprint(scene.array.taxel_width / 2, "flat")


def design_map(scene, out: Path | None = None):
    """The surface map of a design (module docstring), read from OUT/maps when it is there."""
    from taxel.analyses.surface.surface_map import SurfaceMap, build
    from taxel.schema import to_data
    s3 = design_map_scene(scene)
    key = hashlib.sha256(json.dumps(to_data(s3), sort_keys=True, default=str).encode()).hexdigest()[:16]
    path = Path(out) / MAPS / f"{key}.npz" if out is not None else None
    if path is not None and path.exists():
        return SurfaceMap.from_file(path), path
    m = build(s3)
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        m.to_file(path)
    return m, path


def influence_metrics(scene, force: float, noise_V: float, min_detectable_force: float | None = None,
                      out: Path | None = None, per_pitch: int = 8, footprint=None) -> dict:
    """{coverage, localization_error, and how: coverage_minimum (the 3D minimum margin) and
    where, localization_error_p95 / _worst, noise_V, noise_source, force_N, footprint, map
    (its file under OUT), seconds} of a design (a taxel-array scene). When the check cannot
    be made (a mesh or solve that fails) the metrics are None and `error` says why (one line).
    `per_pitch` is kept for callers of the 2D scan; the map does not use it."""
    from taxel.analyses.surface import map_metrics
    t0 = time.perf_counter()
    fp = footprint or default_footprint(scene)
    try:
        m, path = design_map(scene, out)
    except Exception as exc:       # gmsh raises a bare Exception: reported in the row, never hidden
        why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        logging.getLogger(__name__).error("%s: coverage not checked, the 3D surface map failed: %s (the design "
                                          "is not recommended)", scene.name, why)
        return {**dict.fromkeys(INFLUENCE_METRICS), "error": f"the 3D surface map failed: {why}",
                "seconds": time.perf_counter() - t0}
    if min_detectable_force is not None and min_detectable_force > 0:
        mid = len(m.taxels) // 2
        s_mid = abs(float(m.press([m.centres[mid]], 1.0, fp)[0, mid]))
        sigma, source = min_detectable_force * s_mid, "the readout's minimum detectable force"
    else:
        sigma, source = noise_V, "noise on each open-circuit peak"
    cov = map_metrics.coverage(m, force, sigma, fp)
    try:
        loc = map_metrics.localization(m, force, sigma, fp)
    except ValueError:
        loc = None
    return {"coverage": cov.fraction, "localization_error": loc.rms_m if loc else None,
            "coverage_minimum": cov.minimum, "coverage_minimum_at_mm": [1e3 * v for v in cov.minimum_at],
            **({k: v for k, v in loc.record().items() if k != "localization_error"} if loc else {}),
            "force_N": force, "noise_V": sigma, "noise_source": source, "sigmas": cov.sigmas,
            "footprint": {"radius_m": fp.radius, "profile": fp.profile},
            "map": str(path.relative_to(out)) if path is not None else None,
            "map_seconds": m.info.get("seconds", {}).get("total"), "unknowns": m.info.get("unknowns"),
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
    """The influence metrics OUT/coverage.json holds for design `x_mm` ({} when none), and
    CHECK_ERRORS {metric: why} when its check failed."""
    row = next((r for r in record(folder) if same(r["x_mm"], x_mm)), None)
    if row is None:
        return {}
    got = {k: row[k] for k in (*INFLUENCE_METRICS, *WEAKEST) if row.get(k) is not None}
    if row.get("error"):             # the check failed: the design is never recommended (requirements.judge)
        got[CHECK_ERRORS] = {k: row["error"] for k in INFLUENCE_METRICS if row.get(k) is None}
    return got


def judge_lazily(candidates: list[dict], reqs: list, compute, always=()) -> None:
    """Fill in the influence metrics `reqs` name, in place, for the candidates `always` lists
    (the reference design, shown beside the answer), for the one the answer's choice
    (optimize.requirements.choose) recommends and for each design a relaxation's price
    (optimize.answer.prices) names, again until every one of them has them: a candidate
    the choice never reaches is not solved (its value "not evaluated"), and one that
    fails a requirement loses to the next.

    Exact, not a shortcut: coverage and localization_error are limits (met or not, their
    margins never weighed), and a candidate not judged counts as meeting them, so the
    choice among the candidates judged so far is the best it can be; once the design it
    picks (and each price's) has been judged, a candidate not judged can only lose
    (its true values can only exclude it) or, for a price, was already counted in. A
    weighed influence metric (none is: both are limits) would need every candidate
    judged, and gets it. `compute(i)` -> {metric: value, "error": why, when a metric is
    None}; a candidate whose named metric could not be computed gets CHECK_ERRORS
    {metric: why} and is not recommended (optimize.requirements.judge)."""
    named = [r for r in reqs if r.metric in INFLUENCE_METRICS]
    if not named:
        return
    done = set()

    def judged(i):
        got = compute(i)
        failed = {r.metric: got.get("error") or "not computed" for r in named if got.get(r.metric) is None}
        candidates[i].update({k: v for k, v in got.items() if k != "error"})
        if failed:                     # never recommended (optimize.requirements.judge)
            candidates[i][CHECK_ERRORS] = {**candidates[i].get(CHECK_ERRORS, {}), **failed}
        done.add(i)
    for i in (range(len(candidates)) if any(not r.limit for r in named) else always):
        judged(i)
    while True:
        todo = [i for i in reached(candidates, reqs) if i not in done]
        if not todo:
            return
        for i in todo:
            judged(i)


def reached(candidates: list[dict], reqs: list) -> list[int]:
    """The candidates the answer names (judge_lazily): the recommended one and each price's
    design (optimize.requirements.relaxations); every candidate when none is recommended (the
    closest is named among all)."""
    from taxel.optimize.requirements import choose, relaxations
    ch = choose(candidates, reqs)
    if ch.recommended is None:
        return list(range(len(candidates)))
    return list(dict.fromkeys([ch.recommended] + [d for _, _, d in relaxations(candidates, reqs, ch.recommended)]))
