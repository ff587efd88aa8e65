"""The picture of a solve's mesh (pyvista off-screen): edges drawn, piezo orange and
silicone grey, its statistics in the title; kept beside the fields (reports.analysis)."""

from __future__ import annotations

import os

import numpy as np


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
    else:
        kind, nv = pv.CellType.TETRA, 4
    cells = np.hstack([np.full((m.t.shape[1], 1), nv), m.t.T]).ravel()
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
    from taxel.reports.figures import png_of
    return png_of(plotter)
