"""Batch reports: one self-contained HTML page per result folder, and an index.

    taxel report DIR... --out OUT [--pdf]

A folder is recognised by what it holds: a study (results.sqlite + study.json),
an optimization (optimum.json or front.json), an analysis or solve
(scene.json with *-frequency.csv, *-transient.csv or result.json). Each page
shows, as far as the folder allows: the scene drawn to scale with its
materials; the folder's curves (parameter studies, Bode and time plots,
convergence, Pareto front); renders of the solved fields; a model comparison
(lumped, 2D, axisymmetric, 3D; linear and Yeoh) with each model's cost and
deviation; the solver's own figures; and the provenance (scene, code version,
date, material sources), under a banner when a result is outside its model's
range (`findings`). Images are embedded (data URIs): a page opens with no
network and no other file (its full-precision CSVs sit beside it, linked). The
markup is XHTML (well-formed XML), from the jinja2 templates in
`reports/templates/` (page.html, index.html); the index is a summary of the run
with one card per page. `PAGE_KINDS` maps a folder kind to what its page shows.
"""

from __future__ import annotations

import csv
import shutil
import time
from pathlib import Path

from taxel.analyses import output_folder
from taxel.reports import findings, tables
from taxel.reports.page import (Headline, Page, ReportError, csv_link as _csv_link, figures as _figures,  # noqa: F401
                                 provenance, read_json, templates)
from taxel.reports.optimization_page import optimization_page as _optimization
from taxel.reports.scene_sections import data_uri, scene_sections, stored_result
from taxel.reports import noise as noise_page
from taxel.reports.validation import build_page as validation_page
from taxel.reports.ladder import ANSWER_MODEL, ROW
from taxel.studies.store import code_version


def kind_of(folder: Path) -> str:
    if (folder / "results.sqlite").exists() and (folder / "study.json").exists():
        return "study"
    if any((folder / n).exists() for n in ("optimum.json", "front.json", "front-3d.json", "probe-front.json")):
        return "optimization"
    if (folder / "work-precision.json").exists() or (folder / "fidelity.json").exists():   # reports/work_precision.py
        return "work-precision"
    if noise_page.is_noise(folder):                     # a noise budget (reports/noise.py)
        return "noise"
    if (folder / "scene.json").exists():
        return "analysis"
    if (folder / "validation.json").exists():           # a measurement validation (reports/validation.py)
        return "validation"
    raise ReportError(f"{folder}: not a study, optimization or solve folder (no study.json, optimum.json, "
                      "front.json or scene.json); run taxel study/optimize/solve with --out first")


_PRESSED = "pressed_voltage"      # the key plot's output


def _study(folder: Path, out: Path, scene_data) -> dict:
    from taxel.analyses import linear_error
    spec = read_json(folder / "study.json")
    rows = list(csv.DictReader(open(folder / "results.csv"))) if (folder / "results.csv").exists() else []
    cols = list(rows[0]) if rows else []
    params = cols[:cols.index("status")] if "status" in cols else []
    shown = params + [c for c in cols if c in ("pressed_voltage", "max_strain", "stopped_at")
                      or c.startswith("short_circuit_charge_")]
    if any(r.get("status") != "done" for r in rows):
        shown += ["status", "error"]
    plots = sorted((folder / "plots").glob("*.png"), key=lambda p: (not p.name.startswith(_PRESSED), p.name))
    key = [p for p in plots if p.name.startswith(_PRESSED) and "silicone" in p.name] or plots
    model = (scene_data or {}).get("model", {}) or {}
    tol = float(model.get("tolerance", 0.02))
    linear = model.get("silicone", "linear") == "linear"

    def mark(r):
        s = findings.finite_number(r.get("max_strain"))
        return "out-of-range" if linear and s is not None and linear_error(s) > tol else ""
    label = findings.scene_model_label(scene_data)
    from taxel.reports import thesis_claims
    claims = thesis_claims.checks(rows)
    thesis = [{"title": "Beside the thesis's Fig. 2.5 and 2.6", "blocks": [
        {"type": "text", "text": f"The thesis's set-up: {thesis_claims.SETUP} Its statements: "
                                 + "; ".join(f"\u201c{c}\u201d" for _, c in thesis_claims.CLAIMS)
                                 + f"; and {thesis_claims.CHOICE}. Source: {thesis_claims.SOURCE}."},
        {"type": "table", "table": tables.table(claims, title="the thesis's statements checked")},
        {"type": "note", "text": "Each row: one curve of this study. With a linear silicone |V| is proportional "
                                 "to the force, so every force gives the same shape; the thesis's Yeoh silicone "
                                 "bends them apart at large strain (see the banner)."}]}] if claims else []
    from taxel.reports import thesis_model
    if rows and thesis_model.is_thesis_model(rows):
        png = thesis_model.draw(rows, out, folder.name)
        thesis.append({"title": "The thesis's model beside linear silicone", "blocks": [
            {"type": "text", "text": thesis_model.sentence(rows)},
            _figures([png], [f"{folder.name}: linear silicone (dashed) and the thesis's Yeoh at each force (solid); "
                             "crosses: Yeoh points stopped short, at their last converged force"]),
            {"type": "table", "table": tables.table(thesis_model.comparison(rows),
                                                    title="Yeoh against linear silicone, per piezo and force")}]})
    return {"sections": [
        {"title": "Parameter study", "blocks": [{"type": "text", "text": spec.get("description", "")},
                                                {"type": "note", "text": f"Model: {label}."},
                                                _figures(plots)]},
        {"title": "Results", "blocks": [{"type": "table", "table": tables.table(
            rows, shown, sort_by=params, csv=_csv_link(folder / "results.csv", out, folder), mark=mark,
            order={p.get("label"): p.get("labels") for p in spec.get("parameters", []) if p.get("labels")})}]}]
        + thesis,
        "numbers": findings.study_numbers(rows, label),
        "banners": findings.study_banners(rows, scene_data or {}), "scene_banners": False,
        "thumb": key[0].read_bytes() if key else None}


def _redrawn(folder: Path, result, scratch: Path) -> list[Path]:
    """The folder's figures, with its Bode or time plot drawn again from the stored
    result (the current figure style, whatever release wrote the folder)."""
    from taxel.analyses import FrequencyResult, TransientResult
    from taxel.analyses.results.dynamic_figures import bode_png, transient_png
    imgs = sorted(folder.glob("*.png"))
    if isinstance(result, (FrequencyResult, TransientResult)):
        suffix = "-bode.png" if isinstance(result, FrequencyResult) else "-transient.png"
        draw = bode_png if isinstance(result, FrequencyResult) else transient_png
        imgs = [p for p in imgs if not p.name.endswith(suffix)]
        imgs.insert(0, draw(result, scratch / f"{result.scene.name}{suffix}"))
    return imgs


VIEW_ROW = ROW[ANSWER_MODEL]          # a design view's numbers: the answer's 3D press (reports.ladder)


def _design_view(folder: Path) -> str | None:
    """"thesis" or "recommended" for a 3D view of an answer design (the main job's
    <front>-thesis-3d, <front>-recommended-3d: taxel.jobs.answer_3d, the 3D press by the
    rig's probe whose numbers are the answer's, ladder row 7), else None."""
    return next((r for r in ("thesis", "recommended") if folder.name.endswith(f"-{r}-3d")), None)


def _analysis(folder: Path, out: Path, scene_data) -> dict:
    import tempfile
    result = stored_result(folder)
    scratch = Path(tempfile.mkdtemp(prefix="taxel-report-"))
    imgs = _redrawn(folder, result, scratch)
    summary = "\n".join(result.summary()) if result is not None else ""
    links = [c for c in (_csv_link(p, out, folder) for p in sorted(folder.glob("*.csv"))) if c]
    blocks = [{"type": "pre", "text": summary}] if summary else []
    if result is not None and getattr(result, "scene", None) is not None:
        blocks.append({"type": "note", "text": f"Model: {findings.model_label(result.scene)}."})
    blocks += [_figures(imgs)] + [{"type": "csv", "href": c} for c in links]
    thumb = imgs[0].read_bytes() if imgs else None
    shutil.rmtree(scratch, ignore_errors=True)
    role = _design_view(folder)
    if role:
        blocks.insert(0, {"type": "note", "text": f"The answer's {role} design pressed in 3D by the rig's probe on "
                                                  "Yeoh silicone: the same solve as the answer's numbers — ladder row "
                                                  f"{VIEW_ROW} of its ladder in the index."})
    return {"sections": [{"title": "Analysis", "blocks": blocks}], "numbers": findings.analysis_numbers(result),
            "banners": findings.frequency_banners(result),
            "scene_banners": ((scene_data or {}).get("analysis") or {}).get("type", "static") == "static",
            "thumb": thumb}


def _work_precision(folder: Path, out: Path, scene_data) -> dict:
    from taxel.reports.work_precision import chart_files, cheapest_rows
    rec = read_json(chart_files(folder)[0])
    imgs = sorted(folder.glob("*.png"))
    rows = cheapest_rows(rec)
    notes = [{"type": "note", "text": f"{w['scene']} at {w['force_N']:g} N: {w['how']}"} for w in rec["work_precision"]]
    pzt = [r for r in rows if r["output"].startswith("pressed-taxel voltage")][:1]
    numbers = [Headline(f"cheapest for 1 % ({r['scene']}, {r['force (N)']:g} N)", r["cheapest within 1 %"],
                        "every model against the finest 3D") for r in pzt]
    return {"sections": [
        {"title": "Work against precision", "blocks": [
            {"type": "text", "text": "Wall time against error (log-log), one point per model, element order, mesh "
                                     "and silicone law; the Pareto set (cheapest for its accuracy) is ringed."},
            _figures(imgs)] + notes},
        {"title": "Cheapest model for 1 %, 5 % and 10 % error", "blocks": [
            {"type": "table", "table": tables.table(rows, csv=_csv_link(chart_files(folder)[1], out, folder))}]}],
        "numbers": numbers, "banners": [], "thumb": imgs[0].read_bytes() if imgs else None}


# the page of each folder kind: (folder, out, scene data) -> sections, numbers, banners, thumb
PAGE_KINDS = {"study": _study, "optimization": _optimization, "analysis": _analysis, "work-precision": _work_precision,
              "noise": noise_page.page}


def build_page(folder: Path, out: Path, compare=True, answers: list | None = None) -> Page:
    """Write OUT/<folder name>.html (and the folder's CSVs beside it); `answers`
    (reports.answer_numbers.AnswerNumbers): the run's answer designs, whose numbers a page of
    one of them names beside its own model's (reports.answer_numbers.of_answers)."""
    folder = Path(folder)
    if not folder.is_dir():
        raise ReportError(f"{folder}: no such folder")
    kind = kind_of(folder)
    if kind == "validation":
        return validation_page(folder, out)
    scene_data = read_json(folder / "scene.json") if (folder / "scene.json").exists() else None
    title = f"{folder.name} ({kind})"
    out.mkdir(parents=True, exist_ok=True)
    part = PAGE_KINDS[kind](folder, out, scene_data)
    sections, numbers, banners, thumb = part["sections"], part["numbers"], part["banners"], part["thumb"]
    if scene_data:
        sec, nums, ban, compare_ban, key_png = scene_sections(folder, scene_data, compare)
        sections, numbers = sections + sec, numbers + nums
        banners += (ban if part.get("scene_banners", True) else []) + compare_ban
        thumb = thumb or key_png
    if kind == "analysis" and _design_view(folder):          # its card's numbers name their ladder row
        numbers = [n._replace(model=f"{n.model} — ladder row {VIEW_ROW}") for n in numbers]
    elif answers and kind in ("analysis", "noise"):          # an answer design on another model: which, and why
        from taxel.reports.answer_numbers import annotate
        numbers, note = annotate(numbers, scene_data, answers)
        if note is not None:
            sections.insert(0, {"title": "The answer's numbers", "blocks": [note]})
    sections.append({"title": "Provenance", "blocks": provenance(folder, scene_data)})
    tables.write_csvs(sections, out, folder.name)
    path = out / f"{folder.name}.html"
    path.write_text(templates().get_template("page.html").render(
        title=title, kind=kind, folder=folder.name, banners=banners, headline=numbers, sections=sections),
        encoding="utf-8")
    return Page(path, kind, title, numbers, banners, thumb)


def build(folders, out: Path, pdf=False, compare=True, run: dict | None = None) -> Path:
    """One page per result folder and an index, written whole into `out` (a
    failure on any folder leaves no partial report; an existing report is
    replaced only when the new one is complete). `run` adds to the index's run
    summary: "what" was run, "started" (a date), "seconds" it took."""
    t0 = time.perf_counter()
    folders = [Path(f) for f in folders]
    if not folders:
        raise ReportError("no result folders given; name at least one study, optimization or solve folder")
    for f in folders:                             # refuse bad input before writing anything
        if not f.is_dir():
            raise ReportError(f"{f}: no such folder")
        kind_of(f)
        for name in ("scene.json", "study.json", "front.json", "optimum.json"):
            if (f / name).exists():
                read_json(f / name)
    out = Path(out)
    run = run or {}
    with output_folder(out, replace=True) as tmp:
        from taxel.reports.answer import headline_front
        from taxel.reports.answer_numbers import of_answers
        answers = of_answers([a for a in (headline_front(f) for f in folders if kind_of(f) == "optimization") if a])
        pages = [build_page(f, tmp, compare, answers) for f in folders]
        grouped: dict = {}                       # one banner per warning, naming every page it is on
        for p in pages:
            for b in p.banners:
                grouped.setdefault(b, []).append(p.title)
        answer = answer_block(folders, tmp)
        touch = set(answer["folders"]) if answer else set()       # the answer's folders and its design views
        warnings = [{"page": ", ".join(titles), "banner": b, "line": _one_line(b.text),
                     "touches": any(t in touch or t.removesuffix("-thesis-3d").removesuffix("-recommended-3d")
                                    + "-front" in touch for t in titles)} for b, titles in grouped.items()]
        warnings.sort(key=lambda w: not w["touches"])
        cards = [{"href": p.path.name, "title": p.title, "numbers": p.numbers, "warnings": len(p.banners),
                  "thumb": data_uri(p.thumb) if p.thumb else None} for p in pages]
        kinds = {k: sum(w["banner"].kind == k for w in warnings) for k in ("range", "disagreement", "verification")}
        summary = [("what", run.get("what") or ", ".join(p.title for p in pages)),
                   ("when", run.get("started") or time.strftime("%Y-%m-%d %H:%M:%S")),
                   ("code version", code_version()),
                   ("duration", (f"{run['seconds']:.0f} s to compute, " if "seconds" in run else "")
                    + f"{time.perf_counter() - t0:.0f} s to build this report"),
                   ("warnings", f"{kinds['range']} result(s) outside their model's range, {kinds['disagreement']} "
                                f"model disagreement(s), {kinds['verification']} failed verification(s)"
                    if warnings else "none")]
        (tmp / "index.html").write_text(templates().get_template("index.html").render(
            title="taxel report", run=summary, warnings=warnings, cards=cards,
            answer=answer), encoding="utf-8")
        if pdf:
            for p in pages:
                to_pdf(p.path)
    return out / "index.html"


def _one_line(text: str) -> str:
    """A warning's first sentence (the index lists each warning in one line; the page has it whole)."""
    import re
    first = re.split(r"(?<=[a-z0-9%)])\. (?=[A-Z])", text, maxsplit=1)[0]
    return first if first.endswith(".") else first + "."


def answer_block(folders, out: Path) -> dict | None:
    """The index's answer block (reports.answer) from the run's optimization folders,
    with the thesis design's minimum detectable force from a noise budget folder of
    the same design; its table also as OUT/answer.csv."""
    from taxel.reports import answer
    answers = [a for a in (answer.headline_front(f) for f in folders if kind_of(f) == "optimization") if a]
    noise = next((f for f in folders if kind_of(f) == "noise"), None)
    force = None
    if noise is not None:
        from taxel.analyses import read
        res = read(noise)
        arr = res.scene.array
        force = answer.NoiseFloor(res.outputs()["min_detectable_force"],
                                  f"{noise.name} page: {findings.model_label(res.scene)}, through the charge "
                                  "amplifier and notch on the thesis bench's ADC; not computed for the other designs",
                                  arr.piezo, 1e3 * arr.silicone_above, 1e3 * arr.silicone_below)
    blk = answer.block(answers, force, _sweep(folders))
    if blk is not None:
        blk["folders"] = [a.folder for a in answers]
        with open(out / "answer.csv", "w", newline="", encoding="utf-8") as fh:   # numeric: value, error, unit
            w = csv.DictWriter(fh, fieldnames=list(blk["records"][0]))
            w.writeheader()
            w.writerows(blk["records"])
        blk["csv"] = "answer.csv"
        blk["views"] = [{"href": f"{f.name}.html", "role": f"{f.name.rsplit('-', 3)[-3].upper()} "
                         f"{f.name.rsplit('-', 2)[-2]}"} for f in folders
                        if f.name.endswith(("-thesis-3d", "-recommended-3d"))]
        blk["view_row"] = VIEW_ROW
    return blk


def _sweep(folders):
    """The run's frequency sweep (the main job's thesis PZT taxel through the charge
    amplifier and notch) as the answer's first resonance (reports.answer.Sweep); None
    when the run has none."""
    from taxel.analyses import read
    from taxel.reports import answer
    for f in folders:
        if kind_of(f) == "analysis" and (f / "result.json").exists() and \
                read_json(f / "result.json").get("kind") == "frequency":
            res = read(f)
            return answer.Sweep(res.first_resonance(), (float(res.freqs[0]), float(res.freqs[-1])), f.name,
                                findings.model_label(res.scene))
    return None


def chromium():
    import shutil
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                  "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def to_pdf(page: Path) -> Path:
    import subprocess
    import tempfile
    exe = chromium()
    if exe is None:
        raise ReportError("--pdf needs Chromium (apt-get install chromium); the HTML pages are written")
    pdf = page.with_suffix(".pdf")
    with tempfile.TemporaryDirectory() as profile:
        subprocess.run([exe, *CHROMIUM_FLAGS, f"--user-data-dir={profile}", f"--print-to-pdf={pdf}",
                        page.resolve().as_uri()], check=True, capture_output=True, timeout=120)
    return pdf
