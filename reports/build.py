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
import json
import shutil
import time
from pathlib import Path

from taxel.analyses.results import output_folder
from taxel.scene import SceneError
from taxel.reports import findings, tables
from taxel.reports.page import Page, provenance, templates
from taxel.reports.scene_sections import data_uri, scene_sections, stored_result
from taxel.reports import noise as noise_page
from taxel.reports.validation import build_page as validation_page
from taxel.studies.store import code_version


class ReportError(SceneError):
    """A folder that cannot be reported; one line with the fix."""


def read_json(path: Path):
    """A JSON file of a result folder; a corrupt one is one line naming it."""
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ReportError(f"{path}: not valid JSON ({getattr(exc, 'msg', exc)}); rerun the command that "
                          "wrote it") from None


def kind_of(folder: Path) -> str:
    if (folder / "results.sqlite").exists() and (folder / "study.json").exists():
        return "study"
    if (folder / "optimum.json").exists() or (folder / "front.json").exists():
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


def _figures(paths, wide=False) -> dict:
    """A block of embedded figures; wide ones one per row (small multiples)."""
    paths = list(paths)
    for p in paths:
        if not p.read_bytes():
            raise ReportError(f"{p}: an image to embed is empty; rerun the command that wrote it")
    return {"type": "figures", "wide": wide, "images": [data_uri(p.read_bytes()) for p in paths]}


def _csv_link(src: Path, out: Path, folder: Path) -> str | None:
    """Copy a full-precision CSV beside the page; its relative link."""
    if not src.exists():
        return None
    name = f"{folder.name}-{src.name}"
    shutil.copyfile(src, out / name)
    return name


_PRESSED = ("pressed_voltage", "voltage_pressed")     # the key plot's output (its name before this release)


def _study(folder: Path, out: Path, scene_data) -> dict:
    spec = read_json(folder / "study.json")
    rows = list(csv.DictReader(open(folder / "results.csv"))) if (folder / "results.csv").exists() else []
    cols = list(rows[0]) if rows else []
    params = cols[:cols.index("status")] if "status" in cols else []
    shown = params + [c for c in cols if c in ("pressed_voltage", "voltage_pressed", "max_strain", "stopped_at")
                      or c.startswith("charge_")]
    if any(r.get("status") != "done" for r in rows):
        shown += ["status", "error"]
    plots = sorted((folder / "plots").glob("*.png"), key=lambda p: (not p.name.startswith(_PRESSED), p.name))
    key = [p for p in plots if p.name.startswith(_PRESSED) and "silicone" in p.name] or plots
    return {"sections": [
        {"title": "Parameter study", "blocks": [{"type": "text", "text": spec.get("description", "")},
                                                _figures(plots, wide=True)]},
        {"title": "Results", "blocks": [{"type": "table", "table": tables.table(
            rows, shown, sort_by=params, csv=_csv_link(folder / "results.csv", out, folder),
            order={p.get("label"): p.get("labels") for p in spec.get("parameters", []) if p.get("labels")})}]}],
        "numbers": findings.study_numbers(rows),
        "banners": findings.study_banners(rows, scene_data or {}), "scene_banners": False,
        "thumb": key[0].read_bytes() if key else None}


def _optimization(folder: Path, out: Path, scene_data) -> dict:
    blocks, numbers = [], []
    if (folder / "front.json").exists():
        rec = read_json(folder / "front.json")
        numbers += findings.front_numbers(rec)
        blocks.append({"type": "table", "table": tables.table(rec["front"], sort_by=["crosstalk"])})
    if (folder / "optimum.json").exists():
        rec = read_json(folder / "optimum.json")
        numbers += findings.optimum_numbers(rec)
        blocks.append({"type": "table", "table": tables.table(
            [{**rec["x"], "objective": rec["objective"], "evaluations": rec["evaluations"],
              "success": rec["success"], "message": rec["message"]}],
            csv=_csv_link(folder / "optimum-history.csv", out, folder))})
    imgs = sorted(folder.glob("*.png"))
    key = [p for p in imgs if p.name == "pareto.png"] or imgs
    if (folder / "front-3d.json").exists():          # the 3D-verified front (MultiFidelity.to_folder)
        rec = read_json(folder / "front-3d.json")
        numbers += findings.front_3d_numbers(rec)
        blocks += [{"type": "text", "text": rec["sentence"]},
                   {"type": "table", "table": tables.table(rec["front_3d"] + [rec["reference"]])},
                   {"type": "note", "text": f"3D model: {rec['verify_3d']}; rounds: {rec['rounds']}; "
                                            f"plan: {rec['plan']}; spent: {rec['spent']}"}]
    return {"sections": [{"title": "Optimization", "blocks": blocks + [_figures(imgs)]}], "numbers": numbers,
            "banners": [], "thumb": key[0].read_bytes() if key else None}


def _analysis(folder: Path, out: Path, scene_data) -> dict:
    imgs = sorted(folder.glob("*.png"))
    result = stored_result(folder)
    summary = "\n".join(result.summary()) if result is not None else ""
    links = [c for c in (_csv_link(p, out, folder) for p in sorted(folder.glob("*.csv"))) if c]
    blocks = [{"type": "pre", "text": summary}] if summary else []
    blocks += [_figures(imgs)] + [{"type": "note", "text": f"Full precision (SI units): {c}"} for c in links]
    return {"sections": [{"title": "Analysis", "blocks": blocks}], "numbers": findings.analysis_numbers(result),
            "banners": findings.frequency_banners(result),
            "scene_banners": ((scene_data or {}).get("analysis") or {}).get("type", "static") == "static",
            "thumb": imgs[0].read_bytes() if imgs else None}


def _work_precision(folder: Path, out: Path, scene_data) -> dict:
    from taxel.reports.work_precision import chart_files, cheapest_rows
    rec = read_json(chart_files(folder)[0])
    imgs = sorted(folder.glob("*.png"))
    rows = cheapest_rows(rec)
    notes = [{"type": "note", "text": f"{w['scene']} at {w['force_N']:g} N: {w['how']}"} for w in rec["work_precision"]]
    pzt = [r for r in rows if r["output"].startswith("pressed-taxel voltage")][:1]
    numbers = [(f"cheapest for 1 % ({r['scene']}, {r['force (N)']:g} N)", r["cheapest within 1 %"]) for r in pzt]
    return {"sections": [
        {"title": "Work against precision", "blocks": [
            {"type": "text", "text": "Wall time against error (log-log), one point per model, element order, mesh "
                                     "and silicone law; the Pareto set (cheapest for its accuracy) is ringed."},
            _figures(imgs, wide=True)] + notes},
        {"title": "Cheapest model for 1 %, 5 % and 10 % error", "blocks": [
            {"type": "table", "table": tables.table(rows, csv=_csv_link(chart_files(folder)[1], out, folder))}]}],
        "numbers": numbers, "banners": [], "thumb": imgs[0].read_bytes() if imgs else None}


# the page of each folder kind: (folder, out, scene data) -> sections, numbers, banners, thumb
PAGE_KINDS = {"study": _study, "optimization": _optimization, "analysis": _analysis, "work-precision": _work_precision,
              "noise": noise_page.page}


def build_page(folder: Path, out: Path, compare=True) -> Page:
    """Write OUT/<folder name>.html (and the folder's CSVs beside it)."""
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
        sec, nums, ban, key_png = scene_sections(folder, scene_data, compare)
        sections, numbers = sections + sec, numbers + nums
        banners += ban if part.get("scene_banners", True) else []
        thumb = thumb or key_png
    sections.append({"title": "Provenance", "blocks": provenance(folder, scene_data)})
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
        pages = [build_page(f, tmp, compare) for f in folders]
        warnings = [{"page": p.title, "text": b} for p in pages for b in p.banners]
        cards = [{"href": p.path.name, "title": p.title, "numbers": p.numbers, "warnings": len(p.banners),
                  "thumb": data_uri(p.thumb) if p.thumb else None} for p in pages]
        summary = [("what", run.get("what") or ", ".join(p.title for p in pages)),
                   ("when", run.get("started") or time.strftime("%Y-%m-%d %H:%M:%S")),
                   ("code version", code_version()),
                   ("duration", (f"{run['seconds']:.0f} s to compute, " if "seconds" in run else "")
                    + f"{time.perf_counter() - t0:.0f} s to build this report"),
                   ("warnings", f"{len(warnings)} result(s) outside their model's range" if warnings else "none")]
        (tmp / "index.html").write_text(templates().get_template("index.html").render(
            title="taxel report", run=summary, warnings=warnings, cards=cards), encoding="utf-8")
        if pdf:
            for p in pages:
                to_pdf(p.path)
    return out / "index.html"


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
