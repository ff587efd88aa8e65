"""An analysis result written into its folder: the result's own files (result.json,
scene.json, its CSV), a plot, the figures of a static solve's fields (`fields/`),
and the summary lines. Used by the command line and the main job; the report
pages read these files back and never solve again."""

from __future__ import annotations

import io
from pathlib import Path

from taxel.analyses import AnalysisResult, FrequencyResult, LumpedResult, StaticResult, TransientResult
from taxel.reports import figures

FIELDS = "fields"          # the folder's subfolder of field figures (FIELD_FIGURES, in page order)
FIELD_FIGURES = ("render.png", "section.png", "taxels.png", "mesh.png")
RENDER_NOTE = "render-note.txt"   # why the 3D render is missing (no off-screen OpenGL)


def write(result: AnalysisResult, out) -> tuple[list[Path], list[str]]:
    """Write a result into `out`; returns (files written, summary lines). The
    summary is also kept as summary.txt."""
    out = Path(out)
    files = result.to_folder(out)
    name = result.scene.name
    if isinstance(result, FrequencyResult):
        files.append(bode_png(result, out / f"{name}-bode.png"))
    elif isinstance(result, TransientResult):
        files.append(transient_png(result, out / f"{name}-transient.png"))
    elif isinstance(result, LumpedResult):
        files.append(figures.bode(result.freqs, result.output[:, None], ["lumped 3-DoF"], result.label,
                                  out / f"{name}-lumped.png", title=f"{name} (lumped)"))
    elif isinstance(result, StaticResult):
        if result.contact_record() is not None:
            files.append(contact_curves(result.contact_record(), out / f"{name}-contact.png", title=name))
        files += field_figures(result, out / FIELDS)
    summary = result.summary()
    (out / "summary.txt").write_text("\n".join(summary) + "\n")
    return files, summary


def bode_png(result: FrequencyResult, path: Path) -> Path:
    """The Bode plot of a frequency result (fresh or read back), the notch marked."""
    r = result.scene.readout
    notch = r.notch_frequency if getattr(r, "notch", False) else None
    return figures.bode(result.freqs, result.output, result.names, result.label, path, title=result.scene.name,
                        notch=notch)


def transient_png(result: TransientResult, path: Path) -> Path:
    """The force and output of a transient result (fresh or read back)."""
    return figures.time_response(result.t, result.force, result.output, result.names, result.label, path,
                                 title=result.scene.name)


def field_figures(result: StaticResult, folder: Path) -> list[Path]:
    """The solved fields of a fresh static result, drawn into `folder`: the
    off-screen 3D render (or RENDER_NOTE saying why not), the 2D cross-section and
    the taxels' voltage map (an array). Nothing for a result read back (no fields)."""
    if result.mesh is None:
        return []
    folder.mkdir(parents=True, exist_ok=True)
    files = []
    try:
        png = figures.pyvista_render(result)
        (folder / "render.png").write_bytes(png)
        files.append(folder / "render.png")
    except Exception as exc:          # no off-screen OpenGL here: say so, keep the 2D figures
        note = f"3D render unavailable ({type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''})"
        (folder / RENDER_NOTE).write_text(note)
        files.append(folder / RENDER_NOTE)
    try:
        from taxel.reports.mesh_figure import mesh_render
        (folder / "mesh.png").write_bytes(mesh_render(result))
        files.append(folder / "mesh.png")
    except Exception:                 # no off-screen OpenGL: the render note above says so
        pass
    if result.mesh.mesh.dim() == 2:
        buf = io.BytesIO()
        figures.cross_section(result, buf)
        (folder / "section.png").write_bytes(buf.getvalue())
        files.append(folder / "section.png")
    heat = figures.taxel_heatmap(result)
    if heat is not None:
        heat.savefig(folder / "taxels.png", dpi=110)
        figures.pyplot().close(heat)
        files.append(folder / "taxels.png")
    return files


def contact_curves(rec: dict, path: Path, title: str = "") -> Path:
    """The press of an indenter scene: force against travel, and each open
    electrode's voltage against force (StaticResult.contact_record)."""
    plt = figures.pyplot()
    cv = rec["curve"]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(8, 3.4), constrained_layout=True)
    a1.plot([1e3 * d for d in cv["travel_m"]], cv["force_N"], "o-", ms=3, color="k")
    a1.set_xlabel("indenter travel (mm)")
    a1.set_ylabel("force (N)")
    for k, v in cv["voltages_V"].items():
        a2.plot(cv["force_N"], v, "o-", ms=3, label=k)
    a2.set_xlabel("force (N)")
    a2.set_ylabel("open-circuit voltage (V)")
    a2.legend(fontsize=8)
    for a in (a1, a2):
        a.grid(True, alpha=0.3)
    fig.suptitle(f"{title}: {rec['indenter']['shape']} indenter, {rec['load_steps']} load steps", fontsize=9)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
