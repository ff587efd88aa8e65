"""Figures (matplotlib on the Agg backend, no screen needed; pyvista off-screen).

`pyplot()` is the one place the backend is chosen. `docs/readme_figure.py`
makes the landing picture (docs/thesis-pzt-3x3-2d.png) with
`cross_section`.
"""

from __future__ import annotations

import io
import os

import numpy as np

from taxel.analyses.adapter import layout
from taxel.analyses.adapter import scene_materials
from taxel.fem.constitution import stability_limit
from taxel.units import magnitude
from taxel.schema import electrode_name


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
    fig.colorbar(pc, ax=ax, label="vertical displacement (µm)")
    volts = ", ".join(f"{k}: {e.voltage * 1e3:.0f} mV" for k, e in sol.electrodes.items() if e.state != "reference")
    ax.set_title(f"{sol.applied_force:g} N on the taxel; open-circuit {volts}")
    axes[1].set_aspect("equal")
    for a in axes:
        a.set_xlabel("x (mm)")
        a.set_ylabel("z (mm)")
    fig.savefig(path, dpi=130)
    plt.close(fig)


def readable(label: str) -> str:
    """A readout label for a person: resistances with an SI prefix ("voltage across
    5e+08 ohm" -> "voltage across 500 MΩ")."""
    import re
    from taxel.reports.tables import eng
    return re.sub(r"(\d[\d.]*(?:e[+-]?\d+)?) ?ohm", lambda m: eng(float(m.group(1)), "Ω"), label)


def bode(freqs, H, names, label, path, title="", notch: float | None = None):
    """Magnitude and phase (unwrapped) of H (nf, na) against frequency, with the
    resonance (the largest |H| above the lowest decade) and the notch marked."""
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 6.2), sharex=True, layout="constrained")
    freqs = np.asarray(freqs)
    for k, name in enumerate(names):
        a1.loglog(freqs, np.abs(H[:, k]), label=name.replace("_", " "))
        a2.semilogx(freqs, np.degrees(np.unwrap(np.angle(H[:, k]))), label=name.replace("_", " "))
    mag = np.abs(H[:, 0])
    upper = freqs >= 10 * freqs[0]
    if upper.any():
        i = int(np.argmax(np.where(upper, mag, -np.inf)))
        if 0 < i < len(freqs) - 1:              # a peak inside the sweep, not its edge
            for a in (a1, a2):
                a.axvline(freqs[i], color="tab:red", lw=0.8, ls="--")
            a1.annotate(f"resonance {freqs[i]:.3g} Hz", (freqs[i], mag[i]), xytext=(-8, -4),
                        textcoords="offset points", ha="right", va="top", fontsize=8, color="tab:red")
    if notch:
        for a in (a1, a2):
            a.axvline(notch, color="tab:purple", lw=0.8, ls=":")
        a1.annotate(f"notch {notch:g} Hz", (notch, mag.min()), xytext=(6, 0), textcoords="offset points",
                    fontsize=8, color="tab:purple")
    a1.set_ylabel("|output per newton| (V/N)")
    a2.set_ylabel("phase, unwrapped (deg)")
    a2.set_xlabel("frequency (Hz)")
    a1.set_title(f"{title}: {readable(label)}" if title else readable(label), fontsize=10)
    if len(names) > 1:
        a1.legend(fontsize=8, loc="upper left")
    for a in (a1, a2):
        a.grid(True, which="both", alpha=0.3)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def time_response(t, force, y, names, label, path, title=""):
    """Force and output voltages over time."""
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True, layout="constrained")
    a1.plot(t, force, color="k")
    a1.set_ylabel("force (N)")
    a1.set_title(f"{title}: {readable(label)}" if title else readable(label), fontsize=10)
    y = np.asarray(y)
    big = float(np.nanmax(np.abs(y))) if y.size else 1.0
    scale, unit = (1e3, "mV") if big < 1 else (1.0, "V")
    for k, name in enumerate(names):
        a2.plot(t, scale * y[:, k], label=name.replace("_", " "))
    a2.set_ylabel(f"output ({unit})")
    a2.set_xlabel("time (s)")
    if len(names) > 1:
        a2.legend(fontsize=8, loc="best")
    for a in (a1, a2):
        a.grid(True, alpha=0.3)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


# outputs of a study: (axis label, scale from SI, absolute value?)
_OUTPUT_AXES = {"pressed_voltage": ("pressed taxel |V|", "V"), "sensitivity": ("pressed taxel |V| per newton", "V/N"),
                "max_strain": ("largest silicone strain", "%"), "crosstalk": ("crosstalk", "%")}
_PREFIX = [(1.0, ""), (1e-3, "m"), (1e-6, "µ"), (1e-9, "n"), (1e-12, "p")]


def _axis(out, values):
    """(label with unit, scale) for an output: volts and coulombs with the SI prefix
    that suits the largest value, strains and ratios in %."""
    label, unit = _OUTPUT_AXES.get(out, (out.replace("_", " "), "C" if out.startswith("charge") else "V"))
    if unit == "%":
        return f"{label} (%)", 100.0
    big = max([abs(v) for v in values if np.isfinite(v)] or [1.0])
    scale, prefix = next(((s, p) for s, p in _PREFIX if big >= s), _PREFIX[-1])
    return f"{label} ({prefix}{unit})", 1 / scale


def _param_value(v):
    """(number, unit) of a parameter value such as "0.5 mm"; (SI number, "SI") for a bare
    number; None when it is not a number."""
    if isinstance(v, str):
        parts = v.split(maxsplit=1)
        try:
            return float(parts[0]), (parts[1] if len(parts) > 1 else "-")
        except ValueError:
            return None
    m = magnitude(v)
    return (m, "SI") if isinstance(m, float) else None


def study_plots(rows, parameters, outputs, folder, title=""):
    """Each output against each numeric parameter, as small multiples: one panel per
    value of the categorical parameters (material, model), each with its own y
    range; one line per value of the other numeric parameters, in one colour per
    value on every plot of the study; the legend outside the panels. Axis labels
    carry the unit. Returns the files written."""
    plt = pyplot()
    folder.mkdir(parents=True, exist_ok=True)
    done = [r for r in rows if r["status"] == "done"]
    numeric = [p for p in parameters if done and all(_param_value(r.get(p)) is not None for r in done)]
    facets = [p for p in parameters if p not in numeric]
    panels = list(dict.fromkeys(tuple(str(r.get(q)) for q in facets) for r in done)) or [()]
    files = []
    for p in numeric:
        unit = _param_value(done[0][p])[1]
        others = [q for q in numeric if q != p]
        keys = sorted({tuple(_param_value(r[q])[0] for q in others) for r in done})
        colour = {k: f"C{i % 10}" for i, k in enumerate(keys)}
        for out in outputs:
            if not any(isinstance(r.get(out), (int, float)) for r in done):
                continue
            ylabel, yscale = _axis(out, [abs(r[out]) for r in done if isinstance(r.get(out), (int, float))])
            fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels) + 1.8, 3.8), squeeze=False,
                                     layout="constrained")
            for ax, panel in zip(axes[0], panels):
                sub = [r for r in done if tuple(str(r.get(q)) for q in facets) == panel]
                for k in keys:
                    grp = sorted((r for r in sub if tuple(_param_value(r[q])[0] for q in others) == k),
                                 key=lambda r: _param_value(r[p])[0])
                    ys = [abs(r[out]) * yscale if isinstance(r.get(out), (int, float)) else np.nan for r in grp]
                    label = ", ".join(f"{q.replace('_', ' ')} {v:g} {_param_value(done[0][q])[1]}"
                                      for q, v in zip(others, k)) or None
                    ax.plot([_param_value(r[p])[0] for r in grp], ys, "o-", ms=3, color=colour[k], label=label)
                if out == "max_strain":       # the linear silicone's range (2 % voltage error), drawn
                    from taxel.analyses.static import LINEAR_ERROR_PER_STRAIN
                    lim = 100 * 0.02 / LINEAR_ERROR_PER_STRAIN
                    ax.axhline(lim, color="tab:red", lw=0.9, ls="--")
                    ax.axhspan(lim, ax.get_ylim()[1], color="tab:red", alpha=0.06)
                    ax.annotate(f"linear silicone valid below {lim:.2g} %", (0.02, lim), xycoords=("axes fraction",
                                "data"), xytext=(0, 3), textcoords="offset points", fontsize=7, color="tab:red")
                ax.set_title(", ".join(f"{q}: {v}" for q, v in zip(facets, panel)) or title, fontsize=10)
                ax.set_xlabel(f"{p.replace('_', ' ')} ({unit})")
                ax.set_ylabel(ylabel)
                ax.grid(True, alpha=0.3)
            if len(keys) > 1:
                handles, labels = axes[0][0].get_legend_handles_labels()
                fig.legend(handles, labels, loc="outside right upper", fontsize=8, frameon=False)
            if facets and title:
                fig.suptitle(title, fontsize=10)
            path = folder / f"{out}-vs-{p}.png"
            fig.savefig(path, dpi=110)
            plt.close(fig)
            files.append(path)
    return files


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
        ax.text(x1 * 1e3 + 0.3, (L.z0 + L.thickness / 2) * 1e3, f"{L.thickness * 1e3:.3g} mm", va="center", fontsize=7)
    if lay.taxels:
        p = lay.taxels[0]
        ax.annotate("", ((p.x - p.half) * 1e3, -0.35), ((p.x + p.half) * 1e3, -0.35),
                    arrowprops=dict(arrowstyle="<->", lw=0.7))
        ax.text(p.x * 1e3, -0.75, f"{2 * p.half * 1e3:.2f} mm", ha="center", fontsize=7)
        if len(lay.taxels) > 1:
            q = lay.taxels[1]
            ax.annotate("", ((p.x + p.half) * 1e3, -0.35), ((q.x - q.half) * 1e3, -0.35),
                        arrowprops=dict(arrowstyle="<->", lw=0.7, color="0.3"))
            ax.text((p.x + p.half + q.x - q.half) / 2 * 1e3, -0.75, f"gap {(q.x - q.half - p.x - p.half) * 1e3:.2f} mm",
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
        cells = np.hstack([np.full((m.t.shape[1], 1), 4), m.t.T]).ravel()
        grid = pv.UnstructuredGrid(cells, np.full(m.t.shape[1], pv.CellType.TETRA), pts + u)
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
