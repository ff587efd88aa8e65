"""Figures (matplotlib on the Agg backend, no screen needed; pyvista off-screen).

`pyplot()` is the one place the backend is chosen. `docs/readme_figure.py`
makes the README's picture with `cross_section`.
"""

from __future__ import annotations

import io
import os

import numpy as np

from taxel.analyses.geometry import layout
from taxel.analyses.problem import scene_materials
from taxel.fem.yeoh_fit import stability_limit
from taxel.units import magnitude


def pyplot():
    """matplotlib.pyplot on the Agg backend."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


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
    fig.colorbar(pc, ax=ax, label="vertical displacement (um)")
    volts = ", ".join(f"{k}: {e.voltage * 1e3:.0f} mV" for k, e in sol.electrodes.items() if e.state != "reference")
    ax.set_title(f"{sol.applied_force:g} N on the taxel; open-circuit {volts}")
    axes[1].set_aspect("equal")
    for a in axes:
        a.set_xlabel("x (mm)")
        a.set_ylabel("z (mm)")
    fig.savefig(path, dpi=130)
    plt.close(fig)


def bode(freqs, H, names, label, path, title=""):
    """Magnitude and phase of H (nf, na) against frequency."""
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 6), sharex=True, constrained_layout=True)
    for k, name in enumerate(names):
        a1.loglog(freqs, np.abs(H[:, k]), label=name)
        a2.semilogx(freqs, np.degrees(np.angle(H[:, k])), label=name)
    a1.set_ylabel(f"|{label}| (V/N)")
    a2.set_ylabel("phase (deg)")
    a2.set_xlabel("frequency (Hz)")
    a1.set_title(title)
    a1.legend(fontsize=8)
    for a in (a1, a2):
        a.grid(True, which="both", alpha=0.3)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def time_response(t, force, y, names, label, path, title=""):
    """Force and output voltages over time."""
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 5.5), sharex=True, constrained_layout=True)
    a1.plot(t, force, color="k")
    a1.set_ylabel("force (N)")
    a1.set_title(title)
    for k, name in enumerate(names):
        a2.plot(t, y[:, k], label=name)
    a2.set_ylabel(f"{label} (V)")
    a2.set_xlabel("time (s)")
    a2.legend(fontsize=8)
    for a in (a1, a2):
        a.grid(True, alpha=0.3)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def study_plots(rows, parameters, outputs, folder, title=""):
    """Each output against each numeric varied parameter; one line per combination
    of the other parameters (labels in the legend). Returns the files written."""
    plt = pyplot()
    folder.mkdir(parents=True, exist_ok=True)
    done = [r for r in rows if r["status"] == "done"]
    files = []
    for p in parameters:
        xs = [magnitude(r.get(p)) for r in done]
        if not xs or not all(isinstance(x, float) for x in xs):
            continue
        others = [q for q in parameters if q != p]
        for out in outputs:
            if not any(out in r for r in done):
                continue
            fig, ax = plt.subplots(figsize=(7, 4.2), constrained_layout=True)
            groups = {}
            for r in done:
                groups.setdefault(tuple(str(r.get(q)) for q in others), []).append(r)
            for key, grp in sorted(groups.items()):
                grp = sorted(grp, key=lambda r: magnitude(r[p]))
                ys = [abs(r[out]) if isinstance(r.get(out), (int, float)) else np.nan for r in grp]
                ax.plot([magnitude(r[p]) for r in grp], ys, "o-", ms=3,
                        label=", ".join(f"{q}={v}" for q, v in zip(others, key)) or None)
            ax.set_xlabel(f"{p} (SI)")
            ax.set_ylabel(f"|{out}|")
            ax.set_title(title)
            if len(groups) > 1:
                ax.legend(fontsize=6, ncol=2)
            ax.grid(True, alpha=0.3)
            path = folder / f"{out}-vs-{p}.png"
            fig.savefig(path, dpi=110)
            plt.close(fig)
            files.append(path)
    return files


def scene_layout(scene):
    return layout(scene, scene_materials(scene))


def scene_drawing(scene):
    """The scene's cross-section to scale (x-z, mm): layers, taxels, load footprint,
    with dimensions and materials. Returns a matplotlib figure."""
    plt = pyplot()
    from matplotlib.patches import Rectangle

    lay = scene_layout(scene)
    x0, x1 = lay.x_range
    fig, ax = plt.subplots(figsize=(9, 3.2), constrained_layout=True)
    colours = {}
    palette = ["#cfe3f3", "#f6c89f", "#c7e9c0", "#e5c6e8", "#f2e394"]
    for L in lay.layers:
        c = colours.setdefault(L.material, palette[len(colours) % len(palette)])
        ax.add_patch(Rectangle((x0 * 1e3, L.z0 * 1e3), (x1 - x0) * 1e3, L.thickness * 1e3, fc=c, ec="0.4", lw=0.6))
        for p in L.patches:
            cp = colours.setdefault(L.patch_material, palette[len(colours) % len(palette)])
            ax.add_patch(Rectangle(((p.x - p.half) * 1e3, L.z0 * 1e3), 2 * p.half * 1e3, L.thickness * 1e3,
                                   fc=cp, ec="k", lw=0.8))
    H = lay.height * 1e3
    if lay.load is not None:
        a, b = (lay.load.x - lay.load.half) * 1e3, (lay.load.x + lay.load.half) * 1e3
    else:
        a, b = x0 * 1e3, x1 * 1e3
    for xa in np.linspace(a, b, 7):
        ax.annotate("", (xa, H), (xa, H + 0.6), arrowprops=dict(arrowstyle="->", color="crimson"))
    load = scene.load
    what = f"{load.force:g} N" if load.kind != "pressure" else f"{load.pressure:g} Pa"
    ax.text((a + b) / 2, H + 0.7, f"{load.kind}: {what}", ha="center", color="crimson", fontsize=8)
    for L in lay.layers:
        ax.text(x1 * 1e3 + 0.3, (L.z0 + L.thickness / 2) * 1e3, f"{L.thickness * 1e3:g} mm", va="center", fontsize=7)
    if lay.taxels:
        p = lay.taxels[0]
        ax.annotate("", ((p.x - p.half) * 1e3, -0.35), ((p.x + p.half) * 1e3, -0.35),
                    arrowprops=dict(arrowstyle="<->", lw=0.7))
        ax.text(p.x * 1e3, -0.75, f"{2 * p.half * 1e3:g} mm", ha="center", fontsize=7)
        if len(lay.taxels) > 1:
            q = lay.taxels[1]
            ax.annotate("", ((p.x + p.half) * 1e3, -0.35), ((q.x - q.half) * 1e3, -0.35),
                        arrowprops=dict(arrowstyle="<->", lw=0.7, color="0.3"))
            ax.text((p.x + p.half + q.x - q.half) / 2 * 1e3, -0.75, f"gap {(q.x - q.half - p.x - p.half) * 1e3:g} mm",
                    ha="center", fontsize=7)
    handles = [Rectangle((0, 0), 1, 1, fc=c, ec="0.4") for c in colours.values()]
    ax.legend(handles, list(colours), loc="upper right", fontsize=7, ncol=len(colours))
    ax.set_xlim(x0 * 1e3 - 0.5, x1 * 1e3 + 2.5)
    ax.set_ylim(-1.2, H + 1.6)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)" if lay.model != "axisymmetric" else "r (mm)")
    ax.set_ylabel("z (mm)")
    ax.set_title(f"{scene.name}: {lay.model.replace('_', ' ')}"
                 + (f", depth {lay.depth * 1e3:g} mm" if lay.model.startswith("plane") else ""), fontsize=9)
    return fig


def pyvista_render(sol, field="phi", window=(900, 420)) -> bytes:
    """Off-screen pyvista render of the deformed mesh coloured by a field
    (potential by default); 2D meshes are drawn in their x-z plane. PNG bytes."""
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
        cells = np.hstack([np.full((m.t.shape[1], 1), 4), m.t.T]).ravel()
        grid = pv.UnstructuredGrid(cells, np.full(m.t.shape[1], pv.CellType.TETRA), pts + u)
    grid.point_data[field] = getattr(sol.fields, field)
    if m.dim() == 3:                  # cut through the pressed taxel: the piezo's potential is inside
        grid = grid.clip(normal="-y", origin=(0.0, float(np.mean(pts[:, 1])), 0.0))
    plotter = pv.Plotter(off_screen=True, window_size=window)
    plotter.add_mesh(grid, scalars=field, cmap="coolwarm", show_edges=m.dim() == 2, edge_color="lightgray",
                     line_width=0.3, scalar_bar_args={"title": "potential (V)" if field == "phi" else field})
    if m.dim() == 2:
        plotter.view_xz()
    else:
        plotter.view_isometric()
    plotter.add_text(f"{sol.scene.name}: deformed (x1), coloured by {field}", font_size=9)
    img = plotter.screenshot(return_img=True)
    plotter.close()
    import matplotlib.image as mpimg
    buf = io.BytesIO()
    mpimg.imsave(buf, img, format="png")
    return buf.getvalue()


def yeoh_fit(strain, stress, fit, out, check_strain: float | None = None, title: str = ""):
    """PNG of the data, the fit over its range (solid) and beyond it (dashed).

    The fit range 0 < strain <= max_strain is shaded; the plot extends to
    max(3 max_strain, check_strain); where the uniaxial fit loses stability within
    it, a marker shows the point.
    """
    plt = pyplot()

    strain, stress = np.asarray(strain, float), np.asarray(stress, float)
    x_hi = max(3.0 * fit.max_strain, check_strain or 0.0)
    show = (strain >= 0) & (strain <= x_hi)
    order = np.argsort(strain[show])
    xs, ys = strain[show][order], stress[show][order]

    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=120)
    ax.axvspan(0, 100 * fit.max_strain, color="0.9", label=f"fit range (<= {100 * fit.max_strain:g} %)")
    ax.plot(100 * xs, ys / 1e3, ".", ms=4, color="k", label="test data")
    x_in = np.linspace(0, fit.max_strain, 200)
    x_out = np.linspace(fit.max_strain, x_hi, 400)
    lbl = (f"Yeoh: C10 {fit.C10 / 1e3:.3g}, C20 {fit.C20 / 1e3:.3g}, C30 {fit.C30 / 1e3:.3g} kPa"
           f" (R² {fit.r2:.4f})")
    ax.plot(100 * x_in, fit.stress(x_in) / 1e3, "-", color="C0", lw=2, label=lbl)
    ax.plot(100 * x_out, fit.stress(x_out) / 1e3, "--", color="C0", lw=1.5, label="fit, extrapolated")
    lost = stability_limit(fit, (0.5, 1.0 + x_hi))["uniaxial"]["tension"]
    if lost is not None:
        ax.plot(100 * (lost - 1), fit.stress(lost - 1) / 1e3, "x", color="C3", ms=10, mew=2,
                label=f"uniaxial stability lost ({100 * (lost - 1):.0f} %)")
    y_data = ys.max() if len(ys) else float(fit.stress(x_hi))
    ax.set_ylim(min(0.0, ys.min() / 1e3 if len(ys) else 0.0) - 0.05 * y_data / 1e3, 1.3 * y_data / 1e3)
    ax.set_xlim(0, 100 * x_hi)
    ax.set_xlabel("engineering strain (%)")
    ax.set_ylabel("nominal stress (kPa)")
    if title:
        ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)
