"""The answer block on top of the report's index: the design the run recommends and
the thesis design, side by side in engineering units, with the sensitivity,
crosstalk, minimum detectable force and error band of each, the model they come
from, and the trade the recommendation makes.

The answer itself is the owner's (optimize.answer_folder.FolderAnswer: it reads an
optimization folder's headline record, holds its designs, chooses among them with the
requirements and prices them); `headline_front(folder)` draws it into a `FrontAnswer`
(reports.answer_design holds the view's types) with the model, error band and notes of its
numbers. Point it at another folder to change what the index leads with. Nothing is
solved or chosen here.

Crosstalk is the largest neighbouring taxel's open-circuit |V| divided by the
pressed taxel's (taxel.optimize.metrics), defined once in the block's footnote.
"""

from __future__ import annotations

from pathlib import Path

from taxel.reports import friction_band, warm_touch
from taxel.reports.answer_assumptions import of_answer
from taxel.reports.answer_bands import bands
from taxel.reports.answer_design import AnswerDesign, FrontAnswer, NoiseFloor, preference  # noqa: F401
from taxel.reports.answer_3d import pressed_3d
from taxel.reports.findings import verified_model
from taxel.reports.ladder import COLS as LADDER_COLS, ROW, SELECTION_MODEL, SHORT, VERIFY_3D_ERROR
from taxel.reports.first_screen import MATERIALS, Sweep, dynamics, links as _links, title as _title
from taxel.reports.margins import limits, requirement_cols, requirement_ids, requirement_rows, risks
from taxel.reports.tables import eng, percent
from taxel.optimize.answer import Design
from taxel.optimize.answer_folder import READOUT_FILE, FolderAnswer  # noqa: F401

def crosstalk_definition(answers: list[FrontAnswer]) -> str:
    """Crosstalk, defined once for the block, on the answers' own array."""
    sizes = sorted({(a.thesis.values.get("rows"), a.thesis.values.get("cols")) for a in answers} - {(None, None)})
    where = " or ".join(f"{r}x{c}" for r, c in sizes) or "the"
    return ("Crosstalk: the largest neighbouring taxel's open-circuit |V| divided by the pressed taxel's, for a "
            f"press on one taxel of the {where} array (the scene's loaded taxel).")




def headline_front(folder: Path) -> FrontAnswer | None:
    """The answer an optimization folder holds, as the page draws it: the owner's
    (optimize.answer_folder.FolderAnswer: its headline record, designs, choice and prices)
    with the model, error band and notes of its numbers; None when it holds none."""
    o = FolderAnswer.read(Path(folder))
    if o is None:
        return None
    a = {"probe-front": _from_probe_front, "front-3d": _from_front_3d, "front": _from_front,
         "optimum": _from_optimum}[o.kind](o)
    a.path = Path(folder)
    _through_readout(a, o)
    bands(a, Path(folder))
    return a


def _view(o: FolderAnswer, d: Design | None, numbers: dict | None = None) -> AnswerDesign | None:
    """The owner's design `d` as the page draws it (`numbers`: label -> (sensitivity, crosstalk)
    of another model the page shows for it)."""
    if d is None:
        return None
    s, c = (numbers or {}).get(d.label, (d.metrics["sensitivity"], d.metrics["crosstalk"]))
    return AnswerDesign(d.label, d, o.array(d), (o.scene.get("array") or {}).get("piezo", "?"), s, c,
                        min_detectable_force_N=d.metrics.get("min_detectable_force"))


def _views(o: FolderAnswer, numbers: dict | None = None) -> dict:
    """FrontAnswer's design fields of the owner's answer."""
    return {"recommended": _view(o, o.recommended, numbers), "thesis": _view(o, o.reference, numbers),
            "requirements": o.requirements, "binding": o.binding,
            "priced": [(p, _view(o, d)) for p, d in o.priced], "reversed": set(o.reversed)}


def _through_readout(a: FrontAnswer, o: FolderAnswer) -> None:
    """The designs' numbers through the bench's chain (the owner's READOUT_FILE rows), when the run wrote them."""
    for label, r in o.readout.items():
        d = a.recommended if label == "recommended" else a.thesis
        d.min_detectable_force_N = r["min_detectable_force_N"]
        if r.get("bandwidth_Hz"):
            d.bandwidth_Hz = tuple(r["bandwidth_Hz"])
        a.chain = (f"through the thesis bench's charge amplifier and notch with the rig's mains hum "
                   f"({100 * r['hum_share']:.3g} % of the noise), noise band {r['band_Hz'][0]:g}-{r['band_Hz'][1]:g} Hz"
                   + (f", the amplifier's bandwidth {eng(r['bandwidth_Hz'][0], 'Hz', 3)} to "
                      f"{eng(r['bandwidth_Hz'][1], 'Hz', 3)}" if r.get("bandwidth_Hz") else "")
                   + ": from the answer's own sensitivity and the design's capacitance (its 3D model's, the free "
                     "parallel plate)")


def _from_front_3d(o: FolderAnswer) -> FrontAnswer:
    from taxel.analyses.accuracy.error_estimate import CHEAP_3D_ERROR
    rec = o.record
    model, _ = verified_model(rec)
    confirmed = o.confirmed()
    # the finer confirmation mesh solved exactly these designs: its numbers, its error
    error = dict(CHEAP_3D_ERROR) if confirmed else dict(VERIFY_3D_ERROR)
    row = ROW["3D, pressure patch, linear silicone (finer mesh)" if confirmed else
              "3D, pressure patch, linear silicone (verification mesh)"]
    notes = o.notes + [f"The 3D-verified front holds {len(rec['front_3d'])} of the {len(rec['verified'])} designs "
                       "solved in 3D."]
    return FrontAnswer(o.folder.name, model=model + ", 3x3 array, 1 N on the middle taxel", error=error, verified=True,
                       notes=notes, row=row, **_views(o, confirmed))


def _from_probe_front(o: FolderAnswer) -> FrontAnswer:
    """The probe front (optimize.probe_front, probe-front.json): the thesis design and the
    most sensitive pressed front design that dominates it, under the rig's probe
    on Yeoh silicone; the linear pressure-patch answer (the owner's `linear`) in the notes beside it.
    The error band is the record's estimated error, on sensitivity; crosstalk carries
    the same relative band, a lower bound (the correction's crosstalk misses are larger)."""
    rec = o.record
    ref = rec["reference"]
    b = o.recommended.record if o.recommended is not None else None
    err = max([ref["estimated error"]] + ([b["estimated error"]] if b else []))
    press = rec.get("press", {})
    probe = ", ".join(f"{k.replace('_', ' ')} {v}" for k, v in press.items()
                      if v is not None and k in ("shape", "radius", "edge_radius", "force", "silicone", "friction"))
    notes = o.notes + [f"Under the rig's probe ({probe or 'flat punch, Yeoh silicone'}): {rec['sentence']}"]
    for role, r in (("thesis", ref), ("recommended", b)):
        if r is not None:
            notes.append(f"The {role} design's estimated error is {100 * r['estimated error']:.2g} % "
                         f"({'within' if r['estimated error'] <= 0.02 else 'above'} 2 %; {r.get('how', '')}).")
    if err > 0.02 and not rec.get("spent", {}).get("product error measured"):
        notes.append("The estimate's product error is the one measured once by 3D presses of front designs; "
                     "taxel demo --presses-3d N (or --full) measures it on this run's designs.")
    if o.linear is not None:
        linear = _from_front_3d(o.linear)
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
    a = FrontAnswer(o.folder.name, model=model + ", 3x3 array, 1 N on the middle taxel",
                    error={"sensitivity": err, "crosstalk": err}, verified=True, notes=notes,
                    error_source="the probe front's estimated error (discretisation + correction + material law, on "
                    "sensitivity), the same relative band drawn on crosstalk", row=ROW[SELECTION_MODEL],
                    **_views(o))
    pressed_3d(a, o)
    return a


def _from_front(o: FolderAnswer) -> FrontAnswer:
    """The front of any optimization (result.json of kind "front", the cheap model, not
    verified): the reference design (the thesis design for a built-in one, else the
    user's) and the front design meeting the requirements that is best by the objective."""
    from taxel.reports.findings import scene_model_label
    model = f"{scene_model_label(o.scene)}, the optimization's own load; the front's cheap model, not verified in 3D"
    front = o.record["front"]
    dropped = sum(1 for r in front if not r["run"].get("success", True))
    notes = o.notes + ([f"{dropped} of the front's {len(front)} runs found no feasible design."] if dropped else [])
    return FrontAnswer(o.folder.name, model=model, error={"sensitivity": float("nan"), "crosstalk": float("nan")},
                       verified=False, notes=notes, **_views(o))


def _from_optimum(o: FolderAnswer) -> FrontAnswer:
    from taxel.reports.findings import scene_model_label
    arr = o.array(o.reference)
    model = (f"{scene_model_label(o.scene)}, {arr.rows}x{arr.cols} array, the scene's load; a short local search, not "
             "verified in 3D")
    # the 2D model's error against 3D is measured on the full run (front-3d.json): unknown here
    return FrontAnswer(o.folder.name, model=model, error={"sensitivity": float("nan"), "crosstalk": float("nan")},
                       verified=False,
                       notes=o.notes + ["The candidate: the short local search's best design (taxel demo --small)."],
                       **_views(o))


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
