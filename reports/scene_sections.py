"""The sections a page draws from its folder's scene: the scene to scale, the solved
fields, the solver's own figures, and the model comparison, with the headline
numbers and the validity banners of the solve.

Nothing already solved is solved again. The model comparison's points go through
a study store in the folder (`Store.get_or_compute`, report-cache/results.sqlite,
apart from a study's own points),
and the scene's own solve is kept as what the page shows of it (the renders, the
tables, the numbers) in the folder's `report-cache/`, under the key of a study
point (the scene and the code version) and of the drawing code, so a second
build of the same folder solves nothing.
"""

from __future__ import annotations

import base64
import hashlib
import io
import json
import tempfile
import time
from functools import cache
from pathlib import Path

from taxel.analyses import lumped_model, scene_materials, solve_static
from taxel.reports import findings, tables
from taxel.scene import parse, scene_material_names, to_data
from taxel.studies.store import Store, StoreError, point_key
from taxel.units import engineering


def data_uri(png: bytes) -> str:
    return "data:image/png;base64," + base64.b64encode(png).decode()


def figure_png(fig, dpi=110) -> bytes:
    """PNG bytes of a matplotlib figure (closed afterwards)."""
    from taxel.reports.figures import pyplot
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    pyplot().close(fig)
    return buf.getvalue()


def scene_sections(folder: Path, scene_data: dict, compare: bool):
    """(sections, headline numbers, banners, key figure PNG) of the folder's scene."""
    from taxel.reports import figures
    scene = parse({**scene_data, "name": scene_data.get("name", "scene")})
    solved = _solved(folder, scene)
    sections = [
        {"title": "Scene", "blocks": [
            {"type": "figures", "images": [data_uri(figure_png(figures.scene_drawing(scene)))]},
            {"type": "table", "table": tables.table(
                [{"material": m, "source": scene_materials(scene)[m].source} for m in scene_material_names(scene)],
                ["material", "source"])}]},
        {"title": "Fields", "blocks": [{"type": "figures", "images": [data_uri(p) for p in solved["images"]]}]
         + ([{"type": "note", "text": solved["render_note"]}] if solved["render_note"] else [])},
        {"title": "Solver", "blocks": [{"type": "table", "table": solved["solver"]},
                                       {"type": "table", "table": solved["electrodes"]}]},
    ]
    if compare and scene.array is not None and scene.array.rows * scene.array.cols == 1:
        sections.append({"title": "Model comparison", "blocks": comparison(folder, scene)})
    key_png = solved["images"][-1] if solved["images"] else None
    return sections, [tuple(n) for n in solved["numbers"]], solved["banners"], key_png


def _solved(folder: Path, scene) -> dict:
    """What the page shows of the scene's static solve, from report-cache/ or solved now."""
    cache = folder / "report-cache"
    key = hashlib.sha256((point_key(to_data(scene)) + _drawing_version()).encode()).hexdigest()[:24]
    meta = cache / f"{key}.json"
    if meta.exists():
        rec = json.loads(meta.read_text())
        rec["images"] = [(cache / n).read_bytes() for n in rec.pop("image_files")]
        return rec
    from taxel.reports import figures
    sol = solve_static(scene)
    images, note = [], ""
    try:
        images.append(figures.pyvista_render(sol))
    except Exception as exc:          # no off-screen OpenGL here: say so, keep the 2D figures
        note = f"3D render unavailable ({type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''})"
    if sol.mesh.mesh.dim() == 2:
        buf = io.BytesIO()
        figures.cross_section(sol, buf)
        images.append(buf.getvalue())
    heat = figures.taxel_heatmap(sol)
    if heat is not None:
        images.append(figure_png(heat))
    rec = {
        "numbers": findings.static_numbers(sol), "banners": findings.static_banners(sol), "render_note": note,
        "solver": tables.table([{
            "model": scene.model.type.replace("_", " "), "silicone": sol.model_note or scene.model.silicone,
            "order": scene.mesh.order, "unknowns": sol.unknowns, "solver": sol.solver,
            "relative residual": f"{sol.residual:.1e}",
            "Newton iterations": sol.newton.total_iterations if sol.newton else "-",
            "mesh": f"{sol.times['mesh']:.2f} s", "assemble": f"{sol.times['assemble']:.2f} s",
            "solve": f"{sol.times['solve']:.2f} s"}]),
        "electrodes": tables.table(
            [{"electrode": e.name, "open-circuit V": engineering(e.voltage, "V"),
              "short-circuit Q": engineering(e.short_circuit_charge, "C"),
              "capacitance": engineering(e.capacitance, "F")} for e in sol.electrodes.values()],
            sort_by=["electrode"]),
    }
    try:                              # a read-only folder: the page is built, nothing is kept
        cache.mkdir(exist_ok=True)
        names = []
        for i, png in enumerate(images):
            (cache / f"{key}-{i}.png").write_bytes(png)
            names.append(f"{key}-{i}.png")
        meta.write_text(json.dumps({**rec, "image_files": names}))
    except OSError:
        pass
    rec["images"] = images
    return rec


@cache
def _drawing_version() -> str:
    """Hash of the code that draws and words a solve (a change redraws the cached pages)."""
    here = Path(__file__).parent
    return hashlib.sha256(b"".join((here / f).read_bytes() for f in (
        "figures.py", "findings.py", "tables.py", "scene_sections.py"))).hexdigest()[:16]


def comparison(folder: Path, scene) -> list[dict]:
    """Lumped, 2D plane stress/strain, axisymmetric and 3D, linear silicone, at the
    scene's force: voltage per newton, deviation from 3D and the solve's cost. The
    FEM points come from the folder's store (solved once, ever)."""
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
            status, res, err = store.get_or_compute(to_data(s), ("voltage",), {"report": "comparison",
                                                                               "model": label})
            if status != "done":
                rows.append({"model": label, "voltage V/N": None, "vs 3D": (err or "")[:70], "cost": None})
                return None
            v = abs(res["voltage"][res["pressed"]]) / F
            rows.append({"model": label, "voltage V/N": v, "cost": res["seconds"]})
            return v
        t = time.perf_counter()
        lm = abs(lumped_model(scene).V_oc([1e-3])[0]) / F
        rows.append({"model": "lumped 3-DoF", "voltage V/N": lm, "cost": time.perf_counter() - t})
        variant("2D plane stress", "plane_stress")
        variant("2D plane strain", "plane_strain")
        variant("axisymmetric", "axisymmetric")     # PVDF: a row that says why not
        ref = variant("3D", "3d", mesh={"size": 1e-3, "piezo_size": 4e-4})
    finally:
        store.close()
        if scratch is not None:
            scratch.cleanup()
    for r in rows:
        if ref and isinstance(r.get("voltage V/N"), float):
            r["vs 3D"] = f"{100 * (r['voltage V/N'] / ref - 1):+.1f} %"
    for r in rows:
        r["voltage V/N"] = tables.cell(r["voltage V/N"], tables.column("sensitivity_V_per_N")[1])
        r["cost"] = "" if r["cost"] is None else f"{r['cost']:.3g} s"
    return [{"type": "table", "table": tables.table(rows, ["model", "voltage V/N", "vs 3D", "cost"])},
            {"type": "note", "text": (
                f"Open-circuit voltage of the pressed taxel per newton, linear silicone, at {F:g} N. Deviation "
                "from the 3D model (1 mm mesh, 0.4 mm at the taxel; its own mesh error is about 1 %). The Yeoh "
                "silicone changes these by the strain-dependent amount in the README (7 % at 0.2 N). Cost: the "
                "wall seconds of the solve when it was first computed; the results are kept in the folder's "
                "report-cache/results.sqlite and reused.")}]
