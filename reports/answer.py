"""The answer block on top of the report's index: the design the run recommends and
the thesis design, side by side in engineering units, with the sensitivity,
crosstalk, minimum detectable force and error band of each, the model they come
from, and the trade the recommendation makes.

Where the answer comes from is one function, `headline_front(folder)`: it reads
an optimization folder's headline record (the front under the rig's probe,
probe-front.json, with the linear front beside it; else the 3D-confirmed front,
front-3d.json; else a 2D optimum, optimum.json, as `taxel demo --small` writes)
into a `FrontAnswer` (reports.answer_design holds the types). Point it at another folder (or file) to change what the
index leads with. Nothing is solved here.

Crosstalk is the largest neighbouring taxel's open-circuit |V| divided by the
pressed taxel's (taxel.optimize.metrics), defined once in the block's footnote.
"""

from __future__ import annotations

import json
from pathlib import Path

from taxel.reports import friction_band, warm_touch
from taxel.reports.answer_assumptions import of_answer
from taxel.reports.answer_bands import bands
from taxel.reports.answer_design import AnswerDesign, FrontAnswer, NoiseFloor, preference  # noqa: F401
from taxel.reports.answer_3d import pressed_3d
from taxel.reports.findings import verified_model
from taxel.reports.ladder import COLS as LADDER_COLS, READOUT_FILE, ROW, SELECTION_MODEL, SHORT, VERIFY_3D_ERROR
from taxel.reports.first_screen import MATERIALS, Sweep, dynamics, links as _links, title as _title
from taxel.reports.margins import limits, requirement_cols, requirement_ids, requirement_rows, risks
from taxel.reports.tables import eng, percent
from taxel.units import magnitude

def crosstalk_definition(answers: list[FrontAnswer]) -> str:
    """Crosstalk, defined once for the block, on the answers' own array."""
    sizes = sorted({(a.thesis.values.get("rows"), a.thesis.values.get("cols")) for a in answers} - {(None, None)})
    where = " or ".join(f"{r}x{c}" for r, c in sizes) or "the"
    return ("Crosstalk: the largest neighbouring taxel's open-circuit |V| divided by the pressed taxel's, for a "
            f"press on one taxel of the {where} array (the scene's loaded taxel).")




def headline_front(folder: Path) -> FrontAnswer | None:
    """The answer an optimization folder holds, from its headline record (the probe
    front, else the 3D-confirmed front, else a front, else a 2D optimum); None when it
    holds none."""
    a = _headline(Path(folder))
    if a is not None:
        a.path = Path(folder)
        scene = Path(folder) / "scene.json"
        a.geometry = _geometry(json.loads(scene.read_text()).get("array", {})) if scene.exists() else {}
        _through_readout(a, Path(folder) / READOUT_FILE)
        bands(a, Path(folder))
    return a


def _through_readout(a: FrontAnswer, path: Path) -> None:
    """The designs' numbers through the bench's chain (READOUT_FILE), when the run wrote them."""
    if not path.exists():
        return
    rec = json.loads(path.read_text())
    for r in rec["designs"]:
        d = a.recommended if r["role"] == "recommended" else a.thesis
        if d is None or abs(r["x_mm"]["gap"] - d.gap_mm) > 1e-6 or \
                abs(r["x_mm"]["silicone_above"] - d.silicone_above_mm) > 1e-6:
            continue                                     # written for another answer: not this design's
        d.values.update(charge_sensitivity=r["charge_sensitivity_C_per_N"], readout_sensitivity=r["readout_V_per_N"],
                        min_detectable_force=r["min_detectable_force_N"], force_range=r["force_range_N"],
                        capacitance=r.get("capacitance_F"))
        d.min_detectable_force_N = r["min_detectable_force_N"]
        if r.get("bandwidth_Hz"):
            d.bandwidth_Hz = tuple(r["bandwidth_Hz"])
        a.chain = (f"through the thesis bench's charge amplifier and notch with the rig's mains hum "
                   f"({100 * r['hum_share']:.3g} % of the noise), noise band {r['band_Hz'][0]:g}-{r['band_Hz'][1]:g} Hz"
                   + (f", the amplifier's bandwidth {eng(r['bandwidth_Hz'][0], 'Hz', 3)} to "
                      f"{eng(r['bandwidth_Hz'][1], 'Hz', 3)}" if r.get("bandwidth_Hz") else "")
                   + ": from the answer's own sensitivity and the design's capacitance (its 3D model's, the free "
                     "parallel plate)")


def _headline(folder: Path) -> FrontAnswer | None:
    scene = json.loads((folder / "scene.json").read_text()) if (folder / "scene.json").exists() else {}
    array = scene.get("array", {})
    geo = _geometry(array)
    material = array.get("piezo", "?")
    if (folder / "probe-front.json").exists():     # the headline under the rig's probe (issue: the rig's load)
        linear = (_from_front_3d(folder, json.loads((folder / "front-3d.json").read_text()), geo, material)
                  if (folder / "front-3d.json").exists() else None)
        return _from_probe_front(folder, json.loads((folder / "probe-front.json").read_text()), geo, material,
                                 linear)
    if (folder / "front-3d.json").exists():
        return _from_front_3d(folder, json.loads((folder / "front-3d.json").read_text()), geo, material)
    if (folder / "front.json").exists() and (folder / "result.json").exists():
        return _from_front(folder, json.loads((folder / "result.json").read_text()), geo, material)
    if (folder / "optimum.json").exists():
        return _from_optimum(folder, json.loads((folder / "optimum.json").read_text()), scene, geo, material)
    return None


def _lengths(row: dict) -> dict:
    """A front record row's design variables in mm: {"gap": 3.0, ...} from "gap (mm)" keys."""
    return {k.split(" (")[0]: v for k, v in row.items() if k.endswith("(mm)")}


def _geometry(array: dict) -> dict:
    """The array's fixed geometry in SI from a scene.json's array table."""
    def si(key, default):
        return magnitude(array.get(key, default))
    return {"taxel_width": si("taxel_width", "4 mm"), "piezo_thickness": si("piezo_thickness", "0.127 mm"),
            "margin": si("margin", "3 mm"), "cols": int(array.get("cols", 3)), "rows": int(array.get("rows", 3)),
            "silicone_above": si("silicone_above", "1 mm"), "silicone_below": si("silicone_below", "1 mm"),
            "gap": si("gap", "3 mm")}


def _design(role, x: dict, g: dict, material, s, c, extra: dict | None = None) -> AnswerDesign:
    """A design of the answer from its variables `x` (mm) and the array's fixed geometry `g` (_geometry)."""
    width = 1e3 * g["taxel_width"]
    above = x.get("silicone_above", 1e3 * g["silicone_above"])
    below = x.get("silicone_below", 1e3 * g["silicone_below"])
    gap = x.get("gap", 1e3 * g["gap"])
    values = {"sensitivity": s, "crosstalk": c, "gap": 1e-3 * gap, "pitch": 1e-3 * (width + gap),
              "total_thickness": 1e-3 * (above + below) + g["piezo_thickness"], "rows": g["rows"], "cols": g["cols"],
              "footprint": g["cols"] * 1e-3 * width + (g["cols"] - 1) * 1e-3 * gap + 2 * g["margin"],
              **{k: v for k, v in (extra or {}).items() if v is not None}}
    return AnswerDesign(role, above, below, gap, width + gap, material, s, c,
                        min_detectable_force_N=values.get("min_detectable_force"), values=values)


def _recommend(table: dict, thesis: AnswerDesign, candidates: list[AnswerDesign], folder: Path | None = None):
    """The candidate meeting every requirement of `table` (an optimization's
    [requirements]) with the largest margin (optimize.requirements.choose; the thesis
    design is a candidate too: None when it is the one); the requirements (implied
    ones added), the binding requirement when none meets them all, and the rule. The
    coverage and localization error the run computed for a design (`folder`'s
    optimize.coverage.RECORD) join its values."""
    from taxel.optimize.coverage import of as influence_metrics_of
    from taxel.optimize.requirements import choose, implied, read
    for d in (*candidates, thesis):
        if folder is not None:
            d.values.update(influence_metrics_of(folder, {"silicone_above": d.silicone_above_mm, "gap": d.gap_mm,
                                                          "silicone_below": d.silicone_below_mm}))
    reqs = implied(read(table or {}), thesis.values)

    def same(d):
        return all(abs(a - b) < 1e-6 for a, b in ((d.silicone_above_mm, thesis.silicone_above_mm),
                                                 (d.silicone_below_mm, thesis.silicone_below_mm),
                                                 (d.gap_mm, thesis.gap_mm)))
    designs = [d for d in candidates if not same(d)] + [thesis]
    ch = choose([d.values for d in designs], reqs)
    for d, v in zip(designs, ch.verdicts):
        d.margins = v.margins
    best = designs[ch.recommended] if ch.recommended is not None else None
    return (None if best is thesis else best), reqs, ch.binding, ch.notes, _priced(designs, reqs, ch.recommended)


def _priced(designs: list[AnswerDesign], reqs: list, chosen: int | None) -> list[tuple]:
    """What relaxing each binding requirement buys among the candidates (optimize.answer.prices):
    (Price, the design then chosen as a copy with role "relaxed-<metric>") per binding requirement."""
    from dataclasses import replace
    from taxel.optimize.answer import prices
    return [(p, replace(designs[p.design], role=f"relaxed-{p.requirement.metric}",
                        values=dict(designs[p.design].values)))
            for p in prices([d.values for d in designs], reqs, chosen)]


def _from_front_3d(folder: Path, rec: dict, geo: dict, material: str) -> FrontAnswer:
    from taxel.analyses.accuracy.error_estimate import CHEAP_3D_ERROR
    a = rec["answer"]
    ref = rec["reference"]
    x_ref = _lengths(ref)
    names = list(x_ref)
    c = a.get("confirmed")
    model, _ = verified_model(rec)
    s3, c3 = "sensitivity 3D (V/N)", "crosstalk 3D"
    thesis = _design("thesis", x_ref, geo, material, ref[s3], ref[c3])
    rows = [r for r in rec["front_3d"] if r.get(s3) is not None and _lengths(r) != x_ref]
    cands = [_design("recommended", _lengths(r), geo, material, r[s3], r[c3]) for r in rows]
    best, reqs, binding, rule, priced = _recommend(rec.get("requirements", {}), thesis, cands, folder)
    error = dict(VERIFY_3D_ERROR)
    cb = (c or {}).get("best")
    same = best is None or (cb is not None and [round(getattr(best, f"{n}_mm"), 6) for n in names]
                            == [round(v, 6) for v in cb["x"]])
    if c and same:
        # the finer confirmation mesh solved exactly these designs: its numbers, its error
        thesis.sensitivity_V_per_N, thesis.crosstalk = c["thesis"]["sensitivity_V_per_N"], c["thesis"]["crosstalk"]
        if best is not None:
            best.sensitivity_V_per_N, best.crosstalk = cb["sensitivity_V_per_N"], cb["crosstalk"]
        error = dict(CHEAP_3D_ERROR)
    row = ROW["3D, pressure patch, linear silicone (finer mesh)" if c and same else
              "3D, pressure patch, linear silicone (verification mesh)"]
    notes = rule + [f"The 3D-verified front holds {len(rec['front_3d'])} of the {len(rec['verified'])} designs "
                    "solved in 3D."]
    return FrontAnswer(folder.name, best, thesis, model + ", 3x3 array, 1 N on the middle taxel", error, True, notes,
                       requirements=reqs, binding=binding, priced=priced, row=row)


def _from_probe_front(folder: Path, rec: dict, geo: dict, material: str,
                      linear: FrontAnswer | None) -> FrontAnswer:
    """The probe front (optimize.probe_front, probe-front.json): the thesis design and the
    most sensitive pressed front design that dominates it, under the rig's probe
    on Yeoh silicone; the linear pressure-patch answer (`linear`) in the notes beside it.
    The error band is the record's estimated error, on sensitivity; crosstalk carries
    the same relative band, a lower bound (the correction's crosstalk misses are larger)."""
    ref = rec["reference"]
    thesis = _design("thesis", _lengths(ref), geo, material,
                     ref["sensitivity (V/N)"], ref["crosstalk"])
    rows = [d for d in rec["front"] if d["x"] != ref["x"] and d.get("sensitivity (V/N)") is not None]
    cands = [_design("recommended", _lengths(d), geo, material, d["sensitivity (V/N)"], d["crosstalk"])
             for d in rows]
    best, reqs, binding, rule, priced = _recommend(rec.get("requirements", {}), thesis, cands, folder)
    b = rows[cands.index(best)] if best is not None else None
    err = max([ref["estimated error"]] + ([b["estimated error"]] if b else []))
    press = rec.get("press", {})
    probe = ", ".join(f"{k.replace('_', ' ')} {v}" for k, v in press.items()
                      if v is not None and k in ("shape", "radius", "edge_radius", "force", "silicone", "friction"))
    notes = rule + [f"Under the rig's probe ({probe or 'flat punch, Yeoh silicone'}): {rec['sentence']}"]
    for role, r in (("thesis", ref), ("recommended", b)):
        if r is not None:
            notes.append(f"The {role} design's estimated error is {100 * r['estimated error']:.2g} % "
                         f"({'within' if r['estimated error'] <= 0.02 else 'above'} 2 %; {r.get('how', '')}).")
    if err > 0.02 and not rec.get("spent", {}).get("product error measured"):
        notes.append("The estimate's product error is the one measured once by 3D presses of front designs; "
                     "taxel demo --presses-3d N (or --full) measures it on this run's designs.")
    if linear is not None:
        t = linear.thesis
        r = linear.recommended
        notes.append("Beside it, the linear pressure-patch front (" + linear.model + "): thesis "
                     f"{eng(t.sensitivity_V_per_N, 'V/N', 3)} at {percent(t.crosstalk)}"
                     + (f"; recommended there: silicone {r.silicone_above_mm:.2f} / {r.silicone_below_mm:.2f} mm, "
                        f"gap {r.gap_mm:.2f} mm, {eng(r.sensitivity_V_per_N, 'V/N', 3)} at {percent(r.crosstalk)}"
                        if r else "; the thesis design is on that front")
                     + f" ({SHORT[linear.row]} — ladder row {linear.row}).")
    model = ("3D presses by the rig's probe on Yeoh silicone" if rec["level"] == "3D press" else
             "an estimate, not a 3D press: a 2D press by the rig's probe on Yeoh silicone scaled by the linear "
             "model's 3D/2D ratio (ladder row 6, the candidate selection)")
    a = FrontAnswer(folder.name, best, thesis, model + ", 3x3 array, 1 N on the middle taxel",
                    {"sensitivity": err, "crosstalk": err}, True, notes,
                    "the probe front's estimated error (discretisation + correction + material law, on "
                    "sensitivity), the same relative band drawn on crosstalk", requirements=reqs, binding=binding,
                    priced=priced,
                    row=ROW[SELECTION_MODEL])
    pressed_3d(a, rec)
    return a


AT_READOUT = ("readout_sensitivity", "readout_crosstalk", "min_detectable_force")


def _from_front(folder: Path, rec: dict, geo: dict, material: str) -> FrontAnswer | None:
    """The front of any optimization (result.json of kind "front", the cheap model, not
    verified): the reference design (the thesis design for a built-in one, else the
    user's) and the front design meeting the requirements with the largest margin."""
    from taxel.optimize.spec import BUILTIN
    ref = rec.get("reference") or {}
    if ref.get("sensitivity") is None or ref.get("crosstalk") is None:
        return None
    role = "thesis" if (BUILTIN / f"{rec.get('name')}.toml").exists() else "reference"
    units = rec["variables"]
    ref_x = {n: v for n, v in ref["x"].items() if units.get(n) == "mm"}
    thesis = _design(role, ref_x, geo, material, ref["sensitivity"], ref["crosstalk"],
                     {k: ref.get(k) for k in AT_READOUT})
    cands = []
    for r in rec["front"]:
        m, x = r["run"]["metrics"], r["run"]["x"]
        if not r["run"].get("success", True) or m.get("sensitivity") is None:
            continue
        xs = {n: v for (n, u), v in zip(units.items(), x) if u == "mm"}
        if xs != ref_x:
            cands.append(_design("recommended", xs, geo, material, m["sensitivity"], m["crosstalk"],
                                 {k: m.get(k) for k in AT_READOUT}))
    best, reqs, binding, rule, priced = _recommend(rec.get("requirements", {}), thesis, cands, folder)
    from taxel.reports.findings import scene_model_label
    scene = json.loads((folder / "scene.json").read_text()) if (folder / "scene.json").exists() else {}
    model = f"{scene_model_label(scene)}, the optimization's own load; the front's cheap model, not verified in 3D"
    dropped = sum(1 for r in rec["front"] if not r["run"].get("success", True))
    notes = rule + ([f"{dropped} of the front's {len(rec['front'])} runs found no feasible design."] if dropped else [])
    return FrontAnswer(folder.name, best, thesis, model, {"sensitivity": float("nan"), "crosstalk": float("nan")},
                       False, notes, requirements=reqs, binding=binding, priced=priced)


def _from_optimum(folder: Path, rec: dict, scene: dict, geo: dict, material: str) -> FrontAnswer | None:
    from taxel.optimize.spec import load_optimization
    m = rec.get("metrics") or {}
    if m.get("sensitivity") is None or m.get("crosstalk") is None:
        return None
    try:
        spec = load_optimization(folder.name).spec
        ref_x = {k: 1e3 * magnitude(v) for k, v in spec.reference.items()}
    except Exception:                       # not a built-in problem: no thesis design to compare with
        return None
    names = list(rec["x"])
    start = [m for x, m in _history(folder / "optimum-history.csv", len(names))
             if all(abs(v - ref_x.get(n, float("nan"))) < 1e-6 for n, v in zip(names, x))]
    if not start or start[0].get("sensitivity") is None:
        return None
    tm = start[0]
    thesis = _design("thesis", ref_x, geo, material, tm["sensitivity"], tm["crosstalk"])
    best, reqs, binding, rule, priced = _recommend(spec.requirements, thesis, folder=folder, candidates=[
        _design("recommended", rec["x"], geo, material, m["sensitivity"], m["crosstalk"])])
    from taxel.reports.findings import scene_model_label
    model = (f"{scene_model_label(scene)}, {geo['rows']}x{geo['cols']} array, the scene's load; a short local search, not verified "
             "in 3D")
    # the 2D model's error against 3D is measured on the full run (front-3d.json): unknown here
    return FrontAnswer(folder.name, best, thesis, model, {"sensitivity": float("nan"), "crosstalk": float("nan")},
                       False, rule + ["The candidate: the short local search's best design (taxel demo --small)."],
                       requirements=reqs, binding=binding, priced=priced)


def _history(path: Path, n: int) -> list[tuple[list[float], dict]]:
    """(design variables, metrics) of each evaluation in an optimum-history.csv: the n
    variables follow the evaluation and phase columns, the metrics after them (a
    metric may share a variable's name: "gap" in mm, then in m)."""
    import csv
    if not path.exists():
        return []
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    head, out = rows[0], []
    for r in rows[1:]:
        x = [float(v) for v in r[2:2 + n]]
        metrics = {k: float(v) for k, v in zip(head[2 + n:], r[2 + n:]) if v != ""}
        out.append((x, metrics))
    return out


def _stack(a: FrontAnswer) -> str | None:
    from taxel.reports.stack import figure
    return figure(a, MATERIALS.get(a.thesis.material, a.thesis.material).split(" (")[0])


def _stack_caption(a: FrontAnswer) -> str:
    what = ("the recommended design above the reference design" if a.recommended is not None else
            f"{a.reference_name}, which the recommendation keeps")
    return f"a section through two neighbouring taxels, {what}, drawn to scale with every dimension written."


def block(answers: list[FrontAnswer], noise: NoiseFloor | None = None, sweep: Sweep | None = None) -> dict | None:
    """The index's answer block (template data): one table row per design, the model,
    the trade and the crosstalk definition. `noise`: a noise budget's minimum
    detectable force, shown for the design it is of (a single taxel of that design)."""
    if not answers:
        return None
    rows, lines, records, links, titles = [], [], [], [], []
    for a in answers:
        ladders = a.ladders()
        titles.append(_title(a, ladders))
        if noise and noise.of(a.thesis) and a.thesis.values.get("min_detectable_force") is None:
            a.thesis.min_detectable_force_N = noise.force_N
        for d in (a.recommended, a.thesis):
            if d is None:
                continue
            row = d.row(a.error)
            if not a.verified:
                row["open-circuit sensitivity"] = eng(d.sensitivity_V_per_N, "V/N", 3) + " (error not estimated)"
                row["open-circuit crosstalk"] = percent(d.crosstalk)
            rows.append(row)
            links.append(_links(a, d, ladders))
            records += d.records(a.error, a.model, a.bands)
        lines.append({"folder": a.folder, "model": a.model, "trade": a.trade, "notes": a.notes,
                      "requirements": requirement_rows(a), "requirement_cols": requirement_cols(a),
                      "requirement_ids": requirement_ids(a), "ladders": ladders, "limits": limits(a),
                      "risks": risks(a), "friction": friction_band.block(a.path), "warm": warm_touch.answer_row(a.path), "assumptions": of_answer(a),
                      "bands": "; ".join(f"{q.replace('_', ' ')}: {b.text()}" + (" (above 2 %)" if b.flagged else "")
                                         for q, b in a.bands.items() if q in ("sensitivity", "crosstalk")), "stack": _stack(a), "stack_caption": _stack_caption(a), "material": MATERIALS.get(a.thesis.material,
                                                                                     a.thesis.material)})
    parts = [("Recommended: ", None)]
    for i, t in enumerate(titles):
        parts += ([("; ", None)] if i else []) + t
    cols = list(dict.fromkeys(c for row in rows for c in row))
    return {"title": "".join(t for t, _ in parts), "title_parts": parts, "cols": cols,
            "rows": [[row.get(c, "—") for c in cols] for row in rows],
            "links": [[link.get(c) for c in cols] for link in links],
            "roles": [row["design"] for row in rows], "lines": lines, "definition": crosstalk_definition(answers),
            "records": records, "ladder_cols": LADDER_COLS, "preference": preference(answers),
            "chain": next((a.chain for a in answers if a.chain), None), "dynamics": dynamics(answers, sweep),
            "verified": any(a.verified for a in answers),
            "error_source": "; ".join(dict.fromkeys(a.error_source for a in answers if a.verified)),
            "noise_model": noise.model if noise else None}
