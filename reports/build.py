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
date, material sources). Images are embedded (data URIs): a page opens with no
network and no other file. The markup is XHTML (well-formed XML).
"""

from __future__ import annotations

import base64
import csv
import html
import io
import json
import time
from pathlib import Path

from taxel.analyses import lumped_model, scene_materials, solve_static
from taxel.analyses.results import output_folder
from taxel.fem.newton import NewtonError
from taxel.scene import SceneError, parse, scene_material_names
from taxel.studies.store import code_version

CSS = """body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;color:#222;padding:0 1em}
h1{font-size:1.6em}h2{font-size:1.2em;border-bottom:1px solid #ccc;padding-bottom:.2em;margin-top:2em}
img{max-width:100%;border:1px solid #eee;margin:.4em 0}table{border-collapse:collapse;font-size:.85em}
td,th{border:1px solid #ddd;padding:.25em .5em;text-align:right}th{background:#f4f4f4}
.grid{display:grid;grid-template-columns:repeat(auto-fill,minmax(480px,1fr));gap:1em}
.note{color:#555;font-size:.9em}pre{background:#f7f7f7;padding:.6em;overflow:auto;font-size:.8em}"""


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
    if (folder / "scene.json").exists():
        return "analysis"
    if (folder / "validation.json").exists():           # a measurement validation (reports/validation.py)
        return "validation"
    raise ReportError(f"{folder}: not a study, optimization or solve folder (no study.json, optimum.json, "
                      "front.json or scene.json); run taxel study/optimize/solve with --out first")


def _png(path_or_fig) -> str:
    if isinstance(path_or_fig, (str, Path)):
        data = Path(path_or_fig).read_bytes()
    else:
        buf = io.BytesIO()
        path_or_fig.savefig(buf, format="png", dpi=110)
        import matplotlib.pyplot as plt
        plt.close(path_or_fig)
        data = buf.getvalue()
    if not data:
        raise ReportError("an image to embed is empty")
    return f'<img alt="figure" src="data:image/png;base64,{base64.b64encode(data).decode()}"/>'


def _table(rows, cols=None, limit=40) -> str:
    if not rows:
        return "<p class=\"note\">(no rows)</p>"
    cols = cols or list(rows[0])
    head = "".join(f"<th>{html.escape(str(c))}</th>" for c in cols)
    body = "".join("<tr>" + "".join(f"<td>{html.escape(_fmt(r.get(c)))}</td>" for c in cols) + "</tr>"
                   for r in rows[:limit])
    more = f"<p class=\"note\">{len(rows) - limit} more rows in the CSV</p>" if len(rows) > limit else ""
    return f"<table><tr>{head}</tr>{body}</table>{more}"


def _fmt(v):
    """A table cell: numbers (also numeric strings from CSV) to 4 significant digits."""
    if v is None or isinstance(v, bool):
        return "" if v is None else str(v)
    try:
        return f"{float(v):.4g}"
    except (TypeError, ValueError):
        return str(v)


def _page(title, sections) -> str:
    body = "".join(f"<h2>{html.escape(h)}</h2>{content}" for h, content in sections)
    return ("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!DOCTYPE html>\n"
            "<html xmlns=\"http://www.w3.org/1999/xhtml\" lang=\"en\"><head><meta charset=\"utf-8\"/>"
            f"<title>{html.escape(title)}</title><style>{CSS}</style></head>"
            f"<body><h1>{html.escape(title)}</h1>{body}</body></html>\n")


def _scene_sections(scene_data: dict, compare: bool):
    from taxel.reports import figures
    scene = parse({**scene_data, "name": scene_data.get("name", "scene")})
    out = [("Scene", _png(figures.scene_drawing(scene)) + _scene_table(scene))]
    sol = solve_static(scene)
    out.append(("Fields", _render(sol)))
    out.append(("Solver", _table([{
        "model": scene.model.type, "silicone": scene.model.silicone, "order": scene.mesh.order,
        "unknowns": sol.unknowns, "solver": sol.solver, "relative residual": sol.residual,
        "Newton iterations": sol.newton.total_iterations if sol.newton else "-",
        "mesh s": sol.times["mesh"], "assemble s": sol.times["assemble"], "solve s": sol.times["solve"]}])
        + _table([{"electrode": e.name, "voltage V": e.voltage, "short-circuit charge C": e.short_circuit_charge,
                   "capacitance F": e.capacitance} for e in sol.electrodes.values()])))
    if compare and scene.array is not None and scene.array.rows * scene.array.cols == 1:
        out.append(("Model comparison", _comparison(scene)))
    return out, scene


def _scene_table(scene) -> str:
    mats = scene_materials(scene)
    rows = [{"material": m, "source": mats[m].source} for m in scene_material_names(scene)]
    return _table(rows, ["material", "source"])


def _render(sol) -> str:
    """The solved fields: a pyvista render (off-screen) of the deformed mesh
    coloured by the potential, and the 2D cross-section with matplotlib."""
    from taxel.reports import figures
    parts = []
    try:
        parts.append(_png_bytes(figures.pyvista_render(sol)))
    except Exception as exc:          # no off-screen OpenGL here: say so, keep the 2D figure
        parts.append(f"<p class=\"note\">3D render unavailable ({html.escape(type(exc).__name__)}: "
                     f"{html.escape(str(exc).splitlines()[0] if str(exc) else '')})</p>")
    if sol.mesh.mesh.dim() == 2:
        buf = io.BytesIO()
        figures.cross_section(sol, buf)
        parts.append(_png_bytes(buf.getvalue()))
    return "<div class=\"grid\">" + "".join(parts) + "</div>"


def _png_bytes(data: bytes) -> str:
    return f'<img alt="render" src="data:image/png;base64,{base64.b64encode(data).decode()}"/>'


def _comparison(scene) -> str:
    """Lumped, 2D plane stress/strain, axisymmetric, 3D, linear and Yeoh, at the
    scene's force (Yeoh at min(force, 0.2 N), where Newton follows it): voltage,
    cost, and the deviation from the 3D model."""
    rows = []
    F = scene.load.force

    def variant(label, model=None, silicone="linear", mesh=None):
        t = time.perf_counter()
        try:
            s = scene.replace(**{"model.type": model or scene.model.type, "model.silicone": silicone},
                              **{f"mesh.{k}": v for k, v in (mesh or {}).items()})
            v = solve_static(s).voltages()
            v = next(iter(v.values()))
        except (NewtonError, SceneError, ValueError) as exc:
            rows.append({"model": label, "voltage V/N": "-", "seconds": "-", "vs 3D %": str(exc)[:60]})
            return None
        rows.append({"model": label, "voltage V/N": abs(v) / F, "seconds": time.perf_counter() - t})
        return abs(v) / F
    t = time.perf_counter()
    lm = abs(lumped_model(scene).V_oc([1e-3])[0]) / F
    rows.append({"model": "lumped 3-DoF", "voltage V/N": lm, "seconds": time.perf_counter() - t})
    variant("2D plane stress", "plane_stress")
    variant("2D plane strain", "plane_strain")
    variant("axisymmetric", "axisymmetric")      # PVDF: a row that says why not (not transversely isotropic)
    ref = variant("3D", "3d", mesh={"size": 1e-3, "piezo_size": 4e-4})
    for r in rows:
        if ref and isinstance(r.get("voltage V/N"), float):
            r["vs 3D %"] = 100 * (r["voltage V/N"] / ref - 1)
    note = ("<p class=\"note\">Open-circuit voltage of the pressed taxel per newton, linear silicone, at "
            f"{F:g} N. Deviation from the 3D model (1 mm mesh, 0.4 mm at the taxel; its own mesh error is "
            "about 1 %). The Yeoh silicone changes these by the strain-dependent amount in the README "
            "(7 % at 0.2 N). Cost: wall seconds on this machine.</p>")
    return _table(rows, ["model", "voltage V/N", "vs 3D %", "seconds"]) + note


def _provenance(folder: Path, scene_data: dict | None) -> str:
    rows = [{"item": "folder", "value": str(folder.resolve())}, {"item": "code version", "value": code_version()},
            {"item": "report date", "value": time.strftime("%Y-%m-%d %H:%M:%S")}]
    scene_txt = f"<details><summary>scene</summary><pre>{html.escape(json.dumps(scene_data, indent=1))}</pre>" \
                "</details>" if scene_data else ""
    return _table(rows, ["item", "value"]) + scene_txt


def build_page(folder: Path, out: Path, compare=True) -> tuple[Path, str, str]:
    """Write OUT/<folder name>.html; returns (path, kind, title)."""
    folder = Path(folder)
    if not folder.is_dir():
        raise ReportError(f"{folder}: no such folder")
    kind = kind_of(folder)
    if kind == "validation":
        from taxel.reports.validation import build_page as validation_page
        return validation_page(folder, out)
    scene_data = read_json(folder / "scene.json") if (folder / "scene.json").exists() else None
    title = f"{folder.name} ({kind})"
    sections = []
    if scene_data:
        sec, _ = _scene_sections(scene_data, compare)
        sections += sec
    if kind == "study":
        spec = read_json(folder / "study.json")
        plots = sorted((folder / "plots").glob("*.png"))
        sections.insert(0, ("Parameter study", f"<p>{html.escape(spec.get('description', ''))}</p>"
                            + "<div class=\"grid\">" + "".join(_png(p) for p in plots) + "</div>"))
        rows = list(csv.DictReader(open(folder / "results.csv"))) if (folder / "results.csv").exists() else []
        sections.insert(1, ("Results", _table(rows)))
    elif kind == "optimization":
        parts = []
        for name in ("front.json", "optimum.json"):
            if (folder / name).exists():
                rec = read_json(folder / name)
                if name == "front.json":
                    parts.append(_table(rec["front"]))
                    if rec.get("reference"):
                        ref = rec["reference"]
                        parts.append(f"<p>Thesis design: sensitivity {ref['sensitivity']:.4g} V/N, crosstalk "
                                     f"{100 * ref['crosstalk']:.2f} %.</p>")
                else:
                    parts.append(_table([{**rec["x"], "objective": rec["objective"], "evaluations": rec["evaluations"],
                                          "success": rec["success"], "message": rec["message"]}]))
        imgs = sorted(folder.glob("*.png"))
        sections.insert(0, ("Optimization", "".join(parts) + "<div class=\"grid\">"
                            + "".join(_png(p) for p in imgs) + "</div>"))
    else:
        imgs = sorted(folder.glob("*.png"))
        summary = (folder / "summary.txt").read_text() if (folder / "summary.txt").exists() else ""
        sections.insert(0, ("Analysis", f"<pre>{html.escape(summary)}</pre><div class=\"grid\">"
                            + "".join(_png(p) for p in imgs) + "</div>"))
    sections.append(("Provenance", _provenance(folder, scene_data)))
    out.mkdir(parents=True, exist_ok=True)
    path = out / f"{folder.name}.html"
    path.write_text(_page(title, sections), encoding="utf-8")
    return path, kind, title


def build(folders, out: Path, pdf=False, compare=True) -> Path:
    """One page per result folder and an index, written whole into `out` (a
    failure on any folder leaves no partial report; an existing report is
    replaced only when the new one is complete)."""
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
    with output_folder(out, replace=True) as tmp:
        pages = [build_page(f, tmp, compare) for f in folders]
        links = "".join(f"<li><a href=\"{html.escape(p.name)}\">{html.escape(t)}</a></li>" for p, k, t in pages)
        (tmp / "index.html").write_text(_page("taxel reports", [("Pages", f"<ul>{links}</ul>"), (
            "About", "<p>Made by <code>taxel report</code>. Each page is self-contained (images embedded).</p>")]),
            encoding="utf-8")
        if pdf:
            for p, _, _ in pages:
                to_pdf(p)
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
