"""The sections a page draws from its folder: the scene to scale, the solved fields
and the solver's tables of a static solve stored in the folder, and the model
comparison, with the headline numbers and the validity banners of the solve.

Nothing is solved here. The static solve is read from the folder's result.json
(`taxel.analyses.read`) and its fields are the figures drawn when the folder was
written (the result's `to_folder`: `fields/`); a folder without them (a study, an
optimization, a dynamic analysis) shows the scene only. The model comparison's
points go through a study store in the folder (`Store.get_or_compute`,
report-cache/results.sqlite, apart from a study's own points), so a second build
of the same folder solves nothing.
"""

from __future__ import annotations

import io
import tempfile
import time
from pathlib import Path

from taxel.analyses import StaticResult, lumped_model, read
from taxel.analyses.results import RESULT_TYPES, result_kind
from taxel.reports import findings, tables
from taxel.reports.page import data_uri  # noqa: F401  (its home: reports.page)
from taxel.analyses.results.figures import FIELD_FIGURES, FIELDS, RENDER_NOTE
from taxel.scene import parse
from taxel.schema import to_data
from taxel.studies.store import Store, StoreError
from taxel.reports.tables import eng


def figure_png(fig, dpi=110) -> bytes:
    """PNG bytes of a matplotlib figure (closed afterwards)."""
    from taxel.reports.figures import pyplot
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    pyplot().close(fig)
    return buf.getvalue()


def stored_result(folder: Path):
    """The analysis result a folder's result.json holds (taxel.analyses.read), or
    None when the folder has none (or holds an optimization's result). Raises
    ResultError (one line) for an unreadable one."""
    return read(folder) if result_kind(folder) in RESULT_TYPES else None


def scene_sections(folder: Path, scene_data: dict, compare: bool):
    """(sections, headline numbers, banners of the folder's own solve, banners of the
    model comparison, key figure PNG) of the folder's scene."""
    from taxel.reports import figures
    from taxel.reports.captions import caption
    from taxel.reports.materials_table import materials_table
    scene = parse({**scene_data, "name": scene_data.get("name", "scene")})
    sections = [
        {"title": "Scene", "blocks": [
            {"type": "figures", "images": [{"src": data_uri(figure_png(figures.scene_drawing(scene))),
                                            "caption": f"The scene to scale (x-z section, mm): layers, taxels and "
                                                       f"the load; {findings.model_label(scene)}."}]},
            {"type": "table", "table": materials_table(scene)}]}]
    result = stored_result(folder)
    numbers, banners, key_png = [], [], None
    if isinstance(result, StaticResult):
        names = [n for n in FIELD_FIGURES if (folder / FIELDS / n).is_file()]
        images = [(folder / FIELDS / n).read_bytes() for n in names]
        note = folder / FIELDS / RENDER_NOTE
        fields = [{"type": "figures", "images": [{"src": data_uri(p), "caption": caption(Path(n))}
                                                 for p, n in zip(images, names)]}] if images else []
        if note.is_file():
            fields.append({"type": "note", "text": note.read_text().strip()})
        if not images and not note.is_file():
            fields.append({"type": "note", "text": "No field figures in this folder: they are drawn when the "
                                                   "folder is written (taxel solve SCENE --out DIR)."})
        sections += [{"title": "Fields", "blocks": fields},
                     {"title": "Solver", "blocks": [{"type": "table", "table": solver_table(result)},
                                                    {"type": "table", "table": electrode_table(result)}]}]
        from taxel.reports import warm_touch
        warm = warm_touch.section(folder)      # a [warm_touch]: its numbers, the field and the traces
        if warm is not None:
            sections.append(warm)
        numbers, banners = findings.static_numbers(result), findings.static_banners(result)
        key = next((n for n in ("render.png", "taxels.png") if n in names), None)
        key_png = images[names.index(key)] if key else (images[0] if images else None)
    compare_banners = []
    if compare and scene.array is not None and scene.array.rows * scene.array.cols == 1:
        blocks, compare_banners = comparison(folder, scene)
        sections.append({"title": "Model comparison", "blocks": blocks})
    return sections, numbers, banners, compare_banners, key_png


def solver_table(result: StaticResult) -> dict:
    """The model, the silicone law and the solve's cost, one row."""
    scene, n = result.scene, result.newton
    t = result.times
    return tables.table([{
        "model": scene.model.type.replace("_", " "), "silicone": result.model_note or scene.model.silicone,
        "order": scene.mesh.order, "unknowns": result.unknowns, "solver": result.solver,
        "relative residual": f"{result.residual:.1e}",
        "Newton iterations": n.total_iterations if n else "-",
        **{f"{k} time (s)": f"{t[k]:.2f}" for k in ("mesh", "assemble", "solve") if k in t}}], title="solver")


def electrode_table(result: StaticResult) -> dict:
    """Each electrode's open-circuit voltage, short-circuit charge and capacitance."""
    return tables.table(
        [{"electrode": e.name, "open-circuit V": eng(e.voltage, "V"),
          "short-circuit Q": eng(e.short_circuit_charge, "C"),
          "capacitance": eng(e.capacitance, "F")} for e in result.electrodes.values()],
        sort_by=["electrode"], title="electrodes")


def comparison(folder: Path, scene) -> tuple[list[dict], list]:
    """Lumped, 2D plane stress/strain, axisymmetric and 3D, linear silicone, at the
    scene's force: voltage per newton, deviation from 3D, the largest silicone strain
    and the solve's cost; with the banners it calls for (a model off 3D beyond the
    error estimates; a linear strain beyond the linear law's range). The FEM points
    come from the folder's store (solved once, ever)."""
    from taxel.analyses import linear_error
    F = scene.load.force
    rows = []
    scratch = None
    try:
        store = Store(folder / "report-cache")
    except (StoreError, OSError):     # a read-only folder: a store that lasts this build
        scratch = tempfile.TemporaryDirectory(prefix="taxel-report-")
        store = Store(Path(scratch.name))
    try:
        def variant(label, model, mesh=None):
            s = scene.replace(**{"model.type": model, "model.silicone": "linear"},
                              **{f"mesh.{k}": v for k, v in (mesh or {}).items()})
            status, res, err = store.get_or_compute(to_data(s), ("voltage", "max_strain"),
                                                    {"report": "comparison", "model": label})
            if status != "done":
                rows.append({"model": label, "v": None, "vs 3D": (err or "")[:70], "cost": None})
                return None
            v = abs(res["voltage"][res["pressed"]]) / F
            rows.append({"model": label, "v": v, "cost": res["seconds"], "strain": res.get("max_strain")})
            return v
        t = time.perf_counter()
        lm = abs(lumped_model(scene).V_oc([1e-3])[0]) / F
        rows.append({"model": "lumped 3-DoF", "v": lm, "cost": time.perf_counter() - t})
        variant("2D plane stress", "plane_stress")
        variant("2D plane strain", "plane_strain")
        variant("axisymmetric", "axisymmetric")     # PVDF: a row that says why not
        ref = variant("3D", "3d", mesh={"size": 1e-3, "piezo_size": 4e-4})
    finally:
        store.close()
        if scratch is not None:
            scratch.cleanup()
    banners = findings.comparison_banners(rows)
    tol = scene.model.tolerance
    hot = [r for r in rows if r.get("strain") is not None and linear_error(r["strain"]) > tol]
    if hot:
        worst = max(hot, key=lambda r: r["strain"])
        banners.append(findings.Banner("range", (
            f"Linear silicone outside its range at this scene's {F:g} N: the largest silicone strain is "
            f"{100 * worst['strain']:.3g} % ({worst['model']}), an estimated voltage error of "
            f"{100 * linear_error(worst['strain']):.2g} % against a tolerance of {100 * tol:g} %. A frequency or step "
            "response is linear in the force: its V/N holds for small presses; at this force read it as a trend, "
            "or rerun with model.silicone = \"yeoh\" (static) or a smaller load.force.")))
    for r in rows:
        if ref and isinstance(r.get("v"), float):
            r["vs 3D"] = f"{100 * (r['v'] / ref - 1):+.1f} %"
        r["voltage per newton"] = tables.cell(r["v"], tables.column("sensitivity_V_per_N")[1])
        r["largest silicone strain"] = tables.percent(r["strain"]) if r.get("strain") is not None else ""
        r["cost"] = "" if r["cost"] is None else f"{r['cost']:.3g} s"

    def mark(r):
        return "out-of-range" if r in hot else ""
    return [{"type": "table", "table": tables.table(
                rows, ["model", "voltage per newton", "vs 3D", "largest silicone strain", "cost"], mark=mark,
                title="model comparison")},
            {"type": "note", "text": (
                f"Open-circuit voltage of the pressed taxel per newton, linear silicone, at {F:g} N. Deviation "
                "from the 3D model (1 mm mesh, 0.4 mm at the taxel; its own mesh error is about 1 %). The Yeoh "
                "silicone changes these by a strain-dependent amount (7 % at 0.2 N on the thesis taxel: benchmarks/hyperelastic_taxel.py, docs/benchmarks.md). Cost: the "
                "wall seconds of the solve when it was first computed; the results are kept in the folder's "
                "report-cache/results.sqlite and reused.")}], banners
