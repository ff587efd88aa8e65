"""The figures a result folder holds beside its numbers (matplotlib on the Agg
backend, no screen needed; pyvista off-screen): the press of an indenter,
and the solved fields of a fresh static solve in `fields/` (FIELD_FIGURES, in page
order: the 3D render, or RENDER_NOTE saying why not; the 2D cross-section; the taxels'
voltage map; the mesh). `pyplot()` is the one place the backend is chosen. The report
pages (taxel.reports) and the explorer reuse them. A dynamic result's figures (Bode plot,
time response) are results.dynamic_figures.
"""

from __future__ import annotations

import io
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from taxel.meshing.build import TaggedMesh
from taxel.scene import Scene
from taxel.schema import electrode_name
from taxel.units import engineering


def pyplot():
    """matplotlib.pyplot on the Agg backend."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def readable(label: str) -> str:
    """A readout label for a person: resistances with an SI prefix ("voltage across
    5e+08 ohm" -> "voltage across 500 MΩ")."""
    import re
    return re.sub(r"(\d[\d.]*(?:e[+-]?\d+)?) ?ohm", lambda m: eng(float(m.group(1)), "Ω"), label)


def eng(value: float | None, unit: str, digits: int = 3) -> str:
    """A number with an SI prefix, 3 significant figures, micro as µ: eng(2.33e-4, "N") -> "233 µN"."""
    import re
    return re.sub(r"^(\S+) u", r"\1 µ", engineering(value, unit, digits))


def contact_curves(rec: dict, path: Path, title: str = "") -> Path:
    """The press of an indenter scene: force against travel, and each open
    electrode's voltage against force (StaticResult.contact_record)."""
    plt = pyplot()
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


FIELDS = "fields"          # the folder's subfolder of field figures (FIELD_FIGURES, in page order)
FIELD_FIGURES = ("render.png", "section.png", "taxels.png", "mesh.png")
RENDER_NOTE = "render-note.txt"   # why the 3D render is missing (no off-screen OpenGL)


@dataclass(frozen=True)
class SolvedFields:
    """What the field figures draw of a fresh static solve (a StaticResult has the same
    attributes, and is drawn as well)."""

    scene: Scene
    mesh: TaggedMesh
    fields: object              # fem.static's Fields: u, phi, strain, stress
    electrodes: dict            # name -> fem.static.ElectrodeResult
    applied_force: float
    pressed: str | None
    unknowns: int


def field_figures(result: SolvedFields, folder: Path) -> list[Path]:
    """The solved fields drawn into `folder`: the off-screen 3D render (or RENDER_NOTE
    saying why not), the picture of the mesh, the 2D cross-section and the taxels'
    voltage map (an array)."""
    folder.mkdir(parents=True, exist_ok=True)
    files = []
    try:
        png = pyvista_render(result)
        (folder / "render.png").write_bytes(png)
        files.append(folder / "render.png")
    except Exception as exc:          # no off-screen OpenGL here: say so, keep the 2D figures
        note = f"3D render unavailable ({type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''})"
        (folder / RENDER_NOTE).write_text(note)
        files.append(folder / RENDER_NOTE)
    try:
        (folder / "mesh.png").write_bytes(mesh_render(result))
        files.append(folder / "mesh.png")
    except Exception:                 # no off-screen OpenGL: the render note above says so
        pass
    if result.mesh.mesh.dim() == 2:
        buf = io.BytesIO()
        cross_section(result, buf)
        (folder / "section.png").write_bytes(buf.getvalue())
        files.append(folder / "section.png")
    heat = taxel_heatmap(result)
    if heat is not None:
        heat.savefig(folder / "taxels.png", dpi=110)
        pyplot().close(heat)
        files.append(folder / "taxels.png")
    return files


def cross_section(sol, path, exaggerate=None):
    plt = pyplot()
    from matplotlib.tri import Triangulation

    mesh = sol.mesh.mesh
    if mesh.dim() != 2:
        raise ValueError("cross_section draws 2D and axisymmetric scenes")
    p, u = mesh.p * 1e3, sol.fields.u * 1e3                       # mm
    scale = exaggerate or max(1.0, round(0.1 * np.ptp(p[1]) / max(np.abs(u).max(), 1e-30)))
    deformed = p + scale * u.T
    fig, axes = plt.subplots(2, 1, figsize=(9, 6), constrained_layout=True)
    piezo = np.zeros(mesh.nelements, bool)
    for region in sol.mesh.materials:
        if region != "silicone":
            piezo[sol.mesh.regions[region]] = True
    ax = axes[0]
    ax.tripcolor(Triangulation(*deformed, mesh.t[:, ~piezo].T), np.zeros((~piezo).sum()),
                 cmap="Greys", vmin=-1, vmax=4, edgecolors="0.75", linewidth=0.1)
    pc = ax.tripcolor(Triangulation(*deformed, mesh.t[:, piezo].T), sol.fields.phi,
                      shading="gouraud", cmap="coolwarm")
    fig.colorbar(pc, ax=ax, label="electric potential (V)")
    ax.set_xlim(p[0].min() / 2, p[0].max() / 2)
    ax.set_title(f"{sol.scene.name}: potential in the piezo (silicone grey), deformation x{scale:g}")
    ax = axes[1]
    pc = ax.tripcolor(Triangulation(*p, mesh.t.T), u[:, 1] * 1e3, shading="gouraud", cmap="viridis")
    fig.colorbar(pc, ax=ax, label="vertical displacement (µm)")
    volts = ", ".join(f"{k}: {e.voltage * 1e3:.0f} mV" for k, e in sol.electrodes.items() if e.state != "reference")
    ax.set_title(f"{sol.applied_force:g} N on the taxel; open-circuit {volts}")
    axes[1].set_aspect("equal")
    for a in axes:
        a.set_xlabel("x (mm)")
        a.set_ylabel("z (mm)")
    fig.savefig(path, dpi=130)
    plt.close(fig)



def taxel_heatmap(sol):
    """The open-circuit voltage of every taxel for the press, as a rows x cols map
    in mV (the 2D section shows its one row); None for a single taxel."""
    import re
    plt = pyplot()
    cells = {}
    for name, e in sol.electrodes.items():
        m = re.fullmatch(r"taxel_(\d+)_(\d+)", name)
        if m:
            cells[int(m.group(1)), int(m.group(2))] = e.voltage * 1e3
    if len(cells) < 2:
        return None
    r0, r1 = min(r for r, _ in cells), max(r for r, _ in cells)
    c0, c1 = min(c for _, c in cells), max(c for _, c in cells)
    grid = np.full((r1 - r0 + 1, c1 - c0 + 1), np.nan)
    for (r, c), v in cells.items():
        grid[r - r0, c - c0] = v
    lim = np.nanmax(np.abs(grid))
    fig, ax = plt.subplots(figsize=(1.3 * grid.shape[1] + 2.5, 1.3 * grid.shape[0] + 1.2), layout="constrained")
    im = ax.imshow(grid, cmap="coolwarm", vmin=-lim, vmax=lim)
    for (r, c), v in cells.items():
        ax.text(c - c0, r - r0, f"{v:.0f}", ha="center", va="center", fontsize=10,
                fontweight="bold" if electrode_name(r, c) == sol.pressed else "normal")
    ax.set_xticks(range(grid.shape[1]), [str(c) for c in range(c0, c1 + 1)])
    ax.set_yticks(range(grid.shape[0]), [str(r) for r in range(r0, r1 + 1)])
    ax.set_xlabel("column (index)")
    ax.set_ylabel("row (index)")
    fig.colorbar(im, ax=ax, label="open-circuit voltage (mV)")
    ax.set_title(f"{sol.applied_force:g} N on {sol.pressed or 'the array'}", fontsize=9)
    return fig



def pyvista_render(sol, field="phi", window=(1200, 560)) -> bytes:
    """Off-screen pyvista render of the deformed mesh coloured by a field (the
    potential by default), framed on the pressed taxel and its neighbours; 2D
    meshes are drawn in their x-z plane, 3D ones clipped through the pressed row.
    PNG bytes."""
    if not os.environ.get("DISPLAY"):      # headless: EGL directly, not X first (which warns on stderr)
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    import pyvista as pv
    pv.OFF_SCREEN = True
    m = sol.mesh.mesh
    pts = m.p.T * 1e3
    u = sol.fields.u * 1e3
    if m.dim() == 2:
        pts = np.column_stack([pts[:, 0], np.zeros(len(pts)), pts[:, 1]])
        u = np.column_stack([u[:, 0], np.zeros(len(u)), u[:, 1]])
        cells = np.hstack([np.full((m.t.shape[1], 1), 3), m.t.T]).ravel()
        grid = pv.UnstructuredGrid(cells, np.full(m.t.shape[1], pv.CellType.TRIANGLE), pts + u)
    else:
        kind, t = vtk_cells(pv, m)
        cells = np.hstack([np.full((m.t.shape[1], 1), len(t)), t.T]).ravel()
        grid = pv.UnstructuredGrid(cells, np.full(m.t.shape[1], kind), pts + u)
    grid.point_data[field] = getattr(sol.fields, field)
    piezo = np.zeros(m.t.shape[1], bool)
    for region in sol.mesh.materials:
        if region != "silicone":
            piezo[sol.mesh.regions[region]] = True
    grid.cell_data["piezo"] = piezo.astype(float)
    lay = sol.mesh.layout               # the solved layout (cut, for a symmetric model)
    centre = (lay.load.x if lay.load is not None else float(np.mean(pts[:, 0])) * 1e-3) * 1e3
    half = (3 * lay.taxels[0].half + getattr(sol.scene.array, "gap", 0.0)) * 1e3 if lay.taxels else None
    y_load = (lay.load.y * 1e3) if lay.load is not None else float(np.median(pts[:, 1]))
    if m.dim() == 3:                  # a symmetric cut (quarter or half) mirrored back to the whole for the view
        for axis, at in ((0, centre), (1, y_load)):
            if float(pts[:, axis].min()) >= at - 1e-6 * max(1.0, abs(at)):
                normal = [0.0, 0.0, 0.0]
                normal[axis] = 1.0
                point = [0.0, 0.0, 0.0]
                point[axis] = at
                grid = grid.merge(grid.reflect(normal, point=point))
        grid = grid.clip(normal="-y", origin=(0.0, y_load, 0.0))   # cut through the pressed row
    plotter = pv.Plotter(off_screen=True, window_size=window)
    unit = "potential (V)" if field == "phi" else field
    piezo_part = grid.threshold(0.5, scalars="piezo")
    silicone_part = grid.threshold(0.5, scalars="piezo", invert=True)
    plotter.add_mesh(silicone_part, color="#d9d9d9", opacity=0.45, show_edges=m.dim() == 2,
                     edge_color="#bbbbbb", line_width=0.3)
    plotter.add_mesh(piezo_part, scalars=field, cmap="coolwarm",
                     scalar_bar_args={"title": unit, "title_font_size": 20, "label_font_size": 16,
                                      "fmt": "%.2g", "vertical": True, "position_x": 0.88,
                                      "position_y": 0.15, "height": 0.7})
    span = np.ptp(pts, axis=0)
    zscale = float(np.clip(span[0] / (4 * span[2]), 1.0, 3.0)) if m.dim() == 2 else 1.0
    if m.dim() == 2:                  # vertical x3: the 0.1 mm piezo and the 1 mm silicone readable
        plotter.set_scale(zscale=zscale)
        plotter.view_xz()
        if half:                          # frame the pressed taxel and its neighbours' edges
            z0, z1 = float(pts[:, 2].min()), float(pts[:, 2].max())
            plotter.camera.parallel_projection = True
            plotter.camera.focal_point = (centre, 0.0, zscale * (z0 + z1) / 2)
            plotter.camera.position = (centre, -100.0, zscale * (z0 + z1) / 2)
            plotter.camera.parallel_scale = max(0.55 * zscale * (z1 - z0),
                                                min(half, 0.5 * np.ptp(pts[:, 0])) * window[1] / window[0])
    else:                             # looking at the cut face, from the front and above, on the press
        plotter.view_isometric()
        z0, z1 = float(pts[:, 2].min()), float(pts[:, 2].max())
        h = half or 0.5 * float(np.ptp(pts[:, 0]))
        focus = (centre, y_load, (z0 + z1) / 2)
        plotter.camera.focal_point = focus
        plotter.camera.position = (centre + 0.6 * h, y_load - 2.2 * h, z1 + 1.4 * h)
        plotter.camera.view_up = (0.0, 0.0, 1.0)
    plotter.add_text(f"{sol.scene.name}: piezo coloured by {unit}, silicone grey; deformed x1"
                     + (f", vertical x{zscale:.2g}" if zscale != 1 else ""), font_size=11)
    return png_of(plotter)


def png_of(plotter) -> bytes:
    """The PNG bytes of a pyvista plotter's view, with x, y, z axes; the plotter is closed."""
    plotter.add_axes(xlabel="x", ylabel="y", zlabel="z")
    img = plotter.screenshot(return_img=True)
    plotter.close()
    import matplotlib.image as mpimg
    buf = io.BytesIO()
    mpimg.imsave(buf, img, format="png")
    return buf.getvalue()



def mesh_render(sol, window=(1100, 520)) -> bytes:
    """Off-screen pyvista picture of the solved mesh, edges drawn, piezo orange and
    silicone grey, with its statistics (elements, nodes, unknowns, sizes) in the title. PNG bytes."""
    if not os.environ.get("DISPLAY"):
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    import pyvista as pv
    m = sol.mesh.mesh
    pts = m.p.T * 1e3
    if m.dim() == 2:
        pts = np.column_stack([pts[:, 0], np.zeros(len(pts)), pts[:, 1]])
        kind, nv = pv.CellType.TRIANGLE, 3
        t = m.t
    else:
        kind, t = vtk_cells(pv, m)
        nv = len(t)
    cells = np.hstack([np.full((m.t.shape[1], 1), nv), t.T]).ravel()
    grid = pv.UnstructuredGrid(cells, np.full(m.t.shape[1], kind), pts)
    piezo = np.zeros(m.t.shape[1], bool)
    for region in sol.mesh.materials:
        if region != "silicone":
            piezo[sol.mesh.regions[region]] = True
    grid.cell_data["piezo"] = piezo.astype(float)
    plotter = pv.Plotter(off_screen=True, window_size=window)
    plotter.add_mesh(grid.threshold(0.5, scalars="piezo", invert=True), color="#dddddd", show_edges=True,
                     edge_color="#777777", line_width=0.4)
    plotter.add_mesh(grid.threshold(0.5, scalars="piezo"), color="#f0a050", show_edges=True, edge_color="#8a4a10",
                     line_width=0.4)
    if m.dim() == 2:
        plotter.view_xz()
    else:
        plotter.view_isometric()
    plotter.reset_camera()
    plotter.camera.zoom(2.0 if m.dim() == 2 else 1.3)
    scene = sol.scene
    plotter.add_text(f"{sol.scene.name}: {m.t.shape[1]} elements, {m.p.shape[1]} nodes, {sol.unknowns} unknowns; "
                     f"size {1e3 * scene.mesh.size:.2g} mm, {1e3 * (scene.mesh.piezo_size or scene.mesh.size / 4):.2g} mm "
                     f"at the piezo, order {scene.mesh.order}", font_size=10)
    return png_of(plotter)


# scikit-fem's hexahedron vertex order to VTK's (skfem.io.meshio.HEX_MAPPING)
HEX_TO_VTK = [0, 3, 6, 2, 1, 5, 7, 4]


def vtk_cells(pv, m):
    """(VTK cell type, connectivity (vertices, elements)) of a 3D mesh: tetrahedra, or the
    hexahedra of a structured mesh (meshing.hexmesh) in VTK's vertex order."""
    if m.t.shape[0] == 8:
        return pv.CellType.HEXAHEDRON, m.t[HEX_TO_VTK]
    return pv.CellType.TETRA, m.t
