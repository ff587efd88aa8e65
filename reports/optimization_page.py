"""The page of an optimization folder: its search bounds, its requirements against its
designs (optimize.answer), the 2D front or the optimum, the 3D-verified front, the front
under the rig's probe, and the figures (reports.build's PAGE_KINDS)."""

from __future__ import annotations

from pathlib import Path

from taxel.reports import findings, tables
from taxel.reports.page import csv_link as _csv_link, figures as _figures, read_json


def _dominated(points: list[tuple[float, float]]) -> list[bool]:
    """For each (sensitivity, crosstalk): is another point at least as good in both, better in one?"""
    return [any(s2 >= s and c2 <= c and (s2 > s or c2 < c) for s2, c2 in points) for s, c in points]


def _bounds(name: str) -> str | None:
    """The search bounds of a built-in optimization, one sentence; None for another one."""
    from taxel.optimize.spec import load_optimization
    try:
        prob = load_optimization(name)
    except Exception:                 # not a built-in problem: its bounds are in its own spec file
        return None
    v = prob.spec.variables
    return "Search bounds: " + ", ".join(f"{n.replace('_', ' ')} {x.min} to {x.max}" for n, x in v.items()) + "."


def _requirements(folder: Path) -> list[dict]:
    """The run's requirements against its designs (optimize.answer): the table, and what
    relaxing each binding one buys; none without a [requirements] table."""
    from taxel.optimize.answer import Answer
    from taxel.optimize.result import OptimizationResult
    if not (folder / "result.json").exists():
        return []
    result = OptimizationResult.from_folder(folder)
    rows = Answer.of(result).rows()
    if not rows:
        return []
    lines = result.verdict()              # the answer's lines and each binding requirement's price (optimize.relax)
    return [{"type": "table", "table": tables.table(rows, title="requirements")},
            {"type": "note", "text": " ".join(lines[:1] + [ln.strip() for ln in lines if "bind" in ln])}]


def _front_rows(rows: list[dict], ref: dict | None, s_key: str, c_key: str, label: str = "thesis design"):
    """Front rows with a design column, the reference (thesis) design added, and
    each row's mark: reference, dominated or ''."""
    out = [{"design": f"front {i + 1}", **r} for i, r in enumerate(sorted(rows, key=lambda r: r[c_key] or 0))]
    if ref is not None:
        out.append({"design": f"{label} (reference)", **ref})
    dom = _dominated([(r.get(s_key) or 0.0, r.get(c_key) if r.get(c_key) is not None else float("inf"))
                      for r in out])
    marks = {id(r): ("reference" if r["design"].startswith(label) else "") + (" dominated" if d else "")
             for r, d in zip(out, dom)}
    return out, lambda r: marks[id(r)].strip()


def optimization_page(folder: Path, out: Path, scene_data) -> dict:
    blocks, numbers, banners = [], [], []
    cheap = findings.scene_model_label(scene_data)
    name = read_json(folder / "result.json").get("name", folder.name) if (folder / "result.json").exists() else folder.name
    from taxel.optimize.answer import reference_label
    label = reference_label(name)
    bounds = _bounds(name)
    if bounds:
        blocks.append({"type": "note", "text": bounds})
    blocks += _requirements(folder)
    if (folder / "check-3d.json").exists():           # taxel optimize --check-3d (optimize.check_3d)
        from taxel.optimize.check_3d import lines
        blocks.append({"type": "note", "text": " ".join(ln.strip() for ln in lines(read_json(folder / "check-3d.json")))})
    if (folder / "scene.json").exists():
        from taxel.reports.answer_assumptions import assumptions
        rows = assumptions(read_json(folder / "scene.json"))
        if rows:
            blocks.append({"type": "table", "table": tables.table(rows, title="assumptions (values no input file gave)")})
    if (folder / "front.json").exists():
        rec = read_json(folder / "front.json")
        numbers += findings.front_numbers(rec, cheap, label)
        ref = rec.get("reference")
        ref_row = ({**{f"{k} (mm)": v for k, v in ref["x"].items()}, "sensitivity_V_per_N": ref["sensitivity"],
                    "crosstalk": ref["crosstalk"]} if ref else None)
        rows, mark = _front_rows(rec["front"], ref_row, "sensitivity_V_per_N", "crosstalk", label)
        cols = ["design"] + [c for c in rows[0] if c.endswith("(mm)")] + ["sensitivity_V_per_N", "crosstalk"]
        blocks += [{"type": "text", "text": f"The 2D front ({cheap}): the most sensitive design at each crosstalk "
                                            "bound (epsilon-constraint)."},
                   {"type": "table", "table": tables.table(rows, cols, mark=mark, title="2D front")}]
    if (folder / "optimum.json").exists():
        rec = read_json(folder / "optimum.json")
        numbers += findings.optimum_numbers(rec, cheap)
        blocks.append({"type": "table", "table": tables.table(
            [{**{f"{k} (mm)": v for k, v in rec["x"].items()}, "objective": rec["objective"],
              "evaluations": rec["evaluations"], "success": rec["success"], "message": rec["message"]}],
            csv=_csv_link(folder / "optimum-history.csv", out, folder), title="optimum")})
    imgs = sorted(folder.glob("*.png"))
    key = [p for p in imgs if p.name == "pareto-3d.png"] or [p for p in imgs if p.name == "pareto.png"] or imgs
    if (folder / "front-3d.json").exists():          # the 3D-verified front (MultiFidelity.to_folder)
        rec = read_json(folder / "front-3d.json")
        numbers += findings.front_3d_numbers(rec)
        banners += findings.front_3d_banners(rec)
        rows, mark = _front_rows(rec["front_3d"], rec["reference"], "sensitivity 3D (V/N)", "crosstalk 3D")
        from taxel.reports.ladder import FRONT_3D_COLUMNS, named
        rows = [named(r, FRONT_3D_COLUMNS) for r in rows]          # each model's numbers name their ladder row
        model, _ = findings.verified_model(rec)
        from types import SimpleNamespace
        from taxel.optimize.multifidelity import sentence
        names = [k.split(" (")[0] for k in rec["reference"] if k.endswith("(mm)")]
        blocks += [{"type": "text", "text": sentence(SimpleNamespace(names=names, units=["mm"] * len(names)),
                                                     rec["answer"])},      # the record's, in today's words
                   {"type": "table", "table": tables.table(rows, mark=mark, title="3D-verified front")},
                   {"type": "note", "text": f"3D values: {findings.verified_model({**rec, 'answer': {}})[0]} for the "
                                            f"front; the answer's two designs confirmed on {model}."},
                   {"type": "table", "table": tables.table(
                       [{"round": r["round"], "designs verified in 3D": r["verified"],
                         "largest miss of the corrected prediction (ratio)":
                             r["largest disagreement of the corrected prediction"],
                         "largest cheap/expensive disagreement (ratio)": r.get("largest cheap/expensive disagreement")}
                        for r in rec["rounds"]], title="verification rounds")},
                   {"type": "table", "table": tables.table(
                       [{"item": k.replace("seconds", "time (s)"), "value": f"{v:.3g}" if "seconds" in k else v}
                        for k, v in {**rec["plan"], **rec["spent"]}.items()], title="plan and cost")}]
    if (folder / "probe-front.json").exists():       # the headline under the rig's probe (optimize.probe_front)
        from taxel.reports.multifidelity import probe_blocks
        blocks = probe_blocks(read_json(folder / "probe-front.json")) + blocks
    from taxel.reports.warm_touch import section
    warm = section(folder)          # the main job's warm touch of the thesis design (taxel.jobs.warm_touch)
    return {"sections": [{"title": "Optimization", "blocks": blocks + [_figures(imgs)]}] + ([warm] if warm else []),
            "numbers": numbers, "banners": banners, "thumb": key[0].read_bytes() if key else None}


